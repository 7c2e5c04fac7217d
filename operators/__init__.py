"""Operators, one per file."""

import bpy

from .add_ocean import PROJGRID_OT_add_ocean
from .live_preview import PROJGRID_OT_live_preview
from .sea_state import PROJGRID_OT_sea_state

classes = (PROJGRID_OT_add_ocean, PROJGRID_OT_live_preview, PROJGRID_OT_sea_state)

# Registers in order and unregisters in exact reverse.
register, unregister = bpy.utils.register_classes_factory(classes)
