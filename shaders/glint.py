"""The glint's facets in the water group (Jakob et al. 2014; Zirr and Kaplanyan 2016): near the
camera the ripples' undrawn slopes are facets a few centimetres across, each with a normal of
its own, so the sun sparkles on them (water_model.facet_variance)."""

import math

from ..projgrid_addon import water_model as model


def glint_facets(g, i, geo, normal, footprint, log_cos, ripples):
    """(tilt, slope variance) of the glint's facets (model.facet_variance): cells of Facet Log
    on the sea (a Voronoi's, reshuffling with the ripples' time so the glitter twinkles), each
    tilted by a normal slope of that variance per axis halved (Box-Muller from the cell's two
    random values), added to the normal before it is normalised; none on back faces, nor
    where no facet shows the sun (nor without a sun lamp: a Sun Direction of 0). `log_cos`:
    ln of the view's cos to the sea plane as the footprint takes it; `ripples`: the ripples'
    undrawn slope variance."""
    half = g.vector("NORMALIZE", g.vector("ADD", geo["Incoming"], i["Sun Direction"]))
    variance = model.facet_variance(
        g, i, footprint, log_cos, 1.0 - g.value(geo["Backfacing"]),
        g.max(g.vector("DOT_PRODUCT", normal, half), 0.01),
        g.min(g.vector("LENGTH", i["Sun Direction"]), 1.0), ripples)
    cell = g.exp(i["Facet Log"])
    xyz = g.node("ShaderNodeSeparateXYZ", {0: geo["Position"]}).outputs
    at = g.node("ShaderNodeCombineXYZ", {"X": xyz["X"], "Y": xyz["Y"],
                                         "Z": i["Ripple Time"] * cell})
    random = g.node("ShaderNodeSeparateColor", {0: g.node("ShaderNodeTexVoronoi", {
        "Vector": at.outputs[0], "Scale": 1.0 / cell},
        voronoi_dimensions="3D").outputs["Color"]}).outputs
    spread = g.sqrt(g.log(g.max(g.value(random[0]), 1e-6)) * -2.0) * g.sqrt(variance * 0.5)
    angle = g.value(random[1]) * (2.0 * math.pi)
    tilt = g.node("ShaderNodeCombineXYZ", {"X": spread * g.cos(angle),
                                           "Y": spread * g.sin(angle)}).outputs[0]
    return tilt, variance
