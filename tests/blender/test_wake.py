"""Wakes (issue 37): a float whose keys move it across the water leaves its wake in the ocean's
mesh, the heights the core draws for its course (wake_field.draw) and the white trail behind
its stern; the wakes effect's AUTO says why; a frame's wake is the same built alone or in
sequence, and the bake keeps it."""

from types import SimpleNamespace

import bpy
import numpy as np
import pytest

from .helpers import RENDER_RES, add_camera, add_ocean, positions, render_mesh

SPEED = 5.0  # m/s along +X
FRAME = 24 * 24 + 1  # 24 s on: the boat at x = 0, 45 m ahead of the camera


@pytest.fixture
def boat(bridge):
    """A light breeze (no whitecaps: its foam is the wake's), a 10 x 3 x 1.5 m box 45 m ahead
    of the camera keyed to cross the view along +X at 5 m/s, floating."""
    scene = bpy.context.scene
    add_camera(scene)
    ocean = add_ocean()
    assert bpy.ops.projgrid.sea_state(beaufort=2) == {"FINISHED"}
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(-120.0, 45.0, 0.0))
    obj = bpy.context.active_object
    obj.scale = (10.0, 3.0, 1.5)
    obj.keyframe_insert("location", frame=1)
    obj.location.x += SPEED * 40.0
    obj.keyframe_insert("location", frame=1 + 40 * scene.render.fps)
    for curve in bridge.scene.bag_curves(obj):
        for key in curve.keyframe_points:
            key.interpolation = "LINEAR"
    for o in bpy.context.selected_objects:
        o.select_set(o == obj)
    assert bpy.ops.projgrid.float_selected() == {"FINISHED"}
    return scene, ocean, obj


def mesh_with(scene, ocean, mode, frame=FRAME):
    ocean.projgrid.wakes = mode
    scene.frame_set(frame)
    return positions(ocean.data).copy()


def test_a_moving_float_leaves_its_wake_in_the_mesh(boat, bridge, extension):
    """AUTO draws the wake (its reason naming the boat and its speed): the mesh's heights are
    the sea's plus the core's wake for the course the keys give (within 1e-4 m), a wake
    0.1 m high or more behind the boat and none ahead of it; the foam attribute carries the
    white trail behind its stern and no foam beside the course."""
    scene, ocean, obj = boat
    bare = mesh_with(scene, ocean, "OFF")
    drawn = mesh_with(scene, ocean, "AUTO")
    on, reason = bridge.state.RUNTIME.peek(ocean).effects["wakes"]
    assert on and "'Cube'" in reason and "5 m/s" in reason, reason
    core = extension.projgrid_addon
    app = bridge.scene.appearances(scene, only=ocean)[0]
    (riding,) = bridge.floats.gather(app, scene, bpy.context.evaluated_depsgraph_get(),
                                     bridge.shot.scene_time(scene),
                                     bridge.shot.seconds_per_frame(scene), near=(0.0, 0.0))
    course = core.wake_field.course(riding.name, *riding.course, riding.draft, riding.length,
                                    riding.beam)
    assert course.x[-1] == pytest.approx(riding.centre[0]) and len(course.times) > 150
    source = bridge.scene.height_field(ocean.evaluated_get(
        bpy.context.evaluated_depsgraph_get()).projgrid)
    lod = np.empty(len(ocean.data.vertices), np.float32)
    ocean.data.attributes["projgrid_lod"].data.foreach_get("value", lod)
    shape = (-1, ocean.projgrid.resolution_x)  # the grid's rows
    x, y = (bare[:, k].astype(np.float64).reshape(shape) for k in (0, 1))
    grid = SimpleNamespace(surface=(x, y, np.zeros_like(x)), lod=lod,
                           positions=np.zeros_like(bare))
    want = core.wake_field.draw(grid, [course], source.wave_scale)[0].ravel()
    assert np.abs(drawn[:, 2] - bare[:, 2] - want).max() < 1e-4
    behind = (bare[:, 0] < -10.0) & (np.abs(bare[:, 1] - 45.0) < 15.0)
    ahead = bare[:, 0] > 60.0
    assert np.abs(want[behind]).max() > 0.1 and not want[ahead].any()
    foam = np.empty(len(ocean.data.vertices), np.float32)
    ocean.data.attributes["projgrid_foam"].data.foreach_get("value", foam)
    trail = (bare[:, 0] < -8.0) & (bare[:, 0] > -40.0) & (np.abs(bare[:, 1] - 45.0) < 2.0)
    beside = np.abs(bare[:, 1] - 45.0) > 20.0
    assert foam[trail].max() > 0.3 and foam[beside].max() < 0.01


