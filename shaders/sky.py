"""The sky world and sun lamp Add Ocean puts into a scene that has none (never replacing one).

The sky is a gradient on the view direction's height, the same in every Blender version, so
reference renders compare across 4.5 and 5.x, and a glow around the sun: the light the haze
scatters forward, by the Henyey-Greenstein phase function (1 - g^2) / (1 + g^2 - 2 g cos)^1.5
of the angle to the sun, which brightens the sky toward a low sun as in photographs. The glow
follows the scene's sun lamp (`aim_glow`, from the frame handler) and goes out without one.
Under cloud (`weather`: the Sea State operator's storm) it gives way to an overcast whose
brightness grows with the height as the CIE standard overcast sky's, (1 + 2 sin h) / 3 of the
zenith's (Moon and Spencer 1942), mottled by a cloud noise on its base, and the sun lamp
dims behind it. The water reflects it all (§3.4.3).
"""

import math

import bpy

from ..projgrid_addon.look import OVERCAST_ZENITH, SUN_ELEVATION, SUN_STRENGTH
from .nodes import TAG, Graph, empty_tree, socket

WORLD = "Projected Grid Sky"
SUN = "Projected Grid Sun"
# (position on the ramp from z = RAMP_Z[0] to z = RAMP_Z[1], linear colour)
GRADIENT = ((0.0, (0.10, 0.12, 0.14)), (0.09, (0.70, 0.78, 0.88)), (0.35, (0.28, 0.45, 0.75)),
            (1.0, (0.08, 0.20, 0.55)))
RAMP_Z = (-0.1, 1.0)  # the view direction's height mapped onto the ramp's 0 to 1
BACKGROUND = "Background"  # the world's Background node: its Strength scales the sky
GLOW = "Sun Glow"  # the Combine XYZ node holding the unit vector toward the sun (0: no sun)
GLOW_G = 0.8  # the haze's forward scattering (Henyey-Greenstein asymmetry)
GLOW_COLOUR = (0.03, 0.0276, 0.024)  # linear, times the phase function: warm, as sunlight
OVERCAST = "Overcast"  # the Mix node from the clear sky to the overcast (its factor: how much)
# The sun lamp under a full overcast: its strength against a clear sky's, and the angle it
# spreads over (degrees): a bright patch in the cloud, not a disc, so no glitter path.
SUN_UNDER_CLOUD, SUN_ANGLE = 0.15, (0.5, 40.0)
# The overcast's cloud: a fractal noise on the cloud base (the view direction over its height,
# CLOUD_SCALE features per cloud height), brightening and darkening it by up to CLOUD_CONTRAST
# (mean 1: the light on the sea stays the CIE sky's), less toward the horizon, where a pixel
# holds many clouds.
CLOUD_SCALE, CLOUD_CONTRAST, CLOUD_DETAIL, CLOUD_ROUGHNESS = 1.5, 0.45, 6.0, 0.6
CLOUD_SPREAD = 0.2  # the noise's Fac from 0.5 at which the contrast is whole


def cloud_shade(m, fac, fade):
    """The overcast's brightness factor at the cloud noise's Fac `fac`, `fade` (0 to 1) of
    its contrast: the world's nodes are built from it (`m` the node graph, as water_model's
    formulas), the tests evaluate it in NumPy."""
    return m.max((fac - 0.5) * fade * (CLOUD_CONTRAST / CLOUD_SPREAD) + 1.0, 0.2)


def world():
    w = bpy.data.worlds.new(WORLD)
    w[TAG] = True
    g = Graph(empty_tree(w))
    direction = g.node("ShaderNodeTexCoord").outputs["Generated"]
    z = g.node("ShaderNodeSeparateXYZ", {0: direction}).outputs["Z"]
    t = g.node("ShaderNodeMapRange", {0: z, 1: RAMP_Z[0], 2: RAMP_Z[1], 3: 0.0, 4: 1.0}).outputs[0]
    ramp = g.node("ShaderNodeValToRGB", {0: t})
    elements = ramp.color_ramp.elements
    while len(elements) < len(GRADIENT):
        elements.new(0.5)
    for element, (pos, colour) in zip(elements, GRADIENT, strict=True):
        element.position = pos
        element.color = (*colour, 1.0)
    toward = g.node("ShaderNodeCombineXYZ")
    toward.name = toward.label = GLOW
    cos = g.vector("DOT_PRODUCT", direction, toward.outputs[0])
    phase = g.math("MULTIPLY", g.math("POWER", g.math(
        "MULTIPLY_ADD", cos, -2.0 * GLOW_G, 1.0 + GLOW_G**2), -1.5), 1.0 - GLOW_G**2)
    glow = g.vector("SCALE", GLOW_COLOUR, Scale=g.math(
        "MULTIPLY", phase, g.vector("LENGTH", toward.outputs[0])))  # none without a sun
    sky = g.vector("ADD", ramp.outputs["Color"], glow)
    background = g.node("ShaderNodeBackground", {"Color": sky, "Strength": 1.0})
    background.name = BACKGROUND
    output = g.node("ShaderNodeOutputWorld")
    g.set(output.inputs["Surface"], background.outputs[0])
    _overcast(g)
    return w


