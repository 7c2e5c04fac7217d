"""The Beaufort pictures and the rendered white share per force: each force's preset from 5 m
and from 40 m up, and straight down from 300 m (EEVEE, frame 48, the wind blowing away from the
camera 30 degrees to the right of the view, so its streaks run toward a vanishing point, as in
photographs taken downwind; across the view they lie along the foreshortened crests; seen from
above, the white share as a photograph taken straight down measures it; the sun behind the
camera, off its left shoulder, as sea states are photographed: out of the glitter, which hides
the whitecaps in it), written to docs/ as
beaufort_<force>_<height>m.png, and the share of the sea's pixels the foam whitens, beside
Monahan and O'Muircheartaigh's whitecap share (effects.whitecap_coverage).

The white share is measured on the pictures of VIEWS views (`views`: other times, the camera
moved across the sea, so that each holds other breakers; at SHARE_SAMPLES). Each is rendered three
times, as drawn, with the foam muted and with foam everywhere; a pixel's foam cover is how far
it went from the muted picture toward the all-foam one. In linear light (the render's own
values, before the view transform) that is the share of the pixel's area the foam covers (the
Foam mix is linear in it), so its mean over the sea's pixels is the share of the sea the
picture shows covered: Monahan's share is such an area share. In display values (after the view
transform's curve) partial cover reads larger (a pixel a tenth covered reads as a fifth): the
pixels over a half there are the share that looks white (a sea without foam called for, force
2, has none). Monahan's share counts whitecaps and their foam: from Beaufort 7 a fourth render
draws them without the wind's blown streaks (streaks.blown_coverage), whose share is the rest.
`make bench` runs it (step `beaufort`); alone: python -m tools.beaufort [out_dir] [--quick]."""

import json
import math
import os
import sys
import tempfile

FORCES = (2, 4, 6, 8, 10)
HEIGHTS = {5.0: -4.0, 40.0: -12.0, 300.0: -90.0}  # camera height m: pitch deg
WIND = 60.0  # deg counter-clockwise from +X, where the wind blows toward (the camera looks +Y)
FRAME = 48  # the picture's, from the first view's place
# The white share is averaged over this many views (`views`): one view holds a few large
# breakers at most, so its share swings several-fold about the sea's (0.2-1.6x over twelve
# views of force 6 from 300 m, the vertices' foam alone).
VIEWS = 9
SHARE_SAMPLES = 4  # EEVEE's samples for the shares' renders: they read as 16 do, to 1 %
WHITE = 0.5  # a pixel's foam cover from which it reads as white
# deg, counter-clockwise from +Y (ahead of the camera): where the sun shines from, at Add
# Ocean's elevation (shaders/sky.aim)
SUN_AZIMUTH = 140.0


def sun_behind(scene):
    """Aim the scene's sun lamps from SUN_AZIMUTH, behind the camera off its left shoulder: out
    of the glitter, which hides the whitecaps in it."""
    from tools.bench.blender_bench import extension

    for obj in scene.objects:
        if obj.type == "LIGHT" and obj.data.type == "SUN":
            extension().shaders.sky.aim(obj, azimuth=SUN_AZIMUTH)


