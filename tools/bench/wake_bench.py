"""What boats and their wakes cost per frame (issue 37), and its section of the report.

The default sea (Add Ocean, Beaufort 4) from the bench's camera (10 m up, looking along +Y)
with none, one and ten 10 x 3 x 1.5 m boxes floating across its view, keyed at 5 m/s, with the
wakes AUTO and OFF (the boats' poses and the effects they call for alike: the wakes' own cost
is the difference), and one at rest in view, AUTO and OFF (a scene where nothing moves pays
nothing for them): frame_set on the viewport grid (65x129), and the render grid's
frame (257x513, the ocean updated as a render updates it), interleaved, each call a new time;
and the wakes' first frame in a process (the steady wakes summed for the boats' Froude
numbers, kept after)."""

import time

import bpy

from .blender_bench import _ocean, extension, projected_scene
from .core_bench import interleaved
from .report_format import Target, _spread, _table

SPEED = 5.0  # m/s
SECONDS = 40.0  # the keys' span: frame 1 to 1 + 40 fps
VARIANTS = (("sea alone", 0, True, "AUTO"), ("one boat", 1, True, "AUTO"),
            ("one boat, wakes off", 1, True, "OFF"), ("ten boats", 10, True, "AUTO"),
            ("ten boats, wakes off", 10, True, "OFF"), ("one boat at rest", 1, False, "AUTO"),
            ("one boat at rest, wakes off", 1, False, "OFF"))


def boat_scene(count, moving, wakes):
    """The bench's sea with `count` boats floating on it, `moving` or not."""
    scene = projected_scene(65)
    ocean = _ocean(scene)
    ocean.projgrid.resolution_x, ocean.projgrid.resolution_y = 65, 129
    ocean.projgrid.render_resolution_x, ocean.projgrid.render_resolution_y = 257, 513
    ocean.projgrid.wakes = wakes
    mesh = bpy.data.meshes.new("boat")
    mesh.from_pydata([(x - 0.5, y - 0.5, z - 0.5) for x in (0, 1) for y in (0, 1)
                      for z in (0, 1)], [], [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1),
                                             (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)])
    fps = scene.render.fps
    bridge = extension().operators.bridge
    for i in range(count):
        boat = bpy.data.objects.new(f"boat {i}", mesh)
        scene.collection.objects.link(boat)
        boat.scale = (10.0, 3.0, 1.5)
        boat.location = (-SPEED * SECONDS * 0.6 * moving + 15.0 * (i % 3), 60.0 + 25.0 * i, 0.0)
        boat.keyframe_insert("location", frame=1)
        boat.location.x += SPEED * SECONDS if moving else 0.0
        boat.keyframe_insert("location", frame=1 + SECONDS * fps)
        for curve in bridge.scene.bag_curves(boat):
            for key in curve.keyframe_points:
                key.interpolation = "LINEAR"
        with bpy.context.temp_override(scene=scene, view_layer=scene.view_layers[0],
                                       active_object=boat, selected_objects=[boat]):
            assert bpy.ops.projgrid.float_selected() == {"FINISHED"}
    scene.frame_set(1 + int(0.6 * SECONDS * fps))  # the boats in view
    return scene


def wake_cost(repeats=15):
    """Rows (variant, grid, ms, p10, CPU ms, ratio to the sea alone) and the first frame's
    time with and without the boats' steady wakes summed in it."""
    core = extension().projgrid_addon
    bridge = extension().operators.bridge
    rows = []
    for render in (False, True):
        scenes = {name: boat_scene(count, moving, wakes)
                  for name, count, moving, wakes in VARIANTS}

        def frame(scene, render=render):
            if render:  # as a render updates it (no viewport frame beside)
                scene.frame_current += 1
                bridge.frame.update_ocean(_ocean(scene), scene,
                                          scene.view_layers[0].depsgraph, render=True)
            else:
                scene.frame_set(scene.frame_current + 1)
        times = interleaved({k: (lambda s=s: frame(s)) for k, s in scenes.items()}, repeats)
        alone = times["sea alone"].median
        rows += [{"variant": k, "grid": "render 257×513" if render else "viewport 65×129",
                  **t.ms(), "ratio": t.median / alone} for k, t in times.items()]
        if not render:
            for cache in (core.wakes.response, core.steady_wake.steady, core.steady_wake.hull_wake):
                cache.cache_clear()
            first = {}
            for name in ("sea alone", "one boat"):
                start = time.perf_counter()
                frame(scenes[name])
                first[name] = (time.perf_counter() - start) * 1e3
            rows.append({"variant": "one boat, its first frame (steady wakes summed)",
                         "grid": "viewport 65×129", "ms": first["one boat"],
                         "p10_ms": float("nan"), "cpu_ms": float("nan"),
                         "ratio": first["one boat"] / first["sea alone"]})
        for s in scenes.values():
            bpy.data.scenes.remove(s)
    return rows


def section(report):
    """The report's section: the table and the targets."""
    rows = report.results["wakes"]
    report.md += [
        "## Boats and wakes", "",
        "Frames of the default sea with boats floating across the view (10 × 3 × 1.5 m boxes "
        "keyed at 5 m/s: their poses and wakes), interleaved, each a new time: the viewport "
        "grid's frame_set and the render grid's update; and the first frame in a process, "
        "which sums the boats' steady wakes (kept for the frames after). The targets compare "
        "each with the wakes on against off: the boats' poses and the effects a box in view "
        "calls for (reflections, refraction) are paid alike.", "",
        _table(rows, [("variant", "variant", ""), ("grid", "grid", ""), ("ms", "ms", ".1f"),
                      *_spread(fmt=".1f"), ("× the sea alone", "ratio", ".2f")]), ""]
    by = {(r["variant"], r["grid"]): r["ms"] for r in rows}
    for grid in ("viewport 65×129", "render 257×513"):
        one, ten, still = (by[(f"{v}", grid)] / by[(f"{v}, wakes off", grid)]
                           for v in ("one boat", "ten boats", "one boat at rest"))
        why = ("each wake is read at every vertex its course's box reaches (about a quarter of "
               "a microsecond a vertex: its place along and across the course, then the steady "
               "wake at two Froude numbers, near and far), some 75,000 of the render grid's "
               "for a boat crossing the view; wake_field.read_grid reads every other row and "
               "column only where the grid is finer than a 32nd of the transverse wave, which "
               "leaves the viewport grid's read at nearly every vertex")
        report.targets += [
            Target(f"One boat's wake ≤ 1.3× the frame without it ({grid})", f"{one:.2f}×",
                   one <= 1.3, f"**One wake ({grid}).** {one:.2f}× the frame without it: "
                   + why + "."),
            Target(f"Ten boats' wakes ≤ 2× the frame without them ({grid})", f"{ten:.2f}×",
                   ten <= 2.0, f"**Ten wakes ({grid}).** {ten:.2f}× the frame without them: "
                   + why + "; and each boat's course is read from its keys (0.2 ms)."),
            Target(f"A boat at rest: the wakes cost nothing ({grid}, AUTO against OFF)",
                   f"{still:.2f}×", still <= 1.05, f"**A boat at rest ({grid}).** {still:.2f}×"),
        ]
