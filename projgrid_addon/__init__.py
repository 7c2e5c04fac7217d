"""Projected-grid ocean core (Johanson 2004), NumPy only: no bpy is imported here."""

from . import memory
from .band_limit import octave_weights
from .camera import Camera, look_at, orthographic, perspective
from .displaceable_volume import bound_planes, visible_volume_points
from .height_field import HeightField
from .noise_tiles import NoiseTiles
from .projected_grid import (
    GridResult,
    build_grid,
    corner_uv,
    grid_topology,
    grid_uv,
    snapped_origin,
)
from .projector import Projector, aim_projector
from .sea_states import sea_state
from .spectral_field import SpectralField
from .spectrum import SeaState

__all__ = [
    "Camera", "GridResult", "corner_uv", "HeightField", "NoiseTiles", "Projector", "aim_projector",
    "bound_planes", "build_grid", "grid_topology", "grid_uv", "look_at", "memory", "octave_weights",
    "orthographic", "perspective", "SeaState", "sea_state", "snapped_origin", "SpectralField",
    "visible_volume_points",
]
