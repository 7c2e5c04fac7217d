"""A frame of one ocean, in order: read the scene, build the grid, decide the effects, compute
their fields, write our data (`update_appearance`). Everything the steps need is read first;
nothing is written before the core has finished."""

import time

import bpy
import numpy as np

from ...projgrid_addon import Camera, build_grid, effects, foam, memory, optics, shading
from ...projgrid_addon.look import DAYLIGHT, DAYLIGHT_SUN
from ...shaders import sky
from ...shaders.nodes import assign
from . import bake_record, baked, companions, material_inputs, mesh, objects, scene, shot
from .state import RUNTIME


def update_ocean(obj, the_scene, depsgraph, render=None, view=None, settings=None):
    """Rebuild the sea of ocean `obj` wherever it shows in `the_scene` (its settings just
    edited, say); returns the first refusal message or None."""
    messages = [update_appearance(app, the_scene, depsgraph, render, view, settings,
                                  frame_change=False)
                for app in scene.appearances(the_scene, only=obj)]
    return next((m for m in messages if m), None)


def update_scene(the_scene, depsgraph, render, frame_change):
    """Rebuild every ocean showing in `the_scene`; in renders, one line in the render log for
    each sea refused or built with a warning on this frame. `frame_change`: the frame changed
    (so the timeline markers' camera switch applies)."""
    apps = scene.appearances(the_scene)
    if not render and not RUNTIME.rendering:
        companions.remove_stale_stand_ins(the_scene, apps)
    if apps:
        sun = objects.sun_lamp(the_scene, depsgraph, render)
        sky.aim_glow(the_scene.world,
                     None if sun is None else shading.sun_direction(sun.matrix_world))
    for app in apps:
        message = update_appearance(app, the_scene, depsgraph, render=render,
                                    frame_change=frame_change)
        surface = surface_state(app.ocean)
        warning = surface.warning if surface is not None else None
        if render:
            for kind, text in (("not built", message), ("warning", warning)):
                if text:
                    print(f"Projected Grid Ocean: frame {the_scene.frame_current}: "
                          f"{app.ocean.name_full!r} {kind}: {text}", flush=True)


def body_light(the_scene, sun, toward):
    """The light on the sea against the daylight the Water Colour is given in, per RGB channel
    (optics.body_light): the evaluated sun lamp's, shining from unit vector `toward`, and the
    world's."""
    irradiance = 0.0
    if sun is not None:
        irradiance = (float(sun.data.energy) * np.array(sun.data.color, dtype=np.float64)
                      * max(float(toward[2]), 0.0))
    return optics.body_light(irradiance, sky.strength(the_scene.world), DAYLIGHT, DAYLIGHT_SUN)


def surface_state(obj):
    """The state of the surface drawing ocean `obj`: its own, or its stand-in's."""
    own = RUNTIME.peek(obj)
    if own is not None and own.drawn_by:
        drawer = bpy.data.objects.get((own.drawn_by, None))
        return RUNTIME.peek(drawer) if drawer is not None else None
    return own


