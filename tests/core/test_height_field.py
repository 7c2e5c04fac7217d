"""Height field: true bound, determinism, fast path against the exact reference, band limit."""

import numpy as np
import pytest

from projgrid_addon import HeightField, octave_weights
from projgrid_addon import noise as _noise

G = np.array([[1, 1, 0], [-1, 1, 0], [1, -1, 0], [-1, -1, 0], [1, 0, 1], [-1, 0, 1],
              [1, 0, -1], [-1, 0, -1], [0, 1, 1], [0, -1, 1], [0, 1, -1], [0, -1, -1]], float)


def worst_case(p):
    """sup over every assignment of gradients to the 8 corners of |noise| at points p in a cell."""
    total = 0.0
    for corner in np.ndindex(2, 2, 2):
        d = p - np.array(corner)
        w = np.prod([_noise.fade(p[:, a]) if c else 1 - _noise.fade(p[:, a])
                     for a, c in enumerate(corner)], axis=0)
        total = total + w * np.abs(d @ G.T).max(axis=1)
    return total


def test_noise_bound_is_a_true_and_tight_bound():
    t = np.linspace(0, 1, 61)
    p = np.stack(np.meshgrid(t, t, t), -1).reshape(-1, 3)
    sup = worst_case(p).max()
    assert sup <= _noise.NOISE_BOUND
    assert sup >= 0.999 * _noise.NOISE_BOUND  # tight: within 0.1 %
    rng = np.random.default_rng(3)
    x, y, z = rng.uniform(-1e4, 1e4, (3, 400_000))
    n = _noise.noise(x, y, z, _noise.octave_key(5, 0))
    assert np.abs(n).max() < _noise.NOISE_BOUND


def test_noise_spread_constants_are_the_noise_s():
    """NOISE_STD and GRADIENT_RMS, which fit the displaceable volume, re-measured (1 %)."""
    rng = np.random.default_rng(8)
    x, y, z = rng.uniform(-1e3, 1e3, (3, 200_000))
    key, e = _noise.octave_key(2, 3), 1e-3
    assert _noise.noise(x, y, z, key).std() == pytest.approx(_noise.NOISE_STD, rel=0.01)
    gx = _noise.noise(x + e, y, z, key) - _noise.noise(x - e, y, z, key)
    gy = _noise.noise(x, y + e, z, key) - _noise.noise(x, y - e, z, key)
    rms = np.sqrt(np.mean(gx * gx + gy * gy)) / (2.0 * e)
    assert rms == pytest.approx(_noise.GRADIENT_RMS, rel=0.01)


def test_spread_is_the_field_s():
    """The field's standard deviation and its choppy displacement's root mean square are
    `spread`'s (10 %: over 4 km a 100 m first octave gives some 1,600 independent cells)."""
    hf = HeightField(amplitude=1.5, wave_scale=100.0, octaves=5, roughness=0.6, method="exact",
                     choppiness=0.8)
    x, y = np.random.default_rng(9).uniform(0.0, 4e3, (2, 100_000))
    h, d = hf.displacement(np.stack([x, y]), 2.0)
    assert hf.spread == pytest.approx((h.std(), np.sqrt((d * d).sum(0).mean())), rel=0.10)
    # Tessendorf's displacement of a wave, lambda A sin against its height A cos: as large
    # (rms) as the height times the choppiness, when k is the waves' own (noise.WAVELENGTH).
    assert np.sqrt((d * d).sum(0).mean()) == pytest.approx(0.8 * h.std(), rel=0.10)


def test_choppy_noise_moves_points_toward_the_crests():
    """The noise's choppy displacement (Tessendorf's form, per octave) sharpens the crests as the
    spectrum's does: the surface compresses (Jacobian < 1) where it is high and stretches where
    it is low."""
    hf = HeightField(amplitude=1.5, wave_scale=40.0, octaves=4, roughness=0.5, method="exact",
                     choppiness=1.0)
    step = 0.5  # a tenth of the shortest octave
    k = np.arange(512) * step
    xy = np.stack(np.meshgrid(k, k + 100.0))
    h, d = hf.displacement(xy, 2.0)
    dx_dy, dx_dx = np.gradient(d[0], step)
    dy_dy, dy_dx = np.gradient(d[1], step)
    jacobian = (1.0 + dx_dx) * (1.0 + dy_dy) - dx_dy * dy_dx
    assert np.corrcoef(h.ravel(), jacobian.ravel())[0, 1] < -0.3


