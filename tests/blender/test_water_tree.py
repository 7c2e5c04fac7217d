"""The water group's node tree, evaluated node by node in Python (a shader cannot be run
without a render): it computes the look's model (projgrid_addon/water_model.py, from which it is
built), and what it draws is the published formulas': Fresnel's reflectance (Eq. 1.4, with
total internal reflection under water), Bruneton's mean Fresnel of a rough sea, Cox and Munk's
slope variance where no wave is drawn, Monahan's whitecap share."""

import itertools
import math
import os

import bpy
import numpy as np
import pytest
from look_numpy import NUMPY, even_ranks, grain_facs_at

from .helpers import spectral_sea
from .node_eval import FACET_RANDOM, Evaluator


@pytest.fixture
def water(extension):
    """The spectral sea's water group node in its material, and the core's modules."""
    obj = spectral_sea()
    material = extension.operators.bridge.material_inputs.material_of(obj.data)
    return material.node_tree.nodes[extension.shaders.water.GROUP], extension.projgrid_addon


def group_values(node):
    """The group node's input values, as the frame wrote them."""
    return {s.name: (np.array(s.default_value[:3], float)
                     if hasattr(s.default_value, "__len__") else float(s.default_value))
            for s in node.inputs if hasattr(s, "default_value")}


def incoming(cos_view):
    """Toward the camera, at `cos_view` to a flat sea's normal."""
    return np.array([math.sqrt(1.0 - cos_view * cos_view), 0.0, cos_view])


GLOSSY = ("ShaderNodeBsdfGlossy", "ShaderNodeBsdfAnisotropic")  # Blender 4.x names it so


def find(tree, kinds, **linked):
    """The node of one of `kinds` whose named inputs are linked (True) or not (False)."""
    return next(n for n in tree.nodes if n.bl_idname in kinds
                and all(n.inputs[k].is_linked == v for k, v in linked.items()))


def diffuse_colour(tree, operation):
    """The Color input of the diffuse BSDF fed by a Vector Math node of `operation` (SCALE: the
    foam's, ADD: the water body's)."""
    return next(n for n in tree.nodes if n.bl_idname == "ShaderNodeBsdfDiffuse"
                and n.inputs["Color"].is_linked
                and n.inputs["Color"].links[0].from_node.bl_idname == "ShaderNodeVectorMath"
                and n.inputs["Color"].links[0].from_node.operation == operation).inputs["Color"]


CASES = [(d, c, lod) for d in (3.0, 15.0, 40.0, 400.0, 4000.0, 4e4, 4e5) for c in (0.05, 0.4, 1.0)
         for lod in (-6.0, -1.5, 0.7, 3.0)]


