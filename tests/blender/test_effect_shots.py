"""Each effect in a fixed small EEVEE render: two shots (above and under the water) against
committed references as in test_shots.py, and for each effect a check that it shows: the pixels
where it should appear change as it does, measured against the same shot with that effect off.

The shots are 160 x 90 at 2 samples: refraction's dithered transparency is noisy at that count,
so the checks compare region means, not pixels.
"""

import math

import bpy
import numpy as np
import pytest
from bpy_extras.object_utils import world_to_camera_view
from mathutils import Vector

from tools.demo import default_shot

from .test_shots import compare_with_reference, done_updating, luminance, read

pytestmark = pytest.mark.slow  # EEVEE renders: `make test-fast` leaves them out
SIZE = (160, 90)


def box(name, location, scale, colour):
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=location)
    obj = bpy.context.active_object
    obj.name, obj.scale = name, scale
    mat = bpy.data.materials.new(name)
    if mat.node_tree is None:  # before Blender 5.0 (where use_nodes is deprecated)
        mat.use_nodes = True
    mat.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = colour
    obj.data.materials.append(mat)
    return obj


def setup(height, pitch):
    """The default shot with a sea floor 4 m down, a red block under the water, a yellow buoy
    across the surface, the sun 40° up ahead, and a strong wind over a short fetch (a harbour:
    foam, and waves about 30 cm high)."""
    scene = bpy.context.scene
    cam = default_shot(scene, size=SIZE, samples=2, height=height, pitch=pitch)
    sun = next(o for o in scene.objects if o.type == "LIGHT")
    sun.rotation_euler = (math.radians(40.0), 0.0, math.radians(200.0))
    box("Floor", (0.0, 40.0, -4.0), (80.0, 60.0, 0.2), (0.7, 0.6, 0.4, 1.0))
    box("Block", (-1.5, 12.0, -1.6), (1.5, 1.5, 1.5), (0.8, 0.05, 0.05, 1.0))
    box("Buoy", (2.5, 16.0, 0.0), (0.8, 0.8, 3.0), (0.9, 0.8, 0.1, 1.0))
    ocean = bpy.data.objects["Ocean"]
    ocean.projgrid.wind_speed, ocean.projgrid.fetch = 14.0, 2000.0
    ocean.projgrid.swell_height = 0.0
    return scene, cam, ocean


def render(scene, path, frame=12):
    """Render `frame` alone as an animation: the render's own frame handler decides the
    effects (the viewport may be at another frame)."""
    scene.frame_start = scene.frame_end = frame
    scene.render.filepath = path
    bpy.ops.render.render(animation=True)
    return read(path + f"{frame:04d}.png")


def region(scene, cam, point, half=(3, 3)):
    """Pixel window (rows, cols) around the image of a world point."""
    u, v, _ = world_to_camera_view(scene, cam, Vector(point))
    col, row = round(u * SIZE[0]), round((1.0 - v) * SIZE[1])
    return (slice(max(row - half[1], 0), row + half[1] + 1),
            slice(max(col - half[0], 0), col + half[0] + 1))


def yellowness(img):
    return (img[..., 0] + img[..., 1]).mean() / 2.0 - img[..., 2].mean()


def redness(img):
    return img[..., 0].mean() / max(img.mean(), 1e-6)


