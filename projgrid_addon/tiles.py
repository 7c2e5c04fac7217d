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
    last row and column repeat the first (a periodic tile, closed); of a stack of fields
    (..., size+1, size+1), one such row each."""
    size = field.shape[-1] - 1
    f00, f10 = field[..., :-1, :-1], field[..., :-1, 1:]
    f01, f11 = field[..., 1:, :-1], field[..., 1:, 1:]
    out = np.empty(field.shape[:-2] + (size, size, 4), dtype=np.float32)
    out[..., 0] = f00
    np.subtract(f10, f00, out=out[..., 1])
    np.subtract(f01, f00, out=out[..., 2])
    np.subtract(f11, f10, out=out[..., 3])
    out[..., 3] -= out[..., 2]
    return out.reshape(field.shape[:-2] + (-1,)).view(np.complex128)


def periodic_patches(tile):
    """`patches` of a periodic (size, size) tile, or of a stack of them (..., size, size)."""
    n = tile.shape[-1]
    closed = np.empty(tile.shape[:-2] + (n + 1, n + 1), tile.dtype)
    closed[..., :n, :n] = tile
    closed[..., n, :n] = tile[..., 0, :]
    closed[..., :, n] = closed[..., :, 0]
    return patches(closed)


def turned_texel(point, turn, scale, size):
    """The texel coordinates (s, t) of a point (x, y) in a periodic texture `size` texels across
    at `scale` texels per unit, turned by `turn` (cos, sin) on the plane, reduced by its period
    (in double precision: the point may be far away)."""
    x, y = float(point[0]), float(point[1])
    c, sn = turn[0] * scale, turn[1] * scale
    return (x * c + y * sn) % size, (y * c - x * sn) % size


class Lookup:
    """Where points xy (2, ...), less `shift`, fall in a periodic texture `size` texels across
    at `scale` texels per unit: each point's texel and its fractions. Its arrays are scratch
    arrays (see scratch.py) named by `tag`, valid until the next Lookup of that tag.
    `Lookup.turned` finds float32 offsets from an origin in a turned texture."""

    def __init__(self, size, xy, scale, tag="", shift=(0.0, 0.0)):
        s = scratch("s" + tag, xy.shape, np.float64)
        if shift[0] or shift[1]:
            np.subtract(xy, np.reshape(shift, (2,) + (1,) * (xy.ndim - 1)), out=s)
            s *= scale
        else:
            np.multiply(xy, scale, out=s)
        self._locate(size, s, tag)

    @classmethod
    def turned(cls, size, points, origin, scale, turn, tag="", shift_turn=None):
        """A Lookup of the points origin + offsets in a texture turned by `turn` (cos, sin) on
        the plane. `points` (2, ...) float32: the offsets; the texel coordinates are taken in
        single precision, the origin's reduced by the period in double first, so a texel
        coordinate is as exact as the offsets are small (the bands are sampled only within some
        thousand texels of the camera, where the float32 error is below 1e-3 texel).
        With `shift_turn` (cos, sin), `points` (4, ...) are the offsets and then vectors by
        which the points move, turned by that turn first (warp.py): one 2 x 4 product."""
        self = cls.__new__(cls)
        c, sn = turn[0] * scale, turn[1] * scale
        rows = [[c, sn], [-sn, c]]
        if shift_turn is not None:
            # Turned by the shift's turn on the plane, then back by the texture's: one turn.
            sc, ss = shift_turn
            a = scale * (sc * turn[0] + ss * turn[1])
            b = scale * (ss * turn[0] - sc * turn[1])
            rows = [[c, sn, a, -b], [-sn, c, b, a]]
        s = scratch("s32" + tag, (2,) + points.shape[1:], np.float32)
        np.matmul(np.array(rows, np.float32), points.reshape(len(points), -1),
                  out=s.reshape(2, -1))
        start = turned_texel(origin, turn, scale, size)
        s[0] += np.float32(start[0])
        s[1] += np.float32(start[1])
        self._locate(size, s, tag)
        return self

    def _locate(self, size, s, tag):
        """Texel index and fractions of texel coordinates s (2, ...), which it overwrites."""
        self.shape = shape = s.shape[1:]
        cell = scratch("cell" + tag, s.shape, s.dtype)
        np.floor(s, out=cell)
        ij = scratch("ij" + tag, s.shape, np.int32 if s.dtype == np.float32 else np.int64)
        np.copyto(ij, cell, casting="unsafe")
        np.subtract(s, cell, out=s)
        if s.dtype == np.float32:
            self.frac = s
        else:
            self.frac = scratch("frac" + tag, s.shape, np.float32)
            np.copyto(self.frac, s, casting="same_kind")
        np.bitwise_and(ij, size - 1, out=ij)
        self.idx = scratch("idx" + tag, shape, np.intp)
        np.multiply(ij[1], size, out=self.idx)
        self.idx += ij[0]
        # Every sample's buffers, taken once here: a lookup is sampled for many textures, and
        # at a few thousand points the calls cost as much as the arithmetic.
        self._patch = scratch("patch" + tag, shape, np.complex128)
        coefficients = self._patch.view(np.float32).reshape(shape + (4,))
        self._coefficients = tuple(coefficients[..., k] for k in range(4))
        self._n = scratch("n" + tag, shape, np.float32)
        self._t = scratch("t" + tag, shape, np.float32)

    def sample(self, texture, out=None):
        """The texture's bilinear value at the points (float32, into `out` if given, else a
        scratch array valid until the next sample of this lookup's tag)."""
        np.take(texture, self.idx, out=self._patch, mode="wrap")  # "raise" would buffer `out`
        a, b, c, d = self._coefficients
        fx, fy = self.frac
        n = self._n if out is None else out
        np.multiply(d, fx, out=n)
        n += c
        n *= fy
        np.multiply(b, fx, out=self._t)
        n += self._t
        n += a
        return n


def bilinear(values, i, j):
    """`values` (..., rows, columns) at fractional column indices i and row indices j, within
    the table (a plain table, not a periodic texture: past_grid.py, wakes.py, wake_field.py);
    several tables stacked are read at once, their corners and weights found once."""
    rows, cols = values.shape[-2:]
    i0 = np.minimum(i.astype(np.intp), cols - 2)
    j0 = np.minimum(j.astype(np.intp), rows - 2)
    fi = (i - i0).astype(np.float32)
    fj = (j - j0).astype(np.float32)
    at = j0 * cols + i0
    corners = ((at, (1.0 - fi) * (1.0 - fj)), (at + 1, fi * (1.0 - fj)),
               (at + cols, (1.0 - fi) * fj), (at + cols + 1, fi * fj))
    out = []
    for table in values.reshape(-1, rows * cols):  # a table at a time: contiguous gathers
        value = table[at] * corners[0][1]
        for corner, weight in corners[1:]:
            value += table[corner] * weight
        out.append(value)
    return out[0] if values.ndim == 2 else np.stack(out).reshape(*values.shape[:-2], -1)
