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
    """A camera 6 m up looking along +Y a little down, and the ocean at z = 0 (with its sun),
    under a light wind (3 m/s: whitecaps too rare for foam)."""
    scene = bpy.context.scene
    add_camera(scene)
    obj = add_ocean()
    obj.projgrid.wind_speed = 3.0
    scene.frame_set(1)
    return obj


def test_a_bare_ocean_turns_on_nothing(ocean):
    assert ocean.projgrid.active_effects == set()
    lines = effect_lines(ocean)
    assert lines["local_reflections"] == (
        "off: sky only: nothing above the water is mirrored in view")
    assert lines["foam"].startswith("off: wind 3 m/s")
    assert group().nodes["Foam"].mute and group().nodes["Refraction"].mute


def test_wind_brings_foam_and_calm_computes_none(ocean, bridge, monkeypatch):
    calls = []
    foam = import_module(f"{MODULE}.projgrid_addon.foam")
    real = foam.whitecaps
    monkeypatch.setattr(foam, "whitecaps", lambda *a: calls.append(1) or real(*a))
    bpy.context.scene.frame_set(2)
    assert calls == [] and "projgrid_foam" not in ocean.data.attributes  # calm: no foam work
    # Whitecaps cover 1.7 % of the sea at 15 m/s: a grid with vertices enough to catch them.
    ocean.projgrid.resolution_x = ocean.projgrid.resolution_y = 257
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


def attribute(obj, name):
    values = np.empty(len(obj.data.vertices), np.float32)
    obj.data.attributes[name].data.foreach_get("value", values)
    return values


def companions(ocean):
    p = ocean.projgrid
    return p.water_body, p.shadow_caster, p.reflection_probe, p.spray_cloud


def shown(obj):
    return not obj.hide_render and not obj.hide_viewport


def test_a_buoy_across_the_surface_calls_for_the_effects_around_it(ocean, bridge):
    body, caster, probe, _ = companions(ocean)
    assert not any(shown(c) for c in companions(ocean))  # made hidden with the ocean
    assert not ocean.visible_shadow and not ocean.hide_probe_sphere  # never shadows itself
    add_box("Buoy", (0.0, 40.0, 0.0))  # crosses the surface in view, the sun above
    bpy.context.view_layer.update()
    lines = effect_lines(ocean)
    assert lines["local_reflections"] == "on: 'Buoy' stands above the water, mirrored in view"
    assert lines["contact_foam"].startswith("on: 'Buoy' crosses the surface in view, the waves' "
                                            "reach ±")
    assert lines["refraction"] == "on: 'Buoy' is below the surface in view"
    assert lines["caustics"].startswith("on: sun ")
    assert ocean.projgrid.active_effects == {"CONTACT_FOAM", "REFRACTION", "CAUSTICS",
                                             "LOCAL_REFLECTIONS"}
    assert shown(body) and shown(caster) and shown(probe)
    # The reflection is captured by the camera mirrored in the water, which leaves out the
    # water and our own objects and clips at the surface.
    eye = bpy.context.scene.camera.location
    assert tuple(probe.location) == pytest.approx((eye.x, eye.y, -eye.z), abs=1e-5)
    assert probe.data.clip_start == pytest.approx(eye.z, rel=1e-5)
    assert ocean.hide_probe_sphere and body.hide_probe_sphere and caster.hide_probe_sphere
    assert not ocean.visible_shadow and caster.data == ocean.data  # the caster casts it
    assert caster.material_slots[0].material.name == "Projected Grid Water Shadow"
    assert body.location.z == pytest.approx(-bpy.context.scene.eevee.volumetric_end)
    nodes = group().nodes
    assert not any(nodes[n].mute for n in ("Foam", "Refraction"))
    # Contact foam: only near the buoy (1 m from its centre: inside the 2 m box), and only there.
    foam = attribute(ocean, "projgrid_foam")
    grid = bridge.state.RUNTIME.state(ocean).grid
    gx, gy, _ = (grid.positions.astype(np.float64) + grid.origin).T
    distance = np.maximum(np.abs(gx), np.abs(gy - 40.0)) - 1.0
    reach = import_module(f"{MODULE}.projgrid_addon.foam").contact_foam_width(
        bridge.scene.height_field(ocean.projgrid).bounds(
            bridge.shot.scene_time(bpy.context.scene))[0])
    assert foam[distance <= -1e-4].min() == 1.0  # (beside the float32 rounding of positions)
    assert foam[distance > reach + 1e-4].max() == 0.0
    caustics = attribute(ocean, "projgrid_caustics")
    assert caustics.std() > 0.01 and caustics.min() >= -0.5 and caustics.max() <= 0.5

    bpy.data.objects["Buoy"].location = (0.0, -40.0, 0.0)  # behind the camera
    bpy.context.view_layer.update()
    assert effect_lines(ocean)["contact_foam"].startswith(
        "off: nothing in view crosses the surface,")
    assert ocean.projgrid.active_effects == set()
    assert not any(shown(c) for c in companions(ocean)) and not ocean.visible_shadow
    assert not ocean.hide_probe_sphere  # the user's own sphere probes see the water again
    assert "projgrid_foam" not in ocean.data.attributes
    assert "projgrid_caustics" not in ocean.data.attributes
    assert all(nodes[n].mute for n in ("Foam", "Refraction"))


