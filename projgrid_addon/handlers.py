"""Persistent handlers: they, not the modal operator, own correctness in every render path.

frame_change_post runs for viewport frame changes, `frame_set`, and every rendered frame (F12,
animation renders, `blender -b ... -a` and `--render-frame`), each time with the depsgraph of that
evaluation: a render depsgraph in renders, so the render camera, render resolution and animated
settings are used. The render handlers keep Lock Interface on and tell the live preview to step
aside; the load handlers end the live preview and forget per-file state.
"""

import bpy
from bpy.app.handlers import persistent

from . import bridge

# bpy.data.objects' length at the last depsgraph update: a change may be a deleted ocean.
OBJECT_COUNT = {"n": 0}
LOCK_MESSAGE = ("Projected Grid Ocean: switched on Render > Lock Interface for scene {!r} "
                "(the ocean mesh is rebuilt while rendering)")


def ensure_lock_interface(scene):
    """Switch on Lock Interface for a scene with an ocean; returns the message if it changed."""
    if bridge.ocean_objects(scene) and not scene.render.use_lock_interface:
        scene.render.use_lock_interface = True
        return LOCK_MESSAGE.format(scene.name)
    return None


@persistent
def frame_change_post(scene, depsgraph=None):
    if depsgraph is None:
        depsgraph = bpy.context.evaluated_depsgraph_get()
    for obj in bridge.ocean_objects(scene):
        bridge.update_ocean(obj, scene, depsgraph)


@persistent
def depsgraph_update_post(scene, depsgraph):
    """In the viewport, follow edits between frames: the camera moved or retargeted, the ocean
    moved or its settings changed, or another object or lamp moved (the effects depend on them).
    Rebuilds whose inputs are unchanged (such as the update our own mesh write causes) are
    skipped by update_ocean, so this cannot loop."""
    if bridge.RENDERING["active"] or depsgraph.mode == "RENDER":
        return
    if len(bpy.data.objects) != OBJECT_COUNT["n"]:
        bridge.remove_orphan_companions()  # a deleted ocean takes its companions with it
        OBJECT_COUNT["n"] = len(bpy.data.objects)
    oceans = bridge.ocean_objects(scene)
    if not oceans:
        return
    kinds = (bpy.types.Object, bpy.types.Camera, bpy.types.Light, bpy.types.Scene)
    if any(isinstance(u.id, kinds) for u in depsgraph.updates):
        for obj in oceans:
            bridge.update_ocean(obj, scene, depsgraph)


def ensure_companions(scene):
    """Every ocean's companions exist (hidden until an effect needs them)."""
    for obj in bridge.ocean_objects(scene):
        bridge.ensure_companions(obj)


@persistent
def render_init(scene, _=None):
    ensure_companions(scene)  # before the render's depsgraph is built from the scene
    bridge.RENDERING["active"] = True
    message = ensure_lock_interface(scene)  # takes effect from the next render
    if message:
        print(message)


@persistent
def render_done(scene, _=None):
    bridge.RENDERING["active"] = False


@persistent
def load_pre(*_):
    bridge.LIVE_VIEW.clear()
    bridge.STATE.clear()


@persistent
def load_post(*_):
    bridge.RENDERING["active"] = False
    bridge.remove_orphan_companions()
    for scene in bpy.data.scenes:
        ensure_companions(scene)
        message = ensure_lock_interface(scene)
        if message:
            print(message)


HANDLERS = (
    ("frame_change_post", frame_change_post),
    ("depsgraph_update_post", depsgraph_update_post),
    ("render_init", render_init),
    ("render_complete", render_done),
    ("render_cancel", render_done),
    ("load_pre", load_pre),
    ("load_post", load_post),
)


def register():
    for name, fn in HANDLERS:
        getattr(bpy.app.handlers, name).append(fn)


def unregister():
    for name, fn in reversed(HANDLERS):
        handlers = getattr(bpy.app.handlers, name)
        while fn in handlers:
            handlers.remove(fn)
