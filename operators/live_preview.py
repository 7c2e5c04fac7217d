"""Live Preview: a modal operator that rebuilds the ocean from the 3D view being looked at.

A viewport convenience only: the persistent handlers own correctness (they run in background mode
and in renders, where modal operators never do). The grid follows the view's own matrices, or the
scene camera in camera view, whenever the view or the frame changes.
"""

import bpy
import numpy as np

from .bridge import frame, scene
from .bridge.state import RUNTIME

STATUS = "Ocean live preview: Esc or right-click to stop"


def view_matrices(space):
    """(view, proj) of a 3D view, or None in camera view (the scene camera is used then)."""
    rv3d = space.region_3d
    if rv3d.view_perspective == "CAMERA":
        return None
    return (np.array(rv3d.view_matrix, dtype=np.float64),
            np.array(rv3d.window_matrix, dtype=np.float64))


def rebuild(op, context):
    """Point the viewport rebuild at the view and rebuild every ocean (unchanged input: no work)."""
    RUNTIME.live_view = view_matrices(op.space)
    the_scene = context.scene
    depsgraph = context.evaluated_depsgraph_get()
    for app in scene.appearances(the_scene):
        frame.update_appearance(app, the_scene, depsgraph, render=False, frame_change=False)


def finish(op, context):
    RUNTIME.live_view = None
    if op._timer is not None:
        context.window_manager.event_timer_remove(op._timer)
        op._timer = None
    if context.workspace is not None:
        context.workspace.status_text_set(None)


class PROJGRID_OT_live_preview(bpy.types.Operator):
    """Rebuild the ocean from this 3D view while it moves (Esc or right-click to stop)"""

    bl_idname = "projgrid.live_preview"
    bl_label = "Live Preview"

    _timer = None

    @classmethod
    def poll(cls, context):
        return context.area is not None and context.area.type == "VIEW_3D"

    def invoke(self, context, event):
        if not scene.appearances(context.scene):
            self.report({"ERROR"}, "No ocean in this scene: use Add Ocean first")
            return {"CANCELLED"}
        self.space = context.space_data
        wm = context.window_manager
        self._timer = wm.event_timer_add(1.0 / 30.0, window=context.window)
        wm.modal_handler_add(self)
        context.workspace.status_text_set(STATUS)
        rebuild(self, context)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        if event.type in {"ESC", "RIGHTMOUSE"} and event.value == "PRESS":
            finish(self, context)
            return {"CANCELLED"}
        if RUNTIME.rendering:  # step aside: the render handlers own the mesh
            return {"PASS_THROUGH"}
        if event.type == "TIMER":
            try:
                rebuild(self, context)
            except ReferenceError:  # the 3D view was closed
                finish(self, context)
                return {"CANCELLED"}
        return {"PASS_THROUGH"}

    def cancel(self, context):
        """Called when Blender ends the operator itself (file load, window closed)."""
        finish(self, context)
