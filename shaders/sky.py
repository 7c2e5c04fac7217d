"""The sky world and sun lamp Add Ocean puts into a scene that has none (never replacing one).

The sky is a gradient on the view direction's height, the same in every Blender version, so
reference renders compare across 4.5 and 5.x; the water reflects it (§3.4.3).
"""

import math

import bpy

from .nodes import TAG, Graph, empty_tree

WORLD = "Projected Grid Sky"
SUN = "Projected Grid Sun"
# (position on the ramp from z = -0.1 to z = 1, linear colour)
GRADIENT = ((0.0, (0.10, 0.12, 0.14)), (0.09, (0.70, 0.78, 0.88)), (0.35, (0.28, 0.45, 0.75)),
            (1.0, (0.08, 0.20, 0.55)))


def world():
    w = bpy.data.worlds.new(WORLD)
    w[TAG] = True
    g = Graph(empty_tree(w))
    direction = g.node("ShaderNodeTexCoord").outputs["Generated"]
    z = g.node("ShaderNodeSeparateXYZ", {0: direction}).outputs["Z"]
    t = g.node("ShaderNodeMapRange", {0: z, 1: -0.1, 2: 1.0, 3: 0.0, 4: 1.0}).outputs[0]
    ramp = g.node("ShaderNodeValToRGB", {0: t})
    elements = ramp.color_ramp.elements
    while len(elements) < len(GRADIENT):
        elements.new(0.5)
    for element, (pos, colour) in zip(elements, GRADIENT, strict=True):
        element.position = pos
        element.color = (*colour, 1.0)
    background = g.node("ShaderNodeBackground", {"Color": ramp.outputs["Color"], "Strength": 1.0})
    output = g.node("ShaderNodeOutputWorld")
    g.set(output.inputs["Surface"], background.outputs[0])
    return w


def sun(collection, elevation=12.0, azimuth=0.0, strength=3.0):
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
