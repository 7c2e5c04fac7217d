"""The Blender layer does only what changed: the render grid's topology is kept, the shader's
time is driven rather than written, and updates that cannot touch the sea are skipped."""

import bpy
import numpy as np

from .helpers import add_camera, add_ocean


def counting(monkeypatch, module, name):
    calls = []
    real = getattr(module, name)
    monkeypatch.setattr(module, name, lambda *a, **k: calls.append(a) or real(*a, **k))
    return calls


def test_stills_keep_the_render_grid_topology(bridge, monkeypatch):
    scene = bpy.context.scene
    add_camera(scene)
    obj = add_ocean()
    obj.projgrid.render_resolution_x, obj.projgrid.render_resolution_y = 33, 65
    scene.render.engine = "BLENDER_WORKBENCH"
    scene.render.resolution_x, scene.render.resolution_y = 64, 36
    viewport = obj.data
    built = counting(monkeypatch, bridge.mesh, "set_topology")
    bpy.ops.render.render()
    assert len(built) == 1 and built[0][0] == obj.projgrid.render_mesh  # the render mesh only
    assert obj.data == viewport and len(viewport.vertices) == 65 * 129
    scene.frame_set(2)
    bpy.ops.render.render()
    assert len(built) == 1  # kept from the first still; the viewport grid was never rebuilt
    assert obj.projgrid.shadow_caster.data == viewport


def test_shader_time_is_driven_not_written(bridge):
    scene = bpy.context.scene
    add_camera(scene)
    obj = add_ocean()
    scene.frame_set(2)
    mat = obj.data.materials[0]
    path = mat.node_tree.nodes["Projected Grid Water"].inputs["Detail Time"].path_from_id(
        "default_value")
    driver = mat.node_tree.animation_data.drivers.find(path).driver
    assert driver.is_simple_expression  # runs where Python is blocked, on farms too
    values, drifts = [], []
    for frame in (2, 30):
        scene.frame_set(frame)
        evaluated = mat.evaluated_get(bpy.context.evaluated_depsgraph_get())
        inputs = evaluated.node_tree.nodes["Projected Grid Water"].inputs
        values.append(inputs["Detail Time"].default_value)
        drifts.append(inputs["Gust Drift"].default_value)
    detail = bridge.scene.height_field(obj.projgrid).shader_detail(
        *bridge.state.RUNTIME.state(obj).grid.shader_octaves)
    assert driver.expression == bridge.frame.water.drive_expression(
        detail.time_rate * bridge.shot.seconds_per_frame(scene))  # unchanged since frame 2
    seconds = 28 * bridge.shot.seconds_per_frame(scene)
    assert np.isclose(values[1] - values[0], detail.time_rate * seconds, rtol=1e-5)
    # the gusts drift with the wind at its speed
    assert np.isclose(drifts[1] - drifts[0], obj.projgrid.wind_speed * seconds, rtol=1e-5)


def test_updates_that_cannot_touch_the_sea_are_skipped(bridge, monkeypatch):
    scene = bpy.context.scene
    add_camera(scene)
    add_ocean()
    mesh = bpy.data.meshes.new("triangle")
    mesh.from_pydata([(0, 0, 0), (1, 0, 0), (0, 1, 0)], [], [(0, 1, 2)])
    behind = bpy.data.objects.new("Behind", mesh)
    behind.location = (0.0, -60.0, 0.0)
    buoy = bpy.data.objects.new("Buoy", mesh)
    buoy.location = (0.0, 40.0, 0.0)
    for obj in (behind, buoy):
        scene.collection.objects.link(obj)
    bpy.context.view_layer.update()
    calls = counting(monkeypatch, bridge.frame, "update_appearance")
    behind.location.x += 1.0  # out of view, before and after
    bpy.context.view_layer.update()
    assert calls == []
    buoy.location.x += 1.0  # in view: the facts may change
    bpy.context.view_layer.update()
    assert len(calls) == 1
    behind.location.y = 30.0  # into view
    bpy.context.view_layer.update()
    assert len(calls) == 2
