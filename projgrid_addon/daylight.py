"""Daylight by the sun's elevation, as Blender's own sky gives it: the Sky Texture at
SKY_ALTITUDE (5.x's MULTIPLE_SCATTERING, after Fernando Garcia Linan, as the Blender manual
credits it; 4.5's NISHITA, single scattering after Nishita et al. 1993, kept in 5.x as
SINGLE_SCATTERING), measured once by tools/measure_sky.py (Cycles: the sky's irradiance on a
level plane, its sun disc's on a plane facing the sun) and re-measured by
tests/blender/test_sky.py. Add Ocean's world draws that sky times SKY_SCALE, and its sun lamp
carries the disc's light, so the lamp's colour and strength follow the sky's sun (Bruneton,
Neyret and Holzschuch 2010 light the sea by one sun and sky too). Pure Python: look.py's
DAYLIGHT is built from it."""

import math

SKY_ALTITUDE = 50.0  # m above the sea: the Sky Texture's Altitude
# The Sky Texture's radiance in our world: its own units are physical (W/m^2/sr); this puts
# the daylight at Add Ocean's 12 degree sun near the irradiance the look was calibrated in.
SKY_SCALE = 0.07
SUN_SIZE = 0.545  # degrees across: the Sky Texture's default sun disc, drawn by our world

ELEVATIONS = (-4.0, -2.0, 0.0, 1.0, 2.0, 3.0, 4.0, 6.0, 8.0, 12.0, 16.0, 20.0, 30.0, 45.0, 60.0,
              90.0)
# RGB irradiance (linear, the Sky Texture at strength 1, disc off) on a level plane, and its
# sun disc's on a plane facing it (at 0 degrees half the disc is below the horizon), per model:
# Blender 5's multiple scattering and 4.5's single scattering.
SKY_MULTIPLE = ((0.049, 0.085, 0.2784), (0.3697, 0.3884, 0.7659), (1.2277, 1.295, 1.9055),
                (1.7347, 1.9634, 2.7393), (2.2086, 2.694, 3.7179), (2.6352, 3.4307, 4.7991),
                (3.0187, 4.1394, 5.9311), (3.677, 5.4216, 8.1863), (4.217, 6.5042, 10.2484),
                (5.0486, 8.1558, 13.4849), (5.6663, 9.3382, 15.7551), (6.1562, 10.2533, 17.4774),
                (7.0762, 11.954, 20.6664), (8.0404, 13.74, 24.0392), (8.699, 14.9686, 26.3727),
                (9.2322, 15.9655, 28.2705))
SUN_MULTIPLE = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (3.646, 0.458, 0.0), (17.063, 3.757, 0.0),
                (32.851, 10.187, 0.048), (47.489, 18.422, 1.535), (60.346, 27.339, 4.327),
                (80.991, 44.625, 12.593), (96.298, 59.514, 22.361), (116.674, 81.699, 40.973),
                (129.235, 96.585, 56.011), (137.596, 106.972, 67.678), (149.631, 122.563, 86.981),
                (157.91, 133.714, 102.106), (161.742, 138.99, 109.646), (164.075, 142.237, 114.41))
SKY_SINGLE = ((0.0517, 0.0591, 0.0812), (0.3128, 0.3454, 0.4216), (1.0039, 1.1184, 1.2142),
              (1.5141, 1.6944, 1.7779), (1.9984, 2.3058, 2.4252), (2.4289, 2.8934, 3.1136),
              (2.8155, 3.4338, 3.8023), (3.4778, 4.3537, 5.0844), (4.0212, 5.0854, 6.1858),
              (4.8534, 6.1566, 7.8925), (5.4583, 6.9021, 9.126), (5.9053, 7.4469, 10.0558),
              (6.6233, 8.3261, 11.6224), (7.1773, 9.0319, 12.981), (7.4542, 9.4113, 13.7788),
              (7.616, 9.6624, 14.3664))
SUN_SINGLE = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (1.529, 0.273, 0.0), (14.352, 3.853, 0.0),
              (30.924, 10.83, 0.073), (46.937, 19.715, 1.608), (60.739, 29.006, 4.43),
              (81.707, 45.992, 12.531), (96.163, 59.708, 21.788), (114.125, 78.974, 38.903),
              (124.603, 91.303, 52.417), (131.382, 99.683, 62.768), (140.926, 111.979, 79.703),
              (147.373, 120.593, 92.831), (150.331, 124.622, 99.335), (152.126, 127.089, 103.433))
MODELS = {"MULTIPLE_SCATTERING": (SKY_MULTIPLE, SUN_MULTIPLE),
          "SINGLE_SCATTERING": (SKY_SINGLE, SUN_SINGLE), "NISHITA": (SKY_SINGLE, SUN_SINGLE)}
MODEL = "MULTIPLE_SCATTERING"  # the look's daylight (look.DAYLIGHT) is Blender 5's


def _at(table, elevation):
    """`table`'s RGB at `elevation` degrees, linear between the measured elevations, held
    beyond them."""
    e = min(max(float(elevation), ELEVATIONS[0]), ELEVATIONS[-1])
    i = max(j for j in range(len(ELEVATIONS) - 1) if ELEVATIONS[j] <= e)
    f = (e - ELEVATIONS[i]) / (ELEVATIONS[i + 1] - ELEVATIONS[i])
    return tuple(a + f * (b - a) for a, b in zip(table[i], table[i + 1], strict=True))


def sky_light(elevation, model=MODEL):
    """RGB irradiance our world's clear sky (the Sky Texture's `model`) puts on the sea plane
    with the sun `elevation` degrees up (its disc apart)."""
    return tuple(SKY_SCALE * v for v in _at(MODELS[model][0], elevation))


