"""The band limit (thesis §3.2): what the grid can hold at each vertex, the rest to the shader.

A height field sampled by the grid aliases where a wave is shorter than two vertex spacings (the
Nyquist limit). Each vertex therefore carries a level of detail

    lod = log2(wave_scale / (2 spacing))

and octave i (lattice period wave_scale / 2^i; its waves are noise.WAVELENGTH times as long,
so this is conservative) is weighted clip(lod - i, 0, 1): kept whole while its
wavelength is at least four spacings, faded out until it is two, as a mip-map blends its levels.
The octaves some vertex dropped go to the shader as bump detail (`shader_octaves`), faded in by
the same per-vertex lod, so the surface keeps its detail across the hand-over (§3.1.3).

The spacing at a vertex is the larger grid step of the projector's homography there; it is
exact per row along u and per column along v up to the w of the vertex and the columns' and
rows' own spacing (`grid_steps`; Projector.spacing), so a frame needs no per-vertex square
roots or logarithms (`lod_from_w`, with `pseudo_log2`).
"""

import numpy as np

from .scratch import scratch


def octave_weights(lod, octave, out=None):
    """Band-limit weight of `octave` at per-point level of detail `lod` (None: no band limit),
    into `out` if given."""
    if lod is None:
        return None
    w = np.subtract(lod, octave, out=out)
    return np.clip(w, 0.0, 1.0, out=w)


def row_jobs(lod2, level):
    """Where a band at octave `level` is needed in a (rows, columns) level-of-detail array:
    (rows, weighted), the contiguous rows between the first and the last where some point
    keeps it and whether some point there keeps it only in part, or None where none keeps it
    (`lod2` None: every row, whole). Contiguous slices: no gathers or scatters."""
    if lod2 is None:
        return slice(None), False
    needed = np.flatnonzero(lod2.max(axis=1) > level)
    if needed.size == 0:
        return None
    rows = slice(needed[0], needed[-1] + 1)
    return rows, bool(lod2[rows].min() < level + 1)


# Levels above its fade-in from which a band is sampled on every other row and column of a grid
# and interpolated between (`row_parts`, `fill_every_other`): its shortest wave then spans at
# least 64 vertex spacings, so linear interpolation over two spacings loses at most
# (2 pi / 32)^2 / 8 = 0.5 % of that wave's height, and less of the band's longer waves.
COARSE = 5
COARSE_MIN = 5  # rows (and columns) a grid needs before the coarse sampling pays


def row_parts(lod2, row_min, level, rows, weighted):
    """The job `rows` of a band at `level` (row_jobs) on a grid, split: (fine, coarse), fine a
    list of (rows, weighted) sampled at every vertex, coarse the longest run of rows in which
    every vertex keeps the band COARSE levels above its fade-in (None if shorter than
    COARSE_MIN rows or columns), sampled on every other row and column."""
    if lod2.shape[1] < COARSE_MIN:
        return [(rows, weighted)], None
    flags = row_min[rows] >= level + COARSE
    if flags.sum() < COARSE_MIN:
        return [(rows, weighted)], None
    edges = np.flatnonzero(np.diff(np.concatenate(([0], flags.view(np.int8), [0]))))
    runs = edges.reshape(-1, 2)
    a, b = runs[np.argmax(runs[:, 1] - runs[:, 0])]
    if b - a < COARSE_MIN:
        return [(rows, weighted)], None
    start = rows.start or 0
    fine = [(part, bool(row_min[part].min() < level + 1))
            for part in (slice(start, start + a), slice(start + b, rows.stop))
            if part.stop > part.start]
    return fine, slice(start + a, start + b)


def every_other(n):
    """The indices 0, 2, 4, ... of n, and n - 1: the coarse samples of `fill_every_other`."""
    return np.r_[0:n:2, n - 1] if n % 2 == 0 else np.arange(0, n, 2)


