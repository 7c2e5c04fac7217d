"""Benchmarks inside Blender: per-frame rebuild through `scene.frame_set` for the projected grid,
Blender's Ocean modifier and a world-space grid of the same vertex count, and EEVEE render cost."""

import importlib
import itertools
import os
import shutil
import tempfile
import time

import bpy
import numpy as np

from projgrid_addon import Camera, HeightField
from projgrid_addon.effects import EFFECTS
from tools.demo import MODULE, add_camera

from .core_bench import WAVES, interleaved, visible_extent, world_grid_points

# Ocean modifier viewport resolution r gives (r^2 + 1)^2 vertices: the common sizes.
OCEAN_RES = {17: 4, 65: 8, 145: 12, 257: 16, 577: 24, 1025: 32}


def extension():
    """The installed extension's package (installed by tools.bench before any step runs)."""
    return importlib.import_module(MODULE)


# Each scene of a step starts at its own frame (its own time), so no variant reuses a texture,
# a synthesised sea or a foam calibration another variant cached at the same time. (Not its own
# seed: a sea is made per settings and kept for four, so ten variants' seeds would measure the
# making of a sea every frame, which no frame of an artist's pays.)
_DISTINCT = itertools.count(1)


def _scene(name):
    scene = bpy.data.scenes.new(name)
    add_camera(scene, (0.0, 0.0, 10.0), (82.0, 0.0, 0.0))
    scene.render.resolution_x, scene.render.resolution_y = 1920, 1080
    scene["bench_index"] = next(_DISTINCT)
    scene.frame_current = 1 + 37 * scene["bench_index"] % 2000  # inside the modifier's keys
    return scene


def _ocean(scene):
    return next(o for o in scene.objects if o.type == "MESH" and o.projgrid.is_ocean)


def projected_scene(n, noise="FAST", source="SPECTRUM"):
    """Add Ocean's sea (the spectrum, Beaufort 4) on an n² grid, or with `source` 'PERLIN' the
    noise by the `noise` path (Beaufort 4's height and wavelength, kept whatever the wind)."""
    scene = _scene(f"projected {n} {source} {noise}")
    with bpy.context.temp_override(scene=scene, view_layer=scene.view_layers[0]):
        bpy.ops.projgrid.add_ocean()
    obj = _ocean(scene)
    obj.projgrid.resolution_x = obj.projgrid.resolution_y = n
    obj.projgrid.height_source = source
    obj.projgrid.noise_from_wind = False
    obj.projgrid.noise = noise
    return scene


def ocean_modifier_scene(n, choppiness=0.0, foam=False, name=""):
    scene = _scene(f"ocean modifier {n}{name}")
    obj = bpy.data.objects.new("Ocean Modifier", bpy.data.meshes.new("Ocean Modifier"))
    scene.collection.objects.link(obj)
    mod = obj.modifiers.new("Ocean", "OCEAN")
    mod.viewport_resolution = OCEAN_RES[n]
    mod.spatial_size = 200
    mod.choppiness = choppiness
    mod.use_foam = foam
    mod.time = 0.0
    mod.keyframe_insert("time", frame=1)
    mod.time = 100.0
    mod.keyframe_insert("time", frame=2401)  # so every frame re-evaluates the modifier
    return scene


WORLD_GRIDS = {}


def world_grid_scene(n):
    """An n x n grid in world space over the area the projected grid covers, displaced by the same
    height field each frame (band-limited to its own spacing) through the same fast mesh path."""
    scene = _scene(f"world grid {n}")
    bridge = extension().operators.bridge
    mesh = bpy.data.meshes.new("World Grid")
    bridge.mesh.set_topology(mesh, n, n)
    obj = bpy.data.objects.new("World Grid", mesh)
    scene.collection.objects.link(obj)
    with bpy.context.temp_override(scene=scene, view_layer=scene.view_layers[0]):
        depsgraph = bpy.context.evaluated_depsgraph_get()
    extent = visible_extent(Camera(*bridge.shot.camera_for(scene, depsgraph)),
                            HeightField(**WAVES))
    WORLD_GRIDS[scene.name] = (mesh, *world_grid_points(n, extent, WAVES["wave_scale"]))
    return scene


def world_grid_handler(scene, depsgraph=None):
    entry = WORLD_GRIDS.get(scene.name)
    if entry is None:
        return
    mesh, gx, gy, lod = entry
    t = scene.frame_current / scene.render.fps
    h = HeightField(**WAVES).heights(gx, gy, t, lod)
    co = np.column_stack([gx.ravel(), gy.ravel(), h.ravel()]).astype(np.float32)
    mesh.attributes["position"].data.foreach_set("vector", co.ravel())
    mesh.update()


def step(scene):
    """Advance a scene by one frame (a new time: nothing can be reused from the last frame)."""
    scene.frame_set(scene.frame_current + 1)


