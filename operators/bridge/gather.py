"""Gather: one frame of one ocean read from the scene into plain data (`Gathered`), the core's
`FrameInputs` among it. Nothing here writes Blender data (tests/blender/test_frame.py runs it
where any write raises); what is made or written is apply.py's."""

import hashlib
from dataclasses import dataclass

import numpy as np

from ...projgrid_addon import Camera, foam, frame_plan, shading
from ...shaders import sky
from . import bake_record, companions, floats, material_inputs, objects, scene, shot
from .state import RUNTIME


@dataclass(frozen=True)
class Visibility:
    """How our objects beside an ocean follow it where it shows (companions.follow_visibility):
    hidden in renders and in the viewport, a holdout, indirect only, and hidden in this view
    layer alone (the eye)."""

    hidden_render: bool
    hidden_viewport: bool
    holdout: bool
    indirect: bool
    eye: bool


@dataclass(frozen=True, eq=False)
class Gathered:
    """What one frame of appearance `app` read. `surface` is the local object of ours drawing
    it (None: a stand-in is to be made, `make_stand_in`); `refusal` says why no grid is built
    (`empty`: and the drawing mesh is emptied); `inputs` is None where nothing is to be
    planned (refused, not shown, or `unchanged` since the last build)."""

    app: object
    scene: object
    view_layer: object  # the evaluation's
    render: bool
    surface: object = None
    make_stand_in: bool = False
    refusal: str | None = None
    empty: bool = False
    shown: bool = True
    visibility: Visibility | None = None
    restructured: bool = False  # objects or collections changed since the last build
    generation: int = -1
    recording: object = None  # the bake being recorded (bake_record.Recording), or None
    inputs: frame_plan.FrameInputs | None = None
    key: tuple | None = None  # every input of the build: an equal key skips it
    unchanged: bool = False
    fingerprint: str | None = None  # what a bake being recorded keeps of the frame


def frame(app, the_scene, depsgraph, render, view=None, values=None, frame_change=True):
    """Read one frame of `app` (see Gathered). `view`: the live preview's (view, proj);
    `values`: the settings just edited (else the evaluated ocean's)."""
    ocean = app.ocean
    recording = bake_record.baking(app)
    render = render or recording is not None  # the bake's frames are the render's
    making = not render and not RUNTIME.rendering
    surface = companions.surface_for(app, the_scene, create=False)
    shown = app.shown(depsgraph, render)
    make = surface is None and making and app.needs_stand_in and shown
    base = dict(app=app, scene=the_scene, view_layer=depsgraph.view_layer, render=render,
                surface=surface, make_stand_in=make, recording=recording,
                fingerprint=(fingerprint(app, the_scene, depsgraph, frame_change)
                             if recording is not None else None))
    if surface is None and not make:  # (nothing to draw where it does not show)
        return Gathered(**base, shown=shown, refusal="its stand-in is made at the next "
                        "viewport update or render start" if shown else None)
    if surface is not None and not scene.owns(surface.data):
        return Gathered(**base, refusal="the ocean's mesh was replaced; it is left untouched "
                                        "(Add Ocean makes a new one)")
    if surface is not None and surface.data.is_editmode:
        return Gathered(**base, refusal=f"{surface.name!r} is in Edit Mode: the grid is rebuilt "
                                        "when you leave it")
    generation = scene.generation(the_scene)
    state = RUNTIME.peek(surface) if surface is not None else None
    base.update(shown=shown, visibility=visibility(app, shown, render, depsgraph.view_layer),
                generation=generation,
                restructured=state is None or state.generation != generation)
    if not shown:
        return Gathered(**base)
    values = values or ocean.evaluated_get(depsgraph).projgrid
    s = scene.read_settings(values)
    try:
        resolution = scene.resolution(s, render)
        camera, dolly = view or (None if render else RUNTIME.live_view), False
        if camera is None:
            obj = shot.scene_camera(the_scene, frame_change)
            camera = shot.camera_for(the_scene, depsgraph, obj, frame_change=frame_change)
            dolly = shot.dolly(obj)
        world = app.world(depsgraph)
        to_local = np.eye(3) if surface is not ocean else shot.ocean_axes(world)
        cam = Camera(*camera)
        level = float(world[2, 3])
        sun = objects.sun_lamp(the_scene, depsgraph, render)
        camera_key = cam.view.tobytes() + cam.proj.tobytes()
        facts = objects.scene_facts(the_scene, depsgraph, render, sun, cam, camera_key, level,
                                    s)
    except ValueError as e:
        return Gathered(**base, refusal=str(e), empty=True)
    sun_light = (0.0, 0.0, 0.0)
    if sun is not None:
        toward = shading.sun_direction(sun.matrix_world)
        sun_light = tuple(float(sun.data.energy) * float(c) * max(float(toward[2]), 0.0)
                          for c in sun.data.color)
    t = shot.scene_time(the_scene)
    size = shot.render_size(the_scene)
    sky_strength, sky_overcast = sky.strength(the_scene.world), sky.overcast(the_scene.world)
    sky_model, sky_hazes = sky.model(the_scene.world), sky.hazes(the_scene.world)
    near = tuple(cam.position[:2]) if s.wakes != "OFF" else None
    per_frame = shot.seconds_per_frame(the_scene)
    riding = floats.gather(app, the_scene, depsgraph, t, per_frame, near=near)
    wakers = () if near is None else floats.wakers(the_scene, depsgraph, facts, t, per_frame,
                                                   near, {f.name for f in riding})
    key = (render, resolution, camera_key, world.tobytes(), t, s, size,
           surface.data.session_uid if surface is not None else None, sun_light, sky_strength,
           sky_overcast, sky_model, sky_hazes, facts.key(), dolly, riding, wakers)
    if state is not None and key == state.key:
        return Gathered(**base, key=key, unchanged=True)
    frame_now = the_scene.frame_current + the_scene.frame_subframe
    ahead = not (render or RUNTIME.rendering or RUNTIME.baking)
    inputs = frame_plan.FrameInputs(
        settings=s, render=render, resolution=resolution, camera=(cam.view, cam.proj),
        world=world, to_local=to_local, time=t, frame=frame_now,
        per_frame=per_frame, render_width=size[0], facts=facts,
        sun_light=sun_light, sky_strength=sky_strength, sky_overcast=sky_overcast,
        sky_model=sky_model, sky_hazes=sky_hazes,
        wind_samples=wind_samples(ocean, frame_now, s),
        vertices=len(surface.data.vertices) if surface is not None else 0,
        our_material=our_material(app, surface),
        volume_reach=(float(the_scene.eevee.volumetric_end) if hasattr(the_scene, "eevee")
                      else 100.0),
        ahead=ahead, winds_ahead=winds_ahead(ocean, frame_now, t, per_frame) if ahead else (),
        dolly=dolly, floats=riding, wakers=wakers)
    return Gathered(**base, inputs=inputs, key=key)


