"""Foam (NumPy only): whitecaps on the crests (Jensen and Golias) covering the share of the sea
the wind whitecaps (Monahan and Mac Niocaill, Fleck Eq. 32: effects.whitecap_coverage), and
contact foam around objects that cross the surface.

The crest threshold is the value of the source's fold cue exceeded by that share of the sea,
calibrated every FOAM_PERIOD seconds over each band's fade-in, so foam is a function of the
frame alone (a farm splitting frames renders the same foam)."""

import numpy as np

from . import made_once, past_grid, residual_foam, streaks
from .cascade import wind_lattice
from .effects import FOAM_MIN_COVERAGE, whitecap_coverage

# Added to a whitecap threshold where the sea has no wave to foam: out of any cue's reach.
NO_FOAM = 1e6
FOAM_PERIOD = 1.0  # seconds between the foam's calibrations (foam_thresholds)
FOAM_SOFTNESS = 1.0  # a whitecap's ramp at full detail, in the cue's standard deviations

# A linear ramp this many standard deviations wide has the slope of the normal distribution's
# CDF at its middle (sqrt(2 pi)): the share of a vertex that the waves it leaves out foam.
UNRESOLVED_RAMP = 2.5

# m: waves longer than this make whitecaps a vertex should place; the foam of shorter ones is
# the shader's grain (as the shader's WHITECAP: beyond it a pixel shows the mean cover).
WHITECAP_WAVE = 8.0


def sea_sample(span, samples=4096):
    """x, y of a fixed pattern of `samples` points over a square `span` metres across: a
    rotated lattice, which spreads them over the square without lining up with a texture."""
    n = int(np.sqrt(samples))
    k = (np.arange(n) + 0.5) / n
    gx, gy = np.meshgrid(k, k)
    return ((gx + 0.37 * gy) % 1.0 * span).ravel(), ((gy + 0.61 * gx) % 1.0 * span).ravel()


def foam_thresholds(source, time, coverage, samples=16384, kept=None):
    """Whitecap thresholds of a height source's foam cue (its `foam_cue`: the height for the
    noise, how far the choppy surface folds for the spectrum), at each of its band limits
    (`foam_levels`): on a fixed pattern of sea points, the mean foam is `coverage` at the
    band limit they are evaluated with, so a vertex's foam covers the wind's share of the sea
    whatever detail its geometry holds (Jensen and Golias put foam where the surface is high
    or folds; Monahan and Mac Niocaill give how much). Above the whitecaps' level
    (`whitecap_level`) the cue is of the waves it keeps, over the finer spacing (a fine grid's
    differences see more of their folding). Returns (levels, thresholds, widths): each the
    width of the ramp the foam rises over (`whitecaps`).

    The sources' statistics drift with time (the noise's octaves move through their lattices;
    the spectrum's tiles hold finitely many waves, whose rare folds come and go: one threshold
    for all times let the cover drift between 0.55 and 1.6 times the coverage). So it is
    calibrated every FOAM_PERIOD seconds (`calibration`, kept in `kept`: CALIBRATIONS by
    default) and interpolated between: a frame is a function of the settings and its time."""
    kept = CALIBRATIONS if kept is None else kept
    coverage = min(max(float(coverage), 1e-6), 1.0)
    t0 = float(np.floor(time / FOAM_PERIOD) * FOAM_PERIOD)
    a, b = (kept.get(source, (t, coverage, samples)) for t in (t0, t0 + FOAM_PERIOD))
    f = (time - t0) / FOAM_PERIOD
    return a[0], (1.0 - f) * a[1] + f * b[1], (1.0 - f) * a[2] + f * b[2]


def ahead_times(time):
    """The starts of the next two FOAM_PERIODs after `time`: the calibrations a sequence
    playing there needs next are theirs."""
    t0 = float(np.floor(time / FOAM_PERIOD) * FOAM_PERIOD)
    return tuple(t0 + k * FOAM_PERIOD for k in (1, 2))


def ahead(time, coverage, samples=16384):
    """The calibrations (their keys: time, coverage, samples) of `ahead_times`."""
    coverage = min(max(float(coverage), 1e-6), 1.0)
    return [(t, coverage, samples) for t in ahead_times(time)]


class Calibrations(made_once.MadeOnce):
    """The whitecap calibrations made, kept per height source (which the plan keeps per
    settings: frame_plan.height_source) and per (time, coverage, samples): KEPT a source, the
    oldest made dropped first (made_once.MadeOnce: made once across threads, the Blender
    layer's worker making some ahead)."""

    KEPT = 4  # the frame's two and two ahead

    def get(self, source, key):
        """The calibration of `source` at `key`, made here if nobody has or is making it (on
        a twin where it has one: the source keeps no fields of it)."""
        return self.made(source, key, lambda: calibration(
            getattr(source, "twin", lambda: source)(), *key))


