"""The spectral sea's bands summed at points (spectral_field.SpectralField.sample), each weighted
by the band limit (thesis §3.2, band_limit.py), and with it the crest sum: the sideways
displacement of the waves up to a band limit `cap` (the whitecaps' level, foam.whitecap_level),
which the foam's cue is taken from (foam.foam_field) without sampling the sea again.

The bands come longest first, so the crest sum is, for most bands, a copy of the running sum
once the bands it keeps whole are in: every band with level + 1 <= cap, summed before the
first that is not, is what the crest sum holds of them; the band `cap` falls within is added
to both, each with its own weight (`crest_weights`), and so is any later band the cap keeps
(none in a sea laid out by cascade.layout: the one band out of order, a swell's core, is not
displaced sideways)."""

import numpy as np

from .band_limit import (
    every_other_of,
    every_other_shape,
    fill_every_other,
    octave_weights,
    row_jobs,
    row_parts,
)
from .cascade import SIDEWAYS
from .scratch import scratch
from .tiles import Lookup
from .warp import Warp


def sum_bands(sea, textures, origin, points, lods, fields, out, on_grid, crest=None):
    """Add the bands' `fields` (of `textures`: per time, per cascade) at origin + offsets
    into `out` (times, fields, rows, columns), band by band (its tiles share its rows and
    coarse part; `lods`: each of sea.groups' band limit), each tile read where the warp
    turned by its own turn moves the points `points` (4, rows, columns: offsets, warp).
    `crest` (cap, into): also the SIDEWAYS fields (which `fields` must hold) of the waves
    band limit min(lod, cap) keeps, into `into` (times, 2, rows, columns)."""
    mins = {}
    cap, into = crest if crest is not None else (None, None)
    copied = crest is None
    sideways = [fields.index(f) for f in SIDEWAYS] if crest is not None else None
    for (level, _, tiles), lod in zip(sea.groups, lods, strict=True):
        if not sea.cascades[tiles[0]].gives.intersection(fields):
            continue
        if not copied and level + 1.0 > cap:  # every band the cap keeps whole is in
            _copy(out, sideways, into)
            copied = True
        keeps = copied and cap is not None and level < cap  # in the crest sum too
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
                    None if lod is None else lod[rows], level, cap))
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
                for i in range(len(fields)):
                    fill_every_other(sums[k, i], filled)
                    out[k, i, coarse] += filled
                    if share is not None and i in sideways:
                        into[k, sideways.index(i), coarse] += filled * share
    if not copied:
        _copy(out, sideways, into)


def crest_weights(lod, level, cap):
    """The crest sum's weight of the band at `level`: its band limit weight at min(lod, cap)
    (band_limit.octave_weights), at the cap alone where `lod` is None (every band whole, or
    rows that keep the band whole)."""
    if lod is None:
        return np.float32(min(max(cap - level, 0.0), 1.0))
    return octave_weights(np.minimum(lod, np.float32(cap)), level,
                          scratch("crest weights", lod.shape, lod.dtype))


def _copy(out, sideways, into):
    """The running sums' SIDEWAYS fields into the crest sum."""
    into[...] = out[:, sideways]


def _add(sea, textures, j, points, origin, fields, out, weight, part):
    """Add tile j's `fields` (of each time's `textures`) at `points` as `sum_bands`'s into
    `out`, times `weight` if given; with `part` (into, weight), its SIDEWAYS fields into `into`
    (times, 2, ...) too, times that weight if given."""
    cascade = sea.cascades[j]
    where = Lookup.turned(cascade.texels, points, origin, cascade.texels / cascade.size,
                          cascade.turn, shift_turn=Warp.turn(j))
    for k, (at, into) in enumerate(zip(textures, out, strict=True)):
        for i, f in enumerate(fields):
            if f not in at[j]:  # a field the tile does not hold: 0
                continue
            v = where.sample(at[j][f])
            if part is not None and f in SIDEWAYS:
                crest = part[0][k, SIDEWAYS.index(f)]
                if part[1] is None:
                    crest += v
                else:
                    crest += v * part[1]
            if weight is not None:
                v *= weight
            into[i] += v
