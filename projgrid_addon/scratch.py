"""Reusable per-thread scratch arrays for the per-vertex passes.

A fresh NumPy temporary of a few hundred kilobytes is mapped from the OS and faulted in page by
page, and the allocator hands it back when it is freed (docs/benchmarks.md, findings). The
passes therefore write their temporaries into buffers kept between frames, and run CHUNK
points at a time, so the buffers stay a few megabytes for any grid.
"""

import math
import threading

import numpy as np

# Points per pass of the per-vertex stages, so their buffers keep this size whatever the grid.
CHUNK = 1 << 16

_local = threading.local()


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