def test_a_float_at_rest_makes_no_wake(boat, bridge):
    """Without keys moving it, AUTO leaves the wakes off and says why; the mesh is the sea's
    alone (as with the effect off)."""
    scene, ocean, obj = boat
    obj.animation_data_clear()
    bare = mesh_with(scene, ocean, "OFF")
    drawn = mesh_with(scene, ocean, "AUTO")
    on, reason = bridge.state.RUNTIME.peek(ocean).effects["wakes"]
    assert not on and reason == "nothing on the water moves faster than 0.5 m/s"
    assert np.array_equal(drawn, bare)


def test_a_frame_s_wake_is_the_same_alone_or_in_sequence(boat):
    """A pure function of the scene and its time: frame N built first, or after frames before
    and after it, is bit-identical."""
    scene, ocean, _ = boat
    alone = mesh_with(scene, ocean, "AUTO")
    for frame in (FRAME - 30, FRAME + 11, FRAME - 1):
        scene.frame_set(frame)
    assert np.array_equal(mesh_with(scene, ocean, "AUTO"), alone)


def test_the_bake_keeps_the_wake(boat, bridge, tmp_path):
    """Baked, the ocean plays the render grid with the wake in it (the live render mesh)."""
    scene, ocean, _ = boat
    scene.frame_end = FRAME + 1
    ocean.projgrid.render_resolution_x, ocean.projgrid.render_resolution_y = RENDER_RES
    ocean.projgrid.wakes = "OFF"
    bare = render_mesh(scene, ocean, bridge, FRAME)
    ocean.projgrid.wakes = "AUTO"
    live = render_mesh(scene, ocean, bridge, FRAME)
    assert np.abs(live[:, 2] - bare[:, 2]).max() > 0.05
    assert bpy.ops.projgrid.bake(filepath=str(tmp_path / "sea.usdc"), frame_start=FRAME,
                                 frame_end=FRAME + 1) == {"FINISHED"}
    scene.frame_set(FRAME)
    played = ocean.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
    assert np.allclose(positions(played), live, rtol=1e-6, atol=1e-5)


def test_the_nearest_floats_leave_wakes_and_a_stepping_course_none(boat, bridge):
    """Of 20 floats keyed across the water, the wakes of the MOST_WAKES nearest the camera
    are drawn (their courses read; a thousand floats cost no more); a float keyed with
    constant interpolation jumps from key to key: its course starts at its last jump, so it
    leaves no wake (and nothing fails)."""
    scene, ocean, obj = boat
    obj.animation_data_clear()
    obj.location.x = 5000.0  # out of the way: the nearest are the 20
    ocean.projgrid.wakes = "OFF"  # (while they are made: each change rebuilds the frame)
    for i in range(20):
        bpy.ops.mesh.primitive_cube_add(size=1.0, location=(-60.0, 30.0 + 12.0 * i, 0.0))
        other = bpy.context.active_object
        other.keyframe_insert("location", frame=1)
        other.location.x += SPEED * 40.0
        other.keyframe_insert("location", frame=1 + 40 * scene.render.fps)
        for o in bpy.context.selected_objects:
            o.select_set(o == other)
        assert bpy.ops.projgrid.float_selected() == {"FINISHED"}
    ocean.projgrid.wakes = "AUTO"
    scene.frame_set(FRAME)
    app = bridge.scene.appearances(scene, only=ocean)[0]
    riding = bridge.floats.gather(app, scene, bpy.context.evaluated_depsgraph_get(),
                                  bridge.shot.scene_time(scene),
                                  bridge.shot.seconds_per_frame(scene), near=(0.0, 0.0))
    with_course = sorted(f.centre[1] for f in riding if f.course)
    assert len(riding) == 21 and len(with_course) == bridge.floats.MOST_WAKES
    assert max(with_course) < min(f.centre[1] for f in riding if not f.course and f.name
                                  != obj.name)
    assert bridge.state.RUNTIME.peek(ocean).effects["wakes"][0]
    for o in [o for o in scene.objects if o.name.startswith("Cube.") and o.type == "MESH"]:
        bridge.floats.unfloat_object(o)
        bpy.data.objects.remove(o)
    obj.location.x = 0.0
    obj.keyframe_insert("location", frame=1)
    obj.location.x += 5.0
    obj.keyframe_insert("location", frame=FRAME - 12)
    for curve in bridge.scene.bag_curves(obj):
        for key in curve.keyframe_points:
            key.interpolation = "CONSTANT"
    scene.frame_set(FRAME)
    on, reason = bridge.state.RUNTIME.peek(ocean).effects["wakes"]
    assert not on and "faster than" in reason


