"""The EEVEE node group "Projected Grid Water" (thesis §3.4, App. B) and our water material.

    colour = lerp(refraction, reflection of the sky and the sun, F)               (§3.4.8)

The octaves the geometry left out (GridResult.shader_octaves) come back as bump detail, faded in
where the vertices' band limit (the per-vertex `projgrid_lod` attribute) dropped them (§3.1.3),
and the ripples below the last band as a second bump. Waves shorter than a pixel shows become
the roughness of the reflection (Bruneton, Neyret and Holzschuch 2010; shading.Filtering): each
bump is drawn as far as a pixel shows its waves, and the slope variance of the rest is the GGX
lobe's, so the sky's reflection blurs and the sun lamp's highlight widens into a glitter path
with distance, and nothing flickers as detail finer than a pixel would. Near the camera the
ripples' undrawn slopes are the glint's facets instead (shading.facet_variance), each with its
own normal, so the sun sparkles on them as on the sea. F is, from above, the
mean Fresnel over those slopes (Bruneton's fit), which keeps a rough far sea darker than the sky
at the horizon; from under water the exact unpolarised reflectance (Eq. 1.4) for IOR 1.333, in
the form Blender's Fresnel node uses (total internal reflection when g^2 < 0). The sky is the
world, or with local reflections our sphere probe's capture; the refraction is the light the water
scatters back up, lit by the scene (from below, the sky through Snell's window).

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

The tree is built top to bottom as the shading model reads (detail, filtering, Fresnel,
reflection, refraction, foam); the materials that use it are materials.py's.
"""

import math

import bpy

from ..projgrid_addon.look import (
    DAYLIGHT,
    FOAM_CHURN,
    FOAM_COLOUR,
    FOAM_DETAIL,
    FOAM_EDGE,
    FOAM_GRAIN,
    FOAM_GRAIN_STD,
    FOAM_RANK,
    FOAM_ROUGHNESS,
    FOAM_STREAK,
    GUST_DETAIL,
    GUST_EVOLVE,
    GUST_FAC_STD,
    GUST_SCALE,
    WATER_COLOUR,
    WHITECAP,
)
from .glint import glint_facets
from .nodes import TAG, Graph

E, LN2 = math.e, math.log(2.0)

