"""Recording a bake: each frame's mesh arrays kept beside the target (`keep`, read back by
the export: `kept`), and what our materials and companions were given (`progress`): socket
values, muted branches, the slope layer's images and the godrays' tile as numbered EXR files."""

import os
from dataclasses import dataclass, field

import bpy
import numpy as np

from ...shaders import materials as shader_materials
from ...shaders import water
from . import material_inputs, scene
from .baked import baked_companions, body_material, drift_drivers, get_path
from .state import RUNTIME

SCRATCH = "Projected Grid Bake Scratch"
SPRAY_KEYS = ("spray_positions", "spray_radii", "spray_opacities", "spray_level")


# What our companions are given each frame (companions.place_companions, and the spray's air by
# companions.write_spray): keyed where it changes.
COMPANION_PROPS = (("object", "location"), ("object", "rotation_euler"), ("object", "scale"),
                   ("object", "hide_render"),
                   ("object", "hide_viewport"), ("data", "clip_start"), ("data", "clip_end"),
                   ("data", "parallax_distance"),
                   *(("object", f'["{name}"]') for name in water.SPRAY_AIR))


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
    fingerprints: dict = field(default_factory=dict)  # frame -> gather.fingerprint
    error: str | None = None  # what went wrong in the handler (Blender swallows it there)
    frames: str = ""  # a folder of each frame's mesh arrays (`keep`), read by the export
    replaying: bool = False  # the exporter runs: the frames are written from `frames`
    spray: bool = False  # a frame kept puffs: the spray's companion is exported and played


def baking(app):
    """The Recording of the bake being made of appearance `app`'s ocean, or None."""
    recording = RUNTIME.baking
    if recording is None or app.needs_stand_in or app.ocean.name != recording.ocean:
        return None
    return recording


def keep(frame, arrays, fingerprint, spray=None, level=0.0):
    """Keep frame `frame`'s mesh arrays (mesh.grid_arrays; None: empty) and its spray's puffs
    (spray.spray, None: none; over the sea's `level`) for the export, and what it was built
    for (gather.fingerprint)."""
    recording = RUNTIME.baking
    if recording.replaying or not recording.first <= frame <= recording.last:
        return
    recording.fingerprints[frame] = fingerprint
    kept = dict(arrays or {})
    if spray is not None and len(spray[0]):
        kept.update(zip(SPRAY_KEYS, (*spray, np.float64(level)), strict=True))
        recording.spray = True
    try:
        np.savez(kept_path(recording, frame), **kept)
    except OSError as err:
        recording.error = f"keeping frame {frame} failed: {err.strerror}"


def spray_of(arrays):
    """The puffs (positions, radii, opacities; or None) and the sea's level `keep` kept among a
    frame's arrays, taken out of them."""
    if SPRAY_KEYS[0] not in arrays:
        return None, 0.0
    *puffs, level = (arrays.pop(k) for k in SPRAY_KEYS)
    return tuple(puffs), float(level)


def kept(frame):
    """The mesh arrays `keep` kept of `frame` ({}: an empty mesh), or None for a frame outside
    the bake's; a frame of it not kept or not read is the bake's error."""
    recording = RUNTIME.baking
    if not recording.first <= frame <= recording.last:
        return None
    try:
        with np.load(kept_path(recording, frame)) as data:
            return {name: data[name] for name in data.files}
    except (OSError, ValueError) as err:
        recording.error = f"reading frame {frame} back failed: {err}"
        return None


def kept_path(recording, frame):
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
    mat = material_inputs.material_of(obj.data) if obj is not None else None
    if mat is None:
        return
    _record_sockets(mat.node_tree, recording.animated, recording.values, frame)
    for path, curve in drift_drivers(mat.node_tree).items():
        recording.drifts.setdefault(path, {})[frame] = curve.driver.expression
    group = shader_materials.group_tree(mat)
    for node in group.nodes if group is not None else ():
        recording.muted.setdefault(node.name, {})[frame] = node.mute
    recording.companions.setdefault(("", "hide_probe_sphere"), {})[frame] = obj.hide_probe_sphere
    for companion in baked_companions(obj):
        for owner, prop in COMPANION_PROPS:
            target = companion.data if owner == "data" else companion
            value = get_path(target, prop)
            if value is not None:
                key = (companion.name, f"{owner}.{prop}")
                recording.companions.setdefault(key, {})[frame] = (
                    tuple(value) if hasattr(value, "__len__") else value)
    for b, image in shader_materials.layer_taps(mat):
        if image is None:
            continue
        name = os.path.join(recording.slopes, f"band{b}_{frame:04d}.exr")
        _save(image, name)
        recording.images.setdefault(b, os.path.basename(name))
    body = body_material(obj)
    if body is not None:
        _record_sockets(body.node_tree, recording.body_animated, recording.body_values, frame)
        tile = shader_materials.caustic_tap(body)
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
