"""Our materials, built from plain values: the water material (the group of water.py on the
ocean's mesh, with the slope layer's texture taps), the water body's volume with the godrays'
caustic tile, and the shadow caster's material; and where their nodes are (read by the Blender
layer, which writes their inputs each frame)."""

import bpy

from ..projgrid_addon.look import (
    FOAM_COLOUR,
    GODRAY_DENSITY,
    SPRAY_CHORD,
    SPRAY_OPACITY,
    WATER_COLOUR,
    body_volume,
)
from . import sky
from .nodes import TAG, Graph, empty_tree, socket
from .water import (
    BODY_MATERIAL,
    CAUSTIC_ATTRIBUTE,
    CAUSTIC_IMAGE,
    GROUP,
    HAZE,
    LAYER_BANDS,
    MATERIAL,
    SHADOW_MATERIAL,
    SPRAY_AIR,
    SPRAY_ATTRIBUTES,
    SPRAY_MATERIAL,
    SPRAY_POINTS,
    VERSION,
    node_group,
)


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


PUFF = "Puff"  # the spray's Mix Shader from clear to the hazed white (its factor: how opaque)


def spray_material():
    """The spray's puffs: clouds of droplets, each a sphere of even density, o its opacity
    attribute times SPRAY_OPACITY, as opaque along a ray through it as 1 - (1 - o)^(SPRAY_CHORD
    c) (Beer-Lambert over the chord, c = |normal . view| its share of the diameter), so a puff
    fades out to its rim, its mean over the disc o's for a thin one, instead of ending in a
    hard disc; lit as a level white patch (a droplet cloud scatters light many times: no
    terminator of a solid ball) seen through the air as the water is (sky.through_air: its
    object's SPRAY_AIR properties), the rest passing, casting no shadow."""
    mat, g = _versioned_material(SPRAY_MATERIAL)
    if g is None:
        return mat
    opacity = g.node("ShaderNodeAttribute", attribute_name=SPRAY_ATTRIBUTES[1]).outputs["Fac"]
    geo = g.node("ShaderNodeNewGeometry").outputs
    chord = g.abs(g.vector("DOT_PRODUCT", geo["Normal"], geo["Incoming"]))
    middle = g.math("MULTIPLY", opacity, SPRAY_OPACITY, clamp=True)
    seen = 1.0 - g.pow(g.max(1.0 - middle, 0.0), chord * SPRAY_CHORD)
    white = g.node("ShaderNodeBsdfDiffuse", {"Color": (*FOAM_COLOUR, 1.0),
                                             "Normal": (0.0, 0.0, 1.0)})
    haze, cloud = (g.value(g.node("ShaderNodeAttribute", attribute_type="OBJECT",
                                  attribute_name=name).outputs["Fac"]) for name in SPRAY_AIR)
    distance = g.value(g.node("ShaderNodeCameraData").outputs["View Distance"])
    hazed = sky.through_air(g, white.outputs[0], haze, cloud, distance, geo["Incoming"])
    clear = g.node("ShaderNodeBsdfTransparent", {"Color": (1.0, 1.0, 1.0, 1.0)})
    hazed.name = HAZE
    puff = g.node("ShaderNodeMixShader", {0: g.clamp(seen), 1: clear.outputs[0],
                                          2: hazed.outputs[0]})
    puff.name = PUFF
    g.set(g.node("ShaderNodeOutputMaterial").inputs["Surface"], puff.outputs[0])
    return mat


def spray_points():
    """Our geometry nodes drawing the spray's puffs as points of their radius attribute, in the
    spray material (rebuilt if of another VERSION): a vertex per puff live, or a baked mesh's
    triangle per puff (its face's centre and attributes) when the mesh has faces."""
    tree = bpy.data.node_groups.get((SPRAY_POINTS, None))
    if tree is not None and tree.get(TAG) == VERSION:
        return tree
    if tree is None or not tree.get(TAG):
        tree = bpy.data.node_groups.new(SPRAY_POINTS, "GeometryNodeTree")
    tree[TAG] = VERSION
    tree.nodes.clear()
    tree.interface.clear()
    for side in ("INPUT", "OUTPUT"):
        tree.interface.new_socket("Geometry", in_out=side, socket_type="NodeSocketGeometry")
    g = Graph(tree)
    mesh = g.node("NodeGroupInput").outputs[0]
    radius = g.node("GeometryNodeInputNamedAttribute", {"Name": SPRAY_ATTRIBUTES[0]},
                    data_type="FLOAT")
    points = [g.node("GeometryNodeMeshToPoints", {"Mesh": mesh,
                                                  "Radius": radius.outputs["Attribute"]},
                     mode=mode) for mode in ("VERTICES", "FACES")]
    faces = g.node("GeometryNodeAttributeDomainSize", {"Geometry": mesh}, component="MESH")
    either = g.node("GeometryNodeSwitch", {"Switch": faces.outputs["Face Count"],
                                           "False": points[0].outputs[0],
                                           "True": points[1].outputs[0]},
                    input_type="GEOMETRY")
    drawn = g.node("GeometryNodeSetMaterial", {"Geometry": either.outputs[0],
                                               "Material": spray_material()})
    g.set(g.node("NodeGroupOutput").inputs[0], drawn.outputs[0])
    return tree


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
    colour, density, glow_colour, strength = body_volume(absorption, WATER_COLOUR)
    absorb.inputs["Color"].default_value = colour
    absorb.inputs["Density"].default_value = density
    glow.inputs["Color"].default_value = glow_colour
    glow.inputs["Strength"].default_value = strength
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
    layer_nodes(mat.node_tree, group)
    return mat


def layer_nodes(tree, group):
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


def group_tree(mat):
    """Our water group's node tree in material `mat` (None if it has none of ours)."""
    node = mat.node_tree.nodes.get(GROUP)
    tree = node.node_tree if node is not None and node.type == "GROUP" else None
    return tree if tree is not None and tree.get(TAG) and tree.library is None else None


def layer_tap_nodes(nodes, b):
    """The slope layer's four texture nodes of band b (None if the material lacks them)."""
    taps = [nodes.get(f"Layer {b} Tap {t}") for t in range(4)]
    return None if any(tap is None for tap in taps) else taps


def layer_taps(mat):
    """(band, image) of the slope layer's texture nodes in our material (image None if unset)."""
    nodes = mat.node_tree.nodes
    return [(b, taps[0].image) for b in range(1, LAYER_BANDS + 1)
            if (taps := layer_tap_nodes(nodes, b)) is not None]
