"""The bake: an ocean's meshes for a range of frames written into a USD file, and the ocean
switched to play them with a Mesh Sequence Cache modifier, so the file renders those frames
where no script runs (a farm that blocks Python, the extension not installed).

First each frame is built as a render builds it (`Bake.step`, one frame at a time, so the
operator can run it from the interface and Esc cancel it between frames): the frame handler
builds the render grid for the scene camera (from the scene as the viewport evaluates it),
keeps the mesh's arrays in a folder beside the target (`keep`) and records what our material is
given (`progress`): the inputs that change are keyed afterwards, the slope layer's images saved
as numbered EXR files; the water body's material and its godrays' caustic tile alike. Then
Blender's own USD exporter steps through the frames as a render does, and the frame handler
writes it each kept mesh (`kept`): the exporter writes them with the attributes the material
reads (the projector UV map under its own name, foam, detail); not their normals, which Blender
computes alike from the positions (2.5 MB a frame at 257x513 instead of 8.5). The exporter
samples a mesh per frame only for objects that change with time, so the ocean carries a
modifier of ours whose output depends on the scene time (and moves nothing) while it writes.
Everything is written beside its target and renamed onto it only when whole, and the ocean is
switched only then: a failed or cancelled bake leaves it live.
"""

import os
import shutil
import tempfile
from dataclasses import dataclass, field

import bpy
import numpy as np

from ...shaders import water
from .. import effects
from . import mesh, scene, shot
from .companions import COMPANIONS
from .state import RUNTIME

MODIFIER = "Projected Grid Bake"
TIMER = "Projected Grid Bake Time"  # the node group that makes the exporter sample each frame
KEYED = "projgrid_bake_keys"  # on our material's node tree: the socket paths the bake keyed
SCRATCH = "Projected Grid Bake Scratch"
# What our companions are given each frame (companions.place_companions): keyed where it changes.
COMPANION_PROPS = (("object", "location"), ("object", "scale"), ("object", "hide_render"),
                   ("object", "hide_viewport"), ("data", "clip_start"), ("data", "clip_end"),
                   ("data", "parallax_distance"))
FOLLOW = {"hide_render": "projgrid_bake_hide_render",  # the recorded visibility (_key_companion)
          "hide_viewport": "projgrid_bake_hide_viewport"}


@dataclass
class Recording:
    """What a bake records of each frame as the exporter steps through them: our material's
    socket values (keyed afterwards where they change), the group's muted branches, and the
    slope layer's images (written as numbered EXR files into `slopes`, a folder renamed onto
    its target when the bake is whole); the same of the water body's material and its
    godrays' caustic tile."""

    first: int
    last: int
    ocean: str
    slopes: str
    animated: set  # socket paths the user or we already animate: not recorded
    values: dict = field(default_factory=dict)  # socket path -> {frame: value}
    muted: dict = field(default_factory=dict)  # node name -> {frame: muted}
    images: dict = field(default_factory=dict)  # band -> first frame's file name
    companions: dict = field(default_factory=dict)  # (name, data path) -> {frame: value}
    body_animated: set = field(default_factory=set)  # as `animated`, of the body's material
    body_values: dict = field(default_factory=dict)  # as `values`
    godrays: dict = field(default_factory=dict)  # frame -> shown (the branch not muted)
    tiles: dict = field(default_factory=dict)  # frame -> caustic tile file name
    drifts: dict = field(default_factory=dict)  # gust drift socket path -> {frame: expression}
    error: str | None = None  # what went wrong in the handler (Blender swallows it there)
    frames: str = ""  # a folder of each frame's mesh arrays (`keep`), read by the export
    replaying: bool = False  # the exporter runs: the frames are written from `frames`


def cache_modifier(obj):
    """Our Mesh Sequence Cache modifier on `obj`, or None: the ocean plays its bake."""
    mod = obj.modifiers.get(MODIFIER)
    return mod if mod is not None and mod.type == "MESH_SEQUENCE_CACHE" else None


