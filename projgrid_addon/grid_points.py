"""The projected grid's points on S_base (thesis §2.4 steps 2 to 6), before any displacement:
the projector aimed and ranged for a displaceable volume, its grid's columns and rows, and the
points where their lines meet S_base. `projected_grid.build_grid` displaces them (step 7); the
residual foam takes its past on another camera's (past_grid.py).

A grid is made for its camera moved across the sea to stand over the world's origin, then moved
back (`GridPoints.moved`): the projector, spacing and band limits follow the camera's height and
turn alone, so a camera that only moves across the sea (a still one, one that dollies or trucks)
keeps them (`KEPT`), and a frame's grid is the same whichever frames were made before."""

import threading
from collections import OrderedDict
from dataclasses import dataclass, replace

import numpy as np

from .band_limit import grid_steps, lod_from_w
from .displaceable_volume import visible_volume_points
from .scratch import CHUNK, scratch


@dataclass
class GridPoints:
    """A grid's points on S_base: `xy` (2, ny, nx) float64; `lod` (ny, nx) float32 band limits
    or None; the projector; its homogeneous corners `c` (4, 4: u, v = 00, 10, 01, 11) and each
    column's u (nx,) and row's v (ny, 1) in its span (Projector.spacing)."""

    projector: object
    c: np.ndarray
    u: np.ndarray
    v: np.ndarray
    xy: np.ndarray
    lod: np.ndarray | None

    def moved(self, shift):
        """These points moved by `shift` (x, y) across the sea, with their projector and
        corners (the columns, rows and band limits are the same arrays); the points are
        interpolated from the moved corners, as `_made` interpolates them."""
        x, y = shift
        move = np.eye(4)
        move[:2, 3] = -x, -y
        p = self.projector
        projector = replace(p, view=p.view @ move, position=p.position + (x, y, 0.0))
        c = self.c.copy()
        c[:, 0] += x * c[:, 3]
        c[:, 1] += y * c[:, 3]
        return GridPoints(projector, c, self.u, self.v, _interpolated(c, self.u, self.v),
                          self.lod)


# Grids kept by what they are made of: a viewport's and a render's, each with the volumes a
# frame may try (displaceable_volume.FIT_SIGMAS and the true bounds), within KEPT_BYTES of
# their arrays (a grid larger alone is not kept).
KEPT, KEPT_BYTES = 8, 64 * 2**20
SLACK_STEP = 64.0  # m (`_slack`)
_KEPT = OrderedDict()
_LOCK = threading.Lock()


def widened(points, side):
    """Points on S_base and the corners of the square `side` metres around each: where grid
    points may lie whose choppy displacement (at most `side`) brings them into view."""
    offsets = np.array([(-side, -side, 0.0), (side, -side, 0.0), (-side, side, 0.0),
                        (side, side, 0.0)])
    return np.concatenate([points, (points[:, None, :] + offsets).reshape(-1, 3)])


def grid_points(camera, level, extent, resolution, elevation, aim, origin, wave_scale=None,
                keep=None):
    """The GridPoints of `camera`'s grid of `resolution` (nx, ny) for the displaceable volume
    `extent` (§2.4 steps 2 to 6), each point's band limit for waves of `wave_scale` (None: no
    band limit); None where the volume is not in view. `keep`: (columns, rows), indices of
    those kept alone (their points and band limits as the whole grid's)."""
    if not np.array_equal(camera.view[3], (0.0, 0.0, 0.0, 1.0)):
        made = _made(camera, level, extent, resolution, elevation, aim, origin, wave_scale, keep)
        return made if made is None else made.moved((0.0, 0.0))
    # Over the origin at the camera's height over S_base in float32: its place returns from
    # the float64 view with some ulps of noise, which would keep nothing (the grid's range has
    # a margin of 1e-5 of the span).
    shift = camera.position[:2]
    height = level + float(np.float32(camera.position[2] - level))
    view = camera.view.copy()
    view[:3, 3] = -view[:3, 2] * height
    slack = _slack(np.abs(shift - np.asarray(origin, np.float64)[:2]).max())
    here = (0.0, 0.0, float(origin[2]))
    key = None
    if keep is None:
        key = (b"".join(np.ascontiguousarray(a, np.float64).tobytes() for a in (
            view, camera.proj, (level, extent.lower, extent.upper, extent.side, elevation,
                                here[2], slack, np.nan if wave_scale is None else wave_scale),
            resolution)), aim)
        with _LOCK:
            made = _KEPT.get(key)
            if made is not None:
                _KEPT.move_to_end(key)
        if made is not None:
            return made.moved(shift)
    made = _made(type(camera)(view, camera.proj), level, extent, resolution, elevation, aim,
                 here, wave_scale, keep, slack)
    if made is None:
        return None
    if key is not None and _bytes(made) <= KEPT_BYTES:
        with _LOCK:
            _KEPT[key] = made
            while len(_KEPT) > KEPT or sum(map(_bytes, _KEPT.values())) > KEPT_BYTES:
                _KEPT.popitem(last=False)
    return made.moved(shift)


def _bytes(made):
    return sum(a.nbytes for a in (made.u, made.v, made.lod) if a is not None)


