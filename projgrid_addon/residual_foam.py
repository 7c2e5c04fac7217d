"""Residual whitecap foam (stage B, Monahan and Lu 1990): the patches an active breaker (stage A,
foam.whitecaps) leaves on the water, fading exponentially as their bubbles rise and burst
(Callaghan, Deane, Stokes and Ward 2012: area decay times of 0.5 to 8 s, three to four times
longer for bigger breakers).

A pure function of the settings and the time, never state carried from frame to frame. Active
foam of share A at a point lays residual foam at the rate A / T_A (T_A how long a breaker stays
active), each patch fading as e^(-age / tau), so the residual share there is

    R(t) = integral over ages a of A(t - a) / T_A e^(-a / tau) da        (at most 1)

summed over a past window on an absolute time lattice (a third of tau apart; consecutive
frames share the samples), at the frame's grid points before the choppy displacement: the
water's own points, which the waves carry back and forth, so foam stays with the water it
fell on. A patch active for T_A leaves R = 1 and fades; a sea whose active share is W_A
everywhere has R = W_A tau / T_A. So the active share is the part of Monahan's coverage W that
breakers are active for, W T_A / (T_A + tau), the residual the rest (tests/core/test_foam.py
measures the sum).

Only the young foam, WINDOW decay times, is placed at the points; the older, e^-WINDOW of the
residual (`aged_share`), has drifted and spread from where it fell by then, and is drawn where
the wind gathers it, in streaks along it (the shader's, water_model.foam_cover)."""

import hashlib
import threading
import weakref
from collections import OrderedDict
from functools import lru_cache

import numpy as np

from . import spectrum
from .band_limit import every_other_of, every_other_shape, fill_every_other
from .cascade import SIDEWAYS

SAMPLES_PER_DECAY = 3.0  # past samples per decay time (an absolute lattice of step tau / 3)
ACTIVE_TIME = 0.7  # s a breaker stays active (stage A)
WINDOW = 2.0  # decay times of history placed at the points, tapered out over the last step
DECAY_PER_ROOT_METRE = 0.25  # s: tau = this sqrt(breaking wavelength), within DECAY_RANGE
DECAY_RANGE = (0.5, 8.0)  # s, Callaghan et al. 2012's range
COARSE = 2  # the past is taken at every other point each way, twice over (on_coarse)


def decay_time(source):
    """tau (s) of the source's residual foam: longer for longer breakers, as the square root
    of its peak wavelength (the spectrum's wind sea, the noise's first octave)."""
    state = getattr(source, "state", None)
    wavelength = (spectrum.peak_wavelength(state) if state is not None
                  else source.wavelength(0))
    return float(np.clip(DECAY_PER_ROOT_METRE * np.sqrt(max(wavelength, 0.0)), *DECAY_RANGE))


def active_share(tau):
    """The share of the whitecap coverage that is active breaking: T_A / (T_A + tau)."""
    return ACTIVE_TIME / (ACTIVE_TIME + tau)


def aged_share():
    """The share of the residual foam older than the window: e^-WINDOW."""
    return float(np.exp(-WINDOW))


def samples(time, tau):
    """The past samples (time, weight) at `time` for R's integral: the lattice times within
    WINDOW tau before it, tau / SAMPLES_PER_DECAY apart, each weighted by its share of the
    integral (step / T_A e^(-age / tau)), ramped in over its first step of age and out over
    the window's last, so the foam changes continuously as samples enter and leave, and
    scaled so a steady A lays the window's R = A tau / T_A (1 - `aged_share`) on average over a
    step (within 2 %). The weights are functions of the ages alone: a patch fades without
    pulsing."""
    reach, step = WINDOW * tau, tau / SAMPLES_PER_DECAY
    scale = tau * (1.0 - aged_share()) / ACTIVE_TIME / _laid(step, tau)
    last = int(np.floor(time / step))
    out = []
    for k in range(int(np.ceil(reach / step)) + 1):
        when = (last - k) * step  # the same float for a lattice point whatever the frame
        age = time - when
        weight = np.exp(-age / tau) * min(age / step, 1.0, max((reach - age) / step, 0.0))
        if weight > 0.0:
            out.append((when, float(weight * step * scale)))
    return out


@lru_cache(maxsize=64)  # the same few decay times every frame
def _laid(step, tau):
    """The weights' sum, e^(-age / tau) over the samples, ramps and all, times the step: its
    mean over where `time` falls within a step (its swing over a step is under 2 %)."""
    reach = WINDOW * tau
    total = 0.0
    for phase in (np.arange(16) + 0.5) / 16.0 * step:
        ages = phase + step * np.arange(int(np.ceil(reach / step)) + 1)
        ramp = np.minimum(np.minimum(ages / step, 1.0), np.clip((reach - ages) / step, 0.0, None))
        total += float(np.sum(np.exp(-ages / tau) * ramp)) * step / 16.0
    return total


def cue_at(source, xy, time, lod, top=None):
    """The source's foam cue at time `time` at grid points `xy` (2, rows, columns, before any
    choppy displacement), its folding taken from the grid the points make at that time, of
    the waves band limit `lod` keeps, at most `top`'s; for a tuple of times, their cues (the
    points located in the sea's tiles once for all)."""
    if top is not None:
        lod = np.minimum(lod, np.float32(top))
    times = time if isinstance(time, tuple) else (time,)
    if hasattr(source, "grid_cue"):  # the spectrum's: its folding, on the grid
        cues = [source.grid_cue(xy, shift)
                for shift in source.sample(xy, times, lod, SIDEWAYS, on_grid=True)]
    else:
        cues = [source.foam_cue(xy, t, lod) for t in times]
    return cues if isinstance(time, tuple) else cues[0]


