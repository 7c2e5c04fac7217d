"""The height field f_HF (thesis §1.6 Eq. 1.2, §3.2, App. B): fractal animated noise.

    f_HF(x, y, t) = amplitude * sum_i  alpha^i * w_i * noise_i((p - c_i t d) 2^i / scale, z_i(t))

Octave i's lattice period is scale / 2^i; its waves are noise.WAVELENGTH (1.7) times as long,
lambda_i (2 pi over the noise's rms wavenumber), and it travels along the wind's direction d at
their deep-water phase speed, c_i = sqrt(g lambda_i / (2 pi)), so long waves outrun short ones
as on the sea (dispersion), while it changes shape slowly, at EVOLUTION times the deep-water
frequency sqrt(g / (2 pi lambda_i)); `speed` scales both. Each octave has its own hash key.
With choppiness lambda, each point also moves toward the crests by lambda grad h_i / k_i per
octave (k_i = 2 pi / lambda_i: Tessendorf's choppy displacement of a wave).
w_i in [0, 1] is the band limit (§3.2, band_limit.py): 1 where the grid can carry octave i, fading
to 0 over one octave as a mip-map would. noise_i is normalised so that |noise_i| <= 1, which makes
`bound` a true bound of every height either path returns.

Two evaluation paths give the same function: "exact" evaluates the gradient noise per point (the
reference); "fast" is the thesis's path, which renders each octave into a tileable texture per frame
and samples it bilinearly (error measured in tests/core/test_height_field.py).

Over 300 lines on purpose: the two paths, the bounds and the travel share one octave table and
must stay the same function; they are tested side by side.
"""


import numpy as np

from . import noise as _noise
from . import shading
from .band_limit import octave_weights, shader_octaves
from .noise_tiles import shared_tiles
from .scratch import CHUNK, scratch
from .validation import finite, integer, non_negative, positive

GRAVITY = 9.81
# How fast an octave changes shape as it travels, against the deep-water frequency of its
# wavelength: waves keep their shape for several periods as they pass.
EVOLUTION = 0.3
METHODS = ("exact", "fast")
# A bound of |grad noise| per lattice unit for the exact path's choppy bound (the fast path
# takes its own from its textures); tests/core/test_height_field.py checks it.
GRADIENT_BOUND = 4.0


