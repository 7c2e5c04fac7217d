"""The bake: an ocean's meshes for a range of frames written into a USD file, and the ocean
switched to play them with a Mesh Sequence Cache modifier, so the file renders those frames
where no script runs (a farm that blocks Python, the extension not installed).

Blender's own USD exporter writes the meshes: it steps through the frames as a render does,
so our frame handler builds each frame's render grid for the scene camera, and the exporter
writes it with the attributes the material reads (the projector UV map under its own name,
foam, detail); not its normals, which Blender computes alike from the positions (2.5 MB a frame
at 257x513 instead of 8.5). The exporter samples a mesh per frame only for objects that change
with time, so the ocean carries a modifier of ours whose output depends on the scene time (and
moves nothing) while it writes. The file is written beside the target and renamed onto it only
when whole, and the ocean is switched only then: a failed bake leaves it live.
"""

import os
import tempfile
from dataclasses import dataclass, field

import bpy
import numpy as np

from ...shaders import water
from . import scene
from .state import RUNTIME

MODIFIER = "Projected Grid Bake"
TIMER = "Projected Grid Bake Time"  # the node group that makes the exporter sample each frame
KEYED = "projgrid_bake_keys"  # on our material's node tree: the socket paths the bake keyed
SCRATCH = "Projected Grid Bake Scratch"


@dataclass
class Recording:
    """What a bake records of each frame as the exporter steps through them: the material's
    socket values (keyed afterwards where they change) and the slope layer's images (written
    as numbered EXR files beside the cache)."""

    first: int
    last: int
    ocean: str
    slopes: str  # the folder of the layer's image sequences
    values: dict = field(default_factory=dict)  # socket path -> {frame: value}
    images: dict = field(default_factory=dict)  # band -> first frame's file
    written: set = field(default_factory=set)  # every file written, removed if the bake fails


def cache_modifier(obj):
    """Our Mesh Sequence Cache modifier on `obj`, or None: the ocean plays its bake."""
    mod = obj.modifiers.get(MODIFIER)
    return mod if mod is not None and mod.type == "MESH_SEQUENCE_CACHE" else None


def is_baked(obj):
    return cache_modifier(obj) is not None


def check(the_scene, obj, filepath, frame_start, frame_end):
    """The bake's inputs, or ValueError naming the one that is wrong. Returns the absolute path
    of the file to write."""
    if obj is None or obj.type != "MESH" or not obj.projgrid.is_ocean:
        raise ValueError("object: select an ocean to bake")
    if not scene.writable(obj):
        raise ValueError(f"object: {obj.name!r} is linked or overridden from a library; bake "
                         "it in its own file")
    if the_scene.camera is None:
        raise ValueError("camera: the scene has no camera to bake the ocean for")
    if frame_start > frame_end:
        raise ValueError(f"frame_start: {frame_start} is after frame_end {frame_end}")
    if frame_start < the_scene.frame_start or frame_end > the_scene.frame_end:
        raise ValueError(f"frame_start, frame_end: {frame_start}-{frame_end} is outside the "
                         f"scene's frames {the_scene.frame_start}-{the_scene.frame_end}")
    cameras = {shot_camera(the_scene, frame_start).name} | {
        m.camera.name for m in the_scene.timeline_markers
        if m.camera is not None and frame_start < m.frame <= frame_end}
    if len(cameras) > 1:
        raise ValueError(f"frame_end: timeline markers switch between cameras {sorted(cameras)} "
                         f"within frames {frame_start}-{frame_end}; bake each camera's frames "
                         "apart")
    path = bpy.path.abspath(filepath) if filepath else ""
    if not path.lower().endswith((".usd", ".usdc", ".usda")):
        raise ValueError(f"filepath: {filepath!r} is not a USD file (.usdc, .usd or .usda)")
    folder = os.path.dirname(path) or "."
    try:
        os.makedirs(folder, exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=folder):
            pass
    except OSError as err:
        raise ValueError(f"filepath: cannot write in {folder!r} ({err.strerror})") from None
    return path


def shot_camera(the_scene, frame):
    """The camera at `frame` as Blender switches cameras: that of the last timeline marker
    binding one at or before it, else of the first marker binding one, else the scene's."""
    bound = [m for m in the_scene.timeline_markers if m.camera is not None]
    before = [m for m in bound if m.frame <= frame]
    if before:
        return max(before, key=lambda m: m.frame).camera
    return min(bound, key=lambda m: m.frame).camera if bound else the_scene.camera


