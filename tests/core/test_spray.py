"""The spray torn off the crests (spray.py): its droplets' motion against the drag law it
integrates, its launches against the whitecaps' share, and every frame a pure function of
the time."""

import math

import numpy as np
import pytest

from projgrid_addon import effects, foam, residual_foam, spray
from projgrid_addon.camera import Camera, look_at, perspective
from projgrid_addon.sea_states import sea_state
from projgrid_addon.spectral_field import SpectralField
from projgrid_addon.spectrum import SeaState

WIND = math.radians(60.0)
AHEAD = ((0.0, 1.0), math.radians(30.0))  # a view along +Y, 60 degrees wide


def _sea(force):
    p = sea_state(force)
    return p, SpectralField(SeaState(wind_speed=p.wind_speed, fetch=p.fetch, wind_direction=WIND,
                                     swell_height=p.swell_height, swell_period=p.swell_period),
                            choppiness=p.choppiness)


def test_a_droplet_follows_stokes_drag_toward_the_wind_and_gravity():
    """`droplets` is the solution of dv/dt = (W - v) / tau + g (integrated here by small
    steps), its turbulent walk aside; a droplet ends falling at g tau through air moving
    with the wind."""
    rng = np.random.default_rng(3)
    n = 6
    x0, v0 = rng.normal(size=(n, 3)) * 3.0, rng.normal(size=(n, 3)) * 4.0
    tau = np.array([0.02, 0.05, 0.1, 0.2, 0.4, 0.3])
    wind, age = (18.0, -7.0), 1.3
    x, v, dt = x0.copy(), v0.copy(), 1e-5
    w = np.array([wind[0], wind[1], 0.0])
    for _ in range(int(round(age / dt))):
        v += ((w - v) / tau[:, None] + spray.GRAVITY) * dt
        x += v * dt
    got = spray.droplets(x0, v0, tau, np.full(n, age), wind, np.zeros((n, 3)))
    assert got == pytest.approx(x, abs=2e-3)
    late = spray.droplets(x0, v0, tau, np.full(n, 30.0), wind, np.zeros((n, 3))) - \
        spray.droplets(x0, v0, tau, np.full(n, 29.0), wind, np.zeros((n, 3)))
    assert late == pytest.approx(w + spray.GRAVITY * tau[:, None], rel=1e-6)


def test_no_spray_below_beaufort_8_and_more_with_the_wind():
    """None below SPRAY_ONSET (force 7: AUTO leaves it off too); from force 8 the puffs grow
    in number with the wind, and the share of launch sites throwing them grows as the active
    whitecaps' share times `spray_rate`."""
    p7, sea7 = _sea(7)
    assert p7.wind_speed < effects.SPRAY_ONSET and spray.spray_rate(p7.wind_speed) == 0.0
    assert spray.spray(sea7, 10.0, (0.0, 0.0), AHEAD, 0.0, p7.wind_speed, WIND) is None
    facts = effects.SceneFacts(camera_height=5.0, bound=3.0, wind_speed=p7.wind_speed,
                               sun_elevation=10.0)
    assert effects.decide({}, facts)["spray"][0] is False
    facts.wind_speed = effects.SPRAY_ONSET
    assert effects.decide({}, facts)["spray"][0] is True
    counts = []
    for force in (8, 9, 10):
        p, sea = _sea(force)
        puffs = spray.spray(sea, 10.0, (0.0, 0.0), AHEAD, 0.0, p.wind_speed, WIND)
        counts.append(len(puffs[0]))
        # world positions in float64 (the puffs' offsets from their mean are made float32)
        assert puffs[0].dtype == np.float64 and puffs[1].dtype == np.float32
        assert all(len(v) == counts[-1] for v in puffs)
    assert 0 < counts[0] < counts[1] < counts[2], counts


def test_sites_launch_with_the_chance_of_their_active_whitecaps():
    """Over a gale's launch sites and lattice times, the sites launching are the active
    whitecaps' share (foam.active_coverage: Monahan's, less what the residual foam holds)
    times `spray_rate`, within the binomial spread and the calibration's own."""
    p, sea = _sea(10)
    near = spray.blocks((0.0, 0.0), None)
    ks = range(40, 48)
    hits = sum(int(born.size) for k in ks for born, *_ in spray.launches(
        sea, near, k, p.wind_speed, WIND)) // spray.PER_LAUNCH
    sites = len(near) * spray.BLOCK ** 2 * len(ks)
    want = foam.active_coverage(sea, p.wind_speed) * spray.spray_rate(p.wind_speed)
    assert hits / sites == pytest.approx(want, rel=0.25), (hits, sites, want)