GROUP = "Projected Grid Water"
MATERIAL = "Projected Grid Water"
BODY_MATERIAL = "Projected Grid Water Body"
SHADOW_MATERIAL = "Projected Grid Water Shadow"
CAUSTIC_IMAGE = "Projected Grid Caustics"  # the godrays' caustic tile (optics.caustic_tile)
VERSION = 23  # stored in the TAG property; a group or material of another version is rebuilt
LOD_ATTRIBUTE = "projgrid_lod"  # per-vertex band limit, written by the bridge
GUST_DRIFT = ("Gust Drift X", "Gust Drift Y", "Gust Path")  # the inputs the drift drives
FOAM_ATTRIBUTE = "projgrid_foam"  # per-vertex foam in [0, 1], written while foam is on
# Per-vertex caustic shadow transparency minus the flat water's, written while caustics are on
# (absent, the attribute reads 0: the flat water's shadow).
CAUSTIC_ATTRIBUTE = "projgrid_caustics"
# The node joining a branch to the water, and the effects that need it; muted while none is on.
EFFECT_NODES = {"Foam": ("foam", "contact_foam"), "Refraction": ("refraction",)}
BODY_NODES = {"Godrays": ("godrays",)}
INPUTS = (  # name, socket type, default; all but IOR are written by the frame handler
    ("Water Colour", "NodeSocketColor", (*WATER_COLOUR, 1.0)),
    ("Foam Colour", "NodeSocketColor", (*FOAM_COLOUR, 1.0)),
    ("IOR", "NodeSocketFloat", 1.333),
    ("Detail Scale", "NodeSocketFloat", 1.0),
    ("Detail Height", "NodeSocketFloat", 0.0),
    ("Detail Octaves", "NodeSocketFloat", 0.0),
    ("Detail Roughness", "NodeSocketFloat", 0.5),
    ("Detail Time", "NodeSocketFloat", 0.0),
    ("Detail First Octave", "NodeSocketFloat", 0.0),
    ("Detail Top Log", "NodeSocketFloat", 0.0),
    ("Ripple Scale", "NodeSocketFloat", 1.0),
    ("Ripple Height", "NodeSocketFloat", 0.0),
    ("Ripple Octaves", "NodeSocketFloat", 0.0),
    ("Ripple Time", "NodeSocketFloat", 0.0),
    # m the gusts have drifted with the wind (shading.wind_run): GUST_DRIFT
    ("Gust Drift X", "NodeSocketFloat", 0.0),
    ("Gust Drift Y", "NodeSocketFloat", 0.0),
    ("Gust Path", "NodeSocketFloat", 0.0),
    ("Gust Amplitude", "NodeSocketFloat", 0.0),  # shading.Filtering.gust
    ("Gust Norm", "NodeSocketFloat", 1.0),  # shading.Filtering.gust_norm
    ("Wind Direction", "NodeSocketFloat", 0.0),  # radians, counter-clockwise from +X
    ("Foam Coverage", "NodeSocketFloat", 0.0),  # the share of the sea whitecaps cover
    # The filtering of the waves too short to draw into roughness (shading.Filtering).
    ("Pixel Log", "NodeSocketFloat", -6.0),
    ("Cos Floor", "NodeSocketFloat", 0.1),
    ("Distance Power", "NodeSocketFloat", 1.0),
    ("Slope Floor", "NodeSocketFloat", 0.0),
    ("Ripple Slopes", "NodeSocketFloat", 0.0),
    ("Slope Density", "NodeSocketFloat", 0.0),
    ("Shortest Log", "NodeSocketFloat", -3.5),
    ("Ripple Top Log", "NodeSocketFloat", -1.4),
    ("Slope Ceiling", "NodeSocketFloat", 0.0),
    ("Left Out Log", "NodeSocketFloat", -100.0),
    # The glint's facets (shading.facet_variance): ln of their size, of the facets a pixel
    # holds while it sparkles fully, and of those from which it shows the mean lobe.
    ("Facet Log", "NodeSocketFloat", -4.17),
    ("Facets Sharp Log", "NodeSocketFloat", 1.386),
    ("Facets Mean Log", "NodeSocketFloat", 6.931),
    ("Sun Reach", "NodeSocketFloat", 100.0),
    ("Sun Direction", "NodeSocketVector", (0.0, 0.0, 0.0)),  # toward the sun lamp; none: 0
    ("Layer Top Log", "NodeSocketFloat", -100.0),
    ("Layer Density", "NodeSocketFloat", 0.0),
    # The slope layer's bands (projgrid_addon/slope_layer.py): slopes from the material's
    # images, the band limit from which the vertices hold each, its waves' range (ln m).
    *((f"Layer Slopes {b}", "NodeSocketVector", (0.0, 0.0, 0.0)) for b in (1, 2, 3)),
    *((f"Layer Level {b}", "NodeSocketFloat", -100.0) for b in (1, 2, 3)),
    *((f"Layer Top Log {b}", "NodeSocketFloat", 0.0) for b in (1, 2, 3)),
    *((f"Layer Bottom Log {b}", "NodeSocketFloat", -1.0) for b in (1, 2, 3)),
)
DEFAULTS = {name: default for name, _, default in INPUTS}
LAYER_BANDS = 3
LAYER_IMAGE = "Projected Grid Slopes"  # and the band's number: a material's own images