CALIBRATIONS = Calibrations()


def calibration(source, time, coverage, samples, pause=None):
    """One calibration of `source` at `time` (see foam_thresholds): (levels, thresholds,
    widths), a function of the source's settings and the time alone. `pause`, called before
    each level's cue is taken: a worker making it ahead waits there while a frame is built."""
    x, y = sea_sample(source.foam_span, samples)
    xy = np.stack([x, y])
    levels = np.asarray(source.foam_levels(), dtype=np.float64)
    placed = whitecap_level(source)
    cues = []
    for level in levels:
        if pause is not None:
            pause()
        cues.append(crest_cue(source, xy, time, np.full(x.shape, level, np.float32)))
    spreads = np.array([float(cue.std()) for cue in cues])
    whole = float(np.interp(placed, levels, spreads))
    widths = _ramp_widths(spreads, whole)
    thresholds = []
    for cue, spread, width in zip(cues, spreads, widths, strict=True):
        # no wave here, nor any whitecap-long (WHITECAP_WAVE) for the ramp to stand for: no
        # foam (a light air's, whose share is below FOAM_MIN_COVERAGE anyway)
        if max(spread, whole) <= 1e-9 * (1.0 + float(np.abs(cue).max())):
            thresholds.append(float(cue.max()) + NO_FOAM)
        else:  # the threshold whose foam, ramp and all, covers `coverage` of the pattern
            thresholds.append(_covering(cue, coverage, width))
    return levels, np.array(thresholds), widths


def whitecap_level(source):
    """The band limit from which the waves whitecaps break on (longer than WHITECAP_WAVE) are
    whole, within the calibrated levels: vertices finer than that take their cue there, so
    a whitecap is a patch as large as its breaker, not the shorter waves' folds; their foam
    is the shader's grain."""
    levels = source.foam_levels()
    return float(np.clip(source.whole_level(WHITECAP_WAVE), levels[0], levels[-1]))


def crest_cue(source, xy, time, lod):
    """The whitecaps' cue at points `xy` apart of band limit `lod` (None: every band whole), as
    a frame's vertices take it (`foam_field`): finer than `whitecap_level`, of the waves it
    keeps alone over the points' own spacing (seeing more of their folding than its)."""
    return source.foam_cue(xy, time, lod, band=whitecap_level(source))


def _ramp_widths(spreads, placed):
    """The width of each level's foam ramp: FOAM_SOFTNESS of the cue's spread there, widened
    by the spread of the waves longer than WHITECAP_WAVE the level leaves out (`placed`, the
    cue's spread with them whole, less the level's own, the two independent), so a vertex
    holding only the long waves gets the share of its area the shorter ones would foam,
    rising smoothly on the long waves' crests, not a whole whitecap along each long crest."""
    unresolved = np.sqrt(np.maximum(placed * placed - spreads * spreads, 0.0))
    widths = np.hypot(FOAM_SOFTNESS * spreads, UNRESOLVED_RAMP * unresolved)
    return np.where(widths > 0.0, widths, 1.0)


def _covering(cue, coverage, width):
    """The threshold at which the mean of `whitecaps` over the sample `cue` is `coverage`."""
    lo, hi = float(cue.min()) - width, float(cue.max()) + width
    for _ in range(40):  # bisection: the mean foam falls as the threshold rises
        mid = 0.5 * (lo + hi)
        if np.clip((cue - mid) / width + 0.5, 0.0, 1.0).mean() > coverage:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def whitecaps(cue, lod, calibration):
    """Per-vertex foam in [0, 1], the share of the sea there whitecaps cover, from the cue at
    the vertices and `foam_thresholds`: rising from 0 to 1 across the vertex's threshold over
    the ramp's width, centred on it, so the mean foam over the sea is the coverage. `lod`
    None: every band, whole."""
    return at_thresholds(lod, calibration)(cue)


def at_thresholds(lod, calibration):
    """`whitecaps` of points of band limit `lod` as a function of their cue: the thresholds
    and widths at `lod` looked up once, for cues of several times at the same points."""
    levels, thresholds, widths = calibration
    if lod is None:
        t, width = np.float32(thresholds[-1]), np.float32(widths[-1])
    else:
        lod = np.asarray(lod, dtype=np.float64).ravel()
        t = np.interp(lod, levels, thresholds).astype(np.float32)
        width = np.interp(lod, levels, widths).astype(np.float32)

    def foam(cue):
        out = np.subtract(np.asarray(cue, dtype=np.float32).ravel(), t, dtype=np.float32)
        out /= width
        out += np.float32(0.5)
        return np.clip(out, 0.0, 1.0, out=out)
    return foam


