"""The memory a grid's build takes: a fresh process per size, its peak against the estimate
checked before building (projgrid_addon/memory.py)."""

import os
import subprocess
import sys

MEMORY_WORKER = """
import sys
import tracemalloc

import bpy
import numpy as np

nx, ny, root = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
sys.path.insert(0, root)
from tools.bench.blender_bench import extension
from tools.bench.memory_bench import memory_status, reset_peak
from tools.demo import MODULE, add_camera

bpy.ops.preferences.addon_enable(module=MODULE)  # installed by the bench's process
bpy.ops.wm.read_homefile(use_empty=True)
scene = bpy.context.scene
add_camera(scene)
bpy.ops.projgrid.add_ocean()
obj = bpy.context.active_object
obj.projgrid.render_resolution_x, obj.projgrid.render_resolution_y = nx, ny
bridge = extension().operators.bridge
core = extension().projgrid_addon
depsgraph = bpy.context.evaluated_depsgraph_get()
n = nx * ny
out = {}
# The core alone: the grid's own arrays and the passes' buffers (NumPy reports to tracemalloc).
camera = core.Camera(*bridge.shot.camera_for(scene, depsgraph))
hf = bridge.scene.height_field(obj.projgrid)
tracemalloc.start()
grid = core.build_grid(camera, hf, time=1.0, resolution=(nx, ny))
out["core"] = tracemalloc.get_traced_memory()[1] / n
tracemalloc.stop()
del grid
for name, frame in (("topology", 2), ("rebuild", 3)):
    scene.frame_current = frame
    before = reset_peak()
    bridge.frame.update_ocean(obj, scene, depsgraph, render=True)
    rss, peak = memory_status()
    out[name] = (peak - before) / n
    out[name + " held"] = (rss - before) / n
assert len(obj.data.vertices) == n
print(" ".join(f"{k}={v:.1f}" for k, v in out.items()).replace(" held", "_held"))
"""


def memory_status():
    """(resident, peak resident) bytes of this process (Linux /proc)."""
    values = {}
    with open("/proc/self/status") as f:
        for line in f:
            key = line.split(":")[0]
            if key in ("VmRSS", "VmHWM"):
                values[key] = int(line.split()[1]) * 1024
    return values["VmRSS"], values["VmHWM"]


def reset_peak():
    """Reset the peak resident size to the current one; returns it."""
    with open("/proc/self/clear_refs", "w") as f:
        f.write("5")
    return memory_status()[0]


def memory_cost(sizes=((257, 513), (1025, 2049))):
    """Bytes per vertex of a render-grid rebuild, each size in a fresh Blender process: the
    core's peak (NumPy, tracemalloc), and the process's peak resident growth (Linux VmHWM, reset
    before each step) for a rebuild that builds the mesh's topology and for one that reuses it,
    with what stays resident after each."""

    from tools.package import ROOT

    rows = []
    for nx, ny in sizes:
        done = subprocess.run([sys.executable, "-c", MEMORY_WORKER, str(nx), str(ny), ROOT],
                              capture_output=True, text=True, timeout=1200, env=os.environ)
        line = [x for x in done.stdout.splitlines() if x.startswith("core=")]
        if done.returncode != 0 or not line:
            raise RuntimeError(f"memory worker failed: {done.stderr[-2000:]}")
        values = dict(item.split("=") for item in line[-1].split())
        rows.append({"resolution": f"{nx}×{ny}", "vertices": nx * ny,
                     **{k: float(v) for k, v in values.items()}})
    return rows
