"""Sea State: an ocean's wind, fetch, choppiness and swell set to a Beaufort force at once."""

import bpy
from bpy.props import BoolProperty, IntProperty

from ..projgrid_addon import sea_states, spectrum
from ..shaders import sky
from .bridge import frame, scene, settings


class PROJGRID_OT_sea_state(bpy.types.Operator):
    """Set the ocean's waves to a force of the Beaufort scale: its wind, fetch, choppiness and
    swell (and the noise's height and wavelength for the same sea)"""

    bl_idname = "projgrid.sea_state"
    bl_label = "Sea State"
    bl_options = {"REGISTER", "UNDO"}

    beaufort: IntProperty(name="Beaufort", description="Beaufort force, 0 (calm) to 10 (storm)",
                          default=4, min=0, max=10)
    weather: BoolProperty(
        name="Weather", default=True,
        description="Also cloud Add Ocean's sky over and dim its sun as the force asks: clear "
                    "to a fresh breeze, a low dark overcast from a gale on")

    @classmethod
    def poll(cls, context):
        obj = scene.active_ocean(context)
        return obj is not None and obj.library is None

    def execute(self, context):
        obj = scene.active_ocean(context)
        source = obj.projgrid.height_source
        preset = settings.apply_sea_state(obj.projgrid, self.beaufort)
        obj.projgrid.height_source = source  # the waves' kind is the user's
        if self.weather:
            sky.weather(context.scene, sea_states.overcast(self.beaufort))
        frame.update_ocean(obj, context.scene, context.evaluated_depsgraph_get())
        height = spectrum.significant_height(spectrum.SeaState(
            wind_speed=preset.wind_speed, fetch=preset.fetch, spectrum=obj.projgrid.spectrum))
        self.report({"INFO"}, f"Beaufort {self.beaufort} ({preset.name}): wind "
                    f"{preset.wind_speed:g} m/s, significant wave height {height:.2g} m")
        return {"FINISHED"}
