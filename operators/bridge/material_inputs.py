"""Writing our materials each frame: the water group's inputs (the plan's values, each written
only when it changed), its muted branches, the drivers that advance its times, the slope
layer's and the godrays' images, the water body's inputs; and making a material our own before
it is written (never a user's or a library's)."""

import zlib

import bpy
import numpy as np

from ...projgrid_addon import water_model
from ...projgrid_addon.look import FOAM_COLOUR, WATER_COLOUR, body_volume
from ...shaders import water
from ...shaders.materials import body_material, caustic_image, caustic_tap, layer_nodes, material
from ...shaders.nodes import TAG, assign

# This session's layer images: {image session_uid: (owning material's session_uid, checksum
# of the tile written)}. Not saved: a reopened file's images are claimed and written anew.
_LAYER_WRITTEN = {}


def own_body_material(mesh, absorption, tile_texels):
    """The body material of one water body: its own (oceans' clarities and colours differ) and
    of this water.VERSION (a file from an older version carries an older one), made from
    `body_material` when it is not."""
    mat = mesh.materials[0] if len(mesh.materials) else None
    current = mat is not None and mat.get(TAG) == water.VERSION and mat.library is None
    own = mat if current else body_material(absorption, tile_texels)  # ours, rebuilt if older
    if own.users - int(own.use_fake_user) - int(own is mat) > 0:  # another body's too
        own = own.copy()
    if own is not mat:
        mesh.materials[0] = own
    return own


def update_body(mat, absorption, water_colour):
    """The water body's absorption per metre (RGB) and its glow toward `water_colour`
    (look.body_volume), written only when they change."""
    nodes = mat.node_tree.nodes
    absorb, glow = nodes.get("Absorption"), nodes.get("Water Glow")
    if absorb is None or glow is None:
        return
    colour, density, glow_colour, strength = body_volume(absorption, water_colour)
    assign(absorb.inputs["Color"], default_value=colour)
    assign(absorb.inputs["Density"], default_value=density)
    assign(glow.inputs["Color"], default_value=glow_colour)
    assign(glow.inputs["Strength"], default_value=strength)


def update_godrays(mat, tile, lookup):
    """The caustic tile's intensities (n x n) into our image and its `lookup` ((a, b, c): the
    texture coordinates of a point Q are a.Q + c[0], b.Q + c[1]) into the body material."""
    nodes = mat.node_tree.nodes
    node = caustic_tap(mat)
    if node is None:
        return
    if node.image is None or not node.image.get(TAG) or tuple(node.image.size) != tile.shape:
        node.image = caustic_image(tile.shape[0])
    image = node.image
    rgba = np.empty((*tile.shape, 4), dtype=np.float32)
    rgba[..., :3] = tile[..., None]
    rgba[..., 3] = 1.0
    image.pixels.foreach_set(rgba.ravel())
    image.update()
    image.pack()  # packed, it is not a "modified image" Blender offers to save at closing
    a, b, c = lookup
    assign(nodes["Caustic U"].inputs[1], default_value=tuple(a))
    assign(nodes["Caustic V"].inputs[1], default_value=tuple(b))
    assign(nodes["Caustic U Offset"].inputs[1], default_value=float(c[0]))
    assign(nodes["Caustic V Offset"].inputs[1], default_value=float(c[1]))


