"""Rendered pictures: fixed small EEVEE shots against committed references, checks that need no
reference, and the water group's Fresnel against Blender's own Fresnel node.

References live in tests/blender/reference/<blender major.minor>/ (EEVEE differs a little between
versions). Tolerances, on linear-to-sRGB 8-bit PNGs in [0, 1]: mean absolute difference <= 0.02
and at most 2 % of pixels off by more than 0.1 (EEVEE's noise at 4 samples and CPU/driver
differences stay well inside; a wrong grid, a missing glint or a flipped Fresnel do not).
Regenerate after an intended change with PROJGRID_UPDATE_REFERENCES=1.
"""

import dataclasses
import math
import os

import bpy
import numpy as np
import OpenImageIO as oiio
import pytest

from tools.demo import default_shot, eevee_engine

pytestmark = pytest.mark.slow  # EEVEE renders: `make test-fast` leaves them out

REFERENCE = os.path.join(os.path.dirname(__file__), "reference",
                         "{}.{}".format(*bpy.app.version[:2]))
UPDATING = bool(os.environ.get("PROJGRID_UPDATE_REFERENCES"))
MEAN_TOL = 0.02
OUTLIER_TOL, OUTLIER_SHARE = 0.1, 0.02
# Pictures are compared over blocks of BLOCK x BLOCK pixels: the sun's glints and the foam's
# specks are single pixels whose places move with the CPU's floating point (llvmpipe's vector
# paths: one shot differed in 3 % of its pixels by over OUTLIER_TOL between two x86 machines,
# in 0.6 % of its 2x2 blocks), a change of the look spans more.
BLOCK = 2

SHOTS = {  # name: (height, pitch, yaw) of the camera; the sun is low toward +Y
    "horizon": (6.0, 0.0, 180.0),  # sun behind the camera: no glint
    "looking_down": (20.0, -60.0, 180.0),
    "sun_glint": (6.0, -6.0, 0.0),
    "underwater_up": (-3.0, 45.0, 180.0),  # Snell's window and total internal reflection
}


def read(path):
    return oiio.ImageBuf(path).get_pixels(oiio.FLOAT)[..., :3]


