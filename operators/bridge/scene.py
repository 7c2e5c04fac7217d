"""Reading the scene: the oceans and their height sources, what is kept between viewport
updates, and where oceans show (the camera and the time: shot.py; the sun and the objects:
objects.py).

Nothing here writes Blender data. What a viewport update did not touch is kept from the last
one (`SceneCache`): the list of oceans, where they show, the sun lamp, and the objects' world
boxes, so an update unrelated to the ocean costs little however big the scene is. Renders read
everything afresh from the render's own evaluation.
"""

from dataclasses import dataclass, field

import bpy
import numpy as np

from ...projgrid_addon import frame_plan
from ...projgrid_addon.projected_grid import check_resolution
from ...shaders.nodes import TAG
from .state import RUNTIME

COMPANIONS = {  # setting: (name suffix, effects that show it)
    "water_body": (" Water Body", ("underwater", "refraction")),
    # Light passes the water: the ocean casts no shadow of its own, this one does (caustics).
    "shadow_caster": (" Shadow", ("underwater", "refraction", "caustics", "godrays")),
    # The ocean is left out of sphere probes' captures while this one is shown.
    "reflection_probe": (" Reflection", ("local_reflections",)),
    "spray_cloud": (" Spray", ("spray",)),
}
COMPANION = "projgrid_companion"  # ID property naming a companion's setting on its surface
STAND_IN = "projgrid_stand_in"  # ID property of a stand-in: the appearance key it draws
# Object types with geometry that can stand in, on or under the water.
GEOMETRY_TYPES = {"MESH", "CURVE", "SURFACE", "META", "FONT", "CURVES", "POINTCLOUD", "VOLUME",
                  "GPENCIL", "GREASEPENCIL"}
# A frame change updating more data-blocks than this is followed in bulk (note_frame).
MANY_UPDATES = 64
# The effects whose AUTO decision looks at the objects in view (and the ON ones that use them).
OBJECT_EFFECTS = ("contact_foam", "refraction", "caustics", "local_reflections")


def owns(id_block):
    return id_block is not None and bool(id_block.get(TAG))


def local(id_block):
    """Data of this file: neither linked from a library nor a library override."""
    return id_block.library is None and id_block.override_library is None


def writable(obj):
    """Whether the ocean's own mesh is ours to write: a local object with a local mesh (a linked
    ocean's or a library override's mesh belongs to its library, which we never write)."""
    return local(obj) and obj.data is not None and local(obj.data)


def height_field(settings):
    """The core height source for (possibly evaluated) settings (frame_plan.height_source)."""
    return frame_plan.height_source(read_settings(settings))


def read_settings(values):
    """frame_plan.Settings of an ocean's (possibly evaluated) `values` (obj.projgrid), with the
    span of its keyframed wind speed (`wind_span`)."""
    return frame_plan.settings_of(values, wind_span(values.id_data))


WIND_PATHS = ("projgrid.wind_speed", "projgrid.wind_direction")


def wind_span(ocean):
    """(least, most) wind speed (m/s) the ocean's keyframed wind takes over its keyframes, or
    None when it is not keyframed: the spectral sea lays its tiles out for the whole span, so a
    wind that builds changes the waves' heights smoothly, not their tiles (a pure function of
    the scene, not of the frame)."""
    curve = wind_curves(ocean).get(WIND_PATHS[0])
    if curve is None or not len(curve.keyframe_points):
        return None
    start, end = curve.range()
    frames = np.linspace(start, end, max(int(end - start) + 1, 2))
    speeds = [max(curve.evaluate(f), 0.0) for f in frames]
    return (round(float(min(speeds)), 6), round(float(max(speeds)), 6))


def wind_curves(ocean):
    """{data path: F-curve} of the ocean's keyframed wind speed and direction (WIND_PATHS)."""
    return {c.data_path: c for c in bag_curves(ocean) if c.data_path in WIND_PATHS}


def bag_curves(tree):
    """The F-curves of `tree`'s (an ID's) action for it (none without one)."""
    bag = channelbag(tree)
    return list(bag.fcurves) if bag is not None else []


def channelbag(tree):
    """`tree`'s action's channels for its slot, or None."""
    data = tree.animation_data
    if data is None or data.action is None:
        return None
    from bpy_extras import anim_utils

    return anim_utils.action_get_channelbag_for_slot(data.action, data.action_slot)


def is_ocean(obj):
    return obj.type == "MESH" and obj.projgrid.is_ocean


def ocean_objects(scene):
    """The oceans placed in `scene` itself."""
    return [obj for obj in scene.objects if is_ocean(obj)]


def active_ocean(context):
    """The ocean the user works on: the active object if an ocean, else the scene's first."""
    obj = context.active_object
    if obj is not None and is_ocean(obj):
        return obj
    oceans = ocean_objects(context.scene) if context.scene else []
    return oceans[0] if oceans else None


# ---- What is kept between viewport updates ----------------------------------------------------

