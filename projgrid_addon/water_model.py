"""The water shading's model, written once: the group's inputs and the formulas of the look
(thesis §3.4; Bruneton, Neyret and Holzschuch 2010; Fresnel; Jensen and Golias's foam).
shaders/water.py builds the "Projected Grid Water" node tree by calling these formulas with a
node graph; the tests call them with NumPy and evaluate the built tree, and compare both with
the published formulas (Cox and Munk, Fresnel, Monahan).

Each formula takes `m`, the maths it is evaluated in: + - * / on its values, and the methods
max, min, clamp (to [0, 1]), log (natural), exp, sqrt (of a negative: 0), pow, abs, less and
greater (1 or 0), mix(t, a, b) = a + t (b - a), cos and sin, as Blender's Math node has them.
`i` maps the group's input names (INPUTS) to values. bpy-free and NumPy-free."""

import math

from .look import (
    AGED_FILM,
    BUBBLE_ALBEDO,
    BUBBLE_PATH,
    BUBBLE_RESIDUAL,
    BUBBLE_SPREAD,
    FILM_FILL,
    FILM_WEB,
    FOAM_AGED,
    FOAM_BLOWN,
    FOAM_COLOUR,
    FOAM_EDGE,
    FOAM_GRAIN,
    FOAM_GRAIN_STD,
    FOAM_LACE,
    FOAM_NET,
    FOAM_RANK,
    FOAM_STREAK,
    FOAM_TEXTURE,
    GUST_FAC_STD,
    GUST_SCALE,
    RESIDUAL_BRIGHTNESS,
    WATER_COLOUR,
    WHITECAP,
)

LN2 = math.log(2.0)
LINE_PIXELS = 2.0  # a line is drawn while a pixel is at most this many times its width
LAYER_BANDS = 3
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
    # m the gusts have drifted with the wind (shading.wind_run)
    ("Gust Drift X", "NodeSocketFloat", 0.0),
    ("Gust Drift Y", "NodeSocketFloat", 0.0),
    ("Gust Path", "NodeSocketFloat", 0.0),
    ("Gust Amplitude", "NodeSocketFloat", 0.0),  # shading.Filtering.gust
    ("Gust Norm", "NodeSocketFloat", 1.0),  # shading.Filtering.gust_norm
    ("Wind Direction", "NodeSocketFloat", 0.0),  # radians, counter-clockwise from +X
    # The share of the sea the active whitecaps cover, their young residual foam's and their
    # aged foam's, and how much longer along the wind than across the residual's lace and
    # streaks are, and the share the wind's blown streaks cover besides (foam.foam_look).
    ("Foam Coverage", "NodeSocketFloat", 0.0),
    ("Residual Coverage", "NodeSocketFloat", 0.0),
    ("Aged Coverage", "NodeSocketFloat", 0.0),
    ("Foam Streak", "NodeSocketFloat", 1.0),
    ("Blown Coverage", "NodeSocketFloat", 0.0),
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
    # The glint's facets (`facet_variance`): ln of their size, of the facets a pixel holds
    # while it sparkles fully, and of those from which it shows the mean lobe.
    ("Facet Log", "NodeSocketFloat", -4.17),
    ("Facets Sharp Log", "NodeSocketFloat", 1.386),
    ("Facets Mean Log", "NodeSocketFloat", 6.931),
    ("Sun Reach", "NodeSocketFloat", 100.0),
    ("Body Reach", "NodeSocketFloat", 1e6),  # m: as far as the water body is drawn (`body_seen`)
    ("Sun Direction", "NodeSocketVector", (0.0, 0.0, 0.0)),  # toward the sun lamp; none: 0
    ("Haze", "NodeSocketFloat", 0.0),  # per m: the air's extinction (daylight.haze_extinction)
    ("Overcast", "NodeSocketFloat", 0.0),  # how far our sky is overcast (the haze's light)
    ("Layer Top Log", "NodeSocketFloat", -100.0),
    ("Layer Density", "NodeSocketFloat", 0.0),
    # The slope layer's bands (slope_layer.py): slopes from the material's images, the band
    # limit from which the vertices hold each, its waves' range (ln m).
    *((f"Layer Slopes {b}", "NodeSocketVector", (0.0, 0.0, 0.0))
      for b in range(1, LAYER_BANDS + 1)),
    *((f"Layer Level {b}", "NodeSocketFloat", -100.0) for b in range(1, LAYER_BANDS + 1)),
    *((f"Layer Top Log {b}", "NodeSocketFloat", 0.0) for b in range(1, LAYER_BANDS + 1)),
    *((f"Layer Bottom Log {b}", "NodeSocketFloat", -1.0) for b in range(1, LAYER_BANDS + 1)),
)
DEFAULTS = {name: default for name, _, default in INPUTS}
BODY_FADE = 0.25  # of Body Reach: the water body fades out over it (`body_seen`)


