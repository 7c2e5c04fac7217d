"""Where the residual foam's past is taken (residual_foam.py): on the grids of canonical
cameras, the frame's moved back along its heading onto a lattice of lines across it, so frames
of a camera moving along its heading (a dolly, a flyover) share their past cues, and each frame
reads its residual from those grids at its own points.

A frame between lines k and k + 1, a share f of a step past k, takes the residual of the
cameras at lines k and k - 1 weighted f and 1 - f: a step or so behind it, at its height,
looking its way. Crossing a line the weights hand over continuously (at line k + 1, all of line
k's), so the residual changes as the camera moves, without a jump (a single canonical camera,
the line behind, jumped each step: half as large a change as the frame's own grid's swimming
between frames, but three times it at a line). The canonical cameras are made from the frame's
camera alone (position snapped, axes rounded), so a frame's foam is a function of the frame,
whatever was drawn before: farms splitting frames render the same foam. A frame whose view the
camera two steps behind would not hold (one looking down) takes its past on its own grid."""

import numpy as np

from .band_limit import every_other
from .camera import Camera, view_matrix
from .grid_points import grid_points, grid_uv_of
from .residual_foam import COARSE, Kept, coarse_points, coarse_shapes, past_foam, residual, spread
from .tiles import bilinear

SNAP = 2.0  # the lattice's step in camera heights above the sea (rounded down to a power of 2)
# The camera's axes are rounded to ROUND, its height to PLACE m and its sideways place to
# SIDEWAYS of a step: their last bits vary with its position (the view matrix is an inverse;
# Blender's float32 location is millimetres coarse kilometres out; the rounded heading is not
# quite the one it moves along). None a power of 2, of which coordinates often are multiples.
ROUND, PLACE, SIDEWAYS = 1e-9, 1e-4, 1.0 / 250.0
GRIDS = Kept(8)  # canonical grids' coarse points by their key
WHERE = Kept(4)  # where a frame's grid's coarse points lie in a canonical grid, by both keys


def canonical_cameras(camera, level):
    """((canonical camera, weight), ...) of `camera` over S_base at `level` (see the module),
    those of weight 0 left out; None if it has none (not a perspective camera above the sea)."""
    return None if (made := _lines(camera, level)) is None else [
        (Camera(view, camera.proj), weight) for view, weight in made[0]]


def _lines(camera, level):
    """(((view matrix, weight), ...), step, heading) of `canonical_cameras`, or None."""
    lattice = _lattice(camera, level)
    if lattice is None:
        return None
    step, ahead, across = lattice
    along, side = float(camera.position[:2] @ ahead), float(camera.position[:2] @ across)
    line = np.floor(along / step)
    past = float(along / step - line)
    sideways = _rounded(side, SIDEWAYS * step) * across
    r, u, f = (_rounded(a) for a in (camera.right, camera.up, camera.forward))
    z = _rounded(camera.position[2], PLACE)
    views = [(view_matrix((*(step * k * ahead + sideways), z), r, u, f), weight)
             for k, weight in ((line, past), (line - 1.0, 1.0 - past)) if weight > 0.0]
    return views, step, ahead


def _lattice(camera, level):
    """(step m, heading, right of it) of the camera's lattice, or None: the heading is the
    view's horizontal part, else (a camera looking down) the top of its screen's, rounded."""
    height = float(camera.position[2]) - level
    if camera.orthographic or height <= 0.0:
        return None
    for axis in (camera.forward, camera.up):
        norm = float(np.hypot(axis[0], axis[1]))
        if norm > 1e-3:
            ahead = _rounded(np.asarray(axis[:2], np.float64) / norm)
            return 2.0 ** np.floor(np.log2(SNAP * height)), ahead, np.array([ahead[1], -ahead[0]])
    return None


def _rounded(a, unit=ROUND):
    return np.round(np.asarray(a, np.float64) / unit) * unit


def residual_foam(source, result, xy, lod, time, active, tau, grid, placed=1.0, top=None,
                  dolly=True):
    """residual_foam.residual at the frame's grid points `xy` (`lod` their band limits; of
    `result`, a GridResult): its past taken on the canonical cameras' grids (`GRIDS`, their
    cues kept under their keys), read at the frame's coarse points, bilinear between each
    grid's, and weighted; on the frame's own grid (`grid` its key) where there are none, where
    they would not hold the frame's view wherever in its step the camera were (`_held`, then
    `_inside`), or where the camera does not `dolly` (move along its heading alone: one that
    turns, climbs, zooms or slides sideways would have new canonical cameras each frame, twice
    its own grid's cues to make; a still one's own grid keeps its cues)."""
    made = _canonical(source, result) if dolly else None
    if made is not None:
        total = np.zeros(coarse_shapes(xy.shape[1:], COARSE)[-1], np.float32)
        here = []  # the frame's coarse points and which of them it sees, once
        for canonical, weight, step, ahead in made:
            found = _found(source, result, xy, grid, canonical, step, ahead, here)
            if found is False:
                break
            key, *_, points, at = canonical
            foam = past_foam(source, points, at, time, active, tau, key, placed, top)
            total += bilinear(foam, *found) * np.float32(weight)
        else:
            full = spread(total, coarse_shapes(xy.shape[1:], COARSE))
            return np.minimum(full, 1.0, out=full)
    return residual(source, xy, lod, time, active, tau, grid, placed, top)


