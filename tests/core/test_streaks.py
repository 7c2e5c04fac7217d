"""The foam the wind blows into streaks against the WMO's Beaufort descriptions and Holthuijsen,
Powell and Pietrzak (2012), and as the water group's formula draws it."""

import numpy as np
import pytest
from look_numpy import NUMPY, even_ranks, grain_facs, grain_facs_at, group_inputs

from projgrid_addon import foam, look, sea_states, shading, streaks, water_model
from projgrid_addon.camera import perspective
from projgrid_addon.spectral_field import SpectralField
from projgrid_addon.spectrum import SeaState


def test_blown_streaks_from_beaufort_7_to_the_white_out():
    """None up to Beaufort 6; from Beaufort 7's lower wind (13.9 m/s, "begins to be blown in
    streaks") growing with the wind; at 40 m/s the sea white (Holthuijsen et al.'s white-out);
    at 19-23 m/s (Beaufort 8-9) about the whitecaps' share to 2.5 times it (Ross and Cardone's
    thin streaks), at Beaufort 10 a quarter of the sea ("a white appearance")."""
    winds = [sea_states.sea_state(f).wind_speed for f in range(11)]
    blown = [streaks.blown_coverage(u) for u in winds]
    assert blown[:7] == [0.0] * 7
    assert 0.0 < blown[7] < blown[8] < blown[9] < blown[10]
    assert streaks.blown_coverage(13.9) == 0.0 and streaks.blown_coverage(40.0) == 1.0
    assert streaks.blown_coverage(60.0) == 1.0
    assert 0.2 <= blown[10] <= 0.3
    for force in (8, 9):
        assert 1.0 <= blown[force] / foam.foam_coverage(winds[force]) <= 2.5


def test_the_streaks_draw_out_along_the_wind():
    """Round patches up to Beaufort 6 (12 m/s); from Beaufort 8 (17.2 m/s, "well-marked
    streaks") at least 2.5 times longer along the wind than across (the issue's measure), and
    most of the residual foam gathered into them."""
    assert streaks.foam_streak(12.0) == 1.0
    assert streaks.foam_streak(17.2) >= 2.5
    assert streaks.streak_share(8.0) < streaks.streak_share(17.5) < 1.0


@pytest.mark.parametrize("force", [8, 10])
def test_the_group_draws_the_blown_streaks_over_the_aged_foam(force):
    """The water group's formula (water_model.foam_cover, what the node tree is built from)
    draws the aged foam as the top ranks of the streak noise (patches drawn out along the
    wind, which photographs count as whitecaps) and the blown streaks as the ridges of a noise
    of their own (thin lines), both a film of AGED_FILM: over the noises' ranks their mean is
    the aged share plus the blown share of what it leaves, the foam's look (foam.foam_look)
    carrying both; the rest bare water. Far off, where a pixel holds many, their mean."""
    u = sea_states.sea_state(force).wind_speed
    source = SpectralField(SeaState(wind_speed=u))
    _, _, aged, stretch, blown = foam.foam_look(source, u)
    assert blown == streaks.blown_coverage(u) and stretch == streaks.foam_streak(u)
    f = shading.filtering(perspective(np.radians(40.0), 16 / 9, 0.1, 1e4), 960, source.slopes, u)
    i = group_inputs(f, **{"Aged Coverage": aged, "Blown Coverage": blown})
    fac, other = grain_facs(200_000, force), grain_facs(200_000, force + 100)
    net = grain_facs(200_000, force + 300)
    zero, half = np.zeros_like(fac), np.full_like(fac, 0.5)
    lp, log_cos = water_model.footprint(NUMPY, i, 3.0, 1.0)

    def drawn(streak, lines, grain=half):
        return water_model.foam_cover(NUMPY, i, zero, zero, grain, zero, zero, streak, lines,
                                      net, lp, log_cos)
    cover, brightness, _ = drawn(fac, other)
    want = aged + (1.0 - aged) * blown
    assert cover.mean() == pytest.approx(want, rel=0.03)
    assert cover.max() == pytest.approx(look.AGED_FILM) and cover.min() == 0.0
    assert np.all(brightness == look.RESIDUAL_BRIGHTNESS)
    # the film thicker and thinner with the grain (FOAM_TEXTURE), its mean kept
    marbled, *_ = drawn(fac, other, grain_facs(200_000, force + 200))
    assert marbled.mean() == pytest.approx(want, rel=0.03)
    assert marbled.max() > look.AGED_FILM * (1.0 + 0.9 * look.FOAM_TEXTURE)
    lp, log_cos = water_model.footprint(NUMPY, i, 5e4, 1e-4)
    far, *_ = water_model.foam_cover(NUMPY, i, 0.0, 0.0, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5, lp,
                                     log_cos)
    assert far == pytest.approx(want, rel=1e-6)


