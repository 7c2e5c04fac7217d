"""Ocean wave spectra: how the sea's energy spreads over wavelengths and directions.

Following Horvath, *Empirical directional wave spectra for computer graphics* (DigiPro 2015):
the non-directional spectrum S(omega) is JONSWAP (Hasselmann et al. 1973) for a wind blowing
over a fetch, whose fully developed limit is Pierson-Moskowitz; Phillips (Tessendorf,
*Simulating Ocean Water*) is kept for parity with Blender's Ocean modifier. The directional
spreading D(omega, theta) is Donelan-Banner's sech^2 (Horvath §5.2.4), narrower near the peak.
A swell is a second, narrow-banded JONSWAP of its own height, period and direction.

Waves obey deep-water dispersion, omega^2 = g k, so a spectrum over (omega, theta) becomes one
over the wave vector k: E(k) = S(omega) D(omega, theta) (d omega / d k) / k.

Every function is vectorised over omega (rad/s) or k (rad/m); directions are radians,
counter-clockwise from +X, the way the waves travel (the wind blows toward `wind_direction`).
"""

from dataclasses import dataclass

import numpy as np

from .validation import finite, non_negative

GRAVITY = 9.81
integrate = getattr(np, "trapezoid", None) or np.trapz  # NumPy 2 renamed it
SPECTRA = ("JONSWAP", "PIERSON_MOSKOWITZ", "PHILLIPS")
GAMMA = 3.3  # JONSWAP peak enhancement
SWELL_GAMMA = 8.0  # a swell's narrow band (Goda's range for swell is 3.3 to 10)
SWELL_SPREAD = 12.0  # Donelan-Banner beta of a swell: most of it within +-15 degrees
# The swell's core, which tiles of its own hold (spectral_field.py): frequencies from 0.85 to
# 1.2 times its peak, directions within 0.15 rad of its own (95 % of its spreading).
SWELL_CORE = (0.85, 1.2)
SWELL_HALF_ANGLE = 0.15


@dataclass(frozen=True)
class SeaState:
    """The wind and swell a spectrum is made from. `fetch` 0 means fully developed."""

    wind_speed: float = 7.0  # m/s at 10 m
    wind_direction: float = 0.0  # rad, where the wind blows toward, CCW from +X
    fetch: float = 0.0  # m
    spectrum: str = "JONSWAP"
    swell_height: float = 0.0  # significant height of the swell, m
    swell_direction: float = 0.0  # rad
    swell_period: float = 10.0  # s

    def __post_init__(self):
        non_negative("wind_speed", self.wind_speed)
        finite("wind_direction", self.wind_direction)
        non_negative("fetch", self.fetch)
        non_negative("swell_height", self.swell_height)
        finite("swell_direction", self.swell_direction)
        if not finite("swell_period", self.swell_period) > 0.0:
            raise ValueError(f"swell_period: must be > 0, got {self.swell_period}")
        if self.spectrum not in SPECTRA:
            raise ValueError(f"spectrum: must be one of {SPECTRA}, got {self.spectrum!r}")

    def fully_developed(self):
        """Whether the wind's sea has reached Pierson-Moskowitz: no fetch given, or a fetch
        beyond the one at which JONSWAP's peak frequency falls to Pierson-Moskowitz's."""
        return self.fetch == 0.0 or self.fetch >= full_fetch(self.wind_speed)


def full_fetch(wind_speed):
    """The fetch (m) at which JONSWAP's sea holds as much energy as the fully developed one:
    its m0 = alpha g^2 I / omega_p^4 grows as F^(4/3 - 0.22), alpha = 0.076 (U^2 / (F g))^0.22
    and omega_p = 22 (g^2 / (U F))^(1/3) (Horvath Eq. 29-30), I the spectrum's shape integral;
    beyond it the sea is Pierson-Moskowitz's (m0 = 8.1e-3 g^2 / (5 omega_p^4))."""
    u = max(float(wind_speed), 1e-6)
    pm = 8.1e-3 / 5.0 / (0.855 * GRAVITY / u) ** 4 * GRAVITY**2
    # m0(F) = c F^(4/3 - 0.22): c from F = 1 m.
    c = 0.076 * (u * u / GRAVITY) ** 0.22 * GRAVITY**2 * _SHAPE / (
        22.0 * (GRAVITY**2 / u) ** (1.0 / 3.0)) ** 4
    return (pm / c) ** (1.0 / (4.0 / 3.0 - 0.22))


