"""Floating objects (issue 37): Float Selected makes a mesh ride the ocean through our Child Of
constraint to our follower, the object's own keyframes untouched; Unfloat Selected undoes it
exactly; the pose is the core's (floating.pose) of the sea the frame built."""

import bpy
import numpy as np
import pytest

from .helpers import positions, spectral_sea, workbench


@pytest.fixture
def boat():
    """A 4 x 2 x 1 m box keyframed along +X (its course) near the camera, over a force 5
    spectral sea; only it selected and active."""
    ocean = spectral_sea()
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0.0, 25.0, 0.3))
    obj = bpy.context.active_object
    obj.scale = (4.0, 2.0, 1.0)
    obj.rotation_euler.z = 0.4
    obj.keyframe_insert("location", frame=1)
    obj.location.x = 12.0
    obj.keyframe_insert("location", frame=48)
    for o in bpy.context.selected_objects:
        o.select_set(o == obj)
    return ocean, obj


def expected(bridge, extension, ocean, obj):
    """The core's pose for `obj` on this frame's sea, and the object's own placement."""
    depsgraph = bpy.context.evaluated_depsgraph_get()
    scene = bpy.context.scene
    app = bridge.scene.appearances(scene, only=ocean)[0]
    (riding,) = bridge.floats.gather(app, scene, depsgraph)
    source = bridge.scene.height_field(ocean.evaluated_get(depsgraph).projgrid)
    world = np.array(ocean.matrix_world, dtype=np.float64)
    pose = extension.projgrid_addon.floating.pose(
        source, bridge.shot.scene_time(scene), world, riding)
    return pose @ np.array(obj.matrix_basis, dtype=np.float64), riding


def test_a_float_rides_the_waves_and_keeps_its_keyframes(boat, bridge, extension):
    """Each frame the boat is where the core's pose puts it (within 1e-4 m), its keel the
    density's draft (500 kg/m^3: 0.49 of its 1 m depth) under the sea's mean over its
    footprint, it heaves and tilts from frame to frame, and its keyframes and own location
    are as the user set them; the panel says what it rides; no contact foam rings it."""
    ocean, obj = boat
    frames = (2, 9, 17, 30)
    own = []
    for frame in frames:
        bpy.context.scene.frame_set(frame)
        own.append(tuple(obj.location))
    assert bridge.state.RUNTIME.peek(ocean).effects["contact_foam"][0] is True
    assert bpy.ops.projgrid.float_selected() == {"FINISHED"}
    lifts, tilts = [], []
    for frame, placed in zip(frames, own, strict=True):
        bpy.context.scene.frame_set(frame)
        want, riding = expected(bridge, extension, ocean, obj)
        assert np.array(obj.matrix_world) == pytest.approx(want, abs=1e-4)
        assert riding.draft == pytest.approx(500.0 / 1025.0 * 1.0, rel=1e-3)
        lifts.append(want[2, 3])
        tilts.append(np.degrees(np.arccos(want[2, 2])))
        assert tuple(obj.location) == placed  # its own course, as keyed
    assert np.std(lifts) > 0.02 and max(tilts) > 0.2, (lifts, tilts)
    lines = extension.panels.float_panel.float_lines(obj)
    assert lines == [("MOD_OCEAN", f"Rides {ocean.name!r}")]
    # it rides the waves: none wash up it (standing, the box crossing the surface had them)
    assert bridge.state.RUNTIME.peek(ocean).effects["contact_foam"][0] is False


def test_unfloat_puts_it_back_exactly(boat, bridge):
    """Unfloat Selected: the object where its own animation places it (matrix as before the
    float), our constraint and follower gone, the ocean's frame untouched otherwise."""
    ocean, obj = boat
    bpy.context.scene.frame_set(9)
    before = np.array(obj.matrix_world)
    constraints = len(obj.constraints)
    assert bpy.ops.projgrid.float_selected() == {"FINISHED"}
    bpy.context.scene.frame_set(9)
    assert np.abs(np.array(obj.matrix_world) - before).max() > 1e-3
    assert bpy.ops.projgrid.unfloat_selected() == {"FINISHED"}
    bpy.context.scene.frame_set(9)
    assert np.array(obj.matrix_world) == pytest.approx(before, abs=1e-6)
    assert len(obj.constraints) == constraints and obj.projgrid_float.ocean is None
    assert not [o for o in bpy.data.objects if o.name.startswith(obj.name + " Float")]


def test_what_cannot_float_is_refused_with_its_reason(boat, bridge, extension):
    """A parented object, the ocean itself: not floated, and the report and the panel say
    why; with nothing floatable selected the operator cannot run."""
    ocean, obj = boat
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(3.0, 30.0, 0.0))
    child = bpy.context.active_object
    child.parent = obj
    for o in bpy.context.selected_objects:
        o.select_set(o == child)
    assert not bpy.ops.projgrid.float_selected.poll()
    assert "it has a parent" in extension.panels.float_panel.float_lines(child)[0][1]
    obj.select_set(True)
    assert bpy.ops.projgrid.float_selected() == {"FINISHED"}
    assert child.projgrid_float.ocean is None and obj.projgrid_float.ocean == ocean


