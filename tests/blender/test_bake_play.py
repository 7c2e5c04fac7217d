"""Playing a bake: the scene restored and baked again, keys kept through renders, companions
under the water, duplicates, and a bake flagged out of date once its camera or settings
change."""

import errno
import math
import os
import textwrap
import time

import bpy
import numpy as np
import pytest

from .helpers import RENDER_RES, positions, render_mesh, seen_without_extension

live = render_mesh  # the mesh a render of a frame builds


def test_a_bake_restores_the_scene_and_bakes_again_from_the_live_sea(moving, bridge, tmp_path):
    """The frame range, current frame, selection and active object are as they were; a bake
    made again over a baked ocean records the live sea (not the old bake) and replaces it."""
    scene, obj = moving
    scene.frame_set(3)
    path = str(tmp_path / "sea.usdc")
    assert bpy.ops.projgrid.bake(filepath=path, frame_start=1, frame_end=2) == {"FINISHED"}
    assert (scene.frame_start, scene.frame_end, scene.frame_current) == (1, 3, 3)
    assert bpy.context.view_layer.objects.active == obj
    assert [o.name for o in bpy.context.view_layer.objects if o.select_get()] == ["Ocean"]

    def played():
        scene.frame_set(2)
        return positions(obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data).copy()

    first = played()
    obj.projgrid.seed += 1  # another sea: a second bake must record it, not the first bake
    assert bpy.ops.projgrid.bake_free() == {"FINISHED"}
    want = live(scene, obj, bridge, 2)
    assert bpy.ops.projgrid.bake(filepath=str(tmp_path / "sea.usdc"), frame_start=1,
                                 frame_end=2) == {"FINISHED"}
    obj.projgrid.seed -= 1
    assert bpy.ops.projgrid.bake(filepath=path, frame_start=1, frame_end=2) == {"FINISHED"}
    obj.projgrid.seed += 1
    assert bpy.ops.projgrid.bake(filepath=path, frame_start=1, frame_end=2) == {"FINISHED"}
    assert len([m for m in obj.modifiers if m.type == "MESH_SEQUENCE_CACHE"]) == 1
    again = played()
    assert np.allclose(again, want, rtol=1e-6, atol=1e-5) and not np.allclose(again, first)
    assert sorted(os.listdir(tmp_path)) == ["sea.usdc", "sea_slopes"]


def test_a_parented_ocean_with_any_name_plays_its_bake(moving, bridge, tmp_path):
    """The cache's mesh is found under the exporter's names for a parent and a non-ASCII name."""
    scene, obj = moving
    rig = bpy.data.objects.new("Rig 1", None)
    scene.collection.objects.link(rig)
    obj.parent = rig
    obj.name = "Océan"
    want = live(scene, obj, bridge, 2)
    assert bpy.ops.projgrid.bake(filepath=str(tmp_path / "sea.usdc"), frame_start=1,
                                 frame_end=2) == {"FINISHED"}
    scene.frame_set(2)
    played = positions(obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data)
    assert np.allclose(played, want, rtol=1e-6, atol=1e-5)


def test_a_failed_export_leaves_the_ocean_live_and_nothing_behind(moving, bridge, tmp_path):
    scene, obj = moving
    (tmp_path / "sea.partial.usdc").mkdir()  # the exporter cannot write its file
    with pytest.raises(RuntimeError, match="Bake not made"):
        bpy.ops.projgrid.bake(filepath=str(tmp_path / "sea.usdc"), frame_start=1, frame_end=2)
    assert not bridge.baked.is_baked(obj) and not obj.modifiers
    assert not [n for n in os.listdir(tmp_path) if n != "sea.partial.usdc"]
    assert bpy.data.node_groups.get(bridge.bake.TIMER) is None
    assert bpy.data.images.get(bridge.bake_record.SCRATCH) is None


