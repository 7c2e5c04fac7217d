"""Wakes (projgrid_addon/wakes.py) against what linear deep-water theory and the measurements
say a wake is: the hydrostatic dent of a hull at rest, Kelvin's transverse wavelength
2 pi U^2 / g, the cusp at 19.47 degrees, and its narrowing at high Froude numbers (Rabaud and
Moisy 2013: about 0.2 / Fr rad)."""

import numpy as np
import pytest

from projgrid_addon import wakes
from projgrid_addon.spectrum import integrate

G, LENGTH = 9.81, 8.0


def test_j0_is_the_bessel_function():
    x = np.linspace(0.0, 40.0, 801)
    theta = np.linspace(0.0, np.pi, 4001)
    integral = integrate(np.cos(np.outer(x, np.sin(theta))), theta, axis=1) / np.pi
    assert np.abs(wakes.j0(x) - integral).max() < 1e-7


def test_a_hull_at_rest_sits_in_its_hydrostatic_dent():
    """Long at rest, the water under the pressure patch is pushed down by the draft:
    -D exp(-r^2 / (2 sigma^2)), within 3 % of D."""
    r = np.array([0.0, 1.0, 2.0, 4.0])
    still = wakes.wake_heights(np.stack([r, np.zeros_like(r)]), 100.0,
                               lambda taus: np.zeros((2, len(taus))), 1.0, LENGTH)
    assert still == pytest.approx(-np.exp(-r**2 / (2.0 * (LENGTH / 4.0) ** 2)), abs=0.03)


def cusp(froude, t=50.0):
    """The angle (degrees) of the wake's largest waves from the track, median over rows
    25-65 m behind, and the transverse wavelength along the track, for a hull moving along
    +x at Froude number `froude`."""
    u = froude * np.sqrt(G * LENGTH)

    def path(taus):
        return np.stack([u * taus, np.zeros_like(taus)])
    behind = np.arange(25.0, 70.0, 5.0)
    across = np.arange(1.0, 50.0, 0.25)
    bx, by = np.meshgrid(u * t - behind, across, indexing="ij")
    h = np.abs(wakes.wake_heights(np.stack([bx, by]), t, path, 1.0, LENGTH))
    angle = np.degrees(np.arctan(across[np.argmax(h, axis=1)] / behind))
    track = u * t - np.arange(10.0, 60.0, 0.1)
    along = wakes.wake_heights(np.stack([track, np.zeros_like(track)]), t, path, 1.0, LENGTH)
    crossings = np.flatnonzero(np.diff(np.sign(along)) != 0)
    return float(np.median(angle)), 2.0 * float(np.mean(np.abs(np.diff(track[crossings])))), u


def test_kelvin_s_wake_its_cusp_and_transverse_waves():
    """At Fr 0.6: the largest waves 19.47 degrees from the track (within 2), the transverse
    waves 2 pi U^2 / g long (within 5 %)."""
    angle, wavelength, u = cusp(0.6)
    assert angle == pytest.approx(np.degrees(np.arcsin(1.0 / 3.0)), abs=2.0)
    assert wavelength == pytest.approx(2.0 * np.pi * u * u / G, rel=0.05)


def test_a_fast_hull_s_wake_narrows():
    """At Fr 1 the wake narrows below Kelvin's angle, toward Rabaud and Moisy's 0.2 / Fr rad
    (11.5 degrees; within 35 %)."""
    angle, _, _ = cusp(1.0)
    assert angle < 16.0 and angle == pytest.approx(np.degrees(0.2), rel=0.35)


def test_a_wake_moves_on_smoothly_from_frame_to_frame():
    """A pure function of the time: a frame's wake is the same alone or after others, and
    changes from one frame to the next by less than a sixth of its height (an emission enters
    as a ring of height zero; emissions sit on an absolute time lattice)."""
    u = 0.6 * np.sqrt(G * LENGTH)

    def path(taus):
        return np.stack([u * taus, 0.3 * np.sin(taus)])
    xy = np.stack(np.meshgrid(np.arange(150.0, 270.0, 0.5), np.arange(-40.0, 40.0, 0.5)))
    frames = [wakes.wake_heights(xy, 50.0 + f / 24.0, path, 1.0, LENGTH) for f in range(4)]
    assert np.array_equal(frames[2], wakes.wake_heights(xy, 50.0 + 2 / 24.0, path, 1.0, LENGTH))
    height = np.abs(frames[0]).max()
    assert np.abs(np.diff(frames, axis=0)).max() < height / 6.0


def test_the_raster_sum_is_the_pointwise_sum():
    """raster_heights (an emission at a time, read in r only) gives wake_heights' heights."""
    u = 0.6 * np.sqrt(G * LENGTH)

    def path(taus):
        return np.stack([u * taus, 2.0 * np.sin(0.1 * taus)])
    xs, ys = np.arange(200.0, 280.0, 1.3), np.arange(-30.0, 30.0, 1.1)
    raster = wakes.raster_heights(xs, ys, 50.0, path, 0.7, LENGTH)
    points = wakes.wake_heights(np.stack(np.meshgrid(xs, ys)), 50.0, path, 0.7, LENGTH)
    assert np.abs(raster - points).max() < 1e-4 * np.abs(points).max()
