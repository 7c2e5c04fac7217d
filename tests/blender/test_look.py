"""The look in Blender: Water Colour, Foam Colour, Clarity and Gusts written into our
materials, the water body's light, the foam's grain and the gusts against the core's
numbers (through Geometry Nodes), and the slope layer's images."""

import math

import bpy
import numpy as np
import pytest
from look_numpy import NUMPY

from .helpers import add_ocean


def group_input(obj, name):
    return obj.data.materials[0].node_tree.nodes["Projected Grid Water"].inputs[name]


def test_the_look_is_written_into_our_materials_and_animates(sea, extension):
    """Water colour, foam colour and clarity reach our water material and water body (the body
    absorbs as clear coastal water scaled to the clarity), keyframed too; a material of the
    user's is left as it is, and the panel says so."""
    s = sea.projgrid
    s.water_colour = (0.01, 0.05, 0.04)
    s.foam_colour = (0.9, 0.85, 0.8)
    s.clarity = 5.0
    assert tuple(group_input(sea, "Water Colour").default_value)[:3] == pytest.approx(
        (0.01, 0.05, 0.04))
    assert tuple(group_input(sea, "Foam Colour").default_value)[:3] == pytest.approx(
        (0.9, 0.85, 0.8))
    body = s.water_body.data.materials[0].node_tree.nodes
    absorption = extension.projgrid_addon.optics.absorption(5.0)
    assert absorption[2] == pytest.approx(1.0 / 5.0)  # blue keeps 1/e over the clarity
    assert body["Absorption"].inputs["Density"].default_value == pytest.approx(
        max(absorption), rel=1e-5)

    scene = bpy.context.scene
    s.water_colour = (0.0, 0.0, 0.0)
    s.keyframe_insert("water_colour", frame=1)
    s.water_colour = (0.2, 0.4, 0.6)
    s.keyframe_insert("water_colour", frame=11)
    scene.frame_set(6)
    assert tuple(group_input(sea, "Water Colour").default_value)[:3] == pytest.approx(
        (0.1, 0.2, 0.3), abs=1e-3)

    panel = extension.panels.ocean_panel
    assert panel.look_note(sea) is None
    mine = bpy.data.materials.new("My Water")
    sea.data.materials[0] = mine
    s.water_colour = (0.5, 0.5, 0.5)
    assert "My Water" in panel.look_note(sea)
    assert not mine.get("projgrid_ocean")
    assert mine.node_tree is None or "Projected Grid Water" not in mine.node_tree.nodes


def test_the_water_body_glows_with_the_scene_s_light(sea, extension):
    """The water body scatters the Water Colour in proportion to the light on the sea
    (optics.body_light), as the lit surface does: the same in Add Ocean's daylight, darker
    with the sun lamp out and the sky dimmed, greyer under the overcast (the sky's Overcast
    factor read, as Sea State's Weather sets it), nothing in the dark."""
    scene = bpy.context.scene
    glow = sea.projgrid.water_body.data.materials[0].node_tree.nodes["Water Glow"].inputs

    def emitted():
        return np.array(glow["Color"].default_value[:3]) * glow["Strength"].default_value
    scene.frame_set(2)
    sun = next(o for o in scene.objects if o.type == "LIGHT")
    optics, model = extension.projgrid_addon.optics, extension.shaders.sky.model(scene.world)
    # Add Ocean's daylight in this version's sky (5.x's is DAYLIGHT itself: 1 there)
    lamp = sun.data.energy * np.array(sun.data.color) * math.sin(math.radians(12.0))
    full = np.array(optics.body_light(lamp, optics.sky_irradiance(1.0, 0.0, 12.0, model)))
    daylight = emitted() / full
    sun.data.energy = 0.0
    scene.world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.25
    scene.frame_set(3)
    want = optics.body_light(0.0, optics.sky_irradiance(0.25, 0.0, 12.0, model))
    assert emitted() == pytest.approx(daylight * np.array(want), rel=1e-4)
    assert max(want) < 0.25
    scene.world.node_tree.nodes["Overcast"].inputs["Factor"].default_value = 1.0
    scene.frame_set(5)
    grey = optics.body_light(0.0, optics.sky_irradiance(0.25, 1.0, 12.0, model))
    assert emitted() == pytest.approx(daylight * np.array(grey), rel=1e-4)
    assert grey[2] / grey[0] < 0.8 * want[2] / want[0]
    scene.world = None
    scene.frame_set(4)
    assert emitted().max() < 1e-9