def test_a_full_disk_leaves_the_ocean_live_and_nothing_behind(moving, bridge, monkeypatch,
                                                              tmp_path):
    scene, obj = moving

    def full(*args, **kwargs):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(bridge.bake_record.np, "savez", full)
    scene.frame_set(2)
    with pytest.raises(RuntimeError, match="Bake not made.*keeping frame 1 failed: No space"):
        bpy.ops.projgrid.bake(filepath=str(tmp_path / "sea.usdc"), frame_start=1, frame_end=2)
    assert not bridge.baked.is_baked(obj) and not obj.modifiers and not os.listdir(tmp_path)
    assert bridge.state.RUNTIME.baking is None and scene.frame_current == 2


def test_a_baked_ocean_keeps_its_keys_through_renders(moving, bridge, tmp_path):
    """Renders (their start makes each surface's material its own) leave a baked ocean's
    material playing its keys and its slope layer's sequences."""
    scene, obj = moving
    assert bpy.ops.projgrid.bake(filepath=str(tmp_path / "sea.usdc"), frame_start=1,
                                 frame_end=3) == {"FINISHED"}
    keyed = set(obj.data.materials[0].node_tree[bridge.baked.KEYED])
    for _ in range(2):
        bridge.handlers.render_init(scene)
        bridge.handlers.render_done(scene)
    tree = obj.data.materials[0].node_tree
    assert keyed and set(tree[bridge.baked.KEYED]) == keyed
    assert keyed <= {c.data_path for c in bridge.scene.bag_curves(tree)}


def test_a_frame_that_sees_no_water_bakes_empty(moving, bridge, tmp_path):
    """A frame whose camera sees only the sky is baked as an empty mesh (the bake still plays,
    found by its prim path, not by the mesh of the frame it starts at)."""
    scene, obj = moving
    cam = scene.camera
    cam.rotation_euler.x = math.radians(170.0)  # straight up at frame 1
    cam.keyframe_insert("rotation_euler", frame=1)
    cam.rotation_euler.x = math.radians(80.0)
    cam.keyframe_insert("rotation_euler", frame=2)
    scene.frame_set(1)
    assert len(live(scene, obj, bridge, 1)) == 0 and len(live(scene, obj, bridge, 3))
    assert bpy.ops.projgrid.bake(filepath=str(tmp_path / "sea.usdc"), frame_start=1,
                                 frame_end=3) == {"FINISHED"}
    for frame, empty in ((1, True), (3, False)):
        scene.frame_set(frame)
        played = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
        assert (len(played.vertices) == 0) == empty, frame


def test_an_ocean_drawn_by_stand_ins_is_refused(moving, bridge, tmp_path):
    scene, obj = moving
    group = bpy.data.collections.new("Sea")
    group.objects.link(obj)
    holder = bpy.data.objects.new("Instancer", None)
    holder.instance_type, holder.instance_collection = "COLLECTION", group
    scene.collection.objects.link(holder)
    with pytest.raises(RuntimeError, match="Bake not made.*object: 'Ocean' shows more than"):
        bpy.ops.projgrid.bake(filepath=str(tmp_path / "sea.usdc"), frame_start=1, frame_end=2)
    assert not bridge.baked.is_baked(obj) and not os.listdir(tmp_path)


COMPANIONS_SEEN = textwrap.dedent("""
    out = sys.argv[2]
    scene, seen = bpy.context.scene, {}
    for frame in (1, 2):
        scene.frame_set(frame)
        body = bpy.data.objects["Ocean Water Body"]
        caster = bpy.data.objects["Ocean Shadow"]
        mesh = caster.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
        nodes = body.data.materials[0].node_tree.nodes
        seen[str(frame)] = np.array([*body.location, float(body.hide_render),
                                     len(mesh.vertices),
                                     nodes["Caustic U Offset"].inputs[1].default_value])
    bpy.data.objects["Ocean"].hide_render = True  # hidden after the bake: its companions too
    scene.frame_set(1)
    seen["hidden"] = np.array([body.hide_render, caster.hide_render])
    tile = nodes["Caustic Tile"]
    seen["tile"] = np.array([tile.image.source == "SEQUENCE", not nodes["Godrays"].mute,
                             tile.image_user.frame_start, tile.image_user.frame_duration])
    np.savez(out, **seen)
""")