def test_a_float_survives_saving_and_opening(boat, bridge, extension, tmp_path):
    """Saved and opened again, the object floats on (its constraint and our follower kept, the
    pose the core's)."""
    ocean, obj = boat
    assert bpy.ops.projgrid.float_selected() == {"FINISHED"}
    path, names = str(tmp_path / "float.blend"), (ocean.name, obj.name)
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.open_mainfile(filepath=path)
    ocean, obj = (bpy.data.objects[name] for name in names)
    bpy.context.scene.frame_set(17)
    want, _ = expected(bridge, extension, ocean, obj)
    assert np.array(obj.matrix_world) == pytest.approx(want, abs=1e-4)


def test_a_bake_keys_the_floats_and_back_to_live_unkeys_them(moving, bridge, tmp_path):
    """Baking the ocean keys our follower of each float on every baked frame (a farm running
    no scripts floats them through the constraint): played back, the float is where the live
    frame put it; Back to Live leaves the follower unkeyed."""
    scene, ocean = moving
    bpy.ops.mesh.primitive_cube_add(size=2.0, location=(0.0, 20.0, 0.0))
    obj = bpy.context.active_object
    for o in bpy.context.selected_objects:
        o.select_set(o == obj)
    assert bpy.ops.projgrid.float_selected() == {"FINISHED"}
    live = {}
    for frame in (1, 2, 3):
        scene.frame_set(frame)
        live[frame] = np.array(obj.matrix_world)
    assert np.abs(live[1] - live[3]).max() > 1e-3
    assert bpy.ops.projgrid.bake(filepath=str(tmp_path / "sea.usdc"), frame_start=1,
                                 frame_end=3) == {"FINISHED"}
    follower = obj.projgrid_float.follower
    assert bridge.scene.bag_curves(follower)
    for frame in (3, 1, 2):
        scene.frame_set(frame)
        assert np.array(obj.matrix_world) == pytest.approx(live[frame], abs=1e-4)
    assert bpy.ops.projgrid.bake_free() == {"FINISHED"}
    assert follower.animation_data is None or not bridge.scene.bag_curves(follower)


def test_a_float_moved_by_hand_rides_where_it_is_put(boat, bridge, extension):
    """Moved in the viewport (no frame change), the float is posed anew at its new place."""
    ocean, obj = boat
    assert bpy.ops.projgrid.float_selected() == {"FINISHED"}
    bpy.context.scene.frame_set(9)
    obj.location.y += 7.0
    bpy.context.view_layer.update()
    want, riding = expected(bridge, extension, ocean, obj)
    assert riding.origin[1] == pytest.approx(obj.location.y)
    assert np.array(obj.matrix_world) == pytest.approx(want, abs=1e-4)


def test_a_render_of_a_frame_never_built_floats_it_there(boat, bridge, extension, tmp_path):
    """As `blender -b -f 40` renders it: opened at frame 10 (our follower saved there), the
    frame set by the render alone; the rendered frame's float is at the core's pose for 40."""
    ocean, obj = boat
    assert bpy.ops.projgrid.float_selected() == {"FINISHED"}
    bpy.context.scene.frame_set(10)
    at_ten = np.array(obj.matrix_world)
    path, names = str(tmp_path / "float.blend"), (ocean.name, obj.name)
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.open_mainfile(filepath=path)
    ocean, obj = (bpy.data.objects[name] for name in names)
    scene = bpy.context.scene
    workbench(scene)
    scene.frame_current = 40
    bpy.ops.render.render()
    rendered = np.array(obj.matrix_world)
    want, _ = expected(bridge, extension, ocean, obj)
    assert rendered == pytest.approx(want, abs=1e-4)
    assert np.abs(rendered - at_ten).max() > 1e-3


def surface_at(ocean, points):
    """The ocean mesh's height at world points (M, 2) (the mesh at the world's origin,
    unrotated): in the triangle of the grid holding each point, barycentric."""
    p = positions(ocean.data).astype(np.float64)
    grid = p.reshape(-1, ocean.projgrid.resolution_x, 3)
    a, b, c, d = (grid[:-1, :-1], grid[:-1, 1:], grid[1:, 1:], grid[1:, :-1])
    triangles = np.concatenate([np.stack([a, b, c], -2).reshape(-1, 3, 3),
                                np.stack([a, c, d], -2).reshape(-1, 3, 3)])
    lo, hi = triangles[:, :, :2].min(axis=1), triangles[:, :, :2].max(axis=1)
    out = []
    for q in np.asarray(points, dtype=np.float64):
        near = triangles[np.flatnonzero(((lo <= q) & (q <= hi)).all(axis=1))]
        v0, v1, v2 = near[:, 0, :2], near[:, 1, :2], near[:, 2, :2]
        e1, e2, w = v1 - v0, v2 - v0, q - v0
        det = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
        s = (w[:, 0] * e2[:, 1] - w[:, 1] * e2[:, 0]) / det
        t = (e1[:, 0] * w[:, 1] - e1[:, 1] * w[:, 0]) / det
        k = np.flatnonzero((s >= -1e-9) & (t >= -1e-9) & (s + t <= 1 + 1e-9))[0]
        z = near[k, :, 2]
        out.append(z[0] + s[k] * (z[1] - z[0]) + t[k] * (z[2] - z[0]))
    return np.array(out)