@dataclass
class SceneCache:
    """A scene's facts kept between viewport updates (rebuilt when `valid` is False)."""

    valid: bool = False
    generation: int = 0  # how many times it was made: companions follow collections anew
    counts: tuple = ()  # objects, collections and scenes in the file when it was made
    oceans: list = field(default_factory=list)
    floats: list = field(default_factory=list)  # mesh objects riding an ocean (floats.py)
    appearances: list = field(default_factory=list)
    sun: object = None
    boxes: object = None  # objects.ObjectBoxes, made on first use


def _file_cache(scene):
    return RUNTIME.scenes.setdefault(scene.session_uid, SceneCache())


def _counted(scene, object_count, changed=False):
    """The cache of `scene`, dropped if `changed` or if the file's counts of objects
    (`object_count`; -1: not read), collections or scenes changed since it was made."""
    cache = _file_cache(scene)
    counts = (object_count, len(bpy.data.collections), len(bpy.data.scenes))
    if changed or (cache.counts != counts and object_count >= 0):
        cache.valid, cache.counts = False, counts
    return cache


def note_updates(scene, updates, object_count):
    """Let the cache of `scene` follow a depsgraph update: structural changes (objects or
    collections added, removed, relinked) drop it; moved, reshaped or hidden objects refresh
    their boxes; a lamp's change drops the sun. Returns whether the update can matter to an
    ocean: not when it only touched objects that stay out of view and unmirrored, say, or a
    material of the user's (`updates`: the IDs of depsgraph.updates; `object_count`:
    len(bpy.data.objects), -1 if not read)."""
    cache = _counted(scene, object_count)
    relevant = not cache.valid
    moved = []  # geometry whose boxes are read again together
    for id_block in updates:
        if isinstance(id_block, bpy.types.Collection):
            cache.valid, relevant = False, True
        elif isinstance(id_block, bpy.types.Object):
            obj = id_block.original
            if obj == scene.camera or obj.type in ("CAMERA", "LIGHT"):
                relevant = True
                if obj.type == "LIGHT":
                    cache.sun = None
            elif obj.type == "EMPTY":
                relevant = relevant or obj.instance_type == "COLLECTION"
            elif obj.type in GEOMETRY_TYPES:
                moved.append(obj)
        elif isinstance(id_block, (bpy.types.Scene, bpy.types.Camera, bpy.types.Light)):
            relevant = True
            if isinstance(id_block, bpy.types.Light):
                cache.sun = None
    if moved:
        boxes = cache.boxes if cache.valid else None
        relevant = (boxes.refresh(moved) if boxes is not None else True) or relevant
    return relevant


def note_frame(scene, object_count, collections_updated):
    """Let the cache of `scene` follow a frame change in the viewport that updated more than
    MANY_UPDATES data-blocks: every box is read again at once and the sun lamp looked for
    again (walking the update's list cost more than the frame with thousands of animated
    objects); an updated collection, or a change in the file's counts of objects, collections
    or scenes, drops it."""
    cache = _counted(scene, object_count, collections_updated)
    cache.sun = None
    if cache.valid and cache.boxes is not None:
        cache.boxes.refresh_all()


def valid_cache(scene):
    """The scene's cache, rebuilt if dropped or if an object it holds was deleted."""
    cache = _file_cache(scene)
    if cache.valid:
        try:
            for obj in (*cache.oceans, *cache.floats):
                obj.name_full  # noqa: B018 (raises ReferenceError once deleted)
            for app in cache.appearances:
                for instancer, _ in app.chain:
                    instancer.name_full  # noqa: B018
        except ReferenceError:
            cache.valid = False
    if not cache.valid:
        meshes = [o for o in bpy.data.objects if o.type == "MESH"]
        cache.oceans = [o for o in meshes if o.projgrid.is_ocean]
        cache.floats = [o for o in meshes if o.projgrid_float.ocean is not None]
        cache.appearances = _appearances(scene, cache.oceans)
        cache.sun, cache.boxes, cache.valid = None, None, True
        cache.generation += 1
    return cache


def generation(scene):
    """A number that changes whenever the scene's structure may have (see SceneCache)."""
    return valid_cache(scene).generation


def drop_caches():
    """Forget everything kept between updates (after an undo or a load)."""
    RUNTIME.scenes.clear()


# ---- Where oceans show --------------------------------------------------------------------