def test_the_companions_under_the_water_play_their_bake(moving, bridge, tmp_path):
    """With the water body and the shadow caster in use, a fresh process without the extension
    finds the body where the live frames put it, shown, and the caster drawing the cache; the
    godrays' caustic tile, written each frame, is an image sequence of the frames' tiles, and
    the body material's inputs are the frames'. The ocean hidden after the bake hides them."""
    scene, obj = moving
    obj.projgrid.underwater = obj.projgrid.godrays = "ON"
    body = obj.projgrid.water_body
    want, tiles = {}, {}
    for f in (1, 2):
        scene.frame_set(f)
        bridge.frame.update_ocean(obj, scene, bpy.context.evaluated_depsgraph_get(),
                                  render=True)
        nodes = body.data.materials[0].node_tree.nodes
        want[f] = [*body.location, float(body.hide_render), RENDER_RES[0] * RENDER_RES[1],
                   nodes["Caustic U Offset"].inputs[1].default_value]
        tiles[f] = np.empty(len(nodes["Caustic Tile"].image.pixels), np.float32)
        nodes["Caustic Tile"].image.pixels.foreach_get(tiles[f])
    assert want[1][:2] != want[2][:2] and not want[1][3]  # it follows the moving camera
    assert want[1][-1] != want[2][-1] and not np.array_equal(tiles[1], tiles[2])
    scene.frame_set(1)
    assert bpy.ops.projgrid.bake(filepath=str(tmp_path / "sea.usdc"), frame_start=1,
                                 frame_end=2) == {"FINISHED"}
    seen = seen_without_extension(tmp_path, COMPANIONS_SEEN)
    for f in (1, 2):
        assert np.allclose(seen[str(f)], want[f], atol=1e-5), (f, seen[str(f)], want[f])
        saved = bpy.data.images.load(str(tmp_path / "sea_slopes" / f"godrays_{f:04d}.exr"))
        pixels = np.empty(len(saved.pixels), np.float32)
        saved.pixels.foreach_get(pixels)
        assert np.allclose(pixels, tiles[f], rtol=2e-3, atol=1e-3)  # (half floats)
    assert list(seen["tile"]) == [True, True, 1, 2]
    assert list(seen["hidden"]) == [True, True]
    assert bridge.baked.free(obj)  # (the operator's live update would mend the tile anyway)
    assert body.animation_data is None and not obj.projgrid.shadow_caster.modifiers
    tree = body.data.materials[0].node_tree
    assert tuple(tree.nodes["Caustic Tile"].image.size) == (256, 256)
    assert not [i for i in bpy.data.images if i.name.startswith("Projected Grid Caustics.")]
    assert tree.animation_data is None or not tree.animation_data.action
    assert tree.nodes["Caustic Tile"].image.name == "Projected Grid Caustics"


def test_no_calibration_runs_beside_the_export(moving, bridge, extension, monkeypatch,
                                              tmp_path):
    """The foam's calibrations made ahead on a worker (started by the viewport's frames) are
    finished before Blender's exporter starts, and none starts while it runs (a worker beside
    the export crashed Blender 4.5)."""
    scene, obj = moving
    foam = extension.projgrid_addon.foam
    slow = bridge.ahead._make

    def calibrate(*args):
        time.sleep(0.3)
        return slow(*args)

    monkeypatch.setattr(bridge.ahead, "_make", calibrate)
    seen, progress = [], bridge.bake_record.progress
    monkeypatch.setattr(bridge.bake_record, "progress", lambda frame: (
        seen.append(foam.CALIBRATIONS.making()), progress(frame)))
    scene.frame_set(60)  # a viewport frame 2.5 s in: seconds 3 and 4 are calibrated ahead
    assert foam.CALIBRATIONS.making()
    assert bpy.ops.projgrid.bake(filepath=str(tmp_path / "sea.usdc"), frame_start=1,
                                 frame_end=2) == {"FINISHED"}
    assert seen and not any(seen)