def test_a_wake_adds_to_the_noise_sea_too(boat, bridge):
    """On the thesis's noise sea (the other height source) the wake adds to the mesh alike:
    heights 0.1 m or more behind the boat, none ahead of it."""
    scene, ocean, _ = boat
    ocean.projgrid.height_source = "PERLIN"
    bare = mesh_with(scene, ocean, "OFF")
    drawn = mesh_with(scene, ocean, "AUTO")
    lift = drawn[:, 2] - bare[:, 2]
    behind = (bare[:, 0] < -10.0) & (np.abs(bare[:, 1] - 45.0) < 15.0)
    assert np.abs(lift[behind]).max() > 0.1 and not lift[bare[:, 0] > 60.0].any()


def test_a_marker_camera_sees_the_float_and_its_wake(boat):
    """Timeline markers switch cameras: under the second camera the boat rides as under the
    first (its pose is the sea's, whatever the camera) and the mesh the second camera's grid
    builds carries its wake behind it."""
    scene, ocean, obj = boat
    first = scene.camera
    scene.frame_set(FRAME)
    pose = np.array(obj.matrix_world)
    second = add_camera(scene, location=(-60.0, 0.0, 25.0), rotation=(65.0, 0.0, -34.0))
    scene.camera = first
    scene.timeline_markers.new("A", frame=1).camera = first
    scene.timeline_markers.new("B", frame=FRAME - 10).camera = second
    bare = mesh_with(scene, ocean, "OFF")
    drawn = mesh_with(scene, ocean, "AUTO")
    assert scene.camera == second
    assert np.array(obj.matrix_world) == pytest.approx(pose, abs=1e-5)
    behind = (bare[:, 0] < -10.0) & (bare[:, 0] > -60.0) & (np.abs(bare[:, 1] - 45.0) < 15.0)
    assert behind.sum() > 100  # the second camera's grid covers the wake
    assert np.abs(drawn[behind, 2] - bare[behind, 2]).max() > 0.1


def test_a_keyed_object_that_does_not_float_leaves_its_wake(boat, bridge):
    """The box keyed across the water without floating (its keys alone place it, half under):
    AUTO draws its wake too, behind it and none ahead; at rest, none."""
    scene, ocean, obj = boat
    assert bpy.ops.projgrid.unfloat_selected() == {"FINISHED"}
    bare = mesh_with(scene, ocean, "OFF")
    drawn = mesh_with(scene, ocean, "AUTO")
    on, reason = bridge.state.RUNTIME.peek(ocean).effects["wakes"]
    assert on and "'Cube'" in reason and "5 m/s" in reason, reason
    behind = (bare[:, 0] < -10.0) & (np.abs(bare[:, 1] - 45.0) < 15.0)
    ahead = bare[:, 0] > 60.0
    assert np.abs(drawn[behind, 2] - bare[behind, 2]).max() > 0.1
    assert np.array_equal(drawn[ahead], bare[ahead])
    obj.animation_data_clear()
    assert np.array_equal(mesh_with(scene, ocean, "AUTO"), mesh_with(scene, ocean, "OFF"))