def _found(source, result, xy, grid, canonical, step, ahead, here):
    """Where the frame's coarse points (`here`: [] until made) lie in a `canonical` grid
    (`_inside`), or False if the canonical cameras would not hold its view (`_held`): kept
    (WHERE) by the frame's grid's key (`grid`) and camera and the canonical grid's key."""
    key, c, u, v, horizon_row = canonical[:5]
    level = result.settings[0]

    def where(*_):
        if not here:
            points = coarse_points(xy, None, COARSE)[0]
            here.extend((points, _seen(result.camera, points, level)))
        points, seen = here
        held = _held(result.camera, 2.0 * step, ahead, points[:, seen], level)
        return [held and _inside(c, u, v, points, seen, horizon_row)]
    if not grid:
        return where()[0]
    seen_by = result.camera.view.tobytes() + result.camera.proj.tobytes()
    return WHERE.get(source, [(grid, seen_by, key)], where)[0]


def _on_plane(xy, level):
    """Points xy (2, ...) on S_base at `level`, as (..., 3) float64."""
    return np.stack([*np.asarray(xy, np.float64), np.full(xy.shape[1:], level)], axis=-1)


def _seen(camera, xy, level):
    """Which of the points `xy` (2, ...) on S_base are in `camera`'s view (within its clip
    range too: a canonical camera's far clip ends nearer the frame's)."""
    c = camera.clip(_on_plane(xy, level))
    return (c[..., 3] > 0.0) & (np.abs(c[..., :3]) <= c[..., 3:]).all(axis=-1)


def _held(camera, back, ahead, xy, level):
    """Whether the points `xy` (2, n) on S_base that `camera` sees are in the view of the
    camera `back` m behind it along `ahead` (two lattice steps: the farthest a canonical camera
    stands), clip range and all: then in every canonical camera's between (a point's image
    moves along a line as the camera moves back, its depth grows), whose grid covers its
    view, so a frame takes the canonical path wherever in its step it is, or nowhere in it."""
    back = camera.proj @ camera.view @ _moved(back * ahead)
    there = _on_plane(xy, level) @ back[:, :3].T + back[:, 3]
    return bool((there[:, 3] > 0.0).all() and (np.abs(there[:, :3]) <= there[:, 3:]).all())


def _moved(offset):
    """The 4x4 translation of world points by `offset` (x, y): a view matrix times it is the
    camera's moved back by it."""
    m = np.eye(4)
    m[:2, 3] = offset
    return m


def _canonical(source, result):
    """[((key, corners, coarse columns' u, rows' v, the projector's horizon row, coarse
    points, their band limit), weight, the lattice's step, the heading), ...] of the
    canonical cameras' grids (`canonical_cameras`), or None (also for a grid without a band
    limit: its whitecaps' thresholds do not follow the spacing, another grid's would differ)."""
    if getattr(result, "settings", None) is None or result.camera is None or result.base is None:
        return None
    level, elevation, aim, wave_scale = result.settings
    lines = None if wave_scale is None else _lines(result.camera, level)
    if lines is None:
        return None
    views, step, ahead = lines
    e, proj = result.extent, result.camera.proj
    out = []
    for view, weight in views:
        key = (b"".join(np.ascontiguousarray(a, np.float64).tobytes() for a in (
            view, proj, result.origin, (level, elevation, e.lower, e.upper, e.side),
            result.resolution, (wave_scale,))), aim)

        def make(keys, view=view):  # its coarse points alone, as coarse_points takes them
            nx, ny = result.resolution
            keep = [np.arange(n) for n in (nx, ny)]
            for _ in range(COARSE):
                keep = [k[every_other(len(k))] for k in keep]
            made = grid_points(Camera(view, proj), level, e, result.resolution, elevation,
                               aim, result.origin, wave_scale, keep)
            return [None if made is None else (made.c, made.u, made.v[:, 0],
                                               made.projector.horizon_row, made.xy,
                                               made.lod - np.float32(COARSE))]
        made = GRIDS.get(source, [key], make)[0]
        if made is None:
            return None
        out.append(((key, *made), weight, step, ahead))
    return out


def _inside(c, u, v, xy, seen, horizon_row):
    """Where points `xy` lie among the canonical grid's coarse columns and rows (fractional
    indices, each (...), those beyond its border at the border), or False if some it `seen`
    (a mask of them: those on the frame's screen) lie outside it by more than half a coarse
    cell (beyond its far rows, the `horizon_row` side, they are read at its farthest)."""
    pu, pv = grid_uv_of(c, xy)
    if not (np.isfinite(pu).all() and np.isfinite(pv).all()):
        return False
    lo_u = u[0] - 0.5 * (u[1] - u[0])
    hi_u = u[-1] + 0.5 * (u[-1] - u[-2])
    lo_v = v[0] - 0.5 * (v[1] - v[0]) if horizon_row != 0 else -np.inf
    hi_v = v[-1] + 0.5 * (v[-1] - v[-2]) if horizon_row != -1 else np.inf
    su, sv = pu[seen], pv[seen]
    if su.size and (su.min() < lo_u or su.max() > hi_u or sv.min() < lo_v or sv.max() > hi_v):
        return False
    i = np.interp(pu, u, np.arange(len(u)))
    j = np.interp(pv, v, np.arange(len(v)))
    return i, j
