"""Panels."""

import bpy

from .ocean_panel import VIEW3D_PT_projgrid_ocean

classes = (VIEW3D_PT_projgrid_ocean,)

# Registers in order and unregisters in exact reverse.
register, unregister = bpy.utils.register_classes_factory(classes)
