"""The glint's facets in the water group (Jakob et al. 2014; Zirr and Kaplanyan 2016): near the
camera the ripples' undrawn slopes are facets a few centimetres across, each with a normal of
its own, so the sun sparkles on them (shading.facet_variance)."""

import math


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
        "MAXIMUM", random[0], 1e-6), math.e), -2.0)), g.math("SQRT", g.math(
            "MULTIPLY", variance, 0.5)))
    angle = g.math("MULTIPLY", random[1], 2.0 * math.pi)
    tilt = g.node("ShaderNodeCombineXYZ", {
        "X": g.math("MULTIPLY", spread, g.math("COSINE", angle)),
        "Y": g.math("MULTIPLY", spread, g.math("SINE", angle))}).outputs[0]
    return tilt, variance
