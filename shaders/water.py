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
(times the light on the sea against the daylight, effects.body_light), so that radiance after d
metres is e^(-a d) L + (1 - e^(-a d)) water colour (Eq. 14 and 17).

Over 300 lines on purpose: one node tree, built top to bottom as the shading model reads
(detail, filtering, Fresnel, reflection, refraction, foam), plus the versioned materials.
"""

import math
import zlib

import bpy
import numpy as np

from . import sky
from .nodes import TAG, Graph, assign, empty_tree, socket

E = 2.718281828459045  # the natural logarithm's base
LN2 = 0.6931471805599453

GROUP = "Projected Grid Water"
MATERIAL = "Projected Grid Water"
BODY_MATERIAL = "Projected Grid Water Body"
SHADOW_MATERIAL = "Projected Grid Water Shadow"
CAUSTIC_IMAGE = "Projected Grid Caustics"  # the godrays' caustic tile (effects.caustic_tile)
VERSION = 23  # stored in the TAG property; a group or material of another version is rebuilt
LOD_ATTRIBUTE = "projgrid_lod"  # per-vertex band limit, written by the bridge
# The foam's break-up noise, features per metre along the wind: a breaking crest's patches are
# metres long, so a pixel tens of metres away still shows them, not the mean share.
FOAM_GRAIN = 0.3
# How fast the grain churns, in the noise's own time coordinate per unit of Detail Time (the
# noise multiplies W by its Scale, so W is divided by FOAM_GRAIN).
FOAM_CHURN = 1.5
FOAM_DETAIL, FOAM_ROUGHNESS = 4.0, 0.65  # its fractal
# Its Fac's standard deviation about 0.5, and (a, b) of its CDF as 1 / (1 + e^-(a z + b z^3)),
# z in standard deviations: fitted to Blender's own noise over a period of its time
# coordinate (1.3 million samples; the fractal's Fac has lighter tails than a normal one's,
# and its spread varies by 4 % with the time), so the drawn cover is the share over time
# (tests/blender/test_sea.py); at a 2 % share it swings by a quarter as the grain evolves.
FOAM_GRAIN_STD = 0.0619
FOAM_RANK = (1.522, 0.0963)
# How soft a bubble's edge is, in the noise's ranks, per unit of the share (or of what it
# leaves uncovered): the ramp stays inside the ranks, so nothing is drawn at a share of
# nought, everything at one, and the mean is the share (shading.grain_cover).
FOAM_EDGE = 0.5
FOAM_STREAK = 4.0  # and this many times more across it
WHITECAP = 8.0  # m: a pixel this long (and longer) draws the sea's mean whitecap share
# Gusts (cat's paws): the wind's speed varies over the sea in patches that drift with it, and
# the ripples answer it within seconds. Their slope variance is scaled by max(1 + Gust
# Amplitude z, 0) times Gust Norm, z the local wind's departure in its standard deviations: a
# noise of GUST_SCALE features per metre (Detail GUST_DETAIL; its Fac's spread GUST_FAC_STD,
# measured over its time). The factor's mean over the sea is 1, so the sea's mean slope stays
# Cox and Munk's (test_sea.py).
GUST_SCALE, GUST_DETAIL, GUST_FAC_STD = 1.0 / 30.0, 1.0, 0.088
GUST_EVOLVE = 0.5  # the patches' change, in the noise's own time per patch size drifted
GUST_DRIFT = ("Gust Drift X", "Gust Drift Y", "Gust Path")  # the inputs the drift drives
FOAM_ATTRIBUTE = "projgrid_foam"  # per-vertex foam in [0, 1], written while foam is on
# Per-vertex caustic shadow transparency minus the flat water's, written while caustics are on
# (absent, the attribute reads 0: the flat water's shadow).
CAUSTIC_ATTRIBUTE = "projgrid_caustics"
# The node joining a branch to the water, and the effects that need it; muted while none is on.
EFFECT_NODES = {"Foam": ("foam", "contact_foam"), "Refraction": ("refraction",)}
BODY_NODES = {"Godrays": ("godrays",)}
GODRAY_DENSITY = 0.05  # scattering per metre where the caustic intensity is 1 (flat water)

WATER_COLOUR = (0.004, 0.016, 0.024)  # deep water seen from above (linear), in DAYLIGHT
# The irradiance (W/m^2 per channel, linear) Add Ocean's sky and sun (sky.py, the sun 12 deg up)
# put on the mean sea plane: the water scatters Water Colour back up under it, and under other
# light in proportion (tests/blender/test_water_tree.py integrates it).
DAYLIGHT = (1.2865, 1.7202, 2.7205)
# Of it, the sun lamp's (white).
DAYLIGHT_SUN = sky.SUN_STRENGTH * math.sin(math.radians(sky.SUN_ELEVATION))
FOAM_COLOUR = (0.7, 0.7, 0.7)  # the diffuse white of the foam's bubbles
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
# This session's layer images: {image session_uid: (owning material's session_uid, checksum
# of the tile written)}. Not saved: a reopened file's images are claimed and written anew.
_LAYER_WRITTEN = {}


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


def glint_facets(g, i, geo, normal, footprint, log_cos, undrawn):
    """(tilt, slope variance) of the glint's facets (shading.facet_variance): cells of Facet Log
    on the sea (a Voronoi's, reshuffling with the ripples' time so the glitter twinkles), each
    tilted by a normal slope of that variance per axis halved (Box-Muller from the cell's two
    random values), added to the normal before it is normalised; none on back faces, nor
    where no facet shows the sun (nor without a sun lamp: a Sun Direction of 0). `log_cos`:
    ln of the view's cos to the sea plane as the footprint takes it; `undrawn`: the ripples'
    undrawn slope variance."""
    cell = g.math("EXPONENT", i["Facet Log"])
    facets = g.math("MULTIPLY_ADD", g.math("SUBTRACT", footprint, i["Facet Log"]), 2.0,
                    log_cos)  # ln N
    weight = g.math("DIVIDE", g.math("SUBTRACT", i["Facets Mean Log"], facets), g.math(
        "SUBTRACT", i["Facets Mean Log"], i["Facets Sharp Log"]), clamp=True)
    front = g.math("SUBTRACT", 1.0, geo["Backfacing"])
    half = g.vector("NORMALIZE", g.vector("ADD", geo["Incoming"], i["Sun Direction"]))
    cos_half = g.math("MAXIMUM", g.vector("DOT_PRODUCT", normal, half), 0.01)
    tan2 = g.math("SUBTRACT", g.math("DIVIDE", 1.0, g.math("MULTIPLY", cos_half, cos_half)), 1.0)
    reach = g.math("SUBTRACT", 1.0, g.math("DIVIDE", tan2, g.math(
        "MULTIPLY_ADD", i["Sun Reach"], undrawn, 1e-9)), clamp=True)
    sun = g.math("MINIMUM", g.vector("LENGTH", i["Sun Direction"]), 1.0)
    variance = g.math("MULTIPLY", g.math("MULTIPLY", g.math("MULTIPLY", weight, front),
                                         g.math("MULTIPLY", reach, sun)), undrawn)
    xyz = g.node("ShaderNodeSeparateXYZ", {0: geo["Position"]}).outputs
    at = g.node("ShaderNodeCombineXYZ", {"X": xyz["X"], "Y": xyz["Y"],
                                         "Z": g.math("MULTIPLY", i["Ripple Time"], cell)})
    random = g.node("ShaderNodeSeparateColor", {0: g.node("ShaderNodeTexVoronoi", {
        "Vector": at.outputs[0], "Scale": g.math("DIVIDE", 1.0, cell)},
        voronoi_dimensions="3D").outputs["Color"]}).outputs
    spread = g.math("MULTIPLY", g.math("SQRT", g.math("MULTIPLY", g.math("LOGARITHM", g.math(
        "MAXIMUM", random[0], 1e-6), E), -2.0)), g.math("SQRT", g.math(
            "MULTIPLY", variance, 0.5)))
    angle = g.math("MULTIPLY", random[1], 2.0 * math.pi)
    tilt = g.node("ShaderNodeCombineXYZ", {
        "X": g.math("MULTIPLY", spread, g.math("COSINE", angle)),
        "Y": g.math("MULTIPLY", spread, g.math("SINE", angle))}).outputs[0]
    return tilt, variance


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


def _versioned_material(name):
    """(our material `name`, None) if it is of this VERSION; else (ours, emptied, or new if the
    name is free or a user's: never taken over) with a Graph to build it into."""
    mat = bpy.data.materials.get((name, None))
    if mat is not None and mat.get(TAG) == VERSION:
        return mat, None
    if mat is None or not mat.get(TAG):
        mat = bpy.data.materials.new(name)
    mat[TAG] = VERSION
    return mat, Graph(empty_tree(mat))


def shadow_material(caustic_mean):
    """The water's shadow, for our caster object sharing the ocean's mesh: invisible to camera
    rays, and to shadow rays transparent by the caustics (Fleck Eq. 28) where they are computed:
    the attribute holds the transparency minus `caustic_mean`, the flat water's.

    A separate, trivial material because EEVEE evaluates a transparent shadow's whole node tree
    in every shadow-map tile (docs/benchmarks.md, findings).
    """
    mat, g = _versioned_material(SHADOW_MATERIAL)
    if g is None:
        return mat
    mat.use_transparent_shadow = True
    caustic = g.node("ShaderNodeAttribute", attribute_name=CAUSTIC_ATTRIBUTE).outputs["Fac"]
    passed = g.node("ShaderNodeBsdfTransparent", {"Color": g.math("ADD", caustic, caustic_mean)})
    unseen = g.node("ShaderNodeBsdfTransparent", {"Color": (1.0, 1.0, 1.0, 1.0)})
    shadow = g.node("ShaderNodeMixShader", {
        0: g.node("ShaderNodeLightPath").outputs["Is Shadow Ray"], 1: unseen.outputs[0],
        2: passed.outputs[0]})
    out = g.node("ShaderNodeOutputMaterial")
    g.set(out.inputs["Surface"], shadow.outputs[0])
    return mat


def body_material(absorption, tile_texels):
    """The water body's volume (Fleck Eq. 14/17) absorbing `absorption` per metre (RGB), with
    the godrays' in-scattering of the sun: scattering in proportion to the caustic intensity
    (a `tile_texels` square image of ours) where the sun's ray to each point entered the water,
    so the light's pattern becomes shafts along the refracted sun."""
    mat, g = _versioned_material(BODY_MATERIAL)
    if g is None:
        return mat
    absorb = g.node("ShaderNodeVolumeAbsorption")
    absorb.name = "Absorption"
    glow = g.node("ShaderNodeEmission")
    glow.name = "Water Glow"
    update_body(mat, absorption, WATER_COLOUR)
    water = g.node("ShaderNodeAddShader", {0: absorb.outputs[0], 1: glow.outputs[0]})
    position = g.node("ShaderNodeNewGeometry").outputs["Position"]
    uv = []
    for axis in ("U", "V"):  # set per frame by update_godrays
        dot = g.vector("DOT_PRODUCT", position, (0.0, 0.0, 0.0))
        dot.node.name = f"Caustic {axis}"
        offset = g.math("ADD", dot, 0.0)
        offset.node.name = f"Caustic {axis} Offset"
        uv.append(offset)
    tile = g.node("ShaderNodeTexImage", {"Vector": g.node("ShaderNodeCombineXYZ", {
        "X": uv[0], "Y": uv[1]}).outputs[0]}, image=caustic_image(tile_texels),
        interpolation="Linear", extension="REPEAT")
    tile.name = "Caustic Tile"
    scatter = g.node("ShaderNodeVolumeScatter", {
        "Color": (0.6, 0.9, 1.0, 1.0),
        "Density": g.math("MULTIPLY", tile.outputs["Color"], GODRAY_DENSITY)})
    godrays = g.node("ShaderNodeAddShader", {0: water.outputs[0], 1: scatter.outputs[0]})
    godrays.name = "Godrays"
    out = g.node("ShaderNodeOutputMaterial")
    g.set(out.inputs["Volume"], godrays.outputs[0])
    return mat


def own_body_material(mesh, absorption, tile_texels):
    """The body material of one water body: its own (oceans' clarities and colours differ) and
    of this VERSION (a file from an older version carries an older one), made from
    `body_material` when it is not."""
    mat = mesh.materials[0] if len(mesh.materials) else None
    current = mat is not None and mat.get(TAG) == VERSION and mat.library is None
    own = mat if current else body_material(absorption, tile_texels)  # ours, rebuilt if older
    if own.users - int(own.use_fake_user) - int(own is mat) > 0:  # another body's too
        own = own.copy()
    if own is not mat:
        mesh.materials[0] = own
    return own


def update_body(mat, absorption, water_colour):
    """The water body's absorption per metre (RGB) and its glow e = a * water colour, so that
    radiance after d metres tends to the water colour (Fleck Eq. 14, 17); written only when
    they change."""
    nodes = mat.node_tree.nodes
    absorb, glow = nodes.get("Absorption"), nodes.get("Water Glow")
    if absorb is None or glow is None:
        return
    a = np.maximum(np.asarray(absorption, dtype=np.float64), 1e-9)
    emitted = np.maximum(a * np.asarray(water_colour, dtype=np.float64), 1e-12)
    assign(absorb.inputs["Color"], default_value=(*(1.0 - a / a.max()), 1.0))
    assign(absorb.inputs["Density"], default_value=float(a.max()))
    assign(glow.inputs["Color"], default_value=(*(emitted / emitted.max()), 1.0))
    assign(glow.inputs["Strength"], default_value=float(emitted.max()))


def caustic_image(size):
    """Our float image holding the godrays' caustic tile (its pixels are written per frame)."""
    image = bpy.data.images.get((CAUSTIC_IMAGE, None))
    if image is not None and image.get(TAG) and tuple(image.size) == (size, size):
        return image
    image = bpy.data.images.new(CAUSTIC_IMAGE, size, size, float_buffer=True, is_data=True)
    image[TAG] = True
    return image


def caustic_tap(mat):
    """The godrays' caustic tile node of a water body material (None if it has none)."""
    return mat.node_tree.nodes.get("Caustic Tile")


def update_godrays(mat, tile, lookup):
    """The caustic tile's intensities (n x n) into our image and its `lookup` ((a, b, c): the
    texture coordinates of a point Q are a.Q + c[0], b.Q + c[1]) into the body material."""
    nodes = mat.node_tree.nodes
    node = caustic_tap(mat)
    if node is None:
        return
    if node.image is None or not node.image.get(TAG) or tuple(node.image.size) != tile.shape:
        node.image = caustic_image(tile.shape[0])
    image = node.image
    rgba = np.empty((*tile.shape, 4), dtype=np.float32)
    rgba[..., :3] = tile[..., None]
    rgba[..., 3] = 1.0
    image.pixels.foreach_set(rgba.ravel())
    image.update()
    image.pack()  # packed, it is not a "modified image" Blender offers to save at closing
    a, b, c = lookup
    assign(nodes["Caustic U"].inputs[1], default_value=tuple(a))
    assign(nodes["Caustic V"].inputs[1], default_value=tuple(b))
    assign(nodes["Caustic U Offset"].inputs[1], default_value=float(c[0]))
    assign(nodes["Caustic V Offset"].inputs[1], default_value=float(c[1]))


def material():
    """A new water material of ours, for one ocean: the frame handler writes each ocean's own
    shader inputs (detail, time, filtering) into its material (they share the node group), and
    its slope layer's images (a group cannot take images: their texture nodes are the
    material's)."""
    mat = bpy.data.materials.new(MATERIAL)
    mat[TAG] = True
    nodes = empty_tree(mat).nodes
    group = nodes.new("ShaderNodeGroup")
    group.node_tree = node_group()
    group.name = GROUP
    output = nodes.new("ShaderNodeOutputMaterial")
    output.location = (300, 0)
    mat.node_tree.links.new(group.outputs["Shader"], output.inputs["Surface"])
    mat.use_backface_culling = False
    _layer_nodes(mat.node_tree, group)
    return mat


def _layer_nodes(tree, group):
    """The slope layer's texture lookups feeding the group, added if missing (a material of an
    older version gets them at its first frame): per band, its image at texel coordinates
    S = a.(P - origin) + s0, T = b.(P - origin) + t0 (update_layer writes them), bilinear from
    its four nearest texels sampled unfiltered (the shader cuts the slopes per pixel itself;
    EEVEE's mip-mapped, anisotropic filtering makes renders on the CPU tens of times slower)."""
    if tree.nodes.get("Layer Origin") is not None:
        return
    g = Graph(tree)
    g.x = -1600
    position = g.node("ShaderNodeNewGeometry").outputs["Position"]
    near = g.vector("SUBTRACT", position, (0.0, 0.0, 0.0))
    near.node.name = "Layer Origin"
    for b in range(1, LAYER_BANDS + 1):
        corners, fractions = [], []
        for axis in ("S", "T"):
            dot = g.vector("DOT_PRODUCT", near, (0.0, 0.0, 0.0))
            dot.node.name = f"Layer {b} {axis}"
            texel = g.math("ADD", dot, 0.0)
            texel.node.name = f"Layer {b} {axis} Offset"
            first = g.math("FLOOR", texel)
            fractions.append(g.math("SUBTRACT", texel, first))
            centre = g.math("MULTIPLY", g.math("ADD", first, 0.5), 1.0)  # / texels across
            centre.node.name = f"Layer {b} {axis} Texel"
            step = g.math("ADD", centre, 0.0)  # the next texel's centre
            step.node.name = f"Layer {b} {axis} Step"
            corners.append((centre, step))
        taps = []
        for t in corners[1]:
            for s_ in corners[0]:
                tap = g.node("ShaderNodeTexImage", {"Vector": g.node("ShaderNodeCombineXYZ", {
                    "X": s_, "Y": t}).outputs[0]}, interpolation="Closest", extension="REPEAT")
                tap.name = f"Layer {b} Tap {len(taps)}"
                taps.append(tap.outputs["Color"])
        rows = [_mix_vector(g, fractions[0], taps[2 * r], taps[2 * r + 1]) for r in (0, 1)]
        g.set(group.inputs[f"Layer Slopes {b}"], _mix_vector(g, fractions[1], *rows))


def _mix_vector(g, factor, a, b):
    node = g.node("ShaderNodeMix", {"Factor_Float": factor, "A_Vector": a, "B_Vector": b},
                  data_type="VECTOR")
    return socket(node.outputs, "Result_Vector")


def update_layer(mat, slopes, lookups, origin):
    """The slope layer's tiles (per band (2, n, n): the slopes along x and y) into the
    material's own float images, and their lookups ((a, b, c) per band, texel coordinates
    about `origin` (x, y): slope_layer.SlopeLayer.lookups) into its nodes. Images are written,
    not packed, each frame (a pack costs 3 ms; the save handler packs them)."""
    tree = mat.node_tree
    group = tree.nodes.get(GROUP)
    if group is None or group.type != "GROUP" or f"Layer Slopes {LAYER_BANDS}" not in group.inputs:
        return
    _layer_nodes(tree, group)
    nodes = tree.nodes
    assign(nodes["Layer Origin"].inputs[1], default_value=(float(origin[0]), float(origin[1]),
                                                           0.0))
    for b, (tile, (a, bb, c)) in enumerate(zip(slopes, lookups, strict=True), 1):
        n = tile.shape[-1]
        image = nodes[f"Layer {b} Tap 0"].image
        entry = _LAYER_WRITTEN.get(image.session_uid) if image is not None else None
        if (image is None or not image.get(TAG) or tuple(image.size) != (n, n)
                or (entry and entry[0] != mat.session_uid)  # another material's
                or image.library is not None):
            image = bpy.data.images.new(f"{LAYER_IMAGE} {b}", n, n, float_buffer=True,
                                        is_data=True)
            image[TAG] = True
        for tap in range(4):
            if nodes[f"Layer {b} Tap {tap}"].image != image:
                nodes[f"Layer {b} Tap {tap}"].image = image
        written = zlib.crc32(tile.tobytes())  # unchanged (a redraw at the same time, after a
        if _LAYER_WRITTEN.get(image.session_uid) != (mat.session_uid, written):  # save): clean
            rgba = np.zeros((n, n, 4), dtype=np.float32)
            rgba[..., 0], rgba[..., 1], rgba[..., 3] = tile[0], tile[1], 1.0
            image.pixels.foreach_set(rgba.ravel())
            image.update()
            _LAYER_WRITTEN[image.session_uid] = (mat.session_uid, written)
        for axis, row, start in (("S", a, c[0]), ("T", bb, c[1])):
            assign(nodes[f"Layer {b} {axis}"].inputs[1], default_value=tuple(row))
            assign(nodes[f"Layer {b} {axis} Offset"].inputs[1], default_value=float(start))
            assign(nodes[f"Layer {b} {axis} Texel"].inputs[1], default_value=1.0 / n)
            assign(nodes[f"Layer {b} {axis} Step"].inputs[1], default_value=1.0 / n)


BAKED_LAYER = "Projected Grid Bake Slopes"  # and the band's number: a bake's image sequence
BAKED_CAUSTICS = "Projected Grid Bake Caustics"  # the godrays' tile, a bake's image sequence


def group_tree(mat):
    """Our water group's node tree in material `mat` (None if it has none of ours)."""
    node = mat.node_tree.nodes.get(GROUP)
    tree = node.node_tree if node is not None and node.type == "GROUP" else None
    return tree if tree is not None and tree.get(TAG) and tree.library is None else None


def _taps(nodes, b):
    """The slope layer's four texture nodes of band b (None if the material lacks them)."""
    taps = [nodes.get(f"Layer {b} Tap {t}") for t in range(4)]
    return None if any(tap is None for tap in taps) else taps


def layer_taps(mat):
    """(band, image) of the slope layer's texture nodes in our material (image None if unset)."""
    nodes = mat.node_tree.nodes
    return [(b, taps[0].image) for b in range(1, LAYER_BANDS + 1)
            if (taps := _taps(nodes, b)) is not None]


def play_layer_sequences(mat, files, first, last):
    """The slope layer read from image sequences, per band the file of frame `first` (numbered
    by frame, up to `last`), as a bake wrote them; `files` empty: back to the images written
    each frame (the bake's sequences removed, update_layer makes new images)."""
    nodes = mat.node_tree.nodes
    for b in range(1, LAYER_BANDS + 1):
        taps = _taps(nodes, b)
        if taps is None:
            continue
        old = taps[0].image
        if b not in files and (old is None or not old.name.startswith(BAKED_LAYER)):
            continue  # live images: left as they are
        image = _sequence(files[b], f"{BAKED_LAYER} {b}") if b in files else None
        for tap in taps:
            _play(tap, image, first, last)
        _drop_baked(old, BAKED_LAYER)


def play_caustic_sequence(mat, file, first, last, texels):
    """The godrays' caustic tile of a water body material read from an image sequence (the
    file of frame `first`, numbered up to `last`), as a bake wrote it; `file` None: back to
    our image written each frame, `texels` square."""
    node = caustic_tap(mat)
    if node is None:
        return
    old = node.image
    if file is None:
        if old is None or not old.name.startswith(BAKED_CAUSTICS):
            return
        _play(node, caustic_image(texels), first, last)  # (a sequence's size is 0 unread)
    else:
        _play(node, _sequence(file, BAKED_CAUSTICS), first, last)
    _drop_baked(old, BAKED_CAUSTICS)


def _sequence(file, name):
    """Our image sequence (float data) whose first file is `file`, named `name`."""
    image = bpy.data.images.load(file, check_existing=False)
    image.name = name
    image.source = "SEQUENCE"
    image.colorspace_settings.is_data = True
    image[TAG] = True
    return image


def _play(tap, image, first, last):
    """`tap` reads `image`, a sequence's frame `first` on scene frame `first` up to `last`."""
    tap.image = image
    if image is not None and image.source == "SEQUENCE":
        user = tap.image_user
        user.frame_start, user.frame_offset = first, first - 1
        user.frame_duration, user.use_auto_refresh = last - first + 1, True


def _drop_baked(image, prefix):
    """A bake's image sequence of ours that nothing uses any more, removed."""
    if (image is not None and image.get(TAG) and image.name.startswith(prefix)
            and image.users == 0):
        bpy.data.batch_remove([image])


def layer_images():
    """Our slope layer images (the save and render-done handlers pack them: written, not
    packed, each frame, they would be offered as 'modified images' at closing)."""
    return [image for image in bpy.data.images
            if image.get(TAG) and image.name.startswith(LAYER_IMAGE) and image.library is None]


def own_material(mesh):
    """Give our mesh a local copy of its water material of ours if another mesh uses it too (a
    duplicated ocean, or a file from when oceans shared one) or if it is a library's, so its
    inputs are its own to write. Returns the copy, or None."""
    mat = mesh.materials[0] if len(mesh.materials) else None
    if mat is not None and mat.get(TAG) and (
            mat.library is not None or mat.users > 1 + int(mat.use_fake_user)):
        mesh.materials[0] = adopt_material(mat)
        return mesh.materials[0]
    return None


def adopt_material(mat):
    """The material a mesh of ours drawing another's sea takes: a local copy of a water
    material of ours (keeping the artist's changes to its inputs, on our local node group), the
    user's own material as it is (never written), or a new water material if there is none."""
    if mat is None:
        return material()
    if not mat.get(TAG):
        return mat
    copy = mat.copy()
    node = copy.node_tree.nodes.get(GROUP) if copy.node_tree else None
    if node is not None and node.type == "GROUP" and (
            node.node_tree is None or node.node_tree.library is not None):
        node.node_tree = node_group()
    return copy


def material_of(mesh):
    """Our local water material on `mesh`, or None (the user's own material, or a library's,
    is never written)."""
    mat = mesh.materials[0] if len(mesh.materials) else None
    ours = mat is not None and mat.get(TAG) and mat.library is None and mat.node_tree
    return mat if ours else None


def update(mat, effects_on, detail, detail_time_per_frame, ripple, ripple_time_per_frame,
           filtering, water_colour=WATER_COLOUR, foam_colour=FOAM_COLOUR, wind_direction=0.0,
           foam_coverage=0.0, layer=(), sun_direction=None, gust_drift=((0.0, 0.0),) * 3):
    """A frame's inputs into our water material's group, each written only when it changed:
    which effects are on ({effect: bool}), the left-out octaves as detail (shading.Detail) and
    the ripples (shading.Detail), whose times drivers advance with the frame (subframes
    included), so an animation writes nothing per frame; the filtering of the waves too short
    to draw (shading.Filtering); the ocean's look (linear RGB colours); the wind's direction
    (radians), which streaks the foam, and the share of the sea its whitecaps cover, shown
    where a pixel outgrows a whitecap; the slope layer's bands ((level, top log, bottom log)
    each; none: no layer); the unit vector toward the sun lamp (None: no sun, no glint); the
    gusts' drift along X, along Y and its path (m), each (per frame, offset) for a driver like
    the times'."""
    node = mat.node_tree.nodes.get(GROUP)
    if node is None or node.type != "GROUP":
        return
    tree = node.node_tree
    if tree is not None and tree.get(TAG) and tree.library is None:
        if tree.get(TAG) != VERSION:  # a file from an older version: ours, rebuilt
            node.node_tree = tree = node_group()
        set_effects(tree, effects_on, EFFECT_NODES)
    inputs = node.inputs
    values = {
        "Detail First Octave": detail.first, "Detail Scale": detail.scale,
        "Detail Octaves": detail.octaves, "Detail Roughness": detail.roughness,
        "Detail Height": detail.height, "Detail Top Log": -np.log(detail.scale),
        "Ripple Scale": ripple.scale, "Ripple Octaves": ripple.octaves,
        "Ripple Height": ripple.height * filtering.ripple_gain,
        "Pixel Log": filtering.pixel_log, "Distance Power": filtering.distance_power,
        "Cos Floor": filtering.cos_floor,
        "Slope Floor": filtering.floor, "Ripple Slopes": filtering.ripple,
        "Slope Density": filtering.density, "Shortest Log": filtering.shortest_log,
        "Ripple Top Log": filtering.ripple_top_log, "Slope Ceiling": filtering.ceiling,
        "Facet Log": filtering.facet_log, "Facets Sharp Log": filtering.facets_sharp_log,
        "Facets Mean Log": filtering.facets_mean_log, "Sun Reach": filtering.sun_reach,
        "Left Out Log": filtering.left_out_log, "Layer Top Log": filtering.layer_top_log,
        "Layer Density": filtering.layer_density, "Gust Amplitude": filtering.gust,
        "Gust Norm": filtering.gust_norm,
        "Wind Direction": wind_direction, "Foam Coverage": foam_coverage}
    for b in range(1, LAYER_BANDS + 1):
        names = (f"Layer Level {b}", f"Layer Top Log {b}", f"Layer Bottom Log {b}")
        band = layer[b - 1] if b <= len(layer) else (DEFAULTS[n] for n in names)  # none drawn
        values.update(zip(names, band, strict=True))
    for name, value in values.items():
        if name in inputs:  # a group of an older version until it is rebuilt
            assign(inputs[name], default_value=float(value))
    for name, colour in (("Water Colour", water_colour), ("Foam Colour", foam_colour)):
        if name in inputs:
            assign(inputs[name], default_value=(*colour, 1.0))
    if "Sun Direction" in inputs:
        assign(inputs["Sun Direction"], default_value=tuple(
            float(v) for v in (sun_direction if sun_direction is not None else (0.0, 0.0, 0.0))))
    drive_by_frame(mat.node_tree, inputs["Detail Time"], detail_time_per_frame)
    drive_by_frame(mat.node_tree, inputs["Ripple Time"], ripple_time_per_frame)
    for name, (per_frame, offset) in zip(GUST_DRIFT, gust_drift, strict=True):
        drive_by_frame(mat.node_tree, inputs[name], per_frame, offset)


def drive_expression(per_frame, offset=0.0):
    if offset:
        return f"{float(offset)!r} + frame * {float(per_frame)!r}"
    return f"frame * {float(per_frame)!r}"


def driven_value(expression, frame):
    """What a `drive_expression` reads at `frame`."""
    offset, _, per_frame = expression.rpartition("frame * ")
    return float(offset.rstrip(" +") or 0.0) + frame * float(per_frame)


def drive_by_frame(tree, socket, per_frame, offset=0.0):
    """A driver setting `socket`'s value to `offset` plus the frame (with its subframe) times
    `per_frame`, written only when it changes (a simple expression: it runs where Python is
    blocked)."""
    path = socket.path_from_id("default_value")
    expression = drive_expression(per_frame, offset)
    curve = tree.animation_data.drivers.find(path) if tree.animation_data else None
    if curve is None:
        curve = socket.driver_add("default_value")
        curve.driver.type = "SCRIPTED"
    if curve.driver.expression != expression:
        curve.driver.expression = expression


def set_effects(tree, on, nodes):
    """Mute each branch no effect that is on needs (only on change: a change recompiles)."""
    for name, needed_by in nodes.items():
        node = tree.nodes.get(name)
        mute = not any(on.get(effect, False) for effect in needed_by)
        if node is not None and node.mute != mute:
            node.mute = mute
