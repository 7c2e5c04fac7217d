"""The height field f_HF (thesis §1.6 Eq. 1.2, §3.2, App. B): fractal animated noise.

    f_HF(x, y, t) = amplitude * sum_i  alpha^i * w_i * noise_i(x 2^i / scale, y 2^i / scale, z_i(t))

Octave i has wavelength scale / 2^i and evolves at the deep-water rate sqrt(g / (2 pi lambda_i)),
scaled by `speed`, so small waves change faster than large ones. Each octave has its own hash key.
w_i in [0, 1] is the band limit (§3.2, band_limit.py): 1 where the grid can carry octave i, fading
to 0 over one octave as a mip-map would. noise_i is normalised so that |noise_i| <= 1, which makes
`bound` a true bound of every height either path returns.

Two evaluation paths give the same function: "exact" evaluates the gradient noise per point (the
reference); "fast" is the thesis's path, which renders each octave into a tileable texture per frame
and samples it bilinearly (error measured in tests/core/test_height_field.py).
"""

from collections import OrderedDict
from functools import lru_cache

import numpy as np

from . import noise as _noise
from .band_limit import octave_weights
from .scratch import CHUNK, scratch
from .validation import finite, integer, non_negative, positive

GRAVITY = 9.81
MAX_OCTAVES = 24
METHODS = ("exact", "fast")


