"""A frame of one ocean: gather (read the scene into plain data, write nothing: gather.py),
plan (the core, bpy-free: projgrid_addon/frame_plan.py), apply (every write, in one place:
apply.py). A baked ocean plays its bake instead, before anything is gathered (`playback`)."""

import bpy

from ...projgrid_addon import frame_plan, shading
from ...shaders import sky, water
from . import ahead, apply, bake_record, baked, companions, gather, mesh, objects, scene
from .state import RUNTIME


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
    if playback(app, the_scene, depsgraph, frame_change):
        return None
    with ahead.frame():  # the calibrations' worker waits meanwhile
        read = gather.frame(app, the_scene, depsgraph, render, view, settings, frame_change)
        plan, refusal = planned(read)
        return apply.frame(read, plan, refusal)


def planned(read):
    """(the core's plan of the gathered frame or None, the refusal it raised or None)."""
    if read.inputs is None:
        return None, None
    try:
        return frame_plan.plan(read.inputs), None
    except ValueError as e:
        return None, str(e)
    except MemoryError:
        res = read.inputs.resolution
        return None, (f"out of memory building the {res[0]}x{res[1]} grid: lower the grid "
                      "resolution")


def playback(app, the_scene, depsgraph, frame_change):
    """Whether the frame of `app` is a bake's, not built: a baked ocean plays its cache (its
    material's keys and image sequences; a frame whose camera or settings changed since it was
    baked is flagged: baked.changed), and while a bake's export steps through the frames each
    is the mesh the bake kept (bake_record.kept)."""
    if baked.is_baked(app.ocean):
        state = RUNTIME.state(app.ocean)
        state.stale = baked.changed(app.ocean, the_scene.frame_current, gather.fingerprint(
            app, the_scene, depsgraph, frame_change))
        state.warning = (f"its bake is out of date ({state.stale}): re-bake it (Bake panel) "
                         "or go back to live" if state.stale else None)
        return True
    recording = bake_record.baking(app)
    if recording is None or not recording.replaying:
        return False
    arrays = bake_record.kept(the_scene.frame_current)
    try:
        if arrays is not None:
            puffs, level = bake_record.spray_of(arrays)
            mesh.write_arrays(app.ocean.data, arrays or None)
            companions.write_spray(app.ocean, puffs, level, faces=True)
    except (MemoryError, RuntimeError) as err:  # Blender swallows it in a handler
        recording.error = f"writing frame {the_scene.frame_current} failed: {err}"
    return True


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
        trees = (bpy.data.node_groups.get((water.GROUP, None)),
                 bpy.data.materials.get((water.SPRAY_MATERIAL, None)))
        sky.aim_sky(the_scene.world,
                    None if sun is None else shading.sun_direction(sun.matrix_world),
                    tuple(t for t in trees if t is not None))
        if sun is not None:
            sky.follow_sun(sun.original, sky.overcast(the_scene.world),
                           sky.model(the_scene.world), matrix=sun.matrix_world)
    for app in apps:
        message = update_appearance(app, the_scene, depsgraph, render=render,
                                    frame_change=frame_change)
        surface = surface_state(app.ocean)
        warning = surface.warning if surface is not None else None
        if render:
            for kind, text in (("not built", message), ("warning", warning),
                               ("note", cycles_note(the_scene, app.ocean))):
                if text:
                    print(f"Projected Grid Ocean: frame {the_scene.frame_current}: "
                          f"{app.ocean.name_full!r} {kind}: {text}", flush=True)


SPRAY_BOUNCES = 16  # transparent bounces a Cycles ray needs through the puffs toward the horizon


def cycles_note(the_scene, obj):
    """What Cycles would get wrong in this ocean's last built frame, and the setting to change,
    or None: a ray toward the horizon crosses many of the spray's puffs, and one that runs out
    of transparent bounces ends black (a grey band of puffs along the horizon)."""
    if the_scene.render.engine != "CYCLES":  # (its settings exist only while it is enabled)
        return None
    on = last_effects(obj).get("spray", (False,))[0]
    bounces = the_scene.cycles.transparent_max_bounces
    if not on or bounces >= SPRAY_BOUNCES:
        return None
    return (f"Cycles stops rays after {bounces} transparent bounces: the spray renders grey "
            f"toward the horizon; raise Render > Light Paths > Max Bounces > Transparent to "
            f"{2 * SPRAY_BOUNCES}")


def last_effects(obj):
    """{effect: (on, reason)} of the last frame built for ocean `obj` ({} before any)."""
    state = surface_state(obj)
    return (state.effects if state is not None else None) or {}


def surface_state(obj):
    """The state of the surface drawing ocean `obj`: its own, or its stand-in's."""
    own = RUNTIME.peek(obj)
    if own is not None and own.drawn_by:
        drawer = bpy.data.objects.get((own.drawn_by, None))
        return RUNTIME.peek(drawer) if drawer is not None else None
    return own
