"""Persistent handlers: they, not the modal operator, own correctness in every render path.

frame_change_post runs for viewport frame changes, `frame_set`, and every rendered frame (F12,
animation renders, `blender -b ... -a` and `--render-frame`), each time with the depsgraph of that
evaluation: a render depsgraph in renders, so the render camera, render resolution and animated
settings are used. render_init makes what a render will need (stand-ins, companions) before the
render's depsgraph is built from the scene, and tells the live preview to step aside; the load
and undo handlers forget what was kept between updates; the save handlers write our meshes
empty, so a file linking this one's ocean draws it only by its own stand-in.
"""

import time

import bpy
from bpy.app.handlers import persistent

from . import ahead, bake_record, baked, companions, frame, material_inputs, scene
from .state import RUNTIME

LOCK_MESSAGE = ("Projected Grid Ocean: switched on Render > Lock Interface for scene {!r} "
                "(the ocean mesh is rebuilt while rendering)")
UNLOCKED_MESSAGE = ("Projected Grid Ocean: Render > Lock Interface is off in scene {!r}: the "
                    "ocean is rebuilt while rendering, so the interface may show a half-written "
                    "mesh; switch it on for interactive renders")


def ensure_lock_interface(the_scene):
    """Switch on Lock Interface for a scene with an ocean; returns the message if it changed."""
    if scene.ocean_objects(the_scene) and not the_scene.render.use_lock_interface:
        the_scene.render.use_lock_interface = True
        return LOCK_MESSAGE.format(the_scene.name)
    return None


@persistent
def frame_change_post(the_scene, depsgraph=None):
    if depsgraph is None:
        depsgraph = bpy.context.evaluated_depsgraph_get()
    render = depsgraph.mode == "RENDER"
    if not render:
        updates = depsgraph.updates
        if len(updates) > scene.MANY_UPDATES:  # (walking them would cost more than the frame)
            scene.note_frame(the_scene, len(bpy.data.objects),
                             depsgraph.id_type_updated("COLLECTION"))
        else:
            scene.note_updates(the_scene, [u.id for u in updates], len(bpy.data.objects))
    frame.update_scene(the_scene, depsgraph, render, frame_change=True)
    if RUNTIME.baking:
        bake_record.progress(the_scene.frame_current)
    elif not render:
        pack_when_still()


def _forget_deleted(object_count):
    """When objects were added or deleted: a deleted ocean takes its companions and stand-ins
    with it, and deleted objects' states are forgotten."""
    if object_count == RUNTIME.object_count:
        return False
    companions.remove_orphan_companions()
    RUNTIME.prune({o.session_uid for o in bpy.data.objects})
    RUNTIME.object_count = len(bpy.data.objects)
    return True


@persistent
def depsgraph_update_post(the_scene, depsgraph):
    """In the viewport, follow edits between frames: the camera moved or retargeted, the ocean
    moved or its settings changed, or another object or lamp moved (the effects depend on them).
    What the update did not touch is kept (scene.note_updates); rebuilds whose inputs are
    unchanged (such as the update our own mesh write causes) are skipped, so this cannot loop."""
    if RUNTIME.rendering and not bpy.app.background and not bpy.app.is_job_running("RENDER"):
        render_done(the_scene)  # a render that ended without saying so (one that failed early)
    if RUNTIME.rendering or depsgraph.mode == "RENDER":
        return
    # Objects are added, deleted or relinked only with a collection among the updates: only
    # then is the file's object count (a walk over every object) read.
    updates = [u.id for u in depsgraph.updates]  # (a walk over the evaluated data: once)
    structural = any(isinstance(u, bpy.types.Collection) for u in updates)
    object_count = len(bpy.data.objects) if structural else RUNTIME.object_count
    relevant = scene.note_updates(the_scene, updates, object_count)  # drops a stale cache
    if structural and _forget_deleted(object_count):
        companions.remove_stale_stand_ins(the_scene, scene.appearances(the_scene),
                                          everywhere=True)
    if relevant:
        frame.update_scene(the_scene, depsgraph, render=False, frame_change=False)


def prepare(the_scene):
    """Before a render or after a load: every ocean showing in `the_scene` has its surface (a
    stand-in where we may not write the ocean), companions and material of its own."""
    apps = scene.appearances(the_scene)
    companions.remove_stale_stand_ins(the_scene, apps, everywhere=True)
    for app in apps:
        if not any(app.in_layer(layer, render=True) for layer in the_scene.view_layers
                   if layer.use):
            continue  # it renders in no view layer: no stand-in for it
        surface = companions.surface_for(app, the_scene, create=True)
        if surface is not None and scene.owns(surface.data):
            companions.ensure_companions(surface)
            companions.own_material(surface)