def test_each_frame_is_a_pure_function_of_the_time(monkeypatch):
    """A frame's puffs are the same made alone (nothing kept) and after other frames, in any
    order, or another view (a block's launches do not depend on the blocks made with it), and
    a camera moved along the sea keeps the puffs of the blocks both views share."""
    p, sea = _sea(9)

    def frame(t, centre=(0.0, 0.0)):
        return spray.spray(sea, t, centre, AHEAD, 0.0, p.wind_speed, WIND)
    monkeypatch.setattr(spray, "LAUNCHES", residual_foam.Kept(spray.LAUNCHES.kept))
    monkeypatch.setattr(spray, "GATHERED", residual_foam.Kept(spray.GATHERED.kept))
    alone = frame(12.5)
    for t in (14.0, 11.0, 12.5 - 1 / 24, 12.5 + 1 / 24):
        frame(t)
    again = frame(12.5)
    for a, b in zip(alone, again, strict=True):
        assert np.array_equal(a, b)
    moved = frame(12.5, (3.0, 40.0))
    monkeypatch.setattr(spray, "LAUNCHES", residual_foam.Kept(spray.LAUNCHES.kept))
    monkeypatch.setattr(spray, "GATHERED", residual_foam.Kept(spray.GATHERED.kept))
    for a, b in zip(moved, frame(12.5, (3.0, 40.0)), strict=True):  # as made alone
        assert np.array_equal(a, b)
    shared = {tuple(v) for v in alone[0].round(4)} & {tuple(v) for v in moved[0].round(4)}
    assert len(shared) > 0.5 * len(alone[0])


def test_puffs_leave_the_crests_and_ride_the_wind():
    """A gale's puffs start on the water (none below the troughs at launch) and are carried
    downwind: ring 0's puffs' mean displacement from where they were thrown lies along the
    wind."""
    p, sea = _sea(10)
    t = 10.0
    pos, radius, opacity = spray.spray(sea, t, (0.0, 0.0), None, 0.0, p.wind_speed, WIND)
    assert (radius >= spray.RADIUS[0] / math.sqrt(spray.SORTED)).all()
    assert (0.0 < opacity).all() and (opacity <= 1.0).all()
    bound = sea.bounds(t)[0]
    assert pos[:, 2].min() > -bound - 5.0 and pos[:, 2].max() < bound + 10.0
    near = spray.blocks((0.0, 0.0), None)
    sites = np.concatenate([x0 for k in spray.launch_times(t)
                            for _, x0, *_ in spray.launches(sea, near, k, p.wind_speed, WIND)])
    sites = sites[spray.ring_weight(np.hypot(sites[:, 0], sites[:, 1]), 0) > 0.0]
    ring0 = spray._ring(sea, t, (0.0, 0.0), None, 0.0, p.wind_speed, WIND, 0, 0)[0]
    drift = ring0[:, :2].mean(axis=0) - sites[:, :2].mean(axis=0)
    along = drift @ np.array([math.cos(WIND), math.sin(WIND)])
    assert along > 0.9 * np.hypot(*drift) and along > 5.0, drift


def test_the_spray_s_detail_follows_the_camera_in_rings():
    """Ring r's sites lie 2^r CELL apart out to 2^r REACH and throw puffs 2^r as wide; the
    rings' weights sum to 1 from the camera to the last ring's start, so no band of distance
    gets twice the spray or none, and thin out over the last ring's octave to none at its
    reach, falling all the way."""
    d = np.geomspace(1.0, spray.REACH * 2.0 ** (spray.RINGS + 1), 400)
    total = sum(spray.ring_weight(d, r) for r in range(spray.RINGS))
    last = spray.REACH * 2.0 ** (spray.RINGS - 2)
    inside, thinning = d < last * 2.0 ** (-spray.FADE / 2.0), d > last * 2.0 ** (spray.FADE / 2.0)
    assert total[inside] == pytest.approx(1.0) and total[-1] == 0.0
    assert (np.diff(total[thinning]) <= 0.0).all() and total[thinning][0] > 0.8
    assert total[d >= 2.0 * last].max() == 0.0
    assert all((spray.ring_weight(d, r) >= 0.0).all() for r in range(spray.RINGS))
    for ring in (0, 2):
        ix, iy, xy = spray.sites(3, -2, ring)
        gaps = np.diff(np.unique(np.floor(xy[0] / (spray.CELL * 2.0**ring))))
        assert (gaps == 1.0).all() and len(gaps) == spray.BLOCK - 1
    p, sea = _sea(10)
    widest = spray.RADIUS[1] + spray.PUFF_GROWTH * math.sqrt(2.0 * spray.DIFFUSIVITY * spray.LIFE)
    for ring in (0, spray.RINGS - 1):
        _, radius, _ = spray._ring(sea, 10.0, (0.0, 0.0), AHEAD, 0.0, p.wind_speed, WIND, 0, ring)
        scale = 2.0**ring / math.sqrt(spray.SORTED if ring < spray.STREAKED else 1)
        assert scale * spray.RADIUS[0] <= radius.min() and radius.max() <= scale * widest


