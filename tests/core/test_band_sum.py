"""The crest sum (band_sum.py): the sideways displacement of the waves up to the whitecaps' level,
summed in the grid's own sampling pass, is that of those waves sampled on their own (the cue a
frame takes from it spreads as its calibration's: test_foam)."""

import numpy as np
import pytest

from projgrid_addon import band_limit
from projgrid_addon.camera import look_at, perspective
from projgrid_addon.cascade import GEOMETRY, SIDEWAYS
from projgrid_addon.projected_grid import build_grid
from projgrid_addon.spectral_field import SpectralField
from projgrid_addon.spectrum import SeaState

SEAS = [SeaState(wind_speed=19.0), SeaState(wind_speed=9.0, swell_height=1.5, swell_period=12.0,
                                            swell_direction=1.0)]


@pytest.mark.parametrize("state", SEAS, ids=["gale", "swell"])
@pytest.mark.parametrize("choppiness", [0.0, 1.0])
def test_the_crest_sum_is_the_capped_waves_sideways(state, choppiness):
    """At points apart, of band limits across every band's fade-in, the crest sum at a cap is
    the SIDEWAYS fields sampled alone at min(lod, cap), within float32 rounding, at caps on a
    band's level, inside its fade-in and beyond every band; the sums beside it are those
    sampled without it, bit for bit (the grid's geometry does not change with it)."""
    sea = SpectralField(state, choppiness=choppiness, seed=4)
    rng = np.random.default_rng(1)
    xy = rng.uniform(-400.0, 400.0, (2, 40, 50))
    lod = rng.uniform(min(sea.levels) - 1.0, max(sea.levels) + 1.5, (40, 50)).astype(np.float32)
    scale = float(np.abs(sea.sample(xy, 7.0, None, SIDEWAYS)).max())
    for cap in (sea.levels[2], sea.levels[2] + 0.4, max(sea.levels) + 2.0):
        sums, crest = sea.sample(xy, 7.0, lod, GEOMETRY, crest=cap)
        assert np.array_equal(sums, sea.sample(xy, 7.0, lod, GEOMETRY))
        alone = sea.sample(xy, 7.0, np.minimum(lod, np.float32(cap)), SIDEWAYS)
        assert crest.dtype == np.float32 and crest.shape == (2, 40, 50)
        assert np.abs(crest - alone).max() < 1e-5 * scale, cap
    assert not np.allclose(crest, sea.sample(xy, 7.0, lod, SIDEWAYS)[:, :1])


def test_the_crest_sum_of_a_near_grid_keeps_the_capped_band_s_share_on_coarse_rows():
    """A grid 1 m over the water, so fine that the band the cap falls within is summed on
    every other point of its near rows (band_limit.COARSE): there too the crest sum is that
    band's share of its waves, as sampled alone at min(lod, cap), point by point (within 2 %:
    the grid's own sums differ from those by 0.7 % of their largest there)."""
    sea = SpectralField(SeaState(wind_speed=12.0), choppiness=0.8, seed=4)
    eye = np.array([0.0, 0.0, 1.0])
    cam = (look_at(eye, eye + (np.cos(0.4), np.sin(0.4), -1.5)),
           perspective(np.radians(50.0), 16 / 9, 0.1, 1e4))
    cap = sea.levels[1] + 0.4
    result = build_grid(cam, sea, time=6.0, resolution=(257, 257), crest=cap)
    xy, lod = result.base, result.lod.reshape(result.base.shape[1:])
    assert np.median(lod) > sea.levels[1] + band_limit.COARSE + 1.0  # coarse rows of it
    alone = sea.sample(xy, 6.0, np.minimum(lod, np.float32(cap)), SIDEWAYS)
    assert np.abs(result.crest - alone).max() < 0.02 * np.abs(alone).max()
