"""Grids kept by what they are made of (grid_points.KEPT): a camera that moves across the sea
keeps its grid's projector, spacing and band limits, and a frame's grid is the same whatever
grids were built before it."""

from dataclasses import replace

import numpy as np
import pytest

from projgrid_addon import Camera, build_grid, grid_points, perspective, sea_state
from projgrid_addon.camera import view_matrix
from projgrid_addon.projector import Projector
from projgrid_addon.spectral_field import SpectralField
from projgrid_addon.spectrum import SeaState

PROJ = perspective(np.radians(28.0), 16 / 9, 0.1, 2e4)


def _gale():
    p = sea_state(8)
    return SpectralField(SeaState(wind_speed=p.wind_speed, fetch=p.fetch),
                         choppiness=p.choppiness)


def _camera(x, y, height=5.0, heading=37.0, pitch=-4.0):
    """A camera at (x, y, height) turned as given: its turn the same wherever it stands (as a
    Blender camera's, whose rotation is kept apart from its place)."""
    h, p = np.radians(heading), np.radians(pitch)
    forward = np.array([np.cos(h) * np.cos(p), np.sin(h) * np.cos(p), np.sin(p)])
    right = np.array([np.sin(h), -np.cos(h), 0.0])
    return view_matrix((x, y, height), right, np.cross(right, forward), forward), PROJ


def _build(waves, camera, t=3.0):
    return build_grid(camera, waves, time=t, resolution=(65, 129))


def _spacings(monkeypatch):
    made = []
    spacing = Projector.spacing

    def counted(self, *args):
        made.append(1)
        return spacing(self, *args)
    monkeypatch.setattr(Projector, "spacing", counted)
    return made


def test_a_camera_moving_across_the_sea_keeps_its_grid(monkeypatch):
    """Moved 20 m along x and y (its distance from the mesh's origin, which the span's float32
    margin takes, within one of grid_points._slack's steps), the camera's grid is the first
    one's moved with it: no new spacing, the same band limits and span, the points the first's
    plus the move; at another height it is made anew."""
    waves = _gale()
    made = _spacings(monkeypatch)
    first = _build(waves, _camera(2950.0, 20.25))
    count = len(made)
    moved = _build(waves, _camera(2970.0, 40.75), t=4.0)
    assert len(made) == count
    assert np.array_equal(moved.lod, first.lod)
    assert moved.projector.span == first.projector.span
    assert np.allclose(moved.projector.position, first.projector.position + (20.0, 20.5, 0.0),
                       rtol=0.0, atol=1e-9)
    shift = np.reshape((20.0, 20.5), (2, 1))
    assert np.allclose(moved.base.reshape(2, -1), first.base.reshape(2, -1) + shift,
                       rtol=1e-12, atol=1e-9)
    _build(waves, _camera(2970.0, 40.75, height=6.0))
    assert len(made) > count


def test_a_grid_is_the_same_whatever_was_built_before():
    """Built alone or after grids of other places, heights and times, a frame's grid and its
    surface are bit-identical (a farm renders frames alone and out of order)."""
    waves = _gale()
    alone = _build(waves, _camera(-250.0, 1000.5))
    grid_points._KEPT.clear()
    for x, height in ((0.0, 5.0), (-260.0, 5.0), (-250.0, 7.0)):
        _build(waves, _camera(x, 990.0, height), t=1.0)
    after = _build(waves, _camera(-250.0, 1000.5))
    assert np.array_equal(after.positions, alone.positions)
    assert np.array_equal(after.lod, alone.lod)


@pytest.mark.parametrize("what", ["lens", "origin", "band limit", "elevation", "side"])
def test_a_grid_made_of_other_things_is_not_taken(what):
    """A camera's grid built alone, and again after a grid of the same camera made of one other
    thing the key holds (its lens; the mesh's origin 9 km away, which the span's float32
    margin takes; no band limit; the projector's elevation; the volume's sideways reach): the
    same, bit for bit."""
    waves = _gale()
    camera = _camera(-250.0, 1000.5)
    alone = build_grid(camera, waves, time=3.0, resolution=(65, 129))
    grid_points._KEPT.clear()
    other = dict(time=3.0, resolution=(65, 129), extent=alone.extent)
    if what == "lens":
        camera_other = (camera[0], perspective(np.radians(40.0), 16 / 9, 0.1, 2e4))
    else:
        camera_other = camera
        other.update({"origin": {"origin": np.array([9000.0, 0.0, 0.0])},
                      "band limit": {"band_limit": False},
                      "elevation": {"projector_elevation": 20.0},
                      "side": {"extent": replace(alone.extent, side=alone.extent.side + 1.0)},
                      }[what])
    build_grid(camera_other, waves, **other)
    after = build_grid(camera, waves, time=3.0, resolution=(65, 129), extent=alone.extent)
    assert np.array_equal(after.positions, alone.positions)
    assert np.array_equal(after.lod, alone.lod)


def test_a_camera_whose_place_returns_with_noise_keeps_its_grid(monkeypatch):
    """Cameras whose height returns from the float64 view with a few ulps of noise (5.1 m at
    these places) keep the grid: the canonical camera stands at the height in float32."""
    waves = _gale()
    heights = {Camera(*_camera(x, y, 5.1)).position[2] for x, y in ((2950.3, 20.7),
                                                                      (2990.9, 41.1))}
    assert len(heights) == 2 and 5.1 not in heights  # each off by some ulps
    made = _spacings(monkeypatch)
    _build(waves, _camera(2950.3, 20.7, 5.1))
    count = len(made)
    _build(waves, _camera(2990.9, 41.1, 5.1))
    assert len(made) == count


def test_a_step_of_the_span_s_margin_moves_the_grid_far_less_than_a_pixel():
    """16 km from the mesh's origin, a camera moved 2 mm across a step of the span's float32
    margin (grid_points._slack, 64 m there) moves no vertex on the screen by more than 0.003 px
    of a 1920 px wide picture (0.0022 px; a 64th of the octave's step, 256 m, 0.0044 px)."""
    waves = _gale()
    step = grid_points._slack(16000.0)
    screens = []
    for x in (step - 0.001, step + 0.001):
        view, proj = _camera(x, 0.0)
        result = build_grid((view, proj), waves, time=3.0, resolution=(65, 129),
                            origin=np.zeros(3))
        x0, y0 = result.base.reshape(2, -1)
        clip = np.stack([x0, y0, np.zeros_like(x0), np.ones_like(x0)], -1) @ (proj @ view).T
        screens.append(clip[:, :2] / clip[:, 3:] * 960.0)
        if len(screens) == 1:
            first = result
    assert grid_points._slack(step + 0.001) > grid_points._slack(step - 0.001)
    shown = (np.abs(screens[0]) <= 960.0).all(axis=1) & (first.base.reshape(2, -1)[0] > -1e9)
    moved = np.abs(screens[1] - screens[0])[shown].max()
    assert moved < 0.003, moved
