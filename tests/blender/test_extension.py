"""The extension in Blender: registration, Add Ocean, settings, bad input, live preview, panel."""

import math
from importlib import import_module
from types import SimpleNamespace

import bpy
import numpy as np
import pytest
from mathutils import Matrix

from tools.demo import MODULE

from .helpers import add_camera, add_ocean, positions


def stats_lines(obj, scene):
    return import_module(f"{MODULE}.panels.ocean_panel").stats_lines(obj, scene)


def our_handlers():
    found = []
    for name in dir(bpy.app.handlers):
        handlers = getattr(bpy.app.handlers, name)
        if isinstance(handlers, list):
            found += [(name, f) for f in handlers
                      if getattr(f, "__module__", "").startswith(MODULE)]
    return found


def test_registration_is_symmetric(extension):
    assert our_handlers() and hasattr(bpy.types.Object, "projgrid")
    assert hasattr(bpy.types, "PROJGRID_OT_add_ocean")
    assert hasattr(bpy.types, "VIEW3D_MT_projgrid_sea_state")
    bpy.ops.preferences.addon_disable(module=MODULE)
    try:
        assert our_handlers() == []
        assert not hasattr(bpy.types.Object, "projgrid")
        for name in ("PROJGRID_OT_add_ocean", "PROJGRID_OT_live_preview",
                     "VIEW3D_PT_projgrid_ocean", "VIEW3D_MT_projgrid_sea_state",
                     "ProjectedGridSettings"):
            assert not hasattr(bpy.types, name), name
    finally:
        bpy.ops.preferences.addon_enable(module=MODULE)
    assert len(our_handlers()) == len(extension.operators.bridge.handlers.HANDLERS)


def test_add_ocean_in_an_empty_scene(bridge):
    scene = bpy.context.scene
    add_camera(scene)
    scene.cursor.location = (3.0, -2.0, 1.5)
    obj = add_ocean()
    assert obj.name == "Ocean" and obj.projgrid.is_ocean
    assert bpy.context.view_layer.objects.active == obj
    assert obj.matrix_world.translation.z == 1.5
    assert (obj.projgrid.resolution_x, obj.projgrid.resolution_y) == (65, 129)
    assert len(obj.data.vertices) == 65 * 129
    z = positions(obj.data)[:, 2] + 1.5
    assert np.all(np.abs(z - 1.5) <= obj.projgrid.amplitude * 2.0)  # around the cursor's height
    assert scene.world is not None and any(o.type == "LIGHT" for o in scene.objects)
    assert scene.render.use_lock_interface
    assert not obj.cycles.use_deform_motion
    assert obj.data.materials[0].name == "Projected Grid Water"


def test_add_ocean_keeps_the_users_world_and_sun():
    scene = bpy.context.scene
    add_camera(scene)
    world = bpy.data.worlds.new("Mine")
    scene.world = world
    sun = bpy.data.objects.new("My Sun", bpy.data.lights.new("My Sun", "SUN"))
    scene.collection.objects.link(sun)
    cube = bpy.data.objects.new("Cube", bpy.data.meshes.new("Cube"))
    scene.collection.objects.link(cube)
    add_ocean()
    assert scene.world == world and len(bpy.data.worlds) == 1
    assert [o.name for o in scene.objects if o.type == "LIGHT"] == ["My Sun"]
    assert len(cube.data.vertices) == 0 and "Cube" in scene.objects


