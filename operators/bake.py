"""Bake: the ocean's frames written into a USD mesh cache that it then plays, so the file renders
on farms that run no scripts and in other packages (projgrid_addon/bridge/bake.py)."""

import os

import bpy
from bpy.props import IntProperty, StringProperty

from ..projgrid_addon.bridge import bake, scene


class PROJGRID_OT_bake(bpy.types.Operator):
    """Write the ocean as the scene camera sees it, frame by frame, into a USD file and play
    that instead of rebuilding it: the file then renders without the extension"""

    bl_idname = "projgrid.bake"
    bl_label = "Bake Ocean"
    bl_options = {"REGISTER", "UNDO"}

    filepath: StringProperty(name="File", subtype="FILE_PATH", default="//ocean_bake.usdc",
                             description="The USD file to write (.usdc, .usd or .usda)",
                             options={"PATH_SUPPORTS_BLEND_RELATIVE"})
    filter_glob: StringProperty(default="*.usd;*.usdc;*.usda", options={"HIDDEN"})
    frame_start: IntProperty(name="Start", description="First frame to bake", default=1)
    frame_end: IntProperty(name="End", description="Last frame to bake", default=250)

    @classmethod
    def poll(cls, context):
        obj = scene.active_ocean(context)
        return obj is not None and obj.library is None

    def invoke(self, context, event):
        if not self.properties.is_property_set("frame_start"):
            self.frame_start = context.scene.frame_start
        if not self.properties.is_property_set("frame_end"):
            self.frame_end = context.scene.frame_end
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}

    def execute(self, context):
        obj = scene.active_ocean(context)
        print(f"Projected Grid Ocean: baking {obj.name!r}, frames {self.frame_start}-"
              f"{self.frame_end}, into {self.filepath}", flush=True)
        try:
            path, warning = bake.bake(context, obj, self.filepath, self.frame_start,
                                      self.frame_end)
        except (ValueError, RuntimeError) as err:
            self.report({"ERROR"}, f"Bake not made, the ocean is live: {err}")
            return {"CANCELLED"}
        size = os.path.getsize(path) / 2**20
        self.report({"INFO"}, f"Baked {obj.name!r}, frames {self.frame_start}-{self.frame_end}, "
                    f"into {path} ({size:.0f} MB); it now plays the bake")
        if warning:
            self.report({"WARNING"}, f"Baked {obj.name!r}: {warning}")
        return {"FINISHED"}