def test_the_tree_computes_the_model(water):
    """At a flat sea's point, for distances, view angles, band limits, sun directions (or no
    sun lamp), gust and grain noise values and vertex foam: the lobe's roughness and the glint
    facets' tilt, the ripples' bump height, each slope-layer band's gain, the foam drawn and the
    Fresnel output are the model's formulas evaluated in NumPy (the tree is built from them: a
    wrong link or operator in the build shows here)."""
    node, core = water
    model, tree, look = core.water_model, node.node_tree, core.look
    values = group_values(node)
    assert values["Layer Density"] > 0.0 and values["Slope Density"] > 0.0  # not trivial
    assert values["Gust Amplitude"] > 0.1
    values.update({"Foam Coverage": 0.03, "Residual Coverage": 0.05, "Aged Coverage": 0.01,
                   "Foam Streak": 3.0, "Blown Coverage": 0.1})
    glossy = find(tree, GLOSSY, Roughness=True)
    ripples_bump = find(tree, ("ShaderNodeBump",), Normal=True)
    tilt = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeVectorMath"
                and n.operation == "MULTIPLY" and n.inputs[1].is_linked
                and n.inputs[1].links[0].from_node.bl_idname == "ShaderNodeCombineXYZ")
    foam, fresnel = tree.nodes["Foam"].inputs[0], find(tree, ("NodeGroupOutput",)).inputs["Fresnel"]
    foam_colour, body = (diffuse_colour(tree, op) for op in ("SCALE", "ADD"))
    water_albedo = np.minimum(values["Water Colour"] * np.pi / np.asarray(look.DAYLIGHT), 1.0)
    bubbles = model.bubble_albedo(NUMPY, water_albedo, water_albedo.max())
    seen = {"roughness": set(), "facets": set(), "gust": set(), "gain": set(), "foam": set(),
            "plume": set()}
    for (d, c, lod), sun, fac, share, band, left in zip(
            CASES, itertools.cycle((0.0, 0.3, 1.0, None)),
            itertools.cycle((0.5, 0.38, 0.6, 0.71, 0.45)),
            itertools.cycle((0.0, 0.01, 0.6)), itertools.cycle((1, 2, 3, 2, 1)),
            itertools.cycle((0.0, 0.3, 0.0, 0.05)), strict=False):
        # the sun where the view's mirror is, `sun` radians above it, or no sun lamp
        s = math.sqrt(1.0 - c * c)
        toward = np.zeros(3) if sun is None else np.array(
            [c * math.sin(sun) - s * math.cos(sun), 0.0, c * math.cos(sun) + s * math.sin(sun)])
        one = {**values, "Sun Direction": toward,
               **{f"Layer Slopes {k}": np.array([float(k == band), 0.0, 0.0]) for k in (1, 2, 3)}}
        flat = {**one, **{f"Layer Slopes {k}": np.zeros(3) for k in (1, 2, 3)}}
        attributes = {"projgrid_foam": share, "projgrid_foam_residual": left}
        # each foam noise its own value: a noise swapped for another in the build shows
        foams = [fac, *(0.5 + (fac - 0.5) * k + 0.05 * k for k in (-1.0, -0.4, 0.6, 1.5, -0.7))]
        facs = {None: fac, **{round(scale, 6): f for scale, f in zip(
            (look.FOAM_GRAIN, look.FOAM_LACE, look.FOAM_NET, look.FOAM_AGED, look.FOAM_BLOWN,
             look.FILM_WEB), foams, strict=True)}}
        ev = Evaluator(flat, lod, d, incoming(c), attributes=attributes, fac=facs)
        tilted = Evaluator(one, lod, d, incoming(c), attributes=attributes, fac=facs)

        lp, log_cos = model.footprint(NUMPY, flat, d, c)
        gust = model.gust(NUMPY, flat, fac, lp)
        ripples = model.ripples_undrawn(NUMPY, flat, gust, lp)
        slopes = model.roughness(NUMPY, flat, lod, lp, ripples)
        half = incoming(c) + toward
        cos_half = max(half[2] / np.linalg.norm(half), 0.01)
        facets = model.facet_variance(NUMPY, flat, lp, log_cos, 1.0, cos_half,
                                      min(np.linalg.norm(toward), 1.0), ripples)
        want = max(slopes - facets, 0.0) ** 0.25
        assert ev.input(glossy.inputs["Roughness"]) == pytest.approx(want, rel=1e-5, abs=1e-9)
        u, w = FACET_RANDOM  # Box-Muller from the facet's cell's two random values
        slope = math.sqrt(-2.0 * math.log(u) * facets / 2.0)
        normal = np.array([slope * math.cos(2 * math.pi * w), slope * math.sin(2 * math.pi * w),
                           1.0])
        assert ev.input(glossy.inputs["Normal"]) == pytest.approx(
            normal / np.linalg.norm(normal), abs=1e-6)
        _, kept, _ = model.octaves_drawn(NUMPY, flat["Ripple Top Log"], lp,
                                         flat["Ripple Octaves"], 0.5)
        assert ev.input(ripples_bump.inputs["Distance"]) == pytest.approx(
            flat["Ripple Height"] * math.sqrt(gust) * kept, rel=1e-5, abs=1e-12)
        gain = model.layer_gain(NUMPY, lod, one[f"Layer Level {band}"],
                                one[f"Layer Top Log {band}"], one[f"Layer Bottom Log {band}"], lp)
        assert -tilted.output(tilt.outputs[0])[0] == pytest.approx(gain, rel=1e-5, abs=1e-7)
        drawn, brightness, plume = model.foam_cover(NUMPY, flat, share, left, *foams, lp,
                                                    log_cos)
        assert ev.input(foam) == pytest.approx(drawn, rel=1e-5, abs=1e-6)
        assert ev.input(body) == pytest.approx(
            water_albedo + (bubbles - water_albedo) * plume, rel=1e-5)
        assert ev.input(foam_colour) == pytest.approx(
            (values["Foam Colour"] + look.FOAM_SHEEN) * brightness, rel=1e-5)
        exact = model.fresnel(NUMPY, flat["IOR"], c, 0.0)
        assert ev.input(fresnel) == pytest.approx(
            model.mean_fresnel(NUMPY, exact, c, slopes, 0.0), rel=1e-5)
        for key, v in zip(seen, (slopes, facets, gust, gain, drawn, plume), strict=True):
            seen[key].add(round(float(v), 4))
    # the cases reach every part of the formulas: far and near, facets and none, calm and
    # gusty patches beyond a standard deviation of the wind each way, bands held and not,
    # foam whole, none and the sea's mean share
    assert len(seen["roughness"]) > 10 and len(seen["facets"]) > 2
    assert min(seen["gust"]) < 1.0 - values["Gust Amplitude"] < 1.0 + values["Gust Amplitude"] \
        < max(seen["gust"])
    assert {0.0} < seen["gain"] and max(seen["gain"]) > 0.5
    far = 0.03 + 0.97 * (0.05 + 0.95 * (0.01 + 0.99 * 0.1))
    assert {0.0, 1.0, round(far, 4)} <= seen["foam"], sorted(seen["foam"])
    far = 0.03 * look.BUBBLE_SPREAD
    far = far + (1.0 - far) * 0.05 * look.BUBBLE_RESIDUAL
    assert {0.0, 1.0, round(far, 4)} <= seen["plume"], sorted(seen["plume"])


