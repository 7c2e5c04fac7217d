"""The projected grid's points on S_base (thesis §2.4 steps 2 to 6), before any displacement:
the projector aimed and ranged for a displaceable volume, its grid's columns and rows, and the
points where their lines meet S_base. `projected_grid.build_grid` displaces them (step 7); the
residual foam takes its past on another camera's (past_grid.py)."""

from dataclasses import dataclass

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
    nx, ny = resolution
    points = visible_volume_points(camera, level, extent.upper, extent.lower)
    if len(points) == 0:
        return None
    points[:, 2] = level  # onto S_base
    if extent.side > 0.0:
        points = widened(points, extent.side)
    projector = aim(camera, level, extent.upper, elevation, points).with_range(points, origin)
    c = projector.corner_points(level)

    # Bilinear interpolation of the homogeneous corners (exact: they are affine in u, v), in the
    # weighted form: corners can differ in scale by 1e6 (w ~ 1 / distance), and differences of
    # corners would cancel catastrophically near the horizon.
    u, du, v, dv = projector.spacing(camera, level, extent, c, nx, ny)
    left = (1.0 - v) * c[0] + v * c[2]  # (ny, 4): hom at u = 0
    right = (1.0 - v) * c[1] + v * c[3]  # (ny, 4): hom at u = 1
    steps = grid_steps(c, left, right, u, wave_scale, du, dv) if wave_scale is not None else None
    rows = np.arange(ny)
    if keep is not None:
        columns, rows = keep
        u, v, left, right = u[columns], v[rows], left[rows], right[rows]
        if steps is not None:
            along_u, along_v, scale, du, dv = steps
            steps = along_u, along_v[columns], scale, du[columns], dv
    iu = 1.0 - u
    xy = np.empty((2, len(rows), len(u)))
    lod = np.empty(xy.shape[1:], np.float32) if steps is not None else None
    count = max(1, CHUNK // len(u))
    for start in range(0, len(rows), count):
        here = slice(start, min(len(rows), start + count))
        hw = scratch("hw", (here.stop - start, len(u)), np.float64)
        term = scratch("term", hw.shape, np.float64)
        np.multiply(iu, left[here, 3:4], out=hw)
        np.multiply(u, right[here, 3:4], out=term)
        hw += term
        for k in (0, 1):
            np.multiply(iu, left[here, k:k + 1], out=xy[k, here])
            np.multiply(u, right[here, k:k + 1], out=term)
            xy[k, here] += term
            xy[k, here] /= hw
        if lod is not None:
            lod_from_w(steps, here if keep is None else rows[here], hw, lod[here])
    return GridPoints(projector, c, u, v, xy, lod)


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
