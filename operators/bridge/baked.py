"""A baked ocean: what marks it (our Mesh Sequence Cache modifier), what the bake gave it (keys,
drivers, image sequences of the slope layer and the godrays' tile) and undoing it (`free`,
Back to Live), and whether it still matches the scene (`stale`)."""

import os

import bpy

from ...projgrid_addon import optics, water_model
from ...shaders import materials as shader_materials
from ...shaders import water
from ...shaders.nodes import TAG
from . import floats, material_inputs, scene, shot
from .state import RUNTIME

MODIFIER = "Projected Grid Bake"


KEYED = "projgrid_bake_keys"  # on our material's node tree: the socket paths the bake keyed


FOLLOW = {"hide_render": "projgrid_bake_hide_render",  # the recorded visibility (_key_companion)
          "hide_viewport": "projgrid_bake_hide_viewport"}


def get_path(target, path):
    """A property of `target`, or (path '["name"]') its custom property; None if it has none."""
    if path.startswith('["'):
        return target.get(path[2:-2])
    return getattr(target, path, None)


def set_path(target, path, value):
    """Set a property or (path '["name"]') a custom property of `target`."""
    if path.startswith('["'):
        target[path[2:-2]] = value
    else:
        setattr(target, path, value)


def cache_modifier(obj):
    """Our Mesh Sequence Cache modifier on `obj`, or None: the ocean plays its bake."""
    mod = obj.modifiers.get(MODIFIER)
    return mod if mod is not None and mod.type == "MESH_SEQUENCE_CACHE" else None


def is_baked(obj):
    return cache_modifier(obj) is not None


def body_material(obj):
    """Our water body's material of ocean `obj` (None without one of ours)."""
    body = obj.projgrid.water_body
    if body is None or body not in baked_companions(obj) or not len(body.data.materials):
        return None
    mat = body.data.materials[0]
    return mat if mat is not None and mat.get(scene.TAG) and mat.library is None else None


def is_copy(obj):
    """Whether `obj` is a duplicate whose companions and material are still another ocean's
    (the shadow caster, parented to its ocean, tells)."""
    caster = obj.projgrid.shadow_caster
    return caster is not None and caster.parent not in (None, obj)


def baked_companions(obj):
    """Our companions of ocean `obj` (companions.py) a bake keys, and the followers of the
    objects floating on it (floats.py: so a farm running no scripts floats them); none for a
    duplicate (`is_copy`)."""
    if is_copy(obj):
        return []
    out = [getattr(obj.projgrid, prop) for prop in scene.COMPANIONS] + floats.followers(obj)
    return [c for c in out if c is not None and scene.owns(c) and scene.local(c)]


def drift_drivers(tree):
    """The drivers of the gusts' drift (water.GUST_DRIFT) in our material's tree, by path."""
    node = tree.nodes.get(water.GROUP)
    data = tree.animation_data
    if node is None or data is None:
        return {}
    paths = [node.inputs[n].path_from_id("default_value") for n in water.GUST_DRIFT
             if n in node.inputs]
    return {p: c for p in paths if (c := data.drivers.find(p)) is not None}


def _unkey(tree):
    """The keyframes `_key` made, removed (and the action, if they were all it held)."""
    keyed = set(tree.get(KEYED, []))
    bag = scene.channelbag(tree)
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
    play_layer_sequences(mat, {}, 0, 0)


