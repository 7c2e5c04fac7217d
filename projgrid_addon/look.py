"""The look's constants, in one place: the node tree (shaders/) is built from them and the core's
formulas of the look (shading.py, effects.py) use the same numbers. NumPy-free and bpy-free."""

from . import daylight

SUN_ELEVATION = 12.0  # degrees: Add Ocean's sun lamp (shaders/sky.py)

# The foam's break-up noise, features per metre along the wind: a breaking crest's patches are
# metres long, so a pixel tens of metres away still shows them, not the mean share.
FOAM_GRAIN = 0.3
# How fast the grain churns, in the noise's own time coordinate per unit of Detail Time (each
# of our noises is Blender's 3D noise over the water and its time, the third axis, which the
# noise multiplies by its Scale as the position: so the time is divided by FOAM_GRAIN).
FOAM_CHURN = 1.5
FOAM_DETAIL, FOAM_ROUGHNESS = 4.0, 0.65  # its fractal
# Its Fac's standard deviation about 0.5, and (a, b) of its CDF as 1 / (1 + e^-(a z + b z^3)),
# z in standard deviations: fitted to Blender's own noise over a period of its time
# coordinate (1.75 million samples; the fractal's Fac has lighter tails than a normal one's,
# and its spread varies by 4 % with the time), so the drawn cover is the share over time
# (tests/blender/test_look.py); at a 2 % share it swings by a quarter as the grain evolves.
FOAM_GRAIN_STD = 0.0684
FOAM_RANK = (1.522, 0.0963)
# How soft a bubble's edge is, in the noise's ranks, per unit of the share (or of what it
# leaves uncovered): the ramp stays inside the ranks, so nothing is drawn at a share of
# nought, everything at one, and the mean is the share (water_model.grain_cover).
FOAM_EDGE = 0.5
FOAM_STREAK = 1.5  # and this many times more across it: a breaker's patches, a little drawn out
# The young residual foam's noise, features per metre (round rafts of foam, shrinking), the
# aged foam's streak noise and the blown streaks' (each the geometric mean of along and across
# the wind: Foam Streak times longer along than across), all the grain's fractal. The blown
# streaks are the ridges of theirs: at a gale's stretch (10) lines some 10 m apart across the
# wind, about a metre wide at a gale's share, wider as it grows (test_shots.py measures their
# stretch along the wind).
FOAM_LACE, FOAM_AGED, FOAM_BLOWN = 0.25, 0.1, 0.03
# The net noise's and the web noise's features per metre: the cells of the lace the residual
# foam thins into and of the film's foam (aged, blown), their ridges (water_model.web); and
# how much of its rafts the film's web fills at least: foam is a web of bubbles, not a brush
# stroke.
FOAM_NET, FILM_WEB, FILM_FILL = 0.8, 0.6, 0.5
FOAM_LACE_CHURN = 0.5  # their churn (as FOAM_CHURN): residual foam drifts, it does not boil
# m across the wind the streak noises are pushed by the grain noise's departure (in its
# standard deviations): ragged edges a few metres long, fibres rather than brush strokes.
FOAM_WARP = 0.3
WHITECAP = 8.0  # m: a pixel this long (and longer) draws the sea's mean whitecap share
# Gusts (cat's paws): the wind's speed varies over the sea in patches that drift with it, and
# the ripples answer it within seconds. Their slope variance is scaled by max(1 + Gust
# Amplitude z, 0) times Gust Norm, z the local wind's departure in its standard deviations: a
# noise of GUST_SCALE features per metre (Detail GUST_DETAIL; its Fac's spread GUST_FAC_STD,
# measured over its time). The factor's mean over the sea is 1, so the sea's mean slope stays
# Cox and Munk's (tests/blender/test_look.py).
GUST_SCALE, GUST_DETAIL, GUST_FAC_STD = 1.0 / 30.0, 1.0, 0.098
GUST_EVOLVE = 0.5  # the patches' change, in the noise's own time per patch size drifted
# Scattering per metre where the caustic intensity is 1 (flat water), lit by the sky's sun
# (daylight.sunlight): of the order of clear ocean water's (Petzold 1972: 0.037 per metre).
GODRAY_DENSITY = 0.025