def test_aged_foam_lies_in_patches_and_blown_streaks_in_lines():
    """The aged foam covers the streak noise's top ranks (patches of lace: FILM_FILL of them
    filled by the web noise's ridges), the blown streaks the middle ranks of theirs (its
    ridges: lines along its middle contour), each its share."""
    rank = even_ranks(4000)
    # every pair of the streak noises' ranks and the web's, evenly
    fac, net = grain_facs_at(rank)[:, None], grain_facs_at(even_ranks(400))[None, :]
    i = group_inputs(shading.filtering(perspective(1.0, 1.0, 0.1, 1e4), 960,
                                       SpectralField(SeaState(wind_speed=22.6)).slopes, 22.6))
    lp, log_cos = water_model.footprint(NUMPY, i, 3.0, 1.0)
    zero = np.zeros_like(fac)
    for aged, blown in ((0.02, 0.0), (0.0, 0.1)):
        j = {**i, "Aged Coverage": aged, "Blown Coverage": blown}
        cover, *_ = water_model.foam_cover(NUMPY, j, zero, zero, zero + 0.5, zero, zero, fac,
                                          fac, net, lp, log_cos)  # the grain at its median
        on = rank[(cover > 0.5 * look.AGED_FILM).any(axis=1)]
        if blown == 0.0:
            rafts = aged / look.AGED_FILM / look.FILM_FILL
            assert on.min() == pytest.approx(1.0 - rafts, abs=0.005)
            assert (cover[rank > 1.0 - rafts] > 0.5 * look.AGED_FILM).mean() == pytest.approx(
                look.FILM_FILL, abs=0.02)
            assert cover.mean() == pytest.approx(aged, rel=0.02)
        else:
            rafts = blown / look.AGED_FILM / look.FILM_FILL  # the ridge band's share of ranks
            assert np.abs(on - 0.5).max() == pytest.approx(0.5 * rafts, abs=0.01)
            assert cover.mean() == pytest.approx(blown, rel=0.02)


def test_streaks_over_the_whole_sea_stay_a_film():
    """The streaks' ranks never cover more than all of the sea: a white-out draws the film
    everywhere, no more."""
    i = group_inputs(shading.filtering(perspective(1.0, 1.0, 0.1, 1e4), 960,
                                       SpectralField(SeaState(wind_speed=40.0)).slopes, 40.0),
                     **{"Aged Coverage": 0.05, "Blown Coverage": 1.0})
    fac = grain_facs(10_000, 0)
    lp, log_cos = water_model.footprint(NUMPY, i, 3.0, 1.0)
    zero = np.zeros_like(fac)
    drawn, *_ = water_model.foam_cover(NUMPY, i, zero, zero, zero + 0.5, zero, zero, fac,
                                       fac[::-1], grain_facs(10_000, 1), lp, log_cos)
    assert drawn.mean() == pytest.approx(look.AGED_FILM, rel=1e-3)
    assert drawn.max() == pytest.approx(look.AGED_FILM)


def test_blown_lines_thinner_than_a_pixel_draw_their_mean():
    """A blown streak is a line its share of the noise's features wide: drawn while a pixel
    is up to twice as wide (water_model.LINE_PIXELS), its mean film where a pixel is 8 m,
    though the noise's features (33 m) would still be drawn there: lines a fraction of a
    pixel wide crawl as the camera moves."""
    u = sea_states.sea_state(8).wind_speed
    i = group_inputs(shading.filtering(perspective(1.0, 1.0, 0.1, 1e4), 960,
                                       SpectralField(SeaState(wind_speed=u)).slopes, u),
                     **{"Blown Coverage": streaks.blown_coverage(u)})
    fac, net = grain_facs(20_000, 3), grain_facs(20_000, 4)
    zero, half = np.zeros_like(fac), np.full_like(fac, 0.5)
    spread = {}
    for pixel in (0.25, 8.0):
        cover, *_ = water_model.foam_cover(NUMPY, i, zero, zero, half, zero, zero, half, fac,
                                          net, np.log(pixel), 0.0)
        spread[pixel] = cover.std()
        assert cover.mean() == pytest.approx(i["Blown Coverage"], rel=0.05)
    assert spread[0.25] > 0.1 and spread[8.0] < 1e-6
    assert 1.0 / look.FOAM_BLOWN > 8.0 * 2.0  # the noise's own features would be drawn at 8 m
