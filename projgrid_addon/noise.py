"""Animated gradient noise (thesis §1.6): improved Perlin noise in (x, y, time), tileable in x, y.

The noise is periodic in x and y with `PERIOD` lattice cells so it can be rendered into tileable
textures (App. B), and unbounded in the third, time, axis. Only integer and polynomial arithmetic is
used, so a point's value depends on nothing but its coordinates, bit for bit.

Within one pair of time slices k, k+1 the noise is linear in two 2D fields per slice:
    noise(x, y, z) = (1 - s)(A_k + f B_k) + s (A_k+1 + (f - 1) B_k+1),  f = z - k,  s = fade(f)
where A_k interpolates the gradients' xy part and B_k their z part. The exact path evaluates that
per point; the texture path (noise_tiles.NoiseTiles) renders A_k, B_k once per slice.
"""

import numpy as np

PERIOD = 32
MAX_OCTAVES = 24  # the most octaves a HeightField sums
# sup |noise| over every point and every assignment of gradients, found by dense search and local
# refinement (1.0363538...), rounded up; tests/core/test_height_field.py re-checks it.
NOISE_BOUND = 1.0364
# The noise's standard deviation and its gradient's root mean square per lattice unit, measured
# over 200,000 random points of three seeds; tests/core/test_height_field.py re-measures them.
NOISE_STD = 0.269
GRADIENT_RMS = 0.994
# The length, in lattice units, of the waves the noise draws: 2 pi over its rms wavenumber
# sqrt(m2 / m0) = GRADIENT_RMS / NOISE_STD, so a sinusoid of that wavelength is as steep for its
# height (1.70: a lattice cell is not a wave).
WAVELENGTH = 2.0 * np.pi * NOISE_STD / GRADIENT_RMS

_GRADIENTS = np.array(
    [[1, 1, 0], [-1, 1, 0], [1, -1, 0], [-1, -1, 0],
     [1, 0, 1], [-1, 0, 1], [1, 0, -1], [-1, 0, -1],
     [0, 1, 1], [0, -1, 1], [0, 1, -1], [0, -1, -1]], dtype=np.float64,
)
_GX, _GY, _GZ = (np.ascontiguousarray(_GRADIENTS[:, i]) for i in range(3))
_MUL = (np.uint64(0x9E3779B97F4A7C15), np.uint64(0xC2B2AE3D27D4EB4F), np.uint64(0x165667B19E3779F9))
_MIX = (np.uint64(0xBF58476D1CE4E5B9), np.uint64(0x94D049BB133111EB))


def _mix(h):
    """splitmix64 finaliser (wrapping uint64 arithmetic)."""
    h = h ^ (h >> np.uint64(30))
    h = h * _MIX[0]
    h = h ^ (h >> np.uint64(27))
    h = h * _MIX[1]
    return h ^ (h >> np.uint64(31))


def uniforms(key, *ints):
    """Uniform values in [0, 1) hashed from integer arrays (broadcast) and a salt `key`."""
    h = np.array([key & 0xFFFFFFFFFFFFFFFF], np.uint64) * _MUL[2]
    for i, v in enumerate(ints):
        h = _mix(h ^ np.asarray(v, np.int64).astype(np.uint64) * _MUL[i % 2])
    return (h >> np.uint64(11)).astype(np.float64) * (1.0 / 2.0**53)


def octave_key(seed, octave):
    """A 64-bit key that decorrelates seeds and octaves."""
    s = np.array([int(seed) & 0xFFFFFFFFFFFFFFFF], dtype=np.uint64)
    o = np.array([octave + 1], dtype=np.uint64)
    return _mix(_mix(s) ^ o * _MUL[2])[0]


def _gradient(ix, iy, k, key):
    """Gradient index of lattice points (ix, iy wrapped to PERIOD, slice k)."""
    h = (ix & (PERIOD - 1)).astype(np.uint64) * _MUL[0]
    h = h ^ (iy & (PERIOD - 1)).astype(np.uint64) * _MUL[1]
    h = h ^ np.asarray(k, dtype=np.int64).astype(np.uint64) * _MUL[2]
    return (_mix(h ^ key) % np.uint64(12)).astype(np.intp)


def fade(t):
    return t * t * t * (t * (t * 6.0 - 15.0) + 10.0)


def slice_terms(ix, iy, fx, fy, k, key):
    """A_k and B_k at points in cells (ix, iy) with fractions (fx, fy), time slice k."""
    u, v = fade(fx), fade(fy)
    a = b = None
    for cx in (0, 1):
        for cy in (0, 1):
            g = _gradient(ix + cx, iy + cy, k, key)
            w = (u if cx else 1.0 - u) * (v if cy else 1.0 - v)
            da = _GX[g] * (fx - cx) + _GY[g] * (fy - cy)
            db = _GZ[g]
            a = w * da if a is None else a + w * da
            b = w * db if b is None else b + w * db
    return a, b


def time_weights(z):
    """The slice k and the weights of (A_k, B_k, A_k+1, B_k+1) at time coordinate z."""
    k = np.floor(z)
    f = z - k
    s = fade(f)
    return k.astype(np.int64), ((1.0 - s), (1.0 - s) * f, s, s * (f - 1.0))


def noise(x, y, z, key):
    """Exact gradient noise at lattice coordinates (x, y, z), |noise| < NOISE_BOUND."""
    fx0, fy0 = np.floor(x), np.floor(y)
    ix, iy = fx0.astype(np.int64), fy0.astype(np.int64)
    fx, fy = x - fx0, y - fy0
    k, (c0, c1, c2, c3) = time_weights(z)
    a0, b0 = slice_terms(ix, iy, fx, fy, k, key)
    a1, b1 = slice_terms(ix, iy, fx, fy, k + 1, key)
    return c0 * a0 + c1 * b0 + c2 * a1 + c3 * b1