def values(filtering, detail=None, ripple=None, wind_direction=0.0, foam=None, layer=(),
           haze=0.0, overcast=0.0):
    """The group's float inputs for a frame: the filtering of the waves too short to draw
    (shading.Filtering), the left-out octaves and the ripples (shading.Detail; None: the
    defaults), the wind's direction (radians), the foam's (active, residual and aged shares,
    streak, blown share: foam.foam_look; None: no foam), the slope layer's bands ((level,
    top log, bottom log) each; those missing draw nothing), the air's extinction per metre
    (0: no haze) and how far our sky is overcast (0 to 1)."""
    f = filtering
    foam = (0.0, 0.0, 0.0, 1.0, 0.0) if foam is None else foam
    out = {
        "Pixel Log": f.pixel_log, "Distance Power": f.distance_power, "Cos Floor": f.cos_floor,
        "Slope Floor": f.floor, "Ripple Slopes": f.ripple, "Slope Density": f.density,
        "Shortest Log": f.shortest_log, "Ripple Top Log": f.ripple_top_log,
        "Slope Ceiling": f.ceiling, "Facet Log": f.facet_log,
        "Facets Sharp Log": f.facets_sharp_log, "Facets Mean Log": f.facets_mean_log,
        "Sun Reach": f.sun_reach, "Left Out Log": f.left_out_log,
        "Layer Top Log": f.layer_top_log, "Layer Density": f.layer_density,
        "Gust Amplitude": f.gust, "Gust Norm": f.gust_norm,
        "Wind Direction": wind_direction, "Foam Coverage": foam[0],
        "Residual Coverage": foam[1], "Aged Coverage": foam[2], "Foam Streak": foam[3],
        "Blown Coverage": foam[4], "Haze": haze, "Overcast": overcast}
    if detail is not None:
        out.update({"Detail First Octave": detail.first, "Detail Scale": detail.scale,
                    "Detail Octaves": detail.octaves, "Detail Roughness": detail.roughness,
                    "Detail Height": detail.height,
                    "Detail Top Log": -math.log(detail.scale)})
    if ripple is not None:
        out.update({"Ripple Scale": ripple.scale, "Ripple Octaves": ripple.octaves,
                    "Ripple Height": ripple.height * f.ripple_gain})
    for b in range(1, LAYER_BANDS + 1):
        names = (f"Layer Level {b}", f"Layer Top Log {b}", f"Layer Bottom Log {b}")
        band = layer[b - 1] if b <= len(layer) else (DEFAULTS[n] for n in names)
        out.update(zip(names, (float(v) for v in band), strict=True))
    return {name: float(v) for name, v in out.items()}


def body_seen(m, i, distance):
    """How much of the water body (refraction: the surface transparent, the body's volume
    tinting what lies below) a pixel `distance` m from the camera sees: all of it within
    1 - BODY_FADE of Body Reach (as far as EEVEE draws the body's volume), none from Body
    Reach on, where the water's own colour stands in (not the world under a volume that is
    not drawn: from high up, a grey void beyond it)."""
    return m.clamp((i["Body Reach"] - distance) / (i["Body Reach"] * BODY_FADE))


