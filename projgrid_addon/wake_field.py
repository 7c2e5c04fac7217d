"""The wakes the grid draws (the `wakes` effect): each hull's wake read from its steady wake,
laid along its course over the past WINDOW seconds; a pure function of the courses and the
time.

Summing the rings of every emission (wakes.py) costs a point times an emission: too much for
every vertex of every frame. A hull's steady wake (steady_wake.py) is read instead, for each
point at its place in the wake: xi, how far behind the hull along its course, and eta, how far
across it. Where the course turns the wake turns with it; where the speed changed, the waves
there have the length of the speed then (2 pi U^2 / g): xi and eta are stretched by
(U_ref / U)^2 along the course, summed so the phase runs on. Hulls that change speed or turn
sharply get the steady wake of each stretch of their course, not the transients: a wake that
looks right, not an exact one (wakes.wake_heights is).

What is drawn is the moving hull's wake (a hull at rest has none). A hull between two rungs
of the Froude ladder reads both, weighted, so its wake changes continuously with its speed."""

from dataclasses import dataclass

import numpy as np

from . import wakes
from .band_limit import every_other_of, every_other_shape, fill_every_other
from .effects import MOVING
from .spectrum import GRAVITY
from .steady_wake import ACROSS, AHEAD, BEHIND, CELL, FADE, FAR, PATCH, RUNG, hull, hull_wake, rungs
from .tiles import bilinear

CUT = 40.0  # m/s: a course faster than this over a step was cut (a jump): it starts anew
JERK = 20.0  # m/s^2 (2 g): no hull speeds up and slows down again so fast: such a step jumped
SPIKE = 0.2  # s: a step is judged over this at least (a short last step's speed is noisy)
SLOWEST = 0.3  # m/s: the speed below which a stretch of course is taken as at rest
COARSE = 32  # vertex spacings a wake's transverse wave spans where it is read on every
# other row and column (`read_grid`)
SEGMENT = 1.0  # hull lengths: the course is followed on segments about this long, and its
# places found on a raster of cells as wide; at most MOST_SEGMENTS segments, MOST_CELLS cells
# across the course's extent (a small hull's long course)
MOST_SEGMENTS, MOST_CELLS = 64, 96
KNOT = 0.1  # s: the course's knots lie on a lattice of this times a power of two
WEDGE = 0.45  # a wake reaches at most this far across its track per metre behind (Kelvin's
# 0.35, with room for the stretch of a hull that slowed), and MARGIN far sigmas besides
MARGIN = 8.0
FOAM_FROUDE = (0.2, 0.5)  # the hull Froude numbers its stern's wake turns white over
BEAMS = 1.0  # the stern foam's band, in beams (two standard deviations across)
SPREAD = 3.0  # s: the band widens by sqrt(1 + age / SPREAD)
# The bow wave breaks white where its crest (the wake's moving part, in drafts) rises above
# BOW_CREST, all of it from twice that, within BOW_REACH hull lengths behind the hull's centre
BOW_CREST, BOW_REACH = 0.35, 1.0
BOW_ANGLE = 0.3  # and beside the track: further out than this per metre behind the bow
ACTIVE_DECAY, RESIDUAL_DECAY = 2.5, 6.0  # s


@dataclass(frozen=True)
class Course:
    """One hull's course over the past WINDOW seconds, as the scene's animation places it:
    `times` (s, ascending, the last now) and `x`, `y` (m, world) of its footprint's centre;
    its `draft`, `length` and `beam` (m)."""

    name: str
    times: tuple
    x: tuple
    y: tuple
    draft: float
    length: float
    beam: float