def views(count):
    """(frame, the camera's x in m) of `count` views: FRAME's from x = 0 first, then each 2 s
    later, the camera moved 700 m across the view (further than a view from 300 m holds),
    alternately either side."""
    return [(FRAME + 48 * k, 700.0 * ((k + 1) // 2) * (-1.0) ** k) for k in range(count)]


def render(scene, path):
    """Render the shot to `path` (PNG); its luminance in display values and in linear light
    (the render result saved as EXR beside it, before the view transform)."""
    import bpy
    import numpy as np

    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    settings = scene.render.image_settings
    kept = settings.file_format, settings.color_depth
    linear = path[:-4] + ".exr"
    try:
        settings.file_format, settings.color_depth = "OPEN_EXR", "32"
        bpy.data.images["Render Result"].save_render(linear, scene=scene)
    finally:
        settings.file_format, settings.color_depth = kept
    out = []
    for name in (path, linear):
        img = bpy.data.images.load(name)
        w, h = img.size
        px = np.array(img.pixels[:], np.float32).reshape(h, w, 4)[::-1, :, :3]
        bpy.data.images.remove(img)
        out.append(px @ np.array([0.2126, 0.7152, 0.0722]))
    os.remove(linear)
    return tuple(out)


def without_blown(group, scene, path):
    """The shot rendered with the group's Blown Coverage at nought (its links from the group's
    input cut for the render, the sockets they fed at 0)."""
    blown = next(n for n in group.nodes if n.bl_idname == "NodeGroupInput").outputs[
        "Blown Coverage"]
    fed = [link.to_socket for link in blown.links]
    for link in list(blown.links):
        group.links.remove(link)
    try:
        for target in fed:
            target.default_value = 0.0
        return render(scene, path)
    finally:
        for target in fed:
            group.links.new(blown, target)


def covers(off, on, pictures, relative):
    """(the sea's pixels, each of `pictures`' foam cover there): a pixel's cover is how far it
    went from `off` (the foam muted) toward `on` (foam everywhere), unclipped: EEVEE's sampling
    moves a pixel a little either way, and clipping would keep the moves up, so a mean cover
    is the foam's share (test_shots.py); the sea is where that gain is over 0.05 (of its
    largest if `relative`: where foam could show, not the sky)."""
    import numpy as np

    gain = on - off
    sea = gain > 0.05 * (max(float(gain.max()), 1e-9) if relative else 1.0)
    return sea, [((p - off) / np.where(sea, gain, 1.0))[sea] for p in pictures]


def white_share(group, scene, path, blown=True):
    """The shares of the sea's pixels in the shot, from the picture as drawn (written to
    `path`), two more with the Foam mix's factor at 0 and at 1, and one without the blown
    streaks (if `blown`: there are some; else the whitecaps' are the drawn ones'): {white,
    whitecaps: the share over a half covered in display values, of all the foam and of the
    whitecaps and their foam; cover: the mean cover in display values; area, whitecaps_area:
    the mean cover in linear light, the share of the sea's area covered}."""
    import numpy as np

    foam = group.nodes["Foam"].inputs[0]
    link = foam.links[0]
    source = link.from_socket
    group.links.remove(link)
    try:
        lum = {}
        for factor in (0.0, 1.0):
            foam.default_value = factor
            lum[factor] = render(scene, f"{path[:-4]}_foam{int(factor)}.png")
    finally:
        group.links.new(source, foam)
    drawn = render(scene, path)
    whitecaps = without_blown(group, scene, f"{path[:-4]}_whitecaps.png") if blown else drawn
    shares = {}
    for k, space in enumerate(("display", "linear")):
        sea, shares[space] = covers(lum[0.0][k], lum[1.0][k], [p[k] for p in (drawn, whitecaps)],
                                    space == "linear")
        if not sea.any():  # no foam drawn
            return dict.fromkeys(("white", "whitecaps", "cover", "area", "whitecaps_area"), 0.0)
    (drawn, whitecaps), (area, whitecaps_area) = shares["display"], shares["linear"]
    return {"white": float((drawn > WHITE).mean()),
            "whitecaps": float((whitecaps > WHITE).mean()),
            "cover": float(np.clip(drawn, 0.0, 1.0).mean()),
            "area": float(area.mean()), "whitecaps_area": float(whitecaps_area.mean())}


def shoot(out, quick=False):
    """Render every force from each height into `out` (the extension installed); the rows of
    (force, height, white share, mean cover, Monahan's share, picture)."""
    import bpy
    import numpy as np

    from projgrid_addon import effects, streaks
    from tools.demo import default_shot

    size, samples = ((240, 135), SHARE_SAMPLES) if quick else ((480, 270), 16)
    work = tempfile.mkdtemp(prefix="projgrid-beaufort-")
    rows = []
    for force in FORCES:
        for height, pitch in HEIGHTS.items():
            bpy.ops.wm.read_homefile(use_empty=True)
            scene = bpy.context.scene
            camera = default_shot(scene, size=size, samples=samples, height=height, pitch=pitch)
            ocean = bpy.data.objects["Ocean"]
            bpy.context.view_layer.objects.active = ocean
            ocean.projgrid.wind_direction = math.radians(WIND)  # Sea State turns the swell off it
            bpy.ops.projgrid.sea_state(beaufort=force)
            sun_behind(scene)
            group = ocean.data.materials[0].node_tree.nodes["Projected Grid Water"].node_tree
            name = f"beaufort_{force}_{int(height)}m.png"
            u = ocean.projgrid.wind_speed
            shares = []
            foamed = effects.whitecap_coverage(u) > effects.FOAM_MIN_COVERAGE
            # no foam: nothing to average
            for k, (frame, x) in enumerate(views(3 if quick else VIEWS) if foamed else views(1)):
                camera.location.x = x
                scene.frame_set(frame)
                if k == 0:
                    scene.eevee.taa_render_samples = samples
                    render(scene, os.path.join(out, name))
                    scene.eevee.taa_render_samples = SHARE_SAMPLES
                shares.append(white_share(group, scene, os.path.join(work, f"{frame}_{name}"),
                                          streaks.blown_coverage(u) > 0.0))
            rows.append({"force": force, "height": height, "pitch": pitch,
                         **{k: float(np.mean([f[k] for f in shares])) for k in shares[0]},
                         "frames": shares, "monahan": effects.whitecap_coverage(u),
                         "blown": streaks.blown_coverage(u), "path": name})
            print(json.dumps(rows[-1]), flush=True)
    return rows


def standalone(shoot):
    """Run a picture tool's `shoot(out, quick)` from the command line ([out_dir] [--quick]),
    the extension built and installed in a private user directory first."""
    os.environ.setdefault("BLENDER_USER_RESOURCES", tempfile.mkdtemp(prefix="projgrid-user-"))
    from tools.demo import install
    from tools.package import build

    install(build(tempfile.mkdtemp(prefix="projgrid-dist-")))
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    return shoot(args[0] if args else "docs", "--quick" in sys.argv)


if __name__ == "__main__":
    standalone(shoot)
