"""Add Ocean: the ocean object at the 3D cursor, plus a sky and a sun if the scene has none."""

import bpy

from ..projgrid_addon import sea_states
from ..projgrid_addon.bridge import companions, frame, handlers, settings
from ..shaders import sky, water
from ..shaders.nodes import TAG

# A new ocean is the spectral sea at this Beaufort force: a moderate breeze, 1 m waves.
DEFAULT_FORCE = 4


def apply_sea_state(s, force):
    """Set the settings `s` (obj.projgrid) to Beaufort `force`, with one rebuild after (by the
    caller): the spectral sea's wind, fetch, choppiness and swell, and the noise's height and
    wavelength for the same sea at the noise's own octaves and roughness."""
    preset = sea_states.sea_state(force, s.wind_direction)
    with settings.batch():
        s.height_source = "SPECTRUM"
        s.wind_speed, s.fetch, s.choppiness = preset.wind_speed, preset.fetch, preset.choppiness
        s.swell_height, s.swell_period = preset.swell_height, preset.swell_period
        s.swell_direction = sea_states.swell_direction(s.wind_direction)
        s.amplitude, s.wave_scale = sea_states.noise_waves(
            preset.wind_speed, preset.fetch, s.spectrum, s.octaves, s.roughness)
    return preset


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
        mesh.materials.append(water.material())
        obj = bpy.data.objects.new("Ocean", mesh)
        obj.projgrid.is_ocean = True
        obj.location = scene.cursor.location
        apply_sea_state(obj.projgrid, DEFAULT_FORCE)
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
