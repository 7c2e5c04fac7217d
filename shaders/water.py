"""The EEVEE node group "Projected Grid Water" (thesis §3.4, App. B) and our water material.

    colour = lerp(refraction, reflection of the sky and the sun, F)               (§3.4.8)

The octaves the geometry left out (GridResult.shader_octaves) come back as bump detail, faded in
where the vertices' band limit (the per-vertex `projgrid_lod` attribute) dropped them (§3.1.3),
and the ripples below the last band as a second bump. Waves shorter than a pixel shows become
the roughness of the reflection (Bruneton, Neyret and Holzschuch 2010; shading.Filtering): each
bump is drawn as far as a pixel shows its waves, and the slope variance of the rest is the GGX
lobe's, so the sky's reflection blurs and the sun lamp's highlight widens into a glitter path
with distance, and nothing flickers as detail finer than a pixel would. Near the camera the
ripples' undrawn slopes are the glint's facets instead (water_model.facet_variance), each
with its own normal, so the sun sparkles on them as on the sea. F is, from above, the
mean Fresnel over those slopes (Bruneton's fit), which keeps a rough far sea darker than the sky
at the horizon; from under water the exact unpolarised reflectance (Eq. 1.4) for IOR 1.333, in
the form Blender's Fresnel node uses (total internal reflection when g^2 < 0). The sky is the
world, or with local reflections our sphere probe's capture; the refraction is the light the water
scatters back up, lit by the scene (from below, the sky through Snell's window). Far off, it all
gives way to the air's light, the sky's (aerial perspective: daylight.haze, sky.horizon).

Effects are branches muted while off (a muted mix or add shader passes its first shader on, so
the branch is neither compiled nor evaluated): foam and refraction (the water colour
replaced by transparency, dithered; the water body's volume then absorbs and tints what lies
below, Fleck Eq. 14/17). The water's shadow is cast by a caster object of ours with its own
material, transparent by the caustics: the scene's sun projects them onto submerged geometry.
The godrays scatter in the water body by a caustic tile of ours (CAUSTIC_IMAGE). Refraction
stays dithered: EEVEE's blended method is far slower on the CPU (docs/benchmarks.md, findings).
The water body is a volume of our own: absorption a per channel and emission a * water colour
(times the light on the sea against the daylight, optics.body_light), so that radiance after d
metres is e^(-a d) L + (1 - e^(-a d)) water colour (Eq. 14 and 17).

Every formula of the look is projgrid_addon/water_model.py's, built here as Math nodes (the Graph
is the maths they are evaluated in); this file only wires them to the textures, bumps and
shaders. The tree is built top to bottom as the shading model reads (detail, filtering,
Fresnel, reflection, refraction, foam); the materials that use it are materials.py's.
"""

import math

import bpy

from ..projgrid_addon import water_model as model
from ..projgrid_addon.look import (
    DAYLIGHT,
    FILM_WEB,
    FOAM_AGED,
    FOAM_BLOWN,
    FOAM_CHURN,
    FOAM_DETAIL,
    FOAM_GRAIN,
    FOAM_GRAIN_STD,
    FOAM_LACE,
    FOAM_LACE_CHURN,
    FOAM_NET,
    FOAM_ROUGHNESS,
    FOAM_SHEEN,
    FOAM_STREAK,
    FOAM_WARP,
    GUST_DETAIL,
    GUST_EVOLVE,
    GUST_SCALE,
)
from ..projgrid_addon.water_model import INPUTS, LAYER_BANDS
from . import built, sky
from .glint import glint_facets
from .nodes import TAG, Graph

GROUP = "Projected Grid Water"
MATERIAL = "Projected Grid Water"
BODY_MATERIAL = "Projected Grid Water Body"
SHADOW_MATERIAL = "Projected Grid Water Shadow"
SPRAY_MATERIAL = "Projected Grid Spray"
SPRAY_POINTS = "Projected Grid Spray Points"  # the geometry nodes drawing the puffs as points
SPRAY_ATTRIBUTES = ("projgrid_spray_radius", "projgrid_spray_opacity")  # per puff, written
# on the spray's object each frame: the air's extinction per metre and our sky's overcast (its
# haze, as the water's "Haze" and "Overcast")
SPRAY_AIR = ("projgrid_haze", "projgrid_overcast")
CAUSTIC_IMAGE = "Projected Grid Caustics"  # the godrays' caustic tile (optics.caustic_tile)
VERSION = 39  # stored in the TAG property; a group or material of another version is rebuilt
LOD_ATTRIBUTE = "projgrid_lod"  # per-vertex band limit, written by the bridge
GUST_DRIFT = ("Gust Drift X", "Gust Drift Y", "Gust Path")  # the inputs the drift drives
# per-vertex sideways displacement (GridResult.drift): the foam's noises are taken where the water
# came from, so its patterns ride the waves with the water, not the waves under them
DRIFT_ATTRIBUTE = "projgrid_drift"
FOAM_ATTRIBUTE = "projgrid_foam"  # per-vertex foam in [0, 1], written while foam is on
RESIDUAL_ATTRIBUTE = "projgrid_foam_residual"  # and the residual foam's (residual_foam.py)
# Per-vertex caustic shadow transparency minus the flat water's, written while caustics are on
# (absent, the attribute reads 0: the flat water's shadow).
CAUSTIC_ATTRIBUTE = "projgrid_caustics"
# The node joining a branch to the water, and the effects that need it; muted while none is on.
EFFECT_NODES = {"Foam": ("foam", "contact_foam", "wakes"), "Refraction": ("refraction",)}
BODY_NODES = {"Godrays": ("godrays",)}
HAZE = "Haze"  # the Mix Shader toward the air's light (aerial perspective)
LAYER_IMAGE = "Projected Grid Slopes"  # and the band's number: a material's own images