def _shape_integral():
    """I = integral of x^-5 exp(-5/4 x^-4) gamma^r(x) dx over x = omega / omega_p."""
    x = np.linspace(0.3, 12.0, 20_000)
    return float(integrate(_jonswap(x, 1.0, 1.0, GAMMA) / GRAVITY**2, x))


def peak_frequency(state):
    """omega_p (rad/s) of the wind's sea: Pierson-Moskowitz 0.855 g / U fully developed,
    JONSWAP 22 (g^2 / (U F))^(1/3) over a fetch (Horvath Eq. 29-31)."""
    u = max(state.wind_speed, 1e-6)
    if state.spectrum == "PIERSON_MOSKOWITZ" or state.fully_developed():
        return 0.855 * GRAVITY / u
    if state.spectrum == "PHILLIPS":
        return 0.855 * GRAVITY / u
    return 22.0 * (GRAVITY**2 / (u * state.fetch)) ** (1.0 / 3.0)


def _jonswap(omega, alpha, omega_p, gamma):
    """S(omega) = alpha g^2 / omega^5 exp(-5/4 (omega_p / omega)^4) gamma^r (Horvath Eq. 28)."""
    omega = np.asarray(omega, dtype=np.float64)
    w = np.maximum(omega, 1e-9)
    sigma = np.where(w <= omega_p, 0.07, 0.09)
    r = np.exp(-((w - omega_p) ** 2) / (2.0 * sigma**2 * omega_p**2))
    s = alpha * GRAVITY**2 / w**5 * np.exp(-1.25 * (omega_p / w) ** 4) * gamma**r
    return np.where(omega > 0.0, s, 0.0)


def wind_spectrum(omega, state):
    """S(omega) (m^2 s / rad) of the wind's sea alone."""
    u = state.wind_speed
    if u <= 0.0:
        return np.zeros_like(np.asarray(omega, dtype=np.float64))
    omega_p = peak_frequency(state)
    if state.spectrum == "PHILLIPS":
        return phillips_omega(omega, u)
    if state.spectrum == "PIERSON_MOSKOWITZ" or state.fully_developed():
        return _jonswap(omega, 8.1e-3, omega_p, 1.0)
    alpha = 0.076 * (u**2 / (state.fetch * GRAVITY)) ** 0.22
    return _jonswap(omega, alpha, omega_p, GAMMA)


def phillips_omega(omega, wind_speed):
    """The Phillips spectrum (Tessendorf Eq. 40) as S(omega): alpha g^2 / omega^5 with the
    large waves cut off at L = U^2 / g, exp(-1 / (k L)^2), alpha the Pierson-Moskowitz 8.1e-3
    so its height is comparable."""
    omega = np.asarray(omega, dtype=np.float64)
    w = np.maximum(omega, 1e-9)
    k = w * w / GRAVITY
    big = max(wind_speed, 1e-6) ** 2 / GRAVITY
    s = 8.1e-3 * GRAVITY**2 / w**5 * np.exp(-1.0 / (k * big) ** 2)
    return np.where(omega > 0.0, s, 0.0)


def swell_spectrum(omega, state):
    """S(omega) of the swell: a narrow JONSWAP peaked at 2 pi / period, scaled so that its
    significant height 4 sqrt(m0) is `swell_height`."""
    if state.swell_height <= 0.0:
        return np.zeros_like(np.asarray(omega, dtype=np.float64))
    omega_p = 2.0 * np.pi / state.swell_period
    shape = _jonswap(omega, 1.0, omega_p, SWELL_GAMMA)
    grid = np.linspace(0.3 * omega_p, 4.0 * omega_p, 4096)
    m0 = integrate(_jonswap(grid, 1.0, omega_p, SWELL_GAMMA), grid)
    return shape * (state.swell_height / 4.0) ** 2 / m0


def donelan_banner(omega, theta, omega_p, beta_scale=None):
    """Donelan-Banner spreading, beta / (2 tanh(beta pi)) sech^2(beta theta), normalised over
    theta in (-pi, pi] (Horvath Eq. 38-39); `theta` from the mean direction. A fixed
    `beta_scale` gives a swell's narrow spreading instead."""
    omega = np.asarray(omega, dtype=np.float64)
    if beta_scale is None:
        ratio = np.clip(omega / omega_p, 1e-3, 1e3)
        high = np.maximum(ratio, 1.6)  # the third branch, where it applies
        eps = -0.4 + 0.8393 * np.exp(-0.567 * np.log(high**2))
        beta = np.where(ratio < 0.95, 2.61 * ratio**1.3,
                        np.where(ratio < 1.6, 2.28 * ratio**-0.65, 10.0**eps))
    else:
        beta = np.full_like(omega, float(beta_scale))
    theta = np.angle(np.exp(1j * np.asarray(theta, dtype=np.float64)))  # into (-pi, pi]
    return beta / (2.0 * np.tanh(beta * np.pi)) / np.cosh(beta * theta) ** 2


