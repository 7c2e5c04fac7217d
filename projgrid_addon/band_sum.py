"""The spectral sea's bands summed at points (spectral_field.SpectralField.sample), each weighted
by the band limit (thesis §3.2, band_limit.py), and with it the crest sum: the height and
sideways displacement (GEOMETRY) of the waves up to a band limit `cap` (the whitecaps' level,
foam.whitecap_level), which the foam's cue is taken from (foam.foam_field) without sampling
the sea again. Its height is the wind sea's (`crest_height`): a swell's core and the bands of
waves all longer than the sea's `crest_longest` are left out, as swells do not break
(SpectralField.foam_cue).

The bands come longest first, so the crest sum is, for most bands, a copy of the running sum
once the bands it keeps whole are in (less the heights it leaves out, summed aside till then):
every band with level + 1 <= cap, summed before the first that is not, is what the crest sum
holds of them; the band `cap` falls within is added to both, each with its own weight
(`crest_weights`), and so is any later band the cap keeps."""

import numpy as np

from .band_limit import (
    every_other_of,
    every_other_shape,
    fill_every_other,
    octave_weights,
    row_jobs,
    row_parts,
)
from .cascade import GEOMETRY, SIDEWAYS
from .scratch import scratch
from .tiles import Lookup
from .warp import Warp


def sum_bands(sea, textures, origin, points, lods, fields, out, on_grid, crest=None):
    """Add the bands' `fields` (of `textures`: per time, per cascade) at origin + offsets
    into `out` (times, fields, rows, columns), band by band (its tiles share its rows and
    coarse part; `lods`: each of sea.groups' band limit), each tile read where the warp
    turned by its own turn moves the points `points` (4, rows, columns: offsets, warp).
    `crest` (cap, into): also the GEOMETRY fields (which `fields` must hold) of the waves
    band limit min(lod, cap) keeps, into `into` (times, 3, rows, columns)."""
    mins = {}
    cap, into = crest if crest is not None else (None, None)
    copied = crest is None
    kept = [fields.index(f) for f in GEOMETRY] if crest is not None else None
    aside = None  # the heights left out of the crest sum, of the bands summed before its copy
    for (level, _, tiles), lod in zip(sea.groups, lods, strict=True):
        if not sea.cascades[tiles[0]].gives.intersection(fields):
            continue
        if not copied and level + 1.0 > cap:  # every band the cap keeps whole is in
            _copy(out, kept, into, aside)
            copied = True
        feed = None if crest is None else GEOMETRY if crest_height(sea, tiles) else SIDEWAYS
        keeps = copied and cap is not None and level < cap  # in the crest sum too
        set_aside = not copied and feed is SIDEWAYS
        if set_aside and aside is None:
            aside = scratch("aside", into.shape, np.float32)
            aside.fill(0.0)
        if on_grid and id(lod) not in mins:
            mins[id(lod)] = lod.min(axis=1)
        row_min = mins.get(id(lod))
        job = row_jobs(lod, level)
        if job is None:
            continue
        fine, coarse = [job], None
        if on_grid:
            fine, coarse = row_parts(lod, row_min, level, *job)
        for rows, weighted in fine:
            weight = None
            if weighted:
                weight = octave_weights(lod[rows], level,
                                        scratch("weights", lod[rows].shape, lod.dtype))
            part = None
            if keeps:  # a band the cap keeps whole where the points do: the same weight
                part = (into[:, :, rows], weight if level + 1.0 <= cap else crest_weights(
                    None if lod is None else lod[rows], level, cap), feed)
            elif set_aside:
                part = (aside[:, :, rows], weight, (0,))
            for j in tiles:
                _add(sea, textures, j, points[:, rows], origin, fields, out[:, :, rows],
                     weight, part)
        if coarse is not None:  # every point here keeps the band whole: the cap's weight
            few = every_other_of(points[:, coarse], scratch(
                "few", (4,) + every_other_shape(points[0, coarse].shape), np.float32))
            sums = scratch("coarse", out.shape[:2] + few.shape[1:], np.float32)
            sums.fill(0.0)
            for j in tiles:
                _add(sea, textures, j, few, origin, fields, sums, None, None)
            filled = scratch("filled", out[0, 0, coarse].shape, np.float32)
            share = crest_weights(None, level, cap) if keeps else None
            for k in range(out.shape[0]):
                for i, f in enumerate(fields):
                    fill_every_other(sums[k, i], filled)
                    out[k, i, coarse] += filled
                    if share is not None and f in feed:
                        into[k, GEOMETRY.index(f), coarse] += filled * share
                    elif set_aside and f == 0:
                        aside[k, 0, coarse] += filled
    if not copied:
        _copy(out, kept, into, aside)


def crest_height(sea, tiles):
    """Whether the crest sum holds the height of the band of `tiles` (indices into
    sea.cascades): displaced sideways (not a swell's core) and holding a wave shorter than
    the sea's `crest_longest`."""
    first = sea.cascades[tiles[0]]
    return 1 in first.gives and min(
        sea.cascades[j].shortest_held for j in tiles) < sea.crest_longest


def crest_weights(lod, level, cap):
    """The crest sum's weight of the band at `level`: its band limit weight at min(lod, cap)
    (band_limit.octave_weights), at the cap alone where `lod` is None (every band whole, or
    rows that keep the band whole)."""
    if lod is None:
        return np.float32(min(max(cap - level, 0.0), 1.0))
    return octave_weights(np.minimum(lod, np.float32(cap)), level,
                          scratch("crest weights", lod.shape, lod.dtype))


def _copy(out, kept, into, aside):
    """The running sums' GEOMETRY fields into the crest sum, less the heights set `aside`."""
    into[...] = out[:, kept]
    if aside is not None:
        into[:, 0] -= aside[:, 0]


def _add(sea, textures, j, points, origin, fields, out, weight, part):
    """Add tile j's `fields` (of each time's `textures`) at `points` as `sum_bands`'s into
    `out`, times `weight` if given; with `part` (into, weight, feed), its fields in `feed` into
    `into` (times, 3, ...: GEOMETRY's places) too, times that weight if given."""
    cascade = sea.cascades[j]
    where = Lookup.turned(cascade.texels, points, origin, cascade.texels / cascade.size,
                          cascade.turn, shift_turn=Warp.turn(j))
    for k, (at, into) in enumerate(zip(textures, out, strict=True)):
        for i, f in enumerate(fields):
            if f not in at[j]:  # a field the tile does not hold: 0
                continue
            v = where.sample(at[j][f])
            if part is not None and f in part[2]:
                crest = part[0][k, GEOMETRY.index(f)]
                if part[1] is None:
                    crest += v
                else:
                    crest += v * part[1]
            if weight is not None:
                v *= weight
            into[i] += v