@persistent
def render_init(the_scene, _=None):
    # Before the render's depsgraph is built from the scene. An interactive render runs this in
    # its job thread: objects are made only with the interface locked (the viewport makes them
    # otherwise, at its next update).
    companions.use_viewport_mesh()  # after a render that ended without saying so
    ahead.finish()
    if bpy.app.background or the_scene.render.use_lock_interface:
        prepare(the_scene)
        for app in scene.appearances(the_scene):
            surface = companions.surface_for(app, the_scene, create=False)
            if surface is not None:
                companions.use_render_mesh(surface)
    RUNTIME.rendering = True
    if (not bpy.app.background and scene.ocean_objects(the_scene)
            and not the_scene.render.use_lock_interface):
        print(UNLOCKED_MESSAGE.format(the_scene.name), flush=True)


@persistent
def render_done(the_scene, _=None):
    RUNTIME.rendering = False
    companions.use_viewport_mesh()
    pack_layer_images()


@persistent
def load_pre(*_):
    RUNTIME.clear()


@persistent
def load_post(*_):
    """The user's Lock Interface choice is kept: the panel says when renders need it."""
    RUNTIME.clear()
    companions.remove_orphan_companions()
    companions.mend_render_meshes()
    for the_scene in bpy.data.scenes:
        if the_scene.library is None:
            prepare(the_scene)


@persistent
def undo_redo(*_):
    """Undo may have given back other objects at the same places: forget the caches."""
    scene.drop_caches()
    RUNTIME.stand_ins.clear()


@persistent
def save_pre(*_):
    """Our meshes are saved empty and our companions hidden: they are rebuilt from the settings
    whenever the file is used, and a file linking this one's ocean then shows only the sea its
    own stand-in draws, not a grid built for this file's camera."""
    if RUNTIME.rendering:  # a save during a render keeps what the render is writing
        return
    for obj in bpy.data.objects:
        if (obj.type == "MESH" and (obj.projgrid.is_ocean or obj.get(scene.STAND_IN))
                and scene.local(obj) and scene.owns(obj.data) and scene.local(obj.data)
                and not obj.data.is_editmode and not baked.is_baked(obj)):  # as baked
            companions.empty_for_save(obj)
    pack_layer_images()


@persistent
def playback_done(*_):
    """Playback wrote the layer's images each frame: packed once it stops."""
    pack_layer_images()


def pack_layer_images():
    """Our slope layer images, written each frame and not packed (3 ms each), packed once."""
    for image in material_inputs.layer_images():
        if image.is_dirty:
            image.pack()


STILL = 0.5  # s without a frame change after which scrubbing the timeline has stopped
_LAST_CHANGE = [0.0]


def pack_when_still():
    """Scrubbing writes the layer's images each frame, and no handler says when it stops: they
    are packed once the frame has stood still STILL seconds (a timer: the interface's only;
    playback's end packs them itself)."""
    _LAST_CHANGE[0] = time.monotonic()
    if not bpy.app.timers.is_registered(still):
        bpy.app.timers.register(still, first_interval=STILL)


def still():
    """The timer of `pack_when_still`: returns the seconds to wait again, or None when done."""
    wait = _LAST_CHANGE[0] + STILL - time.monotonic()
    if wait > 0.0 or RUNTIME.rendering:
        return max(wait, STILL)
    wm = bpy.context.window_manager
    if wm is not None and any(w.screen is not None and w.screen.is_animation_playing
                              for w in wm.windows):
        return None
    pack_layer_images()
    return None


@persistent
def save_post(*_):
    """Back to what was on screen before the save."""
    context = bpy.context
    if not RUNTIME.rendering and context.scene is not None and context.view_layer is not None:
        frame.update_scene(context.scene, context.evaluated_depsgraph_get(), render=False,
                           frame_change=False)


HANDLERS = (
    ("frame_change_post", frame_change_post),
    ("depsgraph_update_post", depsgraph_update_post),
    ("render_init", render_init),
    ("render_complete", render_done),
    ("render_cancel", render_done),
    ("load_pre", load_pre),
    ("load_post", load_post),
    ("undo_post", undo_redo),
    ("redo_post", undo_redo),
    ("save_pre", save_pre),
    ("animation_playback_post", playback_done),
    ("save_post", save_post),
)


def register():
    for name, fn in HANDLERS:
        getattr(bpy.app.handlers, name).append(fn)


def unregister():
    if bpy.app.timers.is_registered(still):
        bpy.app.timers.unregister(still)
    for name, fn in reversed(HANDLERS):
        handlers = getattr(bpy.app.handlers, name)
        while fn in handlers:
            handlers.remove(fn)