def fresnel_eq_1_4(n1, n2, cos_i):
    """Unpolarised reflectance from a medium of index n1 into n2 (Fresnel; the seed's Eq. 1.4):
    1 beyond the critical angle."""
    sin_t = n1 / n2 * math.sqrt(1.0 - cos_i * cos_i)
    if sin_t >= 1.0:
        return 1.0
    cos_t = math.sqrt(1.0 - sin_t * sin_t)
    rs = ((n1 * cos_i - n2 * cos_t) / (n1 * cos_i + n2 * cos_t)) ** 2
    rp = ((n1 * cos_t - n2 * cos_i) / (n1 * cos_t + n2 * cos_i)) ** 2
    return 0.5 * (rs + rp)


def test_the_reflectance_is_fresnel_s_and_bruneton_s(water):
    """On a mirror-flat sea the group's Fresnel is the exact reflectance of water (IOR 1.333)
    from above and from under water, where beyond the critical angle (48.6 deg) all is
    reflected; on a rough sea (slope variance s^2) from above, less at grazing by Bruneton's
    fit of the mean Fresnel (2010, Eq. 11) against a mirror's: 0.98 ((1 - cos)^(5 e^(-2.69 s))
    / (1 + 22.7 s^1.5) - (1 - cos)^5), s^2 per axis half the variance."""
    node, _ = water
    values = group_values(node)
    out = find(node.node_tree, ("NodeGroupOutput",)).inputs["Fresnel"]
    ior = values["IOR"]
    assert ior == pytest.approx(1.333)
    flat = {**values, "Slope Ceiling": 0.0}
    for degrees in (0.0, 20.0, 40.0, 48.0, 49.0, 60.0, 75.0, 85.0, 89.0):
        c = math.cos(math.radians(degrees))
        above = Evaluator(flat, 0.0, 50.0, incoming(c)).input(out)
        below = Evaluator(flat, 0.0, 50.0, incoming(c), backfacing=1.0).input(out)
        assert above == pytest.approx(fresnel_eq_1_4(1.0, ior, c), rel=1e-4, abs=1e-6)
        assert below == pytest.approx(fresnel_eq_1_4(ior, 1.0, c), rel=1e-4, abs=1e-6)
        assert (below == pytest.approx(1.0)) == (degrees > math.degrees(math.asin(1.0 / ior)))
    for variance in (0.01, 0.05):  # the whole sea's roughness, where nothing is drawn
        rough = {**values, "Slope Floor": variance, "Slope Ceiling": variance}
        for degrees in (30.0, 70.0, 85.0):
            c = math.cos(math.radians(degrees))
            s = math.sqrt(variance / 2.0)
            fit = 0.98 * ((1 - c) ** (5 * math.exp(-2.69 * s)) / (1 + 22.7 * s**1.5) - (1 - c)**5)
            drawn = Evaluator(rough, 0.0, 1e5, incoming(c)).input(out)
            assert drawn == pytest.approx(fresnel_eq_1_4(1.0, ior, c) + fit, rel=1e-4)


