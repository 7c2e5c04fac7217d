"""The sky world and sun lamp Add Ocean puts into a scene that has none (never replacing one).

The sky is a gradient on the view direction's height, the same in every Blender version, so
reference renders compare across 4.5 and 5.x, and a glow around the sun: the light the haze
scatters forward, by the Henyey-Greenstein phase function (1 - g^2) / (1 + g^2 - 2 g cos)^1.5
of the angle to the sun, which brightens the sky toward a low sun as in photographs. The glow
follows the scene's sun lamp (`aim_glow`, from the frame handler) and goes out without one.
The water reflects it all (§3.4.3).
"""

import math

import bpy

from ..projgrid_addon.look import SUN_ELEVATION, SUN_STRENGTH
from .nodes import TAG, Graph, empty_tree

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
    return w


def sun(collection, elevation=SUN_ELEVATION, azimuth=0.0, strength=SUN_STRENGTH):
    """A sun lamp `elevation` degrees above the horizon, shining from `azimuth` (0 = from +Y)."""
    data = bpy.data.lights.new(SUN, "SUN")
    data[TAG] = True
    data.energy = strength
    data.angle = math.radians(0.5)
    obj = bpy.data.objects.new(SUN, data)
    # The lamp shines along its local -Z: tilt +Z from straight up down to the elevation.
    obj.rotation_euler = (math.radians(90.0 - elevation), 0.0, math.radians(180.0 + azimuth))
    collection.objects.link(obj)
    return obj


def strength(world):
    """How bright a world is against our sky: our world's Background Strength; another world
    counts as our sky (1.0), none as dark (0.0)."""
    if world is None:
        return 0.0
    node = (world.node_tree.nodes.get(BACKGROUND) if world.get(TAG) and world.node_tree
            is not None else None)
    return float(node.inputs["Strength"].default_value) if node is not None else 1.0


def aim_glow(world, toward):
    """Point our world's glow at the sun: `toward` the unit vector to it, None without a sun.
    Another world, or a library's, is left alone."""
    node = (world.node_tree.nodes.get(GLOW) if world is not None and world.get(TAG)
            and world.library is None and world.node_tree is not None else None)
    if node is None:
        return
    values = (0.0, 0.0, 0.0) if toward is None else tuple(float(v) for v in toward)
    for socket, value in zip(node.inputs, values, strict=False):
        if abs(socket.default_value - value) > 1e-6:
            socket.default_value = value
