"""Persistent handlers: they, not the modal operator, own correctness in every render path.

frame_change_post runs for viewport frame changes, `frame_set`, and every rendered frame (F12,
animation renders, `blender -b ... -a` and `--render-frame`), each time with the depsgraph of that
evaluation: a render depsgraph in renders, so the render camera, render resolution and animated
settings are used. render_init makes what a render will need (stand-ins, companions) before the
render's depsgraph is built from the scene, and tells the live preview to step aside; the load
handlers end the live preview and forget per-file state; the save handlers write our meshes
empty, so a file linking this one's ocean draws it only by its own stand-in.
"""

import bpy
from bpy.app.handlers import persistent

from . import bridge

# bpy.data.objects' length at the last depsgraph update: a change may be a deleted ocean.
OBJECT_COUNT = {"n": 0}
LOCK_MESSAGE = ("Projected Grid Ocean: switched on Render > Lock Interface for scene {!r} "
                "(the ocean mesh is rebuilt while rendering)")
UNLOCKED_MESSAGE = ("Projected Grid Ocean: Render > Lock Interface is off in scene {!r}: the "
                    "ocean is rebuilt while rendering, so the interface may show a half-written "
                    "mesh; switch it on for interactive renders")


def ensure_lock_interface(scene):
    """Switch on Lock Interface for a scene with an ocean; returns the message if it changed."""
    if bridge.ocean_objects(scene) and not scene.render.use_lock_interface:
        scene.render.use_lock_interface = True
        return LOCK_MESSAGE.format(scene.name)
    return None


def update_scene(scene, depsgraph, render):
    """Rebuild every ocean showing in `scene`; in renders, one line in the render log for each
    sea refused or built with a warning on this frame."""
    apps = bridge.appearances(scene)
    if not render and not bridge.RENDERING["active"]:
        bridge.remove_stale_stand_ins(scene, apps)
    for app in apps:
        message = bridge.update_appearance(app, scene, depsgraph, render=render)
        if not render:
            continue
        surface = bridge.STAND_INS.get(app.key) or app.ocean.name_full
        warning = bridge.STATE.get(surface, {}).get("warning")
        for kind, text in (("not built", message), ("warning", warning)):
            if text:
                print(f"Projected Grid Ocean: frame {scene.frame_current}: "
                      f"{app.ocean.name_full!r} {kind}: {text}", flush=True)


@persistent
def frame_change_post(scene, depsgraph=None):
    if depsgraph is None:
        depsgraph = bpy.context.evaluated_depsgraph_get()
    update_scene(scene, depsgraph, depsgraph.mode == "RENDER")


@persistent
def depsgraph_update_post(scene, depsgraph):
    """In the viewport, follow edits between frames: the camera moved or retargeted, the ocean
    moved or its settings changed, or another object or lamp moved (the effects depend on them).
    Rebuilds whose inputs are unchanged (such as the update our own mesh write causes) are
    skipped by update_appearance, so this cannot loop."""
    if bridge.RENDERING["active"] or depsgraph.mode == "RENDER":
        return
    if len(bpy.data.objects) != OBJECT_COUNT["n"]:
        bridge.remove_orphan_companions()  # a deleted ocean takes its companions with it
        bridge.remove_stale_stand_ins(scene, bridge.appearances(scene), everywhere=True)
        OBJECT_COUNT["n"] = len(bpy.data.objects)
    kinds = (bpy.types.Object, bpy.types.Camera, bpy.types.Light, bpy.types.Scene,
             bpy.types.Collection)
    if any(isinstance(u.id, kinds) for u in depsgraph.updates):
        update_scene(scene, depsgraph, render=False)


def prepare(scene):
    """Before a render or after a load: every ocean showing in `scene` has its surface (a
    stand-in where we may not write the ocean), companions and material of its own."""
    apps = bridge.appearances(scene)
    bridge.remove_stale_stand_ins(scene, apps, everywhere=True)
    for app in apps:
        surface = bridge.surface_for(app, scene, create=True)
        if surface is not None and bridge.owns(surface.data):
            bridge.ensure_companions(surface)
            bridge.own_material(surface)


@persistent
def render_init(scene, _=None):
    prepare(scene)  # before the render's depsgraph is built from the scene
    bridge.RENDERING["active"] = True
    if (not bpy.app.background and bridge.ocean_objects(scene)
            and not scene.render.use_lock_interface):
        print(UNLOCKED_MESSAGE.format(scene.name), flush=True)


@persistent
def render_done(scene, _=None):
    bridge.RENDERING["active"] = False


@persistent
def load_pre(*_):
    bridge.LIVE_VIEW.clear()
    bridge.STATE.clear()
    bridge.STAND_INS.clear()


@persistent
def load_post(*_):
    """The user's Lock Interface choice is kept: the panel says when renders need it."""
    bridge.RENDERING["active"] = False
    bridge.remove_orphan_companions()
    for scene in bpy.data.scenes:
        if scene.library is None:
            prepare(scene)


@persistent
def save_pre(*_):
    """Our meshes are saved empty and our companions hidden: they are rebuilt from the settings
    whenever the file is used, and a file linking this one's ocean then shows only the sea its
    own stand-in draws, not a grid built for this file's camera."""
    for obj in bpy.data.objects:
        if (obj.type == "MESH" and (obj.projgrid.is_ocean or obj.get(bridge.STAND_IN))
                and bridge.local(obj) and bridge.owns(obj.data) and bridge.local(obj.data)
                and not obj.data.is_editmode):
            bridge.empty_for_save(obj)


@persistent
def save_post(*_):
    """Back to what was on screen before the save."""
    bridge.STATE.clear()
    context = bpy.context
    if context.scene is not None and context.view_layer is not None:
        update_scene(context.scene, context.evaluated_depsgraph_get(), render=False)


HANDLERS = (
    ("frame_change_post", frame_change_post),
    ("depsgraph_update_post", depsgraph_update_post),
    ("render_init", render_init),
    ("render_complete", render_done),
    ("render_cancel", render_done),
    ("load_pre", load_pre),
    ("load_post", load_post),
    ("save_pre", save_pre),
    ("save_post", save_post),
)


def register():
    for name, fn in HANDLERS:
        getattr(bpy.app.handlers, name).append(fn)


def unregister():
    for name, fn in reversed(HANDLERS):
        handlers = getattr(bpy.app.handlers, name)
        while fn in handlers:
            handlers.remove(fn)