def directional(omega, theta, state):
    """S(omega) D(omega, theta): the sea's energy per frequency and direction, wind and swell."""
    energy = _wind_directional(omega, theta, state)
    if state.swell_height > 0.0:
        energy = energy + _swell_directional(omega, theta, state)
    return energy


def _wind_directional(omega, theta, state):
    wind = wind_spectrum(omega, state)
    if state.spectrum == "PHILLIPS":  # Tessendorf's |k.w|^2, normalised over the circle
        return wind * np.cos(theta - state.wind_direction) ** 2 / np.pi
    return wind * donelan_banner(omega, theta - state.wind_direction, peak_frequency(state))


def _swell_directional(omega, theta, state):
    return swell_spectrum(omega, state) * donelan_banner(
        omega, theta - state.swell_direction, None, SWELL_SPREAD)


def wavenumber_spectrum(kx, ky, state, part=None):
    """E(k) (m^4): the energy per unit wave-vector area, so that the height variance is the
    integral of E over the k plane. omega = sqrt(g k), d omega / d k = g / (2 omega).
    `part` "swell core": only the swell's core (`in_swell_core`); "without swell core": the
    rest; None: all of it."""
    k = np.hypot(kx, ky)
    kk = np.maximum(k, 1e-12)
    omega = np.sqrt(GRAVITY * kk)
    theta = np.arctan2(ky, kx)
    if part is None:
        e = directional(omega, theta, state)
    else:
        swell = _swell_directional(omega, theta, state)
        core = np.where(in_swell_core(omega, theta, state), swell, 0.0)
        e = core if part == "swell core" else (
            _wind_directional(omega, theta, state) + (swell - core))
    e = e * (GRAVITY / (2.0 * omega)) / kk
    return np.where(k > 0.0, e, 0.0)


def in_swell_core(omega, theta, state):
    """Whether (omega, theta) lies in the swell's core: SWELL_CORE times its peak frequency,
    within SWELL_HALF_ANGLE of its direction (never, without a swell)."""
    if state.swell_height <= 0.0:
        return np.zeros(np.broadcast(omega, theta).shape, bool)
    off = np.abs(np.angle(np.exp(1j * (np.asarray(theta) - state.swell_direction))))
    return _core_frequencies(omega, state) & (off <= SWELL_HALF_ANGLE)


def _core_frequencies(omega, state):
    """Whether `omega` lies within SWELL_CORE times the swell's peak frequency."""
    ratio = np.asarray(omega, dtype=np.float64) * (state.swell_period / (2.0 * np.pi))
    return (ratio >= SWELL_CORE[0]) & (ratio < SWELL_CORE[1])


def swell_core_spectrum(omega, state):
    """S(omega) of the swell's core (`in_swell_core`) over all its directions: the swell's
    within SWELL_CORE times the share of its spreading within SWELL_HALF_ANGLE,
    tanh(beta a) / tanh(beta pi)."""
    share = np.tanh(SWELL_SPREAD * SWELL_HALF_ANGLE) / np.tanh(SWELL_SPREAD * np.pi)
    return np.where(_core_frequencies(omega, state), swell_spectrum(omega, state) * share, 0.0)


def moments(state, n=(0,), samples=20_000):
    """Spectral moments m_n = integral of omega^n S(omega) d omega (wind and swell)."""
    omega_p = peak_frequency(state)
    lo = 0.05 * min(omega_p, 2.0 * np.pi / state.swell_period)
    hi = 30.0 * max(omega_p, 2.0 * np.pi / state.swell_period)
    w = np.geomspace(lo, hi, samples)
    s = wind_spectrum(w, state) + swell_spectrum(w, state)
    return [float(integrate(w**p * s, w)) for p in n]


def significant_height(state):
    """Hs = 4 sqrt(m0) (m)."""
    return 4.0 * np.sqrt(moments(state)[0])


def peak_period(state):
    """Tp = 2 pi / omega_p (s) of the wind's sea."""
    return 2.0 * np.pi / peak_frequency(state)


def peak_wavelength(state):
    """The deep-water wavelength 2 pi g / omega_p^2 (m) of the wind's sea's peak."""
    return 2.0 * np.pi * GRAVITY / peak_frequency(state) ** 2


_SHAPE = _shape_integral()