def update_layer(mat, slopes, lookups, origin):
    """The slope layer's tiles (per band (2, n, n): the slopes along x and y) into the
    material's own float images, and their lookups ((a, b, c) per band, texel coordinates
    about `origin` (x, y): slope_layer.SlopeLayer.lookups) into its nodes. Images are written,
    not packed, each frame (a pack costs 3 ms; the save handler packs them)."""
    tree = mat.node_tree
    group = tree.nodes.get(water.GROUP)
    if (group is None or group.type != "GROUP"
            or f"Layer Slopes {water_model.LAYER_BANDS}" not in group.inputs):
        return
    layer_nodes(tree, group)
    nodes = tree.nodes
    assign(nodes["Layer Origin"].inputs[1], default_value=(float(origin[0]), float(origin[1]),
                                                           0.0))
    for b, (tile, (a, bb, c)) in enumerate(zip(slopes, lookups, strict=True), 1):
        n = tile.shape[-1]
        image = nodes[f"Layer {b} Tap 0"].image
        entry = _LAYER_WRITTEN.get(image.session_uid) if image is not None else None
        if (image is None or not image.get(TAG) or tuple(image.size) != (n, n)
                or (entry and entry[0] != mat.session_uid)  # another material's
                or image.library is not None):
            image = bpy.data.images.new(f"{water.LAYER_IMAGE} {b}", n, n, float_buffer=True,
                                        is_data=True)
            image[TAG] = True
        for tap in range(4):
            if nodes[f"Layer {b} Tap {tap}"].image != image:
                nodes[f"Layer {b} Tap {tap}"].image = image
        written = zlib.crc32(tile.tobytes())  # unchanged (a redraw at the same time, after a
        if _LAYER_WRITTEN.get(image.session_uid) != (mat.session_uid, written):  # save): clean
            rgba = np.zeros((n, n, 4), dtype=np.float32)
            rgba[..., 0], rgba[..., 1], rgba[..., 3] = tile[0], tile[1], 1.0
            image.pixels.foreach_set(rgba.ravel())
            image.update()
            _LAYER_WRITTEN[image.session_uid] = (mat.session_uid, written)
        for axis, row, start in (("S", a, c[0]), ("T", bb, c[1])):
            assign(nodes[f"Layer {b} {axis}"].inputs[1], default_value=tuple(row))
            assign(nodes[f"Layer {b} {axis} Offset"].inputs[1], default_value=float(start))
            assign(nodes[f"Layer {b} {axis} Texel"].inputs[1], default_value=1.0 / n)
            assign(nodes[f"Layer {b} {axis} Step"].inputs[1], default_value=1.0 / n)


def layer_images():
    """Our slope layer images (the save and render-done handlers pack them: written, not
    packed, each frame, they would be offered as 'modified images' at closing)."""
    return [image for image in bpy.data.images
            if image.get(TAG) and image.name.startswith(water.LAYER_IMAGE)
            and image.library is None]


def own_material(mesh):
    """Give our mesh a local copy of its water material of ours if another mesh uses it too (a
    duplicated ocean, or a file from when oceans shared one) or if it is a library's, so its
    inputs are its own to write. Returns the copy, or None."""
    mat = mesh.materials[0] if len(mesh.materials) else None
    if mat is not None and mat.get(TAG) and (
            mat.library is not None or mat.users > 1 + int(mat.use_fake_user)):
        mesh.materials[0] = adopt_material(mat)
        return mesh.materials[0]
    return None


def adopt_material(mat):
    """The material a mesh of ours drawing another's sea takes: a local copy of a water
    material of ours (keeping the artist's changes to its inputs, on our local node group), the
    user's own material as it is (never written), or a new water material if there is none."""
    if mat is None:
        return material()
    if not mat.get(TAG):
        return mat
    copy = mat.copy()
    node = copy.node_tree.nodes.get(water.GROUP) if copy.node_tree else None
    if node is not None and node.type == "GROUP" and (
            node.node_tree is None or node.node_tree.library is not None):
        node.node_tree = water.node_group()
    return copy


def material_of(mesh):
    """Our local water material on `mesh`, or None (the user's own material, or a library's,
    is never written)."""
    mat = mesh.materials[0] if len(mesh.materials) else None
    ours = mat is not None and mat.get(TAG) and mat.library is None and mat.node_tree
    return mat if ours else None