class HeightField:
    """Fractal animated noise heights with a true displacement bound (S_upper/S_lower of §2.2)."""

    layer = None  # no slope layer (slope_layer.py): the shader's noise detail draws its octaves

    def __init__(self, amplitude=0.5, wave_scale=40.0, octaves=8, roughness=0.5, speed=1.0,
                 seed=0, method="fast", texels=4, wind_direction=0.0, choppiness=0.0):
        self.amplitude = non_negative("amplitude", amplitude)
        self.wave_scale = positive("wave_scale", wave_scale)
        self.octaves = integer("octaves", octaves, 0, _noise.MAX_OCTAVES)
        self.roughness = non_negative("roughness", roughness)
        self.speed = finite("speed", speed)
        self.seed = integer("seed", seed, -(2**63), 2**64 - 1)
        if method not in METHODS:
            raise ValueError(f"method: must be one of {METHODS}, got {method!r}")
        self.method = method
        self.direction = np.array([np.cos(finite("wind_direction", wind_direction)),
                                   np.sin(wind_direction)])
        self.choppiness = non_negative("choppiness", choppiness)
        self._tiles = shared_tiles(self.seed, texels) if method == "fast" else None
        self._side = None  # (time, horizontal bound): `bounds`'s cache of the last time read

    def bounds(self, t):
        """(max |f_HF|, max |choppy displacement| at time t; 0 without choppiness), m."""
        t = finite("time", t)
        if self._side is None or self._side[0] != t:
            self._side = (t, self._horizontal_bound(t))
        return self.bound, self._side[1]

    def _horizontal_bound(self, t):
        """Per octave lambda gain |grad n| / k: from the texture patches' gradients (exact for
        what is sampled), or for the exact path a bound of the noise's gradient."""
        if self.choppiness == 0.0 or self.amplitude == 0.0:
            return 0.0
        total = 0.0
        scale = self.amplitude / _noise.NOISE_BOUND
        for i in range(self.octaves):
            gain = scale * self.roughness**i
            if gain == 0.0:
                continue
            if self._tiles is None:
                steepest = GRADIENT_BOUND  # per lattice unit
            else:  # the slope textures the frame samples (bilinear never exceeds a corner)
                z = self.time_coordinate(i, t)
                gx, gy = (self._tiles.texture(i, z, 1.0, kind).view(np.float32)[0::4]
                          for kind in (1, 2))
                steepest = float(np.hypot(gx, gy).max())
            total += self.choppiness * gain * steepest * _noise.WAVELENGTH / (2.0 * np.pi)
        return total

    first_level = 0.0  # the band limit below which no octave is in the geometry

    @property
    def longest_wave(self):
        return self.wavelength(0) if self.octaves and self.amplitude else 0.0

    @property
    def foam_span(self):
        """Metres across the sea pattern whitecaps are calibrated on (foam.foam_thresholds):
        one tile of the first octave, noise.PERIOD lattice periods."""
        return _noise.PERIOD * self.wave_scale

    def whole_level(self, wavelength):
        """The band limit from which waves of `wavelength` (m) are whole in the geometry."""
        return float(np.log2(self.wavelength(0) / wavelength) + 1.0)

    def foam_levels(self):
        """The band limits at which the foam is calibrated: octave i is whole from lod i + 1."""
        return np.arange(self.octaves + 1, dtype=np.float64)

    def foam_cue(self, xy, t, lod=None, grid=None, band=None, origin=None):
        """Where whitecaps form on the noise: the highest crests (Jensen and Golias), of the
        octaves `band` keeps if lower than `lod`. `grid`, the displaced grid the spectrum's cue
        is taken from, and `origin` (the noise is evaluated point by point) are not needed."""
        if band is not None:
            lod = band if lod is None else np.minimum(lod, band)
        return self.heights_xy(xy, t, lod)

    def shader_octaves(self, lod):
        """(first, count): the octaves some vertex left out, in part or whole (§3.2)."""
        return shader_octaves(lod, self.octaves)

    def shader_detail(self, first, count):
        """The octaves from `first` on (`count` of them) as the shader's noise (shading.Detail),
        as high as they are: their standard deviation over the noise texture's."""
        std = self.amplitude / _noise.NOISE_BOUND * _noise.NOISE_STD * np.sqrt(
            sum(self.roughness ** (2 * i) for i in range(first, first + count)))
        return shading.Detail(first=int(first), scale=1.0 / self.lattice(first),
                              octaves=float(max(count - 1, 0)),
                              roughness=min(self.roughness, 1.0),
                              height=float(std / shading.noise_fac_std(
                                  max(count - 1, 0), min(self.roughness, 1.0))),
                              time_rate=float(self.time_coordinate(first, 1.0)))

    def ripple(self):
        """(shading.Detail, the longest one's lattice period m): the fractal carried on below
        its last octave, shading.RIPPLE_OCTAVES octaves each half the height of the one before
        (the roughness the shader's ripples have; every octave of the noise's own reaches the
        shader through `shader_detail`), drawing the slopes they would have (`slopes`; Blender's
        noise draws them a little higher than ours would be, shading.detail_height). Without
        them the wind's slopes all went into the roughness at every distance
        (shading.filtering) and the noise's sea was blurred even at the camera."""
        top = self.lattice(self.octaves)
        octaves = shading.RIPPLE_OCTAVES
        return shading.Detail(first=self.octaves, scale=1.0 / top,
                              octaves=float(octaves - 1), roughness=0.5,
                              height=shading.detail_height(self.slopes.ripple, 1.0 / top,
                                                           octaves - 1),
                              time_rate=float(self.time_coordinate(self.octaves, 1.0))), top

    def _gain(self, octave):
        """Octave i's height over the noise's: amplitude alpha^i over the noise's bound."""
        return self.amplitude / _noise.NOISE_BOUND * self.roughness**octave

    def _ripple_gain(self):
        """The ripples' first octave's: the last octave's times alpha, at most halving (so at
        alpha 0.5 the octave a noise of one more would add; no steeper than the last octave
        above it); none without octaves, so a flat sea has no ripples."""
        if self.octaves == 0:
            return 0.0
        return self._gain(self.octaves - 1) * min(self.roughness, 0.5)

    def travel(self, octave, t):
        """How far octave i has travelled along the wind at time t: (dx, dy) in metres."""
        speed = np.sqrt(GRAVITY * self.wavelength(octave) / (2.0 * np.pi))
        return self.direction * (speed * self.speed * t)

    @property
    def bound(self):
        """max |f_HF|: amplitude * sum alpha^i, since every octave is normalised to |noise| <= 1."""
        return self.amplitude * sum(self.roughness**i for i in range(self.octaves))

    @property
    def slopes(self):
        """The slope variance of the octaves and the ripples (shading.Slopes): octave i's slope
        is its gain times the noise's gradient per lattice unit over its lattice period; each
        ripple octave the first's (`_ripple_gain`), half its height over half its period."""
        def variance(gain, period):
            return (gain * _noise.GRADIENT_RMS / period) ** 2

        octaves = [variance(self._gain(i), self.lattice(i)) for i in range(self.octaves)]
        top = self.lattice(self.octaves)
        ripple = shading.RIPPLE_OCTAVES * variance(self._ripple_gain(), top)
        return shading.Slopes(total=float(sum(octaves) + ripple),
                              density=float(octaves[-1] / np.log(2.0)) if octaves else 0.0,
                              ripple=float(ripple), ripple_top=float(top),
                              shortest=float(top / 2.0**shading.RIPPLE_OCTAVES))

    @property
    def spread(self):
        """(standard deviation of f_HF, root mean square of the choppy displacement), m: the
        octaves are independent noises, so their variances add (noise.NOISE_STD); each octave's
        displacement, lambda grad h / k, is lambda times its height's (k its waves' rms
        wavenumber, noise.WAVELENGTH)."""
        std = self.amplitude / _noise.NOISE_BOUND * _noise.NOISE_STD * np.sqrt(
            sum(self.roughness ** (2 * i) for i in range(self.octaves)))
        return float(std), float(self.choppiness * std)

    def lattice(self, octave):
        """Octave i's lattice period, scale / 2^i (m): the unit the band limit and the filtering
        count in."""
        return self.wave_scale / 2.0**octave

    def wavelength(self, octave):
        """The length of octave i's waves (m): noise.WAVELENGTH lattice periods."""
        return self.lattice(octave) * _noise.WAVELENGTH

    def time_coordinate(self, octave, t):
        """Noise time coordinate of an octave: EVOLUTION times the deep-water frequency of its
        wavelength, sqrt(g / (2 pi lambda))."""
        return (t * self.speed * EVOLUTION
                * np.sqrt(GRAVITY / (2.0 * np.pi * self.wavelength(octave))))

    def heights(self, x, y, t, lod=None):
        """f_HF at world points (x, y) and time t (float64, same shape as x).

        `lod` (per point, band_limit.py) band-limits the sum; None keeps every octave.
        """
        x = np.asarray(x, dtype=np.float64)
        return self.heights_xy(np.stack([x, np.broadcast_to(y, x.shape)]), t, lod)

    def heights_xy(self, xy, t, lod=None):
        """`heights` at a (2, ...) array of x and y, as the grid builds them."""
        return self._evaluate(xy, t, lod, False)[0]

    def displacement(self, xy, t, lod=None, on_grid=False, origin=None, crest=None):
        """(h, (dx, dy) or None) at a (2, ...) array of x and y: the height and, with
        choppiness, the horizontal displacement toward the crests. (`on_grid`, that xy are a
        grid's vertices, `origin` and `crest` are for the spectral source: each octave here is
        sampled at every vertex, point by point, and its foam's cue is its height, so a
        `crest` adds None.)"""
        h, d = self._evaluate(xy, t, lod, self.choppiness > 0.0)
        return (h, d) if crest is None else (h, d, None)

    def _evaluate(self, xy, t, lod, choppy):
        """An octave is evaluated only on the rows (last axis = columns) between the first and
        the last row where some point keeps it: contiguous slices, no gathers or scatters. Rows
        are summed CHUNK vertices at a time, so the scratch buffers keep that size."""
        t = finite("time", t)
        xy = np.asarray(xy, dtype=np.float64)
        shape = xy.shape[1:]
        h = np.zeros(shape, dtype=np.float64)
        d = np.zeros((2,) + shape) if choppy else None
        if self.amplitude == 0.0 or h.size == 0:
            return h, d
        rows = (1, -1) if len(shape) < 2 else (-1, shape[-1])
        lod2 = None if lod is None else np.asarray(lod).reshape(rows)
        xy2, h2 = xy.reshape((2,) + rows), h.reshape(rows)
        d2 = None if d is None else d.reshape((2,) + rows)
        step = max(1, CHUNK // h2.shape[1])
        for start in range(0, h2.shape[0], step):
            band = slice(start, start + step)
            lod_band = None if lod2 is None else lod2[band]
            self._sum_octaves(self._octave_jobs(lod_band), xy2[:, band], lod_band, t, h2[band],
                              None if d2 is None else d2[:, band])
        return h, d

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

    def _sum_octaves(self, jobs, xy2, lod2, t, out, side=None):
        """Add the octaves of `jobs` into `out` (rows x columns), and their choppy displacement
        into `side` (2 x rows x columns) if given."""
        for i, gain, band, weighted in jobs:
            z = self.time_coordinate(i, t)
            inv = 1.0 / self.lattice(i)
            shift = self.travel(i, t)
            # lambda grad h / k: the gradient per lattice unit times gain lambda / k, k the
            # waves' wavenumber per lattice unit.
            chop = gain * self.choppiness * _noise.WAVELENGTH / (2.0 * np.pi)
            if self._tiles is None:
                xs, ys = (xy2[0, band] - shift[0]) * inv, (xy2[1, band] - shift[1]) * inv
                key = _noise.octave_key(self.seed, i)
                n = _noise.noise(xs, ys, np.full(xs.shape, z), key)
                n *= gain
                if side is not None:
                    e = 1e-3  # lattice units: central differences of the exact noise
                    zs = np.full(xs.shape, z)
                    gx = (_noise.noise(xs + e, ys, zs, key) - _noise.noise(xs - e, ys, zs, key))
                    gy = (_noise.noise(xs, ys + e, zs, key) - _noise.noise(xs, ys - e, zs, key))
                    gx *= chop / (2.0 * e)
                    gy *= chop / (2.0 * e)
            else:
                where = self._tiles.lookup(xy2[:, band], inv, shift)
                if side is not None:
                    gx = where.sample(self._tiles.texture(i, z, chop, 1), out=scratch(
                        "chop x", where.shape, np.float32))
                    gy = where.sample(self._tiles.texture(i, z, chop, 2), out=scratch(
                        "chop y", where.shape, np.float32))
                n = where.sample(self._tiles.texture(i, z, gain))
            weights = None
            if weighted:
                weights = octave_weights(lod2[band], i,
                                         scratch("weights", lod2[band].shape, lod2.dtype))
                n *= weights
            out[band] += n
            if side is not None:
                if weights is not None:
                    gx *= weights
                    gy *= weights
                side[0, band] += gx
                side[1, band] += gy

