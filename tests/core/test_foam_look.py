"""The foam's look as the water group's formula draws it: the bubble plume under a fresh
breaker, the residual foam thinning into lace."""

import numpy as np
import pytest
from look_numpy import NUMPY, even_ranks, grain_facs, grain_facs_at, group_inputs

from projgrid_addon import look, shading, water_model
from projgrid_addon.camera import perspective
from projgrid_addon.spectral_field import SpectralField
from projgrid_addon.spectrum import SeaState


def test_a_fresh_breaker_s_bubbles_glow_around_its_white():
    """The plume (water_model.foam_cover's third value) covers BUBBLE_SPREAD times the active
    whitecaps' share by the grain's top ranks, a glow brightest under their white and fading
    beyond it, and BUBBLE_RESIDUAL times the young residual foam's (a fading patch where a
    breaker was); far off, the sea's mean shares."""
    proj = perspective(np.radians(40.0), 16 / 9, 0.1, 1e4)
    f = shading.filtering(proj, 960, SpectralField(SeaState(wind_speed=15.0)).slopes, 15.0)
    i = group_inputs(f, **{"Foam Coverage": 0.01, "Residual Coverage": 0.02})
    fac = grain_facs(400_000, 7)
    zero = np.zeros_like(fac)

    def drawn(d, active, residual):
        lp, log_cos = water_model.footprint(NUMPY, i, d, 1.0)
        cover, _, plume = water_model.foam_cover(NUMPY, i, zero + active, zero + residual, fac,
                                                 fac[::-1], fac, fac, fac, fac, lp, log_cos)
        return cover, plume
    for share in (0.02, 0.2):
        cover, plume = drawn(3.0, share, 0.0)
        assert plume.mean() == pytest.approx(min(share * look.BUBBLE_SPREAD, 1.0), rel=0.03)
        assert plume[cover == 1.0].mean() > 0.6  # brightest under the white's core
        assert ((plume > 0.05) & (cover < 0.05)).mean() > 0.5 * share  # and a margin beyond
    assert drawn(3.0, 0.0, 0.2)[1].mean() == pytest.approx(0.2 * look.BUBBLE_RESIDUAL, rel=0.03)
    assert drawn(3.0, 0.0, 0.0)[1].max() == 0.0
    active, residual = 0.01 * look.BUBBLE_SPREAD, 0.02 * look.BUBBLE_RESIDUAL
    assert drawn(1e5, 0.3, 0.0)[1] == pytest.approx(active + (1.0 - active) * residual)


def test_the_bubbles_light_the_water_its_own_hue_paler():
    """The plume's albedo (water_model.bubble_albedo) is BUBBLE_ALBEDO in the water's brightest
    channel and the water's hue to the power BUBBLE_PATH in the others: under the default water
    a pale turquoise, much brighter than the water and weaker in the red (Bohren 1987's
    "blue-green or green, brighter than the sea"; submerged bubbles lower a whitecap's
    reflectance at the longer wavelengths: Moore et al. 1998); never darker than the water,
    whatever its colour."""
    water = np.minimum(np.asarray(look.WATER_COLOUR) * np.pi / np.asarray(look.DAYLIGHT), 1.0)
    bubbles = water_model.bubble_albedo(NUMPY, water, water.max())
    assert bubbles.max() == pytest.approx(look.BUBBLE_ALBEDO)
    assert bubbles == pytest.approx(look.BUBBLE_ALBEDO * (water / water.max())**look.BUBBLE_PATH)
    assert np.all(bubbles > 5.0 * water)
    assert bubbles[0] < 0.8 * min(bubbles[1], bubbles[2])  # turquoise: red the weakest
    pale = bubbles / bubbles.max()
    assert np.all(pale >= water / water.max())  # paler than the water's own hue
    white = np.array([0.9, 0.4, 0.1])
    assert np.all(water_model.bubble_albedo(NUMPY, white, white.max()) >= white)


def test_residual_foam_thins_into_lace():
    """Near the camera a vertex's young residual share r is drawn as rafts of the lace noise's
    top ranks over sqrt(r) of the sea, each filled sqrt(r) by the net noise's ridges: the
    mean is r, and a patch thins into a network of lines as it decays, not a shrinking blob;
    a fresh one (r = 1) is solid."""
    proj = perspective(np.radians(40.0), 16 / 9, 0.1, 1e4)
    f = shading.filtering(proj, 960, SpectralField(SeaState(wind_speed=15.0)).slopes, 15.0)
    i = group_inputs(f, **{"Residual Coverage": 0.02})
    even = grain_facs_at(even_ranks(1500))
    lace, net = even[:, None], even[None, :]  # every pair of ranks, evenly
    lp, log_cos = water_model.footprint(NUMPY, i, 3.0, 1.0)
    raft = water_model.grain_rank(NUMPY, lace) > 0.5  # the top half of the lace noise's ranks
    filled = {}
    for share in (0.04, 0.25, 1.0):
        cover = water_model.foam_cover(NUMPY, i, 0.0, np.full((1500, 1500), share), 0.5, lace,
                                       net, 0.5, 0.5, 0.5, lp, log_cos)[0]
        assert cover.mean() == pytest.approx(share, rel=0.03)
        rafts = (cover > 0.5).any(axis=1)  # the lace ranks where some of the net is drawn
        assert rafts.mean() == pytest.approx(np.sqrt(share), abs=0.02)
        filled[share] = cover[rafts & raft[:, 0]].mean()
    assert filled[0.04] < 0.3 < filled[0.25] < 0.6 < filled[1.0] == pytest.approx(1.0)
