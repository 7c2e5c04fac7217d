"""The light (issue 38): the sea at Beaufort 3 from 6 m up under the sky Add Ocean makes, at
sunset (the sun 3 degrees up, ahead), at noon (45 degrees up, behind the camera) and under an
overcast with no sun lamp (the Sea State's storm sky turned full, at Beaufort 5); written to
docs/light_sunset.png, light_noon.png and light_overcast.png.

Alone: python -m tools.light_shots [out_dir] [--quick] (a small, few-sample render)."""

import os

SHOTS = {  # name: (Beaufort force, sun elevation or None (no lamp), sun azimuth, cloud)
    "sunset": (3, 3.0, 0.0, 0.0),
    "noon": (3, 45.0, 180.0, 0.0),
    "overcast": (5, None, 0.0, 1.0),
}
FRAME = 48


def shoot(out, quick=False):
    import bpy

    from tools.bench.blender_bench import extension
    from tools.demo import default_shot

    sky = extension().shaders.sky
    paths = []
    for name, (force, elevation, azimuth, cloud) in SHOTS.items():
        bpy.ops.wm.read_homefile(use_empty=True)
        scene = bpy.context.scene
        size, samples = ((320, 180), 4) if quick else ((960, 540), 16)
        default_shot(scene, size=size, samples=samples, height=6.0, pitch=-2.0)
        assert bpy.ops.projgrid.sea_state(beaufort=force, weather=False) == {"FINISHED"}
        sun = next(o for o in scene.objects if o.type == "LIGHT")
        if elevation is None:
            bpy.data.objects.remove(sun)
        else:
            sky.aim(sun, elevation, azimuth)
        sky.weather(scene, cloud)
        scene.frame_set(FRAME)
        scene.render.filepath = os.path.join(out, f"light_{name}.png")
        bpy.ops.render.render(write_still=True)
        paths.append(scene.render.filepath)
    return {"pictures": paths}


if __name__ == "__main__":
    from tools.beaufort import standalone

    print(standalone(shoot))
