"""The whitecaps under a keyed wind: each frame is a sea of its own (its wind), calibrated on the
same sea at the winds of a lattice about it (foam.calibrated_at), so frames share calibrations,
the thresholds change continuously with the wind and the share foamed stays Monahan's."""

import numpy as np
import pytest

from projgrid_addon import cascade, foam, residual_foam, spectral_field
from projgrid_addon.camera import look_at, perspective
from projgrid_addon.cascade import WIND_LATTICE, wind_lattice
from projgrid_addon.projected_grid import build_grid
from projgrid_addon.spectral_field import SpectralField
from projgrid_addon.spectrum import SeaState

SPAN = (4.4, 24.0)  # a storm building from Beaufort 3 to 9 (docs: A storm building)


def keyed(u):
    return SpectralField(SeaState(wind_speed=u), choppiness=1.0, seed=4, wind_span=SPAN)


@pytest.mark.parametrize("u", [8.3, 12.7, 19.2])
def test_a_keyed_wind_s_whitecaps_cover_the_share_of_its_own_wind(u):
    """Between the lattice's winds the interpolated thresholds foam, on the frame's own sea at
    every calibrated band limit, the active share of its wind within 3 % (as a calibration of
    that sea itself does exactly)."""
    sea = keyed(u)
    seas = foam.calibrated_at(sea, u)
    assert len(seas) == 2 and seas[0][1] < u < seas[1][1]
    assert seas[1][1] / seas[0][1] == pytest.approx(np.exp(WIND_LATTICE))
    assert sum(weight for _, _, weight in seas) == pytest.approx(1.0)
    _, (levels, thresholds, widths) = foam.crest_calibration(sea, 3.0, u)
    x, y = foam.sea_sample(sea.foam_span, 16384)
    want = foam.active_coverage(sea, u)
    for k in range(0, len(levels), 5):
        cue = foam.crest_cue(sea, np.stack([x, y]), 3.0, np.full(x.shape, levels[k], np.float32))
        got = np.clip((cue - thresholds[k]) / widths[k] + 0.5, 0.0, 1.0).mean()
        assert got == pytest.approx(want, rel=0.03), (u, levels[k], got / want)


def test_a_keyed_wind_s_thresholds_change_continuously_and_are_shared():
    """Across a lattice wind the thresholds do not jump (each side's nearest calibration is
    the same sea's), a steady wind's sea is calibrated on itself, and a wind keyed from 8 to
    10 m/s over 48 frames makes a calibration per lattice wind and second it crosses, not one
    per frame."""
    lattice = float(np.exp(np.ceil(np.log(9.0) / WIND_LATTICE) * WIND_LATTICE))
    below, above = (foam.crest_calibration(keyed(w), 2.0, w)[1]
                    for w in (lattice * (1 - 1e-6), lattice * (1 + 1e-6)))
    assert np.allclose(below[1], above[1], rtol=1e-4, atol=1e-6)
    assert np.allclose(below[2], above[2], rtol=1e-4, atol=1e-6)
    steady = SpectralField(SeaState(wind_speed=9.0), choppiness=1.0, seed=4)
    assert foam.calibrated_at(steady, 9.0) == ((steady, 9.0, 1.0),)
    kept = foam.Calibrations()
    made = []

    def counted(source, *key):  # what is made, not how (the share: the test above)
        made.append((source.state.wind_speed, key[0]))
        levels = np.asarray(source.foam_levels())
        return levels, np.zeros_like(levels), np.ones_like(levels)

    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(foam, "CALIBRATIONS", kept)
        patch.setattr(foam, "calibration", counted)
        for frame in range(49):
            u = 8.0 + 2.0 * frame / 48.0
            foam.crest_calibration(keyed(u), frame / 24.0, u)
    winds = {w for w, _ in made}
    assert len(winds) <= np.log(10.0 / 8.0) / WIND_LATTICE + 3, sorted(winds)
    assert len(made) == len(set(made)) <= 3 * len(winds), made  # each made once


@pytest.mark.parametrize("u", [6.1, 13.4])
def test_a_keyed_wind_s_sea_is_its_wind_s(u):
    """Between the lattice's winds the keyed sea's waves (their amplitudes interpolated, their
    phases shared) have the height of a steady sea of that wind within 1 %."""
    steady = SpectralField(SeaState(wind_speed=u), choppiness=1.0, seed=4)
    assert keyed(u).spread[0] == pytest.approx(steady.spread[0], rel=0.01)


