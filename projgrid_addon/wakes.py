"""Wakes: the waves a moving hull makes, a pure function of its path over the past WINDOW
seconds (Kelvin's ship waves from linear deep-water theory, no state carried between frames).

A hull of draft D presses on the water as a Gaussian pressure patch, p(r) = rho g D
exp(-r^2 / (2 sigma^2)), sigma a quarter of its length. Moving, it is a train of impulses
p dtau laid down along its path; each spreads as the Cauchy-Poisson ring of deep water,

    G(r, s) = -g D sigma^2 Int_0^inf (k^2 / omega) e^(-k^2 sigma^2 / 2) sin(omega s) J0(k r) dk,

omega^2 = g k (an impulse's potential -p/rho, then eta'' = -g k eta per wave), and the wake is
their sum, eta(x, t) = Sum_i G(|x - p(tau_i)|, t - tau_i) dtau over emissions on an absolute
time lattice (tapered out at the window's end, so the sum moves continuously with t). It
holds what a wake is made of: at rest it is the hydrostatic dent -D exp(-r^2/2 sigma^2);
moving at U, Kelvin's transverse waves of length 2 pi U^2 / g behind it, the divergent waves,
and the cusp line at 19.47 degrees from the track, which narrows once the hull, too long to
make the short waves the cusp needs, moves fast (Rabaud and Moisy 2013: about 0.2 / Fr rad
above a Froude number U / sqrt(g L) of 0.6). G is tabulated once per (sigma, reach) and read
bilinearly."""

from functools import lru_cache

import numpy as np

from .spectrum import GRAVITY
from .tiles import bilinear

WINDOW = 40.0  # s of past path a wake sums
TAPER = 0.25  # of the window: the oldest emissions fade out over it
K_CUT = 5.0  # the pressure's spectrum is left out beyond k sigma = K_CUT (e^-12.5)
CHUNK = 4096  # points summed at once
STEP = 0.2  # s between emissions at most


def j0(x):
    """Bessel J0 (Abramowitz and Stegun 9.4.1 and 9.4.3, |error| < 5e-8 and 1.6e-8)."""
    x = np.abs(np.asarray(x, dtype=np.float64))
    out = np.empty_like(x)
    small = x <= 3.0
    y = (x[small] / 3.0) ** 2
    out[small] = 1.0 + y * (-2.2499997 + y * (1.2656208 + y * (-0.3163866 + y * (
        0.0444479 + y * (-0.0039444 + y * 0.0002100)))))
    big = ~small
    z = 3.0 / x[big]
    f0 = 0.79788456 + z * (-0.00000077 + z * (-0.00552740 + z * (-0.00009512 + z * (
        0.00137237 + z * (-0.00072805 + z * 0.00014476)))))
    theta = x[big] - 0.78539816 + z * (-0.04166397 + z * (-0.00003954 + z * (
        0.00262573 + z * (-0.00054125 + z * (-0.00029333 + z * 0.00013558)))))
    out[big] = f0 * np.cos(theta) / np.sqrt(x[big])
    return out


@lru_cache(maxsize=8)
def response(sigma, reach, window=WINDOW):
    """(G, dr, ds): the ring G(r, s) of a unit-draft impulse (m/s per m of draft) on a table
    of r = 0, dr, ..., reach (m) and s = 0, ds, ..., window (s), by quadrature in omega
    (k = omega^2 / g: the integrand 2 omega^4 / g^3 e^(...) sin(omega s) J0(k r) d omega)."""
    w_max = np.sqrt(GRAVITY * K_CUT / sigma)
    dr = sigma / 5.0  # the shortest wave kept, 2 pi sigma / K_CUT, over 6 samples
    ds = min(0.1, 0.25 * 2.0 * np.pi / w_max)
    # in omega, J0(omega^2 r / g) turns fastest at the table's reach: 4 steps a turn there
    dw = min(np.pi / (4.0 * window), np.pi * GRAVITY / (4.0 * w_max * reach))
    w = np.arange(0.5, int(w_max / dw) + 0.5) * dw
    k = w * w / GRAVITY
    weight = 2.0 * w**4 / GRAVITY**3 * np.exp(-0.5 * (k * sigma) ** 2) * dw
    r = np.arange(0.0, reach + dr, dr)
    s = np.arange(0.0, window + ds, ds)
    table = np.empty((len(s), len(r)), np.float32)
    for start in range(0, len(r), 256):  # J0 a block of r at a time (memory)
        block = j0(np.multiply.outer(k, r[start:start + 256])) * weight[:, None]
        table[:, start:start + 256] = np.sin(np.multiply.outer(s, w)) @ block
    return -GRAVITY * sigma**2 * table, float(dr), float(ds)


