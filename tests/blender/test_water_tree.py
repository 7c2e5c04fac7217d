"""The water group's node tree computes what the core says it does: its roughness and its
slope layer's gains, evaluated node by node in Python (a shader cannot be run without a
render), against shading.unresolved_slope_variance and shading.layer_gain."""

import itertools
import math

import bpy
import numpy as np
import pytest

from .helpers import spectral_sea


def _safe_log(a, b):
    return math.log(a) / math.log(b) if a > 0.0 and b > 0.0 and b != 1.0 else 0.0


def _safe_pow(a, b):
    if a < 0.0 and b != int(b):
        return 0.0
    return a**b if a != 0.0 or b > 0.0 else 0.0


MATH = {
    "ADD": lambda a, b, c: a + b, "SUBTRACT": lambda a, b, c: a - b,
    "MULTIPLY": lambda a, b, c: a * b, "DIVIDE": lambda a, b, c: a / b if b != 0.0 else 0.0,
    "MULTIPLY_ADD": lambda a, b, c: a * b + c, "MAXIMUM": lambda a, b, c: max(a, b),
    "MINIMUM": lambda a, b, c: min(a, b), "ABSOLUTE": lambda a, b, c: abs(a),
    "SQRT": lambda a, b, c: math.sqrt(a) if a > 0.0 else 0.0,
    "LOGARITHM": lambda a, b, c: _safe_log(a, b), "POWER": lambda a, b, c: _safe_pow(a, b),
    "EXPONENT": lambda a, b, c: math.exp(a), "LESS_THAN": lambda a, b, c: float(a < b),
    "COSINE": lambda a, b, c: math.cos(a), "SINE": lambda a, b, c: math.sin(a),
    "GREATER_THAN": lambda a, b, c: float(a > b),
}
VECTOR = {
    "ADD": lambda a, b, s: a + b, "SUBTRACT": lambda a, b, s: a - b,
    "MULTIPLY": lambda a, b, s: a * b, "SCALE": lambda a, b, s: a * s,
    "MINIMUM": lambda a, b, s: np.minimum(a, b),
    "NORMALIZE": lambda a, b, s: a / np.linalg.norm(a) if np.linalg.norm(a) else a * 0.0,
}


FACET_RANDOM = (0.3, 0.2)


class Evaluator:
    """Values of a shader node tree's sockets for given group inputs and stubbed scene inputs
    (the nodes a render would feed: attribute, camera data, geometry)."""

    def __init__(self, group_inputs, lod, distance, incoming, attributes=None, fac=0.5):
        self.inputs, self.cache, self.attributes = group_inputs, {}, attributes or {}
        self.stubs = {"ShaderNodeAttribute": {"Fac": lod},
                      "ShaderNodeCameraData": {"View Distance": distance},
                      "ShaderNodeNewGeometry": {"Incoming": np.asarray(incoming, float),
                                                "Normal": np.array([0.0, 0.0, 1.0]),
                                                "Backfacing": 0.0},
                      # the waves' bumps: a flat sea's normal (the glint's sun reach uses it)
                      "ShaderNodeBump": {"Normal": np.array([0.0, 0.0, 1.0])},
                      # the glint facet's cell: its two random values
                      "ShaderNodeTexVoronoi": {"Color": np.array([*FACET_RANDOM, 0.5])},
                      "ShaderNodeTexNoise": {"Fac": fac}}

    def input(self, socket):
        if socket.is_linked:
            return self.output(socket.links[0].from_socket)
        value = socket.default_value
        return np.array(value[:3], float) if hasattr(value, "__len__") else float(value)

    def output(self, socket):
        key = socket.as_pointer()
        if key not in self.cache:
            self.cache[key] = self._compute(socket.node, socket)
        return self.cache[key]

    def _compute(self, node, socket):
        kind = node.bl_idname
        if kind == "NodeGroupInput":
            return self.inputs[socket.name]
        if kind == "ShaderNodeAttribute" and node.attribute_name in self.attributes:
            return self.attributes[node.attribute_name]
        if kind == "ShaderNodeMix":
            t, a, b = (self.input(next(s for s in node.inputs if s.identifier == k))
                       for k in ("Factor_Float", "A_Float", "B_Float"))
            return a + t * (b - a)
        if kind in self.stubs:
            stub = self.stubs[kind]
            return stub[socket.identifier] if socket.identifier in stub else stub[socket.name]
        if kind == "ShaderNodeMath":
            a, b, c = (self.input(s) for s in node.inputs[:3])
            v = MATH[node.operation](a, b, c)
            return min(max(v, 0.0), 1.0) if node.use_clamp else v
        if kind == "ShaderNodeVectorMath":
            a, b = self.input(node.inputs[0]), self.input(node.inputs[1])
            s = self.input(node.inputs["Scale"]) if node.operation == "SCALE" else None
            if node.operation == "DOT_PRODUCT":
                return float(np.dot(a, b))
            if node.operation == "LENGTH":
                return float(np.linalg.norm(a))
            return VECTOR[node.operation](a, b, s)
        if kind == "ShaderNodeSeparateColor":
            return float(self.input(node.inputs[0])[("Red", "Green", "Blue").index(socket.name)])
        if kind == "ShaderNodeSeparateXYZ":
            return float(self.input(node.inputs[0])["XYZ".index(socket.name)])
        if kind == "ShaderNodeCombineXYZ":
            return np.array([self.input(node.inputs[k]) for k in "XYZ"], float)
        raise NotImplementedError(kind)


