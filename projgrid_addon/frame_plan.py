"""One frame of one ocean, planned (NumPy only): from what the Blender layer read of the scene
(`FrameInputs`: plain values, nothing of Blender's) to everything it then writes (`FramePlan`):
the grid (thesis §2.4), the effects on and their fields, the shader's values, the light on the
water body and what the panel warns of.

A pure function of its inputs but for caches of what is itself a pure function of them (the
height sources per settings, their foam calibrations), so a frame is the same planned alone or
after others, on any machine.
"""

import time as _time
from collections import namedtuple
from dataclasses import dataclass, replace
from functools import lru_cache

import numpy as np

from . import daylight, effects, floating, foam, memory, optics, shading, spray, wake_field
from .camera import Camera
from .height_field import HeightField
from .projected_grid import build_grid
from .sea_states import noise_waves
from .spectral_field import SpectralField
from .spectrum import SeaState

# The settings (obj.projgrid) a frame is built from, and the ocean's look written into our
# materials; read from the evaluated ocean, so animated values count.
SEA = ("resolution_x", "resolution_y", "render_resolution_x", "render_resolution_y",
       "noise_from_wind", "amplitude", "wave_scale", "octaves", "roughness", "speed", "seed",
       "projector_elevation", "noise", "wind_speed", "height_source", "spectrum",
       "wind_direction", "fetch", "choppiness", "swell_height", "swell_direction",
       "swell_period", *effects.EFFECTS)
LOOK = ("water_colour", "foam_colour", "clarity", "gusts")
# And the span (least, most) of a keyframed wind speed over its keyframes (None: not keyed):
# the spectral sea's tiles are laid out for all of it (cascade.layout).
Settings = namedtuple("Settings", (*SEA, *LOOK, "wind_span"), defaults=(None,))


def settings_of(values, wind_span=None):
    """`Settings` from anything with those attributes (obj.projgrid, evaluated or not): plain
    numbers, strings and tuples, hashable; `wind_span` as Settings says."""
    return Settings(*(tuple(v) if hasattr(v, "__len__") and not isinstance(v, str) else v
                      for v in (getattr(values, name) for name in SEA + LOOK)),
                    wind_span=None if wind_span is None else tuple(wind_span))


def height_source(s):
    """The core height source for `Settings` s: the spectral sea, or the noise, whose height
    and wavelength are the wind's sea's with From Wind on. Kept per settings (making one
    evaluates its spectrum over every tile; the noise's textures and either's foam
    calibrations serve the next frames)."""
    if s.height_source == "SPECTRUM":
        state = SeaState(wind_speed=s.wind_speed, wind_direction=s.wind_direction,
                         fetch=s.fetch, spectrum=s.spectrum, swell_height=s.swell_height,
                         swell_direction=s.swell_direction, swell_period=s.swell_period)
        return _spectral(state, s.choppiness, s.seed, s.wind_span)
    amplitude, wave_scale = s.amplitude, s.wave_scale
    if s.noise_from_wind:
        amplitude, wave_scale = noise_waves(s.wind_speed, s.fetch, s.spectrum, s.octaves,
                                            s.roughness)
    return _noise(amplitude, wave_scale, s.octaves, s.roughness, s.speed, s.seed,
                  s.noise.lower(), s.wind_direction, s.choppiness)


@lru_cache(maxsize=4)
def _spectral(state, choppiness, seed, wind_span):
    return SpectralField(state, choppiness, seed, wind_span=wind_span)


@lru_cache(maxsize=4)
def _noise(amplitude, wave_scale, octaves, roughness, speed, seed, method, wind_direction,
           choppiness):
    return HeightField(amplitude=amplitude, wave_scale=wave_scale, octaves=octaves,
                       roughness=roughness, speed=speed, seed=seed, method=method,
                       wind_direction=wind_direction, choppiness=choppiness)


