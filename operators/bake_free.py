"""Back to Live: an ocean that plays its bake is rebuilt every frame again (the file stays)."""

import bpy

from .bridge import baked, frame, scene


class PROJGRID_OT_bake_free(bpy.types.Operator):
    """Stop playing the bake: rebuild the ocean live again (the baked file is kept on disk)"""

    bl_idname = "projgrid.bake_free"
    bl_label = "Back to Live"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        obj = scene.active_ocean(context)
        return obj is not None and obj.library is None and baked.is_baked(obj)

    def execute(self, context):
        obj = scene.active_ocean(context)
        baked.free(obj)
        frame.update_ocean(obj, context.scene, context.evaluated_depsgraph_get())
        self.report({"INFO"}, f"{obj.name!r} is live again")
        return {"FINISHED"}
