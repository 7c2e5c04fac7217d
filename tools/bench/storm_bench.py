"""What the storm's work costs against the sea before it: a gale (Beaufort 8) per frame and per
rendered frame, this tree beside BASELINE (the commit before issue 36's work: whitecaps alone,
no residual foam, no streaks, the even grid), each in its own Blender process, the two
alternated ROUNDS times so the machine's load falls on both alike.

Per frame: frame_set on a 257² grid from 5 m up, the camera still and moving (2 m a frame),
the foam's calibrations made in the frame (no worker beside it). Rendered: a frame rendered
alone as a farm renders it (a time no earlier frame has made: its sea, calibrations and
residual foam's past made in it), the EEVEE render of the default shot at 960×540, 16
samples, after one render compiles the shaders; in this tree alternately with and without
its residual foam (stage B), and without its spray (per frame too).

Alone: python -m tools.bench.storm_bench (the probe: python tools/bench/storm_bench.py --root R)."""

import json
import os
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BASELINE = "51516fb"
ROUNDS = 2
NO_B = ", no stage B"  # the variant without the residual foam
NO_SPRAY = ", no spray"  # and this tree's without its spray


def storm_cost(quick=False):
    """Rows (variant, tree, ms, p10 ms, CPU ms) and the ratios: this tree / BASELINE, and
    this tree's with its residual foam / without, and with its spray / without."""
    base = tempfile.mkdtemp(prefix="projgrid-baseline-")
    subprocess.run(["git", "-C", ROOT, "worktree", "add", "--detach", base, BASELINE],
                   check=True, capture_output=True)
    times = {}
    try:
        for _ in range(1 if quick else ROUNDS):
            for tree, root in (("baseline", base), ("this", ROOT)):
                out = subprocess.run(
                    [sys.executable, os.path.abspath(__file__), "--root", root]
                    + (["--quick"] if quick else []),
                    check=True, capture_output=True, text=True,
                    env={**os.environ,
                         "BLENDER_USER_RESOURCES": tempfile.mkdtemp(prefix="projgrid-user-")})
                for variant, samples in json.loads(out.stdout.splitlines()[-1]).items():
                    times.setdefault((variant, tree), []).extend(samples)
    finally:
        subprocess.run(["git", "-C", ROOT, "worktree", "remove", "--force", base],
                       capture_output=True)
        subprocess.run(["git", "-C", ROOT, "worktree", "prune"], capture_output=True)
    import numpy as np

    rows = []
    for (variant, tree), samples in times.items():
        wall, cpu = np.array(samples).T * 1e3
        rows.append({"variant": variant, "tree": tree, "ms": float(np.median(wall)),
                     "p10": float(np.percentile(wall, 10)), "cpu": float(np.median(cpu)),
                     "n": len(wall)})
    kept = {(r["variant"], r["tree"]): r for r in rows}

    def ratio(what, top, bottom):
        return {"variant": top["variant"], "what": what, "ratio": top["ms"] / bottom["ms"],
                "ratio_p10": top["p10"] / bottom["p10"]}
    ratios = [ratio("this tree / baseline", kept[v, "this"], kept[v, "baseline"])
              for v, tree in kept if tree == "baseline" and (v, "this") in kept]
    ratios += [ratio(f"with {what} / without", kept[v[:-len(cut)], "this"], kept[v, "this"])
               for what, cut in (("stage B", NO_B), ("spray", NO_SPRAY))
               for v, tree in kept if v.endswith(cut)]
    return {"baseline": BASELINE, "rows": rows, "ratios": ratios}


def _timed(fn):
    wall, cpu = time.perf_counter(), time.process_time()
    fn()
    return time.perf_counter() - wall, time.process_time() - cpu


def _stage_b_switch(bpy):
    """A function turning this tree's residual foam (stage B) off and on again: the per-vertex
    residual not made, the water group's noises of the residual foam (its rafts and lace)
    and of the aged foam gone (a copy of the group without them); None in a tree without
    stage B."""
    import importlib

    from tools.demo import MODULE

    try:
        residual_foam = importlib.import_module(MODULE + ".projgrid_addon.residual_foam")
        look = importlib.import_module(MODULE + ".projgrid_addon.look")
    except ImportError:
        return None
    node = bpy.data.objects["Ocean"].data.materials[0].node_tree.nodes["Projected Grid Water"]
    with_b, made = node.node_tree, residual_foam.residual
    without = with_b.copy()
    for noise in [n for n in without.nodes if n.type == "TEX_NOISE"
                  and not n.inputs["Scale"].links and min(
                      abs(n.inputs["Scale"].default_value - s)
                      for s in (look.FOAM_LACE, look.FOAM_NET, look.FOAM_AGED)) < 1e-6]:
        without.nodes.remove(noise)

    def switch(on):
        node.node_tree = with_b if on else without
        residual_foam.residual = made if on else (lambda *a, **k: None)
    return switch


