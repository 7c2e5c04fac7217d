"""Reusable per-thread scratch arrays for the per-vertex passes, and the threads they share.

A fresh NumPy temporary of a few hundred kilobytes is mapped from the OS and faulted in page by
page, and the allocator hands it back when it is freed (docs/benchmarks.md, findings). The
passes therefore write their temporaries into buffers kept between frames, and run CHUNK
points at a time, so the buffers stay a few megabytes for any grid.

NumPy releases the GIL in its FFTs and its longer array operations, so independent passes run
on several cores (`each`): the spectral sea's tiles' transforms, and its sampling of a grid in
chunks of rows (`row_step`: a 257² grid's in two, 20 % faster on two cores; a viewport grid's
is one chunk, its many short NumPy calls not worth sharing). Which passes there are depends on
the data alone, never on the cores, so a frame is bit-identical whatever the number of threads.
"""

import math
import os
import threading
from concurrent.futures import ThreadPoolExecutor

import numpy as np

# Points per pass of the per-vertex stages, so their buffers keep this size whatever the grid.
CHUNK = 1 << 16
# Threads a frame's passes use (the caller's and the pool's): the cores this process may use.
WORKERS = min(4, len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity")
              else os.cpu_count() or 1)

# Points from which a pass is split into an even number of chunks (`row_step`).
SHARED = CHUNK // 2

_local = threading.local()


def row_step(rows, columns):
    """Rows per chunk of a pass over `rows` x `columns` points: at most CHUNK points each (a
    row at least), and from SHARED points on an even number of chunks, which `each` shares
    evenly over two cores. A function of the sizes alone, never of the cores: the chunks, and
    so the frame, are the same whatever runs them."""
    most = max(1, CHUNK // columns)
    n = -(-rows // most)
    if rows * columns >= SHARED:
        n = max(2, n + n % 2)
    return max(1, -(-rows // n))


def scratch(name, shape, dtype):
    """A C-contiguous array of `shape` and `dtype` backed by a buffer reused across calls.

    Its contents are undefined, and it is overwritten by the next call with the same `name`.
    """
    buffers = getattr(_local, "buffers", None)
    if buffers is None:
        buffers = _local.buffers = {}
    dtype = np.dtype(dtype)
    size = math.prod(shape) * dtype.itemsize
    buf = buffers.get(name)
    if buf is None or buf.size < size:
        buf = buffers[name] = np.empty(max(size, 1), dtype=np.uint8)
    return buf[:size].view(dtype).reshape(shape)


_POOL = {"pool": None}
_POOL_LOCK = threading.Lock()


def each(fn, items):
    """[fn(item) for item in items], the items shared among WORKERS threads (the caller's one
    of them). Each item's work must be independent of the others'. After an error no item
    starts; the first error raised is raised here once no item runs."""
    items = list(items)
    if len(items) < 2 or WORKERS < 2:
        return [fn(item) for item in items]
    with _POOL_LOCK:
        if _POOL["pool"] is None:
            _POOL["pool"] = ThreadPoolExecutor(WORKERS - 1, thread_name_prefix="projgrid-pass")
        pool = _POOL["pool"]
    results = [None] * len(items)
    order = iter(range(len(items)))
    lock = threading.Lock()
    errors = []

    def work():
        while True:
            with lock:
                i = None if errors else next(order, None)
            if i is None:
                return
            try:
                results[i] = fn(items[i])
            except BaseException as error:  # noqa: BLE001 - raised by the caller below
                with lock:
                    errors.append(error)
                return

    helpers = [pool.submit(work) for _ in range(min(WORKERS, len(items)) - 1)]
    work()
    for helper in helpers:
        # One not yet started (its thread busy elsewhere, even waiting on this caller) is
        # cancelled: the caller took its items.
        if not helper.cancel():
            helper.result()
    if errors:
        raise errors[0]
    return results
