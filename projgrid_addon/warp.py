"""A slow warp of where each tile is read, so that tiles which repeat near the same distance
do not repeat together (spectral_field.py, the sea's tiles).

A tile of the spectral sea repeats on its lattice; where the lattices of two tiles nearly meet,
the surface's autocorrelation there is the sum of their shares of the variance. Each tile is
read at x + R_j w(x), with w a smooth field of a few metres made of long plane waves and R_j a
turn of its own per tile (the golden angle apart), so two tiles that repeat together at a lag r
at one place are shifted against each other by (R_a - R_b)(w(x + r) - w(x)) elsewhere: the
joint repeat, averaged over the sea, is smeared over metres, wider than the waves that hold the
sea's energy at low winds. Each tile alone still repeats (its share is below SHARE_PER_TILE).

The warp stretches the sea by at most sum 2 pi a / L = 4 % (its waves a = AMPLITUDE, L from
1 to 3 km; 1.5 % root mean square): wavelengths and directions stay within that of the
spectrum's. It does not move with time, so the waves travel and their periods stay as before,
and it moves points without changing what is read there, so the heights' spread is the
same.
"""

import numpy as np

from .scratch import scratch

WAVES = 4
AMPLITUDE = 2.5  # m per wave
LONGEST, SHORTEST = 3000.0, 1000.0  # m: the warp's wavelengths
GOLDEN = np.pi * (3.0 - np.sqrt(5.0))  # rad: tile j's warp is turned by j times this


class Warp:
    """w(x) = sum_m AMPLITUDE e_m sin(q_m . x + phi_m), its directions e_m, q_m and phases
    phi_m fixed by the seed."""

    def __init__(self, seed):
        rng = np.random.default_rng(np.random.SeedSequence([int(seed) & 0xFFFFFFFF, 0x57A9]))
        heading, along, self.phase = rng.random((3, WAVES)) * (2.0 * np.pi)
        length = np.geomspace(SHORTEST, LONGEST, WAVES)
        self.q = np.stack([np.cos(heading), np.sin(heading)]) * (2.0 * np.pi / length)
        self.e = np.stack([np.cos(along), np.sin(along)]) * AMPLITUDE
        self._q32, self._e32 = self.q.T.astype(np.float32), self.e.astype(np.float32)

    @staticmethod
    def turn(j):
        """(cos, sin) of tile j's turn of the warp."""
        return float(np.cos(j * GOLDEN)), float(np.sin(j * GOLDEN))

    def __call__(self, origin, offsets, tag="warp", out=None):
        """w at origin + offsets (2, ...) float32, as (2, ...) float32 (into `out`, C-contiguous,
        else a scratch array of `tag`): the phase at the origin in double precision, the offsets' in
        single (they span some kilometres, a few turns of the warp's waves)."""
        flat = offsets.reshape(2, -1)
        if out is None:
            out = scratch(tag, offsets.shape, np.float32)
        elif not out.flags.c_contiguous:  # its reshape would be a copy, the result lost
            raise ValueError("Warp: `out` must be C-contiguous")
        arg = scratch(tag + "arg", (WAVES, flat.shape[1]), np.float32)
        np.matmul(self._q32, flat, out=arg)
        start = (self.q.T @ np.asarray(origin, np.float64) + self.phase) % (2.0 * np.pi)
        arg += start.astype(np.float32)[:, None]
        np.sin(arg, out=arg)
        np.matmul(self._e32, arg, out=out.reshape(2, -1))
        return out

    def shifts(self, lags, samples=256):
        """(samples, 2, ...) float64: w(x + r) - w(x) at lags r (2, ...) for `samples` draws of
        the warp's phases (q_m . x + phi_m uniform and independent, as over seeds; a Monte
        Carlo estimate, the same draws for every lag). The mean over them of a tile's
        autocorrelation at r + R_j shift is the warped tile's."""
        lags = np.asarray(lags, dtype=np.float64)
        psi = np.random.default_rng(0x57A9).random((samples, WAVES)) * (2.0 * np.pi)
        half = np.tensordot(self.q.T, lags, axes=(1, 0)) / 2.0  # (WAVES, ...)
        # sin(a + 2h) - sin(a) = 2 sin(h) cos(a + h), a + h the drawn phase.
        cos = np.cos(psi).reshape((samples, WAVES) + (1,) * (lags.ndim - 1))
        amp = (2.0 * np.sin(half))[None] * cos  # (samples, WAVES, ...)
        return np.stack([np.tensordot(amp, self.e[0], axes=(1, 0)),
                         np.tensordot(amp, self.e[1], axes=(1, 0))], axis=1)