def test_a_buoy_follows_the_mesh_a_long_hull_barely_heaves_a_boat_pitches_with_it(bridge):
    """Beaufort 5 over 96 frames (issue 37's measures): a 0.5 m buoy of density 500 rides the
    water the mesh shows under it (its waterline correlated 0.95 or more with the mesh's
    height there, rms apart 5 % of Hs or less); a 100 x 20 m hull heaves at most 0.3 times as
    much; a 10 x 3 m boat's pitch is the slope of the plane fitted to the mesh over its
    footprint within 2 degrees."""
    ocean = spectral_sea()
    scene = bpy.context.scene
    made = {}
    for name, size, place in (("buoy", (0.5, 0.5, 0.5), (1.0, 20.0)),
                              ("hull", (100.0, 20.0, 5.0), (0.0, 400.0)),
                              ("boat", (10.0, 3.0, 1.5), (-2.0, 35.0))):
        bpy.ops.mesh.primitive_cube_add(size=1.0, location=(*place, 0.0))
        obj = bpy.context.active_object
        obj.name, obj.scale = name, size
        for o in bpy.context.selected_objects:
            o.select_set(o == obj)
        assert bpy.ops.projgrid.float_selected() == {"FINISHED"}
        made[name] = obj
    hs = 4.0 * bridge.scene.height_field(ocean.evaluated_get(
        bpy.context.evaluated_depsgraph_get()).projgrid).spread[0]
    waterline, under, hull, pitch, fitted = [], [], [], [], []
    along = np.linspace(-4.5, 4.5, 9)
    for frame in range(1, 97):
        scene.frame_set(frame)
        buoy = np.array(made["buoy"].matrix_world)
        waterline.append(buoy[2, 3] - 0.25 + 500.0 / 1025.0 * 0.5)  # its keel, plus its draft
        under.append(surface_at(ocean, [buoy[:2, 3]])[0])
        hull.append(made["hull"].matrix_world[2][3])
        boat = np.array(made["boat"].matrix_world)
        pitch.append(np.degrees(np.arcsin(boat[2, 0] / np.linalg.norm(boat[:3, 0]))))
        x, y = np.meshgrid(along, np.linspace(-1.33, 1.33, 9))
        z = surface_at(ocean, np.stack([x.ravel() - 2.0, y.ravel() + 35.0], axis=1))
        fitted.append(np.degrees(np.arctan(np.polyfit(x.ravel(), z, 1)[0])))
    waterline, under = np.array(waterline), np.array(under)
    assert np.corrcoef(waterline, under)[0, 1] >= 0.95
    assert np.sqrt(np.mean((waterline - under) ** 2)) <= 0.05 * hs
    assert np.std(hull) <= 0.3 * np.std(waterline)
    assert np.abs(np.array(pitch) - np.array(fitted)).max() <= 2.0


def test_a_library_override_floats_and_leaves_its_wake(bridge, extension, tmp_path):
    """A boat linked from another file, made a library override (what Float asks of a
    linked object): Float Selected rides it on the sea (the core's pose; our constraint on
    the override, nothing written to the library) and its keys, from the library, give its
    wake."""
    boat = bpy.data.objects.new("Boat", bpy.data.meshes.new("Boat"))
    bpy.context.scene.collection.objects.link(boat)
    import bmesh

    shape = bmesh.new()
    bmesh.ops.create_cube(shape, size=1.0)
    shape.to_mesh(boat.data)
    shape.free()
    boat.scale, boat.location = (8.0, 3.0, 1.5), (-80.0, 30.0, 0.0)
    boat.keyframe_insert("location", frame=1)
    boat.location.x += 200.0
    boat.keyframe_insert("location", frame=1 + 40 * 24)
    library = str(tmp_path / "boat.blend")
    bpy.ops.wm.save_as_mainfile(filepath=library)
    bpy.ops.wm.read_homefile(use_empty=True)
    ocean = spectral_sea()
    with bpy.data.libraries.load(library, link=True) as (_, dst):
        dst.objects = ["Boat"]
    bpy.context.scene.collection.objects.link(dst.objects[0])
    obj = dst.objects[0].override_create(remap_local_usages=True)
    bpy.context.view_layer.update()
    for o in bpy.context.scene.objects:
        o.select_set(o == obj)
    bpy.context.view_layer.objects.active = obj
    assert bpy.ops.projgrid.float_selected() == {"FINISHED"}
    bpy.context.scene.frame_set(24 * 16)
    want, _ = expected(bridge, extension, ocean, obj)
    assert np.array(obj.matrix_world) == pytest.approx(want, abs=1e-4)
    assert dst.objects[0].constraints.keys() == [] and not dst.objects[0].is_library_indirect
    on, reason = bridge.state.RUNTIME.peek(ocean).effects["wakes"]
    assert on and obj.name in reason
