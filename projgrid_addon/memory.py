"""Whether a grid fits in memory, decided before anything is allocated.

A rebuild's transient and resident memory grows with the vertex count (docs/benchmarks.md,
"Memory"): the core's per-vertex passes, the float32 positions, and Blender's mesh. A grid the
machine cannot hold is refused with a message instead of failing half-way through the write.
"""

import ctypes
import os
import sys

# Peak bytes per vertex of a rebuild at a resolution already built (the positions and attributes
# rewritten), and the extra when the topology is built anew (faces, edges, UVs), measured in
# Blender with the bench's `memory` step (docs/benchmarks.md) and rounded up by about a quarter.
REBUILD_BYTES = 50
TOPOLOGY_BYTES = 200


def available_bytes():
    """Memory the system can hand out without swapping, or None where it cannot be asked."""
    try:
        if sys.platform.startswith("linux"):
            with open("/proc/meminfo") as f:
                for line in f:
                    if line.startswith("MemAvailable:"):
                        return int(line.split()[1]) * 1024
        elif sys.platform == "win32":
            class Status(ctypes.Structure):
                _fields_ = [("length", ctypes.c_ulong), ("load", ctypes.c_ulong),
                            ("total", ctypes.c_ulonglong), ("available", ctypes.c_ulonglong),
                            ("page_total", ctypes.c_ulonglong), ("page_free", ctypes.c_ulonglong),
                            ("virtual_total", ctypes.c_ulonglong),
                            ("virtual_free", ctypes.c_ulonglong), ("extended", ctypes.c_ulonglong)]
            status = Status(length=ctypes.sizeof(Status))
            if ctypes.windll.kernel32.GlobalMemoryStatusEx(ctypes.byref(status)):
                return int(status.available)
        else:
            return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_AVPHYS_PAGES")
    except (OSError, ValueError, AttributeError):
        pass
    return None


def grid_bytes(resolution, new_topology):
    """Peak bytes a rebuild at `resolution` (nx, ny) needs."""
    nx, ny = resolution
    return nx * ny * (REBUILD_BYTES + (TOPOLOGY_BYTES if new_topology else 0))


# Below this a rebuild is not worth asking the system about (it costs a file read per frame).
SMALL_BYTES = 64 * 2**20


def check_grid(resolution, new_topology, which, available=None, large_only=False):
    """ValueError saying what to lower if the grid would not fit in the memory available
    (`available` bytes, default what the system reports; unknown: no check). With `large_only`
    a rebuild needing less than SMALL_BYTES is not checked."""
    need = grid_bytes(resolution, new_topology)
    if large_only and need < SMALL_BYTES:
        return
    free = available_bytes() if available is None else available
    if free is not None and need > free:
        nx, ny = resolution
        raise ValueError(f"a {nx}x{ny} grid needs about {need / 2**30:.1f} GB and "
                         f"{free / 2**30:.1f} GB of memory is free: lower the {which} grid "
                         "resolution")
