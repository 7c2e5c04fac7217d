"""Numerical-stability suite: random and named camera poses, every property checked on each.

Properties (tests/core/grid_checks.py): finite outputs, heights within the bound, no backfiring,
consistent winding, unit upward normals, corner interpolation equal to per-vertex intersection,
coverage by ray tests against the triangles, and no popping under a small camera move.
"""

import os

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings

from projgrid_addon import Camera, displaceable_volume, projector
from projgrid_addon.displaceable_volume import Extent
from projgrid_addon.projected_grid import border_outside
from projgrid_addon.projector import Projector

from .grid_checks import Pose, check_coverage, relative_moves
from .poses import POP, POPPING, check_pose, fresh_poses, poses

__all__ = ["POPPING"]  # read by tests/conftest.py's summary

# A hypothesis pose costs 1.6-2.4 times a fresh one (the poses hypothesis favours, its spectral
# seas most: docs/testing.md); the fresh batch, from a new seed every run, is the larger (about
# 50 s in CI's 4.5 lane at 9.6 ms a pose).
EXAMPLES = 2_000
FRESH = 5_000


@pytest.mark.slow
@settings(max_examples=EXAMPLES, suppress_health_check=list(HealthCheck), deadline=None)
@given(poses)
def test_random_poses(pose):
    check_pose(pose)


@pytest.mark.slow
def test_fresh_poses(capsys):
    """FRESH poses from a new seed every run (CI's hypothesis examples are the same every run).
    The seed is printed, and named with the pose's index in a failure, for replaying."""
    seed = int(os.environ.get("STABILITY_SEED") or int.from_bytes(os.urandom(8), "little"))
    with capsys.disabled():
        print(f"\nfresh poses: seed {seed}, {FRESH} poses (replay: STABILITY_SEED={seed})")
    for i, _, pose in fresh_poses(seed, FRESH):
        try:
            check_pose(pose)
        except AssertionError as e:
            raise AssertionError(f"fresh pose {i} of seed {seed} (replay it alone: python -m "
                                 f"tools.stress --seed {seed} --pose {i}): {e}\n{pose}") from e


