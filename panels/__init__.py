"""Panels."""

import bpy

from .float_panel import VIEW3D_PT_projgrid_float
from .ocean_panel import (
    VIEW3D_MT_projgrid_sea_state,
    VIEW3D_PT_projgrid_bake,
    VIEW3D_PT_projgrid_effects,
    VIEW3D_PT_projgrid_grid,
    VIEW3D_PT_projgrid_look,
    VIEW3D_PT_projgrid_ocean,
    VIEW3D_PT_projgrid_status,
    VIEW3D_PT_projgrid_waves,
)

classes = (VIEW3D_MT_projgrid_sea_state, VIEW3D_PT_projgrid_ocean, VIEW3D_PT_projgrid_waves,
           VIEW3D_PT_projgrid_grid, VIEW3D_PT_projgrid_look, VIEW3D_PT_projgrid_effects,
           VIEW3D_PT_projgrid_bake, VIEW3D_PT_projgrid_status, VIEW3D_PT_projgrid_float)

# Registers in order and unregisters in exact reverse.
register, unregister = bpy.utils.register_classes_factory(classes)