def probe(root, quick):
    """In a fresh process: install `root`'s extension and time its gale; prints JSON."""
    sys.path.insert(0, root)
    import importlib

    import bpy

    from tools.demo import MODULE, default_shot, install
    from tools.package import build

    install(build(tempfile.mkdtemp(prefix="projgrid-dist-")))
    frames = 6 if quick else 30
    out = {}

    def gale(resolution=None, moving=False, first=100):
        bpy.ops.wm.read_homefile(use_empty=True)
        scene = bpy.context.scene
        cam = default_shot(scene, size=(960, 540), samples=4 if quick else 16, height=5.0,
                           pitch=-4.0)
        ocean = bpy.data.objects["Ocean"]
        bpy.context.view_layer.objects.active = ocean
        try:  # under the same sky as the baseline (whose Sea State has no Weather)
            bpy.ops.projgrid.sea_state(beaufort=8, weather=False)
        except TypeError:
            bpy.ops.projgrid.sea_state(beaufort=8)
        if resolution:
            ocean.projgrid.resolution_x = ocean.projgrid.resolution_y = resolution
        if moving:
            bpy.context.preferences.edit.keyframe_new_interpolation_type = "LINEAR"
            for frame in (first, first + 10_000):
                cam.location.y = 2.0 * (frame - first)
                cam.keyframe_insert("location", frame=frame)
        scene.frame_set(first)
        return scene

    # No calibrations ahead on the worker while frames are timed (its thread would take the
    # second core from the frame): a frame starting a second makes them, in both trees.
    ahead = importlib.import_module(MODULE + ".operators.bridge.ahead")
    calibrate, ahead.calibrate = ahead.calibrate, (lambda *a, **k: 0)
    settings = bpy.types.Object.bl_rna.properties["projgrid"].fixed_type.properties
    sprays = (True, False) if "spray" in settings else (True,)
    for moving in (False, True):
        for spray in sprays:  # this tree's without its spray too: what the spray costs
            scene = gale(257, moving)
            bpy.data.objects["Ocean"].projgrid.spray = "AUTO" if spray else "OFF"
            ahead.finish()
            name = f"frame 257², camera {'moving' if moving else 'still'}" + (
                "" if spray else NO_SPRAY)
            out[name] = [_timed(lambda f=f, s=scene: s.frame_set(f)) for f in range(
                scene.frame_current + 1, scene.frame_current + 1 + frames)]
    ahead.calibrate = calibrate
    scene = gale(first=48)
    stage_b = _stage_b_switch(bpy)
    for on in (False, True) if stage_b is not None else (True,):
        if stage_b is not None:
            stage_b(on)
        bpy.ops.render.render()  # compiles the shaders

    def alone(frame, on):  # as `blender -b -f`: the render sets the frame
        if stage_b is not None:
            stage_b(on)
        scene.frame_current = frame
        bpy.ops.render.render()
    ocean = bpy.data.objects["Ocean"]

    def without_spray(frame):
        ocean.projgrid.spray = "OFF"
        try:
            alone(frame, True)
        finally:
            ocean.projgrid.spray = "AUTO"
    # this tree's with and without its residual foam and its spray alternated, each frame a
    # time of its own
    for frame in range(1000, 1000 + (1 if quick else 3) * 500, 500):
        for on in (True, False) if stage_b is not None else (True,):
            out.setdefault("frame rendered alone, 960×540" + ("" if on else NO_B), []).append(
                _timed(lambda f=frame + (0 if on else 250), o=on: alone(f, o)))
        if len(sprays) > 1:
            out.setdefault("frame rendered alone, 960×540" + NO_SPRAY, []).append(
                _timed(lambda f=frame + 125: without_spray(f)))
    print(json.dumps(out))


if __name__ == "__main__":
    if "--root" in sys.argv:
        probe(sys.argv[sys.argv.index("--root") + 1], "--quick" in sys.argv)
    else:
        sys.path.insert(0, ROOT)
        print(json.dumps(storm_cost("--quick" in sys.argv), indent=1))
