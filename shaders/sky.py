"""The sky world and sun lamp Add Ocean puts into a scene that has none (never replacing one).

The sky is Blender's own Sky Texture (daylight.py: 5.x's Multiple Scattering, 4.5's Nishita)
times daylight.SKY_SCALE, aimed at the scene's sun lamp on every frame (`aim_sky`), so a low
sun gives a warm sky and a high one a blue sky; its sun disc, which EEVEE does not draw, is
ours, seen by camera rays only with its aureole (daylight.aureole: the glare about the sun;
the lamp lights the scene and glints on the water). Our sun
lamp carries the disc's light: its colour and strength follow its elevation (`follow_sun`,
daylight.sunlight) while they are as we left them. Below the horizon the world shows the
depths, deep water's own light, which total internal reflection shows from under water.
Under cloud (`weather`: the Sea State operator's storm) the sky gives way to an overcast whose
brightness grows with the height as the CIE standard overcast sky's, (1 + 2 sin h) / 3 of the
zenith's (Moon and Spencer 1942), mottled by a cloud noise on its base, and the sun lamp dims
behind it. The water reflects it all (§3.4.3).
"""

import math

import bpy
import numpy as np

from ..projgrid_addon import daylight, optics, shading
from ..projgrid_addon.look import OVERCAST_ZENITH, SUN_ELEVATION, WATER_COLOUR
from .nodes import TAG, Graph, empty_tree, socket

WORLD = "Projected Grid Sky"
SUN = "Projected Grid Sun"
SKY = "Sky"  # the Sky Texture node
BACKGROUND = "Background"  # the world's Background node: its Strength scales the sky
GLOW = "Sun Glow"  # the Combine XYZ node holding the unit vector toward the sun (0: no sun)
DISC = "Sun Disc"  # the Combine XYZ node holding the disc's RGB radiance
# the Combine XYZ node holding the radiance of deep water seen from within (`depths`), shown
# below the horizon over DEPTHS_BLEND of the view direction's height
DEPTHS, DEPTHS_BLEND = "Depths", 0.02
LIGHT = "projgrid_light"  # on our lamp: (strength, r, g, b) as we last set them
OVERCAST = "Overcast"  # the Mix node from the clear sky to the overcast (its factor: how much)
# The sun lamp under a full overcast: its strength against a clear sky's (its light on the
# sea 2 % of the overcast's with the sun 12 deg up), and the angle it spreads over (degrees):
# a bright patch in the cloud, not a disc, so no glitter path.
SUN_UNDER_CLOUD, SUN_ANGLE = 0.055, (daylight.SUN_SIZE, 40.0)
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
    """Our sky world: the Sky Texture and our sun disc, the overcast over them, the depths
    below the horizon; aimed at Add Ocean's sun (`aim_sky` aims it at the scene's each frame)."""
    w = bpy.data.worlds.new(WORLD)
    w[TAG] = True
    g = Graph(empty_tree(w))
    direction = g.node("ShaderNodeTexCoord").outputs["Generated"]
    sky = _sky_texture(g, direction)
    toward = g.node("ShaderNodeCombineXYZ")
    toward.name = toward.label = GLOW
    disc = g.node("ShaderNodeCombineXYZ")
    disc.name = disc.label = DISC
    cos = g.vector("DOT_PRODUCT", direction, toward.outputs[0])
    inside = g.math("GREATER_THAN", cos, math.cos(math.radians(daylight.SUN_SIZE / 2.0)))
    sunshape = g.mix(inside, daylight.aureole(g, g.math("ARCCOSINE", g.math("MINIMUM", cos,
                                                                               1.0))), 1.0)
    seen = g.math("MULTIPLY", sunshape, g.node("ShaderNodeLightPath").outputs["Is Camera Ray"])
    clear = g.vector("ADD", sky, g.vector("SCALE", disc.outputs[0], Scale=seen))
    background = g.node("ShaderNodeBackground", {"Color": clear, "Strength": 1.0})
    background.name = BACKGROUND
    output = g.node("ShaderNodeOutputWorld")
    g.set(output.inputs["Surface"], background.outputs[0])
    sky_or_cloud = socket(_overcast(g).outputs, "Result_Color")
    # below the horizon the depths (what total internal reflection shows from under water)
    depths = g.node("ShaderNodeCombineXYZ")
    depths.name = depths.label = DEPTHS
    z = g.node("ShaderNodeSeparateXYZ", {0: direction}).outputs["Z"]
    below = g.clamp(g.math("MULTIPLY", z, -1.0 / DEPTHS_BLEND))
    g.set(background.inputs["Color"], socket(g.node(
        "ShaderNodeMix", {"Factor_Float": below, "A_Color": sky_or_cloud,
                          "B_Color": depths.outputs[0]}, data_type="RGBA").outputs,
        "Result_Color"))
    aim_sky(w, _toward(SUN_ELEVATION, 0.0))
    return w


