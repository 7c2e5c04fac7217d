"""The spectral height source: the sea synthesised from its spectrum with FFTs (Tessendorf,
*Simulating Ocean Water*), in cascades (cascade.py), as a height field the projected grid
samples (§1.6).

A tile repeats, and where a band holds much of the sea's energy its repetition would show (the
surface's autocorrelation at the tile's period is the tile's share of the variance), so such a
band's energy is shared among several tiles of sizes that are not multiples of each other
(cascade.TILE_RATIOS), each turned by its own angle and with its own phases: no tile holds more
than SHARE_PER_TILE of the variance. Where two tiles' lattices nearly meet within a few kilometres
they would repeat together; each tile is read through a slow warp of its own (warp.py), which
spreads such a joint repeat over metres.

A swell's core (spectrum.in_swell_core: near its peak, within a few degrees of its heading) has
tiles of its own, band-limited along its headings (band_limit.along_waves): the grid's rows, tens
of metres deep a few hundred metres out, cannot hold a wave heading toward the camera, but one
crossing the view they can, and the swell is the sea's longest and straightest waves. The core is
not displaced sideways: a swell's steepness, a few hundredths, sharpens no crest a picture shows,
and swells do not break, so it adds nothing to the foam's folding.

The choppy displacement moves points toward the crests, D(x) = sum of i lambda (k / |k|) h
e^(i k.x) (Tessendorf §4.4, with the sign that sharpens the crests), and the surface folds where
its Jacobian, (1 + dDx/dx)(1 + dDy/dy) - dDx/dy dDy/dx, falls below zero: the foam's cue. The
Jacobian is taken as the mesh shows it, by differences between neighbouring vertices (`jacobian`).

A frame is a pure function of (seed, sea state, choppiness, time): the phases come from the seed
alone, so frame N is the same computed alone or after 1..N-1, on any machine.
"""

import copy
from collections import OrderedDict
from dataclasses import replace
from functools import cached_property, lru_cache

import numpy as np

from . import shading, spectrum
from .band_limit import along_waves
from .band_sum import sum_bands
from .cascade import (
    BAND_LONGEST,
    BANDS,
    FOAM_STEPS,
    GEOMETRY,
    LAYER_FIRST,
    SIDEWAYS,
    TEXELS,
    band_level,
    band_of,
    band_shares,
    bands,
    has_swell_core,
    layout,
    slope_variance,
    swell_wave,
)
from .projected_grid import grid_jacobian
from .scratch import each, row_step, scratch
from .slope_layer import SlopeLayer
from .validation import finite, integer, non_negative
from .warp import Warp

MOMENTS = 12  # times whose tiles a source keeps (`SpectralField._at`)


