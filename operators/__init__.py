"""Operators, one per file."""

import bpy

from .add_ocean import PROJGRID_OT_add_ocean
from .live_preview import PROJGRID_OT_live_preview

classes = (PROJGRID_OT_add_ocean, PROJGRID_OT_live_preview)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)


def unregister():
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
