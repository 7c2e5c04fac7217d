"""The whitecaps against their share at every band limit: grids coarser than the whitecaps'
level (a band fading in) and finer (the longer waves alone, over a finer spacing)."""

import numpy as np
import pytest

from projgrid_addon import band_limit, foam, sea_states
from projgrid_addon.spectral_field import SpectralField
from projgrid_addon.spectrum import SeaState


@pytest.mark.parametrize("force", [4, 8])
def test_whitecaps_cover_their_share_at_every_grid_spacing(force):
    """On grids 1.5 to 12 m apart (band limits between the calibrated ones, where a band fades
    in and the cue's spread changes fastest), the whitecaps cover the calibrated share within
    0.7-1.3x: with two calibrations per band's fade-in, a 6 m grid at force 4 covered a sixth,
    with four evenly spread a 2 m grid two fifths."""
    preset = sea_states.sea_state(force)
    source = SpectralField(SeaState(wind_speed=preset.wind_speed, fetch=preset.fetch),
                           choppiness=preset.choppiness, seed=2)
    coverage = foam.foam_coverage(preset.wind_speed)
    calibration = foam.calibration(source, 19.0, coverage, 16384)
    for spacing in np.geomspace(1.5, 12.0, 7):
        n = int(480 / spacing)
        xy = np.stack(np.meshgrid(np.arange(n) * spacing, np.arange(n) * spacing))
        lod = np.full(xy.shape[1:], band_limit.lod_for_spacing(source.wave_scale, spacing),
                      np.float32)
        cover = foam.whitecaps(source.foam_cue(xy, 19.0, lod), lod, calibration).mean()
        assert 0.7 * coverage <= cover <= 1.3 * coverage, (spacing, cover / coverage)


@pytest.mark.parametrize("force", [4, 8])
def test_a_grid_finer_than_a_whitecap_covers_their_share(force):
    """Vertices finer than the whitecaps' level take the cue of the waves it keeps
    (foam.foam_field) over their own finer spacing, whose differences see more of those waves'
    folding than the level's spacing does: their thresholds are calibrated so
    (foam.foam_thresholds), and at one to three levels finer the whitecaps cover the share
    within 0.75-1.25x (by the level's thresholds force 4's covered 1.3-1.5x). On points the
    calibration did not use."""
    preset = sea_states.sea_state(force)
    source = SpectralField(SeaState(wind_speed=preset.wind_speed, fetch=preset.fetch),
                           choppiness=preset.choppiness, seed=2)
    coverage = foam.foam_coverage(preset.wind_speed)
    placed = foam.whitecap_level(source)
    calibration = foam.calibration(source, 19.0, coverage, 16384)
    x, y = foam.sea_sample(source.foam_span, 65536)
    xy = np.stack([x + 3.3, y + 7.7])
    for finer in (1.0, 2.0, 3.0):
        lod = np.full(x.shape, placed + finer, np.float32)
        cover = foam.whitecaps(foam.crest_cue(source, xy, 19.0, lod), lod, calibration).mean()
        assert 0.75 * coverage <= cover <= 1.25 * coverage, (finer, cover / coverage)
