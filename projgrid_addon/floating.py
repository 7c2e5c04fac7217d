"""Floating objects: how a hull rides the sea, a pure function of the sea, the time and where
the hull is (its course is the scene's own animation).

A rigid hull on long waves follows the water it displaces (the Froude-Krylov approximation:
the wave's pressure integrated over the hull, no diffraction or radiation). Over a waterline
footprint of length L its heave follows the surface's mean there and its pitch and roll the
plane fitted to it: for a long-crested wave of amplitude a and wavenumber k along L, with
u = k L / 2,

    heave = a sin(u) / u,        slope = a k 3 (sin(u) - u cos(u)) / u^3,

so waves much shorter than the hull average out (a 100 m hull barely heaves in a 10 m chop)
and waves much longer are followed (a 1 m buoy rides them: both tend to a and a k). The
footprint is sampled at the midpoints of SAMPLES x SAMPLES cells (the midpoint rule: up to 2.5
wavelengths long its heave and slope are within 2 % of the formulas'), with the waves shorter
than a few cells left out (the band limit, band_limit.py), which over a footprint average to
nearly nothing. The surface is the displaced one the mesh shows: a choppy sea carries the
water at p to p + D(p), so the height over a world point x is h(p) where p + D(p) = x
(`water_under`).

How deep the hull sits (Archimedes): a hull of volume V and density rho over a waterline
area A sinks until it displaces its mass, V rho / RHO_WATER, to a draft of that over A (a
prism's; a boat's finer hull sits a little deeper)."""

from dataclasses import dataclass

import numpy as np

from . import wake_field
from .band_limit import lod_for_spacing

SAMPLES = 9  # midpoints each way over the footprint
RHO_WATER = 1025.0  # kg/m^3: sea water
CHOP_ITERATIONS = 4  # fixed-point steps finding the water under a point on a choppy sea


def footprint(centre, heading, length, beam, samples=SAMPLES):
    """(2, samples^2) world (x, y) of the midpoints of samples x samples cells over the
    waterline rectangle `length` along `heading` (rad from +x) and `beam` across, about
    `centre` (x, y); and the points' (along, across) offsets from the centre (2, samples^2)."""
    cells = (np.arange(samples) + 0.5) / samples - 0.5
    along, across = (a.ravel() for a in np.meshgrid(cells * length, cells * beam))
    c, s = np.cos(heading), np.sin(heading)
    xy = np.stack([centre[0] + c * along - s * across, centre[1] + s * along + c * across])
    return xy, np.stack([along, across])


def water_under(source, xy, t, lod=None):
    """(p, h): where the water over world points xy (2, ...) came from and the displaced
    surface's height there at time t: p + D(p) = xy, found by fixed-point steps
    p <- xy - D(p) (they converge where the surface does not fold, its Jacobian positive)."""
    p = np.asarray(xy, dtype=np.float64)
    h, d = source.displacement(p, t, lod)
    for _ in range(CHOP_ITERATIONS if d is not None else 0):
        p = xy - d
        h, d = source.displacement(p, t, lod)
    return p, h


def ride(source, t, centre, heading, length, beam, samples=SAMPLES):
    """(heave, slopes): the mean height of the displaced surface over the footprint (m) and
    the slopes (along, across the heading) of the plane fitted to it by least squares."""
    return rides(source, t, [(centre, heading, length, beam)], samples)[0]


def rides(source, t, hulls, samples=SAMPLES, wakes=()):
    """`ride` of each of `hulls` ((centre, heading, length, beam) each), their footprints'
    water found at once (one sampling of the sea for all: a call costs the same for 81
    points as for a thousand), with the heights of `wakes` ((wake_field.Course, the index of
    the hull that makes it or None) each; read once for every footprint) added but a hull's
    own."""
    points, offsets, lods = [], [], []
    for centre, heading, length, beam in hulls:
        length, beam = max(float(length), 1e-3), max(float(beam), 1e-3)
        xy, offset = footprint(centre, heading, length, beam, samples)
        points.append(xy)
        offsets.append(offset)
        lods.append(np.full(xy.shape[1:], lod_for_spacing(source.wave_scale,
                                                          max(length, beam) / samples)))
    if not points:
        return []
    every = np.concatenate(points, axis=1)
    _, h = water_under(source, every, t, np.concatenate(lods))
    n = samples * samples
    if wakes:
        h = h.copy()  # the wakes are added in place
    for course, own in wakes:
        riders = np.ones(every.shape[1], dtype=bool)
        if own is not None:
            riders[own * n:(own + 1) * n] = False
        if riders.any():
            h[riders] += wake_field.heights(course, every[:, riders]).ravel()
    out = []
    for k, offset in enumerate(offsets):
        here = h[k * n:(k + 1) * n]
        # The offsets are centred and the lattice symmetric: the fit's terms are independent.
        out.append((float(here.mean()), tuple(float((o @ here) / (o @ o)) for o in offset)))
    return out


