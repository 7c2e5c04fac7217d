"""The residual foam's machinery on its own: the coarse sampling (`on_coarse`) and the kept past
cues (`PAST`, a `Kept`), which must change nothing a frame draws."""

import numpy as np
import pytest

from projgrid_addon import foam, residual_foam, sea_states
from projgrid_addon.camera import look_at, perspective
from projgrid_addon.projected_grid import build_grid
from projgrid_addon.spectral_field import SpectralField
from projgrid_addon.spectrum import SeaState


def test_on_coarse_samples_every_other_point_and_spreads_back_linearly():
    """`make` sees every other point each way, `steps` times over, with the band limit `steps`
    lower (at most `top`); a field linear in the points comes back exactly at every point."""
    rows, cols = 37, 53
    xy = np.stack(np.meshgrid(np.arange(cols) * 1.5, np.arange(rows) * 2.0)).astype(np.float64)
    lod = np.full((rows, cols), 3.0, np.float32)
    seen = []

    def make(points, at):
        seen.append((points.shape, float(at.min()), float(at.max())))
        return 0.25 * points[0] - 0.5 * points[1] + 7.0
    out = residual_foam.on_coarse(make, xy, lod, 2, top=0.5)
    assert seen == [((2, 10, 14), 0.5, 0.5)]  # 37 -> 19 -> 10 rows, 53 -> 27 -> 14 columns
    want = (0.25 * xy[0] - 0.5 * xy[1] + 7.0).ravel()
    assert out.dtype == np.float32 and out == pytest.approx(want, rel=1e-6, abs=1e-4)
    seen.clear()
    residual_foam.on_coarse(make, xy, lod, 1)
    assert seen == [((2, 19, 27), 2.0, 2.0)]


def test_a_frame_s_residual_foam_is_the_same_with_its_past_kept_or_made(monkeypatch):
    """The past cues kept for a grid (residual_foam.PAST) are those the frame would make: a
    gale's frame after earlier frames (most of its past kept, from a sequence played: it makes
    fewer cues) draws the same residual foam as the same frame with nothing kept."""
    made = []
    real = residual_foam.cue_at

    def counted(source, xy, when, lod, top=None):
        made.append(len(when) if isinstance(when, tuple) else 1)
        return real(source, xy, when, lod, top)
    monkeypatch.setattr(residual_foam, "cue_at", counted)
    preset = sea_states.sea_state(8)
    state = SeaState(wind_speed=preset.wind_speed, fetch=preset.fetch)
    eye = np.array([0.0, 0.0, 12.0])
    cam = (look_at(eye, eye + (0.0, 1.0, -0.3)), perspective(np.radians(40.0), 16 / 9, 0.1, 1e4))

    def frame(source, t):
        result = build_grid(cam, source, time=t, resolution=(65, 129),
                            crest=foam.whitecap_level(source))
        return foam.foam_field(source, result, t, preset.wind_speed, True, [], 0.0)

    cold = frame(SpectralField(state, choppiness=preset.choppiness, seed=5), 30.0)
    cold_made = sum(made)
    warm = SpectralField(state, choppiness=preset.choppiness, seed=5)
    for t in (28.5, 29.25, 29.96):
        frame(warm, t)
    made.clear()
    again = frame(warm, 30.0)
    assert cold[1].max() > 0.0 and sum(made) < cold_made
    assert all(np.array_equal(a, b) for a, b in zip(cold, again, strict=True))