def footprint(m, i, distance, cos_view):
    """(ln L_p, ln cos): the shortest wave a pixel shows at `distance` (m) from the camera,
    PIXELS pixels' footprint stretched where the view meets the mean sea plane at `cos_view`
    (at least Cos Floor: not the waves' faces, or those facing the camera would stay sharp and
    those facing away go milky) (shading.Filtering)."""
    log_cos = m.log(m.max(m.abs(cos_view), i["Cos Floor"]))
    return i["Distance Power"] * m.log(m.max(distance, 1e-6)) + i["Pixel Log"] - log_cos, log_cos


def undrawn(m, top, bottom, footprint_):
    """The share of a log-uniform slope spectrum between wavelengths e^bottom and e^top (ln m)
    whose waves are shorter than the footprint: not drawn, so roughness."""
    return m.clamp((footprint_ - bottom) / m.max(top - bottom, 1e-6))


def octaves_drawn(m, top_log, footprint_, octaves, roughness):
    """A fractal noise bump of `octaves` octaves past its first (wavelength e^top_log, halving)
    keeping only the waves a pixel shows: (its Detail, the share of its height kept, the bump's
    strength). Octave j is whole while log2(top / L_p) >= j + 1; Blender normalises the fractal
    by its octaves' amplitude sum, so the height is kept per octave; the first octave fades with
    the footprint across its band (finer octaves would alias and flicker: their slopes are the
    roughness, counted as `undrawn` counts them)."""
    shown = (top_log - footprint_) / LN2
    detail = m.min(m.max(shown - 1.0, 0.0), octaves)
    r = m.min(roughness, 0.999)  # (1 - r^(n+1)) / (1 - r): n + 1 at r = 1
    kept = (1.0 - m.pow(r, detail + 1.0)) / m.max(1.0 - m.pow(r, octaves + 1.0), 1e-6)
    return detail, kept, m.sqrt(m.clamp(shown))


def layer_gain(m, lod, level, top, bottom, footprint_):
    """How strongly a slope-layer band is drawn at the vertices' band limit `lod`: by
    sqrt(1 - g^2), g the share of it the vertices hold (their tiles are independent of the
    layer's, so the variances add), times the root of the share of its slopes (log-uniform
    between e^bottom and e^top) in waves longer than the footprint."""
    held = m.clamp(lod - level)
    shown = m.clamp((top - footprint_) / m.max(top - bottom, 1e-6))
    return m.sqrt(m.max(1.0 - held * held, 0.0) * shown)


def gust(m, i, fac, footprint_):
    """The factor on the ripples' slope variance where the gusts' noise (GUST_SCALE features per
    metre, its Fac's spread GUST_FAC_STD) is `fac`: max(1 + Gust Amplitude z, 0) times Gust Norm
    (1 / its mean, so the sea's mean slope stays Cox and Munk's), z the local wind's departure
    in standard deviations (a lull leaves the water flat, not negative); faded to 1 as the
    footprint nears a patch, an octave before (a patch no pixel shows would only shimmer)."""
    shown = m.clamp((-math.log(GUST_SCALE) - footprint_) / LN2 - 1.0)
    local = m.max((fac - 0.5) * (i["Gust Amplitude"] / GUST_FAC_STD) + 1.0, 0.0) * i["Gust Norm"]
    return shown * (local - 1.0) + 1.0


def ripples_undrawn(m, i, gust_, footprint_):
    """The ripples' slope variance a pixel does not show, scaled by the gusts."""
    return i["Ripple Slopes"] * gust_ * undrawn(m, i["Ripple Top Log"], i["Shortest Log"],
                                                footprint_)


