"""Periodic textures sampled bilinearly, the way the thesis samples its noise textures (App. B).

Each texel stores the four coefficients of its bilinear patch, v = a + b fx + fy (c + d fx), as
four float32 in one complex128 element, so a lookup is a single gather. Points are found once
(`Lookup`) and any number of textures of the same size sampled there: heights, displacements,
their gradients. A texture is `size` texels across, `size` a power of two.
"""

import numpy as np

from .scratch import scratch


def patches(field):
    """(size^2,) complex128: the bilinear coefficients (a, b, c, d) of a (size+1)^2 field whose
    last row and column repeat the first (a periodic tile, closed)."""
    size = field.shape[0] - 1
    f00, f10 = field[:-1, :-1], field[:-1, 1:]
    f01, f11 = field[1:, :-1], field[1:, 1:]
    out = np.empty((size, size, 4), dtype=np.float32)
    out[..., 0] = f00
    out[..., 1] = f10 - f00
    out[..., 2] = f01 - f00
    out[..., 3] = f11 - f10 - f01 + f00
    return out.reshape(-1).view(np.complex128)


def periodic_patches(tile):
    """`patches` of a periodic (size, size) tile."""
    n = tile.shape[0]
    closed = np.empty((n + 1, n + 1), tile.dtype)
    closed[:n, :n] = tile
    closed[n, :n] = tile[0]
    closed[:, n] = closed[:, 0]
    return patches(closed)


class Lookup:
    """Where points xy (2, ...), less `shift` or turned by `turn` (cos, sin: into the frame of a
    texture turned by that angle), fall in a periodic texture `size` texels across at `scale`
    texels per unit: each point's texel and its fractions. Its arrays are scratch arrays (see
    scratch.py) named by `tag`, valid until the next Lookup of that tag."""

    def __init__(self, size, xy, scale, tag="", shift=(0.0, 0.0), turn=None):
        if turn is not None and (shift[0] or shift[1]):
            raise ValueError("Lookup: points are either shifted or turned, not both")
        self.shape = shape = xy.shape[1:]
        s = scratch("s" + tag, xy.shape, np.float64)
        if turn is not None:
            c, sn = turn[0] * scale, turn[1] * scale
            across = scratch("across" + tag, shape, np.float64)
            np.multiply(xy[0], c, out=s[0])
            s[0] += np.multiply(xy[1], sn, out=across)
            np.multiply(xy[1], c, out=s[1])
            s[1] -= np.multiply(xy[0], sn, out=across)
        elif shift[0] or shift[1]:
            np.subtract(xy, np.reshape(shift, (2,) + (1,) * len(shape)), out=s)
            s *= scale
        else:
            np.multiply(xy, scale, out=s)
        cell = scratch("cell" + tag, xy.shape, np.float64)
        np.floor(s, out=cell)
        ij = scratch("ij" + tag, xy.shape, np.int64)
        np.copyto(ij, cell, casting="unsafe")
        np.subtract(s, cell, out=s)
        self.frac = scratch("frac" + tag, xy.shape, np.float32)
        np.copyto(self.frac, s, casting="same_kind")
        np.bitwise_and(ij, size - 1, out=ij)
        self.idx = scratch("idx" + tag, shape, np.int64)
        np.multiply(ij[1], size, out=self.idx)
        self.idx += ij[0]
        self.tag = tag

    def _patch(self, texture):
        patch = scratch("patch" + self.tag, self.shape, np.complex128)
        np.take(texture, self.idx, out=patch, mode="wrap")  # "raise" would buffer `out`
        return patch.view(np.float32).reshape(self.shape + (4,))

    def sample(self, texture, out=None):
        """The texture's bilinear value at the points (float32, into `out` if given, else a
        scratch array valid until the next sample of this tag)."""
        p = self._patch(texture)
        fx, fy = self.frac[0], self.frac[1]
        n = out if out is not None else scratch("n" + self.tag, self.shape, np.float32)
        np.multiply(p[..., 3], fx, out=n)
        n += p[..., 2]
        n *= fy
        t = scratch("t" + self.tag, self.shape, np.float32)
        np.multiply(p[..., 1], fx, out=t)
        n += t
        n += p[..., 0]
        return n