@pytest.fixture
def water(extension):
    """The spectral sea's water group, the material's group node, and the core's modules."""
    obj = spectral_sea()
    core = extension.projgrid_addon
    material = extension.operators.bridge.material_inputs.material_of(obj.data)
    node = material.node_tree.nodes[extension.shaders.water.GROUP]
    return node, core


def _settings(node, core):
    values = {s.name: (np.array(s.default_value[:3], float)
                       if hasattr(s.default_value, "__len__") else float(s.default_value))
              for s in node.inputs if hasattr(s, "default_value")}
    f = core.shading.Filtering(
        pixel_log=values["Pixel Log"], distance_power=values["Distance Power"],
        floor=values["Slope Floor"], ripple=values["Ripple Slopes"],
        cos_floor=values["Cos Floor"], ripple_gain=1.0, density=values["Slope Density"],
        shortest_log=values["Shortest Log"], ripple_top_log=values["Ripple Top Log"],
        ceiling=values["Slope Ceiling"], layer_top_log=values["Layer Top Log"],
        layer_density=values["Layer Density"], left_out_log=values["Left Out Log"],
        facet_log=values["Facet Log"], facets_sharp_log=values["Facets Sharp Log"],
        facets_mean_log=values["Facets Mean Log"], sun_reach=values["Sun Reach"],
        gust=values["Gust Amplitude"])
    bands = [core.slope_layer.LayerBand(values[f"Layer Level {b}"], values[f"Layer Top Log {b}"],
                                        values[f"Layer Bottom Log {b}"]) for b in (1, 2, 3)]
    return values, f, bands


CASES = [(d, c, lod) for d in (3.0, 15.0, 40.0, 400.0, 4000.0) for c in (0.05, 0.4, 1.0)
         for lod in (-6.0, -1.5, 0.7, 3.0)]


