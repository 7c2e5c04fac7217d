"""Grid pipeline: bad input, topology, result contents, and the core's independence from bpy."""


import numpy as np
import pytest

from projgrid_addon import (
    Camera,
    HeightField,
    build_grid,
    cascade,
    grid_topology,
    look_at,
    perspective,
    sea_state,
    snapped_origin,
    spectrum,
)
from projgrid_addon.projector import Projector
from projgrid_addon.spectral_field import SpectralField
from projgrid_addon.spectrum import SeaState

CAM = (look_at((0, 0, 10), (0, 100, 5)), perspective(np.radians(50), 16 / 9, 0.1, 1e4))


def test_thesis_default_grid():
    r = build_grid(CAM, HeightField(), time=1.0)
    assert r.visible and r.resolution == (65, 129)
    assert r.positions.shape == (65 * 129, 3) and r.positions.dtype == np.float32
    assert r.uv.dtype == np.float32 and r.normals.dtype == np.float32
    assert 0.5 < r.efficiency <= 1.0
    first, count = r.shader_octaves
    assert 0 <= first <= 8 and first + count == 8


def test_topology_counter_clockwise():
    q = grid_topology(4, 3)
    assert q.shape == (6, 4) and q.dtype == np.int32
    assert list(q[0]) == [0, 1, 5, 4]


def test_band_limit_leaves_detail_to_the_shader():
    hf = HeightField(octaves=12, wave_scale=40.0)
    r = build_grid(CAM, hf, resolution=(17, 17))
    assert r.shader_octaves[1] > 0  # a 17x17 grid cannot carry 12 octaves
    full = build_grid(CAM, hf, resolution=(17, 17), band_limit=False)
    assert full.shader_octaves == (12, 0)


def test_origin_keeps_float32_precision_far_away():
    view = look_at((1e6, 2e6, 3), (1e6, 2e6 + 50, 0))
    cam = Camera(view, CAM[1])
    hf = HeightField(amplitude=0.0)
    world = build_grid(cam, hf, resolution=(9, 9))
    local = build_grid(cam, hf, resolution=(9, 9), origin=snapped_origin(cam, 0.0))
    exact = local.positions.astype(np.float64) + local.origin
    err_world = np.abs(world.positions.astype(np.float64) - exact).max()
    err_local = np.abs(local.positions.astype(np.float64) + local.origin - exact).max()
    assert err_world > 1e-2 > 1e-4 > err_local  # float32 at 2e6 m: centimetres; local: sub-mm


@pytest.mark.parametrize(("args", "name"), [
    ({"resolution": (1, 5)}, "resolution"), ({"resolution": (65,)}, "resolution"),
    ({"resolution": (100_000, 100_000)}, "resolution"), ({"time": float("nan")}, "time"),
    ({"level": float("inf")}, "level"), ({"projector_elevation": -1}, "projector_elevation"),
    ({"origin": (0, 0)}, "origin"),
])
def test_bad_input_names_the_parameter(args, name):
    with pytest.raises(ValueError, match=name):
        build_grid(CAM, HeightField(), **args)


@pytest.mark.parametrize(("view", "proj", "name"), [
    (np.full((4, 4), np.nan), CAM[1], "view"), (np.zeros((4, 4)), CAM[1], "view"),
    (CAM[0], np.eye(3), "proj"), (CAM[0], np.ones((4, 4)), "proj"),
])
def test_bad_matrices(view, proj, name):
    with pytest.raises(ValueError, match=name):
        Camera(view, proj)





@pytest.mark.parametrize("flipped", [False, True])
def test_corner_uv_is_the_grid_uv_at_each_corner(flipped):
    from projgrid_addon import corner_uv, grid_uv

    quads = grid_topology(5, 4)
    if flipped:
        quads = quads[:, ::-1]
    assert np.array_equal(corner_uv(5, 4, flipped), grid_uv(5, 4)[quads.ravel()])


def _gale_from(height, pitch):
    p = sea_state(8)
    waves = SpectralField(SeaState(wind_speed=p.wind_speed, fetch=p.fetch,
                                   swell_height=p.swell_height, swell_period=p.swell_period),
                          choppiness=p.choppiness)
    eye = np.array([0.0, 0.0, height])
    forward = (0.0, np.cos(np.radians(pitch)), np.sin(np.radians(pitch)))
    return waves, (look_at(eye, eye + forward), perspective(np.radians(28.0), 16 / 9, 0.1, 2e4))