def blocks(px):
    """The picture's means over BLOCK x BLOCK pixels (the last partial row and column left
    out)."""
    h, w = px.shape[0] // BLOCK * BLOCK, px.shape[1] // BLOCK * BLOCK
    return px[:h, :w].reshape(h // BLOCK, BLOCK, w // BLOCK, BLOCK, -1).mean(axis=(1, 3))


def render_shot(name, tmp_path, gusts=1.0):
    height, pitch, yaw = SHOTS[name]
    scene = bpy.context.scene
    cam = default_shot(scene, size=(320, 180), samples=4, height=height, pitch=pitch)
    cam.rotation_euler.z = math.radians(yaw)
    bpy.data.objects["Ocean"].projgrid.gusts = gusts
    if name == "underwater_up":  # the window alone; the water body's fog: test_effect_shots.py
        ocean = bpy.data.objects["Ocean"]
        ocean.projgrid.underwater = ocean.projgrid.godrays = "OFF"
    scene.frame_set(12)
    path = str(tmp_path / f"{name}.png")
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    return path


def compare_with_reference(name, path):
    """Compare with the committed reference; with PROJGRID_UPDATE_REFERENCES set, write it
    instead (the test then skips at its end, `done_updating`: a picture compared with itself
    proves nothing)."""
    ref = os.path.join(REFERENCE, f"{name}.png")
    if UPDATING:
        os.makedirs(REFERENCE, exist_ok=True)
        oiio.ImageBuf(path).write(ref)
        return
    assert os.path.exists(ref), f"no reference {ref}: run with PROJGRID_UPDATE_REFERENCES=1"
    diff = np.abs(blocks(read(path)) - blocks(read(ref)))
    outliers = float((diff.max(axis=-1) > OUTLIER_TOL).mean())
    assert diff.mean() <= MEAN_TOL and outliers <= OUTLIER_SHARE, (diff.mean(), outliers)


def done_updating():
    if UPDATING:
        pytest.skip("references written: look at them before committing")


def luminance(img):
    return img @ np.array([0.2126, 0.7152, 0.0722])


def linear(img):
    """sRGB display values back to linear light."""
    return np.where(img <= 0.04045, img / 12.92, ((img + 0.055) / 1.055) ** 2.4)


def sky_seen(img):
    """Per row, the share of pixels showing the sky rather than the depths (what the total
    internal reflection shows with the water body off, the world below its horizon): the sky
    is bluer (blue less red about 0.25 in 5.2, 0.14 in 4.5's sky; the depths' 0.13 and 0.09),
    counted from a quarter of the way from the picture's 10th percentile of it to its 90th
    (the sky dims toward the critical angle, its Fresnel)."""
    blue = img[..., 2] - img[..., 0]
    low, high = np.percentile(blue, (10.0, 90.0))
    return (blue > low + 0.25 * (high - low)).mean(axis=1)


def window_share(scene, slope_variance, ior=1.333, n=121):
    """Per row of the camera's picture (from below the sea), the share of the sea's facets
    through which the view ray leaves the water, inside the critical angle asin(1 / ior) of the
    facet's normal: the slopes Gaussian of `slope_variance` (upwind plus crosswind), isotropic,
    each facet counted by the area it shows the camera (its horizontal area's share times
    cos(view, normal) / n_z), over three columns."""
    cam = scene.camera
    corners = [cam.matrix_world.to_3x3() @ v for v in cam.data.view_frame(scene=scene)]
    top_right, bottom_right, bottom_left, top_left = (np.array(c) for c in corners)
    sigma = np.sqrt(slope_variance / 2.0)
    s = np.linspace(-5.0, 5.0, n) * sigma
    sx, sy = np.meshgrid(s, s)
    weight = np.exp(-(sx * sx + sy * sy) / (2.0 * sigma * sigma)).ravel()
    normals = np.stack([-sx.ravel(), -sy.ravel(), np.ones(n * n)])
    normals /= np.linalg.norm(normals, axis=0)
    rows = scene.render.resolution_y
    share = np.zeros(rows)
    for r in range(rows):
        t = (r + 0.5) / rows
        for u in (0.125, 0.5, 0.875):
            ray = ((1 - t) * ((1 - u) * top_left + u * top_right)
                   + t * ((1 - u) * bottom_left + u * bottom_right))
            cos = ray / np.linalg.norm(ray) @ normals
            seen = weight * np.maximum(cos, 0.0) / normals[2]
            share[r] += seen[cos > np.cos(np.arcsin(1.0 / ior))].sum() / seen.sum() / 3.0
    return share


@pytest.mark.lts
@pytest.mark.parametrize("name", SHOTS)
def test_shot(name, tmp_path, extension):
    path = render_shot(name, tmp_path)
    img = luminance(read(path))
    assert np.isfinite(img).all() and img.std() > 0.003  # a picture, not a flat colour
    light = luminance(linear(read(path)))
    if name == "horizon":
        rows = img.mean(axis=1)  # the horizon is the middle row at pitch 0
        sky, water = rows[:80], rows[95:]
        assert sky.mean() > water[-20:].mean() + 0.1  # sky above brighter than the near water
        # Fresnel: the water brightens toward the horizon (grazing angles reflect more sky).
        bands = water.reshape(-1, 17).mean(axis=1)[::-1]  # from the bottom up
        assert np.all(np.diff(bands) > 0), bands
        # ... yet the far sea, rough at a pixel's scale, stays darker than the sky above it:
        # a horizon line (Bruneton's mean Fresnel), at least 10 % in luminance.
        above, below = light[80:89].mean(), light[91:100].mean()
        assert below < 0.9 * above, (below, above)
    if name == "underwater_up":  # Snell's window, broken as far as the sea's slopes break it
        seen = sky_seen(read(path)).reshape(6, -1).mean(axis=1)
        wind = bpy.data.objects["Ocean"].projgrid.wind_speed  # Cox and Munk's slopes for it
        variance = extension.projgrid_addon.shading.cox_munk(wind)
        expected = window_share(bpy.context.scene, variance).reshape(6, -1).mean(axis=1)
        # 0.15: one frame's sea, the Fresnel's dimming of the sky near the critical angle, and
        # the drawn slopes' heavier tails (the ripples' bump drawing a sixth of their slopes
        # gave an edge too sharp, 0.25 off at the critical angle)
        assert np.abs(seen - expected).max() <= 0.15, (seen.round(2), expected.round(2))
    if name == "sun_glint":
        # The sun 12° up ahead: its glitter path reaches the horizon (row 57 at 6° down),
        # twice as bright as the water beside it just below the horizon.
        below = light[58:68]
        assert below[:, 140:180].mean() > 2.0 * np.r_["1", below[:, :60], below[:, -60:]].mean()
    compare_with_reference(name, path)
    done_updating()


def local_detail(img):
    """How much each pixel differs from its four neighbours' mean."""
    around = 0.25 * (img[:-2, 1:-1] + img[2:, 1:-1] + img[1:-1, :-2] + img[1:-1, 2:])
    return img[1:-1, 1:-1] - around


def test_the_glitter_near_sparkles(extension, tmp_path, monkeypatch):
    """Near the camera the sun glitters on the glint's facets (shading.facet_variance): in the
    glitter path, sparkles (pixels a tenth of the display range brighter than their four
    neighbours' mean) are at least three times as many as with the facets' slopes left to
    the lobe, a smooth sheen, and at least 0.5 % of the pixels; and only where a facet may
    show the sun: with the sun behind the camera the picture is the one without them (facets
    there would only make the sky's reflection grainy). The wind steady: the gusts scale the
    facets' slopes alike in both, but a calm patch over the path's near end leaves fewer."""
    shading = extension.projgrid_addon.shading
    filtering = shading.filtering
    sparkles, away = {}, {}
    for facets in (True, False):
        if not facets:
            monkeypatch.setattr(shading, "filtering", lambda *a: dataclasses.replace(
                filtering(*a), facets_sharp_log=-100.0, facets_mean_log=-99.0))
        (tmp_path / str(facets)).mkdir()
        shots = {}
        for name in ("sun_glint", "horizon"):
            bpy.ops.wm.read_homefile(use_empty=True)
            shots[name] = luminance(read(render_shot(name, tmp_path / str(facets), gusts=0.0)))
        path = shots["sun_glint"][120:180, 120:200]  # the glitter path's near end
        sparkles[facets] = float((local_detail(path) > 0.1).mean())
        away[facets] = shots["horizon"]
    assert sparkles[True] > max(3.0 * sparkles[False], 0.005), sparkles
    assert np.abs(away[True] - away[False]).mean() < 1e-4


SEA_STATES = (0, 2, 4, 5, 6, 8, 10)  # Beaufort: calm to storm, every other preset and 5
GROWING = (2, 5, 8)  # light breeze, fresh breeze, gale: their look grows with the force


def test_sea_states(tmp_path):
    """Seven Beaufort presets against their references (camera 20 m up, the sun behind it: no
    glint), and the pictures follow the wind: the water's contrast (slopes turning the
    reflected sky) and its whitecaps grow with the force (under the same sky: Weather off)."""
    scene = bpy.context.scene
    cam = default_shot(scene, size=(240, 135), samples=4, height=20.0, pitch=-12.0)
    cam.rotation_euler.z = math.radians(180.0)
    contrast, white = {}, {}
    for force in SEA_STATES:
        bpy.ops.projgrid.sea_state(beaufort=force, weather=False)
        scene.frame_set(24)
        path = str(tmp_path / f"beaufort_{force}.png")
        scene.render.filepath = path
        bpy.ops.render.render(write_still=True)
        compare_with_reference(f"beaufort_{force}", path)
        water = luminance(read(path))[60:]  # below the horizon (row 39 at 12° down)
        # across each row: the slopes turning the reflection, not the Fresnel's rise with
        # the distance (which a rough sea flattens)
        contrast[force] = float((water - water.mean(axis=1, keepdims=True)).std())
        white[force] = float((water > 0.6).mean())  # brighter than any sky the water mirrors
    contrast, white = [contrast[f] for f in GROWING], [white[f] for f in GROWING]
    assert contrast[0] < contrast[1] < contrast[2], contrast
    # (the white share against Monahan's, over frames and views: tools/beaufort.py, the bench)
    assert white[0] < 0.0005 and white[0] < white[1] and 2.0 * white[1] < white[2], white
    done_updating()


def correlation_length(mask, axis):
    """Pixels along `axis` over which the mask's autocorrelation (over the picture, the mean
    taken out) falls to 1/e, interpolated between pixels."""
    m = mask - mask.mean()
    n = m.shape[axis]
    ac = np.fft.irfft(np.abs(np.fft.rfft(m, n=2 * n, axis=axis)) ** 2, axis=axis)
    ac = ac.mean(axis=1 - axis)[:n // 2]
    ac = ac / ac[0]
    k = int(np.argmax(ac < np.exp(-1.0)))
    return k - 1 + (ac[k - 1] - np.exp(-1.0)) / (ac[k - 1] - ac[k])


def test_a_gale_s_foam_is_blown_in_streaks(tmp_path):
    """Straight down from 80 m (the wind along the picture's rows), the foam (pixels brighter
    than the water seen from above) at Beaufort 8 lies in streaks along the wind (WMO: "foam
    blown in well-marked streaks"): its correlation length along the wind at least 2.5 times
    that across; at Beaufort 4 its patches are roughly round (within 1.6 either way). Three
    views 300 m apart: one view, some 60 m across, holds a wave group or two, and how much
    foam it shows (and so how far its patches run together) changes with them."""
    scene = bpy.context.scene
    cam = default_shot(scene, size=(200, 200), samples=4, height=80.0, pitch=-90.0)
    ratio = {}
    for force in (4, 8):
        bpy.ops.projgrid.sea_state(beaufort=force)
        lengths = []
        for view, frame in enumerate((48, 120, 192)):
            cam.location.x = 300.0 * view
            scene.frame_set(frame)
            scene.render.filepath = path = str(tmp_path / f"down_{force}_{frame}.png")
            bpy.ops.render.render(write_still=True)
            foam = (luminance(read(path)) > 0.35).astype(float)
            assert foam.mean() > 2e-4, (force, frame)  # foam to measure
            lengths.append([correlation_length(foam, axis) for axis in (1, 0)])
        along, across = np.mean(lengths, axis=0)
        ratio[force] = along / across
    assert 1.0 / 1.6 < ratio[4] < 1.6 and ratio[8] >= 2.5, ratio


FRESNEL = {"outside": ((0.0, -6.0, 0.0), (90.0, 0.0, 0.0), 0.0),  # sees front faces
           "outside, rough": ((0.0, -6.0, 0.0), (90.0, 0.0, 0.0), 0.02),
           # sees back faces (as from under water), near the wall and along it: grazing angles
           "inside": ((0.0, -1.8, 0.0), (90.0, 0.0, -90.0), 0.0)}


@pytest.mark.parametrize("view", FRESNEL)
def test_fresnel(extension, tmp_path, view):
    """Red = our group's Fresnel, green = Blender's Fresnel node at IOR 1.333, blue = 1 - |N.I|
    (Layer Weight's Facing), with the same normal, rendered as emission by EEVEE (one sample, so
    all at the pixel centre) to float EXR. From above ours is Bruneton's mean Fresnel over the
    unresolved slopes (sigma^2 set on the group): the exact reflectance (Blender's node's) less
    0.98 ((1 - c)^5 - (1 - c)^(5 e^(-2.69 s)) / (1 + 22.7 s^1.5)), s = sqrt(sigma^2 / 2), which
    a mirror keeps; from under water the exact one. (Cycles'
    Fresnel node also bends smooth normals toward valid reflections, so it is not the plain
    Eq. 1.4 there.)"""
    water = extension.shaders.water
    scene = bpy.context.scene
    bpy.ops.mesh.primitive_uv_sphere_add(radius=2.0, segments=64, ring_count=32)
    sphere = bpy.context.active_object
    bpy.ops.object.shade_smooth()
    mat = bpy.data.materials.new("Fresnel Test")
    tree = extension.shaders.nodes.empty_tree(mat)
    nodes, links = tree.nodes, tree.links
    group = nodes.new("ShaderNodeGroup")
    group.node_tree = water.node_group()
    location, rotation, rough = FRESNEL[view]
    group.inputs["Slope Floor"].default_value = rough
    group.inputs["Slope Ceiling"].default_value = rough
    theirs = nodes.new("ShaderNodeFresnel")
    theirs.inputs["IOR"].default_value = 1.333
    facing = nodes.new("ShaderNodeLayerWeight")
    facing.inputs["Blend"].default_value = 0.5
    combine = nodes.new("ShaderNodeCombineColor")
    links.new(group.outputs["Fresnel"], combine.inputs[0])
    links.new(theirs.outputs[0], combine.inputs[1])
    links.new(facing.outputs["Facing"], combine.inputs[2])
    emission = nodes.new("ShaderNodeEmission")
    links.new(combine.outputs[0], emission.inputs["Color"])
    out = nodes.new("ShaderNodeOutputMaterial")
    links.new(emission.outputs[0], out.inputs["Surface"])
    sphere.data.materials.append(mat)

    data = bpy.data.cameras.new("Camera")
    data.lens = 12.0 if view == "inside" else 50.0  # inside: wide, for grazing angles
    cam = bpy.data.objects.new("Camera", data)
    cam.location, cam.rotation_euler = location, np.radians(rotation)
    scene.collection.objects.link(cam)
    scene.camera = cam
    r = scene.render
    r.engine = eevee_engine()
    scene.eevee.taa_render_samples = 1
    r.resolution_x = r.resolution_y = 48
    r.film_transparent = True
    r.image_settings.file_format = "OPEN_EXR"
    r.image_settings.color_depth = "32"
    r.filepath = str(tmp_path / "fresnel.exr")
    bpy.ops.render.render(write_still=True)
    px = oiio.ImageBuf(r.filepath).get_pixels(oiio.FLOAT)
    hit = px[..., 3] > 0.999
    ours, blenders, grazing = px[..., 0][hit], px[..., 1][hit], px[..., 2][hit]
    assert hit.mean() > 0.2
    if view == "inside":  # total internal reflection outside Snell's window
        assert np.abs(ours - blenders).max() < 1e-3  # EEVEE's film keeps half floats (2^-11)
        assert (blenders > 0.999).mean() > 0.05 and blenders.min() < 0.1
        return
    s = np.sqrt(rough / 2.0)
    mean = grazing ** (5.0 * np.exp(-2.69 * s)) / (1.0 + 22.7 * s**1.5)
    expected = np.maximum(blenders + 0.98 * (mean - grazing**5), 0.0)
    assert np.abs(ours - expected).max() < 2e-3
    assert blenders.min() < 0.03 and blenders.max() > 0.3
    if rough > 0.0:  # at grazing angles a rough sea reflects less than a mirror
        edge = grazing > 0.95
        assert edge.any() and (ours[edge] < 0.8 * blenders[edge]).all()


def test_cycles_gives_a_sensible_image(tmp_path):
    """The same group in Cycles: sky above brighter than the near water, the water neither black
    nor blown out, and the water brightening toward the horizon."""
    scene = bpy.context.scene
    cam = default_shot(scene, size=(160, 90), height=6.0, pitch=0.0)
    cam.rotation_euler.z = math.radians(180.0)  # the sun behind
    scene.render.engine = "CYCLES"
    scene.cycles.samples = 8
    scene.cycles.device = "CPU"
    scene.frame_set(12)
    scene.render.filepath = str(tmp_path / "cycles.png")
    bpy.ops.render.render(write_still=True)
    rows = luminance(read(scene.render.filepath)).mean(axis=1)
    sky, water = rows[:40], rows[48:]
    assert sky.mean() > water[-10:].mean() + 0.1
    assert 0.05 < water.mean() < 0.9
    assert water[:10].mean() > water[-10:].mean()


def test_the_picture_is_linear_in_the_foam(tmp_path):
    """The Foam mix's factor at c everywhere covers c of the sea in linear light (the render's
    own values), however small c: how far the picture went from the one without foam toward
    the one all foam. The far sea's foam is a small share everywhere, and Monahan's share is
    an area share (tools/beaufort.py measures the picture so)."""
    from tools.beaufort import covers, render

    scene = bpy.context.scene
    default_shot(scene, size=(120, 68), samples=2, height=40.0, pitch=-12.0)
    bpy.ops.projgrid.sea_state(beaufort=4)
    scene.frame_set(24)
    group = bpy.data.objects["Ocean"].data.materials[0].node_tree.nodes[
        "Projected Grid Water"].node_tree
    factor = group.nodes["Foam"].inputs[0]
    group.links.remove(factor.links[0])
    linear = {}
    for c in (0.0, 1.0, 0.002, 0.05):
        factor.default_value = c
        linear[c] = render(scene, str(tmp_path / f"foam_{c}.png"))[1]
    sea, cover = covers(linear[0.0], linear[1.0], [linear[c] for c in (0.002, 0.05)], True)
    assert sea.mean() > 0.4  # the sea is 62 % of the view; its far rows gain little
    for c, drawn in zip((0.002, 0.05), cover, strict=True):
        assert drawn.mean() == pytest.approx(c, rel=0.1), c
