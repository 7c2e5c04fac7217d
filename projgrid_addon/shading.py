"""What the water shader needs each frame, as plain values (thesis §3.1.3, §3.4.5).

The octaves the grid's band limit left out (band_limit.shader_octaves) come back in the shader
as bump detail: a fractal from the first left-out octave on, at its wavelength, height and time
rate (each height source's `shader_detail`).

Waves too short for a pixel become the surface's roughness (Bruneton, Neyret and Holzschuch,
*Real-time Realistic Ocean Lighting using Seamless Transitions from Geometry to BRDF*, 2010): a
wave is drawn, by the geometry or the shader's normals, while it spans PIXELS pixels; the slope
variance of the shorter ones is the variance of a microfacet slope distribution, so that the
variance drawn plus the roughness is Cox and Munk's for the wind at every distance.
"""

import math
from dataclasses import dataclass

import numpy as np

# The standard deviation of Blender's noise texture Fac (3D, Detail 2, roughness 0.5) as EEVEE
# draws it: a bump of Distance d moves the surface by 0.080 d (rms). That is 0.92 of the Fac's
# spread through Geometry Nodes (tests/blender/test_look.py), as an EEVEE render of 400
# features measured it for the 4D noise (0.072 against 0.0785).
NOISE_FAC_STD = 0.080
# The ripples: the octaves below the shortest wave a source synthesises, as shading detail
# (each source's `ripple`); under them the wind's slopes Cox and Munk measured that the sea
# does not draw (`filtering`).
RIPPLE_OCTAVES = 3
# The length of that noise's waves in its cells (2 pi times its Fac's spread over its rms
# gradient) by Detail, roughness 0.5: a cell is not a wave, and the fractal's octaves shorten
# them. Measured through Geometry Nodes (tests/blender/test_look.py re-measures them).
NOISE_WAVES = ((0.0, 1.752), (1.0, 1.436), (2.0, 1.223), (3.0, 1.140))


def noise_fac_std(detail, roughness):
    """NOISE_FAC_STD for another Detail and roughness: Blender divides its fractal by the sum of
    its octaves' amplitudes r^i, so the spread is one octave's times sqrt(sum r^2i) / sum r^i
    (the octaves independent)."""
    def spread(n, r):
        amps = r ** np.arange(int(n) + 1)
        return float(np.sqrt(np.sum(amps**2)) / np.sum(amps))
    r = min(max(float(roughness), 0.0), 1.0)  # the noise node clamps it
    return NOISE_FAC_STD / spread(2, 0.5) * spread(max(detail, 0.0), r)


def detail_height(slope_variance, scale, detail):
    """The height (m per unit Fac) of Blender's noise (roughness 0.5) of `scale` cells per metre
    and `detail` whose bump draws `slope_variance`: its slope is its height's spread times the
    rms wavenumber of its waves, 2 pi scale / NOISE_WAVES."""
    levels, waves = zip(*NOISE_WAVES, strict=True)
    wavenumber = 2.0 * np.pi * scale / float(np.interp(detail, levels, waves))
    return float(np.sqrt(slope_variance) / wavenumber / noise_fac_std(detail, 0.5))


@dataclass(frozen=True)
class Detail:
    """The left-out octaves as the shader's fractal noise: the band limit from which the
    vertices hold its first octave (faded in until one more; for the noise its index),
    frequency (1/m), further octaves, roughness, height (m), and its time coordinate per
    second."""

    first: float
    scale: float
    octaves: float
    roughness: float
    height: float
    time_rate: float


def sun_direction(matrix_world):
    """Unit vector towards a sun lamp of world matrix `matrix_world` (4x4): it shines along its
    local -Z."""
    direction = np.asarray(matrix_world, dtype=np.float64)[:3, 2]
    return direction / max(float(np.linalg.norm(direction)), 1e-12)


def sun_elevation(direction):
    """Degrees above the horizon of a unit direction towards the sun."""
    return float(np.degrees(np.arcsin(np.clip(direction[2], -1.0, 1.0))))