def is_baked(obj):
    return cache_modifier(obj) is not None


def check(the_scene, view_layer, obj, filepath, frame_start, frame_end):
    """The bake's inputs, or ValueError naming the one that is wrong. Returns the absolute path
    of the file to write."""
    if obj is None or obj.type != "MESH" or not obj.projgrid.is_ocean:
        raise ValueError("object: select an ocean to bake")
    if not scene.writable(obj):
        raise ValueError(f"object: {obj.name!r} is linked or overridden from a library; bake "
                         "it in its own file")
    if not scene.owns(obj.data):
        raise ValueError(f"object: {obj.name!r} draws a mesh that is not ours; Add Ocean makes "
                         "a new ocean")
    if _is_copy(obj):
        raise ValueError(f"object: {obj.name!r} is a duplicate still sharing another ocean's "
                         "companions and material; Back to Live on it first")
    if any(app.needs_stand_in for app in scene.appearances(the_scene, only=obj)):
        raise ValueError(f"object: {obj.name!r} shows more than once or inside a collection "
                         "instance; bake it where it shows once")
    if not obj.visible_get(view_layer=view_layer):
        raise ValueError(f"object: {obj.name!r} is hidden; show it to bake it")
    if frame_start > frame_end:
        raise ValueError(f"frame_start: {frame_start} is after frame_end {frame_end}")
    if frame_start < the_scene.frame_start or frame_end > the_scene.frame_end:
        raise ValueError(f"frame_start, frame_end: {frame_start}-{frame_end} is outside the "
                         f"scene's frames {the_scene.frame_start}-{the_scene.frame_end}")
    cameras = {shot.scene_camera(the_scene, frame=f) for f in range(frame_start, frame_end + 1)}
    if None in cameras:
        raise ValueError("camera: the scene has no camera to bake the ocean for")
    if len(cameras) > 1:
        raise ValueError(f"frame_end: timeline markers switch between cameras "
                         f"{sorted(c.name for c in cameras)} within frames "
                         f"{frame_start}-{frame_end}; bake each camera's frames apart")
    if filepath.startswith("//") and not bpy.data.filepath:
        raise ValueError(f"filepath: {filepath!r} is relative to the .blend, which is not saved "
                         "yet; save it first or give a full path")
    path = bpy.path.abspath(filepath)
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


def bake(context, obj, filepath, frame_start, frame_end):
    """Write frames frame_start..frame_end of ocean `obj` into `filepath` and switch it to play
    them, at once (`Bake` step by step); returns (the file's absolute path, a warning or
    None). Raises ValueError (bad input) or RuntimeError (the export failed); in both cases the
    ocean is live (an earlier bake of it undone) and the scene as it was."""
    job = Bake(context, obj, filepath, frame_start, frame_end)
    while job.step():
        pass
    return job.finish()


