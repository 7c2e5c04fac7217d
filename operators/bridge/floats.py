"""Floating objects in the Blender layer. A float is a mesh object of the user's with our Child
Of constraint (CONSTRAINT) to our follower, an empty whose matrix carries the object from where
its own animation places it onto the waves (floating.pose): its keyframes stay its own and
editable, and each frame writes only our follower. Gathered per ocean (`gather`: plain
floating.Float), planned with the ocean's frame, written by `apply`."""

from dataclasses import replace

import bpy
import numpy as np
from mathutils import Matrix

from ...projgrid_addon import floating
from ...projgrid_addon.wakes import WINDOW
from ...shaders.nodes import TAG
from . import scene

CONSTRAINT = "Ocean Float"
COURSE_STEP = 0.2  # s between the samples of a float's course (its wake: wake_field.py)
MOST_WAKES = 16  # the floats nearest the camera whose wakes are drawn


def refusal(obj):
    """Why `obj` cannot be made to float (None: it can)."""
    if obj.type != "MESH":
        return "not a mesh"
    if scene.is_ocean(obj) or obj.get(TAG):
        return "an ocean's or ours"
    if obj.library is not None:
        return "linked from a library (make it a library override)"
    if obj.parent is not None:
        return "it has a parent (float the top of the hierarchy)"
    if floating_on(obj) is not None:
        return "it floats already"
    return None


def followers(ocean):
    """Our followers of the objects floating on `ocean`."""
    return [o.projgrid_float.follower for o in bpy.data.objects
            if o.type == "MESH" and o.projgrid_float.ocean == ocean
            and o.projgrid_float.follower is not None]


def floating_on(obj):
    """The ocean `obj` floats on, or None."""
    return obj.projgrid_float.ocean


def float_object(obj, ocean, the_scene):
    """Make `obj` ride `ocean`: our follower (an empty, hidden, in the scene's collection)
    and our constraint on `obj` to it, added last."""
    follower = bpy.data.objects.new(f"{obj.name} Float", None)
    follower[TAG] = True
    follower.empty_display_size = 0.5
    follower.hide_viewport = follower.hide_render = True
    the_scene.collection.objects.link(follower)
    constraint = obj.constraints.new("CHILD_OF")
    constraint.name = CONSTRAINT
    constraint.target = follower
    constraint.inverse_matrix = Matrix.Identity(4)
    obj.projgrid_float.follower = follower
    obj.projgrid_float.ocean = ocean


def unfloat_object(obj):
    """Undo `float_object`: our constraint and our follower removed, the object as it was."""
    settings = obj.projgrid_float
    follower = settings.follower
    for constraint in [c for c in obj.constraints
                       if c.type == "CHILD_OF" and c.name.startswith(CONSTRAINT)
                       and (c.target is None or c.target == follower)]:
        obj.constraints.remove(constraint)
    settings.ocean = None
    settings.follower = None
    if follower is not None and scene.owns(follower) and follower.users <= 1:
        bpy.data.objects.remove(follower)


def gather(app, the_scene, depsgraph, t=0.0, per_frame=0.0, near=None):
    """The floats riding the ocean of appearance `app` (its own placement only), as
    `the_scene` places them at this frame (time `t`, s; `per_frame` s a frame), and with
    `near` (a camera's x, y) where the keys of the MOST_WAKES nearest it took them over the
    wake's window (their courses: reading one costs some 0.2 ms): floating.Float each
    (nothing written)."""
    if app.chain:
        return ()
    out, objects = [], []
    for obj in scene.valid_cache(the_scene).floats:
        settings = obj.projgrid_float
        if settings.ocean != app.ocean or obj.parent is not None or not follows(obj):
            continue
        ev = obj.evaluated_get(depsgraph)
        basis = np.array(ev.matrix_basis, dtype=np.float64)  # its own, before constraints
        corners = np.array([tuple(c) for c in ev.bound_box], dtype=np.float64)
        lo, hi = corners.min(axis=0), corners.max(axis=0)
        world = corners @ basis[:3, :3].T + basis[:3, 3]
        length = (hi[0] - lo[0]) * float(np.linalg.norm(basis[:3, 0]))
        beam = (hi[1] - lo[1]) * float(np.linalg.norm(basis[:3, 1]))
        centre = basis[:3, :3] @ (0.5 * (lo + hi)) + basis[:3, 3]
        s = ev.projgrid_float
        if s.sits == "DRAFT":
            draft = float(s.draft)
        else:
            volume = volume_of(obj.data) * abs(float(np.linalg.det(basis[:3, :3])))
            draft = floating.draft(float(s.density), volume, max(length * beam, 1e-6))
        out.append(floating.Float(
            key=settings.follower.name, origin=tuple(basis[:3, 3]), centre=tuple(centre[:2]),
            heading=float(np.arctan2(basis[1, 0], basis[0, 0])), length=length, beam=beam,
            keel=float(world[:, 2].min()), draft=draft, response=float(s.response),
            name=obj.name))
        objects.append(obj)
    if near is None:
        return tuple(out)
    nearest = sorted(range(len(out)), key=lambda i: np.hypot(
        out[i].centre[0] - near[0], out[i].centre[1] - near[1]))[:MOST_WAKES]
    for i in nearest:
        out[i] = replace(out[i], course=course(objects[i], t, per_frame, out[i].centre))
    return tuple(out)


