"""Reading the camera and the time: the camera rendering this frame as float64 matrices, the
scene time (time stretching included), and the ocean's transform. Nothing here writes."""

import numpy as np

from ...projgrid_addon.camera import blender_projection, rigid_view
from .scene import bag_curves


def render_size(scene):
    r = scene.render
    pct = r.resolution_percentage / 100.0
    return (max(1, round(r.resolution_x * pct)), max(1, round(r.resolution_y * pct)),
            r.pixel_aspect_x, r.pixel_aspect_y)


def scene_camera(scene, frame_change=True, frame=None):
    """The camera this frame (or `frame`) renders with. On a frame change, the timeline
    markers' camera switch, which Blender applies to `scene.camera` only after
    frame_change_post (BKE_scene_camera_switch_find); between frames, the camera the user
    set."""
    markers = [(m.frame, m.camera) for m in scene.timeline_markers
               if m.camera is not None and not m.camera.hide_render]
    if not markers or not frame_change:
        return scene.camera
    frame = scene.frame_current if frame is None else frame
    past = [m for m in markers if m[0] <= frame]
    if past:
        return max(past, key=lambda m: m[0])[1]
    return min(markers, key=lambda m: m[0])[1]


def camera_for(scene, depsgraph, camera=None, frame_change=True):
    """(view, proj) float64 of the camera rendering this frame (ValueError with a user message
    if none or not usable), built from the camera's own settings: Blender's float32 matrix
    loses the far corners for clip ranges wider than about 1e7 (camera.blender_projection)."""
    cam = camera or scene_camera(scene, frame_change)
    if cam is None:
        raise ValueError("the scene has no camera (set one, or use Live Preview)")
    cam_eval = cam.evaluated_get(depsgraph)
    x, y, sx, sy = render_size(scene)
    view = rigid_view(cam_eval.matrix_world)
    if cam_eval.type != "CAMERA":  # a lamp or empty as the camera: Blender's defaults
        proj = cam_eval.calc_matrix_camera(depsgraph, x=x, y=y, scale_x=sx, scale_y=sy)
        return view, np.array(proj, dtype=np.float64)
    data = cam_eval.data
    if data.type == "PANO":
        raise ValueError(f"camera {cam.name!r} is panoramic; the projected grid needs a "
                         "perspective or orthographic camera")
    try:
        proj = blender_projection(data.type == "ORTHO", data.lens, data.ortho_scale,
                                  (data.sensor_width, data.sensor_height), data.sensor_fit,
                                  (data.shift_x, data.shift_y),
                                  (data.clip_start, data.clip_end), (x, y), (sx, sy))
    except ValueError as e:
        raise ValueError(f"camera {cam.name!r}: {e}") from None
    return view, proj


# m: how far across its heading a dollying camera's keyed path may stray (the canonical cameras
# round its sideways place to a 250th of their step, centimetres: past_grid.SIDEWAYS)
STRAY = 0.005
PATH_FRAMES = 256  # at most this many frames of the keyed path read (a baked path: its keys)


def dolly(cam):
    """Whether the camera object `cam` moves along its heading alone (past_grid.py): its
    location's x or y keyed along a line it looks along (the path read at its keys, between
    them and a frame beyond either end, where it may extrapolate), everything else held:
    F-curves on anything else flat (Location and Rotation keyed, the height and rotation
    held), on its camera data too (lens, focus and all); no parent, constraints, drivers,
    F-curve modifiers or NLA strips (a conservative reading: any of those may turn, lift,
    zoom or slide it)."""
    data = getattr(cam, "data", None)
    if cam.parent is not None or len(cam.constraints) or _driven(cam) or (data is not None and (
            _driven(data) or not all(_flat(c) for c in bag_curves(data)))):
        return False
    path = {}
    for curve in bag_curves(cam):
        if _flat(curve):
            continue
        if curve.data_path != "location" or curve.array_index > 1 or len(curve.modifiers):
            return False
        path[curve.array_index] = curve
    if not path:
        return False
    keys = np.unique(np.concatenate([_keys(c) for c in path.values()]))
    frames = np.concatenate([keys, (keys[0] - 1.0, keys[-1] + 1.0), *(
        keys[:-1] + f * np.diff(keys) for f in (0.25, 0.5, 0.75))])
    frames = frames[np.linspace(0, len(frames) - 1, min(len(frames), PATH_FRAMES)).astype(int)]
    xy = np.array([[path[i].evaluate(f) for f in frames] if i in path
                   else np.full(len(frames), cam.location[i]) for i in (0, 1)])
    m = np.array(cam.matrix_world, np.float64)[:3, :3]
    for axis in (-m[:, 2], m[:, 1]):  # the view's heading, else its screen's top (past_grid)
        axis = axis / max(float(np.linalg.norm(axis)), 1e-300)
        norm = float(np.hypot(axis[0], axis[1]))
        if norm > 1e-3:
            return bool(np.ptp(np.array([axis[1], -axis[0]]) @ xy / norm) <= STRAY)
    return False


def _keys(curve):
    """The frames of an F-curve's keys."""
    co = np.empty(2 * len(curve.keyframe_points))
    curve.keyframe_points.foreach_get("co", co)
    return co[0::2]


def _flat(curve):
    """Whether an F-curve holds one value: no modifiers, its keys and their handles level."""
    points = curve.keyframe_points
    values = np.empty((3, 2 * len(points)))
    for row, name in zip(values, ("co", "handle_left", "handle_right"), strict=True):
        points.foreach_get(name, row)
    return not len(curve.modifiers) and (not len(points) or np.ptp(values[:, 1::2]) == 0.0)


def _driven(id_block):
    """Whether `id_block` has drivers or NLA strips."""
    anim = getattr(id_block, "animation_data", None)
    return anim is not None and bool(len(anim.drivers) or any(
        len(track.strips) for track in anim.nla_tracks))


def scene_time(scene):
    """Seconds at the current (sub)frame: Blender's scene time, time stretching included (the
    frame times frame_map_old / frame_map_new: the `frame` drivers see), at the frame rate."""
    r = scene.render
    frame = (scene.frame_current + scene.frame_subframe) * r.frame_map_old / r.frame_map_new
    return frame * seconds_per_frame(scene)


def seconds_per_frame(scene):
    """Seconds per unit of scene time (the drivers' `frame`)."""
    return scene.render.fps_base / scene.render.fps


def ocean_axes(world):
    """The inverse of an ocean's linear transform (ValueError saying what to change if none)."""
    linear = world[:3, :3]
    if not np.all(np.isfinite(world)):
        raise ValueError("the ocean object's transform is not finite: reset its location, "
                         "rotation and scale")
    lengths = np.sqrt((linear * linear).sum(axis=0))
    zero = [axis for axis, length in zip("XYZ", lengths, strict=True) if length == 0.0]
    # Independent axes: the volume they span is not negligible against their lengths.
    if zero or abs(np.linalg.det(linear)) <= 1e-12 * lengths.prod():
        axes = "/".join(zero) or "one axis"
        raise ValueError(f"the ocean object's scale is zero on {axes}: give it a non-zero scale "
                         "(the sea ignores its scale and rotation, but needs them invertible)")
    return np.linalg.inv(linear)
