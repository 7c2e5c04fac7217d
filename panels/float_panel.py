"""The 3D View sidebar tab "Ocean": the Float panel of the active object, a mesh that is not an
ocean: Float Selected, or how it floats and Unfloat Selected."""

import bpy

from ..operators.bridge import floats, scene


def float_lines(obj):
    """The panel's status line for `obj` (plain strings, so tests can check them)."""
    ocean = floats.floating_on(obj)
    if ocean is None:
        why = floats.refusal(obj)
        return [("INFO", f"Cannot float: {why}")] if why else []
    if obj.parent is not None:
        return [("ERROR", "Not floating while it has a parent: clear it, or unfloat")]
    if not floats.follows(obj):
        return [("ERROR", f"Its {floats.CONSTRAINT!r} constraint is missing or muted: "
                          "unfloat and float it again")]
    return [("MOD_OCEAN", f"Rides {ocean.name!r}")]


class VIEW3D_PT_projgrid_float(bpy.types.Panel):
    bl_label = "Float"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Ocean"

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and obj.type == "MESH" and not scene.is_ocean(obj)

    def draw(self, context):
        layout, obj = self.layout, context.active_object
        for icon, text in float_lines(obj):
            layout.label(text=text, icon=icon)
        if floats.floating_on(obj) is None:
            layout.operator("projgrid.float_selected", icon="MOD_OCEAN")
            return
        layout.use_property_split = True
        layout.use_property_decorate = True
        s = obj.projgrid_float
        layout.prop(s, "ocean")
        layout.prop(s, "sits")
        layout.prop(s, "density" if s.sits == "DENSITY" else "draft")
        layout.prop(s, "response")
        layout.operator("projgrid.unfloat_selected", icon="X")
