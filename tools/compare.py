"""Side-by-side shots: our ocean (spectrum, then noise) beside Blender's Ocean modifier at the
same wind, with the same camera, sky, sun and water material (EEVEE). `make bench` renders them
into docs/ (the benchmark's `pictures` step); alone: python -m tools.compare [out_dir] [--quick].

The modifier gets Pierson-Moskowitz at the same wind (its JONSWAP takes a fetch it reads
differently), its wave scale matched to our wind sea's significant height, the same wind
direction and choppiness, and its own foam on; its tile is repeated as far as a render can hold.
Both surfaces wear our water material (its ripples too), the modifier's without the shader
detail the projected grid hands over, so what differs is the sea's shape and motion.
"""

import importlib
import math
import os
import sys
import tempfile

SHOTS = {  # name: (camera height m, pitch deg)
    "low": (4.0, -4.0),
    "aerial": (300.0, -30.0),
}
STATES = {"calm": 2, "fresh breeze": 5, "gale": 8}  # name: Beaufort force


def ocean_modifier(scene, preset, material, frame_time, resolution=12, repeats=8):
    """Blender's Ocean modifier at the preset's wind on a plane of ours, under `material`."""
    import bpy

    from projgrid_addon import spectrum

    state = spectrum.SeaState(wind_speed=preset.wind_speed, fetch=preset.fetch)
    peak = spectrum.peak_wavelength(state)
    obj = bpy.data.objects.new("Ocean Modifier", bpy.data.meshes.new("Ocean Modifier"))
    scene.collection.objects.link(obj)
    mod = obj.modifiers.new("Ocean", "OCEAN")
    mod.spectrum = "PIERSON_MOSKOWITZ"
    mod.wind_velocity = preset.wind_speed
    mod.wave_direction = math.radians(90.0)  # as ours: toward the camera's view
    mod.wave_alignment = 0.5
    mod.resolution = mod.viewport_resolution = resolution
    mod.choppiness = preset.choppiness
    mod.time = frame_time
    # Its wave scale is not in metres: set so its wind sea has our significant height, measured
    # on a tile eight peak wavelengths across (its resolution keeps them).
    mod.spatial_size = max(int(8.0 * peak), 10)
    mod.wave_scale = _matched_wave_scale(obj, mod, spectrum.significant_height(state))
    # The tile, repeated `repeats` times each way (more copies its geometry past what a render
    # can hold), is made as wide as the view needs: the modifier's own trade between detail
    # and reach. It starts just behind the camera.
    span = 4000.0 if scene.camera.location.z > 50.0 else 1000.0
    mod.spatial_size = int(max(mod.spatial_size, span / repeats))
    mod.repeat_x = mod.repeat_y = int(min(max(1, math.ceil(span / mod.spatial_size)), repeats))
    mod.use_foam = True
    mod.foam_coverage = 0.0
    mod.foam_layer_name = "projgrid_foam"
    reach = mod.spatial_size * mod.repeat_x
    obj.location = (-0.5 * reach, -0.02 * reach, 0.0)
    obj.data.materials.append(material)
    # As our ocean's: the water's whole node tree in every shadow-map tile is beyond a CPU
    # render (docs/benchmarks.md, findings); the sky lights the water, not its own shadow.
    obj.visible_shadow = False
    return obj


def _matched_wave_scale(obj, mod, significant_height):
    """The modifier's wave scale giving `significant_height` (4 standard deviations of its
    heights), from two evaluations (its heights go as a power of the scale)."""
    import bpy
    import numpy as np

    def height(scale):
        mod.wave_scale = scale
        mesh = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
        z = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
        mesh.vertices.foreach_get("co", z)
        return 4.0 * float(z[2::3].std())

    chop, mod.choppiness = mod.choppiness, 0.0
    low, high = height(1.0), height(4.0)
    mod.choppiness = chop
    power = math.log(high / low) / math.log(4.0)
    return (significant_height / low) ** (1.0 / power)


def shoot(out_dir, quick=False):
    """Render each state and shot, ours and the modifier's; write the pairs side by side.
    Returns [(state, shot, path)]."""
    import bpy
    import numpy as np
    import OpenImageIO as oiio

    from tools.demo import MODULE, default_shot

    os.makedirs(out_dir, exist_ok=True)
    size, samples = ((240, 135), 4) if quick else ((480, 270), 16)
    states = dict(list(STATES.items())[1:2]) if quick else STATES
    written = []
    for state_name, force in states.items():
        for shot_name, (height, pitch) in SHOTS.items():
            images = []
            for who in ("spectrum", "noise", "modifier"):
                bpy.ops.wm.read_homefile(use_empty=True)
                scene = bpy.context.scene
                default_shot(scene, size=size, samples=samples, height=height, pitch=pitch)
                ocean = bpy.data.objects["Ocean"]
                ocean.projgrid.height_source = "PERLIN" if who == "noise" else "SPECTRUM"
                ocean.projgrid.wind_direction = math.radians(90.0)  # toward the camera's view
                bpy.ops.projgrid.sea_state(beaufort=force)
                scene.frame_set(48)
                if who == "modifier":
                    water = ocean.data.materials[0].copy()
                    group = water.node_tree.nodes["Projected Grid Water"]
                    group.inputs["Detail Height"].default_value = 0.0
                    preset = importlib.import_module(
                        f"{MODULE}.projgrid_addon.sea_states").sea_state(force)
                    # The modifier's plane crosses the water: to the hidden ocean's AUTO effects
                    # an object to refract and ring with foam, which the shots leave out.
                    for effect in ("refraction", "contact_foam", "caustics"):
                        setattr(ocean.projgrid, effect, "OFF")
                    ocean_modifier(scene, preset, water, scene.frame_current / scene.render.fps)
                    ocean.hide_render = True
                path = os.path.join(tempfile.mkdtemp(), f"{who}.png")
                scene.render.filepath = path
                bpy.ops.render.render(write_still=True)
                images.append(oiio.ImageBuf(path).get_pixels(oiio.FLOAT)[..., :3])
            gap = np.ones((size[1], 4, 3))
            pair = np.concatenate([images[0], gap, images[1], gap, images[2]], axis=1)
            name = f"compare_{state_name.replace(' ', '_')}_{shot_name}.png"
            out = os.path.join(out_dir, name)
            spec = oiio.ImageSpec(pair.shape[1], pair.shape[0], 3, oiio.UINT8)
            buf = oiio.ImageBuf(spec)
            buf.set_pixels(oiio.ROI(), np.clip(pair, 0.0, 1.0).astype(np.float32))
            buf.write(out)
            written.append((state_name, shot_name, out))
    return written


def main():
    os.environ.setdefault("BLENDER_USER_RESOURCES", tempfile.mkdtemp(prefix="projgrid-user-"))
    from tools.demo import ROOT, install
    from tools.package import build

    sys.path.insert(0, ROOT)
    install(build(tempfile.mkdtemp(prefix="projgrid-dist-")))
    out = next((a for a in sys.argv[1:] if not a.startswith("--")), os.path.join(ROOT, "out"))
    for row in shoot(out, quick="--quick" in sys.argv):
        print(*row)


if __name__ == "__main__":
    main()