def test_the_far_sea_s_roughness_is_cox_munk_s(water, extension):
    """Where a pixel is longer than every wave (far, grazing, the vertices holding no band) the
    lobe's slope variance (Roughness^4) is Cox and Munk's for the wind, 0.003 + 5.12e-3 U with
    U at 12.5 m (the log profile, roughness length 2e-4 m, from the wind at 10 m); near the
    camera, where the waves are drawn, a small part of it."""
    node, _ = water
    values = {**group_values(node), "Sun Direction": np.zeros(3)}
    u = bpy.context.active_object.projgrid.wind_speed
    assert u > 8.0  # force 5
    cox_munk = 0.003 + 5.12e-3 * u * math.log(12.5 / 2e-4) / math.log(10.0 / 2e-4)
    glossy = find(node.node_tree, GLOSSY, Roughness=True)
    for c in (0.05, 0.2):
        far = Evaluator(values, -10.0, 1e6, incoming(c)).input(glossy.inputs["Roughness"])
        assert far**4 == pytest.approx(cox_munk, rel=1e-4)
    near = Evaluator(values, 8.0, 2.0, incoming(1.0)).input(glossy.inputs["Roughness"])
    assert near**4 < 0.1 * cox_munk


def test_the_foam_drawn_is_monahan_s_share(water, extension):
    """The share of the sea the frame asks whitecaps and their residual foam to cover is Monahan
    and O'Muircheartaigh's 1.59e-5 U^2.55 (Fleck Eq. 32); a pixel longer than a whitecap draws
    that share (the residual's over what the active leaves), and near the camera the grain's
    and the lace's top ranks draw a vertex's shares (over their ranks, evenly: the mean)."""
    node, core = water
    values = group_values(node)
    u = bpy.context.active_object.projgrid.wind_speed
    active, residual, aged = (values[f"{k} Coverage"] for k in ("Foam", "Residual", "Aged"))
    assert active + residual + aged == pytest.approx(1.59e-5 * u**2.55, rel=1e-5)
    assert 0.0 < aged < active < residual
    mix = node.node_tree.nodes["Foam"].inputs[0]
    for share in (0.0, 0.3):
        far = Evaluator(values, 0.0, 2e5, incoming(0.05),
                        attributes={"projgrid_foam": share, "projgrid_foam_residual": share})
        left = residual + (1.0 - residual) * aged
        assert far.input(mix) == pytest.approx(active + (1.0 - active) * left, rel=1e-5)
    look = core.look
    facs = grain_facs_at(even_ranks(400))
    young = {**values, "Aged Coverage": 0.0}
    # every noise's ranks evenly, and every pair of them with the webs' noises'
    each = {None: facs[:, None], **{round(s, 6): facs[None, :]
                                    for s in (look.FOAM_NET, look.FILM_WEB)}}
    for share, stage in itertools.product((0.02, 0.3), ("projgrid_foam", "projgrid_foam_residual")):
        drawn = Evaluator(young, 0.0, 3.0, incoming(1.0),
                          attributes={"projgrid_foam": 0.0, "projgrid_foam_residual": 0.0,
                                      stage: share}, fac=each).input(mix)
        assert np.mean(drawn) == pytest.approx(share, rel=0.02), (share, stage)
        assert drawn.max() == 1.0 and drawn.min() == 0.0  # a solid core, bare water around
    # the aged foam, over the whole sea: a film of AGED_FILM over its share / AGED_FILM (a gale's
    # share: the frame's is too small for the ranks sampled here)
    aged = 0.02
    streaks = Evaluator({**values, "Aged Coverage": aged}, 0.0, 3.0, incoming(1.0),
                        attributes={"projgrid_foam": 0.0, "projgrid_foam_residual": 0.0},
                        fac={**each, round(look.FOAM_GRAIN, 6): 0.5}).input(mix)
    assert np.mean(streaks) == pytest.approx(aged, rel=0.02)
    assert streaks.max() == pytest.approx(look.AGED_FILM) and streaks.min() == 0.0


