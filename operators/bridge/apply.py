"""Apply: every write of one frame of one ocean, in one place, from what was gathered
(gather.Gathered) and planned (frame_plan.FramePlan, or the refusal planning raised): our
stand-in made if missing, our objects following the ocean's visibility, our mesh, our
material's inputs, our companions, the per-surface state the panel shows, and the frame kept
for a bake being recorded. Only our own data is written."""

import time

import numpy as np

from ...projgrid_addon.effects import EFFECTS
from ...projgrid_addon.optics import GODRAY_TILE_TEXELS
from ...shaders.nodes import assign
from . import ahead, bake_record, companions, floats, material_inputs, mesh, scene
from .state import RUNTIME


def frame(read, plan, refusal=None):
    """Write one frame; returns the refusal message or None. `refusal`: why planning failed
    (read.inputs was planned and raised), with `plan` None."""
    app, ocean = read.app, read.app.ocean
    surface = read.surface
    if read.make_stand_in:
        surface = companions.stand_in(app, read.scene, create=True)
    RUNTIME.state(ocean).drawn_by = (None if surface is ocean
                                     else RUNTIME.stand_ins.get(app.key))
    if surface is not ocean and scene.writable(ocean) and scene.owns(ocean.data):
        mesh.empty(ocean.data)  # its own mesh shows in every instance: the stand-ins draw it
        companions.hide_companions(ocean)
    if surface is None:  # no stand-in, and none is made
        return RUNTIME.state(ocean).refused(read.refusal) if read.refusal else None
    if read.refusal and not read.empty:
        return RUNTIME.state(surface).refused(read.refusal)
    state = RUNTIME.state(surface)
    companions.follow_visibility(surface, app, read.visibility, read.render, read.view_layer,
                                 relink=read.restructured)  # (so is a stand-in just made)
    state.generation = read.generation
    if not read.shown:
        state.key, state.message, state.warning, state.hidden = None, None, None, True
        _keep(read, None)  # hidden on this frame: empty in the bake
        return None
    if read.unchanged:
        return None
    refusal = read.refusal or refusal
    if refusal is not None:
        mesh.empty(surface.data)
        return state.refused(refusal)
    inputs, result = read.inputs, plan.result
    start = time.perf_counter()
    to_local = inputs.to_local
    if surface is not ocean:  # the stand-in sits where the ocean shows, unrotated
        assign(surface, location=tuple(inputs.world[:3, 3]), rotation_euler=(0.0, 0.0, 0.0),
               scale=(1.0, 1.0, 1.0))
        to_local = np.eye(3)
    res = inputs.resolution
    try:
        arrays = mesh.grid_arrays(result, to_local, plan.whitecaps, plan.caustics,
                                  plan.residual)
        mesh.write_arrays(surface.data, arrays)
    except (MemoryError, RuntimeError) as e:
        kind = "out of memory" if isinstance(e, MemoryError) else str(e)
        return state.refused(f"writing the {res[0]}x{res[1]} grid failed ({kind}): lower the "
                             "grid resolution")
    _keep(read, arrays, plan.spray, float(inputs.world[2, 3]))
    state.key, state.message, state.hidden = read.key, None, False
    state.vertices, state.grid = len(result.positions), result.without_surface()
    state.effects = plan.decisions
    state.resolution, state.render = res, inputs.render
    state.camera = (plan.camera.view, plan.camera.proj)
    state.warning = plan.warning
    in_use = effects_in_use()
    _write_materials(read, plan, surface, in_use)
    if inputs.ahead and plan.on["foam"] and result.visible:
        ahead.calibrate(plan.source, inputs.time, inputs.settings.wind_speed,
                        inputs.winds_ahead)
    companions.place_companions(surface, plan.camera, float(inputs.world[2, 3]), plan.bound,
                                plan.on, in_use, inputs.volume_reach,
                                (read.visibility.hidden_render, read.visibility.hidden_viewport))
    companions.write_spray(surface, plan.spray, float(inputs.world[2, 3]),
                           air=(plan.haze, inputs.sky_overcast))
    floats.apply(plan.floats)
    state.ms = plan.ms + (time.perf_counter() - start) * 1e3  # planned and written
    return None


def _keep(read, arrays, spray=None, level=0.0):
    if read.recording is not None:
        bake_record.keep(read.scene.frame_current, arrays, read.fingerprint, spray, level)


def _write_materials(read, plan, surface, in_use):
    """Our water material's inputs and slope layer, our materials made our own, the water
    body's volume and godrays."""
    inputs, s = read.inputs, read.inputs.settings
    per_frame = inputs.per_frame
    material = material_inputs.material_of(surface.data)
    if material is not None:
        material_inputs.update(
            material, in_use, plan.detail, plan.detail.time_rate * per_frame,
            plan.ripple, plan.ripple.time_rate * per_frame, plan.filtering, s.water_colour,
            s.foam_colour, s.wind_direction, plan.foam_look,
            plan.layer[2] if plan.layer is not None else (),
            inputs.facts.sun_direction, plan.drift, inputs.volume_reach, plan.haze,
            inputs.sky_overcast)
        if plan.layer is not None:
            material_inputs.update_layer(material, plan.layer[0], plan.layer[1], plan.layer[3])
    if not inputs.render and not RUNTIME.rendering:
        if read.restructured:
            companions.ensure_companions(surface)
        companions.own_material(surface)  # a material shared by hand is split at once
    body = surface.projgrid.water_body
    body_material = (material_inputs.material_of(body.data)
                     if body is not None and scene.owns(body) else None)
    if body_material is not None:
        body_material = material_inputs.own_body_material(body.data, plan.absorption,
                                                          GODRAY_TILE_TEXELS)
        material_inputs.update_body(body_material, plan.absorption, tuple(
            c * e for c, e in zip(s.water_colour, plan.light, strict=True)))
        if plan.godrays is not None:
            material_inputs.update_godrays(body_material, *plan.godrays)


def effects_in_use():
    """{effect: on}: on if on for any surface built, since every ocean shares the water group
    whose branches are muted by it."""
    on = dict.fromkeys(EFFECTS, False)
    for state in RUNTIME.surfaces.values():
        for effect, (active, _) in (state.effects or {}).items():
            on[effect] = on[effect] or active
    return on
