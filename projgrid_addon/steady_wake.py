"""Steady wakes (wake_field.py reads them): the wake a pressure patch makes at a steady speed,
steady in its own frame, and in deep water the same for every patch size once lengths are
counted in its sigma, heights in drafts and speed as the Froude number F = U / sqrt(g sigma).
So a patch's steady wake is summed once per Froude number (`steady`, by the exact ring sum of
wakes.py, on a half-raster: it is symmetric about the track), on a geometric ladder of them.
A hull is a row of such patches along its waterline (`hull`): sigma a third of its beam, 4/3
sigma apart, so the pressure is nearly even over the hull and falls off at its bow and stern,
whose wave systems make the V of divergent waves and the cusps; their steady wake is the
patch's, shifted and summed (`hull_wake`). Fast hulls' patches are widened until their
transverse waves span at most 16 sigma (F at most 1.6, the ladder's top): the wake's
shortest waves then go with the raster's cells. The hydrostatic dent a hull at rest sits in
is taken out: what is kept is the moving hull's wake."""

from functools import cache, lru_cache

import numpy as np

from . import wakes
from .spectrum import GRAVITY

RUNG = 1.12  # the ladder of Froude numbers: F = RUNG^i
LADDER = (-14, 4)  # its rungs: F 0.2 to 1.57 (below 0.2 the wake fades out over 3 rungs)
BEHIND, AHEAD, ACROSS = 120.0, 8.0, 50.0  # a patch's steady wake's extent, in sigma
CELL = 1.0 / 3.0  # its raster's cell, in sigma (its shortest waves, 2 sigma, over 6 cells)
PATCH = 4  # cells between a hull's patches (4/3 sigma: their sum within 1 % of even)
MOST = 8  # patches a hull is made of at most
FADE = 20.0  # sigma: the steady wake's far end fades out over this
# The wake is read near the hull from its patches, and from BEHIND - FADE on (where that fades)
# from patches FAR times as wide: a steady wake reaching FAR times as far, without the
# shortest divergent waves (which that far behind no grid holds but one close over them)
FAR = 2.0
TABLE = (300.0, 150.0)  # the response table (reach, window) every rung reads (sigma 1)


@cache  # at most the ladder's 19 rungs, 4.4 MB
def steady(rung):
    """(heights, xi0): the moving part of the steady wake of a patch of unit peak pressure
    (in drafts) and sigma 1 at Froude number RUNG^rung, on a raster of CELL: rows
    xi = xi0 + i CELL (behind it, from AHEAD ahead), columns eta = j CELL (across, one side)."""
    u = RUNG**rung * np.sqrt(GRAVITY)
    window = min(2.2 * BEHIND / u, TABLE[1])  # its transverse waves formed out to BEHIND
    xi = np.arange(-AHEAD, BEHIND + CELL, CELL)
    eta = np.arange(0.0, ACROSS + CELL, CELL)

    def path(taus):
        return np.stack([u * (taus - window), np.zeros_like(taus)])

    moving = wakes.raster_heights(-xi, eta, window, path, 1.0, 4.0, window, TABLE).T
    dent = np.exp(-0.5 * (xi[:, None] ** 2 + eta**2))  # at rest: -exp(-r^2 / 2)
    fade = np.clip((BEHIND - xi) / FADE, 0.0, 1.0)[:, None] * np.clip(
        (ACROSS - eta) / (0.2 * ACROSS), 0.0, 1.0)
    return ((moving + dent) * fade).astype(np.float32), float(xi[0])


@lru_cache(maxsize=64)
def hull_wake(rung, patches):
    """(heights, xi0) as `steady` of a row of patches PATCH cells apart, centred on xi 0, of
    unit total peak pressure: `patches` (fractional: the two whole counts either side,
    weighted by how near each is) sharing it evenly."""
    one, xi0 = steady(rung)
    low = max(int(np.floor(patches)), 1)
    counts = [(low, 1.0 + low - patches), (low + 1, patches - low)] if patches > 1.0 else [
        (1, 1.0)]
    out = np.zeros((one.shape[0] + PATCH * low, one.shape[1]), np.float32)
    for count, weight in counts:
        if weight <= 0.0:
            continue
        start = PATCH * (low + 1 - count) // 2 if count == low else 0
        for i in range(count):
            out[start + PATCH * i:start + PATCH * i + one.shape[0]] += np.float32(
                weight / count) * one
    return out, xi0 - 0.5 * PATCH * low * CELL


def hull(length, beam, u_ref, widen=1.0):
    """(sigma, patches, peak): a hull of `length` and `beam` moving at U_ref as a row of
    patches along its waterline: their sigma (a third of the beam, widened for a fast hull:
    its transverse waves 2 pi U^2 / g span at most 16 sigma, and for a long one: MOST
    patches), how many (fractional: two counts are read, weighted) and the peak pressure
    (drafts) of each that gives them the hull's waterplane, length times beam."""
    sigma = widen * max(beam / 3.0, 2.0 * np.pi * u_ref * u_ref / GRAVITY / 16.0,
                        length / (PATCH * CELL * MOST), 0.02)
    patches = max(length / (PATCH * CELL * sigma), 1.0)
    return sigma, patches, length * beam / (2.0 * np.pi * sigma * sigma)


def rungs(u_ref, sigma):
    """[(rung, weight)]: the rungs either side of the Froude number of U_ref, weighted (below
    the ladder its lowest, fading out over 3 rungs)."""
    position = np.log(max(u_ref, 1e-6) / np.sqrt(GRAVITY * sigma)) / np.log(RUNG)
    fade = float(np.clip((position - LADDER[0] + 3.0) / 3.0, 0.0, 1.0))
    position = min(max(position, LADDER[0]), LADDER[1])
    low = min(int(np.floor(position)), LADDER[1] - 1)
    w = float(position - low)
    return [(r, v * fade) for r, v in ((low, 1.0 - w), (low + 1, w)) if v * fade > 0.0]
