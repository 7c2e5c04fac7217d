"""The height field f_HF (thesis §1.6 Eq. 1.2, §3.2, App. B): fractal animated noise.

    f_HF(x, y, t) = amplitude * sum_i  alpha^i * w_i * noise_i(x 2^i / scale, y 2^i / scale, z_i(t))

Octave i has wavelength scale / 2^i and evolves at the deep-water rate sqrt(g / (2 pi lambda_i)),
scaled by `speed`, so small waves change faster than large ones. Each octave has its own hash key.
w_i in [0, 1] is the band limit: 1 where the grid can carry octave i, fading to 0 over one octave as
a mip-map would (see `octave_weights`). noise_i is normalised so that |noise_i| <= 1, which makes
`bound` a true bound of every height either path returns.

Two evaluation paths give the same function: "exact" evaluates the gradient noise per point (the
reference); "fast" is the thesis's path, which renders each octave into a tileable texture per frame
and samples it bilinearly (error measured in tests/core/test_height_field.py).
"""

from collections import OrderedDict
from functools import lru_cache

import numpy as np

from . import noise as _noise
from .validation import finite, integer, non_negative, positive

GRAVITY = 9.81
MAX_OCTAVES = 24
METHODS = ("exact", "fast")


def octave_weights(lod, octave):
    """Band-limit weight of `octave` at per-point level of detail `lod` (None: no band limit).

    lod = log2(scale / (2 * spacing)): octave i is kept whole while its wavelength is at least four
    grid spacings and faded out linearly (in octaves) until it is two spacings, the Nyquist limit.
    """
    if lod is None:
        return None
    return np.clip(lod - octave, 0.0, 1.0)


class NoiseTiles:
    """Per-octave tileable noise textures (App. B), rendered per time slice and cached.

    A tile covers PERIOD x PERIOD lattice cells with `texels` samples per cell, plus one wrapped row
    and column so bilinear lookups need no modulo. The texture for time z is a fixed linear
    combination of the slice fields A_k, B_k, A_k+1, B_k+1, so a frame costs four array ops per
    octave and new slices are rendered only when z crosses an integer.
    """

    def __init__(self, seed, texels=4, cache_slices=64):
        self.seed = int(seed)
        self.texels = integer("texels", texels, 1, 64)
        self.size = _noise.PERIOD * self.texels
        n = self.size + 1
        lattice = np.arange(n, dtype=np.float64) / self.texels
        cells = np.floor(lattice)
        ix = cells.astype(np.int64)
        frac = lattice - cells
        self._ix, self._iy = np.meshgrid(ix, ix, indexing="xy")
        self._fx, self._fy = np.meshgrid(frac, frac, indexing="xy")
        self._slices = OrderedDict()
        self._cache_slices = cache_slices
        self._frame = {}

    def _slice(self, octave, k):
        """A_k and B_k of an octave as one (2, (size+1)^2) float32 array, cached."""
        key = (octave, k)
        hit = self._slices.get(key)
        if hit is not None:
            self._slices.move_to_end(key)
            return hit
        a, b = _noise.slice_terms(
            self._ix, self._iy, self._fx, self._fy, k, _noise.octave_key(self.seed, octave)
        )
        hit = np.stack([a.ravel(), b.ravel()]).astype(np.float32)
        self._slices[key] = hit
        if len(self._slices) > self._cache_slices:
            self._slices.popitem(last=False)
        return hit

    def texture(self, octave, z):
        """The (size+1)^2 float32 texture (flattened) of octave `octave` at time coordinate z."""
        key = (octave, z)
        tex = self._frame.get(key)
        if tex is None:
            k, weights = _noise.time_weights(np.float64(z))
            c = np.array(weights, dtype=np.float32)
            (a0, b0), (a1, b1) = self._slice(octave, int(k)), self._slice(octave, int(k) + 1)
            tex = c[0] * a0
            tex += c[1] * b0
            tex += c[2] * a1
            tex += c[3] * b1
            if len(self._frame) > 4 * MAX_OCTAVES:
                self._frame.clear()
            self._frame[key] = tex
        return tex

    def sample(self, octave, z, x, y):
        """Bilinear lookup of the octave's texture at lattice coordinates (x, y)."""
        tex = self.texture(octave, z)
        sx, sy = x * self.texels, y * self.texels
        fx0, fy0 = np.floor(sx), np.floor(sy)
        mask = self.size - 1
        i = fx0.astype(np.int64) & mask
        j = fy0.astype(np.int64) & mask
        fx = (sx - fx0).astype(np.float32)
        fy = (sy - fy0).astype(np.float32)
        row = self.size + 1
        idx = j * row + i
        t00, t10 = tex[idx], tex[idx + 1]
        t01, t11 = tex[idx + row], tex[idx + row + 1]
        bottom = t00 + fx * (t10 - t00)
        top = t01 + fx * (t11 - t01)
        return bottom + fy * (top - bottom)