def test_a_rock_in_front_of_the_mirror_image_keeps_reflections_off(ocean):
    add_box("Mast", (0.0, 40.0, 4.0))
    rock = add_box("Rock", (0.0, 30.0, -2.0))  # 1 m under the water, the camera 6 m above it
    bpy.context.view_layer.update()
    assert effect_lines(ocean)["local_reflections"].startswith(
        "off: 'Rock' would show in the reflection")
    assert not shown(ocean.projgrid.reflection_probe) and not ocean.hide_probe_sphere
    rock.location.z = -8.0  # below the capture point: out of its way
    bpy.context.view_layer.update()
    assert effect_lines(ocean)["local_reflections"] == (
        "on: 'Mast' stands above the water, mirrored in view")
    assert shown(ocean.projgrid.reflection_probe) and ocean.hide_probe_sphere


def test_camera_under_the_water_shows_the_water_body_and_godrays(ocean):
    scene = bpy.context.scene
    scene.camera.location.z = -3.0
    bpy.context.view_layer.update()
    lines = effect_lines(ocean)
    assert lines["underwater"] == "on: camera 3 m below the surface"
    assert lines["godrays"].startswith("on: camera 3 m below the surface, sun ")
    assert lines["refraction"].startswith("off: camera 3 m below")
    body, caster, probe, _ = companions(ocean)
    assert shown(body) and shown(caster) and not shown(probe)
    assert tuple(body.location)[:2] == pytest.approx(tuple(scene.camera.location)[:2], abs=1e-6)
    assert not body.data.materials[0].node_tree.nodes["Godrays"].mute
    # The godrays scatter by the caustic tile around the camera (its lookup: test_effect_shots).
    image = bpy.data.images["Projected Grid Caustics"]
    assert not image.is_dirty  # nothing to save when the file closes
    tile = np.empty(256 * 256 * 4, np.float32)
    image.pixels.foreach_get(tile)
    assert tile[0::4].std() > 0.01 and 0.0 <= tile.min() and tile.max() <= 4.0
    sun = next(o for o in scene.objects if o.type == "LIGHT")
    sun.hide_render = True  # no sun: no godrays, no caustics
    scene.frame_set(2)
    assert ocean.projgrid.active_effects == {"UNDERWATER"}
    assert body.data.materials[0].node_tree.nodes["Godrays"].mute
    assert "projgrid_caustics" not in ocean.data.attributes


def test_effects_that_are_off_compute_nothing(ocean, bridge, monkeypatch):
    calls = []
    effects = import_module(f"{MODULE}.projgrid_addon.effects")
    for module, name in (("foam", "contact_foam"), ("optics", "caustic_intensity"),
                         ("optics", "caustic_tile"), ("foam", "foam_thresholds"),
                         ("optics", "receiving_depth"), ("spray", "spray")):
        module = import_module(f"{MODULE}.projgrid_addon.{module}")
        real = getattr(module, name)
        monkeypatch.setattr(module, name,
                            lambda *a, _n=name, _f=real: calls.append(_n) or _f(*a))
    for effect in effects.EFFECTS:
        setattr(ocean.projgrid, effect, "OFF")
    add_box("Buoy", (0.0, 40.0, 0.0))
    ocean.projgrid.wind_speed = 20.0
    bpy.context.scene.frame_set(3)
    assert calls == [] and ocean.projgrid.active_effects == set()
    assert not any(shown(c) for c in companions(ocean))
    assert not {"projgrid_foam", "projgrid_caustics"} & set(ocean.data.attributes.keys())
    ocean.projgrid.contact_foam = "ON"
    assert calls == ["contact_foam"]