def test_a_storm_clouds_add_ocean_s_sky_over(extension):
    """Sea State turns Add Ocean's sky toward an overcast and dims and spreads its sun as the
    force asks (clear to a fresh breeze, overcast from a gale), unless Weather is off; a sky
    made without the overcast gets it; the user's world and sun lamp are left alone."""
    sky = extension.shaders.sky
    scene = bpy.context.scene
    add_camera(scene)
    ocean = add_ocean()
    ocean.projgrid.foam = ocean.projgrid.spray = "OFF"  # each force's frame: the sky's test
    sun = next(o for o in scene.objects if o.type == "LIGHT").data
    overcast = scene.world.node_tree.nodes[sky.OVERCAST].inputs["Factor"]
    assert overcast.default_value == 0.0
    # Add Ocean's sun, 12 deg up
    clear = extension.projgrid_addon.daylight.sunlight(12.0, sky.model(scene.world))[0]
    for force, cloud in ((4, 0.0), (7, (15.5 - 9.4) / (19.0 - 9.4)), (8, 1.0), (5, 0.0)):
        bpy.ops.projgrid.sea_state(beaufort=force)
        assert overcast.default_value == pytest.approx(cloud)
        assert sun.energy == pytest.approx(clear * (1.0 - (1.0 - sky.SUN_UNDER_CLOUD) * cloud),
                                           rel=1e-5)
        assert math.degrees(sun.angle) == pytest.approx(
            sky.SUN_ANGLE[0] + (sky.SUN_ANGLE[1] - sky.SUN_ANGLE[0]) * cloud, rel=1e-5)
    bpy.ops.projgrid.sea_state(beaufort=9, weather=False)
    assert overcast.default_value == 0.0 and sun.energy == pytest.approx(clear, rel=1e-5)
    tree = scene.world.node_tree  # as made before the overcast: the clear sky straight in
    old = tree.nodes[sky.OVERCAST]
    clear = next(s for s in old.inputs if s.identifier == "A_Color").links[0].from_socket
    tree.nodes.remove(old)
    tree.links.new(clear, tree.nodes[sky.BACKGROUND].inputs["Color"])
    bpy.ops.projgrid.sea_state(beaufort=10)
    assert scene.world.node_tree.nodes[sky.OVERCAST].inputs["Factor"].default_value == 1.0
    background = scene.world.node_tree.nodes[sky.BACKGROUND].inputs["Color"]
    assert background.links[0].from_node.name == sky.OVERCAST
    assert next(s for s in background.links[0].from_node.inputs
                if s.identifier == "A_Color").links[0].from_socket == clear
    mine = bpy.data.worlds.new("Mine")
    scene.world = mine
    lamp = next(o for o in scene.objects if o.type == "LIGHT")
    lamp.data = bpy.data.lights.new("My Sun", "SUN")
    lamp.data.energy = 7.0
    bpy.ops.projgrid.sea_state(beaufort=10)
    assert (mine.node_tree is None or sky.OVERCAST not in mine.node_tree.nodes)
    assert lamp.data.energy == 7.0


def test_settings_are_refused_outside_their_range():
    add_camera(bpy.context.scene)
    s = add_ocean().projgrid
    s.amplitude = -3.0
    s.octaves = 100
    s.resolution_x = 1
    s.wind_speed = -5.0
    assert s.amplitude == 0.0 and s.octaves == 24 and s.resolution_x == 2 and s.wind_speed == 0.0
    with pytest.raises(TypeError, match="SOMETIMES"):
        s.foam = "SOMETIMES"
    assert s.foam == "AUTO"


def test_settings_rebuild_and_are_honoured(bridge):
    scene = bpy.context.scene
    add_camera(scene)
    obj = add_ocean("PERLIN")
    obj.projgrid.resolution_x, obj.projgrid.resolution_y = 9, 17
    assert len(obj.data.vertices) == 9 * 17
    obj.projgrid.amplitude = 0.0
    assert np.all(positions(obj.data)[:, 2] == 0.0)
    obj.projgrid.amplitude = 2.0
    assert np.abs(positions(obj.data)[:, 2]).max() > 0.1


def test_exact_noise_setting():
    """Exact noise gives the reference heights: close to the fast path's, not equal."""
    scene = bpy.context.scene
    add_camera(scene)
    obj = add_ocean("PERLIN")
    fast = positions(obj.data)[:, 2].copy()
    obj.projgrid.noise = "EXACT"
    exact = positions(obj.data)[:, 2]
    diff = np.abs(exact - fast).max()
    assert 0.0 < diff < 0.1 * obj.projgrid.amplitude * 2.0


