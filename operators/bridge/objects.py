"""Reading the sun and the objects around the water: the lamp the glint follows, the objects'
world boxes (kept between viewport updates in the scene's cache), and the frame's
effects.SceneFacts. Nothing here writes."""

import numpy as np

from ...projgrid_addon import effects, shading
from .scene import GEOMETRY_TYPES, OBJECT_EFFECTS, owns, valid_cache


def sun_lamp(scene, depsgraph, render):
    """The first sun lamp of the scene that renders (evaluated), or None; in the viewport the
    one found at the last structural change, unless a lamp changed since."""
    if render:
        found = _find_sun(scene)
    else:
        cache = valid_cache(scene)
        if cache.sun is None:
            cache.sun = _find_sun(scene) or False
        found = cache.sun or None
    return found.evaluated_get(depsgraph) if found is not None else None


def _find_sun(scene):
    for obj in scene.objects:
        if obj.type == "LIGHT" and obj.data.type == "SUN" and not obj.hide_render:
            return obj
    return None


class ObjectBoxes:
    """World bounding boxes of a scene's visible geometry (other than oceans and ours), and
    which are in view or mirrored in view for each of the last few (camera, level) the oceans
    showing asked about (`_View`); a view's facts are kept while nothing in it or mirrored in
    it changes. In the viewport every box is read at once (the scene's objects' bound boxes,
    matrices and switches through foreach_get), and an update's moved objects are re-read
    together (`refresh`); a render reads each object as its own evaluation has it."""

    VIEWS = 4  # two oceans, or a stand-in per instance, each keep their own flags
    BULK = 16  # objects moved in one update from which every box is re-read at once

    def __init__(self, scene, render, depsgraph=None):
        self.scene, self.render, self.depsgraph = scene, render, depsgraph
        every = list(scene.objects)
        self.count = len(every)  # the scene's objects `rows` index
        self.rows = np.array([i for i, o in enumerate(every) if self._counts(o)], dtype=int)
        self.objects = [every[i] for i in self.rows]
        self.names = [o.name for o in self.objects]
        floating = set(valid_cache(scene).floats)  # they ride the waves (floats.py)
        self.rides = np.array([o in floating for o in self.objects], dtype=bool)
        self.index = {o.session_uid: i for i, o in enumerate(self.objects)}
        self.boxes = np.zeros((len(self.objects), 8, 3))
        self.hidden = np.zeros(len(self.objects), dtype=bool)
        self._local = np.empty(24, dtype=np.float32)
        self.views = {}  # (camera key, level) -> _View, oldest first
        if render:
            for i in range(len(self.objects)):
                self._read(i)
        else:
            self._read_all()

    def _counts(self, obj):
        return (obj.type in GEOMETRY_TYPES and not obj.projgrid.is_ocean and not owns(obj))

    def _read(self, i):
        """Row i read from its object alone (its evaluated geometry's box in renders)."""
        obj = self.objects[i]
        self.names[i] = obj.name
        if self.depsgraph is not None:
            obj = obj.evaluated_get(self.depsgraph)
        self.hidden[i] = obj.hide_render if self.render else obj.hide_viewport
        obj.bound_box.foreach_get(self._local)  # the evaluated geometry's box
        world = np.array(obj.matrix_world, dtype=np.float64)
        self.boxes[i] = self._local.reshape(8, 3) @ world[:3, :3].T + world[:3, 3]

    def _read_all(self):
        """Every row read at once from the scene's objects, as many as when `rows` was made
        (else an update changed them and the cache is rebuilt after it): viewport only."""
        objects, count = self.scene.objects, self.count
        if len(objects) != count:
            return
        local = np.empty(count * 24, dtype=np.float32)
        objects.foreach_get("bound_box", local)
        world = np.empty(count * 16, dtype=np.float32)
        objects.foreach_get("matrix_world", world)  # (column-major)
        hidden = np.empty(count, dtype=bool)
        objects.foreach_get("hide_viewport", hidden)
        rows = self.rows
        world = world.reshape(count, 4, 4).transpose(0, 2, 1)[rows].astype(np.float64)
        corners = local.reshape(count, 8, 3)[rows]
        self.boxes[:] = (np.einsum("nkj,nij->nki", corners, world[:, :3, :3])
                         + world[:, None, :3, 3])
        self.hidden[:] = hidden[rows]
        self.names = [o.name for o in self.objects]

    def refresh(self, objects):
        """Re-read the rows of the objects an update touched; returns whether they may matter
        to the facts of some view: in it or mirrored in it, before or after, or their
        visibility changed (an unknown object is new: the cache is rebuilt at the next
        structural change)."""
        found = [self.index.get(o.session_uid) for o in objects]
        unknown = any(i is None for i in found)
        rows = np.unique(np.array([i for i in found if i is not None], dtype=int))
        if rows.size == 0:
            return unknown
        before = [(view.in_view[rows].copy(), view.mirrored[rows].copy())
                  for view in self.views.values()]
        hidden = self.hidden[rows].copy()
        if rows.size >= self.BULK and not self.render:
            self._read_all()
        else:
            for i in rows:
                self._read(i)
        matters = unknown or not self.views or bool((hidden != self.hidden[rows]).any())
        for view, (was_in, was_mirrored) in zip(self.views.values(), before, strict=True):
            view.see(self.boxes, rows)
            # Entered or left the view, or moved while seen there.
            seen_before = (was_in | was_mirrored) & ~hidden
            if ((was_in != view.in_view[rows]).any() or (was_mirrored != view.mirrored[rows]).any()
                    or seen_before.any()):
                view.version += 1
                matters = True
        return matters

    def refresh_all(self):
        """Every row read again (the frame changed: anything animated may have moved)."""
        if self.render:
            for i in range(len(self.objects)):
                self._read(i)
        else:
            self._read_all()
        rows = np.arange(len(self.objects))
        for view in self.views.values():
            view.see(self.boxes, rows)
            view.version += 1

    def facts_objects(self, camera, level, key):
        """(SceneObjects (effects.py) of the boxes in view or mirrored in view, their compact
        key), heights relative to the water `level`; the flags are computed for all only for a
        (camera, level), whose comparable form is `key`, not seen lately."""
        view = self.views.pop(key, None)
        if view is None:
            view = _View(camera, level, len(self.objects))
            if self.objects:
                view.see(self.boxes, np.arange(len(self.objects)))
        self.views[key] = view
        while len(self.views) > self.VIEWS:
            self.views.pop(next(iter(self.views)))
        if view.facts is not None and view.facts[0] == view.version:
            return view.facts[1]
        rows = np.flatnonzero((view.in_view | view.mirrored) & ~self.hidden)
        z = self.boxes[rows, :, 2] - level
        objects = [effects.SceneObject(self.names[i], float(lo), float(hi),
                                       bool(view.in_view[i]), self.boxes[i],
                                       bool(view.mirrored[i]), bool(self.rides[i]))
                   for i, lo, hi in zip(rows, z.min(axis=1), z.max(axis=1), strict=True)]
        facts = (objects, effects.objects_key(objects))
        view.facts = (view.version, facts)
        return facts