def update_appearance(app, the_scene, depsgraph, render=None, view=None, settings=None,
                      frame_change=True):
    """Rebuild the grid drawing `app` for the current frame; returns the refusal message or None.

    `render` defaults to whether `depsgraph` is a render depsgraph: renders use the render camera
    and resolution, the viewport the live preview's view if one runs, else the scene camera.
    Settings are read from the evaluated ocean, so animated values are honoured in renders,
    unless `settings` are given (a settings edit passes the values just set). The mesh written
    is ours: the ocean's own, or a stand-in's (companions.surface_for).
    """
    if render is None:
        render = depsgraph.mode == "RENDER"
    ocean = app.ocean
    if baked.is_baked(ocean):
        return None  # it plays its bake (bake.py): nothing of it is rebuilt
    baking = bake_record.baking(app)
    if baking is not None and baking.replaying:
        arrays = bake_record.kept(the_scene.frame_current)
        try:
            if arrays is not None:
                mesh.write_arrays(ocean.data, arrays or None)
        except (MemoryError, RuntimeError) as err:  # Blender swallows it in a handler
            baking.error = f"writing frame {the_scene.frame_current} failed: {err}"
        return None
    render = render or baking is not None  # the bake's frames are the render's
    making = not render and not RUNTIME.rendering

    # Read: what draws it, whether it shows, and every input of the rebuild.
    surface = companions.surface_for(app, the_scene, create=making)
    RUNTIME.state(ocean).drawn_by = (None if surface is ocean
                                     else RUNTIME.stand_ins.get(app.key))
    if surface is not ocean and scene.writable(ocean) and scene.owns(ocean.data):
        mesh.empty(ocean.data)  # its own mesh shows in every instance: the stand-ins draw it
        companions.hide_companions(ocean)
    if surface is None:
        return RUNTIME.state(ocean).refused(
            "its stand-in is made at the next viewport update or render start")
    state = RUNTIME.state(surface)
    if not scene.owns(surface.data):
        return state.refused("the ocean's mesh was replaced; it is left untouched (Add Ocean "
                             "makes a new one)")
    if surface.data.is_editmode:
        return state.refused(f"{surface.name!r} is in Edit Mode: the grid is rebuilt when you "
                             "leave it")
    shown = app.shown(depsgraph, render)
    generation = scene.generation(the_scene)
    restructured = state.generation != generation  # objects or collections changed since
    hidden = companions.follow_visibility(surface, app, shown, render, depsgraph.view_layer,
                                          relink=restructured)
    state.generation = generation
    if not shown:
        state.key, state.message, state.warning, state.hidden = None, None, None, True
        if baking is not None:
            bake_record.keep(the_scene.frame_current, None)  # hidden: empty in the bake
        return None
    settings = settings or ocean.evaluated_get(depsgraph).projgrid
    try:
        res = scene.resolution(settings, render)
        camera = view or (None if render else RUNTIME.live_view)
        camera = camera or shot.camera_for(the_scene, depsgraph, frame_change=frame_change)
        world = app.world(depsgraph)
        to_local = shot.ocean_axes(world)
        level = world[2, 3]
        t = shot.scene_time(the_scene)
        hf = scene.height_field(settings).prepare(t)
        cam = Camera(*camera)
        sun = objects.sun_lamp(the_scene, depsgraph, render)
        camera_key = cam.view.tobytes() + cam.proj.tobytes()
        facts = objects.scene_facts(the_scene, depsgraph, render, sun, cam, camera_key, level, hf,
                                  settings)
        light = body_light(the_scene, sun, facts.sun_direction)
        key = (render, res, camera_key, world.tobytes(), t,
               tuple(getattr(settings, p) for p in scene.SETTINGS), scene.look(settings),
               tuple(shot.render_size(the_scene)),  # the pixels' footprint (shading.Filtering)
               surface.data.session_uid, light,
               facts.key())
        if key == state.key:
            return None
        memory.check_grid(res, len(surface.data.vertices) != res[0] * res[1],
                          "render" if render else "viewport", large_only=True)
        modes = {e: getattr(settings, e) for e in effects.EFFECTS}
        volume_reach = (float(the_scene.eevee.volumetric_end) if hasattr(the_scene, "eevee")
                        else 100.0)
        per_frame = shot.seconds_per_frame(the_scene)
        water_colour, foam_colour, clarity, gusts = scene.look(settings)
        absorption = optics.absorption(clarity)

        # Build (thesis §2.4), decide the effects, compute the fields of those on.
        start = time.perf_counter()
        result = build_grid(cam, hf, level=level, time=t, resolution=res,
                            projector_elevation=settings.projector_elevation,
                            origin=world[:3, 3])
        decisions = effects.decide(modes, facts)
        on = {e: d[0] for e, d in decisions.items()}
        visible = result.visible
        boxes = effects.crossing_boxes(facts) if visible and on["contact_foam"] else ()
        # Calibrations ahead (a worker thread) only for the viewport's frames, none beside a
        # render or the bake's export.
        ahead = not (render or RUNTIME.rendering or RUNTIME.baking)
        whitecaps = (foam.foam_field(hf, result, t, settings.wind_speed, on["foam"], boxes,
                                     level, ahead=ahead) if visible else None)
        caustics = (optics.caustic_field(result.surface, facts)
                    if visible and on["caustics"] else None)
        godrays = (optics.godray_field(hf, t, cam.position, level, facts)
                   if on["godrays"] else None)
        detail = hf.shader_detail(*result.shader_octaves)
        ripple, _ = hf.ripple()
        material = material_inputs.material_of(surface.data)
        layer_origin = np.round(cam.position[:2])
        layer = (None if hf.layer is None or material is None else  # the user's: no layer
                 (hf.layer.slopes(t), hf.layer.lookups(layer_origin),
                  [(b.level, b.top_log, b.bottom_log) for b in hf.layer.bands]))
        filtering = shading.filtering(cam.proj, shot.render_size(the_scene)[0], hf.slopes,
                                      settings.wind_speed, gusts)
    except ValueError as e:
        mesh.empty(surface.data)
        return state.refused(str(e))
    except MemoryError:
        mesh.empty(surface.data)
        return state.refused(f"out of memory building the {res[0]}x{res[1]} grid: lower the "
                             "grid resolution")

    # Write: our mesh, our material's inputs, our companions.
    if surface is not ocean:  # the stand-in sits where the ocean shows, unrotated
        assign(surface, location=tuple(world[:3, 3]), rotation_euler=(0.0, 0.0, 0.0),
               scale=(1.0, 1.0, 1.0))
        to_local = np.eye(3)
    try:
        arrays = mesh.grid_arrays(result, to_local, whitecaps, caustics)
        mesh.write_arrays(surface.data, arrays)
    except (MemoryError, RuntimeError) as e:
        kind = "out of memory" if isinstance(e, MemoryError) else str(e)
        return state.refused(f"writing the {res[0]}x{res[1]} grid failed ({kind}): lower the "
                             "grid resolution")
    if baking is not None:
        bake_record.keep(the_scene.frame_current, arrays)
    state.key, state.message, state.hidden = key, None, False
    state.vertices, state.grid = len(result.positions), result.without_surface()
    state.ms = (time.perf_counter() - start) * 1e3
    state.effects, state.resolution, state.render = decisions, res, render
    state.camera = (cam.view, cam.proj)
    state.warning = flat_warning(hf, result, settings)
    in_use = effects_in_use()
    if material is not None:
        material_inputs.update(material, in_use, detail, detail.time_rate * per_frame, ripple,
                     ripple.time_rate * per_frame, filtering, water_colour, foam_colour,
                     settings.wind_direction,
                     effects.whitecap_coverage(settings.wind_speed) if on["foam"] else 0.0,
                     layer[2] if layer is not None else (), facts.sun_direction,
                     gust_drift(ocean, the_scene, settings, per_frame))
        if layer is not None:
            material_inputs.update_layer(material, layer[0], layer[1], layer_origin)
    if making:
        if restructured:
            companions.ensure_companions(surface)
        companions.own_material(surface)  # a material shared by hand is split at once
    body = surface.projgrid.water_body
    body_material = (material_inputs.material_of(body.data) if body is not None and scene.owns(body)
                     else None)
    if body_material is not None:
        body_material = material_inputs.own_body_material(body.data, absorption,
                                                optics.GODRAY_TILE_TEXELS)
        material_inputs.update_body(body_material, absorption,
                          tuple(c * e for c, e in zip(water_colour, light, strict=True)))
        if godrays is not None:
            material_inputs.update_godrays(body_material, *godrays)
    companions.place_companions(surface, cam, level, hf.bound, on, in_use, volume_reach,
                                hidden)
    return None