def test_frame_change_rebuilds_and_frames_are_independent():
    scene = bpy.context.scene
    add_camera(scene)
    obj = add_ocean()
    scene.frame_set(5)
    at5 = positions(obj.data).copy()
    scene.frame_set(6)
    assert not np.array_equal(positions(obj.data), at5)
    scene.frame_set(5)
    assert np.array_equal(positions(obj.data), at5)


def test_edits_between_frames_rebuild_the_viewport_grid():
    scene = bpy.context.scene
    cam = add_camera(scene)
    obj = add_ocean()
    obj.projgrid.choppiness = 0.0  # the grid itself, not the crests' sideways displacement
    before = positions(obj.data).copy()
    cam.location.x += 3.0
    bpy.context.view_layer.update()  # what the viewport does after an edit
    moved = positions(obj.data).copy()
    assert np.allclose(moved[:, 0] - before[:, 0], 3.0, atol=1e-3)
    obj.location.z = 2.0  # a new water level, 4 m below the camera instead of 6: a closer grid
    bpy.context.view_layer.update()
    near_edge = positions(obj.data)[:65, 1]
    assert np.all(near_edge < moved[:65, 1] - 1.0)


def test_not_in_view_gives_an_empty_mesh(bridge):
    scene = bpy.context.scene
    cam = add_camera(scene, rotation=(180.0, 0.0, 0.0))  # straight up from 6 m
    obj = add_ocean()
    assert len(obj.data.vertices) == 0
    cam.rotation_euler = np.radians((60.0, 0.0, 0.0))
    scene.frame_set(2)
    assert len(obj.data.vertices) == 65 * 129


@pytest.mark.parametrize("problem", ["no camera", "panoramic", "too many vertices", "zero scale"])
def test_bad_input_is_reported_and_leaves_an_empty_mesh(state, problem):
    scene = bpy.context.scene
    cam = add_camera(scene)
    obj = add_ocean()
    if problem == "no camera":
        scene.camera = None
    elif problem == "panoramic":
        cam.data.type = "PANO"
    elif problem == "too many vertices":
        obj.projgrid.resolution_x = obj.projgrid.resolution_y = 8193
    else:
        obj.scale = (0.0, 1.0, 1.0)
    scene.frame_set(3)
    message = state(obj).message
    assert message and len(obj.data.vertices) == 0
    lines = stats_lines(obj, scene)
    assert any("Not built" in text and message in text for _, text in lines)


def test_a_replaced_mesh_is_never_touched(state):
    scene = bpy.context.scene
    add_camera(scene)
    obj = add_ocean()
    mine = bpy.data.meshes.new("Mine")
    mine.from_pydata([(0, 0, 0), (1, 0, 0), (0, 1, 0)], [], [(0, 1, 2)])
    obj.data = mine
    scene.frame_set(4)
    assert len(mine.vertices) == 3 and tuple(mine.vertices[1].co) == (1.0, 0.0, 0.0)
    assert "replaced" in state(obj).message


def test_deleting_the_ocean_or_disabling_the_extension_mid_session():
    scene = bpy.context.scene
    add_camera(scene)
    obj = add_ocean()
    bpy.data.objects.remove(obj)
    scene.frame_set(7)  # no error
    obj = add_ocean()
    bpy.ops.preferences.addon_disable(module=MODULE)
    try:
        scene.frame_set(8)  # the mesh stays as it was; nothing raises
        assert len(obj.data.vertices) == 65 * 129
    finally:
        bpy.ops.preferences.addon_enable(module=MODULE)
    scene.frame_set(9)
    assert len(bpy.data.objects["Ocean"].data.vertices) == 65 * 129