@pytest.mark.parametrize("method", ["exact", "fast"])
def test_heights_within_bound(method):
    hf = HeightField(amplitude=2.0, octaves=6, roughness=0.9, method=method)
    rng = np.random.default_rng(1)
    x, y = rng.uniform(-5e3, 5e3, (2, 200_000))
    h = hf.heights(x, y, 12.5)
    assert np.abs(h).max() <= hf.bound
    assert np.abs(h).max() > 0.3 * hf.bound  # and not trivially far inside it


@pytest.mark.parametrize("method", ["exact", "fast"])
def test_heights_are_bit_identical_whatever_the_batch_or_order(method):
    rng = np.random.default_rng(2)
    x, y = rng.uniform(-1e6, 1e6, (2, 5000))
    lod = rng.uniform(-1, 10, 5000)
    a = HeightField(seed=11, method=method)
    whole = a.heights(x, y, 1e7, lod)
    b = HeightField(seed=11, method=method)
    b.heights(x[:10], y[:10], 3.0)  # another frame first
    perm = rng.permutation(5000)
    shuffled = b.heights(x[perm], y[perm], 1e7, lod[perm])
    assert np.array_equal(shuffled, whole[perm])
    part = HeightField(seed=11, method=method).heights(x[123:456], y[123:456], 1e7, lod[123:456])
    assert np.array_equal(part, whole[123:456])


def test_seamless_and_continuous():
    hf = HeightField(method="exact", octaves=4)
    x = np.linspace(-3 * hf.wave_scale, 3 * hf.wave_scale, 200_001)
    h = hf.heights(x, np.full_like(x, 17.3), 4.0)
    step = np.abs(np.diff(h)).max()
    assert step < 1e-3 * hf.bound  # no jumps at cell or tile borders


def test_animated():
    hf = HeightField(method="exact")
    x, y = np.random.default_rng(4).uniform(-100, 100, (2, 1000))
    assert np.abs(hf.heights(x, y, 0.0) - hf.heights(x, y, 2.0)).max() > 0.05 * hf.bound


def test_fast_path_error_against_exact():
    """Measured error of the texture path (bilinear, 4 texels per cell) per unit of bound."""
    rng = np.random.default_rng(5)
    x, y = rng.uniform(-2e3, 2e3, (2, 100_000))
    exact = HeightField(method="exact", octaves=8).heights(x, y, 7.0)
    fast = HeightField(method="fast", octaves=8).heights(x, y, 7.0)
    err = np.abs(fast - exact) / HeightField(octaves=8).bound
    assert np.sqrt(np.mean(err**2)) < 0.02
    assert err.max() < 0.08


def test_band_limit_fades_octaves():
    lod = np.array([-1.0, 0.0, 0.5, 1.0, 3.0])
    assert np.allclose(octave_weights(lod, 0), [0, 0, 0.5, 1, 1])
    assert np.allclose(octave_weights(lod, 2), [0, 0, 0, 0, 1])
    hf = HeightField(method="exact", octaves=5)
    x, y = np.random.default_rng(6).uniform(-100, 100, (2, 1000))
    coarse = hf.heights(x, y, 1.0, np.full(1000, 1.0))  # octave 0 only
    only0 = HeightField(method="exact", octaves=1).heights(x, y, 1.0)
    assert np.allclose(coarse, only0)
    assert np.array_equal(hf.heights(x, y, 1.0, np.full(1000, -1.0)), np.zeros(1000))


@pytest.mark.parametrize(("kwargs", "name"), [
    ({"amplitude": -1}, "amplitude"), ({"octaves": -1}, "octaves"), ({"octaves": 2.5}, "octaves"),
    ({"roughness": -0.1}, "roughness"), ({"wave_scale": 0}, "wave_scale"),
    ({"speed": float("nan")}, "speed"), ({"method": "magic"}, "method"),
])
def test_bad_parameters_name_themselves(kwargs, name):
    with pytest.raises(ValueError, match=name):
        HeightField(**kwargs)


def test_nan_time_is_refused():
    with pytest.raises(ValueError, match="time"):
        HeightField().heights(np.zeros(3), np.zeros(3), float("nan"))
