"""Every render path rebuilds the grid for the frame being rendered, with the render camera, the
render grid resolution and the animated settings, and frame N is the same whatever came before.

The renders use Workbench at 64 x 36: what is checked is the mesh each rendered frame saw
(captured by a render_post handler), which does not depend on the engine; the EEVEE shots are in
test_shots.py. The expected mesh is built by the same bridge call in render mode from a separate
viewport evaluation of that frame.
"""

import os
import subprocess
import sys
import textwrap

import bpy
import numpy as np
import pytest

from tools.package import ROOT

from .conftest import USER
from .helpers import RenderCapture, add_camera, add_ocean, render_mesh

RENDER_RES = (33, 65)


@pytest.fixture
def animated(tmp_path):
    """An ocean whose amplitude and camera are keyframed over frames 1..3."""
    scene = bpy.context.scene
    cam = add_camera(scene)
    obj = add_ocean("PERLIN")  # its amplitude, keyframed
    s = obj.projgrid
    s.render_resolution_x, s.render_resolution_y = RENDER_RES
    s.amplitude = 0.05
    s.keyframe_insert("amplitude", frame=1)
    s.amplitude = 2.0
    s.keyframe_insert("amplitude", frame=3)
    cam.keyframe_insert("location", frame=1)
    cam.location.x += 5.0
    cam.keyframe_insert("location", frame=3)
    r = scene.render
    r.engine = "BLENDER_WORKBENCH"
    r.resolution_x, r.resolution_y, r.resolution_percentage = 64, 36, 100
    r.image_settings.file_format = "PNG"
    r.filepath = str(tmp_path / "frame_")
    scene.frame_start, scene.frame_end = 1, 3
    scene.frame_set(1)
    return scene, obj


expected = render_mesh


def test_still_render_f12(animated, bridge):
    scene, obj = animated
    scene.frame_set(2)
    with RenderCapture() as seen:
        bpy.ops.render.render(write_still=False)
    assert seen.frames[2].shape == (RENDER_RES[0] * RENDER_RES[1], 3)
    assert np.array_equal(seen.frames[2], expected(scene, obj, bridge, 2))
    assert len(obj.data.vertices) == 65 * 129  # the viewport grid is back after the render


def test_frame_set_and_write_still(animated, bridge, tmp_path):
    scene, obj = animated
    scene.frame_set(3)
    scene.render.filepath = str(tmp_path / "still.png")
    with RenderCapture() as seen:
        bpy.ops.render.render(write_still=True)
    assert os.path.exists(tmp_path / "still.png")
    assert np.array_equal(seen.frames[3], expected(scene, obj, bridge, 3))


def test_animation_render_honours_animated_settings(animated, bridge):
    scene, obj = animated
    with RenderCapture() as seen:
        bpy.ops.render.render(animation=True)
    assert sorted(seen.frames) == [1, 2, 3]
    for frame, mesh in seen.frames.items():
        assert np.array_equal(mesh, expected(scene, obj, bridge, frame)), frame
    # amplitude 0.05 -> 2.0 and the camera moved 5 m: both reached the render
    assert np.abs(seen.frames[1][:, 2]).max() < 0.1 < np.abs(seen.frames[3][:, 2]).max()
    assert not np.array_equal(seen.frames[1][:, :2], seen.frames[3][:, :2])

    # Frame independence: frame 3 rendered alone is the frame 3 of the sequence.
    scene.frame_start = 3
    with RenderCapture() as alone:
        bpy.ops.render.render(animation=True)
    assert np.array_equal(alone.frames[3], seen.frames[3])


WORKER = textwrap.dedent("""
    import sys
    import bpy
    import numpy as np
    blend, first, last, out, root = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), *sys.argv[4:]
    sys.path.insert(0, root)
    from tests.blender.helpers import positions
    bpy.ops.wm.read_userpref()  # the blender binary loads these at startup; bpy as a module not
    bpy.ops.wm.open_mainfile(filepath=blend)
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = first, last
    seen = {}
    def capture(scene, _=None):
        seen[str(scene.frame_current)] = positions(bpy.data.objects["Ocean"].data).copy()
    bpy.app.handlers.render_post.append(capture)
    bpy.ops.render.render(animation=True)
    np.savez(out, **seen)
    bpy.app.handlers.render_post.remove(capture)  # bpy 4.5 hangs at exit if it is left
""")


@pytest.mark.parametrize("frames", [(1, 3), (2, 3)], ids=["blender -b file -a",
                                                         "farm --render-frame 2..3"])
def test_saved_file_rendered_in_a_fresh_background_process(animated, bridge, tmp_path, frames):
    """A fresh process with the extension enabled in its preferences (as `blender -b` starts)
    opens the saved .blend and renders a frame range, as `-a` and a farm worker's
    `--render-frame a..b` do."""
    scene, obj = animated
    blend = str(tmp_path / "ocean.blend")
    bpy.ops.wm.save_as_mainfile(filepath=blend, copy=True)
    out = str(tmp_path / "seen.npz")
    env = {**os.environ, "BLENDER_USER_RESOURCES": USER}
    done = subprocess.run([sys.executable, "-c", WORKER, blend, *map(str, frames), out, ROOT],
                          env=env, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    seen = np.load(out)
    assert sorted(map(int, seen.files)) == list(range(frames[0], frames[1] + 1))
    for frame in seen.files:
        assert np.array_equal(seen[frame], expected(scene, obj, bridge, int(frame))), frame
