"""A storm building over a shot: the wind keyed from Beaufort 3 to 9 over ten seconds (the sea
state of force 9 otherwise, so its fetch and choppiness), blowing toward the camera from 30
degrees left of its view (the waves come at it, their faces and the streaks along the wind in
view, as a storm is watched from a deck facing the sea), the sun behind the camera as for the
Beaufort pictures (tools/beaufort.py), the sky keyed at each shot to the cloud
of the wind then (sea_states.overcast_for_wind), rendered at six times from 20 m up and put
side by side in docs/storm_strip.png, left to right in time.

`make bench` runs it (step `strip`); alone: python -m tools.storm_strip [out_dir] [--quick]."""

import math
import os
import tempfile

FORCES = (3, 9)
SECONDS = 10.0
TIMES = (0.0, 2.0, 4.0, 6.0, 8.0, 10.0)
HEIGHT, PITCH = 20.0, -8.0
WIND = -60.0  # deg counter-clockwise from +X, where the wind blows toward (the camera looks +Y)


def _key_weather(scene, frame, wind):
    """The weather of a wind of `wind` m/s at `frame`, keyed on our sky's overcast and sun."""
    from tools.bench.blender_bench import extension

    ext = extension()
    ext.shaders.sky.weather(scene, ext.projgrid_addon.sea_states.overcast_for_wind(wind))
    node = scene.world.node_tree.nodes[ext.shaders.sky.OVERCAST]
    node.inputs["Factor"].keyframe_insert("default_value", frame=frame)
    for obj in scene.objects:
        if obj.type == "LIGHT":
            obj.data.keyframe_insert("energy", frame=frame)
            obj.data.keyframe_insert("angle", frame=frame)


def _force(sea_states, wind):
    """The Beaufort force whose wind (the middle of its range) is nearest `wind`."""
    return min(sea_states.BEAUFORT, key=lambda f: abs(sea_states.BEAUFORT[f][1] - wind))


def shoot(out, quick=False):
    """Render the strip into `out` (the extension installed); returns its rows (time, wind,
    force) and the picture's name."""
    import bpy
    import numpy as np
    from bpy_extras import anim_utils

    from projgrid_addon import sea_states
    from tools.beaufort import render, sun_behind
    from tools.demo import default_shot

    size, samples = ((160, 90), 4) if quick else ((320, 180), 16)
    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    default_shot(scene, size=size, samples=samples, height=HEIGHT, pitch=PITCH)
    ocean = bpy.data.objects["Ocean"]
    bpy.context.view_layer.objects.active = ocean
    ocean.projgrid.wind_direction = math.radians(WIND)  # Sea State turns the swell off it
    bpy.ops.projgrid.sea_state(beaufort=FORCES[1])
    sun_behind(scene)
    fps = scene.render.fps / scene.render.fps_base
    frames = [1 + round(t * fps) for t in (0.0, SECONDS)]
    winds = [sea_states.BEAUFORT[force][1] for force in FORCES]
    for frame, wind in zip(frames, winds, strict=True):
        ocean.projgrid.wind_speed = wind
        ocean.projgrid.keyframe_insert("wind_speed", frame=frame)
    bag = anim_utils.action_get_channelbag_for_slot(ocean.animation_data.action,
                                                    ocean.animation_data.action_slot)
    for key in bag.fcurves.find("projgrid.wind_speed").keyframe_points:
        key.interpolation = "LINEAR"  # the wind rises at a steady rate through the shots
    for t in TIMES:  # the weather of the keyed wind, at each shot
        scene.frame_set(1 + round(t * fps))
        wind = ocean.evaluated_get(bpy.context.evaluated_depsgraph_get()).projgrid.wind_speed
        _key_weather(scene, scene.frame_current, wind)
    work = tempfile.mkdtemp(prefix="projgrid-strip-")
    tiles, rows = [], []
    for t in TIMES:
        frame = 1 + round(t * fps)
        scene.frame_set(frame)
        wind = ocean.evaluated_get(bpy.context.evaluated_depsgraph_get()).projgrid.wind_speed
        force = _force(sea_states, wind)
        path = os.path.join(work, f"strip_{frame}.png")
        render(scene, path)
        img = bpy.data.images.load(path)
        w, h = img.size
        tiles.append(np.array(img.pixels[:], np.float32).reshape(h, w, 4))
        bpy.data.images.remove(img)
        rows.append({"time": t, "frame": frame, "wind": float(wind), "force": force})
    strip = np.concatenate(tiles, axis=1)
    name = "storm_strip.png"
    image = bpy.data.images.new("strip", strip.shape[1], strip.shape[0])
    image.pixels.foreach_set(strip.ravel())
    image.filepath_raw = os.path.join(out, name)
    image.file_format = "PNG"
    image.save()
    bpy.data.images.remove(image)
    return {"rows": rows, "path": name}


if __name__ == "__main__":
    from tools.beaufort import standalone

    print(standalone(shoot))