class Bake:
    """A bake in steps, so that the operator runs it frame by frame in the interface and Esc
    cancels it between frames. `step` builds one frame's render grid for the scene camera (the
    frame handler records what our material is given, `progress`, and keeps the mesh's arrays
    in a folder beside the target, `keep`); `finish` has Blender's USD exporter write the kept
    meshes (it blocks the interface, but builds nothing) and switches the ocean to play the
    file; `cancel` leaves the ocean live and nothing on disk. Any failure does as `cancel`
    and raises."""

    def __init__(self, context, obj, filepath, frame_start, frame_end):
        self.context, self.obj = context, obj
        self.scene, self.view_layer = context.scene, context.view_layer
        self.path = check(self.scene, self.view_layer, obj, filepath, frame_start, frame_end)
        self.relative = filepath.startswith("//")
        free(obj)  # a bake again: the frames are built from the live sea
        self.frame = self.scene.frame_current
        mat, body = water.material_of(obj.data), _body_material(obj)
        folder = folder_of(self.path)
        self.recording = Recording(
            frame_start, frame_end, obj.name, tempfile.mkdtemp(dir=folder),
            _animated(mat.node_tree) if mat is not None else set(),
            body_animated=_animated(body.node_tree) if body is not None else set())
        self.next = frame_start
        RUNTIME.baking = self.recording
        try:
            self.recording.frames = tempfile.mkdtemp(dir=folder, prefix=".projgrid-frames-")
            effects.finish_ahead()
            context.window_manager.progress_begin(frame_start, frame_end)
        except BaseException:
            self._close()
            raise

    @property
    def done(self):
        """The share of the frames built."""
        first, last = self.recording.first, self.recording.last
        return (self.next - first) / (last - first + 1)

    def step(self):
        """Build the next frame; returns whether frames are left to build."""
        try:
            RUNTIME.state(self.obj).key = None  # built even if nothing changed since
            self.scene.frame_set(self.next)
            if self.recording.error:
                raise RuntimeError(self.recording.error)
            if not os.path.exists(_kept_path(self.recording, self.next)):
                why = RUNTIME.state(self.obj).message or "the ocean was not rebuilt"
                raise RuntimeError(f"frame {self.next} was not built: {why}")
        except BaseException:
            self._close()
            raise
        self.next += 1
        return self.next <= self.recording.last

    def cancel(self):
        """Stop: the ocean live, the scene at its frame, nothing of the bake on disk."""
        self._close()

    def finish(self):
        """Export the frames built and play them: (the file's path, a warning or None)."""
        recording, the_scene, obj = self.recording, self.scene, self.obj
        stem, ext = os.path.splitext(self.path)
        partial, slopes = f"{stem}.partial{ext}", f"{stem}_slopes"
        frame_range = (the_scene.frame_start, the_scene.frame_end)
        view_layer = self.view_layer
        selected = [o for o in view_layer.objects if o.select_get()]
        active = view_layer.objects.active
        timer = None
        recording.replaying = True
        try:
            timer = obj.modifiers.new(TIMER, "NODES")
            timer.node_group = _time_group()
            the_scene.frame_start, the_scene.frame_end = recording.first, recording.last
            for o in selected:
                o.select_set(False)
            obj.select_set(True)
            view_layer.objects.active = obj
            with self.context.temp_override(selected_objects=[obj], active_object=obj):
                done = bpy.ops.wm.usd_export(
                    filepath=partial, check_existing=False, selected_objects_only=True,
                    export_animation=True, evaluation_mode="RENDER", export_materials=False,
                    rename_uvmaps=False, export_normals=False, export_custom_properties=False,
                    export_lights=False, export_cameras=False, allow_unicode=False)
            if recording.error:
                raise RuntimeError(recording.error)
            if "FINISHED" not in done or not os.path.exists(partial):
                raise RuntimeError("the USD export did not finish")
            os.replace(partial, self.path)
            if recording.images or recording.tiles:
                if os.path.isdir(slopes):
                    shutil.rmtree(slopes)
                os.replace(recording.slopes, slopes)
                recording.slopes = slopes
        except OSError as err:
            raise RuntimeError(f"writing {self.path!r} failed: {err.strerror}") from None
        finally:
            if timer is not None:
                obj.modifiers.remove(timer)
            the_scene.frame_start, the_scene.frame_end = frame_range
            for o in view_layer.objects:
                o.select_set(o in selected)
            view_layer.objects.active = active
            self._close(slopes)
        try:
            return self.path, _play(obj, self.path, self.relative, recording)
        except Exception as err:
            free(obj)
            raise RuntimeError(f"playing {self.path!r} failed: {err}") from err

    def _close(self, kept=None):
        """The bake's state undone and its scratch removed (the folder `kept` stays), the
        scene back at its frame."""
        recording, path = self.recording, self.path
        if RUNTIME.baking is not recording:
            return
        RUNTIME.baking = None
        self.context.window_manager.progress_end()
        if recording.slopes != kept:  # the frames' images of a bake not made
            shutil.rmtree(recording.slopes, ignore_errors=True)
        if recording.frames:
            shutil.rmtree(recording.frames, ignore_errors=True)
        leftover = os.path.basename(os.path.splitext(path)[0]) + ".partial."  # ours and USD's
        try:
            names = os.listdir(folder_of(path))
        except OSError:
            names = []  # the folder is gone: nothing of ours is left in it
        for name in names:
            full = os.path.join(folder_of(path), name)
            if name.startswith(leftover) and os.path.isfile(full):
                try:
                    os.remove(full)
                except OSError:
                    pass  # the error being raised says more
        for block in (bpy.data.node_groups.get(TIMER), bpy.data.images.get(SCRATCH)):
            if block is not None and block.get(scene.TAG) and block.users == 0:
                bpy.data.batch_remove([block])
        RUNTIME.state(self.obj).key = None
        self.scene.frame_set(self.frame)