def course(name, times, x, y, draft, length, beam):
    """The Course of a hull whose animation placed it at (x, y) at `times` (ascending), from
    after the last cut in it: a step faster than CUT, or one faster than the steps either
    side by more than JERK allows over it (the hull jumped: a cut in its path, keys of
    constant interpolation)."""
    t, x, y = (np.asarray(v, dtype=np.float64) for v in (times, x, y))
    dt = np.maximum(np.diff(t), 1e-9)
    u = np.hypot(np.diff(x), np.diff(y)) / dt
    # each step against its neighbours (the first and last against their one neighbour)
    before, after = np.r_[u[1:2], u[:-1]], np.r_[u[1:], u[-2:-1]]
    limit = JERK * np.maximum(dt, SPIKE)
    jumps = np.flatnonzero((u > CUT) | ((u - before > limit) & (u - after > limit)))
    start = int(jumps[-1]) + 1 if len(jumps) else 0
    return Course(str(name), tuple(t[start:]), tuple(x[start:]), tuple(y[start:]),
                  max(float(draft), 0.0), max(float(length), 0.05), max(float(beam), 0.05))


def draw(result, courses, wave_scale):
    """Add the wakes of `courses` to the grid of `result` (projected_grid.GridResult), to its
    vertices' heights and its surface, where the grid holds them: each wake whole where its
    transverse waves (2 pi U_ref^2 / g, `reference_speed`) span four vertex spacings or more,
    faded out until two (the band limit, band_limit.py: a vertex's spacing is
    wave_scale / 2^(lod + 1)).
    Returns (heights added, active foam, residual foam), (ny, nx) float32 each (the foams the
    largest over the wakes)."""
    x, y, h = result.surface
    lod = result.lod.reshape(h.shape)
    total, active, residual = (np.zeros(h.shape, np.float32) for _ in range(3))
    for c in courses:
        _, rms = speeds(c)
        if rms < MOVING:
            continue
        u_ref = reference_speed(c, rms)  # the speed `read` draws the wake for
        waves = np.log2(2.0 * np.pi * u_ref * u_ref / GRAVITY / wave_scale)  # in wave scales
        lift, fresh, old = read_grid(c, x, y, lod, waves)
        total += lift * np.clip(lod + np.float32(waves), 0.0, 1.0)
        np.maximum(active, fresh, out=active)
        np.maximum(residual, old, out=residual)
    result.positions[:, 2] += total.ravel()
    result.surface = (x, y, h + total)
    return total, active, residual


def read_grid(course, x, y, lod, waves):
    """`read` with foam at a grid's points (x, y: (rows, columns)) of level of detail `lod`
    (band_limit.py): where the grid is fine enough (its spacing a COARSE-th of the wake's
    transverse wavelength, 2^`waves` wave scales, or less over at least a quarter of it),
    read on every other row and column and interpolated between
    (band_limit.fill_every_other: within 2 % of a wave COARSE spacings long), elsewhere read
    at every point."""
    fine = lod >= np.float32(np.log2(COARSE) - 1.0 - waves)
    if x.ndim != 2 or min(x.shape) < 3 or fine.mean() < 0.25:
        return read(course, np.stack([x, y]), foam=True)
    coarse = np.empty((2, *every_other_shape(x.shape)))
    every_other_of(x, coarse[0])
    every_other_of(y, coarse[1])
    rest = ~fine
    # one read of both sets: the course's places found once, on a raster over them all
    n = coarse[0].size
    got = read(course, np.concatenate([coarse.reshape(2, -1), np.stack([x[rest], y[rest]])],
                                      axis=1), foam=True)
    out = [fill_every_other(v[:n].reshape(coarse.shape[1:]), np.empty(x.shape, np.float32))
           for v in got]
    for whole, part in zip(out, got, strict=True):
        whole[rest] = part[n:]
    return out


def speeds(course):
    """(U per segment between samples (m/s), U_ref): the speeds along the course and the
    rms speed over it, which sets its Froude number (0 when it has not moved)."""
    t = np.asarray(course.times, dtype=np.float64)
    if len(t) < 2:
        return np.zeros(0), 0.0
    step = np.hypot(np.diff(course.x), np.diff(course.y))
    dt = np.maximum(np.diff(t), 1e-9)
    u = step / dt
    return u, float(np.sqrt((u * u * dt).sum() / dt.sum()))


def reference_speed(course, rms):
    """The speed (m/s) a course's wake is read for: the hull's now (its near wake is its
    steady wake now; the waves it left at other speeds stretched to theirs), or half its rms
    speed over the window if more (a hull that stopped leaves its wake on the water)."""
    return max(speed_now(course), 0.5 * rms)