def test_two_oceans_keep_their_own_clarity(sea, extension):
    """Each water body has its own body material: one ocean's clarity is not another's."""
    other = add_ocean()
    other.location.x = 5.0
    bpy.context.scene.frame_set(3)
    sea.projgrid.clarity, other.projgrid.clarity = 4.0, 40.0
    bpy.context.scene.frame_set(4)
    densities = [o.projgrid.water_body.data.materials[0].node_tree.nodes["Absorption"]
                 .inputs["Density"].default_value for o in (sea, other)]
    optics = extension.projgrid_addon.optics
    assert densities == pytest.approx([max(optics.absorption(4.0)),
                                       max(optics.absorption(40.0))], rel=1e-5)


def test_a_water_group_of_an_older_version_is_rebuilt(sea, extension):
    """A file from an older version carries our group without today's inputs: the next frame
    rebuilds it (ours), so the filtering's inputs are written, not skipped."""
    water = extension.shaders.water
    group = sea.data.materials[0].node_tree.nodes["Projected Grid Water"].node_tree
    group["projgrid_ocean"] = water.VERSION - 1
    group.interface.clear()
    bpy.context.scene.frame_set(5)
    group = sea.data.materials[0].node_tree.nodes["Projected Grid Water"].node_tree
    assert group["projgrid_ocean"] == water.VERSION
    assert group_input(sea, "Slope Ceiling").default_value > 0.0


def grain_noise(look, samples=700, w=3.7):
    """The Fac of the foam's grain noise (as the water group sets it) over a square 600 of its
    features across, evaluated by Blender's own noise through Geometry Nodes."""
    return blender_noise(look.FOAM_GRAIN, look.FOAM_DETAIL, look.FOAM_ROUGHNESS,
                         600.0 / look.FOAM_GRAIN, samples, w)


def blender_noise(scale, detail, roughness, size, samples, w):
    """The Fac of Blender's 3D noise texture over a square `size` across, `samples` a side, at
    time `w` (the third coordinate, as the water group's noises take theirs), evaluated through
    Geometry Nodes."""
    mesh = bpy.data.meshes.new("grain")
    obj = bpy.data.objects.new("grain", mesh)
    bpy.context.scene.collection.objects.link(obj)
    tree = bpy.data.node_groups.new("grain", "GeometryNodeTree")
    tree.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    grid = tree.nodes.new("GeometryNodeMeshGrid")
    for axis in ("X", "Y"):
        grid.inputs[f"Size {axis}"].default_value = size
        grid.inputs[f"Vertices {axis}"].default_value = samples
    noise = tree.nodes.new("ShaderNodeTexNoise")
    noise.noise_dimensions = "3D"
    for name, value in (("Scale", scale), ("Detail", detail), ("Roughness", roughness)):
        noise.inputs[name].default_value = value
    at = tree.nodes.new("ShaderNodeVectorMath")
    at.inputs[1].default_value = (0.0, 0.0, w)
    store = tree.nodes.new("GeometryNodeStoreNamedAttribute")
    store.inputs["Name"].default_value = "fac"
    links = tree.links
    links.new(tree.nodes.new("GeometryNodeInputPosition").outputs[0], at.inputs[0])
    links.new(at.outputs[0], noise.inputs["Vector"])
    links.new(grid.outputs[0], store.inputs["Geometry"])
    links.new(noise.outputs["Fac"], store.inputs["Value"])
    links.new(store.outputs[0], tree.nodes.new("NodeGroupOutput").inputs[0])
    obj.modifiers.new("grain", "NODES").node_group = tree
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
    fac = np.empty(len(evaluated.vertices), np.float32)
    evaluated.attributes["fac"].data.foreach_get("value", fac)
    return fac


def test_the_water_group_s_noises_are_those_measured_here(sea):
    """Every noise of the water group is Blender's 3D one, its time the third coordinate, as
    blender_noise measures them."""
    group = sea.data.materials[0].node_tree.nodes["Projected Grid Water"].node_tree
    noises = [n for n in group.nodes if n.bl_idname == "ShaderNodeTexNoise"]
    assert noises and {n.noise_dimensions for n in noises} == {"3D"}
    for noise in noises:
        at = noise.inputs["Vector"].links[0].from_node
        assert at.bl_idname == "ShaderNodeCombineXYZ"
        assert all(at.inputs[axis].is_linked for axis in "XYZ"), noise.name


def test_the_whitecaps_drawn_cover_the_share(extension):
    """The shader draws a vertex's foam share as the top ranks of its grain noise: over
    Blender's own noise, through a period of its time coordinate (at other times than the
    constants were fitted at), the drawn cover is the share within 10 % from 0.001 to 0.95."""
    look, model = extension.projgrid_addon.look, extension.projgrid_addon.water_model
    facs = [grain_noise(look, samples=300, w=w)  # the noise scales its time as its position
            for w in np.linspace(0.075, 1.425, 7) / look.FOAM_GRAIN]
    spread = np.concatenate(facs).std()
    assert spread == pytest.approx(look.FOAM_GRAIN_STD, rel=0.03)
    for share in (0.001, 0.005, 0.02, 0.1, 0.5, 0.95):
        drawn = np.mean([model.grain_cover(NUMPY, model.grain_rank(NUMPY, f), share).mean()
                         for f in facs])
        assert drawn == pytest.approx(share, rel=0.10), share


