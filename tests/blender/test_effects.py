"""Effects decided from the scene in Blender: active_effects, reasons, muted branches, no work."""

from importlib import import_module

import bpy
import numpy as np
import pytest

from tools.demo import MODULE

from .helpers import add_camera, add_ocean


def effect_lines(obj):
    return dict(import_module(f"{MODULE}.panels.ocean_panel").effect_lines(obj))


def group():
    return bpy.data.node_groups["Projected Grid Water"]


def add_box(name, location, size=2.0):
    bpy.ops.mesh.primitive_cube_add(size=size, location=location)
    obj = bpy.context.active_object
    obj.name = name
    return obj


@pytest.fixture
def ocean():
    """A camera 6 m up looking along +Y a little down, and the ocean at z = 0 (with its sun)."""
    scene = bpy.context.scene
    add_camera(scene)
    obj = add_ocean()
    scene.frame_set(1)
    return obj


def test_a_bare_ocean_turns_on_only_the_sun_glint(ocean):
    assert ocean.projgrid.active_effects == {"SUN_GLINT"}
    lines = effect_lines(ocean)
    assert lines["sun_glint"].startswith("on: sun ") and "above the horizon" in lines["sun_glint"]
    assert lines["local_reflections"] == "off: sky only: nothing stands above the water in view"
    assert lines["foam"].startswith("off: wind 3 m/s")
    assert group().nodes["Foam"].mute and not group().nodes["Sun Glint"].mute


def test_sun_below_the_horizon_or_off_mutes_the_glint(ocean):
    sun = next(o for o in bpy.context.scene.objects if o.type == "LIGHT")
    sun.rotation_euler = (np.radians(120.0), 0.0, 0.0)  # shining upwards: below the horizon
    bpy.context.view_layer.update()
    assert ocean.projgrid.active_effects == set()
    assert "below the horizon" in effect_lines(ocean)["sun_glint"]
    assert group().nodes["Sun Glint"].mute
    sun.rotation_euler = (0.3, 0.0, 0.0)
    ocean.projgrid.sun_glint = "OFF"
    assert ocean.projgrid.active_effects == set()
    assert effect_lines(ocean)["sun_glint"] == "off: switched off"


def test_wind_brings_foam_and_calm_computes_none(ocean, bridge, monkeypatch):
    calls = []
    effects = bridge.effects
    real = effects.foam_amount
    monkeypatch.setattr(effects, "foam_amount", lambda *a: calls.append(1) or real(*a))
    bpy.context.scene.frame_set(2)
    assert calls == [] and "projgrid_foam" not in ocean.data.attributes  # calm: no foam work
    ocean.projgrid.wind_speed = 15.0
    assert "FOAM" in ocean.projgrid.active_effects and calls
    assert effect_lines(ocean)["foam"].startswith("on: wind 15 m/s")
    foam = np.empty(len(ocean.data.vertices), np.float32)
    ocean.data.attributes["projgrid_foam"].data.foreach_get("value", foam)
    assert 0.0 < np.mean(foam > 0) < 0.5 and foam.max() <= 1.0
    assert not group().nodes["Foam"].mute
    ocean.projgrid.foam = "OFF"
    assert "FOAM" not in ocean.projgrid.active_effects and group().nodes["Foam"].mute
    assert "projgrid_foam" not in ocean.data.attributes


def test_the_shared_water_group_keeps_a_branch_any_ocean_needs(ocean):
    windy = add_ocean()  # a second ocean, same material and group
    windy.projgrid.wind_speed = 15.0
    assert "FOAM" in windy.projgrid.active_effects and not group().nodes["Foam"].mute
    ocean.projgrid.seed = 1  # only the calm ocean rebuilds; it must not mute the windy one's foam
    assert "FOAM" not in ocean.projgrid.active_effects
    assert not group().nodes["Foam"].mute
    windy.projgrid.foam = "OFF"
    assert group().nodes["Foam"].mute


def test_objects_decide_reflections_and_what_is_not_rendered_yet(ocean):
    add_box("Buoy", (0.0, 40.0, 0.0))  # crosses the surface in view
    bpy.context.view_layer.update()
    lines = effect_lines(ocean)
    assert lines["local_reflections"].startswith("off: needed ('Buoy' stands above the water")
    assert lines["contact_foam"].startswith("off: needed ('Buoy' crosses the surface")
    assert lines["refraction"].startswith("off: needed ('Buoy' is below the surface")
    assert ocean.projgrid.active_effects == {"SUN_GLINT"}
    bpy.data.objects["Buoy"].location = (0.0, -40.0, 0.0)  # behind the camera
    bpy.context.view_layer.update()
    assert effect_lines(ocean)["contact_foam"] == "off: nothing in view crosses the surface"


def test_camera_under_the_water(ocean):
    bpy.context.scene.camera.location.z = -3.0
    bpy.context.view_layer.update()
    assert effect_lines(ocean)["underwater"].startswith(
        "off: needed (camera 3 m below the surface")


def test_active_effects_is_read_only(ocean):
    with pytest.raises((AttributeError, TypeError)):
        ocean.projgrid.active_effects = {"FOAM"}