def bake(context, obj, filepath, frame_start, frame_end):
    """Write frames frame_start..frame_end of ocean `obj` into `filepath` and switch it to play
    them. Raises ValueError (bad input) or RuntimeError (the export failed); in both cases the
    ocean stays live and the scene as it was."""
    the_scene = context.scene
    path = check(the_scene, obj, filepath, frame_start, frame_end)
    stem, ext = os.path.splitext(path)
    partial = f"{stem}.partial{ext}"
    kept = (the_scene.frame_start, the_scene.frame_end, the_scene.frame_current,
            [o for o in context.view_layer.objects if o.select_get()],
            context.view_layer.objects.active)
    timer = obj.modifiers.new(TIMER, "NODES")
    timer.node_group = _time_group()
    wm = context.window_manager
    recording = RUNTIME.baking = Recording(frame_start, frame_end, obj.name,
                                           f"{os.path.splitext(path)[0]}_slopes")
    wm.progress_begin(frame_start, frame_end)
    whole = False
    try:
        the_scene.frame_start, the_scene.frame_end = frame_start, frame_end
        for o in kept[3]:
            o.select_set(False)
        obj.select_set(True)
        context.view_layer.objects.active = obj
        with context.temp_override(selected_objects=[obj], active_object=obj):
            done = bpy.ops.wm.usd_export(
                filepath=partial, check_existing=False, selected_objects_only=True,
                export_animation=True, evaluation_mode="RENDER", export_materials=False,
                rename_uvmaps=False, export_normals=False, export_custom_properties=False,
                export_lights=False, export_cameras=False)
        if "FINISHED" not in done or not os.path.exists(partial):
            raise RuntimeError("the USD export did not finish")
        os.replace(partial, path)
        whole = True
    except OSError as err:
        raise RuntimeError(f"writing {path!r} failed: {err.strerror}") from None
    finally:
        RUNTIME.baking = None
        wm.progress_end()
        for name in [partial] + ([] if whole else sorted(recording.written)):
            if os.path.exists(name):
                os.remove(name)
        if not whole and os.path.isdir(recording.slopes) and not os.listdir(recording.slopes):
            os.rmdir(recording.slopes)
        obj.modifiers.remove(timer)
        the_scene.frame_start, the_scene.frame_end = kept[0], kept[1]
        for o in context.view_layer.objects:
            o.select_set(o in kept[3])
        context.view_layer.objects.active = kept[4]
        the_scene.frame_set(kept[2])
    _play(obj, path, shot_camera(the_scene, frame_start).name, frame_start, frame_end,
          recording)
    return path


def progress(frame):
    """A frame of the bake being written (the frame handler calls it, after the frame's
    update): recorded, and shown on the command line and the window's progress indicator."""
    recording = RUNTIME.baking
    if not recording.first <= frame <= recording.last:
        return
    print(f"Projected Grid Ocean: baking frame {frame} ({frame - recording.first + 1} of "
          f"{recording.last - recording.first + 1})", flush=True)
    bpy.context.window_manager.progress_update(frame)
    obj = bpy.data.objects.get(recording.ocean)
    mat = water.material_of(obj.data) if obj is not None else None
    if mat is None:
        return
    for node in mat.node_tree.nodes:
        for socket in node.inputs:
            value = getattr(socket, "default_value", None) if not socket.is_linked else None
            if isinstance(value, (float, int)) or (hasattr(value, "__len__") and len(value) <= 4
                                                   and not isinstance(value, str)):
                path = socket.path_from_id("default_value")
                recording.values.setdefault(path, {})[frame] = (
                    (float(value),) if isinstance(value, (float, int)) else tuple(value))
    for b, image in water.layer_taps(mat):
        if image is None:
            continue
        os.makedirs(recording.slopes, exist_ok=True)
        name = os.path.join(recording.slopes, f"band{b}_{frame:04d}.exr")
        scratch = _scratch(image.size)
        pixels = np.empty(len(image.pixels), np.float32)
        image.pixels.foreach_get(pixels)
        scratch.pixels.foreach_set(pixels)
        scratch.filepath_raw = name
        scratch.save()
        recording.written.add(name)
        recording.images.setdefault(b, name)


def _scratch(size):
    """Our float image the layer's tiles are saved through (saving changes an image's source,
    so not the layer's own)."""
    image = bpy.data.images.get(SCRATCH)
    if image is None or tuple(image.size) != tuple(size):
        if image is not None:
            bpy.data.batch_remove([image])
        image = bpy.data.images.new(SCRATCH, *size, float_buffer=True, is_data=True)
        image[scene.TAG] = True
    image.file_format = "OPEN_EXR"
    return image


def _play(obj, path, camera, frame_start, frame_end, recording):
    """Switch `obj` to play the bake at `path` (its mesh's prim under the exporter's root), its
    material's changing inputs keyed and its slope layer read from the image sequences."""
    free(obj)
    before = set(bpy.data.cache_files)
    bpy.ops.cachefile.open(filepath=path)
    cache = next(c for c in bpy.data.cache_files if c not in before)
    cache[scene.TAG] = True
    cache.filepath = _relative(path)
    mod = obj.modifiers.new(MODIFIER, "MESH_SEQUENCE_CACHE")
    mod.cache_file = cache
    mod.object_path = f"/root/{_prim(obj.name)}/{_prim(obj.data.name)}"
    mod.read_data = {"VERT", "POLY", "UV", "COLOR", "ATTRIBUTES"}
    if obj.modifiers.find(MODIFIER) > 0:  # first: the user's modifiers act on the sea
        with bpy.context.temp_override(object=obj, active_object=obj):
            bpy.ops.object.modifier_move_to_index(modifier=MODIFIER, index=0)
    obj.projgrid.bake_camera = camera
    obj.projgrid.bake_frames = (frame_start, frame_end)
    mat = water.material_of(obj.data)
    if mat is not None:
        _key(mat.node_tree, recording.values)
        water.play_layer_sequences(mat, {b: _relative(f) for b, f in recording.images.items()},
                                   frame_start, frame_end)
    scratch = bpy.data.images.get(SCRATCH)
    if scratch is not None:
        bpy.data.batch_remove([scratch])
    RUNTIME.state(obj).key = None