def baking(app):
    """The Recording of the bake being made of appearance `app`'s ocean, or None."""
    recording = RUNTIME.baking
    if recording is None or app.needs_stand_in or app.ocean.name != recording.ocean:
        return None
    return recording


def keep(frame, arrays):
    """Keep frame `frame`'s mesh arrays (mesh.grid_arrays; None: empty) for the export."""
    recording = RUNTIME.baking
    if recording.replaying or not recording.first <= frame <= recording.last:
        return
    try:
        np.savez(_kept_path(recording, frame), **(arrays or {}))
    except OSError as err:
        recording.error = f"keeping frame {frame} failed: {err.strerror}"


def kept(frame):
    """The mesh arrays `keep` kept of `frame` ({}: an empty mesh), or None for a frame outside
    the bake's; a frame of it not kept or not read is the bake's error."""
    recording = RUNTIME.baking
    if not recording.first <= frame <= recording.last:
        return None
    try:
        with np.load(_kept_path(recording, frame)) as data:
            return {name: data[name] for name in data.files}
    except (OSError, ValueError) as err:
        recording.error = f"reading frame {frame} back failed: {err}"
        return None


def _kept_path(recording, frame):
    return os.path.join(recording.frames, f"{frame}.npz")


def folder_of(path):
    return os.path.dirname(path) or "."


def progress(frame):
    """A frame of the bake being written (the frame handler calls it, after the frame's
    update): recorded, and shown on the command line and the window's progress indicator."""
    recording = RUNTIME.baking
    if not recording.first <= frame <= recording.last or recording.error:
        return
    what = "writing" if recording.replaying else "baking"
    print(f"Projected Grid Ocean: {what} frame {frame} ({frame - recording.first + 1} of "
          f"{recording.last - recording.first + 1})", flush=True)
    bpy.context.window_manager.progress_update(frame)
    if recording.replaying:
        return
    try:
        _record(recording, frame)
    except (OSError, RuntimeError, ValueError) as err:  # raised again after the export
        recording.error = f"recording frame {frame} failed: {err}"