def node_group():
    """Our node group, built if missing or of another version."""
    group = bpy.data.node_groups.get((GROUP, None))  # a local one: never a library's
    if group is not None and group.get(TAG) == VERSION:
        return group
    if group is None or group.get(TAG) is None:
        group = bpy.data.node_groups.new(GROUP, "ShaderNodeTree")  # never take over a user's
    else:
        group.nodes.clear()
        group.interface.clear()
    group[TAG] = VERSION
    _build(group)
    return group


def _build(group):
    for name, kind, default in INPUTS:
        socket = group.interface.new_socket(name, in_out="INPUT", socket_type=kind)
        socket.default_value = default
    group.interface.new_socket("Shader", in_out="OUTPUT", socket_type="NodeSocketShader")
    group.interface.new_socket("Fresnel", in_out="OUTPUT", socket_type="NodeSocketFloat")

    g = Graph(group)
    i = g.node("NodeGroupInput").outputs
    out = g.node("NodeGroupOutput")
    geo = g.node("ShaderNodeNewGeometry").outputs
    lod = g.node("ShaderNodeAttribute", attribute_name=LOD_ATTRIBUTE).outputs["Fac"]

    # The shortest wave a pixel shows here (shading.Filtering): PIXELS pixels' footprint at the
    # view distance, stretched where the water is seen at a grazing angle.
    distance = g.math("MAXIMUM", g.node("ShaderNodeCameraData").outputs["View Distance"], 1e-6)
    # Against the mean sea plane, not the waves' faces (those facing the camera would stay
    # sharp and those facing away go milky), and at most shading.GRAZING times.
    log_cos = g.math("LOGARITHM", g.math("MAXIMUM", g.math("ABSOLUTE", g.node(
        "ShaderNodeSeparateXYZ", {0: geo["Incoming"]}).outputs["Z"]), i["Cos Floor"]), E)
    footprint = g.math("SUBTRACT", g.math("MULTIPLY_ADD", i["Distance Power"],
                                          g.math("LOGARITHM", distance, E), i["Pixel Log"]),
                       log_cos)

    def undrawn(top, bottom):  # shading.undrawn_share
        return g.math("DIVIDE", g.math("SUBTRACT", footprint, bottom),
                      g.math("MAXIMUM", g.math("SUBTRACT", top, bottom), 1e-6), clamp=True)

    def drawn_noise(vector, time, scale, octaves, roughness, height, top_log):
        """A fractal noise bump of `octaves` octaves past its first (wavelength e^top_log,
        halving), keeping only the waves a pixel shows here: the noise's Detail is cut per
        pixel (finer octaves would alias and flicker; their slopes are the roughness, counted
        the same way: shading.undrawn_share), its height kept per octave (Blender normalises
        the fractal by its octaves' amplitude sum), and the first octave's slope variance fades
        with the footprint across its band. (strength, distance, height) for a Bump node."""
        # Octave j holds the waves from top / 2^j down to top / 2^(j+1): whole while
        # log2(top / L_p) >= j + 1.
        shown = g.math("DIVIDE", g.math("SUBTRACT", top_log, footprint), LN2)  # log2(top / L_p)
        detail = g.math("MINIMUM", g.math("MAXIMUM", g.math("SUBTRACT", shown, 1.0), 0.0),
                        octaves)
        fac = g.node("ShaderNodeTexNoise", {"Vector": vector, "W": time, "Scale": scale,
                                            "Detail": detail, "Roughness": roughness},
                     noise_dimensions="4D").outputs["Fac"]
        r = g.math("MINIMUM", roughness, 0.999)  # (1 - r^(n+1)) / (1 - r): n + 1 at r = 1
        kept = g.math("DIVIDE", g.math("SUBTRACT", 1.0, g.math("POWER", r, g.math(
            "ADD", detail, 1.0))), g.math("MAXIMUM", g.math("SUBTRACT", 1.0, g.math(
                "POWER", r, g.math("ADD", octaves, 1.0))), 1e-6))
        strength = g.math("SQRT", g.math("MAXIMUM", g.math("MINIMUM", shown, 1.0), 0.0))
        return strength, g.math("MULTIPLY", height, kept), fac

    # The slope layer: each band's slopes by sqrt(1 - g^2), g the share the vertices hold
    # (their tiles are independent of the layer's, so the variances add), times the root of
    # the share of its slopes in waves a pixel shows (shading.layer_gain), tilting the
    # geometry's normal (from below, its flipped one the other way).
    slope = None
    for b in range(1, LAYER_BANDS + 1):
        held = g.math("SUBTRACT", lod, i[f"Layer Level {b}"], clamp=True)
        top, bottom = i[f"Layer Top Log {b}"], i[f"Layer Bottom Log {b}"]
        shown = g.math("DIVIDE", g.math("SUBTRACT", top, footprint),
                       g.math("MAXIMUM", g.math("SUBTRACT", top, bottom), 1e-6), clamp=True)
        gain = g.math("SQRT", g.math("MULTIPLY", g.math("MAXIMUM", g.math(
            "MULTIPLY_ADD", held, g.math("MULTIPLY", held, -1.0), 1.0), 0.0), shown))
        term = g.vector("SCALE", i[f"Layer Slopes {b}"], Scale=gain)
        slope = term if slope is None else g.vector("ADD", slope, term)
    up = g.node("ShaderNodeSeparateXYZ", {0: geo["Normal"]}).outputs["Z"]
    tilt = g.vector("MULTIPLY", slope, g.node("ShaderNodeCombineXYZ", {
        "X": g.math("MULTIPLY", up, -1.0), "Y": g.math("MULTIPLY", up, -1.0)}).outputs[0])

    # Left-out octaves above the layer as bump detail: full where the vertices carry none of
    # the first shader octave (lod <= first), none where they carry it whole; and only as far
    # as a pixel shows them.
    lod_fade = g.math("SUBTRACT", g.math("ADD", i["Detail First Octave"], 1.0), lod, clamp=True)
    strength, height, fac = drawn_noise(geo["Position"], i["Detail Time"], i["Detail Scale"],
                                        i["Detail Octaves"], i["Detail Roughness"],
                                        i["Detail Height"], i["Detail Top Log"])
    normal = g.node("ShaderNodeBump", {"Strength": g.math("MULTIPLY", lod_fade, strength),
                                       "Distance": height, "Height": fac}).outputs["Normal"]
    # Gusts: the ripples' slope variance times the gusts' factor (GUST_SCALE above), faded
    # out where a pixel's footprint nears a patch (as drawn_noise fades an octave: a patch that
    # no pixel shows would only shimmer), so far away the ripples' mean (shading.gust).
    drift = g.node("ShaderNodeCombineXYZ", {"X": i["Gust Drift X"],
                                            "Y": i["Gust Drift Y"]}).outputs[0]
    gust_noise = g.node("ShaderNodeTexNoise", {
        "Vector": g.vector("SUBTRACT", geo["Position"], drift),
        "W": g.math("MULTIPLY", i["Gust Path"], GUST_EVOLVE), "Scale": GUST_SCALE,
        "Detail": GUST_DETAIL, "Roughness": 0.5}, noise_dimensions="4D").outputs["Fac"]
    gust_shown = g.math("SUBTRACT", g.math("DIVIDE", g.math(
        "SUBTRACT", -math.log(GUST_SCALE), footprint), LN2), 1.0, clamp=True)
    local = g.math("MULTIPLY", g.math("MAXIMUM", g.math("MULTIPLY_ADD", g.math(
        "SUBTRACT", gust_noise, 0.5), g.math("DIVIDE", i["Gust Amplitude"], GUST_FAC_STD),
        1.0), 0.0), i["Gust Norm"])
    gust = g.math("MULTIPLY_ADD", gust_shown, g.math("SUBTRACT", local, 1.0), 1.0)
    # Ripples shorter than any wave the sea synthesises, as far as a pixel shows them.
    strength, height, fac = drawn_noise(geo["Position"], i["Ripple Time"], i["Ripple Scale"],
                                        i["Ripple Octaves"], 0.5, g.math(
                                            "MULTIPLY", i["Ripple Height"], g.math("SQRT", gust)),
                                        i["Ripple Top Log"])
    normal = g.node("ShaderNodeBump", {"Strength": strength, "Distance": height, "Height": fac,
                                       "Normal": normal}).outputs["Normal"]
    # The layer tilts the bumped normal after the bumps: a Bump node fed a normal sampled from
    # an image hangs EEVEE's renders of more than one sample (5.2, on the CPU).
    normal = g.vector("NORMALIZE", g.vector("ADD", normal, tilt))
    undrawn_ripples = g.math("MULTIPLY", g.math("MULTIPLY", i["Ripple Slopes"], gust),
                             undrawn(i["Ripple Top Log"], i["Shortest Log"]))

    # The slope variance of the waves not drawn here: the microfacets' roughness
    # (shading.Filtering). Above the ripples, those shorter than the footprint; above the
    # slope layer also those shorter than the geometry holds at the vertices' band limit
    # (ln L_g = Left Out Log - lod ln 2).
    held = g.math("MULTIPLY_ADD", lod, -LN2, i["Left Out Log"])
    layer_top = g.math("MAXIMUM", i["Layer Top Log"], i["Ripple Top Log"])
    below = g.math("MINIMUM", g.math("MAXIMUM", g.math(
        "SUBTRACT", footprint, i["Ripple Top Log"]), 0.0), g.math(
        "SUBTRACT", layer_top, i["Ripple Top Log"]))
    above = g.math("MAXIMUM", g.math("SUBTRACT", g.math("MAXIMUM", footprint, held),
                                     layer_top), 0.0)
    slopes = g.math("MINIMUM", g.math("MULTIPLY_ADD", i["Layer Density"], above, g.math(
        "MULTIPLY_ADD", i["Slope Density"], below, g.math(
            "ADD", undrawn_ripples, i["Slope Floor"]))),
        i["Slope Ceiling"])

    # Exact Fresnel (Eq. 1.4), as Blender's fresnel_dielectric_cos: seen from under water.
    c = g.math("ABSOLUTE", g.vector("DOT_PRODUCT", normal, geo["Incoming"]))
    eta = g.mix(geo["Backfacing"], i["IOR"], g.math("DIVIDE", 1.0, i["IOR"]))
    g2 = g.math("MULTIPLY_ADD", c, c, g.math("MULTIPLY_ADD", eta, eta, -1.0))
    gg = g.math("SQRT", g.math("MAXIMUM", g2, 0.0))
    a = g.math("DIVIDE", g.math("SUBTRACT", gg, c), g.math("ADD", gg, c))
    b = g.math("DIVIDE",
               g.math("MULTIPLY_ADD", c, g.math("ADD", gg, c), -1.0),
               g.math("MULTIPLY_ADD", c, g.math("SUBTRACT", gg, c), 1.0))
    fresnel = g.math("MULTIPLY", g.math("MULTIPLY", g.math("MULTIPLY", a, a), 0.5),
                     g.math("MULTIPLY_ADD", b, b, 1.0))
    fresnel = g.mix(g.math("LESS_THAN", g2, 0.0), fresnel, 1.0)  # total internal reflection
    # From above, less by what the facets' slopes take from it: Bruneton's fit of the mean
    # Fresnel (2010, Eq. 11), 0.02 + 0.98 (1 - cos)^(5 exp(-2.69 s)) / (1 + 22.7 s^1.5), s the
    # slope deviation along the view, less its value for a mirror (Schlick's), so a mirror
    # keeps the exact reflectance and a rough far sea reflects less of the sky at grazing.
    sigma = g.math("SQRT", g.math("MULTIPLY", slopes, 0.5))
    facing = g.math("MAXIMUM", g.math("SUBTRACT", 1.0, c), 0.0)
    mean = g.math("DIVIDE", g.math("POWER", facing, g.math("MULTIPLY", g.math("EXPONENT", g.math(
        "MULTIPLY", sigma, -2.69)), 5.0)),
                  g.math("MULTIPLY_ADD", g.math("POWER", sigma, 1.5), 22.7, 1.0))
    rough = g.math("MAXIMUM", g.math("MULTIPLY_ADD", g.math(
        "SUBTRACT", mean, g.math("POWER", facing, 5.0)), 0.98, fresnel), 0.0)
    fresnel = g.mix(geo["Backfacing"], rough, fresnel)

    # The sky and the sun reflected by microfacets of that slope variance: a GGX lobe of
    # alpha = sigma (alpha = Roughness^2), whose sun lamp highlight is the glint: sparkles on
    # the facets near the camera, a widening path toward the horizon.
    facet_slopes = glint_facets(g, i, geo, normal, footprint, log_cos, undrawn_ripples)
    facet_normal = g.vector("NORMALIZE", g.vector("ADD", normal, facet_slopes[0]))
    sky = g.node("ShaderNodeBsdfGlossy", {"Color": (1.0, 1.0, 1.0, 1.0), "Roughness": g.math(
        "POWER", g.math("MAXIMUM", g.math("SUBTRACT", slopes, facet_slopes[1]), 0.0), 0.25),
                                          "Normal": facet_normal})
    reflection = sky
    # Refraction: the water colour seen from above, or with refraction on what lies below
    # through the water body; from below (back faces) the sky through Snell's window (the BSDF
    # inverts the IOR on back faces itself).
    # The light the water scatters back up is lit (a night sea is dark): diffuse, of the
    # albedo that gives back Water Colour in DAYLIGHT, on the waves' normal, so faces turned
    # from the sun take less of it and go slate.
    albedo = g.vector("MINIMUM", g.vector("MULTIPLY", i["Water Colour"], tuple(
        math.pi / e for e in DAYLIGHT)), (1.0, 1.0, 1.0))  # no more light than it receives
    colour = g.node("ShaderNodeBsdfDiffuse", {"Color": albedo, "Normal": normal})
    body = g.node("ShaderNodeMixShader", {0: 1.0, 1: colour.outputs[0],
                                          2: g.node("ShaderNodeBsdfTransparent").outputs[0]})
    body.name = "Refraction"
    window = g.node("ShaderNodeBsdfRefraction", {"Color": (1.0, 1.0, 1.0, 1.0),
                                                  "Roughness": 0.0, "IOR": i["IOR"],
                                                  "Normal": normal})
    refraction = g.node("ShaderNodeMixShader", {0: geo["Backfacing"], 1: body.outputs[0],
                                                2: window.outputs[0]})
    result = g.node("ShaderNodeMixShader", {0: fresnel, 1: refraction.outputs[0],
                                            2: reflection.outputs[0]})
    # Foam (Jensen and Golias): a rough white cover where the crests carry it. The per-vertex
    # foam f is a share to cover, not an opacity: a point is foam where the rank of a grain
    # noise (its Fac through the noise's own CDF, FOAM_RANK, so nearly uniform in [0, 1]) is
    # above 1 - f. So a whitecap is a solid core whose edge breaks
    # into bubbles and streaks, not the round blob the vertices interpolate, and the covered
    # share stays the calibrated one. The noise is FOAM_STREAK times finer across the wind than
    # along it: the wind draws foam out into streaks.
    foam = g.node("ShaderNodeAttribute", attribute_name=FOAM_ATTRIBUTE).outputs["Fac"]
    wind = g.node("ShaderNodeCombineXYZ", {"X": g.math("COSINE", i["Wind Direction"]),
                                           "Y": g.math("SINE", i["Wind Direction"])}).outputs[0]
    across = g.node("ShaderNodeCombineXYZ", {"X": g.math("MULTIPLY", g.math(
        "SINE", i["Wind Direction"]), -FOAM_STREAK), "Y": g.math("MULTIPLY", g.math(
            "COSINE", i["Wind Direction"]), FOAM_STREAK)}).outputs[0]
    streaked = g.node("ShaderNodeCombineXYZ", {
        "X": g.vector("DOT_PRODUCT", geo["Position"], wind),
        "Y": g.vector("DOT_PRODUCT", geo["Position"], across)}).outputs[0]
    churn = g.math("MULTIPLY", i["Detail Time"], FOAM_CHURN / FOAM_GRAIN)
    grain = g.node("ShaderNodeTexNoise", {"Vector": streaked, "W": churn, "Scale": FOAM_GRAIN,
                                          "Detail": FOAM_DETAIL, "Roughness": FOAM_ROUGHNESS},
                   noise_dimensions="4D")
    # shading.grain_cover, with the noise's own CDF (FOAM_RANK).
    z = g.math("DIVIDE", g.math("SUBTRACT", grain.outputs["Fac"], 0.5), FOAM_GRAIN_STD)
    rank = g.math("DIVIDE", 1.0, g.math("ADD", 1.0, g.math("POWER", E, g.math(
        "MULTIPLY", z, g.math("MULTIPLY_ADD", g.math("MULTIPLY", z, z), -FOAM_RANK[1],
                              -FOAM_RANK[0])))))
    # The share the grain draws: the vertex's, or where the pixel outgrows a whitecap along
    # the view the sea's mean cover (shading.foam_cover).
    whole = g.math("MULTIPLY", g.math("DIVIDE", g.math(
        "SUBTRACT", footprint, math.log(WHITECAP)), LN2, clamp=True), g.math(
        "GREATER_THAN", i["Foam Coverage"], 0.0))  # whitecaps called for (not contact foam alone)
    share = g.mix(whole, foam, i["Foam Coverage"])
    edge = g.math("MULTIPLY_ADD", g.math("MINIMUM", share, g.math("SUBTRACT", 1.0, share)),
                  FOAM_EDGE, 1e-4)
    bubbles = g.math("MULTIPLY", g.math("ADD", g.math("DIVIDE", g.math("ADD", g.math(
        "SUBTRACT", rank, 1.0), share), edge), 0.5, clamp=True),
        g.math("GREATER_THAN", share, 0.0))
    # The grain's patches while the pixel's area holds few of them: far whitecaps stay
    # specks, not a share spread thin over the crests; past that, the share itself.
    grain_shown = g.math("ADD", g.math("DIVIDE", g.math(
        "SUBTRACT", -math.log(FOAM_GRAIN * math.sqrt(FOAM_STREAK)),
        g.math("MULTIPLY_ADD", log_cos, 0.5, footprint)), LN2), 1.0, clamp=True)
    foam = g.mix(grain_shown, share, bubbles)
    # Foam scatters like the white of its bubbles and shines forward like their films: a
    # diffuse cover with a broad specular sheen, so it stays white in the sun's glitter path.
    cover = g.node("ShaderNodeAddShader", {
        0: g.node("ShaderNodeBsdfDiffuse", {"Color": i["Foam Colour"],
                                            "Normal": normal}).outputs[0],
        1: g.node("ShaderNodeBsdfGlossy", {"Color": (0.25, 0.25, 0.25, 1.0), "Roughness": 0.6,
                                           "Normal": normal}).outputs[0]})
    with_foam = g.node("ShaderNodeMixShader", {0: foam, 1: result.outputs[0],
                                               2: cover.outputs[0]})
    with_foam.name = "Foam"
    g.set(out.inputs["Shader"], with_foam.outputs[0])
    g.set(out.inputs["Fresnel"], fresnel)