def crest_calibration(source, time, wind_speed, parts=None):
    """(level, thresholds): the band limit the whitecaps' cue is taken at where the grid is
    finer (`whitecap_level`) and the thresholds calibrated for the active whitecaps' share at
    `time` (`foam_thresholds`), of the seas `calibrated_at` gives, interpolated (`parts`:
    their `calibrated_seas`, if the caller has them)."""
    parts = calibrated_seas(source, time, wind_speed) if parts is None else parts
    if len(parts) == 1:
        return whitecap_level(source), parts[0][1]
    levels = np.asarray(source.foam_levels(), dtype=np.float64)
    thresholds, widths = (sum(weight * np.interp(levels, made[0], made[k])
                              for _, made, weight in parts) for k in (1, 2))
    return whitecap_level(source), (levels, thresholds, widths)


def calibrated_seas(source, time, wind_speed):
    """((sea, its `foam_thresholds` at `time`, weight), ...) of the seas `calibrated_at`
    gives."""
    return [(sea, foam_thresholds(sea, time, active_coverage(sea, wind)), weight)
            for sea, wind, weight in calibrated_at(source, wind_speed)]


def calibrated_at(source, wind_speed):
    """The seas a source's whitecaps are calibrated on, each (sea, its wind, weight): the
    source under a steady wind; under a keyed wind (a spectral sea laid out for its
    `wind_span`: each frame a sea of its own) the same sea at the winds about it of the keyed
    sea's lattice (cascade.wind_lattice), weighted as its waves are: frames share their
    calibrations, the thresholds change continuously, the share within 3 % (test)."""
    span = getattr(source, "wind_span", None)
    if span is None or wind_speed <= 0.0:
        return ((source, wind_speed, 1.0),)
    return tuple((source.at_wind(wind), wind, weight) for wind, weight in wind_lattice(wind_speed))


def foam_coverage(wind_speed):
    """The share of the sea whitecaps cover at `wind_speed`, active and residual together."""
    return min(max(whitecap_coverage(wind_speed), FOAM_MIN_COVERAGE), 1.0)


def active_coverage(source, wind_speed):
    """The share of the sea the active whitecaps (stage A) are calibrated to cover: the
    coverage's active part (residual_foam.active_share), the rest their residual foam's."""
    return foam_coverage(wind_speed) * residual_foam.active_share(
        residual_foam.decay_time(source))


def foam_look(source, wind_speed):
    """The water group's foam inputs (water_model.values): the mean share of the sea the
    active whitecaps cover (`active_coverage`); of the rest, their residual foam, the young
    foam's placed at the points and the aged foam's drawn in streaks
    (streaks.streak_share); the streaks' stretch along the wind (streaks.foam_streak); and the
    share the wind's blown streaks cover besides (streaks.blown_coverage)."""
    active = active_coverage(source, wind_speed)
    residual = foam_coverage(wind_speed) - active
    aged = residual * streaks.streak_share(wind_speed)
    return (active, residual - aged, aged, streaks.foam_streak(wind_speed),
            streaks.blown_coverage(wind_speed))


def contact_foam(x, y, z, boxes, width):
    """Per-vertex foam in [0, 1] around boxes crossing the water: 1 at a box, fading to 0 at
    `width` metres from it. Points and box corners are world space relative to one origin.
    The distance is to the box itself, in its own frame: Blender's bound_box corners 0, 4, 3, 1
    are its origin and its x, y, z edges, which stay orthogonal under rotation and scale. All
    boxes at once (`_near_boxes`); a point keeps its nearest box's foam."""
    width = max(float(width), 1e-6)
    p = np.stack([np.ravel(x), np.ravel(y), np.ravel(z)], axis=-1).astype(np.float64)
    foam = np.zeros(len(p), dtype=np.float32)
    boxes = np.asarray(boxes, dtype=np.float64).reshape(-1, 8, 3)
    if not len(boxes) or not len(p):
        return foam
    lo = boxes[:, :, :2].min(axis=1) - width
    hi = boxes[:, :, :2].max(axis=1) + width
    point, box = _near_boxes(p[:, :2], lo, hi)
    if not len(point):
        return foam
    q = p[point]
    origin = boxes[box, 0]
    edges = boxes[box][:, [4, 3, 1]] - origin[:, None]  # (K, 3, 3)
    length2 = np.einsum("kij,kij->ki", edges, edges)
    t = np.einsum("kj,kij->ki", q - origin, edges) / np.where(length2 > 0.0, length2, 1.0)
    nearest = origin + np.einsum("ki,kij->kj", np.clip(t, 0.0, 1.0), edges)
    near = np.clip(1.0 - np.linalg.norm(q - nearest, axis=-1) / width, 0.0, 1.0)
    np.maximum.at(foam, point, (near * near).astype(np.float32))
    return foam


