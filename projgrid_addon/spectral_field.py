"""The spectral height source: the sea synthesised from its spectrum with FFTs (Tessendorf,
*Simulating Ocean Water*), in cascades, as a height field the projected grid samples (§1.6).

The wavelengths are cut into bands a factor BAND_RATIO apart, from BAND_LONGEST down to a few
tens of centimetres, and each band is synthesised in periodic tiles of TEXELS^2 samples sized so
that its shortest wave spans 8 to 10 samples. No band is counted twice: a tile holds only its
band's wave vectors (`Cascade`). A tile repeats, and where a band holds much of the sea's
energy its repetition would show (the surface's autocorrelation at the tile's period is the
tile's share of the variance), so such a band's energy is shared among several tiles of sizes
that are not multiples of each other (TILE_RATIOS), each turned by its own angle and with its
own phases: no tile holds more than SHARE_PER_TILE of the variance. Where two tiles' lattices
nearly meet within a few kilometres they would repeat together; each tile is read through a
slow warp of its own (warp.py), which spreads such a joint repeat over metres.

A swell's core (spectrum.in_swell_core: near its peak, within a few degrees of its heading) has
tiles of its own, band-limited along its headings (band_limit.along_waves): the grid's rows,
tens of metres deep a few hundred metres out, cannot hold a wave heading toward the camera,
but one crossing the view they can, and the swell is the sea's longest and straightest waves.
The core is not displaced sideways: a swell's steepness, a few hundredths, sharpens no crest a
picture shows, and swells do not break, so it adds nothing to the foam's folding.

    h(k, t) = h0(k) e^(-i omega t) + conj(h0(-k)) e^(i omega t),   omega^2 = g |k|
    h0(k)   = e^(i phi_k) sqrt(E(k) dk^2 / 2)                        (phi_k: a random phase)

so each wave travels along its k at its own phase speed and the height variance is the integral
of E (spectrum.wavenumber_spectrum). The amplitudes are the spectrum's own and only the phases
are random, so every seed has the spectrum's significant height. The choppy displacement
moves points toward the crests, D(x) = sum of i lambda (k / |k|) h e^(i k.x) (Tessendorf §4.4,
with the sign that sharpens the crests), and the surface folds where its Jacobian,
(1 + dDx/dx)(1 + dDy/dy) - dDx/dy dDy/dx, falls below zero: the foam's cue. The Jacobian is
taken as the mesh shows it, by differences between neighbouring vertices (`jacobian`).

A frame is a pure function of (seed, sea state, choppiness, time): the phases come from the
seed alone, so frame N is the same computed alone or after 1..N-1, on any machine.

Over 300 lines on purpose: a cascade (one tile's band of the spectrum) and the field summing
the cascades share the band layout, the phases and the band limit.
"""

import copy
from functools import cached_property, lru_cache

import numpy as np

from . import shading, spectrum
from .band_limit import (
    along_waves,
    every_other_of,
    every_other_shape,
    fill_every_other,
    octave_weights,
    row_jobs,
    row_parts,
)
from .projected_grid import grid_derivative
from .scratch import CHUNK, each, scratch
from .tiles import Lookup, periodic_patches
from .validation import finite, integer, non_negative
from .warp import Warp

TEXELS = 64  # samples across a tile
BAND_LONGEST = 1300.0  # m: the longest waves synthesised (a storm's peak is about 600 m)
BAND_RATIO = 4.17  # each band's longest wave over its shortest
BANDS = 6  # down to BAND_LONGEST / 4.17^6, 0.25 m: shorter waves are the shader's
SAMPLES_PER_WAVE = 8.0  # over a tile's shortest wave: bilinear sampling keeps 95 % of it
# A band's tiles are its base size times these: not multiples of each other, and at most 1.28
# times larger, so the shortest wave still spans 8 / 1.28 = 6.25 samples.
TILE_RATIOS = (1.0, 1.0833, 1.1614, 1.2369, 1.1197, 1.0431, 1.2041, 1.2795)
LAYER_FIRST = 3  # the bands from this one on are the slope layer's too (slope_layer.py)
FOAM_STEPS = 2  # foam calibrations over a band's fade-in (foam_levels)
SHARE_PER_TILE = 0.12  # the most of the sea's height variance one tile may hold
BIG = 2  # how many times more texels (and metres) a band holding more than that has
# Fields a tile can give: the height, the choppy displacement along x and y, and the height's
# slopes along x and y (slope_layer.py).
FIELDS = ("h", "dx", "dy", "sx", "sy")
GEOMETRY = (0, 1, 2)
SIDEWAYS = (1, 2)