def _sky_texture(g, direction):
    """Our sky's radiance toward `direction` in graph `g`: Blender's Sky Texture (node SKY,
    aimed by `aim_sky`) times daylight.SKY_SCALE."""
    sky = g.node("ShaderNodeTexSky", {"Vector": direction},
                 sky_type=daylight.MODEL if bpy.app.version >= (5, 0, 0) else "NISHITA",
                 sun_disc=False, altitude=daylight.SKY_ALTITUDE)
    sky.name = sky.label = SKY
    return g.vector("SCALE", sky.outputs["Color"], Scale=daylight.SKY_SCALE)


def _overcast_radiance(g, height, shade):
    """The overcast's radiance `height` (sin of the elevation, 0 to 1) up: the CIE standard
    overcast sky's (1 + 2 sin h) / 3 of the zenith's, times the cloud's `shade`."""
    cie = g.math("DIVIDE", g.math("MULTIPLY_ADD", height, 2.0, 1.0), 3.0)
    return g.vector("SCALE", OVERCAST_ZENITH, Scale=g.math("MULTIPLY", cie, shade))


# The air's light is read this far (sin of the elevation) above the view's mirror image.
HORIZON_RISE = 0.002


def horizon(g, incoming, cloud):
    """The air's light for the aerial perspective (daylight.haze) in graph `g`: our sky's
    radiance in the view's direction mirrored up (`incoming`, toward the camera, turned
    over), as the world draws it, under `cloud` (0 to 1) of overcast (its cloud's mean):
    along a level view the horizon sky's (Koschmieder's), looking down a steeper, shorter
    path's, bluer and dimmer, up to the zenith's straight down. Its Sky Texture is aimed with
    the world's (`aim_sky`'s `trees`)."""
    away = g.node("ShaderNodeSeparateXYZ", {0: incoming}).outputs
    up = g.math("ADD", g.math("MAXIMUM", away["Z"], 0.0), HORIZON_RISE)
    direction = g.vector("NORMALIZE", g.node("ShaderNodeCombineXYZ", {
        "X": g.math("MULTIPLY", away["X"], -1.0), "Y": g.math("MULTIPLY", away["Y"], -1.0),
        "Z": up}).outputs[0])
    height = g.node("ShaderNodeSeparateXYZ", {0: direction}).outputs["Z"]
    return socket(g.node("ShaderNodeMix", {
        "Factor_Float": cloud, "A_Color": _sky_texture(g, direction),
        "B_Color": _overcast_radiance(g, height, 1.0)}, data_type="RGBA").outputs,
        "Result_Color")


def through_air(g, shader, extinction, cloud, distance, incoming, fade=1.0):
    """A Mix Shader in graph `g`: `shader` seen `distance` m away through air of `extinction`
    per metre (daylight.haze, times `fade`, 0 to 1), the rest the air's light (`horizon`
    along `incoming` under `cloud`), so the water and the spray above it fade alike."""
    airlight = g.node("ShaderNodeEmission", {"Color": horizon(g, incoming, cloud)})
    return g.node("ShaderNodeMixShader", {0: daylight.haze(g, extinction, distance) * fade,
                                          1: shader, 2: airlight.outputs[0]})


