"""Unfloat Selected: the selected floating objects as they were before Float Selected."""

import bpy

from .bridge import floats, frame, scene


class PROJGRID_OT_unfloat_selected(bpy.types.Operator):
    """Stop the selected objects riding the waves: our constraint and empty removed, each
    where its own animation places it"""

    bl_idname = "projgrid.unfloat_selected"
    bl_label = "Unfloat Selected"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return any(floats.floating_on(obj) is not None for obj in context.selected_objects)

    def execute(self, context):
        oceans = set()
        for obj in context.selected_objects:
            ocean = floats.floating_on(obj)
            if ocean is not None:
                floats.unfloat_object(obj)
                oceans.add(ocean)
        scene.drop_caches()
        for ocean in oceans:
            frame.update_ocean(ocean, context.scene, context.evaluated_depsgraph_get())
        self.report({"INFO"}, "The selected objects float no more")
        return {"FINISHED"}