def _relative(path):
    """`path` relative to the saved .blend ("//"), so the file and its bake move together."""
    return bpy.path.relpath(path) if bpy.data.filepath else path


def _key(tree, values):
    """Keyframes (constant between frames) for the sockets whose recorded value changes."""
    keyed = []
    for path, frames in values.items():
        if len(set(frames.values())) < 2:
            continue
        socket = tree.path_resolve(path.rsplit(".", 1)[0])
        for frame, value in sorted(frames.items()):
            socket.default_value = value[0] if len(value) == 1 else value
            socket.keyframe_insert("default_value", frame=frame)
        keyed.append(path)
    for curve in _curves(tree, keyed):
        for point in curve.keyframe_points:
            point.interpolation = "CONSTANT"
    tree[KEYED] = keyed


def _unkey(tree):
    """The keyframes `_key` made, removed."""
    curves = _curves(tree, list(tree.get(KEYED, [])))
    if curves:
        from bpy_extras import anim_utils

        data = tree.animation_data
        bag = anim_utils.action_get_channelbag_for_slot(data.action, data.action_slot)
        for curve in curves:
            bag.fcurves.remove(curve)
    tree.pop(KEYED, None)


def _curves(tree, paths):
    """The F-curves of `tree` animating `paths`."""
    data = tree.animation_data
    if data is None or data.action is None or not paths:
        return []
    from bpy_extras import anim_utils

    bag = anim_utils.action_get_channelbag_for_slot(data.action, data.action_slot)
    return [c for c in (bag.fcurves if bag is not None else []) if c.data_path in paths]


def _prim(name):
    """A Blender name as the USD exporter makes a prim name of it."""
    out = "".join(c if c.isalnum() or c == "_" else "_" for c in name)
    return out if out and not out[0].isdigit() else "_" + out


def free(obj):
    """Back to live: our cache modifier and its cache file removed (the file stays on disk)."""
    mod = cache_modifier(obj)
    if mod is None:
        return False
    cache = mod.cache_file
    obj.modifiers.remove(mod)
    mat = water.material_of(obj.data)
    if mat is not None:
        _unkey(mat.node_tree)
        water.play_layer_sequences(mat, {}, 0, 0)
    if cache is not None and cache.get(scene.TAG) and not any(
            getattr(m, "cache_file", None) == cache for o in bpy.data.objects
            for m in o.modifiers):
        bpy.data.batch_remove([cache])
    obj.projgrid.bake_camera = ""
    RUNTIME.state(obj).key = None
    return True


def stale(the_scene, obj):
    """Why the bake of `obj` no longer matches the scene (a line for the panel), or None."""
    if not is_baked(obj):
        return None
    start, end = obj.projgrid.bake_frames
    camera = shot_camera(the_scene, start)
    camera = camera.name if camera is not None else ""
    if camera != obj.projgrid.bake_camera:
        return f"baked for camera {obj.projgrid.bake_camera!r}, the scene's is {camera!r}"
    if not os.path.exists(bpy.path.abspath(cache_modifier(obj).cache_file.filepath)):
        return "its cache file is missing"
    if the_scene.frame_start < start or the_scene.frame_end > end:
        return (f"baked frames {start}-{end}, the scene renders "
                f"{the_scene.frame_start}-{the_scene.frame_end}")
    return None


def _time_group():
    """A node group whose output depends on the scene time and equals its input."""
    group = bpy.data.node_groups.get(TIMER)
    if group is not None and group.get(scene.TAG):
        return group
    group = bpy.data.node_groups.new(TIMER, "GeometryNodeTree")
    group[scene.TAG] = True
    group.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
    group.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    nodes, links = group.nodes, group.links
    given, out = nodes.new("NodeGroupInput"), nodes.new("NodeGroupOutput")
    time = nodes.new("GeometryNodeInputSceneTime")
    move = nodes.new("GeometryNodeSetPosition")
    zero = nodes.new("ShaderNodeVectorMath")
    zero.operation = "SCALE"
    zero.inputs[0].default_value = (0.0, 0.0, 0.0)
    links.new(time.outputs["Seconds"], zero.inputs["Scale"])
    links.new(given.outputs[0], move.inputs["Geometry"])
    links.new(zero.outputs["Vector"], move.inputs["Offset"])
    links.new(move.outputs[0], out.inputs[0])
    return group