@dataclass(frozen=True, eq=False)
class FrameInputs:
    """What the Blender layer read of the scene for one frame of one ocean."""

    settings: Settings
    render: bool  # a render's frame (or the bake's): the render grid and no look-ahead
    resolution: tuple  # the grid's (nx, ny), checked
    camera: tuple  # (view, proj) float64: world -> camera -> OpenGL clip space
    world: np.ndarray  # (4, 4) float64: the ocean where it shows
    to_local: np.ndarray  # (3, 3): world -> the drawing mesh's axes (identity: a stand-in)
    time: float  # s
    frame: float  # the scene frame, subframe included
    per_frame: float  # s per frame
    render_width: int  # pixels across the render (the pixels' footprint)
    facts: effects.SceneFacts  # its `bound` unset: the plan gives the sea's
    sun_light: tuple  # RGB irradiance the sun lamp puts on the mean sea plane (0: no sun)
    sky_strength: float  # the world's strength
    sky_overcast: float  # how far our sky world is turned to the overcast (0 clear, 1 full)
    sky_model: str  # our sky's Sky Texture model (daylight.MODELS)
    sky_hazes: bool  # the water may draw our sky's light as the air's (sky.hazes)
    wind_samples: tuple | None  # (frames, speeds, directions) of a keyframed wind since 0
    vertices: int  # the drawing mesh's vertices now (memory.check_grid)
    our_material: bool  # the mesh draws our water material (else no slope layer is made)
    volume_reach: float  # m: as far as EEVEE draws volumes
    ahead: bool  # the coming seconds' foam may be calibrated ahead (the viewport's frames)
    winds_ahead: tuple = ()  # a keyed wind's speeds at the coming FOAM_PERIODs' starts
    # the camera moves along the sea alone, its orientation, height and lens held (a dolly,
    # a flyover): the residual foam's past on canonical cameras' grids (past_grid.py)
    dolly: bool = False
    floats: tuple = ()  # floating.Float: the objects riding this ocean, as the scene places them
    # (name, course, draft, length, beam) of objects keyed across the water that do not float
    # (wake_field.course): their wakes
    wakers: tuple = ()


@dataclass(eq=False)
class FramePlan:
    """Everything one frame writes, computed."""

    camera: Camera
    source: object  # the height source (HeightField or SpectralField)
    result: object  # GridResult
    decisions: dict  # {effect: (on, reason)}
    on: dict  # {effect: on}
    bound: float  # the sea's displacement bound now
    whitecaps: np.ndarray | None  # per-vertex foam: active whitecaps and contact foam
    residual: np.ndarray | None  # per-vertex residual foam (residual_foam.py)
    caustics: np.ndarray | None  # per-vertex caustic shadow transparency less the flat water's
    godrays: tuple | None  # (tile, lookup) for the water body's material
    detail: shading.Detail
    ripple: shading.Detail
    filtering: shading.Filtering
    layer: tuple | None  # (slopes, lookups, bands, origin) of the slope layer
    absorption: tuple  # per metre, RGB
    light: tuple  # the light on the sea against DAYLIGHT, RGB
    haze: float  # per m: the air's extinction toward the water (daylight.haze; 0: none)
    drift: tuple  # the gusts' drift along X, Y and its path: (per frame, offset) each
    foam_look: tuple | None  # the water group's foam inputs (foam.foam_look; None: foam off)
    spray: tuple | None  # (positions, radii, opacities) of the spray's puffs (spray.spray)
    warning: str | None
    ms: float  # the time planning took
    floats: tuple = ()  # (key, world matrix) of each float's follower (floating.pose)


