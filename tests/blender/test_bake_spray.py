"""The bake holds the spray (issue 36): a gale's puffs written with its sea into the USD cache,
played by the spray's companion where no script runs."""

import os
import subprocess
import sys
import tempfile
import textwrap

import bpy
import numpy as np
import pytest

from .helpers import positions
from .test_bake import RENDER_FRESH

SPRAY_FRESH = textwrap.dedent("""
    import sys
    import bpy
    import numpy as np
    blend, out = sys.argv[1:3]
    bpy.ops.wm.open_mainfile(filepath=blend)
    assert not [m for m in sys.modules if "projected_grid_ocean" in m]  # no extension
    scene, seen = bpy.context.scene, {}
    cloud = bpy.data.objects["Ocean Spray"]
    for frame in (1, 2, 3):
        scene.frame_set(frame)
        for instance in bpy.context.evaluated_depsgraph_get().object_instances:
            points = instance.object  # valid while the iteration is at it
            if points.original != cloud or points.type != "POINTCLOUD":
                continue
            n = len(points.data.points)
            at, radius = np.empty(3 * n, np.float32), np.empty(n, np.float32)
            opacity = np.empty(n, np.float32)
            points.data.attributes["position"].data.foreach_get("vector", at)
            points.data.attributes["radius"].data.foreach_get("value", radius)
            points.data.attributes["projgrid_spray_opacity"].data.foreach_get("value", opacity)
            world = np.array(instance.matrix_world)
            seen[f"at{frame}"] = at.reshape(n, 3) @ world[:3, :3].T + world[:3, 3]
            seen[f"radius{frame}"], seen[f"opacity{frame}"] = radius, opacity
        seen[f"shown{frame}"] = not cloud.hide_render
    np.savez(out, **seen)
""")


def _puffs(cloud):
    """The live spray companion's puffs: world positions, radii and opacities."""
    n = len(cloud.data.vertices)
    radius, opacity = np.empty(n, np.float32), np.empty(n, np.float32)
    cloud.data.attributes["projgrid_spray_radius"].data.foreach_get("value", radius)
    cloud.data.attributes["projgrid_spray_opacity"].data.foreach_get("value", opacity)
    world = np.array(cloud.matrix_world)
    return positions(cloud.data) @ world[:3, :3].T + world[:3, 3], radius, opacity


def test_a_baked_gale_plays_its_spray_without_the_extension(moving, bridge, tmp_path):
    """A gale's spray is baked with its sea, the spray keyed off on frame 2: opened in a fresh
    process with no extension, the spray's points at frames 1 and 3 are the puffs the live
    render of that frame draws, where they were, as large and as opaque, and frame 2 shows
    none."""
    scene, obj = moving
    obj.projgrid.wind_speed = 22.0  # a strong gale's: spray
    for frame, mode in ((1, "AUTO"), (2, "OFF"), (3, "AUTO")):
        obj.projgrid.spray = mode
        obj.projgrid.keyframe_insert("spray", frame=frame)
    want = {}
    for f in (1, 3):
        scene.frame_set(f)
        bridge.frame.update_ocean(obj, scene, bpy.context.evaluated_depsgraph_get(), render=True)
        want[f] = _puffs(obj.projgrid.spray_cloud)
        assert len(want[f][0]) > 100, f
    assert bpy.ops.projgrid.bake(filepath=str(tmp_path / "sea.usdc"), frame_start=1,
                                 frame_end=3) == {"FINISHED"}
    blend = str(tmp_path / "baked.blend")
    bpy.ops.wm.save_as_mainfile(filepath=blend, copy=True)
    out = str(tmp_path / "seen.npz")
    env = {**os.environ, "BLENDER_USER_RESOURCES": tempfile.mkdtemp(prefix="no-extension-")}
    done = subprocess.run([sys.executable, "-c", SPRAY_FRESH, blend, out], env=env,
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    seen = np.load(out)
    for f in (1, 3):
        at, radius, opacity = want[f]
        assert seen[f"shown{f}"] and seen[f"at{f}"].shape == at.shape, f
        assert np.allclose(seen[f"at{f}"], at, atol=2e-3), f
        assert np.allclose(seen[f"radius{f}"], radius, rtol=1e-6), f
        assert np.allclose(seen[f"opacity{f}"], opacity, rtol=1e-6), f
    assert not seen["shown2"] and "at2" not in seen.files  # spray off on frame 2: none drawn
    assert not np.allclose(want[1][0][:100], want[3][0][:100])  # the spray moved


@pytest.mark.slow
def test_a_baked_gale_renders_its_spray_without_the_extension(tmp_path):
    """A gale from 4 m up, the wind blowing away from the camera, baked over frames 1..2: frame
    2 rendered by a fresh process with no extension matches the live render within the shot
    tolerances, spray and all (the spray changes the live picture several times as much)."""
    from tools.demo import default_shot

    from .test_shots import MEAN_TOL, OUTLIER_SHARE, OUTLIER_TOL, read

    scene = bpy.context.scene
    default_shot(scene, size=(160, 90), samples=4, height=4.0, pitch=-3.0)
    ocean = bpy.data.objects["Ocean"]
    ocean.projgrid.wind_speed, ocean.projgrid.wind_direction = 26.0, 1.57
    scene.frame_start, scene.frame_end = 1, 2
    live = {}
    for spray in ("OFF", "AUTO"):
        ocean.projgrid.spray = spray
        scene.frame_set(2)
        scene.render.filepath = live[spray] = str(tmp_path / f"live_{spray}.png")
        bpy.ops.render.render(write_still=True)
    scene.frame_set(1)
    assert bpy.ops.projgrid.bake(filepath=str(tmp_path / "sea.usdc"), frame_start=1,
                                 frame_end=2) == {"FINISHED"}
    blend = str(tmp_path / "baked.blend")
    bpy.ops.wm.save_as_mainfile(filepath=blend, copy=True)
    env = {**os.environ, "BLENDER_USER_RESOURCES": tempfile.mkdtemp(prefix="no-extension-")}
    baked = str(tmp_path / "baked.png")
    done = subprocess.run([sys.executable, "-c", RENDER_FRESH, blend, "2", baked], env=env,
                          capture_output=True, text=True, timeout=900)
    assert done.returncode == 0, done.stderr[-2000:]
    diff = np.abs(read(baked) - read(live["AUTO"]))
    outliers = float((diff.max(axis=-1) > OUTLIER_TOL).mean())
    assert diff.mean() <= MEAN_TOL and outliers <= OUTLIER_SHARE, (diff.mean(), outliers)
    spray = np.abs(read(live["AUTO"]) - read(live["OFF"])).mean()
    assert spray > 5.0 * diff.mean(), (spray, diff.mean())
