"""The coming seconds' whitecap calibrations, made ahead on a worker thread while the viewport
plays: a spectral calibration costs about ten frames, so made by the frame that first needs
it, playback would stall once a second. The core keeps them (foam.CALIBRATIONS) and waits for
one being made here rather than make it twice. This is our only thread; it is finished before
Blender runs long native work (a render, the bake's export), beside which none may run (one
beside the USD export crashed Blender 4.5)."""

import contextlib
import threading
from concurrent.futures import ThreadPoolExecutor

from ...projgrid_addon import foam

_POOL = []  # the worker, made when first needed
_JOBS = []  # its futures not yet finished (main thread only)
# Set while no frame is being built. The threads share the interpreter, so a worker taking
# cues beside a frame slows it as much as it works (on two cores, a keyed wind's frames 2.5x);
# it waits here between a calibration's levels instead, working between frames (the viewport
# draws them, the playback waits for the next) and while a frame stalls on a calibration.
_IDLE = threading.Event()
_IDLE.set()
_LATEST = [None]  # the sea's time at the frame that last handed the worker calibrations
URGENT = 0.5 * foam.FOAM_PERIOD  # s before the playback needs one: made beside the frames


@contextlib.contextmanager
def frame():
    """Build a frame (main thread): the worker waits between levels meanwhile."""
    _IDLE.clear()
    try:
        yield
    finally:
        _IDLE.set()


@contextlib.contextmanager
def stalled():
    """A frame stalls on a calibration, waiting for the worker's or making it
    (foam.CALIBRATIONS.stalled): the worker goes on meanwhile."""
    was = _IDLE.is_set()
    _IDLE.set()
    try:
        yield
    finally:
        if not was:
            _IDLE.clear()


foam.CALIBRATIONS.stalled = stalled


def calibrate(source, time, wind_speed, winds_ahead=()):
    """Start making the calibrations the next FOAM_PERIODs after `time` need, of the seas a
    source's are made on (foam.calibrated_at) with a `twin` to make them on (the spectrum's;
    the noise's cost little), and under a keyed wind those of the seas of `winds_ahead` (the
    wind at those times) too; returns how many started. What the worker makes is what the
    frame would (foam.calibration, a function of the settings and the time), on a twin."""
    started = 0
    _LATEST[0] = float(time)
    _JOBS[:] = [job for job in _JOBS if not job.done()]
    seas = {id(sea): (sea, wind) for w in (wind_speed, *winds_ahead)
            for sea, wind, _ in foam.calibrated_at(source, w)}  # (a keyed wind's: two each)
    for sea, wind in seas.values():
        if getattr(sea, "twin", None) is None:
            continue
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
    if not foam.CALIBRATIONS.start(source, key):  # a frame took it over
        return
    try:
        foam.CALIBRATIONS.put(source, key, foam.calibration(
            twin, *key, pause=lambda: _pause(key[0])))
    finally:
        foam.CALIBRATIONS.release(source, key)


def _pause(due):
    """Between a calibration's levels: wait while a frame is built, unless the playback is
    within URGENT of the time `due` it is needed at (then it is made beside the frames: slower
    frames rather than one that stalls waiting for it)."""
    while not _IDLE.wait(0.05):
        if _LATEST[0] is not None and due - _LATEST[0] <= URGENT:
            return


def finish():
    """Wait for the calibrations being made (a worker's error is the frame's to meet, when it
    makes the calibration itself)."""
    while _JOBS:
        _JOBS.pop().exception()