def _slack(reach):
    """The span's float32 margin (Projector.with_range) for a mesh placed from an origin
    `reach` from the camera along the sea: at least that, rounded up to a multiple of
    SLACK_STEP m, or of a 512th of its octave beyond 32 km, so a moving camera keeps it for a
    while and the span's steps move the grid far less than a pixel: a step's move grows with
    the step (64 m: 0.002-0.013 px on a 1920 px screen; 2 km, at 1,000 km, about 0.2 px, where
    the float32 mesh's own rounding moves vertices up to 7 px)."""
    step = max(SLACK_STEP, 2.0 ** (np.floor(np.log2(max(reach, SLACK_STEP))) - 9.0))
    return float(max(1.0, np.ceil(reach / step)) * step)


def _made(camera, level, extent, resolution, elevation, aim, origin, wave_scale, keep,
          slack=0.0):
    """`grid_points`' GridPoints made for `camera` as it stands (`slack`: with_range's)."""
    nx, ny = resolution
    points = visible_volume_points(camera, level, extent.upper, extent.lower)
    if len(points) == 0:
        return None
    points[:, 2] = level  # onto S_base
    if extent.side > 0.0:
        points = widened(points, extent.side)
    projector = aim(camera, level, extent.upper, elevation, points).with_range(points, origin,
                                                                           slack)
    projector = replace(projector, **{k: _read_only(getattr(projector, k))
                                      for k in ("view", "position", "forward")})
    c = projector.corner_points(level)
    u, du, v, dv = projector.spacing(camera, level, extent, c, nx, ny)
    steps = None
    if wave_scale is not None:
        left = (1.0 - v) * c[0] + v * c[2]  # (ny, 4): hom at u = 0
        right = (1.0 - v) * c[1] + v * c[3]  # (ny, 4): hom at u = 1
        steps = grid_steps(c, left, right, u, wave_scale, du, dv)
    rows = np.arange(ny)
    if keep is not None:
        columns, rows = keep
        u, v = u[columns], v[rows]
        if steps is not None:
            along_u, along_v, scale, du, dv = steps
            steps = along_u, along_v[columns], scale, du[columns], dv
    lod = None if steps is None else _interpolated(c, u, v, (steps, rows, keep))
    for a in (u, v, lod):  # made here: shared by every grid moved from this one
        if a is not None:
            a.setflags(write=False)
    return GridPoints(projector, c, u, v, None, lod)


def _read_only(a):
    """A read-only copy of array `a`: shared by every grid moved from a kept one."""
    a = np.array(a)
    a.setflags(write=False)
    return a


def _interpolated(c, u, v, band_limit=None):
    """The points (2, rows, columns) at columns u and rows v (rows, 1) of the span of
    homogeneous corners `c`; with `band_limit` (steps, rows, keep: `_made`'s), their band
    limits instead (rows, columns) float32."""
    # Bilinear interpolation of the homogeneous corners (exact: they are affine in u, v), in the
    # weighted form: corners can differ in scale by 1e6 (w ~ 1 / distance), and differences of
    # corners would cancel catastrophically near the horizon.
    left = (1.0 - v) * c[0] + v * c[2]  # (rows, 4): hom at u = 0
    right = (1.0 - v) * c[1] + v * c[3]  # (rows, 4): hom at u = 1
    iu = 1.0 - u
    shape = (len(v), len(u))
    out = np.empty((2,) + shape) if band_limit is None else np.empty(shape, np.float32)
    count = max(1, CHUNK // len(u))
    for start in range(0, len(v), count):
        here = slice(start, min(len(v), start + count))
        hw = scratch("hw", (here.stop - start, len(u)), np.float64)
        term = scratch("term", hw.shape, np.float64)
        np.multiply(iu, left[here, 3:4], out=hw)
        np.multiply(u, right[here, 3:4], out=term)
        hw += term
        if band_limit is not None:
            steps, rows, keep = band_limit
            lod_from_w(steps, here if keep is None else rows[here], hw, out[here])
            continue
        for k in (0, 1):
            np.multiply(iu, left[here, k:k + 1], out=out[k, here])
            np.multiply(u, right[here, k:k + 1], out=term)
            out[k, here] += term
            out[k, here] /= hw
    return out


def grid_uv_of(c, xy):
    """Where world points `xy` (2, ...) on S_base lie in the span of a grid of homogeneous
    corners `c` (GridPoints.c): (u, v), each (...) float64, the inverse of the corners'
    interpolation (affine in u, v: hom = c0 + u (c1 - c0) + v (c2 - c0), x = hom_x / hom_w)."""
    a, b = c[1] - c[0], c[2] - c[0]
    x, y = np.asarray(xy, np.float64)
    # x hom_w - hom_x = 0 and y hom_w - hom_y = 0, linear in u and v
    m00, m01, r0 = a[0] - x * a[3], b[0] - x * b[3], x * c[0][3] - c[0][0]
    m10, m11, r1 = a[1] - y * a[3], b[1] - y * b[3], y * c[0][3] - c[0][1]
    det = m00 * m11 - m01 * m10
    with np.errstate(divide="ignore", invalid="ignore"):
        return (r0 * m11 - m01 * r1) / det, (m00 * r1 - r0 * m10) / det
