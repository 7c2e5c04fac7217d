"""The crest sum (band_sum.py): the sideways displacement of the waves up to a band limit, summed
in the grid's own sampling pass, is that of those waves sampled on their own, and the sums
beside it are unchanged (the cue a frame takes from it spreads as its calibration's:
test_foam)."""

import numpy as np
import pytest

from projgrid_addon import band_limit
from projgrid_addon.camera import look_at, perspective
from projgrid_addon.cascade import GEOMETRY, SIDEWAYS
from projgrid_addon.projected_grid import build_grid
from projgrid_addon.spectral_field import SpectralField
from projgrid_addon.spectrum import SeaState

ORIGIN = (0.0, 0.0)  # every sample's points offset from here
SEAS = [SeaState(wind_speed=19.0), SeaState(wind_speed=9.0, swell_height=1.5, swell_period=12.0,
                                            swell_direction=1.0)]


@pytest.mark.parametrize("state", SEAS, ids=["gale", "swell"])
@pytest.mark.parametrize("choppiness", [0.0, 1.0])
def test_the_crest_sum_is_the_capped_waves_sideways(state, choppiness):
    """At points apart, of band limits across every band's fade-in (and of none: every band
    whole), the crest sum at a cap is the SIDEWAYS fields sampled alone at min(lod, cap),
    within float32 rounding (the points' offsets from one origin, so only the sums' order
    differs), at caps on a band's level, inside its fade-in and beyond every
    band, and so with the bands summed in reverse order; the sums beside it are those sampled
    without it, bit for bit."""
    sea = SpectralField(state, choppiness=choppiness, seed=4)
    rng = np.random.default_rng(1)
    xy = rng.uniform(-400.0, 400.0, (2, 40, 50))
    lod = rng.uniform(min(sea.levels) - 1.0, max(sea.levels) + 1.5, (40, 50)).astype(np.float32)
    scale = float(np.abs(sea.sample(xy, 7.0, None, SIDEWAYS)).max())
    reverse = SpectralField(state, choppiness=choppiness, seed=4)
    reverse.groups = reverse.groups[::-1]
    for cap in (sea.levels[2], sea.levels[2] + 0.4, max(sea.levels) + 2.0):
        for points in (lod, None):
            capped = None if points is None else np.minimum(points, np.float32(cap))
            if points is None:
                capped = np.full(lod.shape, np.float32(cap))
            alone = sea.sample(xy, 7.0, capped, SIDEWAYS, origin=ORIGIN)
            for source in (sea, reverse):
                sums, crest = source.sample(xy, 7.0, points, GEOMETRY, crest=cap, origin=ORIGIN)
                assert np.array_equal(sums, source.sample(xy, 7.0, points, GEOMETRY, origin=ORIGIN))
                assert crest.dtype == np.float32 and crest.shape == (2, 40, 50)
                assert np.abs(crest - alone).max() < 1e-5 * scale, (cap, points is None)
    inside = sea.sample(xy, 7.0, lod, GEOMETRY, crest=sea.levels[2] + 0.4)[1]
    assert np.abs(inside - sea.sample(xy, 7.0, lod, SIDEWAYS)).max() > 0.1 * scale


def test_a_grid_s_crest_sum_keeps_the_capped_band_s_share_on_coarse_rows_too():
    """A grid 1 m over the water, so fine that the band the cap falls within is summed on every
    other point of its near rows (band_limit.COARSE): between caps at the band's level and a
    whole band above it, the crest sum grows by the band's part, each point's share of it
    min(lod, cap) - level over lod - level (within float32 rounding), coarse rows too; the
    grid's geometry is the same with the crest sum and without."""
    sea = SpectralField(SeaState(wind_speed=12.0), choppiness=0.8, seed=4)
    eye = np.array([0.0, 0.0, 1.0])
    cam = (look_at(eye, eye + (np.cos(0.4), np.sin(0.4), -1.5)),
           perspective(np.radians(50.0), 16 / 9, 0.1, 1e4))
    level = sea.levels[1]
    result = build_grid(cam, sea, time=6.0, resolution=(257, 257), crest=level + 0.4)
    assert np.array_equal(result.positions, build_grid(cam, sea, time=6.0,
                                                       resolution=(257, 257)).positions)
    xy, lod = result.base, result.lod.reshape(result.base.shape[1:])
    assert np.median(lod) > level + band_limit.COARSE + 1.0  # coarse rows of the band

    def crest(cap):
        return sea.sample(xy, 6.0, lod, GEOMETRY, on_grid=True, crest=cap)[1]
    below, whole = crest(level), crest(level + 1.0)
    share = np.clip(np.minimum(lod, level + 0.4) - level, 0.0, 1.0) / np.clip(
        lod - level, 1e-9, 1.0)
    want = below + share * (whole - below)
    assert np.array_equal(result.crest[1], crest(level + 0.4)) and result.crest[0] == level + 0.4
    assert np.abs(result.crest[1] - want).max() < 1e-5 * np.abs(whole - below).max()
