"""Floating objects (projgrid_addon/floating.py) against the formulas they stand for: a rigid
hull's heave and pitch over its footprint in a long-crested wave (the Froude-Krylov
approximation), Archimedes' draft, and the hull against the buoy in a spectral sea."""

import numpy as np
import pytest

from projgrid_addon import SeaState, SpectralField, floating, wake_field, wakes


class Wave:
    """One long-crested wave a cos(k x - omega t) along +x (a height source's
    `displacement`; `lod` ignored: the wave is long against every footprint spacing)."""

    wave_scale = 1.0

    def __init__(self, amplitude, wavelength):
        self.a, self.k = amplitude, 2.0 * np.pi / wavelength

    def displacement(self, xy, t, lod=None):
        return self.a * np.cos(self.k * np.asarray(xy)[0] - t), None


def swing(wave, length, heading):
    """The largest heave and the largest slopes (along, across) over a wave period."""
    rides = [floating.ride(wave, phase, (3.0, -2.0), heading, length, 0.3 * length)
             for phase in np.linspace(0.0, 2.0 * np.pi, 73)]
    heave = max(abs(h) for h, _ in rides)
    return heave, np.abs([s for _, s in rides]).max(axis=0)


@pytest.mark.parametrize("ratio", [0.05, 0.25, 0.5, 0.7, 1.0, 1.43, 2.5])
def test_a_hull_heaves_and_pitches_as_the_wave_over_its_length(ratio):
    """Over a hull `ratio` wavelengths long, heading into the wave: heave a sin(u) / u and
    slope a k 3 (sin u - u cos u) / u^3 (u = k L / 2) within 2 % of a and of a k; the
    short hull follows the wave (a, a k), the one a wavelength long does not heave; beam on
    to the wave the slope is the roll's (across) and the heave the beam's."""
    wave = Wave(0.8, 20.0)
    length = ratio * 20.0
    u = wave.k * length / 2.0
    heave, (along, across) = swing(wave, length, 0.0)
    assert heave == pytest.approx(0.8 * abs(np.sin(u) / u), abs=0.02 * 0.8)
    want = 0.8 * wave.k * 3.0 * abs(np.sin(u) - u * np.cos(u)) / u**3
    assert along == pytest.approx(want, abs=0.02 * 0.8 * wave.k)
    assert across < 1e-9
    heave, (along, across) = swing(wave, length, np.pi / 2.0)  # beam on: the beam spans 0.3 L
    assert along < 1e-9
    v = 0.3 * u
    assert across == pytest.approx(0.8 * wave.k * 3.0 * abs(np.sin(v) - v * np.cos(v)) / v**3,
                                   abs=0.02 * 0.8 * wave.k)
    assert heave == pytest.approx(0.8 * abs(np.sin(v) / v), abs=0.02 * 0.8)


def sea_and_places(n=60):
    sea = SpectralField(SeaState(wind_speed=4.0), choppiness=0.8, seed=3)
    places = np.random.default_rng(5).uniform(-2e3, 2e3, (n, 2))
    return sea, places


def test_a_long_hull_barely_heaves_in_a_short_chop_and_a_buoy_rides_it():
    """A 4 m/s sea (waves of 10-15 m): a 100 m x 20 m hull heaves less than a twentieth of
    the sea's spread, a 1 m buoy as the sea at its place (spread within 10 %, correlated
    over 0.97 with the height of the water at its centre)."""
    sea, places = sea_and_places()
    t = 7.0
    _, at = floating.water_under(sea, places.T, t)
    spread = at.std()
    hull = [floating.ride(sea, t, c, 0.3, 100.0, 20.0)[0] for c in places]
    buoy = [floating.ride(sea, t, c, 0.3, 1.0, 1.0)[0] for c in places]
    assert np.std(hull) < spread / 20.0, (np.std(hull), spread)
    assert np.std(buoy) == pytest.approx(spread, rel=0.1)
    assert np.corrcoef(buoy, at)[0, 1] > 0.97


def test_the_water_under_a_point_of_a_choppy_sea_is_found():
    """On a choppy sea the height over a world point is that of the water displaced there:
    p + D(p) within a millimetre of the point, and the height differs from the undisplaced
    h(x) (the chop matters)."""
    sea, places = sea_and_places()
    xy = places.T
    p, h = floating.water_under(sea, xy, 7.0)
    h_p, d = sea.displacement(p, 7.0)
    assert np.abs(p + d - xy).max() < 1e-3
    assert np.array_equal(h, h_p)
    assert np.abs(h - sea.displacement(xy, 7.0)[0]).max() > 0.01


def test_the_tilt_turns_the_hull_onto_the_fitted_plane():
    """tilt: a rotation (orthonormal, determinant 1) taking the hull's up to the plane's normal
    for a response of 1, none for 0, half the angle for 0.5; about a horizontal axis (it
    keeps the heading as near as a tilt can)."""
    slopes, heading = (0.2, -0.1), 0.7
    c, s = np.cos(heading), np.sin(heading)
    gx, gy = c * 0.2 + s * 0.1, s * 0.2 - c * 0.1
    normal = np.array([-gx, -gy, 1.0]) / np.sqrt(1.0 + gx * gx + gy * gy)
    r = floating.tilt(slopes, heading)
    assert r @ r.T == pytest.approx(np.eye(3), abs=1e-12) and np.linalg.det(r) == pytest.approx(1)
    assert r @ [0.0, 0.0, 1.0] == pytest.approx(normal, abs=1e-12)
    assert abs((r @ np.cross([0.0, 0.0, 1.0], normal))[2]) < 1e-12  # the axis stays put
    assert floating.tilt(slopes, heading, 0.0) == pytest.approx(np.eye(3))
    half = floating.tilt(slopes, heading, 0.5) @ [0.0, 0.0, 1.0]
    assert np.arccos(half[2]) == pytest.approx(0.5 * np.arccos(normal[2]), rel=1e-9)