def _record(recording, frame):
    obj = bpy.data.objects.get(recording.ocean)
    mat = water.material_of(obj.data) if obj is not None else None
    if mat is None:
        return
    _record_sockets(mat.node_tree, recording.animated, recording.values, frame)
    for path, curve in _drift_drivers(mat.node_tree).items():
        recording.drifts.setdefault(path, {})[frame] = curve.driver.expression
    group = water.group_tree(mat)
    for node in group.nodes if group is not None else ():
        recording.muted.setdefault(node.name, {})[frame] = node.mute
    recording.companions.setdefault(("", "hide_probe_sphere"), {})[frame] = obj.hide_probe_sphere
    for companion in _companions(obj):
        for owner, prop in COMPANION_PROPS:
            target = companion.data if owner == "data" else companion
            if hasattr(target, prop):
                value = getattr(target, prop)
                key = (companion.name, f"{owner}.{prop}")
                recording.companions.setdefault(key, {})[frame] = (
                    tuple(value) if hasattr(value, "__len__") else value)
    for b, image in water.layer_taps(mat):
        if image is None:
            continue
        name = os.path.join(recording.slopes, f"band{b}_{frame:04d}.exr")
        _save(image, name)
        recording.images.setdefault(b, os.path.basename(name))
    body = _body_material(obj)
    if body is not None:
        _record_sockets(body.node_tree, recording.body_animated, recording.body_values, frame)
        tile = water.caustic_tap(body)
        state = RUNTIME.peek(obj)
        recording.godrays[frame] = bool(state is not None and state.effects
                                        and state.effects.get("godrays", (False,))[0])
        if recording.godrays[frame] and tile is not None and tile.image is not None:
            name = f"godrays_{frame:04d}.exr"
            _save(tile.image, os.path.join(recording.slopes, name))
            recording.tiles[frame] = name


def _record_sockets(tree, animated, values, frame):
    """The unlinked inputs' values of `tree`'s nodes at `frame` into `values` (socket path ->
    {frame: value}), but for the paths in `animated`."""
    for node in tree.nodes:
        for socket in node.inputs:
            value = getattr(socket, "default_value", None) if not socket.is_linked else None
            if isinstance(value, float) or (hasattr(value, "__len__") and len(value) <= 4
                                            and not isinstance(value, str)):
                path = socket.path_from_id("default_value")
                if path not in animated:
                    values.setdefault(path, {})[frame] = (
                        (value,) if isinstance(value, float) else tuple(value))


def _body_material(obj):
    """Our water body's material of ocean `obj` (None without one of ours)."""
    body = obj.projgrid.water_body
    if body is None or body not in _companions(obj) or not len(body.data.materials):
        return None
    mat = body.data.materials[0]
    return mat if mat is not None and mat.get(scene.TAG) and mat.library is None else None


def _save(image, path):
    """`image`'s pixels as an EXR file at `path` (through our scratch image)."""
    scratch = _scratch(image.size)
    pixels = np.empty(len(image.pixels), np.float32)
    image.pixels.foreach_get(pixels)
    scratch.pixels.foreach_set(pixels)
    scratch.filepath_raw = path
    scratch.save()


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