def test_only_the_sites_whose_spray_can_reach_the_view_launch():
    """A camera looking along +Y, 4 degrees down (a 56 degree wide view): its wedge is +Y and
    half its width; the blocks kept are those within MARGIN of it (every block whose centre is
    in view, none beside or behind beyond it), and a camera looking straight down keeps all."""
    eye = np.array([0.0, 0.0, 5.0])
    forward = np.array([0.0, math.cos(math.radians(-4.0)), math.sin(math.radians(-4.0))])
    cam = Camera(*(look_at(eye, eye + forward), perspective(np.radians(32.0), 16 / 9, 0.1, 2e4)))
    ahead, half = spray.view_wedge(cam)
    assert ahead == pytest.approx([0.0, 1.0]) and 0.4 < half < 0.6
    for ring in range(spray.RINGS):
        every, kept = spray.blocks((0.0, 0.0), None, ring), spray.blocks((0.0, 0.0), (ahead, half),
                                                                       ring)
        assert set(kept) < set(every)
        size = spray.BLOCK * spray.CELL * 2.0**ring
        for bx, by in every:
            c = (np.array([bx, by]) + 0.5) * size
            angle = abs(math.atan2(c[0], c[1]))
            side = np.hypot(*c) * math.sin(min(max(angle - half, 0.0), math.pi / 2))
            if angle < half:
                assert (bx, by) in kept
            if side > spray.MARGIN + size:
                assert (bx, by) not in kept
    down = Camera(*(look_at(eye, eye - np.array([0.0, 0.0, 1.0]), up=(0.0, 1.0, 0.0)),
                    perspective(np.radians(40.0), 16 / 9, 0.1, 2e4)))
    assert spray.view_wedge(down) is None


def test_a_puff_draws_out_into_a_streamer_along_the_wind():
    """A puff's droplets, thrown together, are sorted by the drag: its smallest ride ahead
    downwind, its largest lag behind and fall: a gale's puffs draw out into streamers along
    the wind (spindrift's streaks), most at least 2.5 times as long as they are wide."""
    p, sea = _sea(10)
    t = 10.0
    pos, radius, _ = spray._ring(sea, t, (0.0, 0.0), AHEAD, 0.0, p.wind_speed, WIND, 0, 0)
    pos, radius = pos.reshape(-1, spray.SORTED, 3), radius.reshape(-1, spray.SORTED)
    spread = pos[:, 0] - pos[:, -1]  # from the largest droplets to the smallest
    wind = np.array([math.cos(WIND), math.sin(WIND)])
    along = spread[:, :2] @ wind
    assert np.median(along / np.linalg.norm(spread, axis=1)) > 0.8
    assert (pos[:, 0, 2] > pos[:, -1, 2]).mean() > 0.8  # the large droplets lower
    length = np.linalg.norm(spread, axis=1) + 2.0 * radius.max(axis=1)
    assert np.median(length / (2.0 * radius.max(axis=1))) > 2.5


def test_large_droplets_fall_at_their_measured_terminal_speed():
    """Past Stokes' law the drag grows (Schiller and Naumann): `settling`'s terminal speed
    g tau' balances it, and matches Gunn and Kinzer's (1949) measured fall speeds of water
    drops in air: 0.27 m/s at 100 um, 0.72 at 200 um, 1.62 at 400 um (within 10 %)."""
    for diameter, measured in ((100e-6, 0.27), (200e-6, 0.72), (400e-6, 1.62)):
        stokes = spray.WATER_DENSITY * diameter**2 / (18.0 * spray.AIR_VISCOSITY)
        fall = 9.81 * float(spray.settling(stokes))
        reynolds = fall * diameter * spray.AIR_DENSITY / spray.AIR_VISCOSITY
        assert fall == pytest.approx(9.81 * stokes / (1.0 + 0.15 * reynolds**0.687), rel=1e-3)
        assert fall == pytest.approx(measured, rel=0.1), diameter