def roughness(m, i, lod, footprint_, ripples):
    """The slope variance of the waves not drawn at a pixel (shading.Filtering): the ripples'
    undrawn share (`ripples_undrawn`) and the floor; above the ripples the waves shorter than the
    footprint; above the slope layer also those shorter than the geometry holds at the
    vertices' band limit (ln L_g = Left Out Log - lod ln 2); at most the Slope Ceiling."""
    held = i["Left Out Log"] - lod * LN2
    layer_top = m.max(i["Layer Top Log"], i["Ripple Top Log"])
    below = m.min(m.max(footprint_ - i["Ripple Top Log"], 0.0), layer_top - i["Ripple Top Log"])
    above = m.max(m.max(footprint_, held) - layer_top, 0.0)
    return m.min(i["Layer Density"] * above + i["Slope Density"] * below + ripples
                 + i["Slope Floor"], i["Slope Ceiling"])


def fresnel(m, ior, c, backfacing):
    """The exact unpolarised Fresnel reflectance (Eq. 1.4) at |cos| `c` to the normal, from
    above (IOR `ior`) or on back faces from under water (1 / ior; total internal reflection
    where g^2 < 0), in the form of Blender's fresnel_dielectric_cos."""
    eta = m.mix(backfacing, ior, 1.0 / ior)
    g2 = c * c + eta * eta - 1.0
    g = m.sqrt(m.max(g2, 0.0))
    a = (g - c) / (g + c)
    b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0)
    return m.mix(m.less(g2, 0.0), a * a * 0.5 * (b * b + 1.0), 1.0)


def mean_fresnel(m, exact, c, slopes, backfacing):
    """From above, the reflectance less what the facets' slopes (variance `slopes`) take from
    it: Bruneton's fit of the mean Fresnel (2010, Eq. 11), 0.02 + 0.98 (1 - cos)^(5 exp(-2.69
    s)) / (1 + 22.7 s^1.5), s the slope deviation along the view, less its value for a mirror
    (Schlick's), so a mirror keeps the `exact` reflectance and a rough far sea reflects less of
    the sky at grazing. From below, the exact."""
    sigma = m.sqrt(slopes * 0.5)
    facing = m.max(1.0 - c, 0.0)
    mean = m.pow(facing, m.exp(sigma * -2.69) * 5.0) / (m.pow(sigma, 1.5) * 22.7 + 1.0)
    return m.mix(backfacing, m.max((mean - m.pow(facing, 5.0)) * 0.98 + exact, 0.0), exact)


def facet_variance(m, i, footprint_, log_cos, front, cos_half, sun, ripples):
    """The part of the ripples' undrawn slope variance `ripples` drawn as the glint facets' own
    normals (the rest is the lobe's roughness): all of it while the pixel's footprint (L_p along
    the view by L_p cos across) holds at most e^Facets Sharp Log facets of e^Facet Log, none
    from e^Facets Mean Log, between them by ln N; only where a facet may show the sun, its
    share 1 - tan^2 / (Sun Reach s^2) for the half vector of the view and the sun at `cos_half`
    to the normal (elsewhere the sky's light alone, which facets would only make grainy); on
    `front` faces (1 or 0), `sun` the sun lamp's presence (0 to 1)."""
    facets = (footprint_ - i["Facet Log"]) * 2.0 + log_cos  # ln N
    weight = m.clamp((i["Facets Mean Log"] - facets)
                     / (i["Facets Mean Log"] - i["Facets Sharp Log"]))
    tan2 = 1.0 / (cos_half * cos_half) - 1.0
    reach = m.clamp(1.0 - tan2 / (i["Sun Reach"] * ripples + 1e-9))
    return weight * front * (reach * sun) * ripples


def grain_rank(m, fac):
    """The grain noise's rank of Fac `fac`: its CDF 1 / (1 + e^-(a z + b z^3)), z in its standard
    deviations (FOAM_GRAIN_STD, FOAM_RANK: fitted to Blender's own noise), so nearly uniform."""
    z = (fac - 0.5) / FOAM_GRAIN_STD
    return 1.0 / (m.exp(z * (z * z * -FOAM_RANK[1] - FOAM_RANK[0])) + 1.0)


def ridge_rank(m, rank):
    """A rank near the noise's median ranked high: 1 - |2 rank - 1|, as uniform as the rank,
    so its top ranks are bands along the noise's middle contour: thin lines that branch and
    join (drawn out along the wind, the foam's streaks), not the blobs of its top ranks."""
    return 1.0 - m.abs(rank * 2.0 - 1.0)


