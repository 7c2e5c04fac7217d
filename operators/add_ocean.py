"""Add Ocean: the ocean object at the 3D cursor, plus a sky and a sun if the scene has none."""

import bpy

from ..shaders import materials as shader_materials
from ..shaders import sky
from ..shaders.nodes import TAG
from .bridge import companions, frame, handlers, settings

# A new ocean is the spectral sea at this Beaufort force: a moderate breeze, 1 m waves.
DEFAULT_FORCE = 4


def has_sun(scene):
    return any(o.type == "LIGHT" and o.data.type == "SUN" for o in scene.objects)


class PROJGRID_OT_add_ocean(bpy.types.Operator):
    """Add an infinite projected-grid ocean; its water level is the 3D cursor's height"""

    bl_idname = "projgrid.add_ocean"
    bl_label = "Add Ocean"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return context.scene is not None and context.mode == "OBJECT"

    def execute(self, context):
        scene = context.scene
        collection = context.collection or scene.collection
        mesh = bpy.data.meshes.new("Ocean")
        mesh[TAG] = True
        mesh.materials.append(shader_materials.material())
        obj = bpy.data.objects.new("Ocean", mesh)
        obj.projgrid.is_ocean = True
        obj.location = scene.cursor.location
        settings.apply_sea_state(obj.projgrid, DEFAULT_FORCE)
        with settings.batch():
            obj.projgrid.noise_from_wind = True  # the noise, if chosen, follows the wind too
        # Grid vertices do not correspond across frames: no deformation motion blur.
        if hasattr(obj, "cycles"):
            obj.cycles.use_deform_motion = False
        collection.objects.link(obj)
        companions.ensure_companions(obj)

        added = []
        if scene.world is None:
            scene.world = sky.world()
            added.append("a sky world")
        if not has_sun(scene):
            sky.sun(collection)
            added.append("a sun lamp")

        for other in context.view_layer.objects:
            other.select_set(False)
        obj.select_set(True)
        context.view_layer.objects.active = obj

        message = handlers.ensure_lock_interface(scene)
        if message:
            self.report({"INFO"}, message)
        if added:
            self.report({"INFO"}, "Added " + " and ".join(added))
        problem = frame.update_ocean(obj, scene, context.evaluated_depsgraph_get())
        if problem:
            self.report({"WARNING"}, f"Ocean added but not built: {problem}")
        return {"FINISHED"}