def test_the_draft_is_archimedes():
    """A box of density rho sinks to rho / RHO_WATER of its depth; a denser one is awash (its
    whole depth); bad input names the setting."""
    depth, length, beam = 1.5, 8.0, 3.0
    volume, area = depth * length * beam, length * beam
    assert floating.draft(floating.RHO_WATER / 3.0, volume, area) == pytest.approx(0.5)
    assert floating.draft(7800.0, volume, area) == pytest.approx(depth)
    with pytest.raises(ValueError, match="density"):
        floating.draft(-1.0, volume, area)
    with pytest.raises(ValueError, match="area"):
        floating.draft(500.0, volume, 0.0)


def test_a_float_rides_the_waves_where_they_are_whatever_the_ocean_s_place():
    """The grid samples the sea at the world's x, y (the ocean's place across the sea, its
    rotation and scale move no wave): a float keeps its pose, but for the ocean's level,
    when the ocean moves or turns, and its heave is the sea's mean at its world place."""
    sea, places = sea_and_places()
    f = floating.Float(key="f", origin=(40.0, 12.0, 0.0), centre=(40.0, 12.0), heading=0.4,
                       length=1.0, beam=1.0, keel=-0.5, draft=0.2, response=1.0)
    at_origin = floating.pose(sea, 7.0, np.eye(4), f)
    moved = np.eye(4)
    c, s = np.cos(0.9), np.sin(0.9)
    moved[:2, :2] = [[c, -s], [s, c]]
    moved[:3, 3] = (150.0, -60.0, 2.0)
    there = floating.pose(sea, 7.0, moved, f)
    assert there[:3, :3] == pytest.approx(at_origin[:3, :3], abs=1e-12)
    assert there[:3, 3] == pytest.approx(at_origin[:3, 3] + [0.0, 0.0, 2.0], abs=1e-9)
    heave, _ = floating.ride(sea, 7.0, f.centre, f.heading, f.length, f.beam)
    lifted = at_origin @ [*f.origin, 1.0]  # its origin, lifted (turned about itself)
    assert lifted[2] == pytest.approx(f.origin[2] + heave - f.draft - f.keel, abs=1e-9)


def test_floats_posed_together_are_posed_as_alone():
    """`poses` samples every float's footprint in one call to the sea: each pose as `pose`
    gives it alone (a buoy, a boat, a long hull; within 1e-5: the sea's float32 sums)."""
    sea, _ = sea_and_places()
    floats = [floating.Float(key=str(k), origin=(x, y, 0.0), centre=(x, y), heading=h,
                             length=length, beam=beam, keel=-0.5, draft=0.3, response=0.8)
              for k, (x, y, h, length, beam) in enumerate(
                  [(3.0, 4.0, 0.1, 1.0, 1.0), (-20.0, 15.0, 1.2, 10.0, 3.0),
                   (60.0, -30.0, 2.5, 100.0, 20.0)])]
    together = floating.poses(sea, 7.0, np.eye(4), floats)
    for f, matrix in zip(floats, together, strict=True):
        assert matrix == pytest.approx(floating.pose(sea, 7.0, np.eye(4), f), abs=1e-5)


def test_a_float_rides_another_s_wake_and_not_its_own():
    """On a flat sea a buoy in a passing hull's wake heaves by the wake's mean height over its
    footprint (wake_field.heights) and tilts with it; the hull rides as if there were no wake
    (its own is not under it); a float ahead of the hull rides none."""
    flat, u, t = Wave(0.0, 20.0), 6.0, 60.0
    times = np.arange(t - wakes.WINDOW, t + 1e-9, 0.1)
    course = wake_field.course("hull", times, u * times, np.zeros_like(times), 1.0, 10.0, 3.0)
    x = u * t

    def at(name, cx, cy, length, beam):
        return floating.Float(key=name, origin=(cx, cy, 0.0), centre=(cx, cy), heading=0.0,
                              length=length, beam=beam, keel=-0.5, draft=0.3, response=1.0,
                              name=name)
    floats = [at("buoy", x - 40.0, 6.0, 1.0, 1.0), at("hull", x, 0.0, 10.0, 3.0),
              at("ahead", x + 60.0, 0.0, 1.0, 1.0)]
    rode = floating.poses(flat, t, np.eye(4), floats, [course])
    still = floating.poses(flat, t, np.eye(4), floats)
    xy, _ = floating.footprint(floats[0].centre, 0.0, 1.0, 1.0)
    wake = wake_field.heights(course, xy)
    assert abs(wake.mean()) > 0.01 and np.ptp(wake) > 0.005, wake  # a wake to ride
    origin = np.array([*floats[0].origin, 1.0])  # the pose turns about it, lifts it
    assert (rode[0] @ origin)[2] - (still[0] @ origin)[2] == pytest.approx(wake.mean(),
                                                                            abs=1e-6)
    assert not np.allclose(rode[0][:3, :3], np.eye(3), atol=1e-4)  # it tilts with it
    assert np.array_equal(rode[1], still[1]) and np.array_equal(rode[2], still[2])