def tilt(slopes, heading, response=1.0):
    """The world rotation (3 x 3) turning a hull level on calm water onto the plane of
    `slopes` (along, across its `heading`), its angle scaled by `response`: about the
    horizontal axis z x n, n the plane's upward normal."""
    along, across = slopes
    c, s = np.cos(heading), np.sin(heading)
    gx, gy = c * along - s * across, s * along + c * across  # the plane's world gradient
    n = np.array([-gx, -gy, 1.0]) / np.sqrt(1.0 + gx * gx + gy * gy)
    axis = np.array([-n[1], n[0], 0.0])  # z x n
    sin = np.linalg.norm(axis)
    if sin < 1e-12:
        return np.eye(3)
    axis /= sin
    angle = response * np.arctan2(sin, n[2])
    k = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]],
                  [-axis[1], axis[0], 0.0]])
    return np.eye(3) + np.sin(angle) * k + (1.0 - np.cos(angle)) * (k @ k)


def draft(density, volume, area):
    """How deep (m) a hull of `density` (kg/m^3) and `volume` (m^3) over a waterline `area`
    (m^2) sits: the depth of the prism that displaces its mass (never more than it holds,
    volume / area: a hull denser than water sits awash)."""
    if density < 0.0 or volume < 0.0:
        raise ValueError(f"density and volume must be at least 0, got {density}, {volume}")
    if area <= 0.0:
        raise ValueError(f"area: the waterline footprint must be larger than 0, got {area}")
    return min(float(density) / RHO_WATER, 1.0) * float(volume) / float(area)


@dataclass(frozen=True)
class Float:
    """One floating object as the scene places it (its own animation, before the float): its
    `origin` (x, y, z), the waterline footprint's `centre` (x, y), `heading` (rad from +x),
    `length` and `beam` (m), its lowest point's height `keel` (m), how deep it sits (`draft`,
    m) and how far it follows the water's tilt (`response`). All world. And where its
    animation took it over the past seconds (`course`: times, x, y of the footprint's centre,
    for its wake: wake_field.Course) and its `name`."""

    key: str
    origin: tuple
    centre: tuple
    heading: float
    length: float
    beam: float
    keel: float
    draft: float
    response: float
    course: tuple = ()
    name: str = ""


def pose(source, t, world, f):
    """The world matrix (4 x 4) that carries float `f` from where the scene places it onto the
    sea of the ocean at `world` at time t (`poses`)."""
    return poses(source, t, world, [f])[0]


def poses(source, t, world, floats, courses=()):
    """For each float, the world matrix (4 x 4) that carries it from where the scene places it
    onto the sea of the ocean at `world` (its matrix: the sea lies at its level, its waves where
    the world's x, y are, as the grid samples them: the ocean's place across the sea, its
    rotation and scale move no wave) at time t: tilted about its origin onto the plane fitted
    over its footprint (`rides`, `tilt`), lifted so its keel sits `draft` under the water's
    mean there; the wakes of `courses` (wake_field.Course) on the water, but its own."""
    out = []
    names = [f.name for f in floats]
    wakes = [(c, names.index(c.name) if c.name in names else None) for c in courses]
    for f, (heave, slopes) in zip(floats, rides(source, t, [
            (f.centre, f.heading, f.length, f.beam) for f in floats], wakes=wakes),
            strict=True):
        lift = float(world[2, 3]) + heave - f.draft - f.keel
        matrix = np.eye(4)
        matrix[:3, :3] = tilt(slopes, f.heading, f.response)
        origin = np.asarray(f.origin, dtype=np.float64)
        matrix[:3, 3] = origin + np.array([0.0, 0.0, lift]) - matrix[:3, :3] @ origin
        out.append(matrix)
    return out