def test_a_duplicate_of_a_baked_ocean_leaves_the_original_baked(moving, bridge, tmp_path):
    """Shift+D copies the bake's modifier and the companions' pointers: Back to Live on the copy
    frees the copy alone, and the copy is refused a bake of its own until then; the material
    the live copy then takes is without the bake's keys."""
    scene, obj = moving
    assert bpy.ops.projgrid.bake(filepath=str(tmp_path / "sea.usdc"), frame_start=1,
                                 frame_end=2) == {"FINISHED"}
    keyed = list(obj.data.materials[0].node_tree[bridge.baked.KEYED])
    assert keyed  # the moving camera changes inputs from frame to frame
    copy = obj.copy()
    copy.data = obj.data.copy()
    scene.collection.objects.link(copy)
    with pytest.raises(ValueError, match="duplicate"):
        bridge.bake.check(scene, bpy.context.view_layer, copy, str(tmp_path / "b.usdc"), 1, 2)
    assert bridge.baked.free(copy) and not bridge.baked.is_baked(copy)
    assert bridge.baked.is_baked(obj) and obj.projgrid.shadow_caster.modifiers
    assert list(obj.data.materials[0].node_tree[bridge.baked.KEYED]) == keyed
    scene.frame_set(2)  # the live copy takes a material of its own: without the bake's keys
    mine, theirs = copy.data.materials[0].node_tree, obj.data.materials[0].node_tree
    assert mine != theirs and bridge.baked.KEYED not in mine
    assert not {c.data_path for c in bridge.scene.bag_curves(mine)} & set(keyed)
    assert set(keyed) <= {c.data_path for c in bridge.scene.bag_curves(theirs)}


def test_an_out_of_date_bake_is_flagged(moving, bridge, extension, tmp_path, capfd):
    """A bake is made for one camera path and one set of settings: with the camera panned a
    quarter turn or the wind changed, the baked frame is flagged in the panel (with Re-bake)
    and its render writes one warning line to the render log; baked again, it is not."""
    scene, obj = moving
    panel = extension.panels.ocean_panel
    path = str(tmp_path / "sea.usdc")
    assert bpy.ops.projgrid.bake(filepath=path, frame_start=1, frame_end=3) == {"FINISHED"}
    scene.frame_set(2)
    assert bridge.baked.stale(scene, obj) is None
    facing = tuple(scene.camera.rotation_euler)
    scene.camera.rotation_euler.z += math.pi / 2.0  # (the camera's location alone is keyed)
    scene.frame_set(2)
    why = bridge.baked.stale(scene, obj)
    assert why == "the camera or where the ocean shows changed since frame 2 was baked"
    assert ("ERROR", f"Out of date: {why}; bake again or go back to live") in panel.bake_lines(
        obj, scene)
    scene.render.engine = "BLENDER_WORKBENCH"
    scene.render.resolution_percentage = 2  # (a frame's size is what it was baked for too)
    capfd.readouterr()
    bpy.ops.render.render()
    scene.render.resolution_percentage = 100
    log = [line for line in capfd.readouterr().out.splitlines() if "out of date" in line]
    assert log == [f"Projected Grid Ocean: frame 2: 'Ocean' warning: its bake is out of date "
                   f"({why}): re-bake it (Bake panel) or go back to live"]
    scene.camera.rotation_euler = facing
    scene.frame_set(2)
    assert bridge.baked.stale(scene, obj) is None
    obj.projgrid.wind_speed += 3.0
    scene.frame_set(3)
    assert bridge.baked.stale(scene, obj) == "its settings changed since frame 3 was baked"
    assert bpy.ops.projgrid.bake(filepath=path, frame_start=1, frame_end=3) == {"FINISHED"}
    scene.frame_set(3)
    assert bridge.baked.stale(scene, obj) is None