def free(obj):
    """Back to live: our cache modifier, keyframes, layer sequences and cache file removed (the
    files stay on disk). Returns whether there was a bake."""
    mod = cache_modifier(obj)
    cache = mod.cache_file if mod is not None else None
    if mod is not None:
        obj.modifiers.remove(mod)
    for companion in baked_companions(obj):
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
            action = target.animation_data.action if scene.bag_curves(target) else None
            if action is not None or len(target.animation_data.drivers):
                target.animation_data_clear()
            if action is not None and action.users == 0:
                bpy.data.actions.remove(action)
    mat = material_inputs.material_of(obj.data) if not is_copy(obj) else None  # the original's
    if mat is not None:
        _unkey(mat.node_tree)
        play_layer_sequences(mat, {}, 0, 0)
    body = body_material(obj)
    if body is not None:
        _unkey(body.node_tree)
        play_caustic_sequence(body, None, 0, 0, optics.GODRAY_TILE_TEXELS)
    if cache is not None and cache.get(scene.TAG) and not any(
            getattr(m, "cache_file", None) == cache for o in bpy.data.objects
            for m in o.modifiers):
        bpy.data.batch_remove([cache])
    obj.projgrid.bake_camera = ""
    obj.projgrid.bake_frames = (0, 0)
    obj.projgrid.bake_fingerprints = ""
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
    state = RUNTIME.peek(obj)
    return state.stale if state is not None else None


def changed(obj, frame, now):
    """Why baked frame `frame` of `obj` no longer shows what it would be built for now (`now`:
    gather.fingerprint), or None (also outside the baked frames)."""
    start, end = obj.projgrid.bake_frames
    kept = obj.projgrid.bake_fingerprints.split(" ")
    if not start <= frame <= end or len(kept) != end - start + 1 or not kept[frame - start]:
        return None
    was = kept[frame - start].split(":")
    what = [name for name, a, b in zip(("the camera or where the ocean shows", "its settings"),
                                        was, now.split(":"), strict=True) if a != b]
    return f"{' and '.join(what)} changed since frame {frame} was baked" if what else None


BAKED_LAYER = "Projected Grid Bake Slopes"  # and the band's number: a bake's image sequence


BAKED_CAUSTICS = "Projected Grid Bake Caustics"  # the godrays' tile, a bake's image sequence


def play_layer_sequences(mat, files, first, last):
    """The slope layer read from image sequences, per band the file of frame `first` (numbered
    by frame, up to `last`), as a bake wrote them; `files` empty: back to the images written
    each frame (the bake's sequences removed, update_layer makes new images)."""
    nodes = mat.node_tree.nodes
    for b in range(1, water_model.LAYER_BANDS + 1):
        taps = shader_materials.layer_tap_nodes(nodes, b)
        if taps is None:
            continue
        old = taps[0].image
        if b not in files and (old is None or not old.name.startswith(BAKED_LAYER)):
            continue  # live images: left as they are
        image = _sequence(files[b], f"{BAKED_LAYER} {b}") if b in files else None
        for tap in taps:
            _read(tap, image, first, last)
        _drop_baked(old, BAKED_LAYER)


def play_caustic_sequence(mat, file, first, last, texels):
    """The godrays' caustic tile of a water body material read from an image sequence (the
    file of frame `first`, numbered up to `last`), as a bake wrote it; `file` None: back to
    our image written each frame, `texels` square."""
    node = shader_materials.caustic_tap(mat)
    if node is None:
        return
    old = node.image
    if file is None:
        if old is None or not old.name.startswith(BAKED_CAUSTICS):
            return
        # (a sequence's size is 0 unread)
        _read(node, shader_materials.caustic_image(texels), first, last)
    else:
        _read(node, _sequence(file, BAKED_CAUSTICS), first, last)
    _drop_baked(old, BAKED_CAUSTICS)


def _sequence(file, name):
    """Our image sequence (float data) whose first file is `file`, named `name`."""
    image = bpy.data.images.load(file, check_existing=False)
    image.name = name
    image.source = "SEQUENCE"
    image.colorspace_settings.is_data = True
    image[TAG] = True
    return image


def _read(tap, image, first, last):
    """`tap` reads `image`, a sequence's frame `first` on scene frame `first` up to `last`."""
    tap.image = image
    if image is not None and image.source == "SEQUENCE":
        user = tap.image_user
        user.frame_start, user.frame_offset = first, first - 1
        user.frame_duration, user.use_auto_refresh = last - first + 1, True


def _drop_baked(image, prefix):
    """A bake's image sequence of ours that nothing uses any more, removed."""
    if (image is not None and image.get(TAG) and image.name.startswith(prefix)
            and image.users == 0):
        bpy.data.batch_remove([image])