# A wave is drawn while it spans this many pixels along the footprint's major axis, which sets
# what aliases (a GPU picks its mip level by it too, though keeping waves of two texels); EEVEE's
# jittered samples antialias within the pixel. One pixel on the major axis flickers less in the
# far field than two on the geometric mean (docs/benchmarks.md §6) and keeps the near glitter.
PIXELS = 1.0
# The most a pixel's footprint stretches at grazing angles: along the view by 1 / cos (the
# major axis, which sets what aliases), at most this many times (the far band then keeps
# waves of GRAZING pixels and more as normals: smooth, as the flicker bench measures).
GRAZING = 9.0
# Sun glint from discrete facets (Jakob et al. 2014; Zirr and Kaplanyan 2016): each facet that
# meets the sun's reflection slope shows the whole sun, so a pixel holding few facets sparkles
# and only one holding many shows the mean lobe. The facets are half the ripples' shortest
# wave (1.6 cm for the spectrum: the capillary waves' size); the shader gives each its own
# normal from the slopes the ripples leave undrawn and EEVEE's samples find them, while a
# pixel's footprint holds up to FACETS_SHARP facets, fading into the lobe by FACETS_MEAN (a
# pixel of N facets sparkles while N p < 1, p the chance a facet meets the sun's 0.5 deg,
# ~1e-3 at the glitter path's middle).
FACETS_SHARP = 4.0
FACETS_MEAN = 1024.0
# Facets only where the half vector of the view and the sun lies within SUN_REACH times the
# undrawn slope variance of the pixel's normal (a tangent ten times its deviation): the sun is
# so much brighter than the sky that the lobe's tail still shows it there; beyond is only the
# sky's light, which facets finer than EEVEE's samples would make grainy.
SUN_REACH = 100.0
# `left_out_log` of a source that leaves nothing to the roughness: no band limit reaches it.
NOT_LEFT_OUT = -100.0
# The sea's roughness length (m): the wind at 12.5 m, where Cox and Munk measured it, from the
# wind at 10 m by the logarithmic profile U(z) ~ ln(z / Z0).
Z0 = 2e-4


def cox_munk(wind_speed):
    """The mean square slope of a clean sea, upwind plus crosswind (Cox and Munk 1954,
    0.003 + 5.12e-3 U with U in m/s at 12.5 m), for the wind at 10 m."""
    u = max(float(wind_speed), 0.0) * np.log(12.5 / Z0) / np.log(10.0 / Z0)
    return 0.003 + 5.12e-3 * u


# The most the gusts' amplitude (Filtering.gust) reaches: a lull then leaves a third of the sea
# glassy. A source whose ripples hold little of Cox and Munk's slope would otherwise swing them
# many times over.
GUST_CAP = 2.0


def gust_mean(amplitude):
    """E[max(1 + amplitude z, 0)] over a standard normal z: the mean the lulls' clip at nought
    lifts the ripples' factor to, which `gust` divides out (1 + 0.03 % at 0.5, 1.08 at 1)."""
    a = float(amplitude)
    if a <= 0.0:
        return 1.0
    return 0.5 * (1.0 + math.erf(1.0 / (a * math.sqrt(2.0)))) \
        + a * math.exp(-0.5 / (a * a)) / math.sqrt(2.0 * math.pi)


def wind_run(seconds, speeds, directions):
    """How far the wind has blown by the last of `seconds` (from the first): its velocity
    (m/s, toward radians counter-clockwise from +X) integrated by the trapezoid rule over the
    samples, as (along X, along Y, path) in metres; the gusts drift by it."""
    t = np.asarray(seconds, dtype=np.float64)
    u = np.asarray(speeds, dtype=np.float64)
    d = np.asarray(directions, dtype=np.float64)
    v = np.stack([u * np.cos(d), u * np.sin(d), u])
    run = (0.5 * (v[:, 1:] + v[:, :-1]) * np.diff(t)).sum(axis=1)
    return tuple(float(x) for x in run)


def gust_spread(wind_speed):
    """The standard deviation of the wind speed at 10 m (m/s) about its mean (m/s) over a
    smooth surface: 0.4 m/s up to 5 m/s, 8 % of the wind above ("Standard deviations of wind
    speed and direction from observations over a smooth surface", J. Appl. Meteor. 27,
    550-561, 1988)."""
    u = max(float(wind_speed), 0.0)
    return 0.4 if u <= 5.0 else 0.08 * u


@dataclass(frozen=True)
class Slopes:
    """The slope variance a height source draws (geometry, shader detail and ripples): in all;
    per unit ln(wavelength) at the short end of its waves above the ripples; the ripples' own
    (0 for a source without them) and their longest wave (m); the shortest wave drawn (m);
    and where the geometry stops drawing (`left_out_log`)."""

    total: float
    density: float
    ripple: float
    ripple_top: float
    shortest: float
    # ln of the wavelength (m) the geometry holds down to at band limit 0, less ln 2 per unit
    # of band limit; the waves between it and the footprint are the roughness's. None: the
    # shader's detail draws them (the noise's octaves are its own noise).
    left_out_log: float | None = None
    # The longest wave of the slope layer (slope_layer.py: normal maps drawing the waves from
    # it down to the ripples wherever a pixel shows them, whatever the vertices hold); None:
    # no layer.
    layer_top: float | None = None
    # The slope variance per unit ln(wavelength) at the layer's top, over its first octave
    # (near a low wind's peak far below `density`); None: `density`.
    layer_density: float | None = None