def _play(obj, path, relative, recording):
    """Switch `obj` to play the bake at `path`: its mesh's prim under the exporter's root, last
    of its modifiers (what the exporter wrote is the ocean after the user's modifiers), its
    material's changing inputs keyed, the branches any frame needs switched on, and its slope
    layer read from the image sequences. Returns a warning or None."""
    before = set(bpy.data.cache_files)
    bpy.ops.cachefile.open(filepath=path)
    cache = next(c for c in bpy.data.cache_files if c not in before)
    cache[scene.TAG] = True
    if relative:
        cache.filepath = bpy.path.relpath(path)
    mod = obj.modifiers.new(MODIFIER, "MESH_SEQUENCE_CACHE")
    mod.cache_file = cache
    mod.read_data = {"VERT", "POLY", "UV", "COLOR", "ATTRIBUTES"}
    obj.projgrid.bake_camera = shot.scene_camera(bpy.context.scene,
                                                 frame=recording.first).name
    obj.projgrid.bake_frames = (recording.first, recording.last)
    RUNTIME.state(obj).key = None
    mesh.empty(obj.data)  # the cache gives the mesh: what is left is empty if it gives none
    chain = [obj.data.name, obj.name]
    parent = obj.parent
    while parent is not None:
        chain.append(parent.name)
        parent = parent.parent
    # The exporter's prim names: USD's valid identifiers, made per character or (older USD)
    # per byte of a name's UTF-8. (Looked up among the file's paths, not by the mesh the
    # current frame plays, which may rightly be empty: a camera looking at the sky.)
    obj.evaluated_get(bpy.context.evaluated_depsgraph_get())  # the cache read: its paths
    held = {p.path for p in cache.object_paths}
    for per_byte in (False, True):
        mod.object_path = "/root/" + "/".join(_prim(n, per_byte) for n in reversed(chain))
        if mod.object_path in held:
            break
    else:
        raise RuntimeError(f"the cache holds no mesh at {mod.object_path}")
    probe = set(recording.companions.get(("", "hide_probe_sphere"), {}).values())
    if probe:  # out of our probe's capture on every frame if on any (the ocean is the user's
        obj.hide_probe_sphere = True in probe  # object: not keyed; its switch warns below)
    for companion in _companions(obj):
        _key_companion(companion, obj, recording.companions)
        old = companion.modifiers.get(MODIFIER)
        if old is not None:
            companion.modifiers.remove(old)
        if companion.data == obj.data:  # the shadow caster draws the ocean's mesh: the cache
            caster = companion.modifiers.new(MODIFIER, "MESH_SEQUENCE_CACHE")
            caster.cache_file, caster.object_path = cache, mod.object_path
            caster.read_data = mod.read_data

    def file(name):  # a file the bake wrote, as the .blend refers to it
        path = os.path.join(recording.slopes, name)
        return bpy.path.relpath(path) if relative else path

    mat = water.material_of(obj.data)
    switched = False
    if mat is not None:
        _key(mat.node_tree, {**recording.values, **_drifts_keyed(mat.node_tree, recording)})
        water.play_layer_sequences(mat, {b: file(n) for b, n in recording.images.items()},
                                   recording.first, recording.last)
        for name, frames in recording.muted.items():
            if len(set(frames.values())) > 1:
                water.group_tree(mat).nodes[name].mute = False
                switched = True
    body = _body_material(obj)
    if body is not None:
        _key(body.node_tree, recording.body_values)
        if recording.tiles:
            _fill_frames(recording)
            body.node_tree.nodes["Godrays"].mute = False
            water.play_caustic_sequence(body, file(recording.tiles[recording.first]),
                                        recording.first, recording.last,
                                        effects.GODRAY_TILE_TEXELS)
            switched = switched or len(set(recording.godrays.values())) > 1
    if switched:
        return ("effects switch on and off within the frames: the bake draws them on "
                "throughout (bake the frames apart to keep the switch)")
    return None


def _fill_frames(recording):
    """A caustic tile file for every frame: a frame drawn without godrays gets its nearest
    frame's (the bake draws them throughout)."""
    drawn = sorted(recording.tiles)
    for frame in range(recording.first, recording.last + 1):
        if frame not in recording.tiles:
            near = min(drawn, key=lambda f, frame=frame: abs(f - frame))
            name = f"godrays_{frame:04d}.exr"
            shutil.copyfile(os.path.join(recording.slopes, recording.tiles[near]),
                            os.path.join(recording.slopes, name))
            recording.tiles[frame] = name


def _prim(name, per_byte):
    """A Blender name as the USD exporter makes a prim name of it without unicode: each
    character (or each byte of it) that is not an ASCII letter, digit or underscore becomes an
    underscore, and a leading digit gets one before it."""
    parts = name.encode() if per_byte else name
    out = "".join(c if c.isascii() and (c.isalnum() or c == "_") else "_"
                  for c in (map(chr, parts) if per_byte else parts))
    return out if out and not out[0].isdigit() else "_" + out


def _is_copy(obj):
    """Whether `obj` is a duplicate whose companions and material are still another ocean's
    (the shadow caster, parented to its ocean, tells)."""
    caster = obj.projgrid.shadow_caster
    return caster is not None and caster.parent not in (None, obj)


def _companions(obj):
    """Our companions of ocean `obj` (companions.py); none for a duplicate (`_is_copy`)."""
    if _is_copy(obj):
        return []
    out = [getattr(obj.projgrid, prop) for prop in COMPANIONS]
    return [c for c in out if c is not None and scene.owns(c) and scene.local(c)]