def test_the_overcast_s_clouds_mottle_it_and_keep_its_light(extension):
    """The storm sky's cloud noise (sky.CLOUD_*) over Blender's own noise, 400 of its features
    across the cloud base: it brightens and darkens the overcast (by some 15 %, its standard
    deviation; up to CLOUD_CONTRAST), and its mean is 1, so the overcast's light on the sea
    stays the CIE sky's (optics.sky_irradiance)."""
    sky = extension.shaders.sky
    fac = blender_noise(sky.CLOUD_SCALE, sky.CLOUD_DETAIL, sky.CLOUD_ROUGHNESS,
                        400.0 / sky.CLOUD_SCALE, 400, 0.0)
    shade = sky.cloud_shade(NUMPY, fac.astype(np.float64), 1.0)
    assert shade.mean() == pytest.approx(1.0, abs=0.02)
    assert shade.std() > 0.1


def test_the_noise_s_waves_are_as_long_as_the_core_says(extension):
    """Blender's noise (roughness 0.5) draws waves shading.NOISE_WAVES of its cells long (2π
    times its Fac's spread over its rms gradient), which the ripples' height is set by to draw
    the spectrum's slopes: within 4 % over three of its time slices, at each Detail; at Detail
    2 its spread is shading.NOISE_FAC_STD's over 0.92 (EEVEE's draws, within 3 %)."""
    shading = extension.projgrid_addon.shading
    n, size = 600, 40.0
    for detail, waves in shading.NOISE_WAVES:
        measured, spread = [], []
        for w in (0.7, 3.7, 9.1):
            fac = blender_noise(1.0, detail, 0.5, size, n, w).reshape(n, n).astype(np.float64)
            gy, gx = np.gradient(fac, size / (n - 1))
            measured.append(2.0 * np.pi * fac.std() / np.sqrt(np.mean(gx * gx + gy * gy)))
            spread.append(fac.std())
        assert np.mean(measured) == pytest.approx(waves, rel=0.04), detail
        if detail == 2.0:  # and the spread EEVEE draws is 0.92 of it (shading.NOISE_FAC_STD)
            assert shading.NOISE_FAC_STD / np.mean(spread) == pytest.approx(0.92, rel=0.03)


def test_the_gusts_setting_scales_the_gusts(sea):
    """The panel's Gusts scales the wind's spread the water group is given (0: a steady
    wind), and keyframed it animates."""
    s = sea.projgrid
    base = group_input(sea, "Gust Amplitude").default_value
    assert base > 0.05
    s.gusts = 2.0
    assert group_input(sea, "Gust Amplitude").default_value == pytest.approx(2.0 * base)
    s.gusts = 0.0
    assert group_input(sea, "Gust Amplitude").default_value == 0.0
    s.keyframe_insert("gusts", frame=1)
    s.gusts = 1.0
    s.keyframe_insert("gusts", frame=11)
    bpy.context.scene.frame_set(6)
    assert group_input(sea, "Gust Amplitude").default_value == pytest.approx(0.5 * base,
                                                                             rel=0.02)


def test_the_gusts_keep_the_sea_s_mean_slope(extension):
    """The gusts' noise over Blender's own noise: (Fac - 0.5) / look.GUST_FAC_STD is the
    local wind's departure in its standard deviations (its spread over four times is 1 within
    5 %), so the wind's spread is shading.gust_spread's; and at each time the ripples' factor
    at the strongest gusts' amplitude (a light wind's) has mean 1 within 2 %, so the sea's mean
    slope stays Cox and Munk's, with calm and gusty patches (a tenth of the sea beyond one
    standard deviation each way); at the cap (Gusts turned up), where lulls leave the water
    flat, within 5 %."""
    core = extension.projgrid_addon
    look, model = core.look, core.water_model
    shading, proj = core.shading, core.camera.perspective(np.radians(40.0), 16 / 9, 0.1, 1e4)

    def gust(fac, amplitude):
        i = {"Gust Amplitude": amplitude, "Gust Norm": 1.0 / shading.gust_mean(amplitude)}
        return model.gust(NUMPY, i, fac, -10.0)

    amplitude = max(shading.filtering(proj, 960, core.spectral_field.SpectralField(
        core.spectrum.SeaState(wind_speed=u)).slopes, u).gust for u in (2.0, 4.0, 7.0, 15.0))
    assert 0.15 < amplitude < 0.5
    n, spreads = 700, []
    for w in (0.7, 3.7, 9.1, 17.3):
        fac = blender_noise(look.GUST_SCALE, look.GUST_DETAIL, 0.5, 300.0 / look.GUST_SCALE,
                            n, w).astype(np.float64)
        spreads.append(np.std((fac - 0.5) / look.GUST_FAC_STD))
        factor = gust(fac, amplitude)
        assert factor.mean() == pytest.approx(1.0, abs=0.02), w
        assert np.mean(factor < 1.0 - amplitude) > 0.1, w
        assert np.mean(factor > 1.0 + amplitude) > 0.1, w
        # and where the lulls leave the water flat, at the gusts' cap
        capped = gust(fac, shading.GUST_CAP)
        assert capped.mean() == pytest.approx(1.0, abs=0.05), w
    assert np.mean(spreads) == pytest.approx(1.0, rel=0.05)


