"""The ways studios use an object, each giving the right sea or a clear message (issue 12):
wide clip ranges, hidden oceans, mirrored ones, Edit Mode, memory, markers, the render log.
Linked and instanced oceans: test_linked.py. Renders use Workbench at a tiny size."""

from importlib import import_module

import bpy
import numpy as np
import pytest

from tools.demo import MODULE

from .helpers import add_camera, add_ocean, core, positions, workbench


def stats_lines(obj, scene):
    return import_module(f"{MODULE}.panels.ocean_panel").stats_lines(obj, scene)


# ---- 2. Wide clip ranges ----------------------------------------------------------------------

@pytest.mark.parametrize("clip", [(0.1, 1e7), (1e-4, 2e4), (1.0, 1e8), (1e-6, 1e9)],
                         ids=lambda c: f"{c[0]:g}-{c[1]:g}")
def test_wide_clip_ranges_give_a_finite_gap_free_grid(bridge, state, clip):
    scene = bpy.context.scene
    cam = add_camera(scene, rotation=(87.0, 0.0, 0.0))
    cam.data.clip_start, cam.data.clip_end = clip
    obj = add_ocean()
    scene.frame_set(2)
    assert state(obj).message is None
    p = positions(obj.data)
    assert len(p) == 65 * 129 and np.all(np.isfinite(p))
    # Gap-free: the nearest row spans the screen's width, the farthest reaches the horizon.
    view, proj = bridge.shot.camera_for(scene, bpy.context.evaluated_depsgraph_get())
    clip_space = np.c_[p, np.ones(len(p))] @ (proj @ view).T
    ndc = clip_space[:, :2] / clip_space[:, 3:]
    assert ndc[:65, 0].min() <= -1.0 and ndc[:65, 0].max() >= 1.0
    assert ndc[:, 1].min() <= -1.0


@pytest.mark.parametrize("kind", ["PERSP", "ORTHO"])
@pytest.mark.parametrize("fit", ["AUTO", "HORIZONTAL", "VERTICAL"])
def test_float64_projection_equals_blenders(bridge, kind, fit):
    """Where Blender's float32 matrix is exact enough, ours is the same matrix."""
    scene = bpy.context.scene
    cam = add_camera(scene)
    d = cam.data
    d.type, d.sensor_fit, d.lens, d.ortho_scale = kind, fit, 28.0, 12.0
    d.shift_x, d.shift_y, d.sensor_width, d.sensor_height = 0.2, -0.1, 36.0, 20.0
    d.clip_start, d.clip_end = 0.5, 900.0
    scene.render.resolution_x, scene.render.resolution_y = 500, 900
    scene.render.pixel_aspect_x = 2.0
    depsgraph = bpy.context.evaluated_depsgraph_get()
    _, ours = bridge.shot.camera_for(scene, depsgraph)
    x, y, sx, sy = bridge.shot.render_size(scene)
    theirs = np.array(cam.evaluated_get(depsgraph).calc_matrix_camera(
        depsgraph, x=x, y=y, scale_x=sx, scale_y=sy))
    assert np.allclose(ours, theirs, rtol=1e-6, atol=1e-6)


# ---- 3. A hidden ocean hides its helpers --------------------------------------------------------

def underwater_ocean():
    scene = bpy.context.scene
    add_camera(scene, location=(0.0, 0.0, -3.0), rotation=(100.0, 0.0, 0.0))
    sea = bpy.data.collections.new("Sea")
    scene.collection.children.link(sea)
    bpy.context.view_layer.active_layer_collection = \
        bpy.context.view_layer.layer_collection.children["Sea"]
    obj = add_ocean()
    workbench(scene)
    scene.frame_set(1)
    assert "UNDERWATER" in obj.projgrid.active_effects
    return scene, obj


def companions(obj):
    return [getattr(obj.projgrid, p) for p in ("water_body", "shadow_caster",
                                               "reflection_probe")]


class FlagCapture:
    """Records our companions' render visibility as each frame is rendered."""

    def __init__(self, obj):
        self.obj, self.seen = obj, []

    def __call__(self, scene, _=None):
        self.seen.append({c.name: (c.hide_render, c.is_holdout) for c in companions(self.obj)})

    def __enter__(self):
        bpy.app.handlers.render_post.append(self)
        return self

    def __exit__(self, *exc):
        bpy.app.handlers.render_post.remove(self)


def test_hidden_ocean_renders_no_helpers():
    scene, obj = underwater_ocean()
    body = obj.projgrid.water_body
    assert not body.hide_render
    obj.hide_render = True
    with FlagCapture(obj) as flags:
        bpy.ops.render.render()
    assert all(hidden for hidden, _ in flags.seen[0].values())
    obj.hide_render = False
    obj.hide_viewport = True
    bpy.context.view_layer.update()
    assert body.hide_viewport