@pytest.mark.parametrize("height, pitch", [(4.0, 0.0), (5.0, -2.0)])
def test_a_low_camera_in_a_gale_spends_its_vertices_on_the_screen(height, pitch, monkeypatch,
                                                                  grids_anew):
    """A gale (Beaufort 8, its waves nearly as high as the camera) from 4-5 m up: the grid's
    columns and rows follow the camera's screen (Projector.spacing), so over 12 s at least half
    of the viewport grid's vertices are on the screen (median), more than twice an even grid's;
    and the render grid keeps 0.6 of the sea's height (standard deviation) 200 to 1,000 m away
    (the long half of the band holding most of it is whole there: cascade.layout)."""
    waves, cam = _gale_from(height, pitch)
    sigma = waves.spread[0]

    def frames(resolution):
        for t in np.arange(0.0, 12.0, 1.5):
            yield build_grid(cam, waves, time=t, resolution=resolution)

    followed = [r.efficiency for r in frames((65, 129))]
    far = []
    for r in frames((257, 513)):
        x, y, h = r.surface
        d = np.hypot(x, y)
        far.append(h[(d > 200.0) & (d < 1000.0)].std() / sigma)

    def evenly(self, camera, level, extent, corners, nx, ny):
        s_u, s_v = np.linspace(0.0, 1.0, nx), np.linspace(0.0, 1.0, ny)
        return s_u, np.ones(nx), s_v[:, None], np.ones(ny)
    monkeypatch.setattr(Projector, "spacing", evenly)
    evened = [r.efficiency for r in frames((65, 129))]
    assert np.median(followed) >= max(0.5, 2.0 * np.median(evened)), (followed, evened)
    assert np.median(far) >= 0.6, far


@pytest.mark.parametrize("force", [4, 8, 10])
def test_a_band_holding_most_of_the_sea_is_laid_out_as_its_halves(force):
    """cascade.layout: the band holding most of the sea (several tiles) as its long and short
    halves, each a group of tiles holding only its waves (a lattice cell across the cut shares
    it: cascade._cell_energy), the long half's band limit an
    octave of spacing lower (log2 of the half's ratio), the halves' shares the band's, the
    band's tiles shared between them so the busiest tile holds the least, and the sea's
    variance the spectrum's (Parseval)."""
    p = sea_state(force)
    state = SeaState(wind_speed=p.wind_speed, fetch=p.fetch, swell_height=p.swell_height,
                     swell_period=p.swell_period)
    sea = SpectralField(state, choppiness=p.choppiness)
    shares, halves = cascade.band_shares(state), cascade.band_shares(state, halves=True)
    b = int(np.argmax(shares[:cascade.BANDS]))
    (long_lo, long_hi), (short_lo, short_hi) = cascade.pieces(*cascade.bands()[b])
    assert long_lo == short_hi and halves[2 * b] + halves[2 * b + 1] == pytest.approx(
        shares[b], rel=1e-4)
    groups = {level: [sea.cascades[i] for i in tiles] for level, _, tiles in sea.groups}
    long, short = groups[cascade.band_level(long_lo)], groups[cascade.band_level(short_lo)]
    assert cascade.band_level(short_lo) - cascade.band_level(long_lo) == pytest.approx(
        0.5 * np.log2(cascade.BAND_RATIO))
    def cell(c, wavelength):  # a lattice cell's half diagonal as a fraction of the wave
        return 1.0 + wavelength / (np.sqrt(2.0) * c.size)
    assert all(c.shortest_held * cell(c, long_lo) >= long_lo for c in long)
    assert all(c.longest_held <= short_hi * cell(c, short_hi) for c in short)
    count = int(np.ceil(shares[b] / cascade.SHARE_PER_TILE))
    assert len(long) + len(short) == count
    def busiest(n):  # the share of the busiest tile with n tiles for the long half
        return max(halves[2 * b] / n, halves[2 * b + 1] / (count - n))
    assert busiest(len(long)) == min(busiest(n) for n in range(1, count))
    assert sea.spread[0] ** 2 == pytest.approx(spectrum.moments(state)[0], rel=0.01)


def test_the_drift_is_how_far_the_choppy_waves_moved_each_vertex():
    """GridResult.drift: each vertex's sideways displacement from its grid point, so the
    position less the drift is where the water came from (the foam's noises are taken there);
    none without choppiness."""
    state = SeaState(wind_speed=15.0)
    r = build_grid(CAM, SpectralField(state, choppiness=1.0), time=3.0, resolution=(33, 65))
    drift = r.drift
    assert drift.shape == r.positions.shape and drift.dtype == np.float32
    came_from = r.positions[:, :2] - drift[:, :2] + r.origin[:2]
    assert np.allclose(came_from, np.stack([b.ravel() for b in r.base], axis=-1), atol=1e-2)
    assert not drift[:, 2].any() and np.abs(drift[:, :2]).max() > 0.1
    assert build_grid(CAM, SpectralField(state), time=3.0, resolution=(33, 65)).drift is None
