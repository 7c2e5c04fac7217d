"""`obj.projgrid_float`: how a mesh object of the user's floats on an ocean (floats.py), all
animatable and overridable, registered on Object."""

import bpy
from bpy.props import EnumProperty, FloatProperty, PointerProperty

from ...projgrid_addon import floating
from . import frame, scene, settings
from .settings import OVERRIDABLE


def _changed(self, context):
    """A float's setting changed: the scene's facts anew (what floats), its ocean's frame."""
    scene.drop_caches()
    for ocean in scene.ocean_objects(context.scene):
        frame.update_ocean(ocean, context.scene, context.evaluated_depsgraph_get())


class FloatSettings(bpy.types.PropertyGroup):
    ocean: PointerProperty(type=bpy.types.Object, name="Ocean",
                           poll=lambda _, obj: scene.is_ocean(obj), override=OVERRIDABLE,
                           update=_changed,
                           description="The ocean this object rides (none: it does not float)")
    follower: PointerProperty(type=bpy.types.Object, options={"HIDDEN"}, override=OVERRIDABLE,
                              description="Our empty that carries the object onto the waves")
    sits: EnumProperty(
        name="Sits", default="DENSITY", update=_changed, override=OVERRIDABLE,
        description="How deep the object sits in the water",
        items=[("DENSITY", "By Density", "From its density and volume (Archimedes)"),
               ("DRAFT", "By Draft", "At a draft set by hand")])
    density: FloatProperty(
        name="Density", default=500.0, min=1.0, soft_max=floating.RHO_WATER * 1.5, max=2e4,
        update=_changed, override=OVERRIDABLE,
        description="kg/m³: its mass over its volume (sea water 1025; denser ones sit awash)")
    draft: FloatProperty(name="Draft", default=0.5, min=0.0, soft_max=20.0, unit="LENGTH",
                         update=_changed, override=OVERRIDABLE,
                         description="How far its lowest point sits under the water")
    response: FloatProperty(
        name="Response", default=1.0, min=0.0, soft_max=2.0, max=5.0, update=_changed,
        override=OVERRIDABLE,
        description="How far it follows the water's tilt (pitch and roll): 1 as the waves "
                    "over its footprint, 0 level")


register, unregister = settings.on_objects("projgrid_float", FloatSettings)