def test_helpers_follow_exclusion_and_holdout():
    scene, obj = underwater_ocean()
    for companion in companions(obj):
        assert set(companion.users_collection) == set(obj.users_collection)
    # Moved to another collection (M in the viewport): the companions follow it.
    other = bpy.data.collections.new("Other")
    scene.collection.children.link(other)
    other.objects.link(obj)
    bpy.data.collections["Sea"].objects.unlink(obj)
    bpy.context.view_layer.update()
    for companion in companions(obj):
        assert set(companion.users_collection) == {other}
    obj.is_holdout = True
    bpy.context.view_layer.update()
    with FlagCapture(obj) as flags:
        bpy.ops.render.render()
    assert all(holdout for _, holdout in flags.seen[0].values())
    bpy.context.view_layer.layer_collection.children["Other"].exclude = True
    bpy.context.view_layer.update()
    depsgraph = bpy.context.evaluated_depsgraph_get()
    assert not any(c.evaluated_get(depsgraph).is_evaluated for c in companions(obj))


# ---- 5. Negative scale --------------------------------------------------------------------------

@pytest.mark.parametrize("scale", [(-1.0, 1.0, 1.0), (1.0, 1.0, -2.0), (-1.0, -1.0, 1.0)])
def test_mirrored_ocean_faces_up(scale):
    scene = bpy.context.scene
    add_camera(scene)
    obj = add_ocean()
    obj.scale = scale
    scene.frame_set(2)
    bpy.context.view_layer.update()
    m = np.array(obj.matrix_world)
    mesh = obj.data
    normals = np.empty(len(mesh.polygons) * 3, np.float32)
    mesh.polygons.foreach_get("normal", normals)
    # Blender shades with the local normals taken through the inverse transpose of the object's
    # matrix (a mirrored object keeps its outside): they must point up out of the water.
    world = normals.reshape(-1, 3) @ np.linalg.inv(m[:3, :3])
    assert np.all(world[:, 2] > 0.0)


# ---- 6. Edit mode -------------------------------------------------------------------------------

def test_edit_mode_skips_rebuilding_and_says_so(bridge):
    scene = bpy.context.scene
    add_camera(scene)
    obj = add_ocean()
    bpy.ops.object.mode_set(mode="EDIT")
    try:
        depsgraph = bpy.context.evaluated_depsgraph_get()
        scene.frame_set(3)
        bridge.handlers.frame_change_post(scene, depsgraph)
        update = bridge.frame.update_ocean
        assert update(obj, scene, depsgraph).startswith("'Ocean' is in Edit Mode")
        obj.projgrid.resolution_x = 9
        message = update(obj, scene, depsgraph, settings=obj.projgrid)
        assert "Edit Mode" in message
        assert any("Edit Mode" in text for _, text in stats_lines(obj, scene))
    finally:
        bpy.ops.object.mode_set(mode="OBJECT")
    scene.frame_set(4)
    assert len(obj.data.vertices) == 9 * 129


# ---- 7. Memory ----------------------------------------------------------------------------------

def test_a_grid_too_big_for_memory_is_refused_before_allocating(state, monkeypatch):
    scene = bpy.context.scene
    add_camera(scene)
    obj = add_ocean()
    memory = core("memory")
    monkeypatch.setattr(memory, "available_bytes", lambda: 64 * 2**20)
    obj.projgrid.resolution_x = obj.projgrid.resolution_y = 1025
    message = state(obj).message
    assert message.startswith("a 1025x1025 grid needs about") and "viewport grid" in message
    assert len(obj.data.vertices) == 0


def test_out_of_memory_while_writing_leaves_no_half_built_mesh(bridge, monkeypatch):
    scene = bpy.context.scene
    add_camera(scene)
    obj = add_ocean()
    real = bridge.mesh.corner_uv

    def fails(nx, ny, flipped):  # after the faces are made, before the UVs
        raise MemoryError

    monkeypatch.setattr(bridge.mesh, "corner_uv", fails)
    obj.projgrid.resolution_x = 33  # the settings callback: nothing escapes
    message = bridge.frame.update_ocean(obj, scene, bpy.context.evaluated_depsgraph_get(),
                                        settings=obj.projgrid)
    assert "out of memory" in message
    assert len(obj.data.vertices) == 0 and len(obj.data.polygons) == 0
    monkeypatch.setattr(bridge.mesh, "corner_uv", real)
    scene.frame_set(5)
    assert len(obj.data.vertices) == 33 * 129


# ---- Smaller ones -------------------------------------------------------------------------------

