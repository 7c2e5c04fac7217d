"""Operators, one per file."""

import bpy

from .add_ocean import PROJGRID_OT_add_ocean
from .bake import PROJGRID_OT_bake
from .bake_free import PROJGRID_OT_bake_free
from .float_selected import PROJGRID_OT_float_selected
from .live_preview import PROJGRID_OT_live_preview
from .sea_state import PROJGRID_OT_sea_state
from .unfloat_selected import PROJGRID_OT_unfloat_selected

classes = (PROJGRID_OT_add_ocean, PROJGRID_OT_live_preview, PROJGRID_OT_sea_state,
           PROJGRID_OT_bake, PROJGRID_OT_bake_free, PROJGRID_OT_float_selected,
           PROJGRID_OT_unfloat_selected)

# Registers in order and unregisters in exact reverse.
register, unregister = bpy.utils.register_classes_factory(classes)
