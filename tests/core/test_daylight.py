"""Daylight of Blender's sky (projgrid_addon/daylight.py) against the physics it stands for:
Beer-Lambert extinction of the sun along the Kasten-Young air mass, no weaker than Rayleigh
scattering alone (Bodhaine et al. 1999), and Buie et al.'s sunshape for the aureole."""

import math

import numpy as np
import pytest
from look_numpy import NUMPY

from projgrid_addon import daylight, look, sea_states
from projgrid_addon.spectrum import integrate


def air_mass(elevation):
    """Kasten and Young 1989: the relative optical air mass at `elevation` degrees."""
    return 1.0 / (math.sin(math.radians(elevation))
                  + 0.50572 * (elevation + 6.07995) ** -1.6364)


def rayleigh(wavelength):
    """Bodhaine et al. 1999 (Eq. 30): the Rayleigh optical depth at sea level, `wavelength`
    in micrometres."""
    w2 = wavelength * wavelength
    return 0.0021520 * (1.0455996 - 341.29061 / w2 - 0.90230850 * w2) / (
        1.0 + 0.0027059889 / w2 - 85.968563 * w2)


@pytest.mark.parametrize("model", ["MULTIPLE_SCATTERING", "NISHITA"])
def test_the_sun_dims_along_the_air_mass_as_beer_lambert(model):
    """The sun disc's light in the tables falls as e^(-tau m) with the air mass m: the same
    optical depth per channel from three pairs of elevations (within 10 %), at least Rayleigh's
    at 650, 550 and 450 nm and at most 0.08 more (aerosols and ozone)."""
    sun = daylight.MODELS[model][1]
    depths = []
    for low, high in ((4.0, 12.0), (6.0, 20.0), (12.0, 45.0)):
        a, b = np.array(daylight._at(sun, low)), np.array(daylight._at(sun, high))
        depths.append(np.log(b / a) / (air_mass(low) - air_mass(high)))
    depths = np.array(depths)
    assert np.all(depths.max(axis=0) < 1.1 * depths.min(axis=0)), depths
    tau = depths.mean(axis=0)
    floor = np.array([rayleigh(w) for w in (0.65, 0.55, 0.45)])
    assert np.all(tau >= floor) and np.all(tau <= floor + 0.08), (tau, floor)


def test_a_low_sun_is_red_and_dim_and_a_high_one_near_white():
    low, high = daylight.sunlight(3.0), daylight.sunlight(45.0)
    assert low[1][0] == 1.0 and low[1][2] < 0.05 and high[1][2] > 0.6
    assert low[0] < 0.4 * high[0]
    assert daylight.sunlight(-2.0) == (0.0, (1.0, 1.0, 1.0))  # set
    sky_low, sky_high = daylight.sky_light(3.0), daylight.sky_light(45.0)
    assert sky_low[1] < 0.3 * sky_high[1]
    assert look.DAYLIGHT == daylight.daylight(look.SUN_ELEVATION)


def test_the_aureole_is_buie_s_sunshape():
    """Buie, Monger and Dey 2003: kappa and gamma from chi; the aureole's share of the light
    within 2.5 degrees of the sun (its circumsolar ratio) that of a clear sky, 1 to 10 %."""
    chi = daylight.AUREOLE_CHI
    assert daylight.AUREOLE_KAPPA == pytest.approx(0.9 * math.log(13.5 * chi) * chi ** -0.3)
    assert daylight.AUREOLE_GAMMA == pytest.approx(
        2.2 * math.log(0.52 * chi) * chi ** 0.43 - 0.1)
    theta = np.array([0.01, 0.02, 0.04])
    assert daylight.aureole(NUMPY, theta) == pytest.approx(
        np.exp(daylight.AUREOLE_KAPPA) * (1000.0 * theta) ** daylight.AUREOLE_GAMMA)
    edge = math.radians(daylight.SUN_SIZE / 2.0)
    t = np.linspace(edge, daylight.AUREOLE_EDGE, 20001)
    ring = integrate(daylight.aureole(NUMPY, t) * 2.0 * np.pi * t, t)
    csr = ring / (ring + np.pi * edge * edge)
    assert 0.01 < csr < 0.1, csr
    assert daylight.aureole(NUMPY, 2.0 * daylight.AUREOLE_EDGE) == 0.0  # faded out


def test_the_air_hazes_as_koschmieder_with_the_spray_of_a_storm():
    """Koschmieder's law: at the visibility a dark object keeps 2 % of its contrast against
    the horizon sky (the light seen gives way to the air's by 0.98), at a tenth of it 1 -
    0.02^0.1; the visibility is clear air's (23 km) up to Beaufort 7's wind and falls with the
    spray, each stronger wind hazier, into the marine forecasts' classes (of the optical
    range, 5 % contrast) the WMO's words name: Beaufort 9 moderate ("spray may affect
    visibility"), 10 poor ("visibility affected"), one nautical mile there."""
    for wind in (0.0, 9.4, 15.5, 19.0, 26.5, 32.0):
        v = daylight.visibility(wind)
        beta = daylight.haze_extinction(wind)
        assert daylight.haze(NUMPY, beta, v) == pytest.approx(0.98, abs=1e-4)
        assert daylight.haze(NUMPY, beta, 0.1 * v) == pytest.approx(1.0 - 0.02**0.1, abs=1e-4)
        assert daylight.haze(NUMPY, beta, 0.0) == 0.0
    assert daylight.visibility(0.0) == daylight.visibility(15.5) == daylight.CLEAR_VISIBILITY
    assert daylight.CLEAR_VISIBILITY == 23e3
    assert daylight.SPRAY_WINDS == (sea_states.BEAUFORT[7][1], sea_states.BEAUFORT[10][1])
    assert daylight.visibility(26.5) == pytest.approx(daylight.SPRAY_VISIBILITY)
    # the marine forecasts' visibility: the WMO's optical range, where the contrast falls to 5 %
    def optical_range(wind):
        return -math.log(0.05) / daylight.haze_extinction(wind)
    assert optical_range(26.5) == pytest.approx(1852.0, rel=1e-3)
    # (Joint IMO/IHO/WMO Manual on Maritime Safety Information: in nautical miles)
    classes = {"poor": (0.5, 2.0), "moderate": (2.0, 5.0), "good": (5.0, math.inf)}
    for force, named in ((7, "good"), (9, "moderate"), (10, "poor")):
        lo, hi = classes[named]
        miles = optical_range(sea_states.BEAUFORT[force][1]) / 1852.0
        assert lo < miles < hi, (force, miles)
    winds = np.linspace(15.5, 33.0, 8)
    assert np.all(np.diff([daylight.visibility(w) for w in winds]) < 0.0)
