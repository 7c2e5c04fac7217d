"""Grids kept by what they are made of (grid_points.KEPT): a camera that moves across the sea
keeps its grid's projector, spacing and band limits, and a frame's grid is the same whatever
grids were built before it."""

import numpy as np

from projgrid_addon import build_grid, perspective, sea_state
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
    from projgrid_addon import grid_points
    grid_points._KEPT.clear()
    for x, height in ((0.0, 5.0), (-260.0, 5.0), (-250.0, 7.0)):
        _build(waves, _camera(x, 990.0, height), t=1.0)
    after = _build(waves, _camera(-250.0, 1000.5))
    assert np.array_equal(after.positions, alone.positions)
    assert np.array_equal(after.lod, alone.lod)