def plan(inputs):
    """The frame of `inputs` planned (ValueError or MemoryError with a user's message when no
    grid can be built)."""
    s, t = inputs.settings, inputs.time
    start = _time.perf_counter()
    hf = height_source(s)
    bound = hf.bounds(t)[0]
    memory.check_grid(inputs.resolution, inputs.vertices != inputs.resolution[0]
                      * inputs.resolution[1], "render" if inputs.render else "viewport",
                      large_only=True)
    cam = Camera(*inputs.camera)
    level = float(inputs.world[2, 3])
    courses = tuple(wake_field.course(f.name, *f.course, f.draft, f.length, f.beam)
                    for f in inputs.floats if f.course) + tuple(
        wake_field.course(name, *course, draft, length, beam)
        for name, course, draft, length, beam in inputs.wakers)
    facts = replace(inputs.facts, bound=bound,
                    reach=min(bound, effects.REACH_SIGMAS * hf.spread[0]),
                    movers=tuple((c.name, wake_field.speed_now(c), wake_field.speeds(c)[1])
                                 for c in courses))
    decisions = effects.decide({e: getattr(s, e) for e in effects.EFFECTS}, facts)
    on = {e: d[0] for e, d in decisions.items()}
    result = build_grid(cam, hf, level=level, time=t, resolution=inputs.resolution,
                        projector_elevation=s.projector_elevation, origin=inputs.world[:3, 3],
                        crest=foam.whitecap_level(hf) if on["foam"] else None)
    visible = result.visible
    wake_foam = (wake_field.draw(result, courses, hf.wave_scale)[1:]
                 if visible and on["wakes"] else None)
    boxes = effects.crossing_boxes(facts) if visible and on["contact_foam"] else ()
    whitecaps, residual = (foam.foam_field(hf, result, t, s.wind_speed, on["foam"], boxes,
                                           level, inputs.dolly) if visible else (None, None))
    if wake_foam is not None:
        whitecaps, residual = (w.ravel() if f is None else np.maximum(f, w.reshape(f.shape))
                               for f, w in zip((whitecaps, residual), wake_foam, strict=True))
    caustics = optics.caustic_field(result.surface, facts) if visible and on["caustics"] else None
    godrays = optics.godray_field(hf, t, cam.position, level, facts) if on["godrays"] else None
    puffs = spray.spray(hf, t, cam.position[:2], spray.view_wedge(cam), level, s.wind_speed,
                        s.wind_direction, seed=s.seed) if visible and on["spray"] else None
    layer = None
    if hf.layer is not None and inputs.our_material:  # a user's material draws no layer
        origin = np.round(cam.position[:2])
        layer = (hf.layer.slopes(t), hf.layer.lookups(origin),
                 [(b.level, b.top_log, b.bottom_log) for b in hf.layer.bands], origin)
    light = optics.body_light(np.asarray(inputs.sun_light, dtype=np.float64),
                              optics.sky_irradiance(inputs.sky_strength, inputs.sky_overcast,
                                                    inputs.facts.sun_elevation, inputs.sky_model))
    return FramePlan(
        camera=cam, source=hf, result=result, decisions=decisions, on=on, bound=bound,
        whitecaps=whitecaps, residual=residual, caustics=caustics, godrays=godrays,
        detail=hf.shader_detail(*result.shader_octaves), ripple=hf.ripple()[0],
        filtering=shading.filtering(cam.proj, inputs.render_width, hf.slopes, s.wind_speed,
                                    s.gusts),
        layer=layer, absorption=optics.absorption(s.clarity), light=light,
        haze=daylight.haze_extinction(s.wind_speed) if inputs.sky_hazes else 0.0,
        drift=gust_drift(s, inputs.per_frame, inputs.frame, inputs.wind_samples),
        foam_look=foam.foam_look(hf, s.wind_speed) if on["foam"] else None, spray=puffs,
        warning=flat_warning(hf, bound, result, s), ms=(_time.perf_counter() - start) * 1e3,
        floats=tuple(zip((f.key for f in inputs.floats),
                         floating.poses(hf, t, inputs.world, inputs.floats,
                                        courses if on["wakes"] else ()), strict=True)))


def gust_drift(s, per_frame, frame, samples):
    """The gusts' drift along X, along Y and its path, each (per frame, offset) for the water
    group's drivers: the wind's velocity now per frame, and with a keyframed wind (`samples`:
    its speed and direction at each frame since 0) the offset that makes the driver read the
    wind's run since frame 0 (shading.wind_run) at this frame, so the patches move at the
    wind's speed as it changes (a driver of rate times frame alone would move them at
    U + t dU/dt)."""
    speed, direction = float(s.wind_speed), float(s.wind_direction)
    rates = (speed * np.cos(direction) * per_frame, speed * np.sin(direction) * per_frame,
             speed * per_frame)
    if samples is None:
        return tuple((float(r), 0.0) for r in rates)
    frames, speeds, directions = (np.asarray(v, dtype=np.float64) for v in samples)
    run = shading.wind_run(frames * per_frame, speeds, directions)
    return tuple((float(r), float(w - r * frame)) for r, w in zip(rates, run, strict=True))


def flat_warning(hf, bound, result, s):
    """Why a built sea (its waves `bound` m high) has no wave in its geometry, and what to
    change (None if it has)."""
    longest = hf.longest_wave
    if (not result.visible or bound == 0.0 or longest == 0.0
            or result.lod.max() > hf.first_level):
        return None
    spacing = hf.wave_scale / 2.0 ** (float(result.lod.max()) + 1.0)
    text = (f"no wave is in the geometry: the grid's vertices lie {spacing:.3g} m apart or "
            f"more, too sparse for the band limit to keep even the longest waves "
            f"({longest:.3g} m); ")
    if s.projector_elevation > bound:
        return text + (f"Projector Elevation ({s.projector_elevation:.3g} m) lifts the "
                       "projector far above the waves: lower it")
    if s.height_source == "SPECTRUM" or s.noise_from_wind:
        return text + (f"the waves are {bound:.3g} m high, so the projector sits that high: "
                       "raise the grid resolution")
    return text + (f"Amplitude ({hf.amplitude:.3g} m) makes the waves {bound:.3g} m high, "
                   "so the projector sits that high: lower Amplitude or raise Wave Scale")