def _key_companion(companion, ocean, recorded):
    """Keyframes (constant) on our companion for what it was given differently across frames;
    the animation data a bake gives a companion is all it has (free clears it). Its visibility
    is recorded in a property of ours (`FOLLOW`) and a driver hides it where that or the ocean
    says so (a driver of type MAX needs no script), so it is hidden with an ocean whose render
    or viewport switch is turned off after the bake (not the view layer's eye, which no driver
    reads)."""
    for (name, path), frames in recorded.items():
        if name != companion.name:
            continue
        owner, prop = path.split(".")
        target = companion.data if owner == "data" else companion
        if prop in FOLLOW:  # recorded in our property, which the driver reads
            _follow(target, ocean, prop)
            prop = f'["{FOLLOW[prop]}"]'
            frames = {f: int(v) for f, v in frames.items()}
        if _key_frames(target, prop, frames):
            _hold(bag_curves(target))


def _key_frames(target, prop, frames, value=lambda v: v):
    """`prop` of `target` set to its recorded `value` where the frames ({frame: recorded})
    agree (the scene's live viewport frame may have written its own since), else keyed on
    each frame: returns whether it was keyed."""
    if len(set(frames.values())) < 2:
        _set(target, prop, value(next(iter(frames.values()))))
        return False
    for frame, recorded in sorted(frames.items()):
        _set(target, prop, value(recorded))
        target.keyframe_insert(prop, frame=frame)
    return True


def _hold(curves):
    """Keyframes held constant until the next: a baked frame plays what it recorded."""
    for curve in curves:
        for point in curve.keyframe_points:
            point.interpolation = "CONSTANT"


def _set(target, path, value):
    """Set a property or (path '["name"]') a custom property of `target`."""
    if path.startswith('["'):
        target[path[2:-2]] = value
    else:
        setattr(target, path, value)


def _follow(companion, ocean, prop):
    """A driver: the companion's `prop` (hide_render or hide_viewport) is on where the bake
    recorded it on or the ocean's own is."""
    driver = companion.driver_add(prop).driver
    driver.type = "MAX"
    for name, (owner, path) in {"ocean": (ocean, prop),
                                "baked": (companion, f'["{FOLLOW[prop]}"]')}.items():
        var = driver.variables.new()
        var.name, var.type = name, "SINGLE_PROP"
        var.targets[0].id_type = "OBJECT"
        var.targets[0].id, var.targets[0].data_path = owner, path


def _drift_drivers(tree):
    """The drivers of the gusts' drift (water.GUST_DRIFT) in our material's tree, by path."""
    node = tree.nodes.get(water.GROUP)
    data = tree.animation_data
    if node is None or data is None:
        return {}
    paths = [node.inputs[n].path_from_id("default_value") for n in water.GUST_DRIFT
             if n in node.inputs]
    return {p: c for p in paths if (c := data.drivers.find(p)) is not None}


def _drifts_keyed(tree, recording):
    """The drift's values per frame, in place of its drivers, where the driver changed over
    the bake (a keyframed wind: each frame's reads the wind's run at that frame only, and a
    baked sea has no frame handler to write the next), as `values` for `_key`."""
    keyed = {}
    for path, curve in _drift_drivers(tree).items():
        frames = recording.drifts.get(path, {})
        if len(set(frames.values())) > 1:
            tree.animation_data.drivers.remove(curve)
            keyed[path] = {f: (water.driven_value(e, f),) for f, e in frames.items()}
    return keyed


def _animated(tree):
    """The data paths of `tree` that drivers or keyframes animate already."""
    data = tree.animation_data
    if data is None:
        return set()
    return {d.data_path for d in data.drivers} | {c.data_path for c in bag_curves(tree)}