def wakers(the_scene, depsgraph, facts, t, per_frame, near, riding):
    """The objects whose keys move them across the water without floating (the frame's
    objects in view or mirrored in it whose boxes cross the level, not among `riding`'s
    names), the MOST_WAKES nearest `near` (a camera's x, y): (name, course, draft, length,
    beam) each for their wakes (wake_field.course); the draft is how far they reach below
    the level. Nothing written."""
    crossing = [o for o in facts.objects if not o.rides and o.name not in riding
                and o.z_min < 0.0 < o.z_max and o.corners is not None]
    crossing.sort(key=lambda o: np.hypot(*(o.corners[:, :2].mean(axis=0) - near)))
    out = []
    for o in crossing[:MOST_WAKES]:
        obj = the_scene.objects.get(o.name)
        if obj is None or obj.type != "MESH":
            continue
        axes = np.array(obj.evaluated_get(depsgraph).matrix_world, dtype=np.float64)[:3, :2]
        length, beam = (float(np.ptp(o.corners @ (a / max(np.linalg.norm(a), 1e-12))))
                        for a in axes.T)
        path = course(obj, t, per_frame, tuple(o.corners[:, :2].mean(axis=0)))
        if path:
            out.append((o.name, path, -o.z_min, length, beam))
    return tuple(out)


def course(obj, t, per_frame, centre):
    """(times, x, y): where `obj`'s location keys took its footprint's centre (`centre` now,
    x, y) over the past WINDOW seconds up to `t`, on an absolute lattice of COURSE_STEP s
    and now (the lattice's newest dropped when now is nearer it than half a step: a short
    last step's speed is noise); () when neither its x nor its y is keyed to move. The keys
    give the course's shape; it is moved to end at `centre` (what else places the object,
    its delta transform, NLA, drivers, is taken as held over the window)."""
    curves = {c.array_index: c for c in scene.bag_curves(obj)
              if c.data_path == "location" and c.array_index in (0, 1) and not c.mute}
    if per_frame <= 0.0 or not any(
            c.modifiers or len({round(k.co[1], 9) for k in c.keyframe_points}) > 1
            for c in curves.values()):
        return ()
    newest = np.floor(t / COURSE_STEP) * COURSE_STEP
    times = newest - COURSE_STEP * np.arange(int(WINDOW / COURSE_STEP), -1, -1)
    if t - times[-1] < 0.5 * COURSE_STEP:
        times = times[:-1]
    times = np.append(times, t)
    frames = times / per_frame
    x, y = (np.array([curves[i].evaluate(f) for f in frames]) if i in curves
            else np.zeros(len(frames)) for i in (0, 1))
    x, y = x + (centre[0] - x[-1]), y + (centre[1] - y[-1])
    return tuple(times.tolist()), tuple(x.tolist()), tuple(y.tolist())


def follows(obj):
    """Whether `obj` has our constraint to its follower, on."""
    follower = obj.projgrid_float.follower
    return follower is not None and any(
        c.type == "CHILD_OF" and c.target == follower and not c.mute for c in obj.constraints)


_VOLUMES = {}  # (mesh session_uid, vertices, triangles) -> volume


def volume_of(mesh):
    """The volume (m^3, local units) a closed mesh encloses: the sum over its triangles of
    the signed tetrahedra to the origin (kept per mesh and size)."""
    key = (mesh.session_uid, len(mesh.vertices), len(mesh.loop_triangles))
    if key not in _VOLUMES:
        co = np.empty(len(mesh.vertices) * 3, np.float64)
        mesh.vertices.foreach_get("co", co)
        tris = np.empty(len(mesh.loop_triangles) * 3, np.int64)
        mesh.loop_triangles.foreach_get("vertices", tris)
        v = co.reshape(-1, 3)[tris.reshape(-1, 3)]
        _VOLUMES[key] = abs(float(np.einsum("ij,ij->i", v[:, 0],
                                            np.cross(v[:, 1], v[:, 2])).sum()) / 6.0)
    return _VOLUMES[key]


def apply(poses):
    """Each follower (ours) set to its planned world matrix ((key, 4 x 4) pairs)."""
    for key, matrix in poses:
        follower = bpy.data.objects.get(key)
        if follower is None or not scene.owns(follower) or follower.library is not None:
            continue
        new = Matrix(matrix.tolist())
        if any(abs(a - b) > 1e-6 for r, q in zip(follower.matrix_world, new, strict=True)
               for a, b in zip(r, q, strict=True)):
            follower.matrix_world = new