NAMED = {
    "straight down": Pose(pitch=-90.0),
    "straight down rolled": Pose(pitch=-90.0, roll=37.0),
    "straight up inside the volume": Pose(height=0.2, pitch=90.0, amplitude=1.0),
    "exactly at the horizon": Pose(pitch=0.0, height=2.0),
    "horizon, wide": Pose(pitch=0.0, fov=170.0, height=2.0),
    "horizon telephoto": Pose(pitch=0.0, fov=1.0, height=30.0, far=1e7),
    "just above the horizon": Pose(pitch=0.5, height=2.0),
    "looking up": Pose(pitch=45.0, height=2.0, fov=120.0),
    "rolled 90 at the horizon": Pose(pitch=0.0, roll=90.0),
    "rolled 45 looking down": Pose(pitch=-30.0, roll=45.0),
    "upside down": Pose(pitch=-20.0, roll=180.0),
    "orthographic down": Pose(pitch=-90.0, ortho_scale=50.0),
    "orthographic oblique": Pose(pitch=-30.0, ortho_scale=50.0),
    "orthographic horizon": Pose(pitch=0.0, ortho_scale=50.0),
    "orthographic up": Pose(pitch=60.0, ortho_scale=50.0, height=0.1, amplitude=1.0),
    "on the surface": Pose(height=0.0, pitch=-5.0),
    "on the surface, flat sea": Pose(height=0.0, pitch=0.0, amplitude=0.0),
    "inside the volume": Pose(height=0.3, pitch=-10.0, amplitude=2.0),
    "under water looking up": Pose(height=-5.0, pitch=30.0),
    # the mean sea through the eye, a point of the span near it: its NDC was the rows' spacing
    "on the surface, rolled and shifted, a telephoto": Pose(
        height=0.0, pitch=0.0, yaw=-180.0, roll=162.34071060083807, fov=1.0,
        near=3.712890573884195e-06, far=0.25161991181746446, bearing=194.15410716086626,
        aspect=3.224382534674953, shift_x=0.43859798600897193, shift_y=0.2047090653795749,
        level=-29.338015243411064, amplitude=0.0, time=5888711.264179228,
        elevation=21.973201690707356, resolution=(12, 10), choppiness=1.5, wind_speed=20.0),
    "under water looking down": Pose(height=-0.3, pitch=-60.0),
    "deep, looking at the surface": Pose(height=-50.0, pitch=80.0, fov=90.0),
    "amplitude above the camera": Pose(height=3.0, amplitude=20.0, pitch=-20.0),
    "far from the origin": Pose(distance=1e6, bearing=33.0, height=5.0),
    "late in time": Pose(time=1e7),
    "extreme clip range": Pose(near=1e-4, far=1e7, pitch=-1.0),
    # Clip ranges whose float32 projection (Blender's calc_matrix_camera) rounds the depth terms
    # off: the grid is built from the float64 projection (camera.blender_projection).
    "clip 0.1 to 1e7": Pose(near=0.1, far=1e7, pitch=-3.0),
    "clip 1e-4 to 2e4": Pose(near=1e-4, far=2e4, pitch=-3.0),
    "clip 1 to 1e8": Pose(near=1.0, far=1e8, pitch=-3.0),
    "clip 1e-6 to 1e9": Pose(near=1e-6, far=1e9, pitch=-3.0),
    "clip 1e-6 to 1e9 at the horizon": Pose(near=1e-6, far=1e9, pitch=0.0, height=2.0),
    "clip 1e-6 to 1e9 from high up": Pose(near=1e-6, far=1e9, pitch=-20.0, height=10_000.0),
    "high altitude": Pose(height=10_000.0, pitch=-30.0, far=1e7),
    "lens shift": Pose(shift_x=0.5, shift_y=-0.5, pitch=-5.0),
    "projector elevation": Pose(height=1.0, pitch=-5.0, elevation=40.0),
    "2x2 grid": Pose(resolution=(2, 2)),
    "tall narrow screen": Pose(aspect=0.25, fov=120.0, pitch=-2.0),
    # Choppy: the grid widened by the displacement's bound still covers the screen, to its
    # edges, whichever way the waves move the vertices.
    "choppy at the horizon": Pose(pitch=0.0, height=2.0, choppiness=1.0, amplitude=2.0),
    "choppy looking down": Pose(pitch=-90.0, height=5.0, choppiness=1.5, amplitude=2.0),
    "choppy, wide, rolled": Pose(pitch=-20.0, fov=120.0, roll=30.0, choppiness=1.0,
                                 amplitude=3.0, wind_direction=2.0),
    "choppy from inside the volume": Pose(height=0.5, pitch=-10.0, choppiness=1.0,
                                          amplitude=2.0),
    "choppy orthographic": Pose(pitch=-45.0, ortho_scale=40.0, choppiness=1.0, amplitude=2.0),
    "choppy under water": Pose(height=-3.0, pitch=40.0, choppiness=1.0, amplitude=1.0),
    # The spectral sea: its bound is the tiles' extremes at the frame's time.
    "spectrum at the horizon": Pose(pitch=0.0, height=2.0, wind_speed=12.0, choppiness=1.0),
    "spectrum looking down": Pose(pitch=-90.0, height=30.0, wind_speed=20.0, choppiness=1.0),
    "spectrum, gale, from inside the volume": Pose(height=1.0, pitch=-10.0, wind_speed=20.0,
                                                   choppiness=1.0),
    "spectrum from high up": Pose(height=2000.0, pitch=-30.0, wind_speed=10.0, far=1e6,
                                  choppiness=0.8),
    "spectrum under water": Pose(height=-4.0, pitch=35.0, wind_speed=8.0, choppiness=1.0),
    "spectrum, calm, far from the origin": Pose(distance=5e5, height=3.0, wind_speed=3.0,
                                                choppiness=0.5),
    # Low cameras over a rough sea: the grid is built for the volume fitted to the sea's spread.
    "spectrum, moderate breeze, low camera": Pose(height=4.0, pitch=-4.0, fov=40.0,
                                                  wind_speed=6.7, choppiness=0.6),
    "spectrum, gale, low camera": Pose(height=4.0, pitch=-4.0, fov=40.0, wind_speed=19.0,
                                       choppiness=1.0),
    "spectrum, gale, camera 2 m up": Pose(height=2.0, pitch=-2.0, fov=40.0, wind_speed=19.0,
                                          choppiness=1.0),
    # A fitted grid whose whole border lay above the screen: each border segment is outside
    # V_cam, and the grid covered nothing (found by the random poses).
    "fitted border wholly above the screen": Pose(
        height=1.4855, pitch=-76.640625, yaw=-180.0, roll=-180.0, ortho_scale=0.1, near=1e-6,
        far=3.1059, aspect=0.98923, shift_x=-0.5, shift_y=-0.5, level=-100.0, amplitude=1.9608,
        octaves=1, roughness=0.0, time=2662860.6454541944, resolution=(2, 2), method="exact",
        wind_direction=2.7716868186470007),
}