def node_group():
    """Our node group, built if missing or of another version (a missing one appended from
    this session's first build: built.py)."""
    group = bpy.data.node_groups.get((GROUP, None))  # a local one: never a library's
    if group is not None and group.get(TAG) == VERSION:
        return group
    if group is None or group.get(TAG) is None:  # never take over a user's
        group = built.appended(GROUP, VERSION, TAG)
        if group is not None:
            return group
        group = bpy.data.node_groups.new(GROUP, "ShaderNodeTree")
    else:
        group.nodes.clear()
        group.interface.clear()
    group[TAG] = VERSION
    _build(group)
    built.keep(group, GROUP, VERSION)
    return group


def _build(group):
    for name, kind, default in INPUTS:
        socket = group.interface.new_socket(name, in_out="INPUT", socket_type=kind)
        socket.default_value = default
    group.interface.new_socket("Shader", in_out="OUTPUT", socket_type="NodeSocketShader")
    group.interface.new_socket("Fresnel", in_out="OUTPUT", socket_type="NodeSocketFloat")

    g = Graph(group)
    sockets = g.node("NodeGroupInput").outputs
    i = {name: (g.value(sockets[name]) if kind == "NodeSocketFloat" else sockets[name])
         for name, kind, _ in INPUTS}
    out = g.node("NodeGroupOutput")
    geo = g.node("ShaderNodeNewGeometry").outputs
    backfacing = g.value(geo["Backfacing"])
    lod = g.value(g.node("ShaderNodeAttribute", attribute_name=LOD_ATTRIBUTE).outputs["Fac"])

    # The shortest wave a pixel shows here, against the mean sea plane.
    distance = g.value(g.node("ShaderNodeCameraData").outputs["View Distance"])
    footprint, log_cos = model.footprint(
        g, i, distance, g.value(g.node("ShaderNodeSeparateXYZ", {0: geo["Incoming"]}).outputs["Z"]))

    position = g.node("ShaderNodeSeparateXYZ", {0: geo["Position"]}).outputs

    def on_water(x, y, time):
        """A noise's coordinates: across the water and in its time. Each noise is a 3D one, the
        third axis its time (the noise scales it as the position): a 4D one costs about twice
        as much per pixel (docs/design.md, measurements), and the water's height would only
        shift its pattern."""
        return g.node("ShaderNodeCombineXYZ", {"X": x, "Y": y, "Z": time}).outputs[0]

    def drawn_noise(time, scale, octaves, roughness, height, top_log):
        """A fractal noise bump keeping only the waves a pixel shows here
        (model.octaves_drawn): (strength, distance, height) for a Bump node."""
        detail, kept, strength = model.octaves_drawn(g, top_log, footprint, octaves, roughness)
        fac = g.node("ShaderNodeTexNoise", {
            "Vector": on_water(position["X"], position["Y"], time), "Scale": scale,
            "Detail": detail, "Roughness": roughness}, noise_dimensions="3D").outputs["Fac"]
        return strength, height * kept, fac

    # The slope layer: each band's slopes by its gain (model.layer_gain), tilting the
    # geometry's normal (from below, its flipped one the other way).
    slope = None
    for b in range(1, LAYER_BANDS + 1):
        gain = model.layer_gain(g, lod, i[f"Layer Level {b}"], i[f"Layer Top Log {b}"],
                                i[f"Layer Bottom Log {b}"], footprint)
        term = g.vector("SCALE", i[f"Layer Slopes {b}"], Scale=gain)
        slope = term if slope is None else g.vector("ADD", slope, term)
    up = g.value(g.node("ShaderNodeSeparateXYZ", {0: geo["Normal"]}).outputs["Z"])
    tilt = g.vector("MULTIPLY", slope, g.node("ShaderNodeCombineXYZ", {
        "X": -up, "Y": -up}).outputs[0])

    # Left-out octaves above the layer as bump detail: full where the vertices carry none of
    # the first shader octave (lod <= first), none where they carry it whole; and only as far
    # as a pixel shows them.
    lod_fade = g.clamp(i["Detail First Octave"] + 1.0 - lod)
    strength, height, fac = drawn_noise(i["Detail Time"], i["Detail Scale"],
                                        i["Detail Octaves"], i["Detail Roughness"],
                                        i["Detail Height"], i["Detail Top Log"])
    normal = g.node("ShaderNodeBump", {"Strength": lod_fade * strength,
                                       "Distance": height, "Height": fac}).outputs["Normal"]
    # Gusts (model.gust): the ripples' slope variance times the gusts' factor, their noise
    # drifting with the wind.
    gust_noise = g.node("ShaderNodeTexNoise", {
        "Vector": on_water(g.value(position["X"]) - i["Gust Drift X"],
                           g.value(position["Y"]) - i["Gust Drift Y"],
                           i["Gust Path"] * GUST_EVOLVE), "Scale": GUST_SCALE,
        "Detail": GUST_DETAIL, "Roughness": 0.5}, noise_dimensions="3D").outputs["Fac"]
    gust = model.gust(g, i, g.value(gust_noise), footprint)
    # Ripples shorter than any wave the sea synthesises, as far as a pixel shows them.
    strength, height, fac = drawn_noise(i["Ripple Time"], i["Ripple Scale"],
                                        i["Ripple Octaves"], 0.5,
                                        i["Ripple Height"] * g.sqrt(gust), i["Ripple Top Log"])
    normal = g.node("ShaderNodeBump", {"Strength": strength, "Distance": height, "Height": fac,
                                       "Normal": normal}).outputs["Normal"]
    # The layer tilts the bumped normal after the bumps: a Bump node fed a normal sampled from
    # an image hangs EEVEE's renders of more than one sample (5.2, on the CPU).
    normal = g.vector("NORMALIZE", g.vector("ADD", normal, tilt))
    ripples = model.ripples_undrawn(g, i, gust, footprint)
    slopes = model.roughness(g, i, lod, footprint, ripples)

    # Fresnel: exact from under water, Bruneton's mean over the slopes from above.
    c = g.abs(g.vector("DOT_PRODUCT", normal, geo["Incoming"]))
    exact = model.fresnel(g, i["IOR"], c, backfacing)
    fresnel = model.mean_fresnel(g, exact, c, slopes, backfacing)

    # The sky and the sun reflected by microfacets of that slope variance: a GGX lobe of
    # alpha = sigma (alpha = Roughness^2), whose sun lamp highlight is the glint: sparkles on
    # the facets near the camera, a widening path toward the horizon.
    facet_tilt, facets = glint_facets(g, i, geo, normal, footprint, log_cos, ripples)
    facet_normal = g.vector("NORMALIZE", g.vector("ADD", normal, facet_tilt))
    reflection = g.node("ShaderNodeBsdfGlossy", {
        "Color": (1.0, 1.0, 1.0, 1.0), "Roughness": g.pow(g.max(slopes - facets, 0.0), 0.25),
        "Normal": facet_normal})
    # Refraction: the water colour seen from above, or with refraction on what lies below
    # through the water body; from below (back faces) the sky through Snell's window (the BSDF
    # inverts the IOR on back faces itself).
    # The light the water scatters back up is lit (a night sea is dark): diffuse, of the
    # albedo that gives back Water Colour in DAYLIGHT, on the waves' normal, so faces turned
    # from the sun take less of it and go slate (brighter where a fresh breaker's bubbles
    # are: below, with the foam).
    albedo = g.vector("MINIMUM", g.vector("MULTIPLY", i["Water Colour"], tuple(
        math.pi / e for e in DAYLIGHT)), (1.0, 1.0, 1.0))  # no more light than it receives
    colour = g.node("ShaderNodeBsdfDiffuse", {"Color": albedo, "Normal": normal})
    body = g.node("ShaderNodeMixShader", {0: model.body_seen(g, i, distance),
                                          1: colour.outputs[0],
                                          2: g.node("ShaderNodeBsdfTransparent").outputs[0]})
    body.name = "Refraction"
    window = g.node("ShaderNodeBsdfRefraction", {"Color": (1.0, 1.0, 1.0, 1.0),
                                                  "Roughness": 0.0, "IOR": i["IOR"],
                                                  "Normal": normal})
    refraction = g.node("ShaderNodeMixShader", {0: backfacing, 1: body.outputs[0],
                                                2: window.outputs[0]})
    result = g.node("ShaderNodeMixShader", {0: fresnel, 1: refraction.outputs[0],
                                            2: reflection.outputs[0]})
    # Foam (Jensen and Golias; Monahan and Lu's stages; model.foam_cover): a rough white
    # cover where the crests carry it, the active whitecaps drawn by the top ranks of a grain
    # noise, their young residual foam as the lace of a noise the wind draws out, the aged
    # foam as streaks of its top ranks, the wind's blown streaks as a fourth's ridges.
    cos_w, sin_w = g.cos(i["Wind Direction"]), g.sin(i["Wind Direction"])
    stretch = g.sqrt(i["Foam Streak"])
    fibre = g.sqrt(stretch)  # the film's web drawn out half as much (in log) as its streaks
    water = g.vector("SUBTRACT", geo["Position"], g.node(
        "ShaderNodeAttribute", attribute_name=DRIFT_ATTRIBUTE).outputs["Vector"])

    def noise(scale, along, across, churn, offset, warp=None):
        """A foam noise `along` and `across` the wind per metre (of `scale` features a metre),
        pushed `warp` m across it; its time `offset` apart from the others' (decorrelated)."""
        y = g.vector("DOT_PRODUCT", water, g.node("ShaderNodeCombineXYZ", {
            "X": sin_w * -across, "Y": cos_w * across}).outputs[0])
        if warp is not None:
            y = y + warp * across
        w = i["Detail Time"] * (churn / scale)
        if offset:
            w = w + offset / scale
        x = g.vector("DOT_PRODUCT", water, g.node("ShaderNodeCombineXYZ", {
            "X": cos_w * along, "Y": sin_w * along}).outputs[0])
        return g.value(g.node("ShaderNodeTexNoise", {
            "Vector": on_water(x, y, w), "Scale": scale, "Detail": FOAM_DETAIL,
            "Roughness": FOAM_ROUGHNESS}, noise_dimensions="3D").outputs["Fac"])
    active, residual = (g.value(g.node("ShaderNodeAttribute", attribute_name=name)
                                .outputs["Fac"]) for name in (FOAM_ATTRIBUTE, RESIDUAL_ATTRIBUTE))
    grain = noise(FOAM_GRAIN, 1.0, FOAM_STREAK, FOAM_CHURN, 0.0)
    warp = (grain - 0.5) * (FOAM_WARP / FOAM_GRAIN_STD)
    foam, brightness, plume = model.foam_cover(
        g, i, active, residual, grain, noise(FOAM_LACE, 1.0, 1.0, FOAM_LACE_CHURN, 7.0),
        noise(FOAM_NET, 1.0, 1.0, FOAM_LACE_CHURN, 28.0),
        noise(FOAM_AGED, 1.0 / stretch, stretch, FOAM_LACE_CHURN, 14.0, warp),
        noise(FOAM_BLOWN, 1.0 / stretch, stretch, FOAM_LACE_CHURN, 21.0, warp),
        noise(FILM_WEB, 1.0 / fibre, fibre, FOAM_LACE_CHURN, 35.0), footprint, log_cos)
    # The bubble plume under a fresh breaker lights the water body turquoise.
    channels = g.node("ShaderNodeSeparateXYZ", {0: albedo})
    water_rgb = [g.value(channels.outputs[k]) for k in "XYZ"]
    brightest = g.max(g.max(water_rgb[0], water_rgb[1]), water_rgb[2])
    bubbles = g.node("ShaderNodeCombineXYZ", {
        k: model.bubble_albedo(g, c, brightest) for k, c in zip("XYZ", water_rgb, strict=True)})
    g.set(colour.inputs["Color"], g.vector("ADD", albedo, g.vector(
        "SCALE", g.vector("SUBTRACT", bubbles.outputs[0], albedo), Scale=plume)))
    # Foam scatters like the white of its bubbles, its films' sheen included (FOAM_SHEEN, to
    # white at most): one diffuse closure on the water body's normal, so the picture is linear
    # in the foam's share (EEVEE merges closures of one kind).
    cover = g.node("ShaderNodeBsdfDiffuse", {
        "Color": g.vector("SCALE", g.vector("MINIMUM", g.vector(
            "ADD", i["Foam Colour"], (FOAM_SHEEN,) * 3), (1.0, 1.0, 1.0)), Scale=brightness),
        "Normal": normal})
    with_foam = g.node("ShaderNodeMixShader", {0: foam, 1: result.outputs[0],
                                               2: cover.outputs[0]})
    with_foam.name = "Foam"
    # Aerial perspective (daylight.haze): from above, the far water's light gives way to the
    # air's, the sky's in the view's direction mirrored up (sky.horizon).
    hazed = sky.through_air(g, with_foam.outputs[0], i["Haze"], i["Overcast"], distance,
                            geo["Incoming"], 1.0 - backfacing)
    hazed.name = HAZE
    g.set(out.inputs["Shader"], hazed.outputs[0])
    g.set(out.inputs["Fresnel"], fresnel)