class NoiseTiles:
    """Per-octave tileable noise textures (App. B), rendered per time slice and cached.

    A tile covers PERIOD x PERIOD lattice cells with `texels` samples per cell. Each texel stores
    the four coefficients of its bilinear patch, a + b fx + fy (c + d fx), as one 16-byte element,
    so a lookup is a single gather. The texture for time z is a fixed linear combination of the
    slice fields A_k, B_k, A_k+1, B_k+1 (noise.py): one matrix-vector product per octave and frame,
    and new slices are rendered only when z crosses an integer. Its buffers are reused from frame
    to frame, so one thread at a time may use it (Blender runs handlers on the main thread).
    """

    def __init__(self, seed, texels=4, cache_slices=2 * MAX_OCTAVES):
        self.seed = int(seed)
        self.texels = integer("texels", texels, 1, 64)
        self.size = _noise.PERIOD * self.texels
        lattice = np.arange(self.size + 1, dtype=np.float64) / self.texels
        cells = np.floor(lattice)
        ix = cells.astype(np.int64)
        frac = lattice - cells
        self._ix, self._iy = np.meshgrid(ix, ix, indexing="xy")
        self._fx, self._fy = np.meshgrid(frac, frac, indexing="xy")
        self._slices = OrderedDict()
        self._cache_slices = cache_slices
        self._pairs = {}
        self._frame = {}

    def _patches(self, field):
        """(size^2, 4) float32 bilinear coefficients (a, b, c, d) of a (size+1)^2 field."""
        f00, f10 = field[:-1, :-1], field[:-1, 1:]
        f01, f11 = field[1:, :-1], field[1:, 1:]
        out = np.empty((self.size, self.size, 4), dtype=np.float32)
        out[..., 0] = f00
        out[..., 1] = f10 - f00
        out[..., 2] = f01 - f00
        out[..., 3] = f11 - f10 - f01 + f00
        return out.reshape(-1)

    def _slice(self, octave, k):
        """A_k and B_k of an octave as patches, one (2, 4 size^2) float32 array, cached."""
        key = (octave, k)
        hit = self._slices.get(key)
        if hit is not None:
            self._slices.move_to_end(key)
            return hit
        a, b = _noise.slice_terms(
            self._ix, self._iy, self._fx, self._fy, k, _noise.octave_key(self.seed, octave)
        )
        hit = np.stack([self._patches(a), self._patches(b)])
        self._slices[key] = hit
        if len(self._slices) > self._cache_slices:
            self._slices.popitem(last=False)
        return hit

    def texture(self, octave, z, gain=1.0):
        """The octave's patches at time coordinate z, times `gain`: (size^2,) complex128 elements,
        each four float32. Each octave keeps one texture buffer, rewritten when z or gain change
        (a fresh array per frame would be faulted in page by page; see scratch.py)."""
        key = (z, gain)
        last = self._frame.get(octave)
        if last is not None and last[0] == key:
            return last[1]
        k, weights = _noise.time_weights(np.float64(z))
        k = int(k)
        pair = self._pairs.get(octave)
        if pair is None or pair[0] != k:
            pair = (k, np.concatenate([self._slice(octave, k), self._slice(octave, k + 1)]))
            self._pairs[octave] = pair
        buf = np.empty(pair[1].shape[1], np.float32) if last is None else last[1].view(np.float32)
        c = (np.array(weights, dtype=np.float64) * gain).astype(np.float32)
        tex = np.matmul(c, pair[1], out=buf).view(np.complex128)
        self._frame[octave] = (key, tex)
        return tex

    def sample(self, octave, z, xy, scale=1.0, gain=1.0):
        """gain * the octave's texture, bilinear, at lattice coordinates xy * scale.

        `xy` is a (2, ...) array of x and y, so each step below is one NumPy call for both. The
        result is a scratch array (see scratch.py), valid until the next call.
        """
        tex = self.texture(octave, z, gain)
        shape = xy.shape[1:]
        s = scratch("s", xy.shape, np.float64)
        np.multiply(xy, scale * self.texels, out=s)
        cell = scratch("cell", xy.shape, np.float64)
        np.floor(s, out=cell)
        ij = scratch("ij", xy.shape, np.int64)
        np.copyto(ij, cell, casting="unsafe")
        np.subtract(s, cell, out=s)
        frac = scratch("frac", xy.shape, np.float32)
        np.copyto(frac, s, casting="same_kind")
        np.bitwise_and(ij, self.size - 1, out=ij)
        idx = scratch("idx", shape, np.int64)
        np.multiply(ij[1], self.size, out=idx)
        idx += ij[0]
        patch = scratch("patch", shape, np.complex128)
        np.take(tex, idx, out=patch, mode="wrap")  # "raise" would buffer `out`
        patch = patch.view(np.float32).reshape(shape + (4,))
        fx, fy = frac[0], frac[1]
        n = scratch("n", shape, np.float32)
        np.multiply(patch[..., 3], fx, out=n)
        n += patch[..., 2]
        n *= fy
        fx *= patch[..., 1]
        n += fx
        n += patch[..., 0]
        return n


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

        `lod` (per point, band_limit.py) band-limits the sum; None keeps every octave.
        """
        x = np.asarray(x, dtype=np.float64)
        return self.heights_xy(np.stack([x, np.broadcast_to(y, x.shape)]), t, lod)

    def heights_xy(self, xy, t, lod=None):
        """`heights` at a (2, ...) array of x and y, as the grid builds them.

        An octave is evaluated only on the rows (last axis = columns) between the first and the
        last row where some point keeps it: contiguous slices, no gathers or scatters. Rows are
        summed CHUNK vertices at a time, so the scratch buffers keep that size.
        """
        t = finite("time", t)
        xy = np.asarray(xy, dtype=np.float64)
        shape = xy.shape[1:]
        h = np.zeros(shape, dtype=np.float64)
        if self.amplitude == 0.0 or h.size == 0:
            return h
        rows = (1, -1) if len(shape) < 2 else (-1, shape[-1])
        lod2 = None if lod is None else np.asarray(lod).reshape(rows)
        xy2, h2 = xy.reshape((2,) + rows), h.reshape(rows)
        step = max(1, CHUNK // h2.shape[1])
        for start in range(0, h2.shape[0], step):
            band = slice(start, start + step)
            lod_band = None if lod2 is None else lod2[band]
            self._sum_octaves(self._octave_jobs(lod_band), xy2[:, band], lod_band, t, h2[band])
        return h

    def _octave_jobs(self, lod2):
        """(octave, gain, rows, weighted) for each octave some point keeps (§1.6 band limit)."""
        scale = self.amplitude / _noise.NOISE_BOUND
        if lod2 is not None:
            row_max, row_min = lod2.max(axis=1), lod2.min(axis=1)
        jobs = []
        for i in range(self.octaves):
            gain = scale * self.roughness**i
            if gain == 0.0:
                continue
            if lod2 is None:
                jobs.append((i, gain, slice(None), False))
                continue
            needed = np.flatnonzero(row_max > i)
            if needed.size == 0:
                break
            band = slice(needed[0], needed[-1] + 1)
            jobs.append((i, gain, band, bool(row_min[band].min() < i + 1)))
        return jobs

    def _sum_octaves(self, jobs, xy2, lod2, t, out):
        """Add the octaves of `jobs` into `out` (rows x columns)."""
        for i, gain, band, weighted in jobs:
            z = self.time_coordinate(i, t)
            inv = 1.0 / self.wavelength(i)
            if self._tiles is None:
                xs, ys = xy2[0, band] * inv, xy2[1, band] * inv
                n = _noise.noise(xs, ys, np.full(xs.shape, z), _noise.octave_key(self.seed, i))
                n *= gain
            else:
                n = self._tiles.sample(i, z, xy2[:, band], inv, gain)
            if weighted:
                n *= octave_weights(lod2[band], i,
                                    scratch("weights", lod2[band].shape, lod2.dtype))
            out[band] += n

