"""Small helpers shared by the Blender tests."""

import os
import subprocess
import sys
import tempfile
from importlib import import_module

import bpy
import numpy as np

from tools.demo import MODULE, add_camera

__all__ = ["RenderCapture", "add_camera", "add_ocean", "core", "positions",
           "seen_without_extension", "without_extension", "workbench"]


def positions(mesh):
    co = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
    mesh.attributes["position"].data.foreach_get("vector", co)
    return co.reshape(-1, 3)


# What a `without_extension` script starts with: the saved file opened (sys.argv[1]), no
# extension of ours loaded; its own arguments follow in sys.argv[2:].
FRESH = """import sys
import bpy
import numpy as np
bpy.ops.wm.open_mainfile(filepath=sys.argv[1])
assert not [m for m in sys.modules if "projected_grid_ocean" in m]  # no extension
"""


def without_extension(tmp_path, script, *args, timeout=600):
    """The open file saved as a copy (tmp_path/baked.blend), and FRESH then `script` run on it
    by a fresh Python with no extension installed (a private user folder), `args` its own
    arguments; the test fails with the end of its errors if the script does."""
    blend = str(tmp_path / "baked.blend")
    bpy.ops.wm.save_as_mainfile(filepath=blend, copy=True)
    env = {**os.environ, "BLENDER_USER_RESOURCES": tempfile.mkdtemp(prefix="no-extension-")}
    done = subprocess.run([sys.executable, "-c", FRESH + script, blend, *map(str, args)],
                          env=env, capture_output=True, text=True, timeout=timeout)
    assert done.returncode == 0, done.stderr[-2000:]


def seen_without_extension(tmp_path, script, *args):
    """`without_extension` of a script that saves what it saw in the file named by its first
    argument (tmp_path/seen.npz, then `args`): those arrays."""
    out = tmp_path / "seen.npz"
    without_extension(tmp_path, script, out, *args)
    return np.load(out)


def render_mesh(scene, obj, bridge, frame):
    """The mesh a render of `frame` builds for ocean `obj` (the viewport grid back after)."""
    scene.frame_set(frame)
    bridge.frame.update_ocean(obj, scene, bpy.context.evaluated_depsgraph_get(), render=True)
    mesh = positions(obj.data).copy()
    scene.frame_set(frame)
    return mesh


def spectral_sea():
    """A camera 6 m up looking along +Y a little down, and a spectral ocean at force 5, at
    frame 2."""
    scene = bpy.context.scene
    add_camera(scene)
    obj = add_ocean()
    obj.projgrid.height_source = "SPECTRUM"
    assert bpy.ops.projgrid.sea_state(beaufort=5) == {"FINISHED"}
    scene.frame_set(2)
    return obj


def add_ocean(source=None):
    """Add Ocean (the spectral sea at its default force), or with `source` "PERLIN" the noise
    with its height and wavelength set by hand, not From Wind (for the tests of the noise's own
    settings: amplitude, octaves, the exact path)."""
    assert bpy.ops.projgrid.add_ocean() == {"FINISHED"}
    obj = bpy.context.active_object
    if source is not None:
        obj.projgrid.height_source = source
        obj.projgrid.noise_from_wind = source != "PERLIN"
    return obj


class RenderCapture:
    """Records the ocean mesh as each frame is rendered (a render_post handler)."""

    def __init__(self, name="Ocean"):
        self.name = name
        self.frames = {}

    def __call__(self, scene, _=None):
        self.frames[scene.frame_current] = positions(bpy.data.objects[self.name].data).copy()

    def __enter__(self):
        bpy.app.handlers.render_post.append(self)
        return self

    def __exit__(self, *exc):
        bpy.app.handlers.render_post.remove(self)


RENDER_RES = (17, 33)  # the bake tests' render grid


def workbench(scene, size=(64, 36)):
    r = scene.render
    r.engine = "BLENDER_WORKBENCH"
    r.resolution_x, r.resolution_y = size
    r.resolution_percentage = 100


def core(name):
    return import_module(f"{MODULE}.projgrid_addon.{name}")
