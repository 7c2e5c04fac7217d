"""Float Selected: the selected mesh objects ride the scene's ocean (floats.py)."""

import bpy

from .bridge import floats, frame, scene


class PROJGRID_OT_float_selected(bpy.types.Operator):
    """Make the selected mesh objects ride the ocean's waves (the active ocean, else the
    scene's first): their own animation stays theirs, the waves lift and tilt them"""

    bl_idname = "projgrid.float_selected"
    bl_label = "Float Selected"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return scene.active_ocean(context) is not None and any(
            floats.refusal(obj) is None for obj in context.selected_objects)

    def execute(self, context):
        ocean = scene.active_ocean(context)
        made, refused = [], []
        for obj in context.selected_objects:
            if obj == ocean:
                continue
            why = floats.refusal(obj)
            if why is None:
                floats.float_object(obj, ocean, context.scene)
                made.append(obj.name)
            else:
                refused.append(f"{obj.name!r} ({why})")
        scene.drop_caches()
        frame.update_ocean(ocean, context.scene, context.evaluated_depsgraph_get())
        if refused:
            self.report({"WARNING"}, "Not floated: " + ", ".join(refused))
        if not made:
            return {"CANCELLED"}
        self.report({"INFO"}, f"{len(made)} object(s) float on {ocean.name!r}: "
                    + ", ".join(made))
        return {"FINISHED"}