def _overcast(g):
    """Put the overcast between the clear sky and the Background of our world's graph `g`, at
    a factor of 0 (a world made before it had none)."""
    colour = g.nodes[BACKGROUND].inputs["Color"]
    clear = colour.links[0].from_socket if colour.links else tuple(colour.default_value)
    direction = g.node("ShaderNodeTexCoord").outputs["Generated"]
    height = g.clamp(g.node("ShaderNodeSeparateXYZ", {0: direction}).outputs["Z"])
    cie = g.math("DIVIDE", g.math("MULTIPLY_ADD", height, 2.0, 1.0), 3.0)
    base = g.vector("SCALE", direction, Scale=g.math("DIVIDE", 1.0, g.math("MAXIMUM", height,
                                                                             0.02)))
    cloud = g.node("ShaderNodeTexNoise", {"Vector": base, "Scale": CLOUD_SCALE,
                                          "Detail": CLOUD_DETAIL, "Roughness": CLOUD_ROUGHNESS})
    # fading out below 10 degrees up
    shade = cloud_shade(g, g.value(cloud.outputs["Fac"]), g.clamp(g.math("MULTIPLY", height, 6.0)))
    mix = g.node("ShaderNodeMix", {"Factor_Float": 0.0, "A_Color": clear, "B_Color": g.vector(
        "SCALE", OVERCAST_ZENITH, Scale=g.math("MULTIPLY", cie, shade))}, data_type="RGBA")
    mix.name = mix.label = OVERCAST
    g.set(colour, socket(mix.outputs, "Result_Color"))
    return mix


def _ours(block):
    """Whether `block` (a world or a lamp) is one we made and may write: not a library's, nor
    a library override's."""
    return (block is not None and bool(block.get(TAG)) and block.library is None
            and block.override_library is None)


def weather(scene, cloud):
    """Turn the scene's sky toward an overcast by `cloud` (0 clear, 1 a full overcast) and dim
    its sun lamp behind it: our world and our sun lamps only (`_ours`)."""
    world = scene.world
    if _ours(world) and world.node_tree:
        node = world.node_tree.nodes.get(OVERCAST) or _overcast(Graph(world.node_tree))
        node.inputs["Factor"].default_value = cloud
    for obj in scene.objects:
        light = obj.data if obj.type == "LIGHT" else None
        if light is not None and light.type == "SUN" and _ours(light):
            light.energy = SUN_STRENGTH * (1.0 - (1.0 - SUN_UNDER_CLOUD) * cloud)
            light.angle = math.radians(SUN_ANGLE[0] + (SUN_ANGLE[1] - SUN_ANGLE[0]) * cloud)


def sun(collection, elevation=SUN_ELEVATION, azimuth=0.0, strength=SUN_STRENGTH):
    """A sun lamp `elevation` degrees above the horizon, shining from `azimuth` (`aim`)."""
    data = bpy.data.lights.new(SUN, "SUN")
    data[TAG] = True
    data.energy = strength
    data.angle = math.radians(SUN_ANGLE[0])
    obj = bpy.data.objects.new(SUN, data)
    aim(obj, elevation, azimuth)
    collection.objects.link(obj)
    return obj


def aim(obj, elevation=SUN_ELEVATION, azimuth=0.0):
    """Turn a sun lamp to shine from `elevation` degrees above the horizon and `azimuth` (0 =
    from +Y, counter-clockwise seen from above)."""
    # The lamp shines along its local -Z: tilt +Z from straight up down to the elevation.
    obj.rotation_euler = (math.radians(90.0 - elevation), 0.0, math.radians(180.0 + azimuth))


def strength(world):
    """How bright a world is against our sky: our world's Background Strength; another world
    counts as our sky (1.0), none as dark (0.0)."""
    if world is None:
        return 0.0
    node = (world.node_tree.nodes.get(BACKGROUND) if world.get(TAG) and world.node_tree
            is not None else None)
    return float(node.inputs["Strength"].default_value) if node is not None else 1.0


def overcast(world):
    """How far our sky world is turned to the overcast (`weather`; 0 clear, 1 full): its
    Overcast node's factor; another world, or ours from before it had one, 0."""
    node = (world.node_tree.nodes.get(OVERCAST) if world is not None and world.get(TAG)
            and world.node_tree is not None else None)
    return float(node.inputs["Factor"].default_value) if node is not None else 0.0


def aim_glow(world, toward):
    """Point our world's glow at the sun: `toward` the unit vector to it, None without a sun.
    Another world, or a library's, is left alone."""
    node = (world.node_tree.nodes.get(GLOW) if _ours(world) and world.node_tree is not None
            else None)
    if node is None:
        return
    values = (0.0, 0.0, 0.0) if toward is None else tuple(float(v) for v in toward)
    for input_, value in zip(node.inputs, values, strict=False):
        if abs(input_.default_value - value) > 1e-6:
            input_.default_value = value