def sea_cost(repeats=45):
    """Per-frame time (frame_set) of the sea as artists set it: the spectral sea and the noise
    at Beaufort 5 with their choppiness and whitecaps forced on, on a 257² grid, beside the
    Ocean modifier at resolution 16 (257² vertices) with choppiness 1 and its foam; and the
    spectral sea on the default viewport grid (65×129)."""
    def ours(n, source, resolution=None):
        scene = projected_scene(n)
        obj = _ocean(scene)
        with bpy.context.temp_override(scene=scene, view_layer=scene.view_layers[0],
                                       active_object=obj):
            obj.projgrid.height_source = source
            bpy.ops.projgrid.sea_state(beaufort=5)
        obj.projgrid.foam = "ON"
        if resolution:
            obj.projgrid.resolution_x, obj.projgrid.resolution_y = resolution
        return scene

    scenes = {"spectrum 257², choppy, foam": ours(257, "SPECTRUM"),
              "noise 257², choppy, foam": ours(257, "PERLIN"),
              "Ocean modifier 16 (257²), choppy, foam":
                  ocean_modifier_scene(257, choppiness=1.0, foam=True, name=" foam"),
              "spectrum 65×129 (viewport)": ours(65, "SPECTRUM", (65, 129))}
    # No whitecap calibrations ahead on the worker (playback_cost measures those): its
    # thread would take the second core from the Ocean modifier's threads.
    bridge = extension().operators.bridge
    ahead, bridge.ahead.calibrate = bridge.ahead.calibrate, (lambda *a, **k: 0)
    bridge.ahead.finish()
    try:
        times = interleaved({k: (lambda s=s: step(s)) for k, s in scenes.items()}, repeats)
    finally:
        bridge.ahead.calibrate = ahead
    for s in scenes.values():
        bpy.data.scenes.remove(s)
    return [{"variant": k, **v.ms()} for k, v in times.items()]


def playback_cost(seconds=3, rounds=2):
    """Frame times while playing the spectral sea on the viewport grid (Beaufort 5, foam on):
    `seconds` of consecutive frames, each started at its time at 24 fps as the viewport plays
    them (a slow frame starts the next at once), with the coming seconds' whitecap calibrations made
    ahead on a worker thread (operators/bridge/ahead.py), with each made by the frame that
    first needs it, and (ahead) under a wind keyed from 8 to 10 m/s over the seconds (each
    frame a sea of its own), in turn, each round at times of its own. Per variant: the
    median, 90th percentile and slowest frame, and the frames slower than twice the median
    (stalls)."""
    bridge = extension().operators.bridge
    ahead = bridge.ahead.calibrate
    scene = projected_scene(65)
    obj = _ocean(scene)
    with bpy.context.temp_override(scene=scene, view_layer=scene.view_layers[0],
                                   active_object=obj):
        bpy.ops.projgrid.sea_state(beaufort=5)
    obj.projgrid.foam = "ON"
    obj.projgrid.resolution_x, obj.projgrid.resolution_y = 65, 129
    frames = {"ahead on a worker": [], "in the frame": [], "wind keyed 8-10 m/s, ahead": []}
    start, steady = scene.frame_current, obj.projgrid.wind_speed
    try:
        for r in range(rounds):
            for n, variant in enumerate(frames):
                bridge.ahead.calibrate = ahead if n != 1 else (lambda *a, **k: 0)
                bridge.ahead.finish()  # the worker idle as each variant starts
                first = start + (3 * r + n) * 200 * scene.render.fps // 24
                last = first + seconds * scene.render.fps
                if n == 2:
                    for frame, wind in ((first, 8.0), (last, 10.0)):
                        obj.projgrid.wind_speed = wind
                        obj.projgrid.keyframe_insert("wind_speed", frame=frame)
                scene.frame_set(first)
                due = time.perf_counter()
                for f in range(first + 1, last + 1):
                    t = time.perf_counter()
                    scene.frame_set(f)
                    frames[variant].append(time.perf_counter() - t)
                    due = max(due + 1.0 / 24.0, time.perf_counter())  # as the viewport plays
                    time.sleep(max(due - time.perf_counter(), 0.0))
                if n == 2:
                    obj.animation_data_clear()
                    obj.projgrid.wind_speed = steady
    finally:
        bridge.ahead.calibrate = ahead
        bpy.data.scenes.remove(scene)
    rows = []
    for variant, times in frames.items():
        ms = np.array(times) * 1e3
        median = float(np.median(ms))
        rows.append({"variant": variant, "frames": len(ms), "median": median,
                     "p90": float(np.percentile(ms, 90)), "max": float(ms.max()),
                     "stalls": int((ms > 2.0 * median).sum())})
    return rows