def test_the_body_gives_back_its_colour_in_daylight(water, extension):
    """Under DAYLIGHT (Add Ocean's sky and sun lamp 12 degrees up: tests/blender/test_sky.py)
    the water scatters back its Water Colour: the group's diffuse albedo times the daylight
    over pi."""
    water_module = extension.shaders.water
    node, _ = water
    values = group_values(node)
    body = diffuse_colour(node.node_tree, "ADD")  # no whitecap: no bubble plume
    albedo = Evaluator(values, 0.0, 10.0, (0.0, 0.0, 1.0)).input(body)
    assert albedo * np.asarray(water_module.DAYLIGHT) / math.pi == pytest.approx(
        values["Water Colour"], rel=1e-4)
    # A colour brighter than the daylight can give back scatters all it receives, no more.
    bright = {**values, "Water Colour": np.array([0.9, 0.2, 0.9])}
    albedo = Evaluator(bright, 0.0, 10.0, (0.0, 0.0, 1.0)).input(body)
    assert albedo == pytest.approx([1.0, 0.2 * math.pi / water_module.DAYLIGHT[1], 1.0])
    # Lit, not glowing (a dusk sea would shine in the dark): the one emission is the air's
    # light of the aerial perspective, our sky's (sky.horizon), into the Haze mix alone.
    glowing = [n for n in node.node_tree.nodes if n.bl_idname == "ShaderNodeEmission"]
    assert len(glowing) == 1
    assert [(k.to_node.name, k.to_socket.identifier) for k in glowing[0].outputs[0].links] == [
        (water_module.HAZE, "Shader_001")]
    sky = glowing[0].inputs["Color"].links[0].from_node
    assert sky.bl_idname == "ShaderNodeMix"  # the clear sky toward the overcast
    clear = next(i for i in sky.inputs if i.identifier == "A_Color").links[0].from_node
    assert clear.inputs[0].links[0].from_node.name == extension.shaders.sky.SKY  # times a scale


def _described(tree):
    """Everything a node tree computes with: its interface, each node's settings and unlinked
    inputs' values, its links."""
    def value(v):
        return str(tuple(v) if hasattr(v, "__len__") and not isinstance(v, str) else v)

    def settings(node):
        return [(p.identifier, value(getattr(node, p.identifier)))
                for p in node.bl_rna.properties if not p.is_readonly
                and p.type in {"ENUM", "BOOLEAN", "INT", "FLOAT", "STRING"}]
    nodes = {n.name: (n.bl_idname, settings(n), [
        (s.identifier, value(s.default_value)) for s in n.inputs
        if not s.is_linked and hasattr(s, "default_value")]) for n in tree.nodes}
    links = sorted((k.from_node.name, k.from_socket.identifier, k.to_node.name,
                    k.to_socket.identifier) for k in tree.links)
    face = [(i.name, i.in_out, i.socket_type, value(getattr(i, "default_value", None)))
            for i in tree.interface.items_tree]
    return face, nodes, links