def fingerprint(app, the_scene, depsgraph, frame_change=True):
    """What a frame is built for, as "camera:settings": a hash of the camera (its matrices at
    the render's size) and where the ocean shows, and one of its evaluated settings. A bake
    keeps it per frame; a baked frame whose fingerprint differs is out of date (baked.stale)."""
    try:
        view, proj = shot.camera_for(the_scene, depsgraph, frame_change=frame_change)
        seen = [view, proj, app.world(depsgraph), np.array(shot.render_size(the_scene))]
        camera = hashlib.sha1(b"".join(np.round(np.asarray(m, np.float64), 6).tobytes()
                                       for m in seen)).hexdigest()[:12]
    except ValueError:
        camera = "none"
    s = scene.read_settings(app.ocean.evaluated_get(depsgraph).projgrid)
    s = s._replace(resolution_x=0, resolution_y=0)  # the viewport's grid: not baked
    return f"{camera}:{hashlib.sha1(repr(s).encode()).hexdigest()[:12]}"


def visibility(app, shown, render, view_layer):
    """How our objects follow `app` in this evaluation (Visibility): the ocean's and its
    instancers' own switches (never written), this evaluation's view of it, its layer flags."""
    holdout, indirect = app.layer_flags(view_layer)
    return Visibility(
        hidden_render=any(o.hide_render for o in app.objects) or (render and not shown),
        hidden_viewport=any(o.hide_viewport for o in app.objects), holdout=holdout,
        indirect=indirect, eye=not render and not shown)


def our_material(app, surface):
    """Whether the drawing mesh shows our water material (a stand-in to be made takes the
    ocean's: a copy of ours, or the user's own)."""
    if surface is not None:
        return material_inputs.material_of(surface.data) is not None
    ocean = app.ocean.data
    source = ocean.materials[0] if ocean is not None and len(ocean.materials) else None
    return source is None or bool(source.get(scene.TAG))


def winds_ahead(ocean, frame_now, time, per_frame):
    """The keyframed wind speed at the starts of the next two FOAM_PERIODs after `time`
    (foam.ahead's times), for the worker to calibrate the seas of the winds it will reach;
    () when the wind speed is not keyframed."""
    curve = scene.wind_curves(ocean).get(scene.WIND_PATHS[0])
    if curve is None or per_frame <= 0.0:
        return ()
    return tuple(max(float(curve.evaluate(frame_now + (when - time) / per_frame)), 0.0)
                 for when in foam.ahead_times(time))


def wind_samples(ocean, frame_now, s):
    """(frames, speeds, directions) of the ocean's keyframed wind at each frame from 0 to now
    (frame_plan.gust_drift integrates its run), or None when neither is keyframed."""
    curves = scene.wind_curves(ocean)
    if not curves:
        return None
    frames = np.append(np.arange(0.0, frame_now, 1.0 if frame_now >= 0 else -1.0), frame_now)

    def sampled(path, value):
        curve = curves.get(path)
        return tuple(curve.evaluate(f) for f in frames) if curve is not None else (
            (float(value),) * len(frames))

    return (tuple(frames), sampled(scene.WIND_PATHS[0], s.wind_speed),
            sampled(scene.WIND_PATHS[1], s.wind_direction))