_NONE = object()  # a key not kept (a kept value may be None)


class Kept:
    """Values of pure functions of a source and a key, kept per source (the `kept` newest
    made): a still camera's past cues (PAST), the spray's launches (spray.LAUNCHES, GATHERED).
    A cache of pure functions: never changes what is drawn."""

    def __init__(self, kept):
        self.kept = kept
        self._kept = weakref.WeakKeyDictionary()
        self._lock = threading.Lock()

    def get(self, source, keys, make):
        """The values of `keys`, those not kept made by `make(missing keys)`."""
        with self._lock:
            kept = self._kept.setdefault(source, OrderedDict())
            hits = {key: kept.get(key, _NONE) for key in keys}
        missing = [key for key, hit in hits.items() if hit is _NONE]
        if missing:
            hits.update(zip(missing, make(missing), strict=True))
            with self._lock:
                for key in missing:
                    kept[key] = hits[key]
                while len(kept) > self.kept:
                    kept.popitem(last=False)
        return [hits[key] for key in keys]


PAST = Kept(48)  # past cues on a grid, by (grid, time)


def grid_key(result):
    """Bytes naming a frame's grid points (what they are a function of: the projector, its
    span, the columns and rows, the origin), or None for a grid without a projector."""
    projector = getattr(result, "projector", None)
    if projector is None or getattr(result, "spacing", None) is None:
        return None
    return b"".join(np.ascontiguousarray(a, np.float64).tobytes() for a in (
        projector.view, projector.span, *result.spacing, result.origin, result.extent.lower,
        result.extent.upper, result.extent.side, result.resolution))


def coarse_points(xy, lod, steps, top=None):
    """Every other grid point each way `steps` times over (band_limit.every_other_of): (the
    points (2, ...), their band limit `steps` lower, at most `top` (None without `lod`), the
    shapes from `xy`'s (rows, columns) down, for `spread`)."""
    shapes = coarse_shapes(xy.shape[1:], steps)
    points, at = xy, None if lod is None else np.asarray(lod, np.float32).reshape(shapes[0])
    for shape in shapes[1:]:
        points = every_other_of(points, np.empty((2, *shape)))
        if at is not None:
            at = every_other_of(at, np.empty(shape, np.float32))
    if at is not None:
        at = at - np.float32(steps)
        if top is not None:
            at = np.minimum(at, np.float32(top))
    return points, at, shapes


def coarse_shapes(shape, steps):
    """The shapes from a grid's (rows, columns) to its points every other `steps` times over."""
    shapes = [tuple(shape)]
    for _ in range(steps):
        shapes.append(every_other_shape(shapes[-1]))
    return shapes


def spread(values, shapes):
    """Values at `coarse_points` spread linearly back over all the grid's points: float32, flat."""
    out = np.asarray(values, np.float32).reshape(shapes[-1])
    for shape in reversed(shapes[:-1]):
        out = fill_every_other(out, np.zeros(shape, np.float32))
    return out.ravel()


def on_coarse(make, xy, lod, steps, top=None):
    """`make(points, lod)`, per-point values at the points given, taken at `coarse_points`
    (4^-steps of the points, 2^steps their spacing, so a band limit `steps` lower, at most
    `top`) and spread linearly back over all of `xy`'s (2, rows, columns) points: float32,
    flat."""
    points, at, shapes = coarse_points(xy, lod, steps, top)
    return spread(make(points, at), shapes)


def past_foam(source, points, at, time, active, tau, key, placed=1.0, top=None):
    """Stage-B foam R at `points` (2, rows, columns; `at` their band limit) at `time`,
    unclipped (float32 (rows, columns)): `residual`'s sum over the past samples, each
    sample's cue kept under (`key`, its time) (PAST)."""
    foam_of = active(at)
    out = np.zeros(points.shape[1:], np.float32)
    past = samples(time, tau)
    cues = PAST.get(source, [(key, when) for when, _ in past], lambda missing: cue_at(
        source, points, tuple(w for _, w in missing), at, top))
    for cue, (_, weight) in zip(cues, past, strict=True):
        out += foam_of(cue).reshape(out.shape) * np.float32(weight * placed)
    return out


def residual(source, xy, lod, time, active, tau, grid=None, placed=1.0, top=None):
    """Stage-B foam R in [0, 1] at grid points `xy` (2, rows, columns; `lod` their band limit)
    at `time`, from the active foam of the past samples (`samples`): `active(lod)` gives the
    function from a cue at points of band limit `lod` to their whitecaps, by the frame's own
    thresholds (a past sample's foam is the share of its cue over the threshold the frame
    calibrates, so no past second is calibrated again: the sum over the window is what the
    coverage sets). Each sample's cue is kept for the grid (PAST) under `grid`, bytes that name
    it (None: a digest of the points and their band limit); `placed` the share of the
    window's foam left at the points (the rest is drawn as streaks); `top` the band limit
    the cue's waves are taken at, at most (its thresholds still the points' own level's).

    The past cue is taken on a coarser grid (`on_coarse`, COARSE steps: a sixteenth of the
    points) and the foam spread linearly between: a patch is metres across, wider than the
    near grid's spacing, and far off, where the coarse points are tens of metres apart, the
    shader draws the sea's mean share (water_model.foam_cover)."""
    def make(points, at):
        key = grid if grid is not None else hashlib.sha1(
            points.tobytes() + np.asarray(at, np.float32).tobytes()).digest()
        return past_foam(source, points, at, time, active, tau, key, placed, top)
    full = on_coarse(make, xy, lod, COARSE)
    return np.minimum(full, 1.0, out=full)