def fake_view(view_matrix, perspective="PERSP"):
    proj = Matrix(((1.2, 0, 0, 0), (0, 2.1, 0, 0), (0, 0, -1.00002, -0.2), (0, 0, -1, 0)))
    rv3d = SimpleNamespace(view_perspective=perspective, view_matrix=view_matrix,
                           window_matrix=proj)
    return SimpleNamespace(region_3d=rv3d)


def test_live_preview_modal_follows_the_view_and_stops(extension, bridge):
    op_cls = bpy.types.PROJGRID_OT_live_preview
    scene = bpy.context.scene
    add_camera(scene)
    obj = add_ocean("PERLIN")  # bounded for all time: its grid does not move with time
    obj.projgrid.choppiness = 0.0  # the grid itself, not the crests' sideways displacement
    from_camera = positions(obj.data).copy()
    view = Matrix.Rotation(np.radians(-80.0), 4, "X") @ Matrix.Translation((0, 0, -20.0))
    op = SimpleNamespace(space=fake_view(view), _timer=None)
    status = []
    ctx = SimpleNamespace(scene=scene, window_manager=bpy.context.window_manager,
                          workspace=SimpleNamespace(status_text_set=status.append),
                          evaluated_depsgraph_get=bpy.context.evaluated_depsgraph_get)
    timer = SimpleNamespace(type="TIMER", value="NOTHING")

    assert op_cls.modal(op, ctx, timer) == {"PASS_THROUGH"}
    followed = positions(obj.data).copy()
    assert not np.array_equal(followed, from_camera)
    runtime = bridge.state.RUNTIME
    assert runtime.live_view is not None  # frame changes in the viewport follow the view too
    scene.frame_set(3)
    assert np.array_equal(runtime.state(obj).camera[0], np.array(view, dtype=np.float64))

    runtime.rendering = True  # steps aside while rendering
    op.space = fake_view(Matrix.Translation((0, 0, -30.0)) @ view)
    try:
        assert op_cls.modal(op, ctx, timer) == {"PASS_THROUGH"}
        assert np.array_equal(runtime.state(obj).camera[0], np.array(view, dtype=np.float64))
    finally:
        runtime.rendering = False

    op.space = fake_view(view, perspective="CAMERA")  # camera view: the scene camera
    op_cls.modal(op, ctx, timer)
    assert runtime.live_view is None  # the grid (x, y) is the camera's again; heights move
    assert np.array_equal(positions(obj.data)[:, :2], from_camera[:, :2])

    esc = SimpleNamespace(type="ESC", value="PRESS")
    assert op_cls.modal(op, ctx, esc) == {"CANCELLED"}
    assert status == [None] and runtime.live_view is None


def test_live_preview_needs_an_ocean():
    reports = []
    op = SimpleNamespace(report=lambda kind, text: reports.append((kind, text)))
    ctx = SimpleNamespace(scene=bpy.context.scene)
    assert bpy.types.PROJGRID_OT_live_preview.invoke(op, ctx, None) == {"CANCELLED"}
    assert reports == [({"ERROR"}, "No ocean in this scene: use Add Ocean first")]


def test_panel_reports_live_stats(bridge):
    scene = bpy.context.scene
    add_camera(scene)
    obj = add_ocean()
    text = [t for _, t in stats_lines(obj, scene)]
    assert text[0] == "Vertices: 8,385"
    assert text[1].startswith("Vertex efficiency: ") and text[1].endswith("%")
    assert text[2].startswith("Last rebuild: ") and text[2].endswith(" ms")
    assert text[3].startswith("Octaves in the shader: ")


def test_file_load_ends_the_live_preview(bridge):
    scene = bpy.context.scene
    add_camera(scene)
    add_ocean()
    runtime = bridge.state.RUNTIME
    runtime.live_view = (np.eye(4), np.eye(4))
    bpy.ops.wm.read_homefile(use_empty=True)
    assert runtime.live_view is None and not runtime.surfaces
