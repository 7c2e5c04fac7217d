"""Linked, overridden and instanced oceans (issue 12): each drawn by a stand-in of ours where
it shows, built for the rendering scene's camera, and nothing of a library's ever written.

Linked oceans run in a fresh process, as a farm worker does, so a crash fails one test rather
than ending the session. Renders use Workbench at a tiny size: what is checked is the mesh each
rendered frame saw and our objects' flags, which do not depend on the engine.
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
from .helpers import RenderCapture, add_camera, add_ocean, core, positions, workbench


def expected_grid(bridge, scene, settings, level, render=True, origin=None):
    """The grid a local ocean with `settings` at `level` (placed at `origin`, by default over
    the world origin) draws for the scene camera now."""
    depsgraph = bpy.context.evaluated_depsgraph_get()
    res = ((settings.render_resolution_x, settings.render_resolution_y) if render
           else (settings.resolution_x, settings.resolution_y))
    camera = core("projected_grid").Camera(*bridge.shot.camera_for(scene, depsgraph))
    return core("projected_grid").build_grid(
        camera, bridge.scene.height_field(settings), level=level,
        time=bridge.shot.scene_time(scene),
        resolution=res, projector_elevation=settings.projector_elevation,
        origin=np.array([0.0, 0.0, level] if origin is None else origin))


# ---- 1. Linked oceans and library overrides -------------------------------------------------

def make_asset(path):
    """An asset file: the ocean (small render grid, its own waves) in a collection "Sea"."""
    scene = bpy.context.scene
    add_camera(scene)
    sea = bpy.data.collections.new("Sea")
    scene.collection.children.link(sea)
    bpy.context.view_layer.active_layer_collection = \
        bpy.context.view_layer.layer_collection.children["Sea"]
    obj = add_ocean()
    s = obj.projgrid
    s.render_resolution_x, s.render_resolution_y = 17, 33
    s.amplitude, s.seed = 1.0, 3
    group = bpy.data.node_groups["Projected Grid Water"]
    version = group["projgrid_ocean"]
    group["projgrid_ocean"] = 4  # as an older version saved it: linked, never rebuilt here
    bpy.ops.wm.save_as_mainfile(filepath=path, copy=True)
    group["projgrid_ocean"] = version
    assert len(obj.data.vertices) == 65 * 129  # back on screen after the save


LINK_WORKER = textwrap.dedent("""
    import sys
    import bpy
    import numpy as np
    asset, mode, out, root = sys.argv[1:5]
    sys.path.insert(0, root)
    from tests.blender.helpers import add_camera, positions
    bpy.ops.wm.read_userpref()
    bpy.ops.wm.read_homefile(use_empty=True)

    def shot(link):
        scene = bpy.context.scene
        add_camera(scene, location=(30.0, -20.0, 4.0), rotation=(85.0, 0.0, 20.0))
        r = scene.render
        r.engine, r.resolution_x, r.resolution_y = "BLENDER_WORKBENCH", 64, 36
        if mode == "instance":
            with bpy.data.libraries.load(asset, link=link) as (src, dst):
                dst.collections = ["Sea"]
            empty = bpy.data.objects.new("Instance", None)
            empty.instance_type, empty.instance_collection = "COLLECTION", dst.collections[0]
            empty.location = (0.0, 0.0, 2.0)
            scene.collection.objects.link(empty)
            ocean = next(o for o in dst.collections[0].all_objects if o.projgrid.is_ocean)
            if not link:  # appended: the expected sea is the ocean itself at the instance's level
                scene.collection.objects.link(ocean)
                empty.instance_collection = None
                ocean.location.z = 2.0
        else:
            with bpy.data.libraries.load(asset, link=link) as (src, dst):
                dst.objects = ["Ocean"]
            ocean = dst.objects[0]
            scene.collection.objects.link(ocean)
        if link and mode == "override":
            ocean = ocean.override_create(remap_local_usages=True)
            ocean.projgrid.render_resolution_x = 9  # the settings callback on an override
        elif mode == "override":
            ocean.projgrid.render_resolution_x = 9
        bpy.context.view_layer.update()
        seen = {}
        def capture(scene, _=None):
            for o in scene.objects:
                ours = o.projgrid.is_ocean or o.get("projgrid_stand_in")
                if o.type == "MESH" and ours and len(o.data.vertices):
                    seen[o.name] = (positions(o.data).copy(), np.array(o.matrix_world))
        bpy.app.handlers.render_post.append(capture)
        scene.frame_set(5)
        bpy.ops.render.render()
        bpy.app.handlers.render_post.remove(capture)
        return ocean, seen

    ocean, linked = shot(link=True)
    # Saved and opened again (as a farm worker opens the shot): the same sea.
    bpy.ops.wm.save_as_mainfile(filepath=out + ".blend")
    bpy.ops.wm.open_mainfile(filepath=out + ".blend")
    reopened = {}
    def again(scene, _=None):
        o = bpy.data.objects["Ocean Sea"]
        reopened["sea"] = positions(o.data).copy(), np.array(o.matrix_world)
    bpy.app.handlers.render_post.append(again)
    bpy.ops.render.render()
    bpy.app.handlers.render_post.remove(again)
    lib = [o for o in bpy.data.objects if o.library is not None and o.projgrid.is_ocean][0]
    group = next(g for g in bpy.data.node_groups
                 if g.library is not None and g.name == "Projected Grid Water")
    results = {"library_vertices": len(lib.data.vertices),
               "library_amplitude": lib.projgrid.amplitude,
               "library_group": (group["projgrid_ocean"], len(group.nodes)),
               "names": sorted(linked), "stand_ins": [o.name for o in bpy.data.objects
                                                     if o.get("projgrid_stand_in")]}
    bpy.ops.wm.read_homefile(use_empty=True)
    _, local = shot(link=False)
    (drawn, m1), = linked.values()
    (want, m2), = local.values()
    world = lambda p, m: p @ m[:3, :3].T + m[:3, 3]
    np.savez(out, drawn=world(drawn, m1), want=world(want, m2),
             reopened=world(*reopened["sea"]), **{k: np.array(v) for k, v in results.items()})