NOT_VISIBLE = {
    "straight up": Pose(pitch=90.0),
    "deep, looking down": Pose(height=-5.0, pitch=-60.0),
    "high, looking up": Pose(height=100.0, pitch=10.0, fov=10.0),
    "far clip short of the water": Pose(height=100.0, pitch=-90.0, far=50.0),
}


@pytest.mark.parametrize("name", NAMED)
def test_named_pose(name):
    camera, result = check_pose(NAMED[name])
    assert result.visible


@pytest.mark.parametrize("name", NOT_VISIBLE)
def test_not_visible(name):
    camera, result = check_pose(NOT_VISIBLE[name])
    assert not result.visible and result.positions.shape == (0, 3)


@pytest.mark.slow
def test_largest_grid():
    """2049 x 2049 vertices: every property but popping at full size (ray test on a coarse grid)."""
    pose = Pose(pitch=-8.0, height=6.0, resolution=(2049, 2049), amplitude=1.0)
    camera, result = check_pose(pose, popping=False)
    assert result.positions.shape == (2049 * 2049, 3)


LOW_SHOTS = {  # wind m/s: a camera 4 m up looking 4 degrees down, the sea choppy
    6.7: Pose(height=4.0, pitch=-4.0, fov=40.0, wind_speed=6.7, choppiness=0.6,
              resolution=(33, 65), time=2.5),
    12.3: Pose(height=6.0, pitch=-4.0, fov=40.0, wind_speed=12.3, choppiness=0.8,
               resolution=(33, 65), time=2.5),
}


@pytest.mark.parametrize("wind", LOW_SHOTS)
def test_the_fitted_volume_puts_the_vertices_in_view(wind):
    """The true bounds of a spectral sea sum every band's extreme; a low camera's grid built for
    them spends many vertices under the screen. Built for the fitted volume more show."""
    pose = LOW_SHOTS[wind]
    camera, fitted = check_pose(pose)
    full = Extent.true_bounds(pose.height_field(), pose.time)
    _, bounded = pose.build(extent=full)
    assert fitted.fitted and fitted.extent.upper < 0.5 * full.upper
    assert fitted.efficiency > max(0.75, 1.15 * bounded.efficiency), (bounded.efficiency,
                                                                      fitted.efficiency)


@pytest.mark.parametrize("wind", LOW_SHOTS)
def test_the_projector_stands_back_from_a_sea_reaching_under_the_camera(wind, monkeypatch,
                                                                      grids_anew):
    """Built for the true bounds, V_visible reaches under a low camera; a projector right above
    the camera would spend most of its span there. Its columns and rows follow the camera's
    screen (Projector.spacing), so even then more than a third of the vertices show; standing
    back shows more, and three fifths of them."""
    pose = LOW_SHOTS[wind]
    full = Extent.true_bounds(pose.height_field(), pose.time)
    _, back = check_pose(pose, extent=full)
    monkeypatch.setattr(projector, "_standing_back", lambda *args: 0.0)
    _, above = check_pose(pose, extent=full)
    assert back.efficiency > max(0.6, above.efficiency) and above.efficiency > 0.33, (
        above.efficiency, back.efficiency)


