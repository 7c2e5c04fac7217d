"""The coming seconds' whitecap calibrations, made ahead on a worker thread while the viewport
plays: a spectral calibration costs about ten frames, so made by the frame that first needs
it, playback would stall once a second. The core keeps them (foam.CALIBRATIONS) and waits for
one being made here rather than make it twice. This is our only thread; it is finished before
Blender runs long native work (a render, the bake's export), beside which none may run (one
beside the USD export crashed Blender 4.5)."""

from concurrent.futures import ThreadPoolExecutor

from ...projgrid_addon import foam

_POOL = []  # the worker, made when first needed
_JOBS = []  # its futures not yet finished (main thread only)


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
    try:
        foam.CALIBRATIONS.put(source, key, foam.calibration(twin, *key))
    finally:
        foam.CALIBRATIONS.release(source, key)


def finish():
    """Wait for the calibrations being made (a worker's error is the frame's to meet, when it
    makes the calibration itself)."""
    while _JOBS:
        _JOBS.pop().exception()
