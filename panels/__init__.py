"""Panels."""

import bpy

from .ocean_panel import VIEW3D_PT_projgrid_ocean

classes = (VIEW3D_PT_projgrid_ocean,)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)


def unregister():
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