def _toward(elevation, azimuth):
    """Unit vector toward a sun `elevation` degrees up, shining from `azimuth` (`aim`)."""
    e, a = math.radians(elevation), math.radians(azimuth)
    return (-math.cos(e) * math.sin(a), math.cos(e) * math.cos(a), math.sin(e))


def _overcast(g):
    """Put the overcast between the clear sky and the Background of our world's graph `g`, at
    a factor of 0 (a world made before it had none)."""
    colour = g.nodes[BACKGROUND].inputs["Color"]
    clear = colour.links[0].from_socket if colour.links else tuple(colour.default_value)
    direction = g.node("ShaderNodeTexCoord").outputs["Generated"]
    height = g.clamp(g.node("ShaderNodeSeparateXYZ", {0: direction}).outputs["Z"])
    base = g.vector("SCALE", direction, Scale=g.math("DIVIDE", 1.0, g.math("MAXIMUM", height,
                                                                             0.02)))
    cloud = g.node("ShaderNodeTexNoise", {"Vector": base, "Scale": CLOUD_SCALE,
                                          "Detail": CLOUD_DETAIL, "Roughness": CLOUD_ROUGHNESS})
    # fading out below 10 degrees up
    shade = cloud_shade(g, g.value(cloud.outputs["Fac"]), g.clamp(g.math("MULTIPLY", height, 6.0)))
    mix = g.node("ShaderNodeMix", {"Factor_Float": 0.0, "A_Color": clear,
                                   "B_Color": _overcast_radiance(g, height, shade)},
                 data_type="RGBA")
    mix.name = mix.label = OVERCAST
    g.set(colour, socket(mix.outputs, "Result_Color"))
    return mix


def _ours(block):
    """Whether `block` (a world, a lamp or a node group) is one we made and may write: not a
    library's, nor a library override's."""
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
            light.angle = math.radians(SUN_ANGLE[0] + (SUN_ANGLE[1] - SUN_ANGLE[0]) * cloud)
            follow_sun(obj, cloud, model(world), force=True)


def sun(collection, elevation=SUN_ELEVATION, azimuth=0.0):
    """A sun lamp `elevation` degrees above the horizon, shining from `azimuth` (`aim`), with
    the light of our sky's sun there (`follow_sun`)."""
    data = bpy.data.lights.new(SUN, "SUN")
    data[TAG] = True
    data.angle = math.radians(SUN_ANGLE[0])
    obj = bpy.data.objects.new(SUN, data)
    aim(obj, elevation, azimuth)
    collection.objects.link(obj)
    follow_sun(obj, 0.0, model(bpy.context.scene.world), force=True)
    return obj


def follow_sun(obj, cloud, sky_model, force=False, matrix=None):
    """Give our sun lamp `obj` (at world `matrix`, default its own) the colour and strength of
    our sky's sun at its elevation (daylight.sunlight of `sky_model`), dimmed under `cloud`
    (0 to 1): only while they are as we last set them (`force`: set them anyway), so a user's
    own colour or strength stays. Another lamp, or a library's, is left alone."""
    light = obj.data if obj is not None and obj.type == "LIGHT" else None
    if light is None or light.type != "SUN" or not _ours(light):
        return
    now = (light.energy, *light.color)
    last = light.get(LIGHT)
    if not force and last is not None and any(abs(a - b) > 1e-4 * max(abs(b), 1.0)
                                               for a, b in zip(now, last, strict=True)):
        return
    elevation = shading.sun_elevation(shading.sun_direction(
        obj.matrix_world if matrix is None else matrix))
    energy, colour = daylight.sunlight(elevation, sky_model)
    want = (energy * _under_cloud(cloud), *colour)
    if any(abs(a - b) > 1e-6 * max(abs(b), 1.0) for a, b in zip(now, want, strict=True)):
        light.energy, light.color = want[0], want[1:]
    kept = (light.energy, *light.color)
    if last is None or tuple(last) != kept:  # each write would update the scene again
        light[LIGHT] = kept


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