def grain_cover(m, rank, share, soft=FOAM_EDGE):
    """Foam where the grain's `rank` is within `share` of the top, over an edge `soft` *
    min(share, 1 - share) wide: its mean over the grain is the share, and nothing is drawn at
    a share of nought. A whitecap is then a solid core whose edge breaks into bubbles and
    streaks, not the round blob the vertices interpolate (at `soft` 2, a ramp from the top
    rank down: a glow, not a patch)."""
    edge = m.min(share, 1.0 - share) * soft + 1e-4
    return m.clamp((rank - 1.0 + share) / edge + 0.5) * m.greater(share, 0.0)


def grain_shown(m, scale, footprint_, log_cos, log_width=0.0):
    """How much a noise of `scale` features per metre (geometric mean over its axes) is drawn:
    while the pixel's area (its length along the view times sqrt(cos)) holds few of its
    patches (features e^`log_width` as wide: its lines'), so far foam stays specks, not a
    veil, and lines thinner than a pixel do not crawl; past that its mean."""
    return m.clamp((-math.log(scale) + log_width - (log_cos * 0.5 + footprint_)) / LN2 + 1.0)


def grain_drawn(m, shown, rank, share, soft=FOAM_EDGE):
    """A noise covering `share` by its `rank` (`grain_cover`, its edge `soft`) as far as it
    is `shown` (`grain_shown`), past that its mean, the share."""
    return m.mix(shown, share, grain_cover(m, rank, share, soft))


def bubble_albedo(m, albedo, brightest):
    """A fresh breaker's bubble plume's diffuse albedo in a channel where the water body's is
    `albedo` (`brightest` its largest over the channels): BUBBLE_ALBEDO times the water's hue
    to the power BUBBLE_PATH (its light comes through that share of the body's path), never
    darker than the water."""
    return m.max(m.pow(albedo / m.max(brightest, 1e-6), BUBBLE_PATH) * BUBBLE_ALBEDO, albedo)


def web(m, scale, fill, ridge, footprint_):
    """A web of a noise of `scale` features a metre, its ridges (`ridge`, its `ridge_rank`)
    over `fill` of its ranks: lines `fill` of its features wide, drawn while a pixel is up to
    LINE_PIXELS times that, past that all of it (so lace drawn over it stays solid specks,
    not a veil): (its cover, the share it covers as drawn). `footprint_`: (footprint, log cos)
    as `grain_shown` takes them."""
    seen = grain_shown(m, scale, *footprint_, m.log(m.max(fill * LINE_PIXELS, 1e-3)))
    filled = m.mix(seen, 1.0, fill)
    return grain_drawn(m, seen, ridge, filled), filled