def every_other_shape(shape):
    """The shape of the coarse samples (every_other of each axis) of a (rows, columns) grid."""
    return tuple(n // 2 + 1 for n in shape)


def every_other_of(a, out):
    """a (..., rows, columns) at every_other(rows) x every_other(columns), into `out` (...,
    every_other_shape): by slices, the inverse of `fill_every_other`."""
    rows, cols = a.shape[-2:]
    r2, c2 = (rows + 1) // 2, (cols + 1) // 2
    out[..., :r2, :c2] = a[..., 0::2, 0::2]
    if cols % 2 == 0:
        out[..., :r2, -1] = a[..., 0::2, -1]
    if rows % 2 == 0:
        out[..., -1, :c2] = a[..., -1, 0::2]
        if cols % 2 == 0:
            out[..., -1, -1] = a[..., -1, -1]
    return out


def fill_every_other(coarse, out):
    """Values at every_other(rows) x every_other(columns) of `out` (rows, columns) spread into
    all of it, each point between two samples their mean (linear interpolation on the grid);
    what `out` held before is never read."""
    rows, cols = out.shape
    r2, c2 = (rows + 1) // 2, (cols + 1) // 2
    out[0::2, 0::2] = coarse[:r2, :c2]
    if cols % 2 == 0:
        out[0::2, -1] = coarse[:r2, -1]
    if rows % 2 == 0:
        out[-1, 0::2] = coarse[-1, :c2]
        if cols % 2 == 0:
            out[-1, -1] = coarse[-1, -1]
    for samples in (out[0::2], out[-1:]) if rows % 2 == 0 else (out[0::2],):  # rows sampled
        mid = samples[:, 1:cols - 1:2]
        np.add(samples[:, 0:cols - 2:2], samples[:, 2:cols:2], out=mid)
        mid *= 0.5
    mid = out[1:rows - 1:2]
    np.add(out[0:rows - 2:2], out[2:rows:2], out=mid)
    mid *= 0.5
    return out


def lod_for_spacing(wave_scale, spacing):
    """The level of detail of a grid `spacing` metres apart (a world grid's, for comparison)."""
    return np.log2(wave_scale / (2.0 * np.asarray(spacing, dtype=np.float64)))


def pseudo_log2(ratio, out=None):
    """log2 exact at powers of two and linear between them, from the float32 bits (Mitchell),
    into `out` (float32) if given.

    With it an octave's weight fades linearly in the wavelength-to-spacing ratio between 2 and 4
    spacings (a mip-map's linear blend), not linearly in octaves as the exact log2 would.
    """
    ratio = np.asarray(ratio)
    if ratio.dtype != np.float32:
        ratio32 = scratch("ratio32", ratio.shape, np.float32)
        np.copyto(ratio32, ratio, casting="same_kind")
        ratio = ratio32
    if out is None:
        out = np.empty(ratio.shape, np.float32)
    np.copyto(out, ratio.view(np.int32), casting="unsafe")
    out *= np.float32(2.0**-23)
    out -= np.float32(127.0)
    return out


def grid_steps(c, left, right, u, wave_scale, du, dv):
    """The grid's steps per row along u and per column along v, in units of wave_scale / 2, each
    still to be divided by w^2 at the vertex: (along_u (ny,), along_v (nx,), scale, du, dv),
    the step along u at a column being along_u times du there and along v at a row along_v
    times dv (`du`, `dv`: each column's du/ds and row's dv/ds, their spacing against an even
    one).

    For p = h / w with h affine along a row, dp/du = (D_xy left_w - left_xy D_w) / w^2 with
    D = right - left: a per-row vector over w^2, and likewise per column along v. `c` are the
    homogeneous grid corners, `left` and `right` the rows' homogeneous ends (projected_grid).
    """
    nx, ny = len(u), len(left)
    d = right - left
    along_u = np.hypot(d[:, 0] * left[:, 3] - left[:, 0] * d[:, 3],
                       d[:, 1] * left[:, 3] - left[:, 1] * d[:, 3]) / (nx - 1)
    iu = (1.0 - u)[:, None]
    bottom = iu * c[0] + u[:, None] * c[1]  # (nx, 4): hom at v = 0
    e = iu * (c[2] - c[0]) + u[:, None] * (c[3] - c[1])  # (nx, 4): d hom / dv
    along_v = np.hypot(e[:, 0] * bottom[:, 3] - bottom[:, 0] * e[:, 3],
                       e[:, 1] * bottom[:, 3] - bottom[:, 1] * e[:, 3]) / (ny - 1)
    return along_u, along_v, 2.0 / wave_scale, du, dv


def lod_from_w(steps, rows, hw, out):
    """Per-vertex level of detail of the grid `rows` whose homogeneous w are `hw`, into `out`
    (float32): log2 of w^2 over the larger step; `steps` from `grid_steps`."""
    along_u, along_v, scale, du, dv = steps
    step = scratch("step", hw.shape, np.float64)
    across = scratch("across", hw.shape, np.float64)
    np.multiply(along_u[rows, None], du[None, :], out=across)
    np.multiply(along_v[None, :], dv[rows, None], out=step)
    np.maximum(across, step, out=step)
    step *= scale
    ratio = scratch("ratio", hw.shape, np.float64)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        np.multiply(hw, hw, out=ratio)
        ratio /= step
    return pseudo_log2(np.fmax(ratio, 0.0, out=ratio), out)  # a degenerate 0 / 0 keeps no octave


def along_waves(xy, lod, level, along):
    """The band limit on a grid of points xy (2, rows, columns) for waves heading within an
    angle of one direction, `along` = (cos, sin) of the direction and of the angle: `lod`
    raised by log2 of the larger grid step over the larger reach of the steps along those
    headings. A wave of wave vector k aliases on the grid where |k . a| or |k . b| exceeds pi,
    a and b the steps between neighbours along a row and a column; across the waves' crests a
    step counts only by its projection, so a swell crossing the view stays in the geometry
    far beyond where the rows, metres deep there, hold any wave heading toward the camera.
    Only rows where `lod` does not already keep a band of `level` whole are raised."""
    out = lod.copy()
    rows = np.flatnonzero(lod.min(axis=1) < level + 1.0)
    if rows.size == 0 or min(xy.shape[1:]) < 2:
        return out
    start, stop = max(rows[0] - 1, 0), min(rows[-1] + 2, xy.shape[1])
    part = xy[:, start:stop]
    cos, sin, cos_off, sin_off = along
    full = reach = None
    for axis in (2, 1):
        if part.shape[axis] < 2:
            continue
        d = np.gradient(part, axis=axis)
        length = np.hypot(d[0], d[1])
        projected = np.abs(d[0] * cos + d[1] * sin) * cos_off
        projected += np.abs(d[1] * cos - d[0] * sin) * sin_off
        full = length if full is None else np.maximum(full, length)
        reach = projected if reach is None else np.maximum(reach, projected)
    with np.errstate(divide="ignore", invalid="ignore"):
        gain = np.log2(full / reach)
    out[start:stop] += np.clip(np.nan_to_num(gain, nan=0.0, posinf=30.0), 0.0, 30.0)
    return out


def shader_octaves(lod, octaves):
    """(first, count): the octaves some vertex left out, in part or whole, for the shader."""
    if lod is None:
        return octaves, 0
    first = int(np.clip(np.floor(lod.min()), 0, octaves)) if lod.size else octaves
    return first, octaves - first
