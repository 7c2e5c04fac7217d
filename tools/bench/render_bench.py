"""Benchmarks of what EEVEE renders cost: the water group against a plain glossy plane by
samples, the effects' render cost, and the far field's flicker from frame to frame."""

import math
import os
import tempfile
import time

import bpy
import numpy as np
import OpenImageIO as oiio

from .blender_bench import EFFECT_VARIANTS, _ocean, _set_modes, extension
from .core_bench import interleaved


def render_cost(samples=(1, 4, 16, 64), reference_samples=128, size=(320, 180), repeats=3):
    """EEVEE on this CPU: render time and error against a high-sample reference, for the water
    node group and for a plain glossy plane, at equal samples (the default shot): the two
    interleaved `repeats` times at each count up to 16 (once at more), the median wall time,
    its 10th percentile and the median CPU time."""
    from tools.demo import default_shot

    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    default_shot(scene, size=size, samples=1)
    scene.frame_set(12)
    ocean = _ocean(scene)
    water = ocean.data.materials[0]
    glossy = bpy.data.materials.new("Plain Glossy")
    tree = extension().shaders.nodes.empty_tree(glossy)
    bsdf = tree.nodes.new("ShaderNodeBsdfGlossy")
    bsdf.inputs["Roughness"].default_value = 0.05
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    tree.links.new(bsdf.outputs[0], out.inputs["Surface"])
    tmp = tempfile.mkdtemp(prefix="projgrid-bench-")

    def render(material, n):
        ocean.data.materials[0] = material
        scene.eevee.taa_render_samples = n
        scene.render.filepath = os.path.join(tmp, f"{material.name}-{n}.png")
        start, cpu = time.perf_counter(), time.process_time()
        bpy.ops.render.render(write_still=True)
        seconds = (time.perf_counter() - start, time.process_time() - cpu)
        return seconds, oiio.ImageBuf(scene.render.filepath).get_pixels(oiio.FLOAT)[..., :3]

    render(water, 1)  # shader compilation, not counted
    render(glossy, 1)
    refs = {m.name: render(m, reference_samples)[1] for m in (water, glossy)}
    rows = []
    for n in samples:
        times, error = {water.name: [], glossy.name: []}, {}
        for _ in range(repeats if n <= 16 else 1):
            for material in (water, glossy):
                seconds, img = render(material, n)
                times[material.name].append(seconds)
                error[material.name] = float(np.sqrt(np.mean((img - refs[material.name]) ** 2)))
        for material in (water, glossy):
            wall, cpu = np.array(times[material.name]).T
            rows.append({"material": "water group" if material is water else "plain glossy",
                         "samples": n, "seconds": float(np.median(wall)),
                         "p10": float(np.percentile(wall, 10)), "cpu": float(np.median(cpu)),
                         "rms_error": error[material.name]})
    ocean.data.materials[0] = water
    return rows


# name: (camera height m, pitch deg, yaw deg): toward the low sun from near the water, away
# from it from high up; the camera moves FLICKER_STEP m a frame along its view.
FLICKER_SHOTS = (("low, toward the sun", 6.0, -3.0, 0.0), ("aerial, away", 150.0, -12.0, 180.0))


FLICKER_STEP = 0.5


def _rows_below_horizon(pitch, size, degrees, lens=35.0):
    """The image rows (top, bottom) from the horizon to `degrees` below it, for a camera
    pitched `pitch` degrees (down negative) with a 36 mm wide sensor."""
    half = math.atan(36.0 / 2.0 / lens * size[1] / size[0])  # half the vertical field

    def row(angle):  # angle above the view axis
        return int(round(size[1] / 2.0 * (1.0 - math.tan(math.radians(angle)) / math.tan(half))))
    return row(-pitch), row(-pitch - degrees)