def test_marker_camera_switch_is_followed_by_frame_set(bridge, state):
    scene = bpy.context.scene
    first = add_camera(scene)
    second = add_camera(scene, location=(40.0, 0.0, 12.0), rotation=(70.0, 0.0, 90.0))
    scene.camera = first
    obj = add_ocean()
    scene.timeline_markers.new("A", frame=1).camera = first
    scene.timeline_markers.new("B", frame=5).camera = second
    scene.frame_set(5)
    built = state(obj).camera[0]  # before any other evaluation rebuilds it
    view = bridge.shot.camera_for(scene, bpy.context.evaluated_depsgraph_get(), second)[0]
    assert np.array_equal(built, view)


def test_each_ocean_shades_with_its_own_settings(bridge):
    scene = bpy.context.scene
    add_camera(scene)
    calm = add_ocean("PERLIN")
    rough = add_ocean("PERLIN")
    rough.projgrid.amplitude = 3.0
    calm.projgrid.amplitude = 0.2
    scene.frame_set(2)
    heights = []
    for obj in (calm, rough):
        mat = obj.data.materials[0]
        heights.append(mat.node_tree.nodes["Projected Grid Water"].inputs["Detail Height"]
                       .default_value)
    assert calm.data.materials[0] != rough.data.materials[0]
    assert heights[1] > heights[0] > 0.0
    # A duplicate sharing its original's material gets its own at the next update.
    mesh = rough.data.copy()
    twin = rough.copy()
    twin.data = mesh
    scene.collection.objects.link(twin)
    bpy.context.view_layer.update()
    assert twin.data.materials[0] != rough.data.materials[0]


def test_lock_interface_left_off_by_the_user_stays_off(tmp_path):
    scene = bpy.context.scene
    add_camera(scene)
    name = add_ocean().name
    assert scene.render.use_lock_interface
    scene.render.use_lock_interface = False
    path = str(tmp_path / "unlocked.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.open_mainfile(filepath=path)
    scene = bpy.context.scene
    assert not scene.render.use_lock_interface
    lines = [text for _, text in stats_lines(scene.objects[name], scene)]
    assert any("Lock Interface is off" in t and "renders need it" in t for t in lines)


def test_refused_frames_are_named_in_the_render_log(capfd, tmp_path):
    scene = bpy.context.scene
    cam = add_camera(scene)
    add_ocean()
    cam.data.type = "PANO"
    workbench(scene)
    scene.frame_start, scene.frame_end = 1, 2
    scene.render.filepath = str(tmp_path / "f_")
    capfd.readouterr()
    bpy.ops.render.render(animation=True)
    lines = [line for line in capfd.readouterr().out.splitlines()
             if line.startswith("Projected Grid Ocean: frame")]
    assert len(lines) == 2 and "not built" in lines[0] and "panoramic" in lines[0]


def test_scale_messages_say_what_is_wrong_and_what_to_do(state):
    scene = bpy.context.scene
    add_camera(scene)
    obj = add_ocean()
    obj.scale = (1e-5, 1e-5, 1e-5)
    scene.frame_set(2)
    assert state(obj).message is None
    assert len(obj.data.vertices) == 65 * 129
    obj.scale = (1.0, 0.0, 1.0)
    scene.frame_set(3)
    message = state(obj).message
    assert "scale is zero on Y" in message and "give it a non-zero scale" in message


@pytest.mark.parametrize("setting, value, advice", [("amplitude", 1e4, "lower Amplitude")])
def test_settings_at_their_maxima_warn_of_a_flat_sea(state, setting, value, advice):
    scene = bpy.context.scene
    add_camera(scene)
    obj = add_ocean("PERLIN")
    assert state(obj).warning is None
    setattr(obj.projgrid, setting, value)
    warning = state(obj).warning
    assert warning.startswith("no wave is in the geometry") and advice in warning
    assert any(advice in text for _, text in stats_lines(obj, scene))


def test_a_flat_noise_from_wind_is_told_to_raise_the_grid(bridge, extension):
    """From Wind, Amplitude and Wave Scale are unused: the flat-sea warning does not name
    them (a grid whose finest level holds no octave); a Projector Elevation far above the
    waves is named. (Its maximum, 10 km, no longer flattens the default shot's sea: the
    grid's columns and rows follow the camera's screen, Projector.spacing.)"""
    from types import SimpleNamespace

    hf = extension.projgrid_addon.HeightField(amplitude=1.0, wave_scale=40.0)
    result = SimpleNamespace(visible=True, lod=np.array([-3.0]))
    for from_wind, elevation, advice in ((False, 0.0, "lower Amplitude"),
                                         (True, 0.0, "raise the grid resolution"),
                                         (False, 1e4, "lower it")):
        settings = SimpleNamespace(projector_elevation=elevation, height_source="PERLIN",
                                   noise_from_wind=from_wind)
        warning = extension.projgrid_addon.frame_plan.flat_warning(hf, hf.bound, result,
                                                                   settings)
        assert warning.startswith("no wave is in the geometry") and advice in warning