WATER_COLOUR = (0.004, 0.016, 0.024)  # deep water seen from above (linear), in DAYLIGHT
# The irradiance (W/m^2 per channel, linear) Add Ocean's sky and sun lamp (sky.py, the sun 12
# deg up) put on the mean sea plane: the water scatters Water Colour back up under it, and
# under other light in proportion (tests/blender/test_sky.py measures Blender's sky).
DAYLIGHT = daylight.daylight(SUN_ELEVATION)
# Linear radiance of the overcast overhead (Sea State's storm sky, shaders/sky.py); toward the
# horizon a third of it (the CIE standard overcast sky). A camera's exposure follows the light:
# the overcast is drawn as an incident meter exposes it, its irradiance on the sea (7 pi / 9
# of this) pi in luminance, so a grey card of 0.18 reads as the view's middle grey (0.18).
OVERCAST_ZENITH = (1.23, 1.29, 1.39)
FOAM_COLOUR = (0.7, 0.7, 0.7)  # the diffuse white of the foam's bubbles
# The sheen of the bubbles' films, added to the foam's diffuse colour (to white at most): the
# foam is one diffuse closure, so the picture is linear in its share (EEVEE merges closures of
# one kind: a glossy of the foam's own would change the water's reflection wherever any foam
# is; tests/blender/test_shots.py).
FOAM_SHEEN = 0.25
# Residual foam (stage B) against active: it reflects less as its bubbles thin (Koepke 1984:
# 0.22 over a whitecap's life against ~0.5 fresh); drawn much dimmer it reads as grey haze.
RESIDUAL_BRIGHTNESS = 0.85
# Aged foam (streaks) is a thin film over the water: drawn at this share of a full cover, over
# as much more of the sea (its reflectance against fresh foam's, Koepke 1984).
AGED_FILM = 0.75
# The bubble plume under a fresh breaker (stage A) glows turquoise: light scattered back by
# bubbles under the water comes up through less water than the body's, so it is the water's
# hue, paler: "blue-green or green, brighter than the sea but not as bright as the foamiest
# parts" (Bohren 1987); submerged bubbles lower a whitecap's reflectance at the longer
# wavelengths (Frouin, Schwindling and Deschamps 1996; Moore et al. 1998). Its albedo in the
# water's brightest channel, the power of the water's hue it takes (the share of the body's
# path it comes through), how many times the whitecap's share it covers (its margin around
# the white) and how many times the young residual foam's ("even after a wave has broken ...
# a pastel green patch often remains, slowly fading": the bubbles rise faster than the
# surface foam decays).
BUBBLE_ALBEDO, BUBBLE_PATH, BUBBLE_SPREAD, BUBBLE_RESIDUAL = 0.25, 0.3, 2.5, 0.5
# How much thicker and thinner the film is with the grain noise (its rank's departure, while
# the grain is drawn): marbled like foam, not the flat fill of a brush stroke.
FOAM_TEXTURE = 0.3


def body_volume(absorption, water_colour):
    """The water body's volume nodes' values for `absorption` per metre (RGB) and the water
    colour it glows toward: (absorption colour, density, glow colour, glow strength), the
    glow e = a * water colour, so that radiance after d metres is e^(-a d) L + (1 - e^(-a d))
    water colour (Fleck Eq. 14, 17)."""
    a = [max(float(v), 1e-9) for v in absorption]
    glow = [max(v * float(c), 1e-12) for v, c in zip(a, water_colour, strict=True)]
    return ((*(1.0 - v / max(a) for v in a), 1.0), max(a),
            (*(v / max(glow) for v in glow), 1.0), max(glow))
# The spray's puffs (spray.py): a puff's opacity at launch (it thins as it spreads and ages)
# and the white its droplets scatter diffusely, the foam's.
SPRAY_OPACITY = 1.0
# The optical depth along a puff's diameter in units of its opacity's, -ln(1 - opacity): a chord
# averages 2/3 of the diameter over the disc, so a thin puff's mean is its opacity
# (shaders/materials.spray_material)
SPRAY_CHORD = 1.5