def _near_boxes(xy, lo, hi):
    """(point, box) index pairs of the points `xy` (N, 2) inside each box's rectangle [lo, hi]
    (M, 2): the points within the rectangles' extent are binned on a grid of cells as large as
    the typical rectangle and sorted by cell, so each box visits the runs of cells it covers, a
    column at a time."""
    within = np.flatnonzero(((xy >= lo.min(axis=0)) & (xy <= hi.max(axis=0))).all(axis=1))
    if not len(within):
        return within, within
    xy = xy[within]
    cell = max(float(np.median(hi - lo)), 1e-6)
    origin = xy.min(axis=0)
    ij = np.floor((xy - origin) / cell).astype(np.int64)
    rows = int(ij[:, 1].max()) + 3
    key = ij[:, 0] * rows + ij[:, 1]
    order = np.argsort(key, kind="stable")
    key = key[order]
    top = [int(ij[:, 0].max()) + 1, rows - 2]  # past the last column and row: no points
    a = np.floor((lo - origin) / cell).astype(np.int64).clip(-1, top)
    b = np.floor((hi - origin) / cell).astype(np.int64).clip(-1, top)
    columns = np.maximum(b[:, 0] - a[:, 0] + 1, 0)
    box = np.repeat(np.arange(len(lo)), columns)
    column = np.repeat(a[:, 0] - np.cumsum(columns) + columns, columns) + np.arange(columns.sum())
    start = np.searchsorted(key, column * rows + a[box, 1], "left")
    counts = np.maximum(np.searchsorted(key, column * rows + b[box, 1], "right") - start, 0)
    box = np.repeat(box, counts)
    point = order[np.repeat(start - np.cumsum(counts) + counts, counts) + np.arange(counts.sum())]
    inside = ((xy[point] >= lo[box]) & (xy[point] <= hi[box])).all(axis=1)
    return within[point[inside]], box[inside]


CONTACT_FOAM_REACH = 0.5  # metres of foam around an object, beyond the waves' own height


def contact_foam_width(bound):
    """How far contact foam reaches from an object: half a metre plus the waves' bound."""
    return CONTACT_FOAM_REACH + bound


def foam_field(source, result, time, wind_speed, crests, boxes, level, dolly=False):
    """Per-vertex foam of a frame in [0, 1]: (active, residual), either None when off. Active:
    whitecaps breaking now (when `crests`; `whitecaps`, stage A) and rings around the `boxes`
    crossing the water (contact foam), combined by their maximum; residual: the patches the
    whitecaps of the past seconds left (residual_foam, stage B; for a `dolly` camera, its past
    on canonical cameras' grids, past_grid; under a keyed wind, of the lattice winds' seas
    `calibrated_at` gives, whose tiles at the past times frames share). `result` is the
    frame's GridResult: the cue is taken at its grid points before any choppy displacement,
    from the grid itself where the source asks for it (the spectrum's folding: its `crest`)."""
    foam = residual = None
    surface = result.surface
    if crests:
        xy = result.base if result.base is not None else np.stack(surface[:2])
        lods = result.lod.reshape(xy.shape[1:])
        seas = calibrated_seas(source, time, wind_speed)
        placed, thresholds = crest_calibration(source, time, wind_speed, seas)
        # The cue of the waves `placed` keeps, its thresholds those over the points' spacing
        # (foam_thresholds): without a crest sum, sampled again where some vertex is finer,
        # at every other point each way (a band limit one lower everywhere).
        if result.crest is not None and result.crest[0] == placed:
            foam = whitecaps(source.grid_cue(xy, result.crest[1]), lods, thresholds)
        elif lods.max() > placed:
            foam = residual_foam.on_coarse(lambda points, at: whitecaps(
                residual_foam.cue_at(source, points, time, at, placed), at, thresholds),
                xy, lods, 1)
        else:
            foam = whitecaps(source.foam_cue(xy, time, lods, grid=surface[:2]), lods, thresholds)
        grid = residual_foam.grid_key(result)
        kept = (1.0 - streaks.streak_share(wind_speed)) / (1.0 - residual_foam.aged_share())
        residual = sum(weight * past_grid.residual_foam(
            sea, result, xy, lods, time, lambda at, made=made: at_thresholds(at, made),
            residual_foam.decay_time(sea), grid, kept, placed, dolly=dolly)
            for sea, made, weight in seas)
    if len(boxes):
        x, y, h = surface
        ring = contact_foam(x, y, h + level, boxes, contact_foam_width(source.bounds(time)[0]))
        foam = ring if foam is None else np.maximum(foam, ring)
    return foam, residual