def effects_in_use():
    """{effect: on}: on if on for any surface built, since every ocean shares the water group
    whose branches are muted by it."""
    on = dict.fromkeys(effects.EFFECTS, False)
    for state in RUNTIME.surfaces.values():
        for effect, (active, _) in (state.effects or {}).items():
            on[effect] = on[effect] or active
    return on


WIND_PATHS = ("projgrid.wind_speed", "projgrid.wind_direction")


def gust_drift(ocean, the_scene, settings, per_frame):
    """The gusts' drift along X, along Y and its path, each (per frame, offset) for the water
    group's drivers: the wind's velocity now per frame, and with keyframed wind the offset
    that makes the driver read the wind's run since frame 0 (shading.wind_run, its curves
    sampled each frame) at this frame, so the patches move at the wind's speed as it changes
    (a driver of rate times frame alone would move them at U + t dU/dt)."""
    speed, direction = float(settings.wind_speed), float(settings.wind_direction)
    rates = (speed * np.cos(direction) * per_frame, speed * np.sin(direction) * per_frame,
             speed * per_frame)
    curves = {c.data_path: c for c in baked.bag_curves(ocean) if c.data_path in WIND_PATHS}
    if not curves:
        return tuple((float(r), 0.0) for r in rates)
    frame = the_scene.frame_current + the_scene.frame_subframe
    frames = np.append(np.arange(0.0, frame, 1.0 if frame >= 0 else -1.0), frame)

    def sampled(path, value):
        curve = curves.get(path)
        return [curve.evaluate(f) for f in frames] if curve is not None else [value] * len(frames)

    run = shading.wind_run(frames * per_frame, sampled(WIND_PATHS[0], speed),
                           sampled(WIND_PATHS[1], direction))
    return tuple((float(r), float(w - r * frame)) for r, w in zip(rates, run, strict=True))


def flat_warning(hf, result, settings):
    """Why a built sea has no wave in its geometry, and what to change (None if it has)."""
    longest = hf.longest_wave
    if (not result.visible or hf.bound == 0.0 or longest == 0.0
            or result.lod.max() > hf.first_level):
        return None
    spacing = hf.wave_scale / 2.0 ** (float(result.lod.max()) + 1.0)
    text = (f"no wave is in the geometry: the grid's vertices lie {spacing:.3g} m apart or "
            f"more, too sparse for the band limit to keep even the longest waves "
            f"({longest:.3g} m); ")
    if settings.projector_elevation > hf.bound:
        return text + (f"Projector Elevation ({settings.projector_elevation:.3g} m) lifts the "
                       "projector far above the waves: lower it")
    if settings.height_source == "SPECTRUM" or settings.noise_from_wind:
        return text + (f"the waves are {hf.bound:.3g} m high, so the projector sits that high: "
                       "raise the grid resolution")
    return text + (f"Amplitude ({hf.amplitude:.3g} m) makes the waves {hf.bound:.3g} m high, "
                   "so the projector sits that high: lower Amplitude or raise Wave Scale")