def speed_now(course, dt=0.5):
    """The hull's speed (m/s) over the last `dt` s of its course."""
    t = np.asarray(course.times, dtype=np.float64)
    if len(t) < 2:
        return 0.0
    back = max(t[-1] - dt, t[0])
    if back >= t[-1]:
        return 0.0
    x0, y0 = np.interp(back, t, course.x), np.interp(back, t, course.y)
    return float(np.hypot(course.x[-1] - x0, course.y[-1] - y0) / (t[-1] - back))


def follow(course, u, points, ahead):
    """(xi, n, U, arc) of world points (2, M) against the course, in metres: xi the arc
    length behind the hull to the point's nearest place on the course (negative ahead of the
    hull, along its last heading), n the signed distance across the course from there, U the
    course's speed there (`u`: per step, `speeds`); and the course's arc length over the
    window. Unstretched."""
    xy = np.stack([np.asarray(course.x, dtype=np.float64), np.asarray(course.y, np.float64)])
    arc = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(xy, axis=1)))])
    # on segments about SEGMENT hull lengths long, their knots at times on an absolute lattice
    # (the same as the window slides on), the oldest and newest samples kept, and one `ahead` m
    # on
    t = np.asarray(course.times, dtype=np.float64)
    span = max(t[-1] - t[0], 1e-9)
    fastest = max(float(u.max()) if len(u) else 0.0, SLOWEST)
    period = KNOT * 2.0 ** np.round(np.log2(max(
        SEGMENT * course.length / fastest, span / MOST_SEGMENTS, KNOT) / KNOT))
    knots = np.flatnonzero(np.abs(t / period - np.round(t / period)) * period < 1e-6)
    keep = np.unique(np.concatenate([[0], knots, [len(arc) - 1]]))
    a, arc_k = xy[:, keep], arc[keep]
    heading = a[:, -1] - a[:, -2] if a.shape[1] > 1 else np.array([1.0, 0.0])
    heading = heading / max(np.hypot(*heading), 1e-9)
    a = np.concatenate([a, (a[:, -1] + heading * ahead)[:, None]], axis=1)
    arc_k = np.append(arc_k, arc[-1] + ahead)
    start, seg = a[:, :-1, None], np.diff(a, axis=1)[:, :, None]
    length2 = np.maximum((seg * seg).sum(axis=0), 1e-12)
    p = np.asarray(points, dtype=np.float64)[:, None, :]  # (2, segments, points)
    f = np.clip(((p[0] - start[0]) * seg[0] + (p[1] - start[1]) * seg[1]) / length2, 0.0, 1.0)
    dx, dy = p[0] - start[0] - f * seg[0], p[1] - start[1] - f * seg[1]
    k = np.argmin(dx * dx + dy * dy, axis=0)
    cols = np.arange(p.shape[2])
    along = arc_k[k] + f[k, cols] * np.sqrt(length2[k, 0])
    n = (seg[0, k, 0] * dy[k, cols] - seg[1, k, 0] * dx[k, cols]) / np.sqrt(length2[k, 0])
    u_at = (np.interp(along, 0.5 * (arc[1:] + arc[:-1]), u) if len(u)
            else np.zeros_like(along))
    return arc[-1] - along, n, u_at, float(arc[-1])


def heights(course, points):
    """The wake's heights (m) of `course` now at world points (2, ...) (`read`)."""
    return read(course, points)[0]


