"""The spectral sea's bands and tiles (Tessendorf, *Simulating Ocean Water*): the band layout,
each tile's random phases, and a cascade, one tile's band of the spectrum made by an FFT.

The wavelengths are cut into bands a factor BAND_RATIO apart, from BAND_LONGEST down to a few
tens of centimetres, and each band is synthesised in periodic tiles of TEXELS^2 samples sized so
that its shortest wave spans 8 to 10 samples. No band is counted twice: a tile holds only its
band's wave vectors (`Cascade`).

    h(k, t) = h0(k) e^(-i omega t) + conj(h0(-k)) e^(i omega t),   omega^2 = g |k|
    h0(k)   = e^(i phi_k) sqrt(E(k) dk^2 / 2)                        (phi_k: a random phase)

so each wave travels along its k at its own phase speed and the height variance is the integral
of E (spectrum.wavenumber_spectrum). The phases come from (seed, band, tile) alone.
"""

from dataclasses import replace
from functools import lru_cache

import numpy as np

from . import spectrum
from .tiles import periodic_patches

TEXELS = 64  # samples across a tile
BAND_LONGEST = 1300.0  # m: the longest waves synthesised (a storm's peak is about 600 m)
BAND_RATIO = 4.17  # each band's longest wave over its shortest
BANDS = 6  # down to BAND_LONGEST / 4.17^6, 0.25 m: shorter waves are the shader's
SAMPLES_PER_WAVE = 8.0  # over a tile's shortest wave: bilinear sampling keeps 95 % of it
# A band's tiles are its base size times these: not multiples of each other, and at most 1.28
# times larger, so the shortest wave still spans 8 / 1.28 = 6.25 samples.
TILE_RATIOS = (1.0, 1.0833, 1.1614, 1.2369, 1.1197, 1.0431, 1.2041, 1.2795)
LAYER_FIRST = 3  # the bands from this one on are the slope layer's too (slope_layer.py)
# Where over a band's fade-in the foam is calibrated (foam_levels), as fractions of it: closer
# at its start, where the cue's spread changes fastest.
FOAM_STEPS = (0.0, 0.125, 0.25, 0.5, 1.0)
SHARE_PER_TILE = 0.12  # the most of the sea's height variance one tile may hold
BIG = 2  # how many times more texels (and metres) a band holding more than that has
# Fields a tile can give: the height, the choppy displacement along x and y, and the height's
# slopes along x and y (slope_layer.py).
FIELDS = ("h", "dx", "dy", "sx", "sy")
# ln(m/s): a keyed wind's sea is made at winds this far apart in log wind (5 %), its frames'
# interpolated between (`wind_lattice`); its whitecaps are calibrated alike (foam.py).
WIND_LATTICE = 0.05
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


def band_shares(state, halves=False):
    """Each band's share of the sea's height variance (`halves`: each band's long half's and
    then its short half's, `pieces`), and last the swell's core's (spectrum.in_swell_core: its
    own tiles). The waves longer than BAND_LONGEST count with the first band, the shorter than
    the last band's with none."""
    ends = [lo for band in bands() for lo, _ in (pieces(*band) if halves else [band])]
    omega = np.sqrt(spectrum.GRAVITY * np.array([0.0, *(2.0 * np.pi / np.array(ends))]))
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


def pieces(shortest, longest):
    """A band's halves, (shortest, longest) each, the long first: cut at its geometric middle,
    so the long half is whole in the geometry an octave of grid spacing further."""
    middle = float(np.sqrt(shortest * longest))
    return [(middle, longest), (shortest, middle)]


def has_swell_core(state):
    """Whether the swell's core has tiles of its own: a swell longer than the slope layer's
    bands (slope_layer.py: their tiles hold the whole spectrum; a swell of a few seconds stays
    in the bands)."""
    return state.swell_height > 0.0 and swell_core_waves(state)[0] >= bands()[LAYER_FIRST][1]


