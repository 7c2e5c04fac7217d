"""Operators, one per file."""

import bpy

from .add_ocean import PROJGRID_OT_add_ocean
from .live_preview import PROJGRID_OT_live_preview

classes = (PROJGRID_OT_add_ocean, PROJGRID_OT_live_preview)

# Registers in order and unregisters in exact reverse.
register, unregister = bpy.utils.register_classes_factory(classes)
