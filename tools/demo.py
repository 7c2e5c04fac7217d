"""`make demo`: render the built-in default shot (camera, sky, sun, ocean) with EEVEE.

Usage: python tools/demo.py [output.png]   (prints the image's path)
The extension is installed from its built zip into a private user directory, as a user would.
"""

import math
import os
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MODULE = "bl_ext.user_default.projected_grid_ocean"


def install(zip_path):
    """Install and enable the extension zip (BLENDER_USER_RESOURCES must be set before bpy)."""
    import bpy

    result = bpy.ops.extensions.package_install_files(filepath=zip_path, repo="user_default",
                                                      enable_on_install=True)
    if result != {"FINISHED"} or MODULE not in bpy.context.preferences.addons:
        raise RuntimeError(f"installing {zip_path} failed: {result}")


def eevee_engine():
    import bpy

    items = bpy.types.RenderSettings.bl_rna.properties["engine"].enum_items.keys()
    return "BLENDER_EEVEE_NEXT" if "BLENDER_EEVEE_NEXT" in items else "BLENDER_EEVEE"


def add_camera(scene, location=(0.0, 0.0, 6.0), rotation=(84.0, 0.0, 0.0), lens=50.0):
    """A camera (clip 0.1 m to 20 km) as the scene camera; rotation in degrees (XYZ Euler:
    (90, 0, 0) looks along +Y, level)."""
    import bpy

    data = bpy.data.cameras.new("Camera")
    data.lens = lens
    data.clip_start, data.clip_end = 0.1, 20_000.0
    cam = bpy.data.objects.new("Camera", data)
    cam.location = location
    cam.rotation_euler = [math.radians(a) for a in rotation]
    scene.collection.objects.link(cam)
    scene.camera = cam
    return cam


def default_shot(scene, size=(960, 540), samples=16, height=6.0, pitch=-6.0):
    """The default shot: a camera `height` m above the water looking along +Y, EEVEE settings,
    then Add Ocean (which adds the sky and the sun, low ahead of the camera, for the glint)."""
    import bpy

    cam = add_camera(scene, (0.0, 0.0, height), (90.0 + pitch, 0.0, 0.0), lens=35.0)
    r = scene.render
    r.engine = eevee_engine()
    r.resolution_x, r.resolution_y = size
    r.resolution_percentage = 100
    scene.eevee.taa_render_samples = samples
    r.image_settings.file_format = "PNG"
    scene.cursor.location = (0.0, 0.0, 0.0)
    bpy.ops.projgrid.add_ocean()
    return cam


def say(what):
    """One line of progress (on stderr: stdout is the image's path alone)."""
    print(f"demo: {what}", file=sys.stderr, flush=True)


def main(out):
    os.environ.setdefault("BLENDER_USER_RESOURCES", tempfile.mkdtemp(prefix="projgrid-user-"))
    sys.path.insert(0, ROOT)
    say("starting Blender (as a Python module)")
    import bpy

    from tools.package import build

    say("building and installing the extension as a user does")
    install(build(tempfile.mkdtemp(prefix="projgrid-dist-")))
    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    default_shot(scene)
    scene.frame_set(24)
    scene.render.filepath = os.path.abspath(out)
    say("rendering 960x540 with EEVEE on the CPU: compiling its shaders first takes 10-40 s, "
        "the render about a minute")
    bpy.ops.render.render(write_still=True)
    say("done")
    print(os.path.abspath(out))


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "out", "ocean.png"))
