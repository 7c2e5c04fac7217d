"""The noise's fast path (thesis App. B): each octave's tileable texture, rendered per time slice
from noise.py's slice fields and cached, sampled bilinearly by height_field.HeightField."""

from collections import OrderedDict
from functools import lru_cache

import numpy as np

from . import noise as _noise
from .tiles import Lookup, patches, periodic_patches
from .validation import integer


class NoiseTiles:
    """Per-octave tileable noise textures (App. B), rendered per time slice and cached.

    A tile covers PERIOD x PERIOD lattice cells with `texels` samples per cell. Each texel stores
    the four coefficients of its bilinear patch, a + b fx + fy (c + d fx), as one 16-byte element,
    so a lookup is a single gather. The texture for time z is a fixed linear combination of the
    slice fields A_k, B_k, A_k+1, B_k+1 (noise.py): one matrix-vector product per octave and frame,
    and new slices are rendered only when z crosses an integer. Its buffers are reused from frame
    to frame, so one thread at a time may use it (Blender runs handlers on the main thread).
    """

    def __init__(self, seed, texels=4, cache_slices=2 * _noise.MAX_OCTAVES):
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

    def _slice(self, octave, k, kind=0):
        """A_k and B_k of an octave as patches, one (2, 4 size^2) float32 array, cached: the
        values (kind 0), or their derivatives along x or y per lattice unit (kind 1, 2: central
        differences on the periodic tile, so the slopes are continuous where bilinear patches'
        own derivatives jump from texel to texel)."""
        key = (octave, k, kind)
        hit = self._slices.get(key)
        if hit is not None:
            self._slices.move_to_end(key)
            return hit
        fields = _noise.slice_terms(
            self._ix, self._iy, self._fx, self._fy, k, _noise.octave_key(self.seed, octave)
        )
        if kind:
            axis = 2 - kind  # x runs along columns (axis 1), y along rows (axis 0)
            fields = [(np.roll(f[:-1, :-1], -1, axis) - np.roll(f[:-1, :-1], 1, axis))
                      * (0.5 * self.texels) for f in fields]
            hit = np.stack([periodic_patches(f).view(np.float32) for f in fields])
        else:
            hit = np.stack([patches(f).view(np.float32) for f in fields])
        self._slices[key] = hit
        if len(self._slices) > self._cache_slices:
            self._slices.popitem(last=False)
        return hit

    def texture(self, octave, z, gain=1.0, kind=0):
        """The octave's patches at time coordinate z, times `gain`: (size^2,) complex128 elements,
        each four float32; of its values, or its slopes along x or y (kind 1, 2) per lattice
        unit. Each octave and kind keeps one texture buffer, rewritten when z or gain change (a
        fresh array per frame would be faulted in page by page; see scratch.py)."""
        key = (z, gain)
        last = self._frame.get((octave, kind))
        if last is not None and last[0] == key:
            return last[1]
        k, weights = _noise.time_weights(np.float64(z))
        k = int(k)
        pair = self._pairs.get((octave, kind))
        if pair is None or pair[0] != k:
            pair = (k, np.concatenate([self._slice(octave, k, kind),
                                       self._slice(octave, k + 1, kind)]))
            self._pairs[(octave, kind)] = pair
        buf = np.empty(pair[1].shape[1], np.float32) if last is None else last[1].view(np.float32)
        c = (np.array(weights, dtype=np.float64) * gain).astype(np.float32)
        tex = np.matmul(c, pair[1], out=buf).view(np.complex128)
        self._frame[(octave, kind)] = (key, tex)
        return tex

    def lookup(self, xy, scale=1.0, shift=(0.0, 0.0)):
        """Where lattice coordinates (xy - shift) * scale fall in the octaves' textures
        (tiles.Lookup)."""
        return Lookup(self.size, xy, scale * self.texels, shift=shift)

    def sample(self, octave, z, xy, scale=1.0, gain=1.0):
        """gain * the octave's texture, bilinear, at lattice coordinates xy * scale (a (2, ...)
        array of x and y). The result is a scratch array (see scratch.py), valid until the next
        call."""
        return self.lookup(xy, scale).sample(self.texture(octave, z, gain))


@lru_cache(maxsize=8)
def shared_tiles(seed, texels):
    """The NoiseTiles of a seed, shared by every HeightField using it: a field is rebuilt whenever
    a setting such as amplitude changes (or is animated), and its rendered slices stay valid."""
    return NoiseTiles(seed, texels)