def test_no_standing_back_for_a_camera_upside_down_past_straight_down():
    """Its heading points behind its view: the steepest ray's angle against the heading wraps
    at 180°, and standing back along it would jump (found in review)."""
    pose = Pose(height=2.0, pitch=-60.0, roll=180.0, fov=120.0, amplitude=2.0, aspect=1.0,
                far=1e3)
    full = Extent.true_bounds(pose.height_field(), pose.time)
    _, result = check_pose(pose, extent=full)
    for eps in (-2e-7, 2e-7):
        _, moved = Pose(**{**pose.__dict__, "pitch": pose.pitch + eps}).build(extent=full)
        move, rounding = relative_moves(result, moved)
        assert float(np.max(move - rounding)) <= POP


def test_a_fitted_volume_that_misses_the_sea_is_not_kept(monkeypatch):
    """A volume too thin for the sea leaves a gap under the screen (the coverage check sees it);
    the border check turns it down and the true bounds are used."""
    pose = Pose(**{**LOW_SHOTS[6.7].__dict__, "time": 4.0})  # a crest under the screen's edge
    camera, thin = pose.build(extent=Extent(0.05, 0.05, 0.05, fitted=True))
    with pytest.raises(AssertionError, match="coverage"):
        check_coverage(camera, thin, pose.level, pose.height_field().bounds(pose.time)[0], n=33)
    assert not border_outside(camera, thin, pose.level)
    monkeypatch.setattr(displaceable_volume, "FIT_SIGMAS", (0.2,))
    camera, result = check_pose(pose)
    assert not result.fitted and result.visible


@pytest.mark.parametrize("wind", LOW_SHOTS)
def test_a_still_camera_s_grid_stays_still(wind):
    """The fitted volume depends on the settings, not the time: from a still camera the grid's
    points on S_base are the same every frame and the waves run through them (a volume fitted
    to the sea sampled in view changed from frame to frame, and the grid swam)."""
    pose = LOW_SHOTS[wind]
    grids = [Pose(**{**pose.__dict__, "time": t}).build()[1] for t in np.arange(0.0, 4.0, 0.25)]
    assert all(g.fitted for g in grids)
    for g in grids[1:]:
        assert np.array_equal(g.base, grids[0].base)
        assert not np.array_equal(g.positions, grids[0].positions)


def naive_projector(camera, level, bound, elevation, base_points):
    """§2.3's naive algorithm: the camera itself is the projector, no aiming."""
    return Projector.looking(camera.position, camera.right, camera.up, camera.forward,
                             camera.orthographic)


def test_suite_catches_the_naive_projector(monkeypatch):
    """The same checks reject §2.3's naive algorithm (camera as projector, whole screen, no range)
    on poses the real projector passes."""
    cases = ("exactly at the horizon", "looking up", "under water looking up", "inside the volume")
    for name in cases:
        check_pose(NAMED[name])  # the real projector passes
    monkeypatch.setattr(Projector, "with_range", lambda self, *args: self)
    caught = []
    for name in cases:
        pose = NAMED[name]
        try:
            with np.errstate(all="ignore"):  # its NaNs and infinities are what is being caught
                check_pose(pose, popping=False, aim=naive_projector)
        except (AssertionError, ValueError) as e:  # ValueError: NaN reached an integer cast
            caught.append((name, str(e).split(":")[0]))
    assert [name for name, _ in caught] == list(cases), caught
    assert any(kind == "backfiring" for _, kind in caught), caught


def test_camera_is_not_modified():
    pose = NAMED["rolled 45 looking down"]
    camera = pose.camera()
    view, proj = camera.view.copy(), camera.proj.copy()
    pose.build(camera)
    assert np.array_equal(camera.view, view) and np.array_equal(camera.proj, proj)
    assert isinstance(camera, Camera)
