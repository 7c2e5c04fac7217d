"""The Blender layer does only what changed: the render grid's topology is kept, the shader's
time is driven rather than written, and updates that cannot touch the sea are skipped."""

import bpy
import numpy as np
import pytest

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
        drifts.append(np.array([inputs[n].default_value
                                for n in ("Gust Drift X", "Gust Drift Y", "Gust Path")]))
    detail = bridge.scene.height_field(obj.projgrid).shader_detail(
        *bridge.state.RUNTIME.state(obj).grid.shader_octaves)
    assert driver.expression == bridge.material_inputs.drive_expression(
        detail.time_rate * bridge.shot.seconds_per_frame(scene))  # unchanged since frame 2
    seconds = 28 * bridge.shot.seconds_per_frame(scene)
    assert np.isclose(values[1] - values[0], detail.time_rate * seconds, rtol=1e-5)
    # the gusts drift with the wind at its speed, toward where it blows
    s = obj.projgrid
    assert drifts[1] - drifts[0] == pytest.approx(s.wind_speed * seconds * np.array(
        [np.cos(s.wind_direction), np.sin(s.wind_direction), 1.0]), rel=1e-5, abs=1e-6)


def test_the_gusts_drift_with_a_keyframed_wind(bridge):
    """With the wind's speed and direction keyframed, the gusts have drifted by the wind's
    run since frame 0 (its velocity integrated), not by its speed now times the time: a wind
    rising from 4 to 12 m/s and turning a quarter over two seconds, read at frames 25 and 49
    with a subframe, against the integral of its curves at 2400 steps."""
    scene = bpy.context.scene
    add_camera(scene)
    obj = add_ocean()
    s = obj.projgrid
    s.foam = "OFF"  # (its calibrations cost seconds, and are not what is tested)
    for frame, speed, direction in ((1, 4.0, 0.0), (49, 12.0, np.pi / 2)):
        s.wind_speed, s.wind_direction = speed, direction
        s.keyframe_insert("wind_speed", frame=frame)
        s.keyframe_insert("wind_direction", frame=frame)
    spf = bridge.shot.seconds_per_frame(scene)
    curves = {c.data_path: c for c in bridge.scene.bag_curves(obj)}
    for frame, subframe in ((25, 0.0), (49, 0.5)):
        scene.frame_set(frame, subframe=subframe)
        mat = obj.data.materials[0]
        inputs = mat.evaluated_get(bpy.context.evaluated_depsgraph_get()).node_tree.nodes[
            "Projected Grid Water"].inputs
        drift = [inputs[n].default_value for n in ("Gust Drift X", "Gust Drift Y", "Gust Path")]
        steps = np.linspace(0.0, frame + subframe, 2401)
        u = np.array([curves["projgrid.wind_speed"].evaluate(f) for f in steps])
        d = np.array([curves["projgrid.wind_direction"].evaluate(f) for f in steps])
        want = [float(np.sum(0.5 * (v[1:] + v[:-1]) * np.diff(steps * spf)))
                for v in (u * np.cos(d), u * np.sin(d), u)]
        assert drift == pytest.approx(want, rel=2e-3), (frame, subframe)
    assert want[2] < 0.9 * s.wind_speed * (frame + subframe) * spf  # not speed now x time


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
