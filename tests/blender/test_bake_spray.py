"""The bake holds the spray (issue 36): a gale's puffs written with its sea into the USD cache,
played by the spray's companion where no script runs (a baked storm's render: test_bake.py)."""

import textwrap

import bpy
import numpy as np
import pytest

from .helpers import positions, seen_without_extension

SPRAY_SEEN = textwrap.dedent("""
    out = sys.argv[2]
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
        seen[f"haze{frame}"] = cloud.get("projgrid_haze", 0.0)
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


def test_a_baked_gale_plays_its_spray_without_the_extension(moving, bridge, extension,
                                                              tmp_path):
    """A gale's spray is baked with its sea, the spray keyed off on frame 2: opened in a fresh
    process with no extension, the spray's points at frames 1 and 3 are the puffs the live
    render of that frame draws, where they were, as large and as opaque, in the same haze
    (the air's extinction the live frame gave its material), and frame 2 shows none."""
    scene, obj = moving
    obj.projgrid.wind_speed = 22.0  # a strong gale's: spray
    for frame, mode in ((1, "AUTO"), (2, "OFF"), (3, "AUTO")):
        obj.projgrid.spray = mode
        obj.projgrid.keyframe_insert("spray", frame=frame)
    # a file's spray of an older version: its points' tree and material rebuilt, hazed
    water, materials = extension.shaders.water, extension.shaders.materials
    old = (bpy.data.node_groups[water.SPRAY_POINTS], bpy.data.materials[water.SPRAY_MATERIAL])
    for block in old:
        block[extension.shaders.nodes.TAG] = water.VERSION - 1
    old[1].node_tree.nodes.remove(old[1].node_tree.nodes[materials.HAZE])
    want = {}
    for f in (1, 3):
        scene.frame_set(f)
        bridge.frame.update_ocean(obj, scene, bpy.context.evaluated_depsgraph_get(), render=True)
        want[f] = _puffs(obj.projgrid.spray_cloud)
        assert len(want[f][0]) > 100, f
    assert materials.HAZE in old[1].node_tree.nodes and all(
        block[extension.shaders.nodes.TAG] == water.VERSION for block in old)
    haze = obj.projgrid.spray_cloud["projgrid_haze"]  # Add Ocean's sky: the water's haze
    assert haze == pytest.approx(extension.projgrid_addon.daylight.haze_extinction(22.0))
    assert bpy.ops.projgrid.bake(filepath=str(tmp_path / "sea.usdc"), frame_start=1,
                                 frame_end=3) == {"FINISHED"}
    seen = seen_without_extension(tmp_path, SPRAY_SEEN)
    for f in (1, 3):
        at, radius, opacity = want[f]
        assert seen[f"shown{f}"] and seen[f"at{f}"].shape == at.shape, f
        assert np.allclose(seen[f"at{f}"], at, atol=2e-3), f
        assert np.allclose(seen[f"radius{f}"], radius, rtol=1e-6), f
        assert np.allclose(seen[f"opacity{f}"], opacity, rtol=1e-6), f
        assert seen[f"haze{f}"] == pytest.approx(haze), f
    assert not seen["shown2"] and "at2" not in seen.files  # spray off on frame 2: none drawn
    assert not np.allclose(want[1][0][:100], want[3][0][:100])  # the spray moved