def band_of(wavelength):
    """The index of the band holding `wavelength` (m); the first for longer waves."""
    return min(sum(lo > wavelength for lo, _ in bands()), BANDS - 1)


def swell_core_waves(state):
    """(shortest, longest) wavelength (m) of the swell's core."""
    return tuple(swell_wave(state, f) for f in reversed(spectrum.SWELL_CORE))


def swell_wave(state, f=1.0):
    """The wavelength (m) of `f` times the swell's peak frequency: 2 pi g / omega^2."""
    return 2.0 * np.pi * spectrum.GRAVITY / (f * 2.0 * np.pi / state.swell_period) ** 2


def slope_variance(state, shortest, longest, samples=4000):
    """The spectrum's slope variance over wavelengths `shortest` to `longest` (m): the
    integral of k^2 S(omega) d omega, k = omega^2 / g."""
    w = np.geomspace(np.sqrt(2.0 * np.pi * spectrum.GRAVITY / longest),
                     np.sqrt(2.0 * np.pi * spectrum.GRAVITY / shortest), samples)
    k = w * w / spectrum.GRAVITY
    s = spectrum.wind_spectrum(w, state) + spectrum.swell_spectrum(w, state)
    return float(spectrum.integrate(k * k * s, w))


def line_angle(headings, direction):
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


def wind_lattice(wind_speed):
    """((wind, weight), ...): the winds about `wind_speed` of a lattice WIND_LATTICE apart in
    log wind, weighted linearly in log wind (those of weight 0 left out)."""
    x = np.log(max(float(wind_speed), 1e-6)) / WIND_LATTICE
    if abs(x - round(x)) < 1e-9:  # a lattice wind (its log a rounding away): that wind alone
        x = float(round(x))
    k = np.floor(x)
    return tuple((float(np.exp(step * WIND_LATTICE)), float(weight))
                 for step, weight in ((k, 1.0 - (x - k)), (k + 1.0, x - k)) if weight > 0.0)