@dataclass(frozen=True)
class Filtering:
    """The shader's per-pixel slope variance of the waves too short to draw (Bruneton 2010).
    With L_p the shortest wave drawn, PIXELS pixels' footprint at distance d, the view at cos
    to the mean sea plane (at least cos_floor), and L_g the shortest wave the geometry holds
    at the vertices' band limit lod (a source whose shader detail draws what the geometry
    leaves out: none):

        ln L_p  = distance_power ln d - ln(cos) + pixel_log
        ln L_g  = left_out_log - lod ln 2
        sigma^2 = min(floor + ripple clamp((ln L_p - ln S) / (ln T - ln S), 0, 1)
                      + density clamp(ln L_p - ln T, 0, ln N - ln T)
                      + above max(max(ln L_p, ln L_g) - max(ln N, ln T), 0), ceiling)

    S and T are the ripples' shortest and longest waves (`shortest_log`, `ripple_top_log`), N
    the slope layer's longest (`layer_top_log`; none: T): the waves above the ripples that
    no pixel shows are roughness, and above the layer also those the geometry leaves out, their
    slopes per unit ln(wavelength) `density` below N and `above` (`layer_density`) above. The
    slope variance Cox and Munk measured for the wind beyond what the sea draws is added to the
    ripples where there are any (their bump grows by `ripple_gain`: near the camera the sun
    glitters on them), else it is the `floor`; `ceiling` is the whole. Of the ripples' share,
    the glint facets' normals draw `water_model.facet_variance`, the lobe the rest."""

    pixel_log: float
    distance_power: float
    floor: float
    ripple: float
    cos_floor: float  # 1 / GRAZING
    ripple_gain: float
    density: float
    shortest_log: float
    ripple_top_log: float
    ceiling: float
    layer_top_log: float
    layer_density: float
    left_out_log: float = NOT_LEFT_OUT
    facet_log: float = -100.0  # ln of a glint facet's size (m): FACETS_SHARP and FACETS_MEAN
    facets_sharp_log: float = float(np.log(FACETS_SHARP))
    facets_mean_log: float = float(np.log(FACETS_MEAN))
    sun_reach: float = SUN_REACH
    # The ripples' slope variance a gust one standard deviation (Gusts times gust_spread)
    # stronger than the mean wind adds, per unit of theirs: Cox and Munk's at the gust's wind
    # less at the mean's (the longer waves, hours in the making, do not follow a gust; the
    # ripples do in seconds), at most GUST_CAP.
    gust: float = 0.0

    @property
    def gust_norm(self):
        """1 / gust_mean of the gusts' amplitude (the shader has no erf to compute it)."""
        return 1.0 / gust_mean(self.gust)


def pixel_footprint(proj, width):
    """(ln of PIXELS pixels' size at 1 m, distance power) for a camera of OpenGL projection
    `proj` and an image `width` pixels wide: a perspective pixel subtends 2 / (proj[0, 0] width)
    radians, so its footprint grows with the distance (power 1); an orthographic one is that
    many metres everywhere (power 0)."""
    proj = np.asarray(proj, dtype=np.float64)
    pixel = 2.0 / (abs(proj[0, 0]) * max(int(width), 1))
    return float(np.log(PIXELS * pixel)), (0.0 if proj[3, 3] != 0.0 else 1.0)


def filtering(proj, width, slopes, wind_speed, gusts=1.0):
    """The Filtering of a source drawing `slopes` (Slopes) under a wind (m/s at 10 m) whose
    gusts spread `gusts` times gust_spread's."""
    if not gusts >= 0.0:
        raise ValueError(f"gusts must be at least 0 (got {gusts})")
    pixel_log, power = pixel_footprint(proj, width)
    extra = max(cox_munk(wind_speed) - slopes.total, 0.0)
    ripple, floor, gain, gust_ = slopes.ripple, extra, 1.0, 0.0
    if ripple > 0.0:
        ripple, floor, gain = ripple + extra, 0.0, float(np.sqrt((ripple + extra) / ripple))
        gusty = wind_speed + gusts * gust_spread(wind_speed)
        gust_ = min((cox_munk(gusty) - cox_munk(wind_speed)) / ripple, GUST_CAP)
    return Filtering(pixel_log=pixel_log, distance_power=power, floor=floor, ripple=ripple,
                     ripple_gain=gain, density=slopes.density,
                     shortest_log=float(np.log(slopes.shortest)),
                     ripple_top_log=float(np.log(slopes.ripple_top)),
                     ceiling=slopes.total + extra, cos_floor=1.0 / GRAZING,
                     left_out_log=(NOT_LEFT_OUT if slopes.left_out_log is None
                                   else slopes.left_out_log),
                     layer_top_log=float(np.log(slopes.layer_top or slopes.ripple_top)),
                     layer_density=(slopes.density if slopes.layer_density is None
                                    else slopes.layer_density),
                     facet_log=float(np.log(slopes.shortest / 2.0)), gust=gust_)