def test_the_roughness_is_the_core_s(water, extension):
    """The lobe's roughness is the slope variance not drawn, less what the glint's facets
    draw of it (shading.facet_variance), which near the camera is not nothing; the gusts
    scale the ripples' share by the core's factor (shading.gust) wherever their noise is, and
    the ripples' bump height by its root."""
    node, core = water
    shaders = extension.shaders.water
    values, f, _ = _settings(node, core)
    assert f.layer_density > 0.0 and f.density > 0.0  # the spectral sea's: not a trivial case
    tree = node.node_tree
    glossy = next(n for n in tree.nodes if n.bl_idname in (
        "ShaderNodeBsdfGlossy", "ShaderNodeBsdfAnisotropic") and n.inputs["Roughness"].is_linked)
    # the ripples' bump (the one bumping the detail's normal): its height by sqrt(gust)
    ripples = next(n for n in tree.nodes
                   if n.bl_idname == "ShaderNodeBump" and n.inputs["Normal"].is_linked)
    seen, facets, gusts, bumped = set(), set(), set(), set()
    for (d, c, lod), sun, fac in zip(CASES, itertools.cycle((0.0, 0.3, 1.0, None)),
                                     itertools.cycle((0.5, 0.38, 0.6, 0.71, 0.45)),
                                     strict=False):
        # the sun where the view's mirror is (a facet as flat as the sea shows it), `sun`
        # radians above it (the half vector sun / 2 from the normal), or no sun lamp
        s = math.sqrt(1.0 - c * c)
        toward = (0.0, 0.0, 0.0) if sun is None else (
            c * math.sin(sun) - s * math.cos(sun), 0.0, c * math.cos(sun) + s * math.sin(sun))
        ev = Evaluator({**values, "Sun Direction": np.array(toward)}, lod, d, (s, 0.0, c),
                       fac=fac)
        drawn = ev.input(glossy.inputs["Roughness"]) ** 4
        gust = float(core.shading.gust(fac, core.shading.footprint_log(f, d, c),
                                       shaders.GUST_SCALE, f.gust, shaders.GUST_FAC_STD))
        facet = (0.0 if sun is None else float(core.shading.facet_variance(
            f, d, c, math.tan(sun / 2.0) ** 2, gust)))
        want = float(core.shading.unresolved_slope_variance(f, d, c, lod, gust)) - facet
        assert drawn == pytest.approx(want, rel=1e-5, abs=1e-9), (d, c, lod, sun)
        # the glossy's normal: the flat sea's tilted by the facet's slopes (Box-Muller from
        # its cell's two random values, facet / 2 per axis)
        u, w = FACET_RANDOM
        slope = math.sqrt(-2.0 * math.log(u) * facet / 2.0)
        tilt = np.array([slope * math.cos(2 * math.pi * w), slope * math.sin(2 * math.pi * w),
                         1.0])
        assert ev.input(glossy.inputs["Normal"]) == pytest.approx(
            tilt / np.linalg.norm(tilt), abs=1e-6), (d, c, lod, sun)
        seen.add(round(want, 6))
        facets.add(round(facet, 6))
        gusts.add(round(gust, 3))
        steady = Evaluator({**values, "Sun Direction": np.array(toward)}, lod, d, (s, 0.0, c))
        height = steady.input(ripples.inputs["Distance"])
        if height > 0.0:
            assert ev.input(ripples.inputs["Distance"]) == pytest.approx(
                height * math.sqrt(gust), rel=1e-5), (d, c, lod, fac)
            bumped.add(round(gust, 3))
    assert len(seen) > 10  # the cases reach different parts of the formula
    assert len(facets) > 2 and max(facets) > 0.1 * f.ripple  # and the facets' share
    # and calm and gusty patches, beyond a standard deviation of the wind each way
    assert f.gust > 0.1 and min(gusts) < 1.0 - f.gust and max(gusts) > 1.0 + f.gust
    assert min(bumped) < 0.95 and max(bumped) > 1.05  # bumps of calm and gusty patches


def test_the_slope_layer_s_gains_are_the_core_s(water):
    node, core = water
    values, f, bands = _settings(node, core)
    tree = node.node_tree
    tilt = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeVectorMath"
                and n.operation == "MULTIPLY" and n.inputs[1].is_linked
                and n.inputs[1].links[0].from_node.bl_idname == "ShaderNodeCombineXYZ")
    seen = set()
    for b, band in enumerate(bands, start=1):
        for d, c, lod in CASES:
            one = {**values, **{f"Layer Slopes {k}": np.array([float(k == b), 0.0, 0.0])
                                for k in (1, 2, 3)}}
            ev = Evaluator(one, lod, d, (math.sqrt(1.0 - c * c), 0.0, c))
            drawn = -ev.output(tilt.outputs[0])[0]  # tilted against the slope, up = 1
            want = float(core.shading.layer_gain(band, lod, core.shading.footprint_log(f, d, c)))
            assert drawn == pytest.approx(want, rel=1e-5, abs=1e-7), (b, d, c, lod)
            seen.add(round(want, 4))
    assert len(seen) > 8 and 0.0 in seen and max(seen) > 0.5