def _key(tree, values):
    """Keyframes (constant between frames) for the sockets whose recorded value changes; the
    others set to it (`_key_frames`)."""
    keyed = [path for path, frames in values.items()
             if _key_frames(tree.path_resolve(path.rsplit(".", 1)[0]), "default_value", frames,
                            lambda v: v[0] if len(v) == 1 else v)]
    _hold(c for c in bag_curves(tree) if c.data_path in keyed)
    tree[KEYED] = keyed


def bag_curves(tree):
    """The F-curves of `tree`'s (an ID's) action for it (none without one)."""
    bag = _channelbag(tree)
    return list(bag.fcurves) if bag is not None else []


def _channelbag(tree):
    data = tree.animation_data
    if data is None or data.action is None:
        return None
    from bpy_extras import anim_utils

    return anim_utils.action_get_channelbag_for_slot(data.action, data.action_slot)


def _unkey(tree):
    """The keyframes `_key` made, removed (and the action, if they were all it held)."""
    keyed = set(tree.get(KEYED, []))
    bag = _channelbag(tree)
    if bag is not None:
        for curve in [c for c in bag.fcurves if c.data_path in keyed]:
            bag.fcurves.remove(curve)
        action = tree.animation_data.action
        if keyed and not len(bag.fcurves) and action.users == 1:
            tree.animation_data.action = None
            bpy.data.actions.remove(action)
    tree.pop(KEYED, None)


def drop_bake(mat):
    """A copy of a baked ocean's material, made for a live ocean: the bake's keys removed (from
    an action of its own, the original's keeps them) and the slope layer live again."""
    tree = mat.node_tree
    if tree is None or KEYED not in tree:
        return
    data = tree.animation_data
    if data is not None and data.action is not None and data.action.users > 1:
        data.action = data.action.copy()
    _unkey(tree)
    water.play_layer_sequences(mat, {}, 0, 0)


def free(obj):
    """Back to live: our cache modifier, keyframes, layer sequences and cache file removed (the
    files stay on disk). Returns whether there was a bake."""
    mod = cache_modifier(obj)
    cache = mod.cache_file if mod is not None else None
    if mod is not None:
        obj.modifiers.remove(mod)
    for companion in _companions(obj):
        own = companion.modifiers.get(MODIFIER)
        if own is not None:
            companion.modifiers.remove(own)
        for target in (companion, companion.data):
            if target is None or target == obj.data:
                continue
            for key in FOLLOW.values():
                target.pop(key, None)
            if target.animation_data is None:
                continue
            action = target.animation_data.action if bag_curves(target) else None
            if action is not None or len(target.animation_data.drivers):
                target.animation_data_clear()
            if action is not None and action.users == 0:
                bpy.data.actions.remove(action)
    mat = water.material_of(obj.data) if not _is_copy(obj) else None  # the original's
    if mat is not None:
        _unkey(mat.node_tree)
        water.play_layer_sequences(mat, {}, 0, 0)
    body = _body_material(obj)
    if body is not None:
        _unkey(body.node_tree)
        water.play_caustic_sequence(body, None, 0, 0, effects.GODRAY_TILE_TEXELS)
    if cache is not None and cache.get(scene.TAG) and not any(
            getattr(m, "cache_file", None) == cache for o in bpy.data.objects
            for m in o.modifiers):
        bpy.data.batch_remove([cache])
    obj.projgrid.bake_camera = ""
    obj.projgrid.bake_frames = (0, 0)
    RUNTIME.state(obj).key = None
    return mod is not None


def stale(the_scene, obj):
    """Why the bake of `obj` no longer matches the scene (a line for the panel), or None."""
    mod = cache_modifier(obj)
    if mod is None:
        return None
    start, end = obj.projgrid.bake_frames
    camera = shot.scene_camera(the_scene, frame=start)
    camera = camera.name if camera is not None else ""
    if camera != obj.projgrid.bake_camera:
        return f"baked for camera {obj.projgrid.bake_camera!r}, the scene's is {camera!r}"
    if mod.cache_file is None or not os.path.exists(bpy.path.abspath(mod.cache_file.filepath)):
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