def _contrast(img, block=4):
    """The spread of `block`-pixel squares' means across each row: the waves' structure, not
    one pixel's noise."""
    h, w = (img.shape[0] // block) * block, (img.shape[1] // block) * block
    means = img[:h, :w].reshape(h // block, block, w // block, block).mean(axis=(1, 3))
    return float((means - means.mean(axis=1, keepdims=True)).std())


def flicker(out_dir, size=(320, 180), samples=4, frames=4, converged=64, supersample=8):
    """How much the far field (the horizon to 10° below it) changes from frame to frame as the
    camera moves over a still sea, with the filtering (shading.Filtering) and without it (every
    wave drawn as normals, a mirror's roughness and Fresnel), at equal samples: the mean
    per-pixel change of linear luminance from frame to frame, and its second difference over
    three frames (steady motion cancels there, flicker does not); and the near field's
    contrast (below that band, across each row, of 4-pixel squares). The first frame is also
    rendered without the filtering at `converged` samples ("converged"): what the pixels
    average to when every wave is drawn, so contrast that is aliasing is not counted as the
    waves'. That mirror lacks the roughness of the waves shorter than a pixel (Blender's bump
    takes its slopes across a pixel), so the filtered frames are also rendered with
    `supersample` times the pixels each way (one sample each) and averaged down
    ("supersampled", every frame): the same sea with waves down to that fraction of a pixel
    drawn as normals, what the filtering should keep, and how much that picture itself changes
    from frame to frame. Each shot's first frame, without and with the
    filtering side by side, is written to `out_dir` as bench_horizon_<n>.png."""
    import dataclasses

    from tools.demo import default_shot

    shading = extension().projgrid_addon.shading
    filtering = shading.filtering

    def unfiltered(*args):  # the same sea (its ripples carry Cox and Munk's slopes), all drawn
        return dataclasses.replace(filtering(*args), pixel_log=-50.0, floor=0.0, ripple=0.0,
                                   density=0.0, ceiling=0.0)
    weights = np.array([0.2126, 0.7152, 0.0722])
    tmp = tempfile.mkdtemp(prefix="projgrid-flicker-")
    rows = []
    try:
        for n, (shot, height, pitch, yaw) in enumerate(FLICKER_SHOTS):
            top, bottom = _rows_below_horizon(pitch, size, 10.0)
            firsts = {}
            for variant in ("unfiltered", "filtered", "converged", "supersampled"):
                filtered = variant in ("filtered", "supersampled")
                shading.filtering = filtering if filtered else unfiltered
                bpy.ops.wm.read_homefile(use_empty=True)
                scene = bpy.context.scene
                scale = supersample if variant == "supersampled" else 1
                cam = default_shot(scene, size=(size[0] * scale, size[1] * scale),
                                   height=height, pitch=pitch,
                                   samples={"converged": converged,
                                            "supersampled": 1}.get(variant, samples))
                cam.rotation_euler.z = math.radians(yaw)
                heading = np.array([-math.sin(math.radians(yaw)), math.cos(math.radians(yaw))])
                images = []
                for k in range(1 if variant == "converged" else frames):
                    cam.location.x, cam.location.y = FLICKER_STEP * k * heading
                    scene.frame_set(24)  # the sea still: what changes is the camera's doing
                    scene.render.filepath = os.path.join(tmp, f"{variant}-{k}.png")
                    bpy.ops.render.render(write_still=True)
                    img = oiio.ImageBuf(scene.render.filepath).get_pixels(oiio.FLOAT)[..., :3]
                    firsts.setdefault(variant, img)
                    linear = np.where(img <= 0.04045, img / 12.92,
                                      ((img + 0.055) / 1.055) ** 2.4)
                    luminance = linear @ weights
                    images.append(luminance.reshape(size[1], scale, size[0], scale).mean(
                        axis=(1, 3)))  # a pixel of the shot: the mean of its light
                far = [np.abs(b[top:bottom] - a[top:bottom]).mean()
                       for a, b in zip(images[:-1], images[1:], strict=True)]
                # The second difference: a steady motion's change cancels, a flicker's not.
                bent = [np.abs(c[top:bottom] - 2.0 * b[top:bottom] + a[top:bottom]).mean()
                        for a, b, c in zip(images[:-2], images[1:-1], images[2:], strict=True)]
                near = [_contrast(i[bottom:]) for i in images]
                row = {"shot": shot, "variant": variant, "near_contrast": float(np.mean(near)),
                       "far_luminance": float(np.mean([i[top:bottom].mean() for i in images]))}
                if variant != "converged":
                    row.update(flicker=float(np.mean(far)), flicker_2=float(np.mean(bent)))
                if variant in ("unfiltered", "filtered"):
                    row.update(picture=f"bench_horizon_{n}.png")
                rows.append(row)
            pair = np.concatenate([firsts["unfiltered"], np.ones((size[1], 4, 3)),
                                   firsts["filtered"]], axis=1)
            buf = oiio.ImageBuf(oiio.ImageSpec(pair.shape[1], pair.shape[0], 3, oiio.UINT8))
            buf.set_pixels(oiio.ROI(), pair.astype(np.float32))
            buf.write(os.path.join(out_dir, f"bench_horizon_{n}.png"))
    finally:
        shading.filtering = filtering
    return rows


def effect_render_cost(size=(320, 180), samples=4, repeats=3):
    """EEVEE render time of the default shot per effect variant (each variant compiles its own
    shader first, not counted; renders are sequential because a variant change recompiles,
    except for the no-sun pair of the target, which shares its shader and is interleaved)."""
    from tools.demo import default_shot

    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    default_shot(scene, size=size, samples=samples)
    tmp = tempfile.mkdtemp(prefix="projgrid-bench-")
    scene.render.filepath = os.path.join(tmp, "effect.png")
    # The target's pair shows the same shader (no effect is on in either), so it is measured
    # round-robin, side by side like the rebuilds, after the others.
    pair = ("everything off, no sun", "bare ocean, auto, no sun")
    rows = []
    for name in EFFECT_VARIANTS:
        if name in pair:
            continue
        _set_modes(scene, name)
        scene.frame_set(12)
        bpy.ops.render.render(write_still=True)  # compile this variant's shader
        times = []
        for _ in range(repeats):
            start = time.perf_counter()
            bpy.ops.render.render(write_still=True)
            times.append(time.perf_counter() - start)
        rows.append({"variant": name, "seconds": float(np.median(times))})

    def shot(name):
        _set_modes(scene, name)
        scene.frame_set(12)
        bpy.ops.render.render(write_still=True)

    side_by_side = interleaved({n: (lambda n=n: shot(n)) for n in pair}, 2 * repeats - 1)
    return rows + [{"variant": n, "seconds": t.median, "p10_seconds": t.p10,
                    "cpu_seconds": t.cpu} for n, t in side_by_side.items()]