def test_the_foam_is_the_core_s(water, extension):
    """The foam drawn (the Foam mix's factor) is shading.foam_cover's: the grain's top ranks
    covering the vertex's share near, the sea's mean share where a pixel is longer than a
    whitecap, and far whitecaps still drawn by the grain while the pixel's area is small."""
    node, core = water
    shaders = extension.shaders.water
    values, f, _ = _settings(node, core)
    values["Foam Coverage"] = coverage = 0.03
    mix = node.node_tree.nodes["Foam"].inputs[0]
    grain = 1.0 / (shaders.FOAM_GRAIN * math.sqrt(shaders.FOAM_STREAK))
    seen = set()
    for d, c, share, fac in itertools.product((3.0, 40.0, 400.0, 4000.0, 40000.0),
                                              (0.05, 0.4, 1.0), (0.0, 0.01, 0.6),
                                              (0.3, 0.5, 0.62)):
        ev = Evaluator(values, 0.0, d, (math.sqrt(1.0 - c * c), 0.0, c),
                       attributes={shaders.FOAM_ATTRIBUTE: share}, fac=fac)
        want = float(core.shading.foam_cover(
            f, d, c, share, coverage, fac, shaders.FOAM_GRAIN_STD, shaders.FOAM_RANK, grain,
            shaders.WHITECAP))
        assert ev.input(mix) == pytest.approx(want, rel=1e-5, abs=1e-6), (d, c, share, fac)
        seen.add(round(want, 3))
    assert {0.0, 1.0, coverage} <= seen and len(seen) > 5


def test_daylight_is_add_ocean_s_sky_and_sun(water, extension):
    """DAYLIGHT, under which the water scatters back its Water Colour, is the irradiance Add
    Ocean's sky (its gradient and glow around the sun) and sun lamp put on the mean sea plane,
    integrated here over the sky's hemisphere; and the group's diffuse albedo gives it back."""
    sky, water_module = extension.shaders.sky, extension.shaders.water
    look = extension.projgrid_addon.look
    sun_lamp = next(o for o in bpy.context.scene.objects if o.type == "LIGHT")
    toward = np.array(sun_lamp.matrix_world)[:3, 2]
    n = 300
    theta, phi = np.meshgrid((np.arange(n) + 0.5) / n * math.pi / 2.0,
                             (np.arange(2 * n) + 0.5) / n * math.pi, indexing="ij")
    d = np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)], -1)
    pos = [p for p, _ in sky.GRADIENT]
    low, high = sky.RAMP_Z
    t = np.clip((d[..., 2] - low) / (high - low), 0.0, 1.0)
    radiance = np.stack([np.interp(t, pos, [c[k] for _, c in sky.GRADIENT]) for k in range(3)],
                        axis=-1)
    g = sky.GLOW_G
    phase = (1.0 - g * g) / (1.0 + g * g - 2.0 * g * (d @ toward)) ** 1.5
    radiance = radiance + np.asarray(sky.GLOW_COLOUR) * phase[..., None]
    weight = np.cos(theta) * np.sin(theta) * (math.pi / 2.0 / n) * (math.pi / n)
    irradiance = (radiance * weight[..., None]).sum(axis=(0, 1))
    sun = sun_lamp.data.energy * max(toward[2], 0.0)
    assert sun == pytest.approx(sky.SUN_STRENGTH * math.sin(math.radians(sky.SUN_ELEVATION)))
    assert look.DAYLIGHT_SUN == pytest.approx(sun, rel=1e-3)
    irradiance += sun * np.array(sun_lamp.data.color)
    assert np.asarray(water_module.DAYLIGHT) == pytest.approx(irradiance, rel=0.01)

    node, core = water
    values, _, _ = _settings(node, core)
    diffuse = next(n for n in node.node_tree.nodes if n.bl_idname == "ShaderNodeBsdfDiffuse"
                   and n.inputs["Color"].is_linked
                   and n.inputs["Color"].links[0].from_node.bl_idname == "ShaderNodeVectorMath")
    albedo = Evaluator(values, 0.0, 10.0, (0.0, 0.0, 1.0)).input(diffuse.inputs["Color"])
    assert albedo * np.asarray(water_module.DAYLIGHT) / math.pi == pytest.approx(
        values["Water Colour"], rel=1e-4)
    # A colour brighter than the daylight can give back scatters all it receives, no more.
    bright = {**values, "Water Colour": np.array([0.9, 0.2, 0.9])}
    albedo = Evaluator(bright, 0.0, 10.0, (0.0, 0.0, 1.0)).input(diffuse.inputs["Color"])
    assert albedo == pytest.approx([1.0, 0.2 * math.pi / water_module.DAYLIGHT[1], 1.0])
    # Lit, not glowing: nothing in the group emits (a dusk sea would shine in the dark).
    assert not any(n.bl_idname == "ShaderNodeEmission" for n in node.node_tree.nodes)