def foam_cover(m, i, active, residual, fac, lace, net, streak, blown, web_, footprint_,
               log_cos):
    """The foam drawn at a point: (the Foam mix's factor, its brightness against fresh foam,
    how much of the water body the whitecaps' bubble plume lights: `bubble_albedo`).
    The vertices carry the active whitecaps' share `active` (stage A) and their young residual
    foam's `residual` (stage B, residual_foam.py). The top ranks of the grain noise (Fac `fac`)
    cover the first (`grain_cover`), the lace noise's (Fac `lace`: larger patches, churning
    slower) the second, thinning into lace as it decays (rafts over the square root of its
    share, each filled as much by the web of the net noise, Fac `net`), the streak
    noise's (Fac `streak`, Foam Streak times longer along the wind than across) the aged foam
    (Aged Coverage, over the whole sea: patches drawn out along the wind, which photographs
    count as whitecaps), and over what that leaves the ridges
    (`ridge_rank`) of the blown streaks' noise (Fac `blown`, as drawn out) the wind's blown
    streaks (Blown Coverage): thin lines. Both in rafts filled by the web of the web noise
    (Fac `web_`), and a film of AGED_FILM (thicker and thinner by
    FOAM_TEXTURE with the grain's rank) over as much more of the sea as makes their mean
    cover the shares (all of it at most): the residual over what the
    active leaves, at RESIDUAL_BRIGHTNESS. Where the pixel's footprint
    along the view outgrows a WHITECAP the vertices' shares are the sea's means (per-vertex
    foam on a grid that moves with the camera would pop), if whitecaps are called for (not
    contact foam alone); each noise is drawn while `grain_shown`, past that its share. The
    plume covers BUBBLE_SPREAD times the active share by the grain's top ranks and
    BUBBLE_RESIDUAL times the young residual's by the lace noise's, each a glow fading from
    the core out (`grain_cover`'s ramp): a margin around each whitecap's white and a fading
    patch under the lace where it broke (far off, the sea's mean shares)."""
    whole = m.clamp((footprint_ - math.log(WHITECAP)) / LN2) * m.greater(i["Foam Coverage"], 0.0)
    a = m.mix(whole, active, i["Foam Coverage"])
    r = m.mix(whole, residual, i["Residual Coverage"])
    aged = m.min(i["Aged Coverage"] / AGED_FILM, 1.0)
    # of the ranks the aged foam leaves, the share that makes the film's mean aged + (1 - aged)
    # blown
    lines = m.min((1.0 - i["Aged Coverage"]) * i["Blown Coverage"]
                  / m.max(AGED_FILM - i["Aged Coverage"], 1e-6), 1.0)
    shown = (footprint_, log_cos)
    grain, grain_seen = grain_rank(m, fac), grain_shown(m, FOAM_GRAIN * math.sqrt(FOAM_STREAK),
                                                        *shown)
    lace, lace_seen = grain_rank(m, lace), grain_shown(m, FOAM_LACE, *shown)
    # the plume glows from the whitecap's core (its top ranks) out, and under the residual's
    plume = grain_drawn(m, grain_seen, grain, m.min(a * BUBBLE_SPREAD, 1.0), 2.0)
    plume = plume + (1.0 - plume) * grain_drawn(m, lace_seen, lace, r * BUBBLE_RESIDUAL, 2.0)
    a = grain_drawn(m, grain_seen, grain, a)
    # the film thick and thin with the grain while it is drawn (its mean AGED_FILM)
    film = AGED_FILM + (AGED_FILM * FOAM_TEXTURE) * (grain * 2.0 - 1.0) * grain_seen
    # Lace: the residual's rafts (the lace noise's top ranks) filled by the net noise's web,
    # sqrt(r) each, so it thins into lace as it decays; the film's foam, aged and blown, in
    # rafts filled by the web noise's, FILM_FILL at least (foam is a web of bubbles, not a
    # brush stroke). Where a web is not drawn its rafts are the shares (solid specks).
    net, net_filled = web(m, FOAM_NET, m.sqrt(r), ridge_rank(m, grain_rank(m, net)), shown)
    r = grain_drawn(m, lace_seen, lace, r / m.max(net_filled, 1e-6)) * net
    total = aged + (1.0 - aged) * lines
    film_web, filled = web(m, FILM_WEB, m.max(total, FILM_FILL),
                           ridge_rank(m, grain_rank(m, web_)), shown)
    aged_rafts = aged / m.max(filled, 1e-6)
    # a ridge band of the ranks is that share of its features wide (lines: `web`)
    line_rafts = (total - aged) / m.max(filled - aged, 1e-6)
    aged = grain_drawn(m, grain_shown(m, FOAM_AGED, *shown), grain_rank(m, streak), aged_rafts)
    lines = grain_drawn(m, grain_shown(m, FOAM_BLOWN, *shown, m.log(m.max(
        line_rafts * LINE_PIXELS, 1e-3))), ridge_rank(m, grain_rank(m, blown)), line_rafts)
    r = r + (1.0 - r) * film * film_web * (aged + (1.0 - aged) * lines)
    cover = a + (1.0 - a) * r
    return cover, m.mix(a / m.max(cover, 1e-6), RESIDUAL_BRIGHTNESS, 1.0), plume