class SpectralField:
    """A sea from its spectrum, sampled at world points: heights and choppy displacements.

    Time is an argument of every read: `bounds(t)` are true bounds of what is sampled at t
    (bilinear samples never exceed their tile's extremes); the tiles' fields of the last times
    read are kept as a cache keyed by the time, not as state a reader must set up."""

    def __init__(self, state, choppiness=0.0, seed=0, texels=TEXELS, wind_span=None):
        """`wind_span`: (least, most) wind speed a shot's keyframed wind takes; the tiles are
        laid out for all of it, so the sea changes smoothly as the wind does (None: this
        state's wind only)."""
        self.state, self.wind_span = state, None if wind_span is None else tuple(wind_span)
        self.choppiness = non_negative("choppiness", choppiness)
        self.seed = integer("seed", seed, 0, 2**63)
        self.texels = integer("texels", texels, 8, 1024)
        if self.texels & (self.texels - 1):
            raise ValueError(f"texels: must be a power of two, got {self.texels}")
        self.cascades, self.groups = layout(state, self.seed, self.texels, wind_span)
        swell, shares = has_swell_core(state), band_shares(state)
        # The band limit (band_limit.py) in units of 1 m: a band is kept whole while its shortest
        # wave is at least sqrt(2) * 2 grid spacings long, faded out over the next octave.
        self.wave_scale = 1.0
        self.octaves = BANDS
        # The displacement the tiles hold and the foam looks for: the displayed choppiness, or
        # Tessendorf's lambda = 1 on a sea drawn without it (its crests still break), which
        # `displacement` then does not apply.
        self.fold = self.choppiness if self.choppiness > 0.0 else 1.0
        self.warp = Warp(self.seed)
        self._moments = OrderedDict()  # t: (t, per-cascade fields, bound, side, fields made)
        # The shader's stand-in noise draws the bands the geometry leaves out, the swell's
        # core with its band (where the geometry drops it, nothing else draws it).
        self._shares = shares[:BANDS]
        if swell:
            self._shares[band_of(swell_wave(state))] += shares[BANDS]
        self._m0 = spectrum.moments(state)[0]

    foam_span = BAND_LONGEST  # metres across the sea pattern whitecaps are calibrated on

    def twin(self):
        """The same sea for another thread (operators/bridge/ahead.py): its cascades and caches
        shared (read only but for caches of pure functions), its time's fields its own."""
        other = copy.copy(self)
        other._moments = OrderedDict()
        return other

    @cached_property
    def layer(self):
        """The slopes of the short bands as the shader's normal maps (slope_layer.py)."""
        return SlopeLayer(self.state, self.seed, self.wind_span is not None)

    @cached_property
    def spread(self):
        """(standard deviation of the height, root mean square of the choppy displacement), m:
        each wave vector's mean power |h0(k)|^2 + |h0(-k)|^2 summed (Parseval), at any time;
        the displacement's is lambda times the height's (|k / |k|| = 1) over the moved tiles."""
        power = [float(np.sum(c.power())) for c in self.cascades]
        moved = sum(p for p, c in zip(power, self.cascades, strict=True) if 1 in c.gives)
        return float(np.sqrt(sum(power))), float(self.choppiness * np.sqrt(moved))

    @cached_property
    def volume_spread(self):
        """The `spread` the displaceable volume is fitted to (fitted_extents): the sea's own, or
        under a keyed wind (`wind_span`) the sea's at the span's strongest wind, the same at
        every frame, so a still camera's grid stays still while the wind changes (and the
        residual foam's past cues made on it serve the next frames)."""
        if self.wind_span is None or self.state.wind_speed >= self.wind_span[1]:
            return self.spread
        return self.at_wind(self.wind_span[1]).spread

    def at_wind(self, wind_speed):
        """This sea under another wind, its tiles laid out for the same `wind_span`: kept, as a
        keyed wind's lattice seas (foam.calibrated_at) and its span's strongest
        (`volume_spread`) serve many frames."""
        return _at_wind(replace(self.state, wind_speed=wind_speed), self.choppiness, self.seed,
                        self.texels, self.wind_span)

    @property
    def levels(self):
        """The band limits of the bands (and the swell's core) in the tiles, one each."""
        return [level for level, _, _ in self.groups]

    @property
    def first_level(self):
        """The band limit below which no band is in the geometry."""
        return min(self.levels) if self.levels else 0.0

    @property
    def longest_wave(self):
        """The longest wave (m) a tile holds."""
        return max(c.longest_held for c in self.cascades) if self.cascades else 0.0

    def whole_level(self, wavelength):
        """The band limit from which waves of `wavelength` (m) are whole in the geometry: the
        level of the band holding them + 1 (a band fades in whole)."""
        return band_level(bands()[band_of(wavelength)][0]) + 1.0

    def foam_levels(self):
        """The band limits at which the foam is calibrated: at FOAM_STEPS over each band's
        fade-in (band_limit.octave_weights: from its level to its level + 1), where the cue's
        spread changes fast; between fades nothing changes, so the thresholds interpolate."""
        levels = sorted({float(level + f) for level in self.levels for f in FOAM_STEPS})
        return levels or [0.0]

    def foam_cue(self, xy, t, lod=None, grid=None, band=None, origin=None):
        """Where whitecaps form on the spectral sea: where the surface folds, its Jacobian
        lowest (Jensen and Golias). See `jacobian`."""
        return -self.jacobian(xy, t, lod, grid, band, origin)

    def grid_cue(self, xy, shift):
        """`foam_cue` of a grid's points xy (2, rows, columns) displaced by `shift` (the crest
        sum, say: `sample`'s `crest`), between neighbours as the mesh shows it."""
        return -grid_jacobian(xy, shift)

    def shader_octaves(self, lod):
        """(first, count): the bands some vertex left out, in part or whole."""
        if lod is None or not self.levels:
            return BANDS, 0
        low = float(lod.min())
        out = [b for b, (shortest, _) in enumerate(bands())
               if band_level(shortest) + 1.0 > low]
        first = out[0] if out else BANDS
        return first, BANDS - first

    def shader_detail(self, first, count):
        """The bands from `first` on above the slope layer (which draws the rest) as the
        shader's noise (shading.Detail): two octaves a band, from the band's longest wave, each
        half the height of the one before (the spectrum's tail), as high as those bands' share
        of the sea's height (its standard deviation over the noise texture's)."""
        count = min(first + count, LAYER_FIRST) - first
        if count <= 0 or first >= BANDS:
            return shading.Detail(first=BANDS, scale=1.0, octaves=0.0, roughness=0.5,
                                  height=0.0, time_rate=0.0)
        longest = bands()[first][1]
        sigma = np.sqrt(self._m0 * sum(self._shares[first:first + count]))
        return shading.Detail(first=band_level(bands()[first][0]), scale=1.0 / longest,
                              octaves=float(2 * count - 1), roughness=0.5,
                              height=float(sigma / shading.noise_fac_std(2 * count - 1, 0.5)),
                              time_rate=float(np.sqrt(spectrum.GRAVITY / (2.0 * np.pi * longest))))

    def ripple(self):
        """(shading.Detail, longest wavelength m) of the spectrum's tail: see `_ripple`."""
        return self._ripple

    @cached_property
    def _ripple(self):
        """The waves shorter than the last band, which no tile holds, down
        shading.RIPPLE_OCTAVES octaves, as shading detail (shading.Detail, `first` unused;
        drawn where a pixel shows them, shading.Filtering), and the longest of them (m), each
        octave half the one before. They draw the spectrum's slopes over that range
        (shading.detail_height; the filtering books them as drawn), so the near water, whose
        every band the geometry holds, has detail finer than 25 cm."""
        top = bands()[-1][0]
        octaves = shading.RIPPLE_OCTAVES
        detail = shading.Detail(first=BANDS, scale=1.0 / top, octaves=float(octaves - 1),
                                roughness=0.5,
                                height=shading.detail_height(self.slopes.ripple, 1.0 / top,
                                                             octaves - 1),
                                time_rate=float(np.sqrt(spectrum.GRAVITY / (2.0 * np.pi * top))))
        return detail, float(top)

    @cached_property
    def slopes(self):
        """The slope variance of the waves this sea draws (shading.Slopes): the spectrum's
        k^2 S over the bands and over the ripples, down to the ripples' shortest wave. What the
        geometry's band limit leaves out is roughness where the pixel could show it too: a band
        is half in the geometry at lod = its level + 1/2, where its shortest wave is 2^(1 - lod)
        (`left_out_log`). (The shader's detail noise has a sea's height but hardly any of its
        slopes: noise octaves halving in height from the band's longest wave.)"""
        top = bands()[-1][0]
        shortest = top / 2.0**shading.RIPPLE_OCTAVES
        ripple = slope_variance(self.state, shortest, top)
        layer_top = bands()[LAYER_FIRST][1]
        return shading.Slopes(
            total=ripple + slope_variance(self.state, top, 10.0 * BAND_LONGEST),
            density=slope_variance(self.state, top, 2.0 * top) / np.log(2.0), ripple=ripple,
            ripple_top=top, shortest=shortest, left_out_log=float(np.log(2.0 * self.wave_scale)),
            layer_top=layer_top,
            layer_density=slope_variance(self.state, layer_top, 2.0 * layer_top) / np.log(2.0))

    def wavelength(self, octave):
        return self.wave_scale / 2.0**octave

    def _at(self, t, fields=GEOMETRY):
        """The tiles' fields at time t, with their bounds: (t, per-cascade {field: texture},
        bound, side, fields made). Made once per time, each field when first asked for (without
        choppiness, the displacement only when the foam asks for it); the last MOMENTS times
        are kept (the residual foam reads a few past ones each frame)."""
        t = finite("time", t)
        moment = self._moments.get(t)
        if moment is None:
            first = GEOMETRY if self.choppiness > 0.0 else (0,)
            made = each(lambda c: c.fields(t, self.fold, first), self.cascades)
            moment = (t, [m[0] for m in made], sum(m[1] for m in made),
                      sum(m[2] for m in made), set(first))
            self._moments[t] = moment
            while len(self._moments) > MOMENTS:
                self._moments.popitem(last=False)
        else:
            self._moments.move_to_end(t)
        missing = set(fields) - moment[4]
        if missing:
            made = each(lambda c: c.fields(t, self.fold, missing)[0], self.cascades)
            for textures, more in zip(moment[1], made, strict=True):
                textures.update(more)
            moment[4].update(missing)
        return moment

    def bounds(self, t):
        """(max |height|, max |choppy displacement|) of what is sampled at time t (m)."""
        _, _, bound, side, _ = self._at(t)
        return bound, side

    def sample(self, xy, t, lod=None, fields=(0,), on_grid=False, origin=None, crest=None):
        """The sum over tiles of `fields` (indices into FIELDS) at world points xy (2, ...),
        each band weighted by the band limit (`lod`, as the grid gives it, or None): (len(fields),
        ...) float64; for a tuple of times `t`, (len(t), len(fields), ...), each tile located once.
        `on_grid`: xy (2, rows, columns) are a grid's vertices, neighbours both ways, so a band
        long against the spacing is sampled on every other row and column (band_limit.COARSE).
        `origin` (x, y): every chunk's offsets' (None: `_origin`), so each point's are its own.
        `crest` (a band limit; `fields` holding SIDEWAYS): (sums, crest sums), the latter the
        SIDEWAYS fields of the waves min(lod, crest) keeps (band_sum.py), float32."""
        times = t if isinstance(t, tuple) else (t,)
        textures = [self._at(when, fields)[1] for when in times]
        xy = np.asarray(xy, dtype=np.float64)
        shape = xy.shape[1:]
        rows = (1, -1) if len(shape) < 2 else (-1, shape[-1])
        out = np.empty((len(times), len(fields)) + shape)
        xy2, out2 = xy.reshape((2,) + rows), out.reshape((len(times), len(fields)) + rows)
        crests = None if crest is None else np.empty((len(times), 2) + shape, np.float32)
        crests2 = None if crest is None else crests.reshape((len(times), 2) + rows)
        lod2 = None if lod is None else np.asarray(lod).reshape(rows)
        on_grid = on_grid and lod2 is not None and len(shape) == 2
        lods = [lod2 if along is None or not on_grid else along_waves(xy2, lod2, level, along)
                for level, along, _ in self.groups]
        step = row_step(*out2.shape[2:])  # the same chunks whatever the times, on the threads
        def chunk(start):
            band = slice(start, start + step)
            at = np.array(origin, np.float64) if origin is not None else self._origin(
                xy2[:, band], None if lod2 is None else lod2[band])
            # The offsets from the origin, then the warp there (Lookup.turned reads both).
            points = scratch("points", (4,) + xy2[:, band].shape[1:], np.float32)
            np.subtract(xy2[:, band], at[:, None, None], out=points[:2], casting="same_kind")
            self.warp(at, points[:2], out=points[2:])
            sums = scratch("sums", out2[:, :, band].shape, np.float32)  # summed in single
            sums.fill(0.0)
            crest_sums = None if crest is None else (crest, scratch(
                "crest sums", crests2[:, :, band].shape, np.float32))
            sum_bands(self, textures, at, points, [None if g is None else g[band] for g in lods],
                      fields, sums, on_grid, crest_sums)
            out2[:, :, band] = sums
            if crest is not None:
                crests2[:, :, band] = crest_sums[1]
        each(chunk, range(0, out2.shape[2], step))
        if crest is not None:
            return (out, crests) if isinstance(t, tuple) else (out[0], crests[0])
        return out if isinstance(t, tuple) else out[0]

    @staticmethod
    def _origin(xy, lod):
        """Where a chunk's points are taken from in single precision: the point of the finest
        detail (the shortest bands are sampled only near it), else the chunk's extent's middle."""
        if lod is None:
            return 0.5 * (xy.min(axis=(1, 2)) + xy.max(axis=(1, 2)))
        i = np.unravel_index(np.argmax(lod), lod.shape)
        return xy[:, i[0], i[1]].copy()

    def displacement(self, xy, t, lod=None, on_grid=False, origin=None, crest=None):
        """(h, (dx, dy) or None) at world points xy (2, ...): the height and, with choppiness,
        the horizontal displacement (`on_grid`, `origin`: `sample`'s); with `crest` (a band
        limit) also the crest sum (`sample`'s: the foam's cue, with or without choppiness)."""
        if crest is not None:
            (h, dx, dy), crests = self.sample(xy, t, lod, GEOMETRY, on_grid, origin, crest)
            return h, None if self.choppiness == 0.0 else np.stack([dx, dy]), crests
        if self.choppiness == 0.0:
            return self.sample(xy, t, lod, (0,), on_grid, origin)[0], None
        h, dx, dy = self.sample(xy, t, lod, GEOMETRY, on_grid, origin)
        return h, np.stack([dx, dy])

    def heights(self, x, y, t, lod=None):
        x = np.asarray(x, dtype=np.float64)
        return self.sample(np.stack([x, np.broadcast_to(y, x.shape)]), t, lod, (0,))[0]

    def jacobian(self, xy, t, lod=None, grid=None, band=None, origin=None):
        """The choppy surface's Jacobian (1 flat, < 0 folded) as a mesh shows it: by differences
        between neighbouring vertices, each wave's slope lessened as they lessen it.

        `grid` given: xy (2, rows, columns) are a frame's grid points on the sea and `grid` the
        same points displaced (`displacement`; without choppiness, xy itself), and the Jacobian
        is that of the map from one to the other between neighbours (central differences,
        one-sided on the border). Otherwise xy (2, ...) are points apart, and the differences
        are central over the spacing their `lod` stands for (band_limit.lod_for_spacing; None:
        every band whole), along x and y, of the waves `band` keeps if lower (a finer grid's;
        `origin`: `sample`'s)."""
        xy = np.asarray(xy, dtype=np.float64)
        if grid is not None:
            return grid_jacobian(xy, self.sample(xy, t, lod, SIDEWAYS) if self.choppiness == 0.0
                                 else grid - xy)
        top = max(self.levels, default=0.0) + 1.0  # every band whole: no finer spacing counts
        level = np.full(xy.shape[1:], top) if lod is None else np.minimum(lod, top)
        step = self.wave_scale * 2.0 ** -level / 2.0  # lod = log2(wave_scale / (2 spacing))
        points = np.repeat(xy[:, None], 4, axis=1)  # (2, 4, ...): +x, -x, +y, -y
        points[0, :2] += np.multiply.outer((1.0, -1.0), step)
        points[1, 2:] += np.multiply.outer((1.0, -1.0), step)
        kept = level if band is None else np.minimum(level, band)
        lods = None if lod is None and band is None else np.broadcast_to(
            kept.astype(np.float32), points.shape[1:])
        dx, dy = self.sample(points, t, lods, SIDEWAYS, origin=origin)
        span = 2.0 * step
        ddx_x, ddy_x = (dx[0] - dx[1]) / span, (dy[0] - dy[1]) / span
        ddx_y, ddy_y = (dx[2] - dx[3]) / span, (dy[2] - dy[3]) / span
        return (1.0 + ddx_x) * (1.0 + ddy_y) - ddx_y * ddy_x


@lru_cache(maxsize=8)
def _at_wind(state, choppiness, seed, texels, wind_span):
    return SpectralField(state, choppiness, seed, texels, wind_span)