@lru_cache(maxsize=512)  # a lattice wind's tiles: 30-40 of them
def _cell_waves(size, angle, shortest, longest, state, texels, part):
    """(amplitude, held) of a tile's wave vectors: the square root of `_cell_energy` (the whole
    lattice) and which of the half lattice's wave vectors hold a wave (theirs or their
    mirror's). Kept: a keyed wind's frames share the lattice winds', so a frame only weights
    them (`Cascade`)."""
    energy = _cell_energy(size, angle, shortest, longest, state, texels, part)
    _, _, neg = _lattice(texels)
    held = ((energy > 0.0) | (energy[neg][:, neg] > 0.0))[:, :texels // 2 + 1]
    amplitude = np.sqrt(energy)
    for a in (amplitude, held):
        a.setflags(write=False)
    return amplitude, held


def _cell_energy(size, angle, shortest, longest, state, texels, part):
    """Sixteen times each lattice wave vector's energy (spectrum.wavenumber_spectrum of `part`)
    in a tile `size` m across turned by `angle`, within the band: the sum over its lattice
    cell (4 x 4 samples) of the spectrum inside the band, so neighbouring bands share the k
    plane exactly and the sum over the lattice is the spectrum's integral even where the
    lattice is coarse against the peak and the spreading. The spectrum is evaluated only
    inside the band's ring (a tenth of the lattice)."""
    nx, ny, _ = _lattice(texels)
    lo, hi = size / longest, size / shortest  # band edges in lattice units
    sub = (np.arange(4) + 0.5) / 4.0 - 0.5
    energy = np.zeros(nx.shape)
    for a in sub:
        for b in sub:
            n = np.hypot(nx + a, ny + b)
            inside = (n >= lo) & (n < hi)
            energy[inside] += spectrum.wavenumber_spectrum(
                *_on_sea(nx[inside] + a, ny[inside] + b, size, angle), state, part)
    return energy


@lru_cache(maxsize=512)
def _wave_vectors(size, angle, texels):
    """(kx, ky, |k|, omega, ux, uy) of the half lattice (nx >= 0) of a tile `size` m across
    turned by `angle`: the same at every wind (kept)."""
    nx, ny, _ = _lattice(texels)
    half = slice(0, texels // 2 + 1)
    kx, ky = _on_sea(nx[:, half], ny[:, half], size, angle)
    k = np.hypot(kx, ky)
    safe = np.where(k > 0.0, k, 1.0)
    out = (kx, ky, k, np.sqrt(spectrum.GRAVITY * k), kx / safe, ky / safe)
    for a in out:
        a.setflags(write=False)
    return out


def _on_sea(ax, ay, size, angle):
    """The wave vectors (kx, ky) on the sea of lattice points (ax, ay) of a tile `size` m
    across turned by `angle`."""
    dk, c, s = 2.0 * np.pi / size, np.cos(angle), np.sin(angle)
    return (c * ax - s * ay) * dk, (s * ax + c * ay) * dk


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
                 part=None, smooth=False, keyed=False):
        """`keyed`: the state's wind is a keyed wind's, its waves' amplitudes interpolated
        between the lattice winds' about it (`wind_lattice`)."""
        self.size, self.shortest = float(size), float(shortest)
        self.texels = texels
        self.turn = (np.cos(angle), np.sin(angle))
        _, _, neg = _lattice(texels)
        dk = 2.0 * np.pi / self.size
        cell = (self.size, float(angle), float(shortest), float(longest))
        # keyed: the amplitudes interpolated between the lattice winds' (the waves are, their
        # phases shared), each a kept array, so a frame's sea only weights them
        winds = wind_lattice(state.wind_speed) if keyed else ((state.wind_speed, 1.0),)
        waves = [(weight, _cell_waves(*cell, replace(state, wind_speed=wind) if keyed
                                      else state, texels, part)) for wind, weight in winds]
        amplitude = sum(weight * a for weight, (a, _) in waves) if len(waves) > 1 else (
            waves[0][1][0])
        held = np.logical_or.reduce([h for _, (_, h) in waves])
        # The tiles are synthesised in single precision: the vertices are float32 anyway, and
        # the transforms and the patches move half the bytes.
        self.h0 = (phases * (amplitude * (np.sqrt(0.5 * share / 16.0) * dk))).astype(
            np.complex64)
        self.h0_neg_conj = np.conj(self.h0[neg][:, neg])
        # The fields are real, their spectra Hermitian: each is made from the half of the
        # lattice with nx >= 0 by a real inverse transform (no band reaches the Nyquist row).
        half = slice(0, texels // 2 + 1)
        self._h0, self._h0_neg_conj = self.h0[:, half], self.h0_neg_conj[:, half]
        self.kx, self.ky, k, self.omega, self.ux, self.uy = _wave_vectors(
            self.size, float(angle), texels)
        self.empty = not held.any()
        self.gives = frozenset(range(len(FIELDS))) - (set(SIDEWAYS) if smooth else set())
        # The waves it holds, each wave vector of the half lattice standing for k and -k.
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
        return power * np.r_[1.0, np.full(power.shape[1] - 2, 2.0), 1.0]

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


def layout_shares(state, wind_span=None, halves=False):
    """The band shares (`band_shares`) a layout is made for: `state`'s, or over a `wind_span`
    (least, most m/s; widened to the state's own wind) the most each band takes at any wind
    in it (sampled every 0.25 m/s and at its ends), so one layout serves a wind keyframed
    through the span."""
    if wind_span is None:
        return band_shares(state, halves)
    u = float(state.wind_speed)
    lo, hi = min(*wind_span, u), max(*wind_span, u)
    return list(_span_shares(replace(state, wind_speed=float(lo)), float(hi), halves))


@lru_cache(maxsize=16)
def _span_shares(state, most, halves):
    """`layout_shares` from `state`'s wind up to `most` (kept: every frame of the shot asks)."""
    winds = np.linspace(state.wind_speed, most, int((most - state.wind_speed) / 0.25) + 2)
    return tuple(np.max([band_shares(replace(state, wind_speed=float(u)), halves)
                         for u in winds], axis=0))


def _count(share):
    """How many tiles a `share` of the sea's variance is spread over (SHARE_PER_TILE each)."""
    return int(np.clip(np.ceil(share / SHARE_PER_TILE), 1, len(TILE_RATIOS)))


def layout(state, seed, texels_base, wind_span=None):
    """The tiles of a sea: (cascades, groups), groups (band limit, swell heading or None,
    range of its cascades) per band. Each band's share of the variance (`layout_shares`: over
    a keyframed wind's span) is spread over ceil(share / SHARE_PER_TILE) tiles of sizes
    TILE_RATIOS apart, turned evenly over a quarter turn, with phases of their own, and their
    energy is the state's (under a keyed wind, interpolated: Cascade); the swell's core (the
    last group) is band-limited along its headings. A band longer than the slope layer's
    that needs several tiles (most of the sea's height) is laid out as its halves (`pieces`),
    a group each, the band's tiles shared so the busiest holds the least: where the grid
    drops the short half (a few hundred metres from a low camera) the long half stays, so the
    far sea keeps its height to twice the distance, at no more tiles."""
    cascades, groups, swell = [], [], has_swell_core(state)
    shares, halves = (layout_shares(state, wind_span, halves) for halves in (False, True))
    for b, ((shortest, longest), share) in enumerate(zip(
            [*bands(), swell_core_waves(state)], shares, strict=True)):
        if share < 1e-7:
            continue
        core = b == BANDS
        count = _count(share)
        parts = [((shortest, longest), share, count, False)]
        if not core and b < LAYER_FIRST and count > 1:  # split, the busiest tile the least
            two, n = halves[2 * b:2 * b + 2], np.arange(1, count)
            long = int(n[np.argmin(np.maximum(two[0] / n, two[1] / (count - n)))])
            parts = zip(pieces(shortest, longest), two, (long, count - long), (True, False),
                        strict=True)
        for (lo, hi), part, n, long_half in parts:
            group = _group(state, seed, texels_base, wind_span, swell, b, lo, hi, part, n,
                           long_half)
            if group is not None:
                groups.append((*group[0], range(len(cascades), len(cascades) + len(group[1]))))
                cascades.extend(group[1])
    return cascades, groups


def _group(state, seed, texels_base, wind_span, swell, b, shortest, longest, share, count,
           long_half):
    """((band limit, heading), tiles) of band b's waves from `shortest` to `longest` (m) with
    `share` of the variance over `count` tiles (`long_half`: they are the band's long half),
    or None if no tile holds a wave."""
    core = b == BANDS
    # A band holding much of the sea gets larger tiles: fewer repeats in view.
    texels = texels_base * (BIG if share > SHARE_PER_TILE else 1)
    base = texels * shortest / SAMPLES_PER_WAVE  # the shortest wave's samples
    part = ("swell core" if core else "without swell core") if swell else None
    made = []
    for j in range(count):
        # Turned evenly over the quarter turn a square lattice repeats in, so no two tiles'
        # lattices line up (and the crests of a band never run along them all); a long half
        # turned half a step from its short half.
        angle = np.radians((90.0 * (j + 0.5 * long_half) / count + 23.0 * b) % 90.0)
        cascade = Cascade(base * TILE_RATIOS[j], angle, shortest, longest, 1.0 / count, state,
                          tile_phases(seed, b, j + len(TILE_RATIOS) * long_half, texels),
                          texels, part, smooth=core, keyed=wind_span is not None)
        if not cascade.empty:
            made.append(cascade)
    if not made:
        return None
    if core:  # the band limit of the waves its tiles hold, along their directions
        off = max(line_angle(c.headings, state.swell_direction) for c in made)
        return (band_level(min(c.shortest_held for c in made)),
                (np.cos(state.swell_direction), np.sin(state.swell_direction),
                 np.cos(off), np.sin(off))), made
    return (band_level(shortest), None), made