def bands():
    """(shortest, longest) wavelength of each band, longest first (m)."""
    return [(BAND_LONGEST / BAND_RATIO ** (b + 1), BAND_LONGEST / BAND_RATIO**b)
            for b in range(BANDS)]


def band_level(shortest):
    """The band limit (band_limit.py, in units of 1 m) from which a band whose shortest wave is
    `shortest` (m) fades in: whole one level up, while that wave is at least sqrt(2) * 2 grid
    spacings long."""
    return float(np.log2(1.0 / shortest) + 0.5)


def band_shares(state):
    """Each band's share of the sea's height variance, and last the swell's core's
    (spectrum.in_swell_core: its own tiles). The waves longer than BAND_LONGEST count with the
    first band, the shorter than the last band's with none."""
    edges = [2.0 * np.pi / lo for lo, _ in bands()]  # wavenumbers of the bands' short ends
    omega = np.sqrt(spectrum.GRAVITY * np.array([0.0, *edges]))
    parts, core, own = [], 0.0, has_swell_core(state)
    for a, b in zip(omega[:-1], omega[1:], strict=True):
        w = np.linspace(max(a, 1e-4), b, 4000)
        inside = (float(spectrum.integrate(spectrum.swell_core_spectrum(w, state), w)) if own
                  else 0.0)
        parts.append(float(spectrum.integrate(spectrum.wind_spectrum(w, state)
                                              + spectrum.swell_spectrum(w, state), w)) - inside)
        core += inside
    total = sum(parts) + core
    return [p / total if total > 0.0 else 0.0 for p in [*parts, core]]


def has_swell_core(state):
    """Whether the swell's core has tiles of its own: a swell longer than the slope layer's
    bands (slope_layer.py: their tiles hold the whole spectrum; a swell of a few seconds stays
    in the bands)."""
    return state.swell_height > 0.0 and swell_core_waves(state)[0] >= bands()[LAYER_FIRST][1]


def _band_of(wavelength):
    """The index of the band holding `wavelength` (m); the first for longer waves."""
    return min(sum(lo > wavelength for lo, _ in bands()), BANDS - 1)


def swell_core_waves(state):
    """(shortest, longest) wavelength (m) of the swell's core."""
    return tuple(swell_wave(state, f) for f in reversed(spectrum.SWELL_CORE))


def swell_wave(state, f=1.0):
    """The wavelength (m) of `f` times the swell's peak frequency: 2 pi g / omega^2."""
    return 2.0 * np.pi * spectrum.GRAVITY / (f * 2.0 * np.pi / state.swell_period) ** 2


def _slope_variance(state, shortest, longest, samples=4000):
    """The spectrum's slope variance over wavelengths `shortest` to `longest` (m): the
    integral of k^2 S(omega) d omega, k = omega^2 / g."""
    w = np.geomspace(np.sqrt(2.0 * np.pi * spectrum.GRAVITY / longest),
                     np.sqrt(2.0 * np.pi * spectrum.GRAVITY / shortest), samples)
    k = w * w / spectrum.GRAVITY
    s = spectrum.wind_spectrum(w, state) + spectrum.swell_spectrum(w, state)
    return float(spectrum.integrate(k * k * s, w))


def _line_angle(headings, direction):
    """The largest angle (rad, 0 to pi / 2) between the lines of `headings` and `direction`."""
    return float(np.abs(np.angle(np.exp(2j * (np.asarray(headings) - direction)))).max(
        initial=0.0)) / 2.0


@lru_cache(maxsize=64)
def tile_phases(seed, band, tile, texels):
    """e^(i phi) per wave vector of one tile, phi uniform: fixed by the seed alone."""
    rng = np.random.default_rng(np.random.SeedSequence([int(seed) & 0xFFFFFFFF, band, tile]))
    out = np.exp(2j * np.pi * rng.random((texels, texels)))
    out.setflags(write=False)
    return out


@lru_cache(maxsize=8)
def _lattice(texels):
    """Integer wave-vector coordinates (nx, ny) of an FFT grid, and the index of -n."""
    n = np.fft.fftfreq(texels, 1.0 / texels)
    nx, ny = np.meshgrid(n, n)
    return nx, ny, (-np.arange(texels)) % texels