def read(course, points, foam=False):
    """(heights, active, residual) of `course`'s wake now at world points (2, ...): the
    heights (m) of its hull's steady wake read at each point's stretched place along and
    across the course, faded out over the oldest wakes.TAPER of the course's arc (the
    window's end); with `foam`, its foam's shares in [0, 1] (`stern_foam`), else None each.
    The places are found on a raster of cells SEGMENT hull lengths wide over the wake
    (`places`) and read bilinearly (exact on a straight course, where they are linear; n is
    signed so it is across the track too); points in no cell the wedge reaches are left
    out."""
    points = np.asarray(points, dtype=np.float64)
    flat = points.reshape(2, -1)
    u, rms = speeds(course)
    out = np.zeros(flat.shape[1], np.float32)
    shares = [np.zeros_like(out), np.zeros_like(out)] if foam else [None, None]
    done = (out.reshape(points.shape[1:]), *(None if v is None else v.reshape(
        points.shape[1:]) for v in shares))
    if rms < MOVING or not flat.size:
        return done
    u_ref = reference_speed(course, rms)
    sigma = hull(course.length, course.beam, u_ref)[0]
    # how far across the wake reaches (ACROSS far sigmas where the hull went fastest) and
    # ahead of the hull
    reach = ACROSS * FAR * sigma * min((u.max() / u_ref) ** 2, 4.0) * RUNG
    ahead = 0.5 * course.length + (AHEAD + PATCH * CELL) * sigma  # the bow's wave and more
    cell = 2.0 ** np.ceil(np.log2(max(SEGMENT * course.length, (
        np.ptp(course.x) + np.ptp(course.y) + 2.0 * reach) / MOST_CELLS)))  # (steady as it moves)
    lo = np.array([min(course.x), min(course.y)]) - reach - ahead - 2.0 * cell
    hi = np.array([max(course.x), max(course.y)]) + reach + ahead + 2.0 * cell
    within = np.flatnonzero((flat[0] > lo[0]) & (flat[0] < hi[0]) & (flat[1] > lo[1])
                            & (flat[1] < hi[1]))
    if not within.size:
        return done
    p = flat[:, within]
    lo = np.floor(p.min(axis=1) / cell - 1.0) * cell  # on a lattice: the same for any view
    shape = tuple(np.ceil((p.max(axis=1) + cell - lo) / cell).astype(int)[::-1] + 1)
    fields, alive, arc = places(course, u, lo, cell, shape, ahead, sigma)
    ci, cj = (p[0] - lo[0]) / cell, (p[1] - lo[1]) / cell
    keep = alive[cj.astype(np.intp), ci.astype(np.intp)]
    within, ci, cj = within[keep], ci[keep], cj[keep]
    xi, eta, stretch, slow, since = bilinear(fields, ci, cj)
    across = np.abs(eta) * slow
    taper = np.clip((arc - xi) / max(wakes.TAPER * arc, 1e-9), 0.0, 1.0)
    got = np.zeros(len(within), np.float32)
    kept = None  # how much of the near wake each point reads (the far wake the rest)
    for widen in (1.0, FAR):
        sigma, patches, peak = hull(course.length, course.beam, u_ref, widen)
        ladder = rungs(u_ref, sigma)
        if not ladder:
            break
        total = sum(w for _, w in ladder)
        at = np.arange(len(within)) if kept is None else np.flatnonzero(kept < 1.0)
        rest = None if kept is None else (1.0 - kept[at]).astype(np.float32)
        here, wide = stretch[at], across[at]
        fade = np.zeros(len(at), np.float32)
        for rung, weight in ladder:
            scale = RUNG ** (2 * rung) * GRAVITY / CELL  # U_rung^2 / sigma per s^2/m, in cells
            if kept is None:  # the near wake's own fade (`steady`), weighted as it is read
                fade += np.float32(weight / total) * np.clip(
                    (BEHIND - scale * CELL * here) / FADE, 0.0, 1.0)
            table, xi0 = hull_wake(rung, round(patches, 3))
            i = scale * here - xi0 / CELL
            j = scale * wide
            inside = np.flatnonzero((i >= 0.0) & (i < table.shape[0] - 1)
                                    & (j < table.shape[1] - 1))
            part = np.float32(weight * peak) * bilinear(table, j[inside], i[inside])
            got[at[inside]] += part if rest is None else part * rest[inside]
        if kept is None:
            kept = fade
    out[within] = got * (taper * course.draft).astype(np.float32)
    if foam:
        parts = stern_foam(course, u_ref, xi, eta, since)
        white = whiteness(course, u_ref)
        beside = np.abs(eta) > 0.5 * course.beam + BOW_ANGLE * np.maximum(
            xi + 0.5 * course.length, 0.0)  # its divergent crests, not the transverse ones
        bow = white * np.clip(got / BOW_CREST - 1.0, 0.0, 1.0) * (
            xi < BOW_REACH * course.length) * beside
        parts = (np.maximum(parts[0], bow), parts[1])
        for share, part in zip(shares, parts, strict=True):
            share[within] = part * taper
    return done