def test_a_later_file_appends_the_first_build(extension, monkeypatch):
    """The water group is built once per session (a build is seconds: Blender updates the
    tree after each node added); a file that lacks it later appends that first build's copy
    (shaders/built.py): the same interface, nodes, settings, values and links, and no
    library left behind."""
    water, built = extension.shaders.water, extension.shaders.built
    monkeypatch.setattr(built, "_FILES", {})
    made = water.node_group()
    try:
        want = _described(made)
        assert len(built._FILES) == 1 and len(made.nodes) > 100
        bpy.data.node_groups.remove(made)
        copy = water.node_group()
        assert copy.get(extension.shaders.nodes.TAG) == water.VERSION
        assert _described(copy) == want
        assert copy.library is None and len(bpy.data.libraries) == 0
    finally:
        for path, _ in built._FILES.values():
            os.remove(path)


def test_a_spray_puff_fades_out_to_its_rim(extension):
    """The spray material draws a puff as a sphere of droplets of even density: opaque along a
    ray as Beer-Lambert over the chord through it, 1 - (1 - o)^(1.5 cos), o its opacity (the
    attribute times SPRAY_OPACITY), so it fades to nothing at its rim, its mean over the disc
    o for a thin puff; lit as a level white patch (the diffuse's normal up), not a ball; seen
    through the air as the water is: its white gives way to the air's light as
    1 - exp(-beta d), beta its object's haze property (Koschmieder)."""
    materials, look = extension.shaders.materials, extension.projgrid_addon.look
    water_module = extension.shaders.water
    tree = materials.spray_material().node_tree
    mix = tree.nodes[materials.PUFF]
    diffuse = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeBsdfDiffuse")
    assert not diffuse.inputs["Normal"].is_linked
    assert tuple(diffuse.inputs["Normal"].default_value) == pytest.approx((0.0, 0.0, 1.0))
    name = extension.shaders.water.SPRAY_ATTRIBUTES[1]

    def seen(attribute, cos):
        incoming = (math.sqrt(1.0 - cos * cos), 0.0, cos)  # the normal is up: |N . I| = cos
        return Evaluator({}, 0.0, 10.0, incoming, attributes={name: attribute}).input(
            mix.inputs[0])
    o = 0.9 * look.SPRAY_OPACITY
    assert seen(0.9, 1.0) == pytest.approx(1.0 - (1.0 - o) ** 1.5, rel=1e-5)
    assert seen(0.9, 0.001) < 0.01 * seen(0.9, 1.0)
    thin = 0.05
    r = (np.arange(400) + 0.5) / 400.0  # rings of the disc, weighted by their area
    mean = sum(seen(thin / look.SPRAY_OPACITY, math.sqrt(1.0 - x * x)) * x for x in r) / r.sum()
    assert mean == pytest.approx(thin, rel=0.05)
    haze = tree.nodes[materials.HAZE]
    assert mix.inputs[2].links[0].from_node == haze
    assert haze.inputs[1].links[0].from_node == diffuse
    glow = haze.inputs[2].links[0].from_node
    assert glow.bl_idname == "ShaderNodeEmission"
    air = dict(zip(water_module.SPRAY_AIR, (3.912 / 5000.0, 0.0), strict=True))
    for d in (0.0, 500.0, 5000.0):
        assert Evaluator({}, 0.0, d, (0.0, 0.0, 1.0), attributes=air).input(
            haze.inputs[0]) == pytest.approx(1.0 - math.exp(-3.912 / 5000.0 * d), abs=1e-6)