def test_a_keyed_wind_s_waves_are_the_lattice_winds_interpolated():
    """Between two lattice winds the keyed sea's waves are theirs interpolated (each wave's
    amplitude linearly in log wind, its phase shared), and another frame in the same lattice
    cell evaluates no spectrum (the lattice winds' are kept)."""
    u = 9.3
    (w0, a), (w1, b) = wind_lattice(u)
    assert w0 < u < w1 and a + b == pytest.approx(1.0)
    assert wind_lattice(w1) == ((pytest.approx(w1), 1.0),)  # a lattice wind: itself alone
    seas = [keyed(w) for w in (u, w0, w1)]
    for c, c0, c1 in zip(*(s.cascades for s in seas), strict=True):
        assert np.allclose(np.abs(c.h0), a * np.abs(c0.h0) + b * np.abs(c1.h0), rtol=1e-5,
                           atol=1e-12)
    misses = cascade._cell_waves.cache_info().misses
    keyed(u * 1.001)
    assert cascade._cell_waves.cache_info().misses == misses


def test_a_keyed_wind_s_residual_foam_is_shared_between_frames_and_continuous(monkeypatch):
    """Under a wind keyed from 8 to 10 m/s, each frame a sea of its own and a grid built for
    it (as frame_plan does), the residual foam is the lattice winds' seas' (each with its own
    decay time, so its past lattice of times is fixed), weighted as their waves are: a frame
    after another transforms no tile at a past time unless a lattice time or a lattice wind
    is new (a sea of each frame's own made them all, every frame), and the residual changes
    by less across a lattice wind than within a frame's step elsewhere."""
    made = []
    real = spectral_field.SpectralField._at

    def counted(sea, t, fields=spectral_field.GEOMETRY):
        if t not in sea._moments and t < 2.0:  # a past sample's time: not the frame's
            made.append((id(sea), t))
        return real(sea, t, fields)
    monkeypatch.setattr(spectral_field.SpectralField, "_at", counted)
    eye = np.array([0.0, 0.0, 8.0])
    cam = (look_at(eye, eye + (0.0, 1.0, -0.2)), perspective(np.radians(40.0), 16 / 9, 0.1, 1e4))
    span = (8.0, 10.0)
    lattice = float(np.exp(np.ceil(np.log(8.5) / WIND_LATTICE) * WIND_LATTICE))
    frames, residuals = [], []
    for u in (8.50, 8.52, lattice * (1 - 1e-6), lattice * (1 + 1e-6), 8.62, 8.64):
        sea = SpectralField(SeaState(wind_speed=u), choppiness=1.0, seed=4, wind_span=span)
        grid = build_grid(cam, sea, time=2.0, resolution=(33, 65),
                          crest=foam.whitecap_level(sea))
        made.clear()
        residuals.append(foam.foam_field(sea, grid, 2.0, u, True, [], 0.0)[1])
        frames.append(len(made))
    assert frames[1] == frames[5] == 0 and frames[0] > 0, frames  # the tiles kept, not made
    steps = [np.abs(b - a).max() for a, b in zip(residuals[:-1], residuals[1:], strict=True)]
    assert steps[2] < 0.2 * min(steps[0], steps[4]) and max(steps) > 0.0, steps


def test_a_keyed_wind_s_still_grid_keeps_its_past_cues(monkeypatch):
    """Under a keyed wind a still camera's grid is fitted to the span's strongest sea
    (SpectralField.volume_spread), the same whatever each frame's wind, so the residual foam's
    past cues made at one frame serve the next (a grid fitted to each frame's own sea was new
    every frame, and made them all again)."""
    cues, real = [], residual_foam.cue_at
    monkeypatch.setattr(residual_foam, "cue_at", lambda *a, **k: cues.append(1) or real(*a, **k))
    monkeypatch.setattr(residual_foam, "PAST", residual_foam.Kept(48))  # none kept before
    eye = np.array([0.0, 0.0, 8.0])
    cam = (look_at(eye, eye + (0.0, 1.0, -0.2)), perspective(np.radians(40.0), 16 / 9, 0.1, 1e4))
    keys, made = set(), []
    for u in (8.50, 8.51, 8.52):
        sea = SpectralField(SeaState(wind_speed=u), choppiness=1.0, seed=4, wind_span=(8.0, 10.0))
        grid = build_grid(cam, sea, time=2.0, resolution=(33, 65), crest=foam.whitecap_level(sea))
        keys.add(residual_foam.grid_key(grid))
        cues.clear()
        assert foam.foam_field(sea, grid, 2.0, u, True, [], 0.0)[1].max() > 0.0
        made.append(len(cues))
    assert len(keys) == 1 and made[0] > 0 and made[1:] == [0, 0], made