def emissions(t, step, window=WINDOW):
    """The emission times tau_i (a lattice `step` apart, the newest not after t) within the
    window, and each one's weight dtau times the taper (1, falling to 0 over the oldest TAPER
    of the window)."""
    newest = np.floor(t / step)
    taus = (newest - np.arange(int(window / step))) * step
    age = t - taus
    taper = np.clip((window - age) / (TAPER * window), 0.0, 1.0)
    return taus, taper * step


def wake_heights(xy, t, path, draft, length, window=WINDOW):
    """The wake's heights (m) at world points xy (2, ...) at time t of a hull of `draft` and
    `length` (m) whose path is `path(taus)` -> (2, n) positions at past times (the scene's
    animation evaluated there). About 12 microseconds a point (20,000 in 0.25 s): not yet
    for every vertex of every frame."""
    sigma, taus, weights, at = _emitted(path, t, length, window)
    xy = np.asarray(xy, dtype=np.float64)
    flat = xy.reshape(2, -1)
    lo, hi = flat.min(axis=1, initial=0.0), flat.max(axis=1, initial=0.0)
    reach = float(np.hypot(*np.maximum(np.abs(hi[:, None] - at), np.abs(lo[:, None] - at))).max())
    table, dr, ds = response(sigma, float(np.ceil(reach / 50.0) * 50.0), window)
    out = np.empty(flat.shape[1])
    age = (t - taus) / ds
    for start in range(0, flat.shape[1], CHUNK):  # (points, emissions) a chunk at a time
        p = flat[:, start:start + CHUNK, None]
        d = np.hypot(p[0] - at[0], p[1] - at[1]) / dr
        out[start:start + CHUNK] = (bilinear(table, d, age) * weights).sum(axis=-1)
    return draft * out.reshape(xy.shape[1:])


def raster_heights(xs, ys, t, path, draft, length, window=WINDOW, extent=None):
    """The wake's heights on the raster of points (xs[j], ys[i]) -> (len(ys), len(xs))
    float32, as `wake_heights` gives them, an emission at a time: each ring is a row of the
    table at its age, read linearly in r (8 ns a point and emission, against 60 for
    `wake_heights`' reads in r and s at once). `extent`: the (reach, window) of the response
    table to read (one shared by several rasters), at least what this one needs."""
    sigma, taus, weights, at = _emitted(path, t, length, window)
    xs, ys = np.asarray(xs, dtype=np.float64), np.asarray(ys, dtype=np.float64)
    reach = float(np.hypot(np.maximum(np.abs(xs.max() - at[0]), np.abs(xs.min() - at[0])),
                           np.maximum(np.abs(ys.max() - at[1]), np.abs(ys.min() - at[1]))).max())
    reach, span = extent or (float(np.ceil(reach / 50.0) * 50.0), window)
    table, dr, ds = response(sigma, reach, span)
    age = (t - taus) / ds
    row = np.minimum(age.astype(np.intp), table.shape[0] - 2)
    part = (age - row)[:, None]
    rows = ((table[row] * (1.0 - part) + table[row + 1] * part) * weights[:, None]).astype(
        np.float32)
    steps = np.diff(rows, axis=1, append=np.float32(0.0))
    out = np.zeros((len(ys), len(xs)), np.float32)
    last = rows.shape[1] - 2
    for e in range(len(taus)):
        dx = ((xs - at[0, e]) / dr).astype(np.float32)
        dy = ((ys - at[1, e]) / dr).astype(np.float32)
        d = np.sqrt(dy[:, None] * dy[:, None] + dx * dx)
        i = np.minimum(d.astype(np.intp), last)
        d -= i
        out += rows[e][i] + d * steps[e][i]
    return out * np.float32(draft)


def _emitted(path, t, length, window):
    """(sigma, taus, weights, at): a hull of `length`'s pressure patch, its emission times
    and weights within the window, and where its `path` put it then. Successive rings'
    phases close (half a sigma apart along the path): from a lattice of STEP s halved per
    octave of speed, nested, so a speed change shifts no emission."""
    sigma = max(float(length), 0.1) / 4.0
    need = 0.5 * sigma / max(_speed(path, t), 0.5)
    taus, weights = emissions(t, STEP / 2.0 ** max(np.ceil(np.log2(STEP / need)), 0.0), window)
    return sigma, taus, weights, path(taus)


def _speed(path, t, dt=0.5):
    """The hull's speed (m/s) over the last `dt` s of its path."""
    a, b = path(np.array([t - dt, t])).T
    return float(np.hypot(*(b - a)) / dt)