def sunlight(elevation, model=MODEL):
    """(strength, colour) of a sun lamp that carries our sky's sun disc `elevation` degrees up:
    its irradiance on a plane facing it, W/m^2 in Blender's units, and its colour scaled to a
    largest channel of 1 (white, strength 0, below the horizon)."""
    rgb = [SKY_SCALE * v for v in _at(MODELS[model][1], elevation)]
    top = max(rgb)
    return (top, tuple(v / top for v in rgb)) if top > 0.0 else (0.0, (1.0, 1.0, 1.0))


def disc_radiance(elevation, model=MODEL):
    """RGB radiance of our sky's sun disc `elevation` degrees up: the lamp's irradiance over
    the disc's solid angle."""
    solid_angle = 2.0 * math.pi * (1.0 - math.cos(math.radians(SUN_SIZE / 2.0)))
    return tuple(SKY_SCALE * v / solid_angle for v in _at(MODELS[model][1], elevation))


def sun_on_sea(elevation, model=MODEL):
    """RGB irradiance our sun lamp (`sunlight`) puts on the sea plane `elevation` degrees up."""
    up = max(math.sin(math.radians(elevation)), 0.0)
    strength, colour = sunlight(elevation, model)
    return tuple(strength * c * up for c in colour)


def daylight(elevation, model=MODEL):
    """RGB irradiance our sky and sun lamp put on the sea plane with the sun `elevation`
    degrees up."""
    return tuple(s + u for s, u in zip(sky_light(elevation, model), sun_on_sea(elevation, model),
                                       strict=True))


# The sun's aureole, the light aerosols scatter within a few degrees of it: what a camera sees
# as the glare about the sun. Buie, Monger and Dey 2003's sunshape (Solar Energy 74): radiance
# against the disc's e^kappa (1000 theta)^gamma from the disc's edge (theta in radians) out
# to AUREOLE_EDGE, kappa = 0.9 ln(13.5 chi) chi^-0.3 and gamma = 2.2 ln(0.52 chi) chi^0.43 - 0.1
# for their parameter chi (a clear sky's; its circumsolar ratio: test_daylight.py); faded out
# over as far again beyond the edge, where the sky's own scattering takes over.
AUREOLE_CHI = 0.05
AUREOLE_EDGE = 43.6e-3
AUREOLE_KAPPA = 0.9 * math.log(13.5 * AUREOLE_CHI) * AUREOLE_CHI ** -0.3
AUREOLE_GAMMA = 2.2 * math.log(0.52 * AUREOLE_CHI) * AUREOLE_CHI ** 0.43 - 0.1


def aureole(m, theta):
    """The aureole's radiance against the sun disc's at `theta` radians from the sun's centre,
    beyond the disc (`m` the maths: the world's node graph, or NumPy in the tests)."""
    disc = math.radians(SUN_SIZE / 2.0)
    fade = m.clamp((2.0 * AUREOLE_EDGE - theta) * (1.0 / AUREOLE_EDGE))
    return math.exp(AUREOLE_KAPPA) * m.pow(m.max(theta, disc) * 1000.0, AUREOLE_GAMMA) * fade


# Aerial perspective (Koschmieder 1924): along d metres of air a far object's light falls as
# e^(-beta d) and the air's own light (along a level view the horizon sky's) fills the rest; a
# dark object's contrast falls to 2 % at the meteorological range V, so beta = KOSCHMIEDER / V
# (and to 5 % at the WMO's meteorological optical range, the visibility marine forecasts
# give: OPTICAL_RANGE / beta). Clear air's V is CLEAR_VISIBILITY (LOWTRAN's and MODTRAN's
# "clear" meteorological range, 23 km; Kneizys et al. 1988); from Beaufort 7's wind the spray
# thickens it, exponentially in the wind, to an optical range of one nautical mile at Beaufort
# 10's: the geometric middle of "poor" visibility in the marine forecasts' terms (Joint
# IMO/IHO/WMO Manual on Maritime Safety Information, MSC.1/Circ.1310 8.5.4: poor 0.5-2,
# moderate 2-5, good over 5 nautical miles), so force 9 ("spray may affect visibility") sees
# a moderate 4.1 km and 10 ("visibility affected") a poor 1.9 km (test_daylight.py). A look
# anchored to the WMO's words, not a measured law.
KOSCHMIEDER = 3.912  # -ln 0.02
OPTICAL_RANGE = 2.996  # -ln 0.05
NAUTICAL_MILE = 1852.0  # m
CLEAR_VISIBILITY = 23e3  # m
SPRAY_VISIBILITY = NAUTICAL_MILE * KOSCHMIEDER / OPTICAL_RANGE  # m: an optical range of 1 nmi
SPRAY_WINDS = (15.5, 26.5)  # m/s: Beaufort 7's and 10's (sea_states.BEAUFORT)


def visibility(wind_speed):
    """The air's meteorological range (m, 2 % contrast) over the sea in a wind of `wind_speed`
    m/s."""
    lo, hi = SPRAY_WINDS
    rise = max(float(wind_speed) - lo, 0.0) / (hi - lo)
    return CLEAR_VISIBILITY * (SPRAY_VISIBILITY / CLEAR_VISIBILITY) ** rise


def haze_extinction(wind_speed):
    """The air's extinction (per metre) in a wind of `wind_speed` m/s: Koschmieder's."""
    return KOSCHMIEDER / visibility(wind_speed)


def haze(m, extinction, distance):
    """How far the light seen `distance` m away has given way to the air's (0 to 1)."""
    return 1.0 - m.exp(extinction * -distance)