def test_the_grain_churns_at_its_rate_whatever_its_size(sea, extension):
    """Blender's noise multiplies its coordinates by its Scale, its time (the third) too: the
    water group divides the Detail Time by the grain's scale, so the bubbles' pattern changes
    FOAM_CHURN of the noise's own time per unit of Detail Time, whatever the grain's size."""
    water, look = extension.shaders.water, extension.projgrid_addon.look
    tree = bpy.data.node_groups[water.GROUP]
    noise = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeTexNoise"
                 and n.inputs["Scale"].default_value == pytest.approx(look.FOAM_GRAIN))
    at = noise.inputs["Vector"].links[0].from_node
    assert at.bl_idname == "ShaderNodeCombineXYZ"
    rate = at.inputs["Z"].links[0].from_node
    assert rate.operation == "MULTIPLY"
    assert rate.inputs[0].links[0].from_socket.name == "Detail Time"
    per_unit = rate.inputs[1].default_value * noise.inputs["Scale"].default_value
    assert per_unit == pytest.approx(look.FOAM_CHURN)


def test_the_slope_layer_is_each_ocean_s_own_and_follows_the_frame(sea, bridge, extension,
                                                                   tmp_path):
    """Each ocean's material samples its own images of the slope layer, holding the core's
    tiles of the frame (slopes along x and y); the end of playback and a save pack them
    (nothing left 'modified'); the noise draws none."""
    water = extension.shaders.water
    scene = bpy.context.scene

    def images(obj):
        nodes = obj.data.materials[0].node_tree.nodes
        return [nodes[f"Layer {b} Tap 0"].image for b in (1, 2, 3)]

    other = add_ocean()
    other.location.x = 5.0
    scene.frame_set(7)
    ours, theirs = images(sea), images(other)
    assert all(i is not None for i in ours + theirs) and not set(ours) & set(theirs)
    t = 7 / scene.render.fps
    for obj, drawn in ((sea, ours), (other, theirs)):
        layer = bridge.scene.height_field(obj.projgrid).layer
        for image, tile in zip(drawn, layer.slopes(t), strict=True):
            pixels = np.empty(len(image.pixels), np.float32)
            image.pixels.foreach_get(pixels)
            pixels = pixels.reshape(*tile.shape[1:], 4)
            assert np.allclose(pixels[..., :2], np.moveaxis(tile, 0, -1), atol=1e-6)
            assert np.std(tile) > 1e-3
    before = np.array(ours[0].pixels[:64])
    scene.frame_set(8)
    assert not np.allclose(np.array(ours[0].pixels[:64]), before)  # the band travels
    group = sea.data.materials[0].node_tree.nodes[water.GROUP]
    assert group.inputs["Layer Level 1"].default_value == pytest.approx(layer.bands[0].level)
    assert any(i.is_dirty for i in bridge.material_inputs.layer_images())
    bridge.handlers.playback_done()  # as when playback stops
    assert not any(i.is_dirty for i in bridge.material_inputs.layer_images())
    # Scrubbing: packed by a timer once the frame stands still (timers do not run here).
    scene.frame_set(9)
    assert bpy.app.timers.is_registered(bridge.handlers.still)
    assert bridge.handlers.still() > 0.0  # just changed: not yet
    assert any(i.is_dirty for i in bridge.material_inputs.layer_images())
    bridge.handlers._LAST_CHANGE[0] -= bridge.handlers.STILL
    assert bridge.handlers.still() is None
    assert not any(i.is_dirty for i in bridge.material_inputs.layer_images())
    scene.frame_set(10)
    bpy.ops.wm.save_as_mainfile(filepath=str(tmp_path / "layer.blend"))
    images = bridge.material_inputs.layer_images()
    assert all(i.packed_file is not None and not i.is_dirty for i in images)
    sea.projgrid.height_source = "PERLIN"
    scene.frame_set(9)
    # the noise: no layer (its bands' gain sqrt(1 - g^2) is 0 where g = clip(lod - level) = 1)
    assert all(group.inputs[f"Layer Level {b}"].default_value < -50.0 for b in (1, 2, 3))
