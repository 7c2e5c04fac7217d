"""Each core test starts with no grid kept (grid_points.KEPT): a test that patches how grids are
made (the projector, its spacing, the volume) builds them anew."""

import pytest

from projgrid_addon import grid_points


@pytest.fixture(autouse=True)
def no_grid_kept(monkeypatch):
    grid_points._KEPT.clear()
    yield
    grid_points._KEPT.clear()


@pytest.fixture
def grids_anew(monkeypatch):
    """No grid kept at all: for a test that patches how grids are made part way through."""
    monkeypatch.setattr(grid_points, "KEPT", 0)
