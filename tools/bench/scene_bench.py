"""Benchmarks of the ocean in big scenes: a viewport update among thousands of still objects,
and frames among thousands of moving ones, with our handlers and without."""

import importlib
import time

import bpy
import numpy as np

from tools.demo import MODULE

from .blender_bench import projected_scene
from .core_bench import interleaved


def _timed(handler):
    """`handler` wrapped to record the seconds each call spends in it: (wrapper, the list)."""
    spent = []

    def timed(scene, depsgraph):
        start = time.perf_counter()
        handler(scene, depsgraph)
        spent.append(time.perf_counter() - start)
    return timed, spent


def scene_update_cost(counts=(0, 1000, 10000), repeats=7):
    """Viewport cost of a depsgraph update in a scene of `count` small objects scattered around
    the ocean (the effects at AUTO look at them): the whole update with our handler and without
    it, interleaved, and the time spent inside our handler (our own share, which the difference
    of the two whole updates measures only as well as a shared machine allows); after a camera
    nudge (the ocean must follow) and after a move of one object behind the camera (unrelated to
    the ocean: only that object's box is read again)."""
    handlers = importlib.import_module(MODULE + ".operators.bridge.handlers")
    ours_handler = handlers.depsgraph_update_post
    timed, spent = _timed(ours_handler)

    rows = []
    rng = np.random.default_rng(3)
    hook = bpy.app.handlers.depsgraph_update_post
    hook.remove(ours_handler)
    try:
        for count in counts:
            scene = projected_scene(65)
            layer = scene.view_layers[0]
            mesh = bpy.data.meshes.new("triangle")
            mesh.from_pydata([(0, 0, 0), (1, 0, 0), (0, 1, 0)], [], [(0, 1, 2)])
            for x, y, z in rng.uniform((-300, -300, -5), (300, 300, 5), (count, 3)):
                obj = bpy.data.objects.new("object", mesh)
                obj.location = (x, y, z)
                scene.collection.objects.link(obj)
            behind = bpy.data.objects.new("behind the camera", mesh)
            behind.location = (0.0, -50.0, 0.0)
            scene.collection.objects.link(behind)
            hook.append(timed)
            layer.update()
            inside = {}

            def change(ours, what, kind, layer=layer, inside=inside):
                if ours != (timed in hook):
                    (hook.append if ours else hook.remove)(timed)
                spent.clear()
                what.location.x += 1e-3
                layer.update()
                if ours:
                    inside.setdefault(kind, []).append(sum(spent))

            moved = {"camera": scene.camera, "unrelated": behind}
            variants = {(kind, ours): (lambda w=moved[kind], o=ours, k=kind: change(o, w, k))
                        for kind in moved for ours in (True, False)}
            with bpy.context.temp_override(scene=scene, view_layer=layer):
                times = interleaved(variants, repeats)
            if timed in hook:
                hook.remove(timed)
            rows.append({"objects": count,
                         "ours_ms": times[("camera", True)].median * 1e3,
                         "ours_p10_ms": times[("camera", True)].p10 * 1e3,
                         "ours_cpu_ms": times[("camera", True)].cpu * 1e3,
                         "without_ms": times[("camera", False)].median * 1e3,
                         "handler_ms": float(np.median(inside["camera"])) * 1e3,
                         "unrelated_ours_ms": times[("unrelated", True)].median * 1e3,
                         "unrelated_ours_p10_ms": times[("unrelated", True)].p10 * 1e3,
                         "unrelated_ours_cpu_ms": times[("unrelated", True)].cpu * 1e3,
                         "unrelated_without_ms": times[("unrelated", False)].median * 1e3,
                         "unrelated_handler_ms": float(np.median(inside["unrelated"])) * 1e3})
            bpy.data.scenes.remove(scene)
    finally:
        if ours_handler not in hook:
            hook.append(ours_handler)
    return rows


def moving_objects_cost(counts=(0, 2000), repeats=7):
    """Frame changes (frame_set, frame after frame) in a scene of `count` keyframed cubes moving
    through the water in view of the ocean (Add Ocean's 65x129 viewport grid, effects at AUTO
    but its whitecaps off: their calibrations, made ahead on a worker thread, would overlap
    Blender's own work and blur the difference), interleaved: with our handlers, without them
    (the ocean's share of a frame is the difference), and without them but with a handler that
    writes a plain mesh of the grid's size each frame (what Blender charges for any mesh
    written from frame_change_post among those objects); and the time inside our frame
    handler."""
    handlers = importlib.import_module(MODULE + ".operators.bridge.handlers")
    ours_frame = handlers.frame_change_post
    timed, spent = _timed(ours_frame)

    post = bpy.app.handlers.frame_change_post
    ours = [(post, timed), (bpy.app.handlers.depsgraph_update_post,
                            handlers.depsgraph_update_post)]
    post.remove(ours_frame)
    rows = []
    rng = np.random.default_rng(7)
    try:
        for count in counts:
            scene = projected_scene(65)
            ocean = next(o for o in scene.objects if o.projgrid.is_ocean)
            ocean.projgrid.resolution_y, ocean.projgrid.foam = 129, "OFF"
            layer = scene.view_layers[0]
            mesh = bpy.data.meshes.new("cube")
            mesh.from_pydata([(x, y, z) for x in (0, 1) for y in (0, 1) for z in (0, 1)], [],
                             [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6),
                              (0, 2, 6, 4), (1, 5, 7, 3)])
            for x, y, z in rng.uniform((-200, 20, -4), (200, 400, 2), (count, 3)):
                obj = bpy.data.objects.new("cube", mesh)
                scene.collection.objects.link(obj)
                obj.location = (x, y, z)
                obj.keyframe_insert("location", frame=1)
                obj.location.z = z + 3.0
                obj.keyframe_insert("location", frame=48)
            plain = bpy.data.meshes.new("plain write")
            plain.vertices.add(65 * 129)
            scene.collection.objects.link(bpy.data.objects.new("plain write", plain))
            positions = np.zeros(65 * 129 * 3, np.float32)

            def write(scene, depsgraph, plain=plain, positions=positions):
                positions[2::3] = scene.frame_current * 1e-3
                plain.attributes["position"].data.foreach_set("vector", positions)
                plain.update()

            frames = iter(range(10**6))

            def step(variant, scene=scene, frames=frames, write=write):
                for hook, handler in ours:
                    if variant == "ocean" and handler not in hook:
                        hook.append(handler)
                    elif variant != "ocean" and handler in hook:
                        hook.remove(handler)
                if (variant == "plain") != (write in post):
                    (post.append if variant == "plain" else post.remove)(write)
                scene.frame_set(1 + next(frames) % 47)

            spent.clear()
            with bpy.context.temp_override(scene=scene, view_layer=layer):
                times = interleaved({v: (lambda v=v: step(v)) for v in ("ocean", "none", "plain")},
                                    repeats)
                step("none")
            row = {"objects": count, "handler_ms": float(np.median(spent)) * 1e3}
            for key, variant in (("with", "ocean"), ("without", "none"), ("plain", "plain")):
                row.update({f"{key}_ms": times[variant].median * 1e3,
                            f"{key}_p10_ms": times[variant].p10 * 1e3,
                            f"{key}_cpu_ms": times[variant].cpu * 1e3})
            rows.append(row)
            bpy.data.scenes.remove(scene)
    finally:
        for hook, handler in ours:
            if handler in hook:
                hook.remove(handler)
        for hook, handler in ((post, ours_frame), (bpy.app.handlers.depsgraph_update_post,
                                                   handlers.depsgraph_update_post)):
            if handler not in hook:
                hook.append(handler)
    return rows