def bake_cost(frames=24, repeats=7):
    """The bake (bridge/bake.py) of Add Ocean's sea at its render grid (257×513) over `frames`
    frames: wall and CPU seconds a frame and megabytes a frame (the USD cache and the slope
    layer's EXR files); then the per-frame time (frame_set, interleaved) of the baked ocean,
    which reads its cache, against the same ocean live at that grid; and the share of the
    bake's time spent building the frames (the steps Esc can cancel), the rest the export."""
    def made(name):
        scene = projected_scene(257)
        scene.name = f"bake {name}"
        obj = _ocean(scene)
        obj.projgrid.resolution_x, obj.projgrid.resolution_y = 257, 513  # as rendered
        scene.frame_start, scene.frame_end = 1, frames
        scene.frame_set(1)
        return scene, obj

    folder = tempfile.mkdtemp(prefix="projgrid-bake-")
    baked, obj = made("baked")
    live, _ = made("live")
    bake = extension().operators.bridge.bake
    with bpy.context.temp_override(scene=baked, view_layer=baked.view_layers[0],
                                   active_object=obj, object=obj):
        wall, cpu = time.perf_counter(), time.process_time()
        job = bake.Bake(bpy.context, obj, os.path.join(folder, "sea.usdc"), 1, frames)
        while job.step():
            pass
        building = time.perf_counter() - wall
        job.finish()  # as the operator: the steps, then the export
        wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    size = sum(os.path.getsize(os.path.join(root, f))
               for root, _, files in os.walk(folder) for f in files)

    def play(scene):
        scene.frame_set(1 + scene.frame_current % frames)

    times = interleaved({"baked (reads its cache)": lambda: play(baked),
                         "live (builds the grid)": lambda: play(live)}, repeats)
    extension().operators.bridge.baked.free(obj)
    for scene in (baked, live):
        bpy.data.scenes.remove(scene)
    shutil.rmtree(folder, ignore_errors=True)
    return {"frames": frames, "seconds_per_frame": wall / frames, "cpu_per_frame": cpu / frames,
            "building_share": building / wall,
            "mb_per_frame": size / 2**20 / frames,
            "play": [{"variant": k, **v.ms()} for k, v in times.items()]}


def rebuild_cost(sizes=(17, 65, 145, 257, 577, 1025), repeats=15):
    """Per-frame time of `scene.frame_set` (camera update -> vertices in the Blender mesh)."""
    bpy.app.handlers.frame_change_post.append(world_grid_handler)
    rows = []
    try:
        for n in sizes:
            scenes = {"projected grid": _calm(projected_scene(n, source="PERLIN")),
                      "projected grid, exact noise": _calm(projected_scene(n, "EXACT",
                                                                           "PERLIN")),
                      "projected grid, spectrum": _calm(projected_scene(n)),
                      "Ocean modifier": ocean_modifier_scene(n),
                      "world grid": world_grid_scene(n)}
            times = interleaved({k: (lambda s=s: step(s)) for k, s in scenes.items()},
                                max(3, repeats if n <= 257 else repeats // 3))
            for kind, timing in times.items():
                rows.append({"n": n, "vertices": n * n, "mesh": kind, **timing.ms()})
            for s in scenes.values():
                bpy.data.scenes.remove(s)
    finally:
        bpy.app.handlers.frame_change_post.remove(world_grid_handler)
    return rows


EFFECT_VARIANTS = {  # name: (modes set on the ocean, the rest AUTO; whether the sun shines)
    "everything off": (dict.fromkeys(EFFECTS, "OFF"), True),
    "bare ocean, auto": ({}, True),
    "everything off, no sun": (dict.fromkeys(EFFECTS, "OFF"), False),
    "bare ocean, auto, no sun": ({}, False),
    **{f"{e.replace('_', ' ')} on": ({e: "ON"}, True) for e in EFFECTS},
}


def _calm(scene):
    """The scene's ocean on a light breeze (Beaufort 2), whose wind calls for no whitecaps, and
    not choppy."""
    ocean = _ocean(scene)
    ocean.projgrid.wind_speed, ocean.projgrid.fetch, ocean.projgrid.choppiness = 2.5, 0.0, 0.0
    return scene


def _set_modes(scene, variant):
    """The effects of `variant` on a light breeze: a bare ocean's AUTO then calls for none."""
    modes, sun = EFFECT_VARIANTS[variant]
    ocean = _ocean(_calm(scene))
    for effect in EFFECTS:
        setattr(ocean.projgrid, effect, modes.get(effect, "AUTO"))
    for obj in scene.objects:
        if obj.type == "LIGHT" and obj.data.type == "SUN":
            obj.hide_render = obj.hide_viewport = not sun
    return ocean


def effect_cost(n=257, repeats=15):
    """Per-frame rebuild time of the same ocean with its effects off, at AUTO (a bare ocean:
    nothing is called for, with or without a sun), and with each effect on alone, measured
    interleaved."""
    scenes = {}
    for name in EFFECT_VARIANTS:
        scenes[name] = projected_scene(n)
        _set_modes(scenes[name], name)
    times = interleaved({k: (lambda s=s: step(s)) for k, s in scenes.items()}, repeats)
    rows = []
    for name, timing in times.items():
        ocean = _ocean(scenes[name])
        rows.append({"variant": name, **timing.ms(),
                     "active": sorted(ocean.projgrid.active_effects)})
    for s in scenes.values():
        bpy.data.scenes.remove(s)
    return rows