@dataclass
class Appearance:
    """One place an ocean shows in a scene: in the scene or a background set of it (`chain`
    empty), or inside collection instances (`chain`: (instancer, instanced collection) pairs,
    outermost first)."""

    ocean: object
    scene: object
    chain: tuple = ()
    count: int = 1  # the ocean's appearances in the scene

    @property
    def key(self):
        """What a stand-in of ours draws: the scene it renders in, the ocean's and the
        instancers' full names."""
        names = (self.scene, self.ocean, *(i for i, _ in self.chain))
        return "|".join(o.name_full for o in names)

    @property
    def needs_stand_in(self):
        """Drawn by a stand-in of ours: the ocean's mesh is not ours to write, it shows more
        than once (one mesh cannot be right in two places), or it shows inside an instance
        (whose transform its own companions would take too)."""
        return self.count > 1 or bool(self.chain) or not writable(self.ocean)

    @property
    def objects(self):
        """The ocean and its instancers: the objects whose visibility decides whether it shows."""
        return (self.ocean, *(i for i, _ in self.chain))

    def world(self, depsgraph):
        """The ocean's evaluated world matrix where it shows (float64)."""
        m = np.eye(4)
        for instancer, collection in self.chain:
            offset = np.eye(4)
            offset[:3, 3] = -np.array(collection.instance_offset, dtype=np.float64)
            m = m @ np.array(instancer.evaluated_get(depsgraph).matrix_world,
                             dtype=np.float64) @ offset
        return m @ np.array(self.ocean.evaluated_get(depsgraph).matrix_world, dtype=np.float64)

    @property
    def top(self):
        """The outermost object: the ocean itself, or the outermost instancer."""
        return self.chain[0][0] if self.chain else self.ocean

    def shown(self, depsgraph, render):
        """Whether this evaluation draws it: each object on the way is in the depsgraph (so
        visible in renders or viewports and not in an excluded collection), and in the viewport
        the outermost one is not hidden in the depsgraph's view layer."""
        if not all(o.evaluated_get(depsgraph).is_evaluated for o in self.objects):
            return False
        if not self.in_layer(depsgraph.view_layer, render):
            return False
        return render or not hidden_in(self.top, depsgraph.view_layer)

    def in_layer(self, view_layer, render):
        """Whether the ocean, placed in the scene itself, is in `view_layer` through a
        collection neither excluded nor, in renders, hidden in renders. (An object in such a
        collection is still evaluated when the collection is instanced elsewhere: there it
        shows, here it does not.) True for an appearance through instances or a background
        set."""
        if self.chain or self.scene not in self.ocean.users_scene:
            return True
        holders = set(self.ocean.users_collection)
        todo = [view_layer.layer_collection]
        while todo:
            layer = todo.pop()
            if layer.exclude or (render and layer.collection.hide_render):
                continue
            if layer.collection in holders:
                return True
            todo.extend(layer.children)
        return False

    def layer_flags(self, view_layer):
        """(holdout, indirect only) of the outermost object in `view_layer`, its collections'
        flags included."""
        try:
            return (self.top.holdout_get(view_layer=view_layer) or self.ocean.is_holdout,
                    self.top.indirect_only_get(view_layer=view_layer))
        except RuntimeError:  # not in this view layer (a background set's object)
            return self.ocean.is_holdout, False


def hidden_in(obj, view_layer):
    """Whether `obj` is hidden (the eye) in `view_layer`; False where it is not in it."""
    try:
        return obj.hide_get(view_layer=view_layer)
    except RuntimeError:
        return False


def _placements(obj, scenes, parents, depth=0):
    """The instancer chains through which `obj` shows in `scenes` (the empty chain: directly)."""
    chains = []
    users = obj.users_scene
    if any(s in users for s in scenes):
        chains.append(())
    if depth >= 8:  # instances nested deeper than this are left out
        return chains
    holders, todo = [], list(obj.users_collection)
    while todo:
        c = todo.pop()
        if c not in holders:
            holders.append(c)
            todo.extend(parents().get(c.as_pointer(), ()))
    for collection in holders:
        for instancer in collection.users_dupli_group:
            if (instancer.instance_type != "COLLECTION"
                    or instancer.instance_collection != collection):
                continue  # a collection pointer kept by an object that no longer instances
            for outer in _placements(instancer, scenes, parents, depth + 1):
                chains.append(outer + ((instancer, collection),))
    return chains


def _appearances(scene, oceans):
    scenes = [scene]
    while scenes[-1].background_set is not None and scenes[-1].background_set not in scenes:
        scenes.append(scenes[-1].background_set)
    table = {}

    def parents():  # child collection -> its parents, built when first needed
        if not table:
            table[None] = None
            for collection in bpy.data.collections:
                for child in collection.children:
                    table.setdefault(child.as_pointer(), []).append(collection)
        return table

    found = []
    for ocean in oceans:
        chains = _placements(ocean, scenes, parents)
        found += [Appearance(ocean, scene, chain, len(chains)) for chain in chains]
    return found


def appearances(scene, only=None):
    """Every place an ocean (or only `only`) shows in `scene`, its background sets included."""
    found = valid_cache(scene).appearances
    return [a for a in found if a.ocean == only] if only is not None else list(found)


def resolution(settings, render):
    """The grid resolution the settings ask for (ValueError naming it if out of range)."""
    if render:
        return check_resolution((settings.render_resolution_x, settings.render_resolution_y))
    return check_resolution((settings.resolution_x, settings.resolution_y))
