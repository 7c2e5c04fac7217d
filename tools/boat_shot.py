"""A boat crossing the sea (issue 37): a 10 m hull with a cabin keyed across a Beaufort 2 sea
at 6 m/s, floating 0.5 m deep, its wake and its foam, seen from a low camera (8 m up, 60 m off
its course) and an aerial one (80 m up, looking down on its wake), the sun behind the cameras
(as for the Beaufort pictures); written to docs/boat_low.png and docs/boat_aerial.png.

Alone: python -m tools.boat_shot [out_dir] [--quick] (a small, few-sample render)."""

import math
import os

SPEED = 6.0  # m/s along +X
SECONDS = 40.0  # the keys' span
AT = 26.0  # s: the shot's time (the boat 10 m right of the camera's line)
# A hull 10 m long, 3 m wide, 1.6 m deep: a pointed bow (+X), a transom stern, a narrower
# bottom; and a cabin 3.5 x 2 x 1.3 m on its deck.
HULL = ([(-5.0, -1.5, 0.8), (2.0, -1.5, 0.8), (5.0, 0.0, 0.8), (2.0, 1.5, 0.8), (-5.0, 1.5, 0.8),
         (-5.0, -1.1, -0.8), (2.0, -0.9, -0.8), (4.2, 0.0, -0.8), (2.0, 0.9, -0.8),
         (-5.0, 1.1, -0.8),
         *((x, y, z) for z in (0.8, 2.1) for x, y in ((-2.5, -1.0), (1.0, -1.0), (1.0, 1.0),
                                                       (-2.5, 1.0)))],
        [(0, 1, 2, 3, 4), (9, 8, 7, 6, 5), (0, 5, 6, 1), (1, 6, 7, 2), (2, 7, 8, 3),
         (3, 8, 9, 4), (4, 9, 5, 0),
         (10, 13, 12, 11), (14, 15, 16, 17), (10, 11, 15, 14), (11, 12, 16, 15),
         (12, 13, 17, 16), (13, 10, 14, 17)])


def boat(bpy, scene):
    """The hull, painted, keyed along +X at SPEED (linear), floating on the scene's ocean."""
    mesh = bpy.data.meshes.new("Boat")
    mesh.from_pydata(*HULL[:1], [], HULL[1])
    mesh.update()
    obj = bpy.data.objects.new("Boat", mesh)
    scene.collection.objects.link(obj)
    paint = bpy.data.materials.new("Boat Paint")
    paint.diffuse_color = (0.8, 0.12, 0.05, 1.0)
    if paint.node_tree is None:
        paint.use_nodes = True
    paint.node_tree.nodes["Principled BSDF"].inputs[0].default_value = (0.8, 0.12, 0.05, 1.0)
    mesh.materials.append(paint)
    fps = scene.render.fps
    obj.location = (-SPEED * AT + 10.0, 60.0, 0.0)
    obj.keyframe_insert("location", frame=1)
    obj.location.x += SPEED * SECONDS
    obj.keyframe_insert("location", frame=1 + SECONDS * fps)
    from tools.bench.blender_bench import extension

    for curve in extension().operators.bridge.scene.bag_curves(obj):
        for key in curve.keyframe_points:
            key.interpolation = "LINEAR"
    with bpy.context.temp_override(active_object=obj, selected_objects=[obj]):
        assert bpy.ops.projgrid.float_selected() == {"FINISHED"}
    obj.projgrid_float.sits = "DRAFT"
    obj.projgrid_float.draft = 0.5
    return obj


def shoot(out, quick=False):
    import bpy

    from tools.demo import default_shot

    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    size, samples = ((320, 180), 4) if quick else ((960, 540), 16)
    cam = default_shot(scene, size=size, samples=samples, height=8.0, pitch=-10.0)
    assert bpy.ops.projgrid.sea_state(beaufort=2) == {"FINISHED"}
    sun = next(o for o in scene.objects if o.type == "LIGHT")
    sun.rotation_euler.z += math.radians(180.0)  # behind the cameras
    hull = boat(bpy, scene)
    frame = 1 + int(AT * scene.render.fps)
    paths = []
    for view in ("low", "aerial"):
        if view == "aerial":
            from mathutils import Vector

            target = Vector((-30.0, 60.0, 0.0))
            cam.location = target + Vector((-30.0, -60.0, 80.0))
            cam.rotation_euler = (target - cam.location).to_track_quat("-Z", "Y").to_euler()
        scene.frame_set(frame)
        scene.render.filepath = os.path.join(out, f"boat_{view}.png")
        bpy.ops.render.render(write_still=True)
        paths.append(scene.render.filepath)
    return {"pictures": paths, "speed": SPEED, "hull": hull.name}


if __name__ == "__main__":
    from tools.beaufort import standalone

    print(standalone(shoot))
