"""The coming seconds' whitecap calibrations, made ahead on a worker thread while the viewport
plays: a spectral calibration costs about ten frames, so made by the frame that first needs
it, playback would stall once a second. The core keeps them (foam.CALIBRATIONS) and waits for
one being made here rather than make it twice. This is our only thread; it is finished before
Blender runs long native work (a render, the bake's export), beside which none may run (one
beside the USD export crashed Blender 4.5)."""

import contextlib
import math
import threading
import weakref
from concurrent.futures import ThreadPoolExecutor

from ...projgrid_addon import foam

_POOL = []  # the worker, made when first needed
_JOBS = []  # its futures not yet finished (main thread only)
# Set while no frame is being built. The threads share the interpreter, so a worker taking
# cues beside a frame slows it as much as it works (on two cores, a keyed wind's frames 2.5x);
# it waits here between a calibration's levels instead, working between frames (the viewport
# draws them, the playback waits for the next), while a frame stalls on a calibration, and
# beside the frames once the playback is URGENT from needing the one it makes.
_IDLE = threading.Event()
_IDLE.set()
_BUILDING = [0]  # threads building a frame, not stalled
_LOCK = threading.Lock()
_LOCAL = threading.local()  # this thread's frame depth and whether it is stalled
_LATEST = weakref.WeakKeyDictionary()  # sea -> its time at the last frame handing it over
URGENT = 0.5 * foam.FOAM_PERIOD  # s


def _building(change):
    with _LOCK:
        _BUILDING[0] += change
        (_IDLE.clear if _BUILDING[0] else _IDLE.set)()


@contextlib.contextmanager
def frame():
    """Build a frame: the worker waits between levels meanwhile (nested frames count once)."""
    depth = getattr(_LOCAL, "depth", 0)
    _LOCAL.depth = depth + 1
    if not depth:
        _building(1)
    try:
        yield
    finally:
        _LOCAL.depth = depth
        if not depth:
            _building(-1)


@contextlib.contextmanager
def stalled():
    """A frame stalls on a calibration, waiting for the worker or making it itself
    (foam.CALIBRATIONS.stalled; `finish`): the worker goes on meanwhile."""
    inside = getattr(_LOCAL, "depth", 0) > 0 and not getattr(_LOCAL, "stalled", False)
    if inside:
        _LOCAL.stalled = True
        _building(-1)
    try:
        yield
    finally:
        if inside:
            _LOCAL.stalled = False
            _building(1)


foam.CALIBRATIONS.stalled = stalled


def calibrate(source, time, wind_speed, winds_ahead=()):
    """Start making the calibrations the next FOAM_PERIODs after `time` need, of the seas a
    source's are made on (foam.calibrated_at) with a `twin` to make them on (the spectrum's;
    the noise's cost little), and under a keyed wind those of the seas of `winds_ahead` (the
    wind at those times) too; returns how many started. What the worker makes is what the
    frame would (foam.calibration, a function of the settings and the time), on a twin."""
    started = 0
    _JOBS[:] = [job for job in _JOBS if not job.done()]
    seas = {id(sea): (sea, wind) for w in (wind_speed, *winds_ahead)
            for sea, wind, _ in foam.calibrated_at(source, w)}  # (a keyed wind's: two each)
    for sea, wind in seas.values():
        if getattr(sea, "twin", None) is None:
            continue
        _LATEST[sea] = float(time)
        keys = foam.CALIBRATIONS.reserve(sea, foam.ahead(time, foam.active_coverage(sea, wind)))
        for n, key in enumerate(keys):
            try:
                if not _POOL:
                    _POOL.append(ThreadPoolExecutor(1, thread_name_prefix="projgrid-foam"))
                _JOBS.append(_POOL[0].submit(_make, sea.twin(), sea, key))
            except BaseException:  # (shutting down, say): none waits for what will not be made
                for left in keys[n:]:
                    foam.CALIBRATIONS.release(sea, left)
                raise
        started += len(keys)
    return started


def _make(twin, source, key):
    """Make the calibration `key` of `source` on its `twin`, unless a frame took it over or the
    playback has passed its time (a scrub ahead: no frame needs it now)."""
    if not foam.CALIBRATIONS.start(source, key):
        return
    try:
        latest = _LATEST.get(source)
        if latest is None or key[0] >= math.floor(latest / foam.FOAM_PERIOD) * foam.FOAM_PERIOD:
            foam.CALIBRATIONS.put(source, key, foam.calibration(
                twin, *key, pause=lambda: _pause(source, key[0] - foam.FOAM_PERIOD)))
    finally:
        foam.CALIBRATIONS.release(source, key)


def _pause(source, needed):
    """Between a calibration's levels: wait while a frame is built, unless the playback of
    `source` is within URGENT of the time `needed` from which its frames need it (a frame at t
    interpolates the calibrations at floor(t) and the next): then it is made beside the frames,
    slower frames rather than one that stalls on it."""
    while not _IDLE.wait(0.05):
        latest = _LATEST.get(source)
        if latest is not None and needed - latest <= URGENT:
            return


def finish():
    """Wait for the calibrations being made (a worker's error is the frame's to meet, when it
    makes the calibration itself)."""
    with stalled():
        while _JOBS:
            _JOBS.pop().exception()