@lru_cache(maxsize=8)
def shared_tiles(seed, texels):
    """The NoiseTiles of a seed, shared by every HeightField using it: a field is rebuilt whenever
    a setting such as amplitude changes (or is animated), and its rendered slices stay valid."""
    return NoiseTiles(seed, texels)


class HeightField:
    """Fractal animated noise heights with a true displacement bound (S_upper/S_lower of §2.2)."""

    def __init__(self, amplitude=0.5, wave_scale=40.0, octaves=8, roughness=0.5, speed=1.0,
                 seed=0, method="fast", texels=4):
        self.amplitude = non_negative("amplitude", amplitude)
        self.wave_scale = positive("wave_scale", wave_scale)
        self.octaves = integer("octaves", octaves, 0, MAX_OCTAVES)
        self.roughness = non_negative("roughness", roughness)
        self.speed = finite("speed", speed)
        self.seed = integer("seed", seed, -(2**63), 2**64 - 1)
        if method not in METHODS:
            raise ValueError(f"method: must be one of {METHODS}, got {method!r}")
        self.method = method
        self._tiles = shared_tiles(self.seed, texels) if method == "fast" else None

    @property
    def bound(self):
        """max |f_HF|: amplitude * sum alpha^i, since every octave is normalised to |noise| <= 1."""
        return self.amplitude * sum(self.roughness**i for i in range(self.octaves))

    def wavelength(self, octave):
        return self.wave_scale / 2.0**octave

    def time_coordinate(self, octave, t):
        """Noise time coordinate of an octave: deep-water frequency sqrt(g / (2 pi lambda))."""
        return t * self.speed * np.sqrt(GRAVITY / (2.0 * np.pi * self.wavelength(octave)))

    def heights(self, x, y, t, lod=None):
        """f_HF at world points (x, y) and time t (float64, same shape as x).

        `lod` (per point, see `octave_weights`) band-limits the sum; None keeps every octave.
        Only points where an octave's weight is non-zero evaluate it.
        """
        t = finite("time", t)
        x = np.asarray(x, dtype=np.float64)
        y = np.asarray(y, dtype=np.float64)
        h = np.zeros(x.shape, dtype=np.float64)
        if self.amplitude == 0.0:
            return h
        scale = self.amplitude / _noise.NOISE_BOUND
        for i in range(self.octaves):
            gain = scale * self.roughness**i
            if gain == 0.0:
                continue
            w = octave_weights(lod, i)
            if w is None:
                sel, wi = slice(None), 1.0
            else:
                sel = np.flatnonzero(w > 0.0)
                if sel.size == 0:
                    break
                wi = w.ravel()[sel]
            xs = x.ravel()[sel] / self.wavelength(i)
            ys = y.ravel()[sel] / self.wavelength(i)
            z = self.time_coordinate(i, t)
            if self._tiles is None:
                key = _noise.octave_key(self.seed, i)
                n = _noise.noise(xs, ys, np.full(xs.shape, z), key)
            else:
                n = self._tiles.sample(i, z, xs, ys)
            h.ravel()[sel] += gain * wi * n
        return h
