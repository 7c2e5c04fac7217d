"""`obj.projgrid`: an ocean's settings (all animatable and overridable), registered on Object."""

from contextlib import contextmanager

import bpy
from bpy.props import (
    BoolProperty,
    EnumProperty,
    FloatProperty,
    FloatVectorProperty,
    IntProperty,
    IntVectorProperty,
    PointerProperty,
    StringProperty,
)

from ...projgrid_addon import effects, look, optics, sea_states
from ...projgrid_addon.sea_states import WAVE_SCALE_MIN
from . import frame
from .state import RUNTIME

OVERRIDABLE = {"LIBRARY_OVERRIDABLE"}  # a library override of an ocean keeps its own settings


@contextmanager
def batch():
    """Set several settings with one rebuild (by the caller, after): none per setting."""
    RUNTIME.batching = True
    try:
        yield
    finally:
        RUNTIME.batching = False


def apply_sea_state(s, force):
    """Set the settings `s` (obj.projgrid) to Beaufort `force`, with one rebuild after (by the
    caller): the spectral sea's wind, fetch, choppiness and swell, and the noise's height and
    wavelength for the same sea at the noise's own octaves and roughness."""
    preset = sea_states.sea_state(force, s.wind_direction)
    with batch():
        s.height_source = "SPECTRUM"
        s.wind_speed, s.fetch, s.choppiness = preset.wind_speed, preset.fetch, preset.choppiness
        s.swell_height, s.swell_period = preset.swell_height, preset.swell_period
        s.swell_direction = sea_states.swell_direction(s.wind_direction)
        s.amplitude, s.wave_scale = sea_states.noise_waves(
            preset.wind_speed, preset.fetch, s.spectrum, s.octaves, s.roughness)
    return preset


def _settings_changed(self, context):
    """Rebuild at once with the values just set (the evaluated copy is updated only later)."""
    obj = self.id_data
    if RUNTIME.batching:
        return
    if context.scene is not None and obj.projgrid.is_ocean and not RUNTIME.rendering:
        frame.update_ocean(obj, context.scene, context.evaluated_depsgraph_get(), settings=self)


def _mode(effect, description):
    return EnumProperty(
        name=effect.replace("_", " ").title(), default="AUTO", update=_settings_changed,
        description=description,
        override=OVERRIDABLE,
        items=(("AUTO", "Auto", "On when the scene calls for it, decided each frame"),
               ("ON", "On", "Always on"), ("OFF", "Off", "Always off: costs nothing")))


def _active_effects(self):
    """Bit set of the effects on for the last built frame (read-only `active_effects`)."""
    decisions = frame.last_effects(self.id_data)
    return sum(1 << i for i, e in enumerate(effects.EFFECTS) if decisions.get(e, (False,))[0])


def _int(name, description, default, lo, hi, soft_hi=None):
    return IntProperty(name=name, description=description, default=default, min=lo, max=hi,
                       soft_max=soft_hi or hi, update=_settings_changed, override=OVERRIDABLE)


def _float(name, description, default, lo, hi, soft_hi, unit="NONE", **kw):
    return FloatProperty(name=name, description=description, default=default, min=lo, max=hi,
                         soft_max=soft_hi, unit=unit, update=_settings_changed,
                         override=OVERRIDABLE, **kw)