class Cascade:
    """One tile `size` metres across, turned by `angle` (radians) on the sea, holding the wave
    vectors of a band (wavelengths between `shortest` and `longest`) with `share` of the band's
    energy (of the spectrum's `part`: spectrum.wavenumber_spectrum). Its lattice is the tile's;
    its wave vectors, and so its fields, are the world's. `smooth`: it has no choppy
    displacement (`gives`, the fields it gives, leaves those out)."""

    def __init__(self, size, angle, shortest, longest, share, state, phases, texels,
                 part=None, smooth=False):
        self.size, self.shortest = float(size), float(shortest)
        self.texels = texels
        self.turn = (np.cos(angle), np.sin(angle))
        nx, ny, neg = _lattice(texels)
        dk = 2.0 * np.pi / self.size
        c, s = self.turn

        def world(ax, ay):  # a tile lattice wave vector, turned onto the sea
            return (c * ax - s * ay) * dk, (s * ax + c * ay) * dk
        lo, hi = self.size / longest, self.size / shortest  # band edges in lattice units
        # Each wave vector stands for its lattice cell: its energy is the mean over the cell
        # (4 x 4 samples) of the spectrum inside the band, so neighbouring bands share the k
        # plane exactly and the sum over the lattice is the spectrum's integral even where the
        # lattice is coarse against the peak and the spreading.
        sub = (np.arange(4) + 0.5) / 4.0 - 0.5
        energy = np.zeros(nx.shape)
        for a in sub:
            for b in sub:
                n = np.hypot(nx + a, ny + b)
                inside = (n >= lo) & (n < hi)
                energy += np.where(inside, spectrum.wavenumber_spectrum(
                    *world(nx + a, ny + b), state, part), 0.0)
        energy *= share / 16.0
        # The tiles are synthesised in single precision: the vertices are float32 anyway, and
        # the transforms and the patches move half the bytes.
        self.h0 = (phases * (np.sqrt(0.5 * energy) * dk)).astype(np.complex64)
        self.h0_neg_conj = np.conj(self.h0[neg][:, neg])
        # The fields are real, their spectra Hermitian: each is made from the half of the
        # lattice with nx >= 0 by a real inverse transform (no band reaches the Nyquist row).
        half = slice(0, texels // 2 + 1)
        self._h0, self._h0_neg_conj = self.h0[:, half], self.h0_neg_conj[:, half]
        self.kx, self.ky = world(nx[:, half], ny[:, half])
        k = np.hypot(self.kx, self.ky)
        self.omega = np.sqrt(spectrum.GRAVITY * k)
        safe = np.where(k > 0.0, k, 1.0)
        self.ux, self.uy = self.kx / safe, self.ky / safe  # unit wave vectors
        self.empty = not np.any(energy > 0.0)
        self.gives = frozenset(range(len(FIELDS))) - (set(SIDEWAYS) if smooth else set())
        # The waves it holds, each wave vector of the half lattice standing for k and -k.
        held = ((energy > 0.0) | (energy[neg][:, neg] > 0.0))[:, half]
        self.shortest_held = 2.0 * np.pi / max(float(k[held].max(initial=0.0)), 1e-12)
        self.longest_held = 2.0 * np.pi / max(float(k[held & (k > 0.0)].min(initial=np.inf)),
                                              1e-12)
        self.headings = np.arctan2(self.ky[held], self.kx[held])
        self._factors = {}

    def power(self):
        """|h0(k)|^2 + |h0(-k)|^2 per wave vector of the lattice: its mean power."""
        return np.abs(self.h0) ** 2 + np.abs(self.h0_neg_conj) ** 2

    def half_power(self):
        """|h0(k)|^2 + |h0(-k)|^2 over the half lattice the transforms use, each column but
        the first and the last counted twice: it stands for its mirror too."""
        power = self.power()[:, :self.texels // 2 + 1]
        twice = np.full(power.shape[1], 2.0)
        twice[0] = twice[-1] = 1.0
        return power * twice

    def _factor(self, field, lam):
        """The multiplier taking h(k) to the spectrum of `field` (index into FIELDS),
        complex64, made once per field and choppiness."""
        key = (field, lam)
        hit = self._factors.get(key)
        if hit is None:
            hit = {0: lambda: np.ones_like(self.ux), 1: lambda: 1j * lam * self.ux,
                   2: lambda: 1j * lam * self.uy, 3: lambda: 1j * self.kx,
                   4: lambda: 1j * self.ky}[field]()
            hit = self._factors[key] = np.asarray(hit, np.complex64)
        return hit

    def fields(self, t, lam, which):
        """Patches (tiles.periodic_patches) of the `which` fields (indices into FIELDS) at time
        t, the displacement's of choppiness `lam`, {index: texture}, and the largest |h| and
        |(dx, dy)| of the samples (0 where those fields were not asked for or not given)."""
        which = [f for f in which if f in self.gives]
        if not which:
            return {}, 0.0, 0.0
        real = self.samples(t, lam, which)
        at = {f: i for i, f in enumerate(which)}
        bound = float(np.abs(real[at[0]]).max()) if 0 in at else 0.0
        side = (float(np.hypot(real[at[1]], real[at[2]]).max()) if 1 in at and 2 in at
                else 0.0)
        made = periodic_patches(real)
        return {f: made[i] for f, i in at.items()}, bound, side

    def samples(self, t, lam, which):
        """(len(which), texels, texels) float32: the `which` fields (indices into FIELDS) at
        time t, the tile's samples, row y, column x of its turned lattice (one batched inverse
        transform)."""
        turns = self.omega * (t / (2.0 * np.pi))  # in float64: t may be large
        turns -= np.floor(turns)
        angle = (2.0 * np.pi) * turns.astype(np.float32)  # float32 sines are many times faster
        phase = np.empty(angle.shape, np.complex64)
        phase.real = np.cos(angle)
        phase.imag = -np.sin(angle)
        h = self._h0 * phase
        h += self._h0_neg_conj * np.conj(phase)
        spectra = np.empty((len(which),) + h.shape, np.complex64)
        for i, f in enumerate(which):
            if f:
                np.multiply(h, self._factor(f, lam), out=spectra[i])
            else:
                spectra[i] = h
        return np.fft.irfft2(spectra, s=(self.texels, self.texels), norm="forward")


class SpectralField:
    """A sea from its spectrum, sampled at world points: heights and choppy displacements.

    `bound` and `horizontal_bound` are true bounds of what is sampled at the time last
    `prepare`d (bilinear samples never exceed their tile's extremes).
    """

    def __init__(self, state, choppiness=0.0, seed=0, texels=TEXELS):
        self.state = state
        self.choppiness = non_negative("choppiness", choppiness)
        self.seed = integer("seed", seed, 0, 2**63)
        self.texels = integer("texels", texels, 8, 1024)
        if self.texels & (self.texels - 1):
            raise ValueError(f"texels: must be a power of two, got {self.texels}")
        self.cascades, self.groups = [], []  # groups: (level, along, tiles) per band
        swell = has_swell_core(state)
        shares = band_shares(state)
        for b, ((shortest, longest), share) in enumerate(zip(
                [*bands(), swell_core_waves(state)], shares, strict=True)):
            if share < 1e-7:
                continue
            core = b == BANDS
            count = int(np.clip(np.ceil(share / SHARE_PER_TILE), 1, len(TILE_RATIOS)))
            # A band holding much of the sea gets larger tiles: fewer repeats in view.
            texels = self.texels * (BIG if share > SHARE_PER_TILE else 1)
            base = texels * shortest / SAMPLES_PER_WAVE  # the shortest wave's samples
            part = ("swell core" if core else "without swell core") if swell else None
            first = len(self.cascades)
            for j in range(count):
                # Turned evenly over the quarter turn a square lattice repeats in, so no two
                # tiles' lattices line up (and the crests of a band never run along them all).
                angle = np.radians((90.0 * j / count + 23.0 * b) % 90.0)
                cascade = Cascade(base * TILE_RATIOS[j], angle, shortest, longest, 1.0 / count,
                                  state, tile_phases(self.seed, b, j, texels), texels, part,
                                  smooth=core)
                if not cascade.empty:
                    self.cascades.append(cascade)
            made = self.cascades[first:]
            if not made:
                continue
            if core:  # the band limit of the waves its tiles hold, along their directions
                level = band_level(min(c.shortest_held for c in made))
                off = max(_line_angle(c.headings, state.swell_direction) for c in made)
                along = (np.cos(state.swell_direction), np.sin(state.swell_direction),
                         np.cos(off), np.sin(off))
            else:
                level, along = band_level(shortest), None
            self.groups.append((level, along, range(first, len(self.cascades))))
        # The band limit (band_limit.py) in units of 1 m: a band is kept whole while its shortest
        # wave is at least sqrt(2) * 2 grid spacings long, faded out over the next octave.
        self.wave_scale = 1.0
        self.octaves = BANDS
        # The displacement the tiles hold and the foam looks for: the displayed choppiness, or
        # Tessendorf's lambda = 1 on a sea drawn without it (its crests still break), which
        # `displacement` then does not apply.
        self.fold = self.choppiness if self.choppiness > 0.0 else 1.0
        self.warp = Warp(self.seed)
        self._prepared = None
        # The shader's stand-in noise draws the bands the geometry leaves out, the swell's
        # core with its band (where the geometry drops it, nothing else draws it).
        self._shares = shares[:BANDS]
        if swell:
            self._shares[_band_of(swell_wave(state))] += shares[BANDS]
        self._m0 = spectrum.moments(state)[0]

    foam_span = BAND_LONGEST  # metres across the sea pattern whitecaps are calibrated on

    def twin(self):
        """The same sea for another thread (effects.calibrate_ahead): its cascades, caches
        and calibrations shared (read only but for caches of what is a pure function of the
        settings), its prepared fields its own."""
        other = copy.copy(self)
        other._prepared = None
        other.textures = []
        return other

    @cached_property
    def layer(self):
        """The slopes of the short bands as the shader's normal maps (slope_layer.py)."""
        from .slope_layer import SlopeLayer  # it builds on this module's cascades
        return SlopeLayer(self.state, self.seed)

    @cached_property
    def spread(self):
        """(standard deviation of the height, root mean square of the choppy displacement), m:
        each wave vector's mean power |h0(k)|^2 + |h0(-k)|^2 summed (Parseval), the same at
        every time; the displacement's is lambda times the height's (|k / |k|| = 1) over the
        tiles that are displaced."""
        power = [float(np.sum(c.power())) for c in self.cascades]
        moved = sum(p for p, c in zip(power, self.cascades, strict=True) if 1 in c.gives)
        return float(np.sqrt(sum(power))), float(self.choppiness * np.sqrt(moved))

    def autocorrelation(self, lags, fine=4, samples=256):
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
        for c in self.cascades:
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
            shifts = (self.warp.shifts(part, samples).astype(np.float32) if samples
                      else np.zeros((1,) + part.shape, np.float32))
            for j, (c, (n, acf)) in enumerate(zip(self.cascades, tiles, strict=True)):
                for shift in shifts:
                    points[2:] = shift
                    out[start:start + CHUNK] += Lookup.turned(
                        n, points, (0.0, 0.0), n / c.size, c.turn, "acf",
                        Warp.turn(j)).sample(acf)
        out = out.reshape(lags.shape[1:]) / len(shifts) if flat.shape[1] else out
        return out / self.spread[0] ** 2 if self.cascades else out

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
        """The band limit from which waves of `wavelength` (m) are whole in the geometry: that
        of the band holding them (a band fades in whole), its level + 1."""
        return band_level(bands()[_band_of(wavelength)][0]) + 1.0

    def foam_levels(self):
        """The band limits at which the foam is calibrated: FOAM_STEPS steps over each band's
        fade-in (band_limit.octave_weights: from its level to its level + 1), where the cue's
        spread changes fast; between fades nothing changes, so the thresholds interpolate."""
        steps = np.linspace(0.0, 1.0, FOAM_STEPS + 1)
        levels = sorted({float(level + f) for level in self.levels for f in steps})
        return levels or [0.0]

    def foam_cue(self, xy, t, lod=None, grid=None):
        """Where whitecaps form on the spectral sea: where the surface folds, its Jacobian
        lowest (Jensen and Golias). See `jacobian`."""
        return -self.jacobian(xy, t, lod, grid)

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
        (shading.detail_height; the filtering books them as drawn): as high as the spectrum's
        own (its height, k⁻⁴ under the tail) they drew a sixth of them, the noise's waves longer
        than its cells and the spectrum's slope near each octave's short end. Without them the
        near water, whose every band the geometry holds, had no detail finer than 25 cm and
        looked glassy."""
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
        ripple = _slope_variance(self.state, shortest, top)
        layer_top = bands()[LAYER_FIRST][1]
        return shading.Slopes(
            total=ripple + _slope_variance(self.state, top, 10.0 * BAND_LONGEST),
            density=_slope_variance(self.state, top, 2.0 * top) / np.log(2.0), ripple=ripple,
            ripple_top=top, shortest=shortest, left_out_log=float(np.log(2.0 * self.wave_scale)),
            layer_top=layer_top,
            layer_density=_slope_variance(self.state, layer_top, 2.0 * layer_top) / np.log(2.0))

    def wavelength(self, octave):
        return self.wave_scale / 2.0**octave

    def prepare(self, t, fields=GEOMETRY):
        """The tiles' fields at time t: made once per time, each field when first asked for
        (without choppiness, the displacement only when the foam asks for it)."""
        t = finite("time", t)
        if self._prepared is None or self._prepared[0] != t:
            first = GEOMETRY if self.choppiness > 0.0 else (0,)
            made = each(lambda c: c.fields(t, self.fold, first), self.cascades)
            self.textures = [m[0] for m in made]
            self._bound = sum(m[1] for m in made)
            self._side = sum(m[2] for m in made)
            self._prepared = (t, set(first))
        missing = set(fields) - self._prepared[1]
        if missing:
            made = each(lambda c: c.fields(t, self.fold, missing)[0], self.cascades)
            for textures, more in zip(self.textures, made, strict=True):
                textures.update(more)
            self._prepared[1].update(missing)
        return self

    @property
    def bound(self):
        return self._bound if self._prepared is not None else 0.0

    @property
    def horizontal_bound(self):
        return self._side if self._prepared is not None else 0.0

    def sample(self, xy, t, lod=None, fields=(0,), on_grid=False):
        """The sum over tiles of `fields` (indices into FIELDS) at world points xy (2, ...),
        each band weighted by the band limit (`lod`, as the grid gives it, or None): a
        (len(fields), ...) float64 array. `on_grid`: xy (2, rows, columns) are a grid's
        vertices, neighbours along both axes, so a band long against the spacing is sampled
        on every other row and column and interpolated between (band_limit.COARSE)."""
        self.prepare(t, fields)
        xy = np.asarray(xy, dtype=np.float64)
        shape = xy.shape[1:]
        rows = (1, -1) if len(shape) < 2 else (-1, shape[-1])
        out = np.empty((len(fields),) + shape)
        xy2, out2 = xy.reshape((2,) + rows), out.reshape((len(fields),) + rows)
        lod2 = None if lod is None else np.asarray(lod).reshape(rows)
        on_grid = on_grid and lod2 is not None and len(shape) == 2
        lods = [lod2 if along is None or not on_grid else along_waves(xy2, lod2, level, along)
                for level, along, _ in self.groups]
        step = max(1, CHUNK // out2.shape[-1])
        for start in range(0, out2.shape[1], step):
            band = slice(start, start + step)
            origin = self._origin(xy2[:, band], None if lod2 is None else lod2[band])
            # The offsets from the origin, then the warp there (Lookup.turned reads both).
            points = scratch("points", (4,) + xy2[:, band].shape[1:], np.float32)
            np.subtract(xy2[:, band], origin[:, None, None], out=points[:2],
                        casting="same_kind")
            self.warp(origin, points[:2], out=points[2:])
            sums = scratch("sums", out2[:, band].shape, np.float32)  # summed in single
            sums.fill(0.0)
            self._sum(origin, points, [None if g is None else g[band] for g in lods], fields,
                      sums, on_grid)
            out2[:, band] = sums
        return out

    @staticmethod
    def _origin(xy, lod):
        """Where a chunk's points are taken from in single precision: the point of the finest
        detail (the shortest bands are sampled only near it), or without a band limit the
        middle of the chunk's extent."""
        if lod is None:
            return 0.5 * (xy.min(axis=(1, 2)) + xy.max(axis=(1, 2)))
        i = np.unravel_index(np.argmax(lod), lod.shape)
        return xy[:, i[0], i[1]].copy()

    def _sum(self, origin, points, lods, fields, out, on_grid):
        """Add the bands' `fields` at origin + offsets into `out`, band by band (a band's
        tiles share its level, so its rows and its coarse part; `lods` the band limit for
        each of self.groups), each tile read where the warp there turned by its own turn
        moves the points. `points` (4, rows, columns): the offsets, then the warp."""
        mins = {}
        for (level, _, tiles), lod in zip(self.groups, lods, strict=True):
            if not self.cascades[tiles[0]].gives.intersection(fields):
                continue
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
                for j in tiles:
                    self._add(j, points[:, rows], origin, fields, out[:, rows], weight)
            if coarse is not None:
                few = every_other_of(points[:, coarse], scratch(
                    "few", (4,) + every_other_shape(points[0, coarse].shape), np.float32))
                sums = scratch("coarse", (len(fields),) + few.shape[1:], np.float32)
                sums.fill(0.0)
                for j in tiles:
                    self._add(j, few, origin, fields, sums, None)
                filled = scratch("filled", out[0, coarse].shape, np.float32)
                for i in range(len(fields)):
                    out[i, coarse] += fill_every_other(sums[i], filled)

    def _add(self, j, points, origin, fields, out, weight):
        """Add tile j's `fields` at origin + offsets (moved by its turn of the warp; `points`
        as `_sum`'s) into `out`, times `weight` if given."""
        cascade, textures = self.cascades[j], self.textures[j]
        where = Lookup.turned(cascade.texels, points, origin, cascade.texels / cascade.size,
                              cascade.turn, shift_turn=Warp.turn(j))
        for i, f in enumerate(fields):
            if f not in textures:  # a field the tile does not hold: 0
                continue
            v = where.sample(textures[f])
            if weight is not None:
                v *= weight
            out[i] += v

    def displacement(self, xy, t, lod=None, on_grid=False):
        """(h, (dx, dy) or None) at world points xy (2, ...): the height and, with choppiness,
        the horizontal displacement (`on_grid`: see `sample`)."""
        if self.choppiness == 0.0:
            return self.sample(xy, t, lod, (0,), on_grid)[0], None
        h, dx, dy = self.sample(xy, t, lod, GEOMETRY, on_grid)
        return h, np.stack([dx, dy])

    def heights(self, x, y, t, lod=None):
        x = np.asarray(x, dtype=np.float64)
        return self.sample(np.stack([x, np.broadcast_to(y, x.shape)]), t, lod, (0,))[0]

    def jacobian(self, xy, t, lod=None, grid=None):
        """The choppy surface's Jacobian (1 flat, < 0 folded) as a mesh of it shows it: by
        differences between neighbouring vertices, which see the waves the band limit keeps,
        each wave's slope lessened as the differences over its vertices lessen it.

        `grid` given: xy (2, rows, columns) are a frame's grid points on the sea and `grid` the
        same points displaced (`displacement`; without choppiness, xy itself), and the Jacobian
        is that of the map from one to the other between neighbours (central differences,
        one-sided on the border). Otherwise xy (2, ...) are points apart, and the differences
        are central over the vertex spacing their `lod` stands for (band_limit.lod_for_spacing;
        `lod` None: the spacing at which every band is whole), along x and along y."""
        xy = np.asarray(xy, dtype=np.float64)
        if grid is not None:
            moved = xy + self.sample(xy, t, lod, SIDEWAYS) if self.choppiness == 0.0 else grid
            return _grid_jacobian(xy, moved)
        top = max(self.levels, default=0.0) + 1.0  # every band whole: no finer spacing counts
        level = np.full(xy.shape[1:], top) if lod is None else np.minimum(lod, top)
        step = self.wave_scale * 2.0 ** -level / 2.0  # lod = log2(wave_scale / (2 spacing))
        points = np.repeat(xy[:, None], 4, axis=1)  # (2, 4, ...): +x, -x, +y, -y
        points[0, 0] += step
        points[0, 1] -= step
        points[1, 2] += step
        points[1, 3] -= step
        lods = np.broadcast_to(level.astype(np.float32), points.shape[1:])
        dx, dy = self.sample(points, t, None if lod is None else lods, SIDEWAYS)
        span = 2.0 * step
        ddx_x, ddy_x = (dx[0] - dx[1]) / span, (dy[0] - dy[1]) / span
        ddx_y, ddy_y = (dx[2] - dx[3]) / span, (dy[2] - dy[3]) / span
        return (1.0 + ddx_x) * (1.0 + ddy_y) - ddx_y * ddy_x


def _grid_jacobian(base, moved):
    """det(d moved / d(i, j)) / det(d base / d(i, j)) over a grid: x and y (rows, columns)."""
    d = grid_derivative
    area = d(base[0], 1) * d(base[1], 0) - d(base[0], 0) * d(base[1], 1)
    turned = d(moved[0], 1) * d(moved[1], 0) - d(moved[0], 0) * d(moved[1], 1)
    return np.divide(turned, area, out=np.ones_like(area), where=area != 0.0)