""")


@pytest.mark.parametrize("mode", ["link", "override", "instance"])
def test_linked_ocean_renders_its_sea_through_a_stand_in(tmp_path, mode):
    """A fresh worker links the asset's ocean (the object, a library override of it, or its
    collection as an instance 2 m up) and renders: the sea is drawn by a local stand-in of ours,
    equal to the sea the same ocean appended (made local) draws, the same again when the saved
    shot is opened and rendered, and the library's mesh and settings are never written."""
    asset = str(tmp_path / "asset.blend")
    make_asset(asset)
    out = str(tmp_path / "seen.npz")
    env = {**os.environ, "BLENDER_USER_RESOURCES": USER}
    done = subprocess.run([sys.executable, "-c", LINK_WORKER, asset, mode, out, ROOT],
                          env=env, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout[-1500:] + done.stderr[-2000:]
    seen = np.load(out)
    assert list(seen["names"]) == ["Ocean Sea"] and list(seen["stand_ins"]) == ["Ocean Sea"]
    assert int(seen["library_vertices"]) == 0  # saved empty, never written
    assert float(seen["library_amplitude"]) == 1.0
    assert seen["library_group"][0] == 4 and seen["library_group"][1] > 10  # not rebuilt
    rows = 9 if mode == "override" else 17
    assert seen["drawn"].shape == seen["want"].shape == (rows * 33, 3)
    assert np.allclose(seen["drawn"], seen["want"], atol=1e-4)
    assert np.array_equal(seen["reopened"], seen["drawn"])
    if mode == "instance":
        assert abs(np.median(seen["drawn"][:, 2]) - 2.0) < 0.5


NESTED_WORKER = textwrap.dedent("""
    import sys
    import bpy
    import numpy as np
    asset, out, root = sys.argv[1:4]
    sys.path.insert(0, root)
    from tests.blender.helpers import add_camera, positions
    bpy.ops.wm.read_userpref()
    # Shot A links the asset's ocean into its collection "Layout"; its stand-in is made.
    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    add_camera(scene)
    layout = bpy.data.collections.new("Layout")
    scene.collection.children.link(layout)
    with bpy.data.libraries.load(asset, link=True) as (src, dst):
        dst.objects = ["Ocean"]
    layout.objects.link(dst.objects[0])
    bpy.context.view_layer.update()
    shot_a = out + ".a.blend"
    bpy.ops.wm.save_as_mainfile(filepath=shot_a)
    # Shot B links A's "Layout" and A's stand-in (same key as B's own appearance).
    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    add_camera(scene, location=(30.0, -20.0, 4.0), rotation=(85.0, 0.0, 20.0))
    r = scene.render
    r.engine, r.resolution_x, r.resolution_y = "BLENDER_WORKBENCH", 64, 36
    with bpy.data.libraries.load(shot_a, link=True) as (src, dst):
        dst.collections = ["Layout"]
        dst.objects = ["Ocean Sea"]
    scene.collection.children.link(dst.collections[0])
    scene.collection.objects.link(dst.objects[0])
    bpy.context.view_layer.update()
    seen = {}
    def capture(scene, _=None):
        for o in scene.objects:
            if o.get("projgrid_stand_in") and o.library is None:
                seen[o.name] = positions(o.data).copy()
    bpy.app.handlers.render_post.append(capture)
    bpy.ops.render.render()
    bpy.app.handlers.render_post.remove(capture)
    linked = [o for o in bpy.data.objects if o.get("projgrid_stand_in") and o.library]
    np.savez(out, names=np.array(sorted(seen)), linked=np.array([o.name for o in linked]),
             linked_vertices=np.array([len(o.data.vertices) for o in linked]),
             drawn=np.concatenate(list(seen.values())) if seen else np.zeros((0, 3)))
""")


def test_a_stand_in_linked_from_another_shot_is_never_touched(tmp_path):
    """Shot B links shot A's collection holding the asset's ocean, and A's own stand-in (whose
    key is B's too): B draws the sea with a stand-in of its own and leaves A's untouched."""
    asset = str(tmp_path / "asset.blend")
    make_asset(asset)
    out = str(tmp_path / "nested.npz")
    env = {**os.environ, "BLENDER_USER_RESOURCES": USER}
    done = subprocess.run([sys.executable, "-c", NESTED_WORKER, asset, out, ROOT],
                          env=env, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout[-1500:] + done.stderr[-2000:]
    seen = np.load(out)
    assert list(seen["linked"]) == ["Ocean Sea"] and list(seen["linked_vertices"]) == [0]
    assert len(seen["names"]) == 1 and seen["drawn"].shape == (17 * 33, 3)


def test_saving_writes_our_meshes_empty_and_keeps_the_view(tmp_path):
    scene = bpy.context.scene
    bpy.ops.wm.save_as_mainfile(filepath=str(tmp_path / "empty.blend"))
    dirty = bpy.data.is_dirty  # (bpy 4.5 as a module leaves every saved file dirty)
    add_camera(scene)
    obj = add_ocean()
    bpy.ops.wm.save_as_mainfile(filepath=str(tmp_path / "saved.blend"))
    assert len(obj.data.vertices) == 65 * 129 and bpy.data.is_dirty == dirty
    copy = str(tmp_path / "copy.blend")
    bpy.ops.wm.save_as_mainfile(filepath=copy, copy=True)
    with bpy.data.libraries.load(copy) as (src, dst):
        dst.meshes = ["Ocean"]
    assert len(dst.meshes[0].vertices) == 0


# ---- 4. Background sets and collection instances ------------------------------------------------

def test_ocean_in_a_background_set_is_built_for_the_rendering_camera(bridge):
    shot = bpy.context.scene
    backdrop = bpy.data.scenes.new("Backdrop")
    add_camera(backdrop, location=(50.0, 50.0, 30.0), rotation=(60.0, 0.0, 90.0))
    with bpy.context.temp_override(scene=backdrop, view_layer=backdrop.view_layers[0]):
        assert bpy.ops.projgrid.add_ocean() == {"FINISHED"}
    obj = backdrop.objects["Ocean"]
    obj.projgrid.render_resolution_x, obj.projgrid.render_resolution_y = 17, 33
    add_camera(shot, location=(0.0, 0.0, 6.0), rotation=(84.0, 0.0, 0.0))
    shot.background_set = backdrop
    workbench(shot)
    with RenderCapture() as seen:
        bpy.ops.render.render(scene=shot.name)
    want = expected_grid(bridge, shot, obj.projgrid, 0.0).positions
    assert np.allclose(seen.frames[shot.frame_current], want, atol=1e-5)


def stand_ins(scene):
    return sorted((o for o in scene.objects if o.get("projgrid_stand_in")),
                  key=lambda o: o.location.z)


def test_ocean_inside_collection_instances(bridge):
    """An ocean shown through collection instances is drawn by a stand-in of ours per instance,
    in the scene's own collection (its companions would otherwise take the instance's
    transform too); the ocean's own mesh, shown in every instance, is empty. Back in the scene
    itself, once, it draws itself again and the stand-ins go."""
    scene = bpy.context.scene
    add_camera(scene, location=(0.0, 0.0, 4.0))
    obj = add_ocean()
    sea = bpy.data.collections.new("Sea")
    sea.objects.link(obj)
    scene.collection.objects.unlink(obj)
    first = bpy.data.objects.new("First", None)
    first.instance_type, first.instance_collection = "COLLECTION", sea
    first.location = (5.0, 0.0, 2.0)
    scene.collection.objects.link(first)
    scene.frame_set(2)
    (only,) = stand_ins(scene)
    assert len(obj.data.vertices) == 0 and tuple(only.location) == (5.0, 0.0, 2.0)
    # The same grid, about the stand-in's origin (the projector's range allows for the float32
    # rounding of the points about it, so the grid depends on the origin by that much).
    want = expected_grid(bridge, scene, obj.projgrid, 2.0, render=False, origin=(5.0, 0.0, 2.0))
    assert np.allclose(positions(only.data), want.positions, rtol=1e-5, atol=1e-5)
    for helper in [only] + [getattr(only.projgrid, p) for p in ("water_body", "shadow_caster",
                                                                  "reflection_probe")]:
        assert set(helper.users_collection) == {scene.collection}
    # Shown twice: a stand-in for each instance.
    second = bpy.data.objects.new("Second", None)
    second.instance_type, second.instance_collection = "COLLECTION", sea
    second.location = (0.0, 0.0, -1.0)
    scene.collection.objects.link(second)
    scene.frame_set(3)
    assert len(obj.data.vertices) == 0
    assert [round(o.location.z, 6) for o in stand_ins(scene)] == [-1.0, 2.0]
    assert all(len(o.data.vertices) == 65 * 129 for o in stand_ins(scene))
    # An instancer that no longer instances (its collection pointer kept) shows nothing.
    second.instance_type = "NONE"
    bpy.context.view_layer.update()
    assert [round(o.location.z, 6) for o in stand_ins(scene)] == [2.0]
    # Hidden in renders with its instancer.
    first.hide_render = True
    bpy.context.view_layer.update()
    assert stand_ins(scene)[0].hide_render
    # Back in the scene, not instanced: the ocean draws itself and the stand-ins are deleted.
    bpy.data.objects.remove(first)
    bpy.data.objects.remove(second)
    scene.collection.objects.link(obj)
    bpy.context.view_layer.update()
    scene.frame_set(4)
    assert len(obj.data.vertices) == 65 * 129 and stand_ins(scene) == []


@pytest.mark.parametrize("how", ["excluded", "hidden in renders"])
def test_an_ocean_in_a_collection_left_out_draws_only_its_instances(bridge, how):
    """An ocean whose own collection is excluded from the view layer (or hidden in renders) and
    instanced twice elsewhere draws two stand-ins with a grid, at the instances: none where the
    collection itself would be, in the viewport or in a render."""
    scene = bpy.context.scene
    add_camera(scene, location=(0.0, 0.0, 4.0))
    obj = add_ocean()
    sea = bpy.data.collections.new("Sea")
    scene.collection.children.link(sea)
    sea.objects.link(obj)
    scene.collection.objects.unlink(obj)
    layer = bpy.context.view_layer.layer_collection.children["Sea"]
    if how == "excluded":
        layer.exclude = True
    else:
        sea.hide_render = True
    for name, z in (("First", 2.0), ("Second", -1.0)):
        instancer = bpy.data.objects.new(name, None)
        instancer.instance_type, instancer.instance_collection = "COLLECTION", sea
        instancer.location = (5.0, 0.0, z)
        scene.collection.objects.link(instancer)
    bpy.context.view_layer.update()
    scene.frame_set(2)
    drawn = [o for o in stand_ins(scene) if len(o.data.vertices)]
    want = [-1.0, 2.0] if how == "excluded" else [-1.0, 0.0, 2.0]  # the viewport shows it
    assert sorted(round(o.location.z, 6) for o in drawn) == want
    seen = []

    def capture(*_):  # as the render draws: the instances alone have the render grid
        seen.append(sorted(round(o.location.z, 6) for o in stand_ins(scene)
                           if len(o.data.vertices)))

    workbench(scene)
    bpy.app.handlers.render_post.append(capture)
    try:
        bpy.ops.render.render()
    finally:
        bpy.app.handlers.render_post.remove(capture)
    assert seen == [[-1.0, 2.0]]


def test_a_linked_ocean_in_two_scenes_has_a_stand_in_in_each(bridge, tmp_path):
    asset = str(tmp_path / "asset.blend")
    make_asset(asset)
    bpy.ops.wm.read_homefile(use_empty=True)
    with bpy.data.libraries.load(asset, link=True) as (src, dst):
        dst.objects = ["Ocean"]
    ocean = dst.objects[0]
    first = bpy.context.scene
    second = bpy.data.scenes.new("Second")
    for scene, x in ((first, 0.0), (second, 300.0)):
        add_camera(scene, location=(x, 0.0, 6.0))
        scene.collection.objects.link(ocean)
    for scene in (first, second):
        with bpy.context.temp_override(scene=scene, view_layer=scene.view_layers[0]):
            bridge.handlers.prepare(scene)
            depsgraph = bpy.context.evaluated_depsgraph_get()
            bridge.frame.update_scene(scene, depsgraph, render=False, frame_change=True)
    (a,), (b,) = stand_ins(first), stand_ins(second)
    assert a != b and a.name not in second.objects and b.name not in first.objects
    xa, xb = positions(a.data)[:, 0].mean(), positions(b.data)[:, 0].mean()
    assert abs(xa) < 50.0 and abs(xb - 300.0) < 50.0  # each for its own scene's camera
