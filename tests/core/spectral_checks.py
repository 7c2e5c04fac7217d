"""What the spectral sea's tests measure it with (only tests use these)."""

import numpy as np
import pytest

from projgrid_addon.scratch import CHUNK
from projgrid_addon.tiles import Lookup, periodic_patches
from projgrid_addon.warp import Warp


def surface(source, t, span, n, lod=None):
    """Heights on an n x n world grid `span` metres across (rows along y), band-limited at
    `lod` (band_limit.py) if given."""
    k = np.arange(n) * (span / n)
    x, y = np.meshgrid(k, k)
    return source.heights(x, y, t, None if lod is None else np.full(x.shape, lod))


def autocorrelation(source, lags, fine=4, samples=256):
    """The surface's height autocorrelation at `lags` (2, ...) m, over its random phases
    (Wiener-Khinchin): each tile's power |h0(k)|^2 + |h0(-k)|^2 transformed on its own
    lattice, so it is periodic with the tile and returns to the tile's share of the
    variance wherever the tile repeats, transformed `fine` times denser than the tile's
    texels (exact there) and sampled bilinearly between; each tile's read at the lag
    moved by its turn of the warp's change over the lag, averaged over `samples` of the
    warp's phases (Warp.shifts; `samples` 0: no warp)."""
    lags = np.asarray(lags, dtype=np.float64)
    flat = lags.reshape(2, -1)
    out = np.zeros(flat.shape[1])
    tiles = []
    for c in source.cascades:
        n = c.texels * fine
        power = np.zeros((n, n))
        at = np.fft.fftfreq(c.texels, 1.0 / c.texels).astype(int) % n
        power[np.ix_(at, at)] = c.power()
        tiles.append((n, periodic_patches(np.fft.ifft2(power, norm="forward").real
                                          .astype(np.float32))))
    for start in range(0, flat.shape[1], CHUNK):
        part = flat[:, start:start + CHUNK]
        points = np.empty((4, part.shape[1]), np.float32)  # the lags, then a warp's shift
        points[:2] = part
        shifts = (source.warp.shifts(part, samples).astype(np.float32) if samples
                  else np.zeros((1,) + part.shape, np.float32))
        for j, (c, (n, acf)) in enumerate(zip(source.cascades, tiles, strict=True)):
            for shift in shifts:
                points[2:] = shift
                out[start:start + CHUNK] += Lookup.turned(
                    n, points, (0.0, 0.0), n / c.size, c.turn, "acf",
                    Warp.turn(j)).sample(acf)
    out = out.reshape(lags.shape[1:]) / len(shifts) if flat.shape[1] else out
    return out / source.spread[0] ** 2 if source.cascades else out


def assert_spreads_alike(mesh, apart, lod, least=3):
    """The cue a frame's mesh shows (`mesh`) spreads as the calibration's at the same band
    limits (`apart`, points apart): within 10 % in each half level of `lod` that holds over
    2000 points, of which there are at least `least`."""
    compared = 0
    for low in np.arange(np.floor(lod.min()), np.ceil(lod.max()), 0.5):
        inside = (lod >= low) & (lod < low + 0.5)
        if inside.sum() > 2000:
            assert mesh[inside].std() == pytest.approx(apart[inside].std(), rel=0.1), low
            compared += 1
    assert compared >= least