def test_our_companions_are_ours_and_not_scene_objects(ocean, bridge):
    assert all(bridge.scene.owns(c) and bridge.scene.owns(c.data) for c in companions(ocean))
    assert [c.name for c in companions(ocean)] == ["Ocean Water Body", "Ocean Shadow",
                                                   "Ocean Reflection", "Ocean Spray"]
    bpy.data.objects.remove(ocean.projgrid.reflection_probe)  # deleted by the user: made
    ocean.projgrid.seed = 4  # again, hidden, on the next build
    probe = ocean.projgrid.reflection_probe
    assert probe is not None and probe.type == "LIGHT_PROBE" and not shown(probe)


def test_deleting_an_ocean_deletes_its_companions_only(ocean):
    other = add_ocean()
    mine, theirs = companions(ocean), companions(other)
    names = [c.name for c in mine]
    for obj in bpy.context.view_layer.objects:
        obj.select_set(obj == ocean)
    assert bpy.ops.object.delete() == {"FINISHED"}  # as the user deletes it
    bpy.context.view_layer.update()
    assert "Ocean" not in bpy.data.objects
    assert not set(names) & set(bpy.data.objects.keys())
    assert "Ocean Water Body" not in bpy.data.meshes  # its box went with it
    assert all(c.name in bpy.data.objects for c in theirs)
    assert companions(other) == theirs


def test_a_duplicated_ocean_gets_companions_of_its_own(ocean):
    copy = ocean.copy()  # as Shift+D: the settings, so the pointers, are copied
    copy.data = ocean.data.copy()
    bpy.context.scene.collection.objects.link(copy)
    assert companions(copy) == companions(ocean)
    bpy.context.view_layer.update()
    mine, theirs = companions(ocean), companions(copy)
    assert all(c is not None for c in theirs) and not set(mine) & set(theirs)
    assert theirs[1].parent == copy and theirs[1].data == copy.data  # its own caster
    assert mine[1].parent == ocean and mine[1].data == ocean.data


def test_a_gale_tears_spray_off_the_crests(ocean, bridge):
    """From Beaufort 8 AUTO turns spray on: our spray companion shows, a vertex per puff of
    the frame's spray (spray.spray) with its radius and opacity, drawn as points by our
    geometry nodes in our spray material; below force 8, or OFF, it is hidden,
    costing nothing."""
    cloud = ocean.projgrid.spray_cloud
    assert not shown(cloud)
    assert bpy.ops.projgrid.sea_state(beaufort=9) == {"FINISHED"}
    bpy.context.scene.frame_set(48)
    assert "SPRAY" in ocean.projgrid.active_effects and shown(cloud)
    assert effect_lines(ocean)["spray"].startswith("on: wind 22.6 m/s tears spindrift")
    n = len(cloud.data.vertices)
    assert n > 100 and not cloud.data.polygons
    radius = attribute(cloud, "projgrid_spray_radius")
    opacity = attribute(cloud, "projgrid_spray_opacity")
    assert radius.min() > 0.05 and 0.0 < opacity.max() <= 1.0
    world = np.array(cloud.matrix_world)
    at = np.empty(3 * n, np.float32)
    cloud.data.vertices.foreach_get("co", at)
    height = (at.reshape(n, 3) + world[:3, 3])[:, 2]
    assert -10.0 < np.median(height) < 10.0  # on and above the sea, not somewhere else
    modifier = cloud.modifiers[0]
    assert modifier.type == "NODES" and bridge.scene.owns(modifier.node_group)
    assert any(n.bl_idname == "GeometryNodeMeshToPoints" for n in modifier.node_group.nodes)
    assert cloud.data.materials[0].name == "Projected Grid Spray"
    ocean.projgrid.spray = "OFF"
    assert "SPRAY" not in ocean.projgrid.active_effects and not shown(cloud)
    ocean.projgrid.spray = "AUTO"
    assert bpy.ops.projgrid.sea_state(beaufort=7) == {"FINISHED"}
    assert not shown(cloud)
    assert effect_lines(ocean)["spray"].startswith("off: wind 15.5 m/s tears no spray")


def test_active_effects_is_read_only(ocean):
    with pytest.raises((AttributeError, TypeError)):
        ocean.projgrid.active_effects = {"FOAM"}