class ProjectedGridSettings(bpy.types.PropertyGroup):
    """`obj.projgrid`: the ocean's settings (all animatable) and the effects on this frame."""

    is_ocean: BoolProperty(name="Is Ocean", default=False, options={"HIDDEN"})
    height_source: EnumProperty(
        name="Waves", default="PERLIN", update=_settings_changed, override=OVERRIDABLE,
        description="What makes the waves",
        items=(("SPECTRUM", "Spectrum", "The sea's wave spectrum for the wind, fetch and swell "
                "(JONSWAP; Horvath 2015), synthesised with FFTs: waves travel with the wind"),
               ("PERLIN", "Noise", "Fractal noise (the thesis's height field): each octave "
                "travels with the wind at its wave speed; the cheap path")))
    spectrum: EnumProperty(
        name="Spectrum", default="JONSWAP", update=_settings_changed, override=OVERRIDABLE,
        description="The wave spectrum of the wind's sea",
        items=(("JONSWAP", "JONSWAP", "A wind sea over its fetch; fully developed "
                "(Pierson-Moskowitz) at fetch 0"),
               ("PIERSON_MOSKOWITZ", "Pierson-Moskowitz", "A fully developed sea"),
               ("PHILLIPS", "Phillips", "Tessendorf's spectrum, as Blender's Ocean modifier")))
    wind_direction: _float("Wind Direction", "Where the wind blows toward, counter-clockwise "
                           "from +X; the waves travel with it", 0.0, -1e4, 1e4, 6.2832,
                           "ROTATION", subtype="ANGLE", soft_min=-6.2832)
    fetch: _float("Fetch", "How far the wind has blown over open water; 0: as far as it takes "
                  "to raise a fully developed sea", 0.0, 0.0, 1e8, 5e5, "LENGTH")
    choppiness: _float("Choppiness", "How far points move toward the crests, sharpening them: "
                       "1 is Tessendorf's lambda = 1", 0.0, 0.0, 4.0, 2.0)
    swell_height: _float("Swell Height", "Significant height of a swell from far away (0: "
                         "none)", 0.0, 0.0, 50.0, 8.0, "LENGTH")
    swell_direction: _float("Swell Direction", "Where the swell travels toward, "
                            "counter-clockwise from +X", 0.0, -1e4, 1e4, 6.2832, "ROTATION",
                            subtype="ANGLE", soft_min=-6.2832)
    swell_period: _float("Swell Period", "Seconds between the swell's crests", 10.0, 1.0, 40.0,
                         20.0, "TIME_ABSOLUTE")
    resolution_x: _int("Resolution X", "Grid vertices across the screen in the viewport",
                       65, 2, 8193, 1025)
    resolution_y: _int("Resolution Y", "Grid vertices up the screen in the viewport",
                       129, 2, 8193, 2049)
    render_resolution_x: _int("Render X", "Grid vertices across the screen in renders",
                              257, 2, 8193, 2049)
    render_resolution_y: _int("Render Y", "Grid vertices up the screen in renders",
                              513, 2, 8193, 4097)
    noise_from_wind: BoolProperty(
        name="From Wind", default=False, update=_settings_changed, override=OVERRIDABLE,
        description="The noise's height and wavelength follow the wind, fetch and spectrum: "
        "the wind sea's significant height and peak wavelength (Amplitude and Wave Scale are "
        "then unused)")
    amplitude: _float("Amplitude", "Height of the largest waves (the bound is the sum over "
                      "octaves)", 0.5, 0.0, 1e4, 10.0, "LENGTH")
    wave_scale: _float("Wave Scale", "Cell size of the first octave's noise (its waves are "
                       "1.7 times as long)", 40.0, WAVE_SCALE_MIN,
                       1e5, 500.0, "LENGTH")
    octaves: _int("Octaves", "Noise octaves, each half the wavelength of the one before",
                  8, 0, 24)
    roughness: _float("Roughness", "Amplitude ratio between octaves (alpha)", 0.5, 0.0, 2.0,
                      1.0)
    speed: _float("Speed", "Time scale of the animation", 1.0, -100.0, 100.0, 10.0)
    seed: _int("Seed", "Noise seed", 0, 0, 2**31 - 1, 1000)
    projector_elevation: _float("Projector Elevation", "Extra height of the projector above "
                                "the waves (thesis §2.5)", 0.0, 0.0, 1e4, 100.0, "LENGTH")
    noise: EnumProperty(
        name="Noise", default="FAST", update=_settings_changed, override=OVERRIDABLE,
        description="How heights are evaluated (docs/benchmarks.md has the cost and the error)",
        items=(("FAST", "Fast", "Per-octave noise textures sampled bilinearly (thesis App. B)"),
               ("EXACT", "Exact", "Gradient noise evaluated at every vertex (the reference)")))
    wind_speed: _float("Wind Speed", "Wind at 10 m above the sea: raises the waves of the "
                       "spectrum (and of the noise From Wind) and sets the foam's whitecap "
                       "coverage (Monahan and Mac Niocaill)", 3.0, 0.0, 100.0, 30.0, "VELOCITY")
    gusts: _float("Gusts", "How much the wind varies in patches that drift with it, roughening "
                  "and calming the ripples (cat's paws): 1 is the spread measured over a smooth "
                  "surface, 0.4 m/s in a light breeze and 8 % of a stronger wind; 0: a steady "
                  "wind",
                  1.0, 0.0, 20.0, 4.0)
    water_colour: FloatVectorProperty(
        name="Water Colour", subtype="COLOR", size=3, min=0.0, soft_max=1.0,
        default=look.WATER_COLOUR, update=_settings_changed, override=OVERRIDABLE,
        description="Deep water seen from above in Add Ocean's daylight (its sky, the sun 12° "
        "up): the light it scatters back up, which follows the scene's light (and the colour "
        "the water body tends to with depth)")
    clarity: _float("Clarity", "How far one sees through the water: over this distance its "
                    "clearest (blue) light keeps 1/e of its strength; red fades 7.5 times "
                    "sooner", optics.CLARITY, 0.1, 1e4, 100.0, "LENGTH")
    foam_colour: FloatVectorProperty(
        name="Foam Colour", subtype="COLOR", size=3, min=0.0, max=1.0,
        default=look.FOAM_COLOUR, update=_settings_changed, override=OVERRIDABLE,
        description="The diffuse colour of the foam's bubbles (the sheen of their films adds "
        "a quarter, to white at most)")
    foam: _mode("foam", "Foam on wave crests, its coverage set by the wind")
    contact_foam: _mode("contact_foam", "Foam where objects cross the water surface")
    underwater: _mode("underwater", "Snell's window and absorption fog with the camera below "
                      "the surface")
    refraction: _mode("refraction", "Submerged objects seen through the surface, dimmed and "
                      "tinted with depth")
    caustics: _mode("caustics", "Sunlight focused by the waves onto submerged geometry")
    godrays: _mode("godrays", "Shafts of sunlight seen from under the water")
    local_reflections: _mode("local_reflections", "Reflections of objects above the water "
                             "(sky only without them)")
    spray: _mode("spray", "Spindrift and spray the wind tears off the breaking crests (from "
                 "Beaufort 8)")
    wakes: _mode("wakes", "The waves boats leave behind them: Kelvin's wake of each "
                 "floating object whose keys move it across the water")
    water_body: PointerProperty(type=bpy.types.Object, options={"HIDDEN"},
                                description="Our water body volume (underwater, refraction)")
    shadow_caster: PointerProperty(type=bpy.types.Object, options={"HIDDEN"},
                                   description="Our object casting the water's caustic shadow")
    reflection_probe: PointerProperty(type=bpy.types.Object, options={"HIDDEN"},
                                      description="Our sphere probe capturing the mirror image "
                                      "(local reflections)")
    spray_cloud: PointerProperty(type=bpy.types.Object, options={"HIDDEN"},
                                 description="Our point cloud of the spray's puffs")
    render_mesh: PointerProperty(type=bpy.types.Mesh, options={"HIDDEN"},
                                 description="Our mesh drawn while rendering: its render grid's "
                                 "topology is kept from render to render")
    source: PointerProperty(type=bpy.types.Object, options={"HIDDEN"},
                            description="On a stand-in of ours: the ocean whose sea it draws "
                            "(a linked, overridden or instanced ocean we may not write)")
    bake_camera: StringProperty(options={"HIDDEN"}, description="The camera the ocean's bake "
                                "was made for (empty: not baked; bake.py)")
    bake_frames: IntVectorProperty(size=2, options={"HIDDEN"},
                                   description="The first and last frame of the ocean's bake")
    bake_fingerprints: StringProperty(options={"HIDDEN"}, description="What each baked frame "
                                      "was built for: its camera's and its settings' "
                                      "fingerprints (gather.fingerprint), frame by frame")
    active_effects: EnumProperty(
        name="Active Effects", options={"ENUM_FLAG"}, get=_active_effects,
        description="The effects on for the current frame (read-only)",
        items=[(e.upper(), e.replace("_", " ").title(), "", 1 << i)
               for i, e in enumerate(effects.EFFECTS)])



def on_objects(attr, group):
    """(register, unregister) of PropertyGroup `group` as every object's `attr`."""
    def register():
        bpy.utils.register_class(group)
        setattr(bpy.types.Object, attr, PointerProperty(type=group, override=OVERRIDABLE))

    def unregister():
        delattr(bpy.types.Object, attr)
        bpy.utils.unregister_class(group)
    return register, unregister


_register, _unregister = on_objects("projgrid", ProjectedGridSettings)


def register():
    _register()


def unregister():
    _unregister()
    RUNTIME.clear()