def test_effects_above_the_water(tmp_path):
    scene, cam, ocean = setup(3.0, -12.0)
    scene.frame_set(1)
    # The block would show in the buoy's reflection: local reflections stay off (test_effects).
    assert ocean.projgrid.active_effects == {"FOAM", "CONTACT_FOAM", "REFRACTION", "CAUSTICS"}
    img = render(scene, str(tmp_path / "above"))
    compare_with_reference("effects_above", str(tmp_path / "above0012.png"))

    block = region(scene, cam, (-1.5, 12.0, -1.0))
    ring = [region(scene, cam, (2.5 + dx, 16.0, 0.0), (1, 1)) for dx in (-0.9, 0.9)]
    beside = region(scene, cam, (7.0, 16.0, 0.0), (1, 1))  # open water at the same distance
    # The buoy's mirror image: a flat mirror shows a point where the mirrored point projects.
    mirrored = region(scene, cam, (2.5, 16.0, -0.7), (2, 4))
    aside = region(scene, cam, (7.0, 16.0, -0.7), (2, 4))

    ocean.projgrid.caustics = "OFF"
    off = render(scene, str(tmp_path / "no_caustics"))
    # The caustic shadow changes the sunlit floor seen through the water, and nothing above the
    # horizon. (Subtle at 2 samples: the shadow's pattern has a standard deviation of 0.08 in
    # transmission, and the dithered surface shows the floor in about half the pixels.)
    change = np.abs(img - off).mean(axis=-1)
    assert change[SIZE[1] // 2:].mean() > max(5e-4, 10.0 * change[:10].mean())
    ocean.projgrid.caustics = "AUTO"

    ocean.projgrid.refraction = "OFF"  # opaque water from here on: no dithered noise
    opaque = render(scene, str(tmp_path / "no_refraction"))
    # The block seen through the water (measured 1.08 times redder under the warm 12° sun,
    # which reddens the sky the opaque water mirrors too; the ripples carry Cox and Munk's
    # slopes near the camera, and their tilted facets reflect more at 14° grazing).
    assert redness(img[block]) > 1.05 * redness(opaque[block])
    # Contact foam: white at the buoy's waterline, brighter than open water beside it.
    assert min(luminance(opaque[r]).mean() for r in ring) > (
        luminance(opaque[beside]).mean() + 0.05)


    bpy.data.objects.remove(bpy.data.objects["Block"])  # nothing in front of the mirror image
    # the sun behind the camera: the sky's warm glow around it (which the probe captures at its
    # own resolution) away from the mirror image
    next(o for o in scene.objects if o.type == "LIGHT").rotation_euler.z = math.radians(20.0)
    # Calm: the harbour's 14 m/s roughens the water past any mirror image a 160-pixel picture
    # can show (Cox and Munk's slopes, below its pixels, blur the reflection; as does a
    # light breeze's ripples, 10 cm and shorter, at this size).
    ocean.projgrid.wind_speed = 1.0
    scene.frame_set(12)
    assert "LOCAL_REFLECTIONS" in ocean.projgrid.active_effects
    mirror = render(scene, str(tmp_path / "reflections"))
    compare_with_reference("effects_reflections", str(tmp_path / "reflections0012.png"))
    ocean.projgrid.local_reflections = "OFF"
    sky_only = render(scene, str(tmp_path / "no_reflections"))
    # The yellow buoy in the water below it, blurred by the ripples no pixel resolves (sky
    # only: the blue-grey sky there), and not in the open water beside it (measured: 0.0066
    # against 0.0024, which is the sky's warm glow around the sun as the probe captures it at
    # its own resolution; 0.022 in a mirror).
    gain = yellowness(mirror[mirrored]) - yellowness(sky_only[mirrored])
    elsewhere = yellowness(mirror[aside]) - yellowness(sky_only[aside])
    assert gain > 0.004 and abs(elsewhere) < 0.5 * gain, (gain, elsewhere)
    assert np.abs(mirror - sky_only)[:8].max() < 0.01  # the sky (above 4° up) is untouched
    done_updating()



def test_effects_under_the_water(tmp_path):
    scene, cam, ocean = setup(3.0, 12.0)
    # Above the water at frame 1 (where the viewport stays), 2 m under it at frame 12.
    cam.keyframe_insert("location", frame=1)
    cam.location.z = -2.0
    cam.keyframe_insert("location", frame=12)
    scene.frame_set(1)
    assert "UNDERWATER" not in ocean.projgrid.active_effects
    img = render(scene, str(tmp_path / "under"))
    compare_with_reference("effects_under", str(tmp_path / "under0012.png"))
    scene.frame_set(12)  # the camera where it rendered
    assert ocean.projgrid.active_effects == {"UNDERWATER", "GODRAYS", "CAUSTICS", "FOAM",
                                             "CONTACT_FOAM"}

    block = region(scene, cam, (-1.5, 12.0, -1.6))
    water = (slice(SIZE[1] // 2, None), slice(None))  # below the horizon: the water's depths
    ocean.projgrid.underwater = "OFF"
    off = render(scene, str(tmp_path / "no_underwater"))
    # Absorption (Fleck Eq. 17) takes the red out of the block 10 m away.
    assert redness(img[block]) < 0.8 * redness(off[block])
    ocean.projgrid.underwater = "AUTO"

    ocean.projgrid.godrays = "OFF"
    off = render(scene, str(tmp_path / "no_godrays"))
    assert luminance(img[water]).mean() > luminance(off[water]).mean() + 0.01  # in-scattering
    assert np.isfinite(img).all()
    done_updating()


def test_godrays_scatter_along_the_caustic_pattern(tmp_path, extension, monkeypatch):
    """The water body scatters in proportion to the caustic tile, looked up along the refracted
    sun from where each point's sunlight entered the water. With a tile of 8 m stripes along x,
    swapped on odd frames, the near water on one side of the camera scatters and the other does
    not: the brighter side changes with the frame (the tile is rewritten inside the render)."""
    def stripes(height_field, time, centre, size, n, sun, depth):
        band = (np.arange(n) * (size / n) // 8.0 + 1).astype(int) % 2  # 1 on [x, x + 8 m)
        frame = round(time * bpy.context.scene.render.fps)
        return np.broadcast_to(2.0 * (band ^ (frame % 2)), (n, n)).astype(np.float32)

    monkeypatch.setattr(extension.projgrid_addon.optics, "caustic_tile", stripes)
    scene, cam, ocean = setup(3.0, 0.0)
    cam.location.z = -2.0
    brighter = []
    for frame in (12, 13):
        img = luminance(render(scene, str(tmp_path / "stripes"), frame))
        third = SIZE[0] // 3
        brighter.append(img[:, -third:].mean() - img[:, :third].mean())  # right minus left
    assert brighter[0] > brighter[1] + 0.02


@pytest.fixture(autouse=True)
def _small_volumes():
    """Test scenes only: coarser EEVEE volumes keep the underwater shot quick on the CPU."""
    eevee = bpy.context.scene.eevee
    eevee.volumetric_tile_size = "16"
    eevee.volumetric_samples = 32


def test_spray_shows_in_eevee_and_cycles(tmp_path, extension):
    """A storm (force 10) from 5 m up, the wind blowing away from the camera: with spray (AUTO)
    the puffs torn off the crests whiten the picture, in EEVEE and in Cycles, against the same
    shot with spray off; more pixels brighten than darken (1.2x), mostly about the horizon's
    crests.
    Cycles at its default 8 transparent bounces ends the rays through many puffs black (a
    grey band of puffs along the horizon): the panel says so and which setting to raise."""
    scene = bpy.context.scene
    ocean_panel = extension.panels.ocean_panel
    default_shot(scene, size=(128, 72), samples=2, height=5.0, pitch=-4.0)
    ocean = bpy.data.objects["Ocean"]
    bpy.context.view_layer.objects.active = ocean
    assert bpy.ops.projgrid.sea_state(beaufort=10) == {"FINISHED"}
    ocean.projgrid.wind_direction = math.radians(60.0)
    scene.cycles.samples, scene.cycles.device = 4, "CPU"
    for engine in (scene.render.engine, "CYCLES"):
        scene.render.engine = engine
        shots = {}
        for mode in ("AUTO", "OFF"):
            ocean.projgrid.spray = mode
            scene.frame_set(48)
            assert ("SPRAY" in ocean.projgrid.active_effects) == (mode == "AUTO")
            note = [t for _, t in ocean_panel.stats_lines(ocean, scene) if "Transparent" in t]
            if engine == "CYCLES" and mode == "AUTO":  # the default 8 bounces: grey puffs
                assert len(note) == 1 and "8 transparent bounces" in note[0], note
                scene.cycles.transparent_max_bounces = 32  # as the panel's line says
            assert not [t for _, t in ocean_panel.stats_lines(ocean, scene)
                        if "Transparent" in t]
            scene.render.filepath = str(tmp_path / f"{engine}_{mode}.png")
            bpy.ops.render.render(write_still=True)
            shots[mode] = luminance(read(scene.render.filepath))
        change = shots["AUTO"] - shots["OFF"]
        brighter, darker = (change > 0.05).mean(), (change < -0.05).mean()
        # (5.2 measured EEVEE 0.0025 against 0.0008, Cycles 0.0075 against 0.0003: the far
        # puffs fade into the storm's haze, a nautical mile's visibility, as the far water
        # does: daylight.haze)
        assert brighter > 0.0015 and brighter > 1.2 * darker, (engine, brighter, darker)
        rows = (change > 0.05).mean(axis=1)
        assert rows.argmax() < 0.6 * len(rows), engine  # about the far crests, not the near sea
