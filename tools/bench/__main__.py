"""`make bench`: what accuracy costs in time. Writes docs/benchmarks.md and its plots.

Run from the repository root: python -m tools.bench [--quick] [--only=step,step]
(--only re-measures those steps and keeps the rest from docs/benchmarks.json).
Every figure is measured in this one process; timings are medians of interleaved repeats
(`core_bench.interleaved`), so a load change on a shared machine hits all variants alike.
"""

import json
import os
import platform
import subprocess
import sys
import tempfile
import time

from tools.package import ROOT

DOCS = os.path.join(ROOT, "docs")


RESULTS = os.path.join(DOCS, "benchmarks.json")


def main(quick=False, only=None):
    os.environ.setdefault("BLENDER_USER_RESOURCES", tempfile.mkdtemp(prefix="projgrid-user-"))
    import bpy

    from tools import beaufort, storm_strip
    from tools.demo import install
    from tools.package import build

    from . import (
        blender_bench,
        core_bench,
        memory_bench,
        render_bench,
        report,
        scene_bench,
        storm_bench,
        wake_bench,
    )

    install(build(tempfile.mkdtemp(prefix="projgrid-dist-")))
    bpy.ops.wm.read_homefile(use_empty=True)
    started = time.time()
    results = {}
    steps = [
        ("rebuild", lambda: blender_bench.rebuild_cost(
            sizes=(17, 65, 257) if quick else (17, 65, 145, 257, 577, 1025))),
        ("octaves", lambda: core_bench.octave_cost(repeats=3 if quick else 9)),
        ("height_field", core_bench.height_field_paths),
        ("precision", core_bench.precision),
        ("efficiency", core_bench.efficiency),
        ("sea_efficiency", lambda: core_bench.sea_efficiency(frames=12 if quick else 96)),
        ("accuracy", lambda: core_bench.accuracy(
            sizes=(33, 65) if quick else (33, 65, 129, 257),
            world_sizes=(33, 65, 129) if quick else (33, 65, 129, 257, 513),
            image=(48, 27) if quick else (96, 54))),
        ("effects", lambda: blender_bench.effect_cost(repeats=5 if quick else 15)),
        ("sea", lambda: blender_bench.sea_cost(repeats=5 if quick else 45)),
        ("playback", lambda: blender_bench.playback_cost(seconds=2 if quick else 3)),
        ("bake", lambda: blender_bench.bake_cost(frames=12 if quick else 24,
                                                 repeats=3 if quick else 7)),
        ("scene_update", lambda: scene_bench.scene_update_cost(
            counts=(0, 1000) if quick else (0, 1000, 10000), repeats=3 if quick else 7)),
        ("moving_objects", lambda: scene_bench.moving_objects_cost(
            counts=(0, 500) if quick else (0, 2000), repeats=3 if quick else 9)),
        ("effect_render", lambda: render_bench.effect_render_cost(repeats=1 if quick else 3)),
        ("memory", lambda: memory_bench.memory_cost(
            sizes=((257, 513),) if quick else ((257, 513), (1025, 2049), (2049, 4097)))),
        ("render", lambda: render_bench.render_cost(
            samples=(1, 4) if quick else (1, 4, 16, 64),
            reference_samples=16 if quick else 128)),
        ("flicker", lambda: render_bench.flicker(DOCS, frames=3 if quick else 4)),
        ("wakes", lambda: wake_bench.wake_cost(repeats=5 if quick else 15)),
        ("storm", lambda: storm_bench.storm_cost(quick)),  # its own processes
        ("beaufort", lambda: beaufort.shoot(DOCS, quick)),  # these three start from empty files
        ("strip", lambda: storm_strip.shoot(DOCS, quick)),
        ("pictures", lambda: pictures(quick)),
    ]
    if only:  # re-measure some steps, keep the others from the last run
        with open(RESULTS) as f:
            results = json.load(f)
    for name, fn in steps:
        if only and name not in only:
            continue
        t = time.time()
        results[name] = fn()
        print(f"bench: {name} done in {time.time() - t:.0f} s", flush=True)
    results["machine"] = machine(bpy)
    if not only:
        results["seconds"] = time.time() - started
        results["command"] = "make bench" + (" QUICK=1" if quick else "")
        results["remeasured"] = []
    else:
        results["remeasured"] = sorted(set(results.get("remeasured", [])) | set(only))
    with open(RESULTS, "w") as f:
        json.dump(results, f, indent=1, default=_plain)
    path = report.write(results, DOCS)
    print(path)


def pictures(quick):
    """The side-by-side shots with Blender's Ocean modifier (tools/compare.py), into docs/."""
    from tools import compare

    return [{"state": state, "shot": shot, "path": os.path.relpath(path, DOCS)}
            for state, shot, path in compare.shoot(DOCS, quick=quick)]


def machine(bpy):
    import numpy

    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as f:
            names = [line.split(":", 1)[1].strip() for line in f if line.startswith("model name")]
        cpu = f"{names[0]} ({len(names)} logical CPUs)" if names else cpu
    except OSError:
        pass
    try:
        commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT,
                                capture_output=True, text=True).stdout.strip()
    except OSError:
        commit = "?"
    return {"cpu": cpu, "os": platform.platform(), "python": platform.python_version(),
            "blender": bpy.app.version_string, "numpy": numpy.__version__, "commit": commit}


def _plain(value):
    """JSON for NumPy scalars and tuples in results."""
    return value.item() if hasattr(value, "item") else str(value)


if __name__ == "__main__":
    only = [a.split("=", 1)[1].split(",") for a in sys.argv if a.startswith("--only=")]
    main(quick="--quick" in sys.argv, only=only[0] if only else None)
