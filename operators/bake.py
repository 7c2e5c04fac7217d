"""Bake: the ocean's frames written into a USD mesh cache that it then plays, so the file renders
on farms that run no scripts and in other packages (operators/bridge/bake.py). From the
interface it runs frame by frame, Esc cancelling; from a script or the command line, at once."""

import os

import bpy
from bpy.props import BoolProperty, IntProperty, StringProperty

from .bridge import bake, scene


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
    interactive: BoolProperty(options={"HIDDEN", "SKIP_SAVE"})  # invoked: frame by frame

    @classmethod
    def poll(cls, context):
        obj = scene.active_ocean(context)
        return obj is not None and obj.library is None

    def invoke(self, context, event):
        if not self.properties.is_property_set("frame_start"):
            self.frame_start = context.scene.frame_start
        if not self.properties.is_property_set("frame_end"):
            self.frame_end = context.scene.frame_end
        self.interactive = True
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}

    def execute(self, context):
        obj = scene.active_ocean(context)
        print(f"Projected Grid Ocean: baking {obj.name!r}, frames {self.frame_start}-"
              f"{self.frame_end}, into {self.filepath}", flush=True)
        try:
            self._job = bake.Bake(context, obj, self.filepath, self.frame_start,
                                  self.frame_end)
            if not self.interactive or context.window is None:
                while self._job.step():
                    pass
                return self._finish(context)
        except (ValueError, RuntimeError) as err:
            return self._failed(err)
        self.interactive = False  # a redo (F9, Repeat Last) runs at once
        self._writing = False
        wm = context.window_manager
        self._timer = wm.event_timer_add(0.001, window=context.window)
        wm.modal_handler_add(self)
        self._status(context, f"frame {self.frame_start}")
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        if event.type == "ESC" and event.value == "PRESS" and not self._writing:
            self.cancel(context)
            self.report({"INFO"}, f"Bake cancelled at frame {self._job.next}: the ocean is "
                        "live and no file was written")
            return {"CANCELLED"}
        if event.type != "TIMER":
            return {"RUNNING_MODAL"}  # the interface waits for the bake, as for a render
        try:
            if self._writing:
                self._end(context)
                return self._finish(context)
            more = self._job.step()
        except Exception as err:  # noqa: BLE001 (the job has cleaned up; the user is told)
            self._end(context)
            return self._failed(err)
        if more:
            self._status(context, f"frame {self._job.next}")
        else:  # shown before the export blocks the interface
            self._writing = True
            self._status(context, "writing the USD file", cancel=False)
        return {"RUNNING_MODAL"}

    def cancel(self, context):
        """Esc, or Blender quitting or loading a file mid-bake: the ocean left live."""
        try:
            self._job.cancel()
        finally:
            self._end(context)

    def _status(self, context, what, cancel=True):
        job = self._job
        context.workspace.status_text_set(
            f"Baking {job.obj.name!r}: {what} of {self.frame_start}-{self.frame_end} "
            f"({job.done:.0%})" + (", Esc to cancel" if cancel else ""))

    def _end(self, context):
        if self._timer is not None:
            context.window_manager.event_timer_remove(self._timer)
            self._timer = None
            context.workspace.status_text_set(None)

    def _failed(self, err):
        self.report({"ERROR"}, f"Bake not made, the ocean is live: {err}")
        return {"CANCELLED"}

    def _finish(self, context):
        path, warning = self._job.finish()
        obj = self._job.obj
        size = os.path.getsize(path) / 2**20
        self.report({"INFO"}, f"Baked {obj.name!r}, frames {self.frame_start}-{self.frame_end}, "
                    f"into {path} ({size:.0f} MB); it now plays the bake")
        if warning:
            self.report({"WARNING"}, f"Baked {obj.name!r}: {warning}")
        return {"FINISHED"}