def places(course, u, lo, cell, shape, ahead, sigma):
    """The course's places on the raster of cells `cell` wide from `lo` of (rows, columns)
    `shape`: (fields, alive, arc): fields (5, rows, columns) of xi, n (`follow`), the stretch
    (arc / U^2 summed from the hull back, s^2 / m; ahead, xi / U_now^2), 1 / U^2 where the
    point's place was passed and the time since the stern passed it (s); which cells (and
    their neighbours) the wake may reach (ahead of the hull to the course's start, within
    WEDGE of the track beside it); and the course's arc length (m)."""
    ny, nx = shape
    gx, gy = np.meshgrid(lo[0] + cell * np.arange(nx), lo[1] + cell * np.arange(ny))
    xi, n, u_at, arc = follow(course, u, np.stack([gx.ravel(), gy.ravel()]), ahead)
    t = np.asarray(course.times, dtype=np.float64)
    dt = np.diff(t)
    per = np.maximum(u, SLOWEST) ** -2.0 * u * dt
    behind = np.concatenate([np.cumsum(per[::-1])[::-1], [0.0]])
    arc_at = np.concatenate([[0.0], np.cumsum(u * dt)])
    stretch = np.where(xi > 0.0, np.interp(arc - xi, arc_at, behind),
                       xi / max(speed_now(course), SLOWEST) ** 2)
    since = t[-1] - np.interp(arc - xi + 0.5 * course.length, arc_at, t)
    fields = np.stack([xi, n, stretch, np.maximum(u_at, SLOWEST) ** -2.0, since])
    reached = ((xi > -ahead - cell) & (xi < arc + cell) & (
        np.abs(n) < WEDGE * np.maximum(xi, 0.0) + MARGIN * FAR * sigma + cell)).reshape(shape)
    alive = reached.copy()
    alive[1:] |= reached[:-1]
    alive[:-1] |= reached[1:]
    alive[:, 1:] |= alive[:, :-1].copy()
    alive[:, :-1] |= alive[:, 1:].copy()
    return fields.reshape(5, ny, nx).astype(np.float32), alive, arc


def whiteness(course, u_ref):
    """How much of its wake a hull at U_ref breaks white: none below the hull Froude number
    U / sqrt(g L) FOAM_FROUDE[0], all of it from FOAM_FROUDE[1]."""
    froude = u_ref / np.sqrt(GRAVITY * course.length)
    return float(np.clip((froude - FOAM_FROUDE[0]) / (FOAM_FROUDE[1] - FOAM_FROUDE[0]), 0, 1))


def stern_foam(course, u_ref, xi, eta, since):
    """(active, residual) foam shares of the turbulent wake behind the stern at points `xi`
    behind the hull's centre and `eta` across its course, passed by the stern `since` s ago:
    white behind a hull fast enough to break the water (`whiteness`), across a band BEAMS wide that
    spreads as the square root of its age, fresh foam decaying over ACTIVE_DECAY s into
    residual foam that decays over RESIDUAL_DECAY (Callaghan et al. 2012: a whitecap's foam
    decays over seconds, its residual longer)."""
    white = whiteness(course, u_ref)
    if white == 0.0:
        return np.zeros(len(xi), np.float32), np.zeros(len(xi), np.float32)
    age = np.maximum(since, 0.0)
    half = 0.5 * BEAMS * course.beam * np.sqrt(1.0 + age / SPREAD)
    band = white * np.exp(-0.5 * (eta / half) ** 2) * (since > 0.0) * np.clip(
        (xi - 0.4 * course.length) / (0.2 * course.length), 0.0, 1.0)
    return ((band * np.exp(-age / ACTIVE_DECAY)).astype(np.float32),
            (band * np.exp(-age / RESIDUAL_DECAY)).astype(np.float32))