class _View:
    """Which boxes are in view, or mirrored in the water at `level` in view, of a camera."""

    def __init__(self, camera, level, count):
        self.camera, self.level = camera, level
        self.in_view = np.zeros(count, dtype=bool)
        self.mirrored = np.zeros(count, dtype=bool)
        self.version, self.facts = 0, None

    def see(self, boxes, rows):
        picked = boxes[rows]
        mirrored = picked * (1.0, 1.0, -1.0) + (0.0, 0.0, 2.0 * self.level)
        seen = effects.boxes_in_view(self.camera, np.concatenate([picked, mirrored]))
        self.in_view[rows], self.mirrored[rows] = seen.reshape(2, -1)

    def flags(self, i):
        return bool(self.in_view[i]), bool(self.mirrored[i])


def scene_facts(scene, depsgraph, render, sun, camera, camera_key, level, settings):
    """effects.SceneFacts of this frame: camera against the water, the objects in view, the
    sun (`sun`: the evaluated lamp or None) and the wind. Heights are relative to the level; the
    waves' bound is the plan's (frame_plan.plan), 0 here."""
    elevation = direction = None
    if sun is not None:
        direction = tuple(shading.sun_direction(sun.matrix_world))
        elevation = shading.sun_elevation(direction)
    needs_objects = (any(getattr(settings, e) == "AUTO" for e in OBJECT_EFFECTS)
                     or any(getattr(settings, e) == "ON" for e in ("contact_foam", "caustics"))
                     or settings.wakes != "OFF")  # keyed objects crossing the water: wakes
    objects, objects_key = [], None
    if needs_objects:
        if render:
            boxes = ObjectBoxes(scene, True, depsgraph)
        else:
            cache = valid_cache(scene)
            if cache.boxes is None:
                cache.boxes = ObjectBoxes(scene, False)
            boxes = cache.boxes
        objects, objects_key = boxes.facts_objects(camera, level, (camera_key, level))
    return effects.SceneFacts(camera_height=float(camera.position[2] - level), bound=0.0,
                              wind_speed=settings.wind_speed, sun_elevation=elevation,
                              objects=objects, sun_direction=direction,
                              objects_key=objects_key)