def update(mat, effects_on, detail, detail_time_per_frame, ripple, ripple_time_per_frame,
           filtering, water_colour=WATER_COLOUR, foam_colour=FOAM_COLOUR, wind_direction=0.0,
           foam=None, layer=(), sun_direction=None, gust_drift=((0.0, 0.0),) * 3,
           body_reach=None, haze=0.0, overcast=0.0):
    """A frame's inputs into our water material's group, each written only when it changed:
    which effects are on ({effect: bool}), the left-out octaves as detail (shading.Detail) and
    the ripples (shading.Detail), whose times drivers advance with the frame (subframes
    included), so an animation writes nothing per frame; the filtering of the waves too short
    to draw (shading.Filtering); the ocean's look (linear RGB colours); the wind's direction
    (radians), which streaks the foam, and the foam's shares and streak (foam.foam_look; None:
    no foam), its shares shown where a pixel outgrows a whitecap; the slope layer's bands
    ((level, top log, bottom log) each; none: no layer); the unit vector toward the sun lamp
    (None: no sun, no glint); the gusts' drift along X, along Y and its path (m), each (per
    frame, offset) for a driver like the times'; how far the water body is drawn (m; None:
    the default); the air's extinction per metre (0: no haze) and our sky's overcast, its
    light."""
    node = mat.node_tree.nodes.get(water.GROUP)
    if node is None or node.type != "GROUP":
        return
    tree = node.node_tree
    if tree is not None and tree.get(TAG) and tree.library is None:
        if tree.get(TAG) != water.VERSION:  # a file from an older version: ours, rebuilt
            node.node_tree = tree = water.node_group()
        set_effects(tree, effects_on, water.EFFECT_NODES)
    inputs = node.inputs
    values = water_model.values(filtering, detail, ripple, wind_direction, foam, layer, haze,
                                overcast)
    for name, value in values.items():
        if name in inputs:  # a group of an older version until it is rebuilt
            assign(inputs[name], default_value=float(value))
    for name, colour in (("Water Colour", water_colour), ("Foam Colour", foam_colour)):
        if name in inputs:
            assign(inputs[name], default_value=(*colour, 1.0))
    if body_reach is not None and "Body Reach" in inputs:
        assign(inputs["Body Reach"], default_value=float(body_reach))
    if "Sun Direction" in inputs:
        assign(inputs["Sun Direction"], default_value=tuple(
            float(v) for v in (sun_direction if sun_direction is not None else (0.0, 0.0, 0.0))))
    drive_by_frame(mat.node_tree, inputs["Detail Time"], detail_time_per_frame)
    drive_by_frame(mat.node_tree, inputs["Ripple Time"], ripple_time_per_frame)
    for name, (per_frame, offset) in zip(water.GUST_DRIFT, gust_drift, strict=True):
        drive_by_frame(mat.node_tree, inputs[name], per_frame, offset)


def drive_expression(per_frame, offset=0.0):
    if offset:
        return f"{float(offset)!r} + frame * {float(per_frame)!r}"
    return f"frame * {float(per_frame)!r}"


def driven_value(expression, frame):
    """What a `drive_expression` reads at `frame`."""
    offset, _, per_frame = expression.rpartition("frame * ")
    return float(offset.rstrip(" +") or 0.0) + frame * float(per_frame)


def drive_by_frame(tree, socket, per_frame, offset=0.0):
    """A driver setting `socket`'s value to `offset` plus the frame (with its subframe) times
    `per_frame`, written only when it changes (a simple expression: it runs where Python is
    blocked)."""
    path = socket.path_from_id("default_value")
    expression = drive_expression(per_frame, offset)
    curve = tree.animation_data.drivers.find(path) if tree.animation_data else None
    if curve is None:
        curve = socket.driver_add("default_value")
        curve.driver.type = "SCRIPTED"
    if curve.driver.expression != expression:
        curve.driver.expression = expression


def set_effects(tree, on, nodes):
    """Mute each branch no effect that is on needs (only on change: a change recompiles)."""
    for name, needed_by in nodes.items():
        node = tree.nodes.get(name)
        mute = not any(on.get(effect, False) for effect in needed_by)
        if node is not None and node.mute != mute:
            node.mute = mute