def hazes(world):
    """Whether the water's aerial perspective may draw our sky's light (`horizon`): `world`
    is ours, with its Sky Texture (another world's light is unknown to the water)."""
    return _ours(world) and world.node_tree is not None and SKY in world.node_tree.nodes


def overcast(world):
    """How far our sky world is turned to the overcast (`weather`; 0 clear, 1 full): its
    Overcast node's factor; another world, or ours from before it had one, 0."""
    node = (world.node_tree.nodes.get(OVERCAST) if world is not None and world.get(TAG)
            and world.node_tree is not None else None)
    return float(node.inputs["Factor"].default_value) if node is not None else 0.0


def depths(elevation, cloud, sun, sky_model):
    """RGB radiance of deep water seen from within: the Water Colour Add Ocean gives (in
    DAYLIGHT) times the light on the sea against it (optics.body_light), with the sun
    `elevation` degrees up (if `sun`: a sun lamp shines), under `cloud` (0 to 1)."""
    sun_light = (_under_cloud(cloud) * np.array(daylight.sun_on_sea(elevation, sky_model))
                 if sun else 0.0)
    light = optics.body_light(sun_light, optics.sky_irradiance(1.0, cloud, elevation,
                                                               sky_model))
    return tuple(float(c * v) for c, v in zip(WATER_COLOUR, light, strict=True))


def _under_cloud(cloud):
    """Our sun lamp's strength under `cloud` (0 to 1) against a clear sky's."""
    return 1.0 - (1.0 - SUN_UNDER_CLOUD) * cloud


def model(world):
    """The Sky Texture model of our world (`daylight.MODELS`); another world's light is
    taken as Blender 5's sky (daylight.MODEL)."""
    node = (world.node_tree.nodes.get(SKY) if world is not None and world.get(TAG)
            and world.node_tree is not None else None)
    return node.sky_type if node is not None and node.sky_type in daylight.MODELS else (
        daylight.MODEL)


def aim_sky(world, toward, trees=()):
    """Aim our world's sky and sun disc at the sun: `toward` the unit vector to it, None
    without a sun lamp (no disc; the sky keeps its last sun); and the Sky Texture of each of
    our node `trees` or materials (`horizon`'s: the water group's, the spray's). Another
    world, or a library's, is left alone; a world of ours made before the Sky Texture gets its
    glow aimed."""
    nodes = world.node_tree.nodes if _ours(world) and world.node_tree is not None else {}
    values = (0.0, 0.0, 0.0) if toward is None else tuple(float(v) for v in toward)
    sky, disc, deep = nodes.get(SKY), nodes.get(DISC), nodes.get(DEPTHS)
    sky_model = model(world)
    elevation = shading.sun_elevation(values)
    if toward is not None:
        sun = (math.radians(elevation), math.atan2(values[0], values[1]) % (2.0 * math.pi))
    else:  # the trees' skies keep the world's last sun
        sun = None if sky is None else (sky.sun_elevation, sky.sun_rotation)
    for node in (sky, *(_ours(t) and getattr(t, "node_tree", t).nodes.get(SKY)
                        for t in trees)):
        if node and sun is not None:
            _set(node, "sun_elevation", sun[0])
            _set(node, "sun_rotation", sun[1])
    if disc is not None:
        radiance = ((0.0, 0.0, 0.0) if toward is None else
                    daylight.disc_radiance(elevation, sky_model))
        for input_, value in zip(disc.inputs, radiance, strict=True):
            _set(input_, "default_value", value)
    if deep is not None and sky is not None:
        shown = math.degrees(sky.sun_elevation) if toward is None else elevation
        for input_, value in zip(deep.inputs, depths(shown, overcast(world), toward is not None,
                                                     sky_model), strict=True):
            _set(input_, "default_value", value)
    glow = nodes.get(GLOW)
    for input_, value in zip(glow.inputs if glow is not None else (), values, strict=False):
        _set(input_, "default_value", value)


def _set(block, name, value):
    """Set `block.name` to `value` only if it changed (each write re-evaluates the world)."""
    if abs(getattr(block, name) - value) > 1e-6 * max(abs(value), 1.0):
        setattr(block, name, value)
