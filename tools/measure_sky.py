"""Measure Blender's Sky Texture as projgrid_addon/daylight.py tabulates it: per sun elevation,
the sky's RGB irradiance on a level plane (disc off) and its sun disc's on a plane facing the
sun, at strength 1, in Cycles (which draws the disc).

    python -m tools.measure_sky [MODEL]    (MODEL: the Sky Texture's sky_type; default the
                                            version's, as Add Ocean's world uses)

prints the tables for daylight.py. tests/blender/test_sky.py measures a few elevations again.
"""

import math
import os
import sys
import tempfile

import numpy as np

PANORAMA = (256, 64)  # equirectangular pixels over the upper hemisphere
DISC_PIXELS = 64  # across a view four discs wide


class SkyMeter:
    """A scene of its own whose world is one Sky Texture, and a camera to read it with."""

    def __init__(self, model=None):
        import bpy

        from projgrid_addon import daylight

        self.scene = bpy.data.scenes.new("Sky Meter")
        self.scene.render.engine = "CYCLES"
        cycles = self.scene.cycles
        cycles.device, cycles.samples, cycles.use_denoising = "CPU", 4, False
        cycles.pixel_filter_type, cycles.filter_width = "BOX", 0.01
        settings = self.scene.render.image_settings
        settings.file_format, settings.color_depth = "OPEN_EXR", "32"
        self.scene.render.resolution_percentage = 100
        world = bpy.data.worlds.new("Sky Meter")
        self.scene.world = world
        world.use_nodes = True
        tree = world.node_tree
        self.sky = tree.nodes.new("ShaderNodeTexSky")
        self.sky.sky_type = model or (daylight.MODEL if bpy.app.version >= (5, 0, 0)
                                      else "NISHITA")
        self.sky.altitude = daylight.SKY_ALTITUDE
        background = tree.nodes["Background"]
        tree.links.new(self.sky.outputs["Color"], background.inputs["Color"])
        background.inputs["Strength"].default_value = 1.0
        self.data = bpy.data.cameras.new("Sky Meter")
        self.camera = bpy.data.objects.new("Sky Meter", self.data)
        self.scene.collection.objects.link(self.camera)
        self.scene.camera = self.camera
        self.dir = tempfile.mkdtemp(prefix="sky-meter-")

    def _render(self, width, height):
        import bpy

        r = self.scene.render
        r.resolution_x, r.resolution_y = width, height
        r.filepath = os.path.join(self.dir, "sky.exr")
        with bpy.context.temp_override(scene=self.scene):
            bpy.ops.render.render(write_still=True, scene=self.scene.name)
        image = bpy.data.images.load(r.filepath, check_existing=False)
        pixels = np.array(image.pixels[:], dtype=np.float64).reshape(height, width, 4)
        bpy.data.images.remove(image)
        return pixels[::-1, :, :3]  # top row first

    def measure(self, elevation):
        """(sky irradiance, disc irradiance) RGB with the sun `elevation` degrees up."""
        self.sky.sun_elevation, self.sky.sun_rotation = math.radians(elevation), 0.0
        self.sky.sun_disc = False
        d = self.data
        d.type, d.panorama_type = "PANO", "EQUIRECTANGULAR"
        d.latitude_min, d.latitude_max = 0.0, math.pi / 2.0
        d.longitude_min, d.longitude_max = -math.pi, math.pi
        self.camera.rotation_euler = (math.pi / 2.0, 0.0, 0.0)
        w, h = PANORAMA
        sky = self._render(w, h)
        height = (np.arange(h)[::-1] + 0.5) / h * (math.pi / 2.0)  # the top row: the zenith
        weight = np.sin(height) * np.cos(height) * (math.pi / 2.0 / h) * (2.0 * math.pi / w)
        sky_irradiance = (sky * weight[:, None, None]).sum(axis=(0, 1))
        # the disc: a view four discs wide centred on it, with the disc less without
        d.type, d.sensor_fit = "PERSP", "HORIZONTAL"
        d.angle = 4.0 * self.sky.sun_size
        e = math.radians(elevation)
        self.camera.rotation_euler = (math.pi / 2.0 + e, 0.0, 0.0)  # the sun: +Y at rotation 0
        n = DISC_PIXELS
        without = self._render(n, n)
        self.sky.sun_disc = True
        with_disc = self._render(n, n)
        pixel = (2.0 * math.tan(d.angle / 2.0) / n) ** 2
        return sky_irradiance, ((with_disc - without) * pixel).sum(axis=(0, 1))

    def close(self):
        import bpy

        world = self.scene.world
        bpy.data.scenes.remove(self.scene)
        bpy.data.worlds.remove(world)
        bpy.data.objects.remove(self.camera)
        bpy.data.cameras.remove(self.data)


def main(argv):
    import bpy  # noqa: F401  (Blender as a module)

    from projgrid_addon import daylight

    meter = SkyMeter(argv[0] if argv else None)
    rows = [meter.measure(e) for e in daylight.ELEVATIONS]
    for name, k in (("SKY", 0), ("SUN", 1)):
        print(f"{name} ({meter.sky.sky_type}) = (" + ", ".join(
            "(" + ", ".join(f"{max(v, 0.0):.4g}" for v in row[k]) + ")" for row in rows) + ")")
    meter.close()


if __name__ == "__main__":
    main(sys.argv[1:])
