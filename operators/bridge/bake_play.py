"""Switching an ocean to play its bake: the cache modifier on the ocean and its shadow caster,
the recorded inputs keyed (constant between frames), the gusts' drift keyed where it changed,
the companions keyed and driven, the image sequences read."""

import os
import shutil

import bpy

from ...projgrid_addon import optics
from ...shaders import materials as shader_materials
from ...shaders import water
from . import material_inputs, mesh, scene, shot
from .baked import (
    FOLLOW,
    KEYED,
    MODIFIER,
    baked_companions,
    body_material,
    drift_drivers,
    play_caustic_sequence,
    play_layer_sequences,
    set_path,
)
from .state import RUNTIME


def play(obj, path, relative, recording):
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
    obj.projgrid.bake_fingerprints = " ".join(
        recording.fingerprints.get(f, "") for f in range(recording.first, recording.last + 1))
    RUNTIME.state(obj).key = None
    mesh.empty(obj.data)  # the cache gives the mesh: what is left is empty if it gives none
    mod.object_path = _prim_path(obj, cache)
    probe = set(recording.companions.get(("", "hide_probe_sphere"), {}).values())
    if probe:  # out of our probe's capture on every frame if on any (the ocean is the user's
        obj.hide_probe_sphere = True in probe  # object: not keyed; its switch warns below)
    for companion in baked_companions(obj):
        _key_companion(companion, obj, recording.companions)
        old = companion.modifiers.get(MODIFIER)
        if old is not None:
            companion.modifiers.remove(old)
        if companion.data == obj.data:  # the shadow caster draws the ocean's mesh: the cache
            caster = companion.modifiers.new(MODIFIER, "MESH_SEQUENCE_CACHE")
            caster.cache_file, caster.object_path = cache, mod.object_path
            caster.read_data = mod.read_data
    _play_spray(obj, cache, mod.read_data, recording.spray)

    def file(name):  # a file the bake wrote, as the .blend refers to it
        path = os.path.join(recording.slopes, name)
        return bpy.path.relpath(path) if relative else path

    mat = material_inputs.material_of(obj.data)
    switched = False
    if mat is not None:
        _key(mat.node_tree, {**recording.values, **_drifts_keyed(mat.node_tree, recording)})
        play_layer_sequences(mat, {b: file(n) for b, n in recording.images.items()},
                                   recording.first, recording.last)
        for name, frames in recording.muted.items():
            if len(set(frames.values())) > 1:
                shader_materials.group_tree(mat).nodes[name].mute = False
                switched = True
    body = body_material(obj)
    if body is not None:
        _key(body.node_tree, recording.body_values)
        if recording.tiles:
            _fill_frames(recording)
            body.node_tree.nodes["Godrays"].mute = False
            play_caustic_sequence(body, file(recording.tiles[recording.first]),
                                        recording.first, recording.last,
                                        optics.GODRAY_TILE_TEXELS)
            switched = switched or len(set(recording.godrays.values())) > 1
    if switched:
        return ("effects switch on and off within the frames: the bake draws them on "
                "throughout (bake the frames apart to keep the switch)")
    return None


def _prim_path(obj, cache):
    """The path of `obj`'s mesh in `cache`: the exporter's prim names (USD's valid identifiers,
    made per character or, older USD, per byte of a name's UTF-8) of the object's parents, the
    object and its mesh under its root. (Looked up among the file's paths, not by the mesh the
    current frame plays, which may rightly be empty: a camera looking at the sky.)"""
    chain = [obj.data.name, obj.name]
    parent = obj.parent
    while parent is not None:
        chain.append(parent.name)
        parent = parent.parent
    obj.evaluated_get(bpy.context.evaluated_depsgraph_get())  # the cache read: its paths
    held = {p.path for p in cache.object_paths}
    for per_byte in (False, True):
        path = "/root/" + "/".join(_prim(n, per_byte) for n in reversed(chain))
        if path in held:
            return path
    raise RuntimeError(f"the cache holds no mesh at {path}")


def _play_spray(obj, cache, read_data, baked):
    """The spray's companion plays the puffs the bake holds (`baked`: a frame kept some) from
    the cache, before its points are drawn (its geometry nodes take a baked triangle per
    puff); else it is left empty (no frame handler writes it while the ocean plays a bake).
    Where it shows, its keyed visibility says (`_key_companion`)."""
    cloud = obj.projgrid.spray_cloud
    if cloud not in baked_companions(obj):
        return
    mesh.empty(cloud.data)
    if not baked:
        return
    points = cloud.modifiers.get(water.SPRAY_POINTS)
    if points is not None and scene.owns(points.node_group):
        points.node_group = shader_materials.spray_points()  # of this version: draws faces
    played = cloud.modifiers.new(MODIFIER, "MESH_SEQUENCE_CACHE")
    played.cache_file, played.read_data = cache, read_data
    cloud.modifiers.move(len(cloud.modifiers) - 1, 0)
    played.object_path = _prim_path(cloud, cache)


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
            _hold(scene.bag_curves(target))


def _key_frames(target, prop, frames, value=lambda v: v):
    """`prop` of `target` set to its recorded `value` where the frames ({frame: recorded})
    agree (the scene's live viewport frame may have written its own since), else keyed on
    each frame: returns whether it was keyed."""
    if len(set(frames.values())) < 2:
        set_path(target, prop, value(next(iter(frames.values()))))
        return False
    for frame, recorded in sorted(frames.items()):
        set_path(target, prop, value(recorded))
        target.keyframe_insert(prop, frame=frame)
    return True


def _hold(curves):
    """Keyframes held constant until the next: a baked frame plays what it recorded."""
    for curve in curves:
        for point in curve.keyframe_points:
            point.interpolation = "CONSTANT"


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


def _drifts_keyed(tree, recording):
    """The drift's values per frame, in place of its drivers, where the driver changed over
    the bake (a keyframed wind: each frame's reads the wind's run at that frame only, and a
    baked sea has no frame handler to write the next), as `values` for `_key`."""
    keyed = {}
    for path, curve in drift_drivers(tree).items():
        frames = recording.drifts.get(path, {})
        if len(set(frames.values())) > 1:
            tree.animation_data.drivers.remove(curve)
            keyed[path] = {f: (material_inputs.driven_value(e, f),) for f, e in frames.items()}
    return keyed


def _key(tree, values):
    """Keyframes (constant between frames) for the sockets whose recorded value changes; the
    others set to it (`_key_frames`)."""
    keyed = [path for path, frames in values.items()
             if _key_frames(tree.path_resolve(path.rsplit(".", 1)[0]), "default_value", frames,
                            lambda v: v[0] if len(v) == 1 else v)]
    _hold(c for c in scene.bag_curves(tree) if c.data_path in keyed)
    tree[KEYED] = keyed
