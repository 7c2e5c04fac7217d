"""The benchmark report's sections on rendering and the scene: EEVEE's render cost and the
filtering's flicker, the effects, the scene's updates, the side-by-side pictures and memory."""

from .report_format import Target, _finish, _maybe, _save, _spread, _table

# §6 without the filtering from geometry to BRDF: seconds per render of the water group and of a
# plain glossy plane at 16 samples, the same shot, stored from one earlier run on another
# machine (an Intel Xeon): the bench renders no unfiltered water. The filtering's cost is judged
# by the water group's time over the plain glossy's, which each run measures side by side.
BEFORE_FILTERING = {"water group": 13.17, "plain glossy": 9.21}


def _render(report):
    """§6: EEVEE render cost against error, and the filtering's flicker and cost."""
    results, docs, plt, md = report.results, report.docs, report.plt, report.md
    rr = results["render"]
    fig, ax = plt.subplots(figsize=(6, 4))
    for mat in ("water group", "plain glossy"):
        pts = [(r["seconds"], r["rms_error"]) for r in rr if r["material"] == mat]
        ax.plot(*zip(*pts, strict=True), "o-", label=mat)
        for r in rr:
            if r["material"] == mat:
                ax.annotate(str(r["samples"]), (r["seconds"], r["rms_error"]), fontsize=7)
    ax.set_xscale("log")
    _finish(ax, "render seconds (EEVEE, 320×180, CPU)", "rms error vs reference",
            legend_size="medium")
    render_png = _save(fig, docs, "bench_render")
    md += ["## 6. Render cost (EEVEE on this CPU, llvmpipe)", "",
           "The default shot at 320×180; error is the rms difference (display values) from a "
           "high-sample render of the same material; shader compilation is excluded. Up to 16 "
           "samples the two materials render in turn three times: the median wall time, its "
           "10th percentile and the median CPU time.", "",
           render_png, "",
           _table(rr, [("material", "material", ""), ("samples", "samples", ""),
                       ("seconds", "seconds", ".2f"), ("p10", _maybe("p10", ".2f"), ""),
                       ("CPU", _maybe("cpu", ".2f"), ""),
                       ("rms error", "rms_error", ".4f")]), ""]
    at16 = {r["material"]: r["seconds"] for r in rr if r["samples"] == 16}
    if len(at16) == 2:
        now = at16["water group"] / at16["plain glossy"]
        before = BEFORE_FILTERING["water group"] / BEFORE_FILTERING["plain glossy"]
        report.targets.append(Target(
            "Filtered water render ≤ 1.1× the unfiltered (16 samples, over a plain glossy)",
            f"{now / before:.3f}×", now / before <= 1.1,
            "**Filtering's render cost.** The per-pixel roughness, mean Fresnel and the bumps' "
            f"fades take the water group to {now:.2f}× a plain glossy plane's render time, "
            f"against {before:.2f}× for the water without them (BEFORE_FILTERING: a ratio "
            "stored from one run on another machine, not re-measured)."))
        err16 = {r["material"]: r["rms_error"] for r in rr if r["samples"] == 16}
        md += [f"The water group renders in {now:.2f}× a plain glossy plane's time at 16 "
               "samples; without the filtering from geometry to BRDF the ratio is "
               f"{before:.2f}× (stored from one earlier run on another machine, not "
               "re-measured). Its error at few samples is mostly the sun glint's facets "
               "(water_model.facet_variance), sparkles EEVEE's samples find: the glitter path "
               "converges more slowly than a smooth sheen would (at 16 samples "
               f"{err16['water group']:.4f} against the plain glossy's "
               f"{err16['plain glossy']:.4f}).", ""]
    fl = results.get("flicker")
    if fl:
        md += ["### Filtering: flicker toward the horizon", "",
               "A camera moving 0.5 m a frame over a still sea, 320×180 at 4 samples: the "
               "mean change of each pixel's linear luminance from frame to frame in the far "
               "field (the horizon to 10° below it), and the mean of its second difference over "
               "three frames (a steady motion's change, the waves sliding across the screen as "
               "the camera moves, cancels there; flicker does not), with the filtering (waves "
               "shorter than a pixel's footprint, its major axis, as the GGX lobe's "
               "roughness, Bruneton's mean Fresnel) "
               "and without it "
               "(every wave drawn as normals on a mirror, the ripples carrying Cox and Munk's "
               "slopes: the same sea); the near field's contrast (below "
               "that band: the spread of 4-pixel squares across each row); the far field's mean "
               "luminance. \"Converged\" is the first frame without the filtering at 64 "
               "samples: what the pixels average to with every wave drawn as normals (at 4 "
               "samples part of the unfiltered contrast is aliasing). It is no ground truth: "
               "Blender's bump takes a wave's slope across a pixel, so waves shorter than a "
               "pixel add almost no slope there, and the mirror lacks the roughness Cox and "
               "Munk measured (most of it in waves of centimetres); it also counts facets "
               "turned away from the camera that a real sea hides. \"Supersampled\" is the "
               "filtered frames rendered with 8 × 8 times the pixels (one sample each) and "
               "averaged down: the same sea with waves down to an eighth of a pixel drawn as "
               "normals and only those below as roughness, the contrast the filtering should "
               "keep and the change from frame to frame that is the picture's own (the waves "
               "and the glitter on them moving across the screen), not flicker.", "",
               _table(fl, [("shot", "shot", ""), ("", "variant", ""),
                           ("far-field change", _maybe("flicker", ".4f"), ""),
                           ("its second difference", _maybe("flicker_2", ".4f"), ""),
                           ("near-field contrast", "near_contrast", ".4f"),
                           ("far-field luminance", "far_luminance", ".3f")]), "",
               "Without the filtering (left) and with it (right), each shot's first frame:", "",
               *(f"![{r['shot']}: unfiltered, filtered]({r['picture']})" for r in fl
                 if r["variant"] == "filtered" and "picture" in r), ""]
        for shot in dict.fromkeys(r["shot"] for r in fl):
            by = {r["variant"]: r for r in fl if r["shot"] == shot}
            gain = by["unfiltered"]["flicker"] / max(by["filtered"]["flicker"], 1e-9)
            own = ""
            if "flicker" in by.get("supersampled", {}):
                truth = max(by["supersampled"]["flicker"], 1e-9)
                own = (" The supersampled picture, waves drawn down to an eighth of a pixel, "
                       f"itself changes {truth:.4f} from frame to frame "
                       f"({by['unfiltered']['flicker'] / truth:.1f}× less than unfiltered), "
                       f"the filtered {by['filtered']['flicker'] / truth:.2f}× that")
                own += (": a 3× cut would take away motion the picture has."
                        if by["unfiltered"]["flicker"] < 3.0 * truth else ".")
            report.targets.append(Target(
                f"Far-field frame-to-frame change filtered ≥ 3× less ({shot})",
                f"{gain:.2f}× less", gain >= 3.0,
                f"**Far-field change, {shot}.** Filtering cuts the far field's frame-to-frame "
                f"change {gain:.2f}×: much of what is left is the resolved waves' own motion "
                "across the screen as the camera moves (and toward the sun the glitter path on "
                "them), which no filtering removes and the second difference cancels." + own))
            truth = by.get("supersampled", by.get("converged", by["unfiltered"]))
            kept = by["filtered"]["near_contrast"] / max(truth["near_contrast"], 1e-9)
            against = {"supersampled": "the supersampled picture's (8 × 8 times the pixels)",
                       "converged": "the converged picture's (every wave drawn, 64 samples)",
                       }.get(truth["variant"], "the unfiltered picture's at equal samples")
            mirror = by.get("converged")
            if mirror is not None and truth is not mirror:
                share = by["filtered"]["near_contrast"] / max(mirror["near_contrast"], 1e-9)
                mirrored = (f"It has {share:.0%} of the 64-sample mirror's contrast, but that "
                            "mirror")
            else:
                mirrored = "The 64-sample mirror is no ground truth: it"
            report.targets.append(Target(
                f"Near-field contrast kept by the filtering ({shot})", f"{kept:.2f}×",
                kept >= 0.9,
                f"**Near-field contrast, {shot}.** Filtered, the water below the far band has "
                f"{kept:.0%} of {against} contrast. {mirrored} has no roughness for the waves "
                "shorter than a pixel (Blender's bump takes slopes across a pixel, however "
                "many pixels), so Cox and Munk's slopes, which the filtered sea carries, are "
                "missing there. Against the supersampled "
                "picture the rest lies in how waves between an eighth of a pixel and the "
                "footprint shade as roughness rather than as normals (Bruneton's mean Fresnel "
                "is a fit)."))
            if "flicker_2" in by["filtered"]:
                gain2 = by["unfiltered"]["flicker_2"] / max(by["filtered"]["flicker_2"], 1e-9)
                report.targets.append(Target(
                    f"Far-field flicker (second difference) filtered ≥ 3× less ({shot})",
                    f"{gain2:.2f}× less", gain2 >= 3.0,
                    f"**Flicker, {shot}.** Filtering cuts the far field's second difference "
                    f"only {gain2:.2f}×."))


def _effects(report):
    """§7: what each effect costs."""
    results, md, targets = report.results, report.md, report.targets
    fx = results["effects"]
    ms = {r["variant"]: r["ms"] for r in fx}
    rows = [{**r, "ratio": r["ms"] / ms["everything off"],
             "active": ", ".join(r["active"]) or "none"} for r in fx]
    renders = {r["variant"]: r["seconds"] for r in results.get("effect_render", [])}
    for r in rows:
        r["render"] = renders.get(r["variant"], float("nan"))
        r["render_ratio"] = r["render"] / renders.get("everything off", float("nan"))
    md += ["## 7. Effects: what each costs", "",
           "The same 257² ocean, a light breeze (2.5 m/s: no whitecaps called for), per frame "
           "(frame_set, interleaved) with every effect off, at "
           "AUTO (the bare ocean: nothing called for, with or without a sun; the sun's glint "
           "is the water's own reflection), and with each effect forced on alone; "
           "and the default shot's EEVEE render time (320×180, 4 samples, each variant's "
           "shader compiled first; the two no-sun variants, which share a shader, rendered "
           "alternately). The default shot has no other objects, so contact foam and "
           "caustics forced on have nothing to ring or to focus for, and local reflections "
           "forced on capture only the sky.", "",
           _table(rows, [("variant", "variant", ""), ("active effects", "active", ""),
                         ("rebuild ms", "ms", ".2f"), *_spread(),
                         ("× all off", "ratio", ".3f"),
                         ("render s", "render", ".2f"),
                         ("render × all off", "render_ratio", ".3f")]), ""]
    bare = ms["bare ocean, auto"] / ms["everything off"]
    targets.append(Target(
        "Bare ocean at AUTO ≤ 1.02 × everything off (rebuild)", f"{bare:.3f} ×",
        bare <= 1.02,
        "**Bare ocean at AUTO.** Deciding the effects costs more than the 2 % margin: "
        "see which effects the bare ocean still has active in the table above."))
    if renders.get("bare ocean, auto, no sun") and renders.get("everything off, no sun"):
        bare = renders["bare ocean, auto, no sun"] / renders["everything off, no sun"]
        targets.append(Target(
            "Bare ocean at AUTO ≤ 1.02 × everything off, both without a sun (render)",
            f"{bare:.3f} ×", bare <= 1.02,
            "**Bare ocean render.** Without a sun AUTO calls for no effect, so the two "
            "renders share one shader: a difference beyond 2 % is the machine's noise "
            "(they are rendered alternately) or an effect left on."))


def _scene_update(report):
    """§8: viewport updates in scenes with many objects."""
    results, md, targets = report.results, report.md, report.targets
    updates = results["scene_update"]
    md += ["## 8. Viewport updates in scenes with many objects", "",
           "A depsgraph update (65×129 grid, effects at AUTO) in scenes of small objects "
           "scattered around the ocean, the whole update with our handler and without it, "
           "interleaved, and the time spent inside our handler (our own share): after a "
           "camera nudge (the ocean follows: every object's box is tested against the new "
           "view, and Blender then evaluates the rewritten mesh, which in a big scene costs "
           "it more than the camera itself), and after a move of one object behind the "
           "camera (unrelated to the ocean: only that object's box is read again and "
           "nothing is rebuilt or written).", "",
           _table(updates, [("objects", "objects", ",d"),
                            ("camera: update ms", "ours_ms", ".1f"),
                            *_spread("ours_", fmt=".1f"),
                            ("without us ms", "without_ms", ".1f"),
                            ("in our handler ms", "handler_ms", ".2f"),
                            ("unrelated: update ms", "unrelated_ours_ms", ".1f"),
                            *_spread("unrelated_ours_", fmt=".1f"),
                            ("without us ms", "unrelated_without_ms", ".1f"),
                            ("in our handler ms", "unrelated_handler_ms", ".2f")]), ""]
    big = max(updates, key=lambda r: r["objects"])
    if "unrelated_handler_ms" in big:
        targets.append(Target(
            f"Our share of an unrelated viewport update with {big['objects']:,} objects "
            "≤ 2 ms", f"{big['unrelated_handler_ms']:.2f} ms",
            big["unrelated_handler_ms"] <= 2.0,
            "**Unrelated updates.** Our handler still walks objects the update did not "
            "touch (SceneCache should keep them)."))


def _moving_objects(report):
    """§8 continued: frames among many moving objects."""
    results, md, targets = report.results, report.md, report.targets
    rows = results["moving_objects"]
    for row in rows:
        row["share_ms"] = row["with_ms"] - row["without_ms"]
        row["write_ms"] = row["plain_ms"] - row["without_ms"]
    md += ["Frames (frame_set, frame after frame) among keyframed cubes moving through the water "
           "in view (65×129 grid, effects at AUTO but the whitecaps off: their calibrations, "
           "made ahead on a worker thread, would overlap Blender's own work and blur the "
           "difference), interleaved: with our handlers, without them (the ocean's share of a "
           "frame is the difference), and without them but with a handler writing a plain mesh "
           "of the grid's size each frame (what Blender charges for any mesh written from "
           "frame_change_post among those objects); and the time inside our frame handler.", "",
           _table(rows, [("objects", "objects", ",d"), ("with the ocean ms", "with_ms", ".1f"),
                         *_spread("with_", fmt=".1f"),
                         ("without ms", "without_ms", ".1f"),
                         *_spread("without_", fmt=".1f"),
                         ("a plain mesh write ms", "plain_ms", ".1f"),
                         ("the ocean's share ms", "share_ms", ".1f"),
                         ("of it, our handler ms", "handler_ms", ".1f"),
                         ("any mesh write's cost ms", "write_ms", ".1f")]), ""]
    none = min(rows, key=lambda r: r["objects"])
    most = max(rows, key=lambda r: r["objects"])
    if most["objects"] > none["objects"] and none["share_ms"] > 0.0:
        ratio = most["share_ms"] / none["share_ms"]
        ours = most["handler_ms"] / none["handler_ms"]
        targets.append(Target(
            f"The ocean's share of a frame with {most['objects']:,} moving objects ≤ 1.3× its "
            "share with none", f"{ratio:.2f}×", ratio <= 1.3,
            "**Moving objects.** The boxes are read at once and the contact foam bins the "
            f"grid's points, so our handler itself grows {ours:.2f}× with the objects "
            f"({none['handler_ms']:.1f} → {most['handler_ms']:.1f} ms). What grows is "
            "Blender's: a mesh written from a frame handler (ours, or the plain one of the "
            f"grid's size) among {most['objects']:,} moving objects costs "
            f"{most['write_ms']:.1f} ms more than no write (with none "
            f"{none['write_ms']:.1f} ms). Profiled (perf), that time is the depsgraph's "
            "visibility flush and scheduling over all its operations "
            "(deg_graph_flush_visibility_flags, schedule_node), which any user edit of "
            "geometry brings about, growing faster than the object count. An ocean that writes "
            "its mesh from a handler cannot reach the target until the depsgraph does less for "
            "such an edit."))


def _pictures(report):
    """§11: side-by-side shots with the Ocean modifier."""
    results, md = report.results, report.md
    shots = results["pictures"]
    md += ["## 11. Side by side with Blender's Ocean modifier", "",
           "The same camera, sky, sun and water material (EEVEE, 16 samples), frame 48, "
           "the wind blowing toward the view: left our spectral sea, middle our noise, "
           "right the Ocean modifier (Pierson-Moskowitz at the same wind, its wave scale "
           "matched to our wind sea's significant height, the same choppiness, its foam; "
           "its tile repeated as far as a render holds). `tools/compare.py`.", ""]
    for r in shots:
        md += [f"**{r['state']}, {r['shot']} camera**", "",
               f"![{r['state']}, {r['shot']}: spectrum, noise, Ocean modifier]({r['path']})",
               ""]


def _beaufort(report):
    """§12: every force as the picture shows it, and the share of the sea its whitecaps cover
    against Monahan's."""
    down = {-90.0: ", straight down"}
    rows = [{**r, "view": f"{r['height']:.0f} m{down.get(r.get('pitch'), '')}"}
            for r in report.results["beaufort"]]
    for r in rows:
        r["ratio"] = r["whitecaps_area"] / r["monahan"] if r["monahan"] > 0 else 0.0
        r["looks"] = r["whitecaps"] / r["monahan"] if r["monahan"] > 0 else 0.0
    table = _table(rows, [("force", "force", "d"), ("camera", "view", ""),
                          ("foam's area", "area", ".2%"),
                          ("whitecaps' area", "whitecaps_area", ".2%"),
                          ("Monahan", "monahan", ".2%"),
                          ("whitecaps' area / Monahan", "ratio", ".2f"),
                          ("looks white", "white", ".2%"),
                          ("whitecaps look white", "whitecaps", ".2%"),
                          ("whitecaps look white / Monahan", "looks", ".2f"),
                          ("blown streaks' share", "blown", ".2%")])
    pictures = [f"![Beaufort {r['force']} from {r['view']}]({r['path']})" for r in rows]
    views = max(len(r["frames"]) for r in rows)
    if foamed := [r["ratio"] for r in rows if r["force"] >= 4]:
        low, high = min(foamed), max(foamed)
        report.targets.append(Target(
            "Rendered whitecaps' share of the sea 0.5-2× Monahan's, forces 4-10, from 5 m "
            "and 40 m and straight down", f"{low:.2f}-{high:.2f}×", 0.5 <= low and high <= 2.0,
            "**Whitecaps' share.** A view holds few breakers, and the foam is placed on the "
            f"breaking crests: the mean of {views} views still swings with a cluster of them "
            "near the camera (each view's share is in benchmarks.json)."))
    report.md += [
        "## 12. The Beaufort forces: the white share in the picture", "",
        "Each force's preset from 5 m (4° down), 40 m (12° down) and straight down from 300 m (a "
        "view some 310 m across: a smaller one holds too few of the streaks), the picture frame 48,"
        f" the shares the mean of {views} views, 2 s apart, the camera moved 700 m across the"
        " view each time, the wind blowing away 30° right of it, the sun low behind the camera's"
        " left (out of the glitter, which hides whitecaps; EEVEE, 16 samples, the shares' 4:"
        " they read the same; `tools/beaufort.py`). A pixel's foam cover is how far it goes from "
        "the picture with the foam muted toward the one with foam everywhere. In linear light (the "
        "render's values before the view transform) that is the share of the pixel's area the foam "
        "covers, and its mean over the sea's pixels the share of the sea the picture shows covered "
        "(*area*), which is what Monahan and O'Muircheartaigh's 1.59e-5 U^2.55 measures, of the "
        "whitecaps and their foam: *whitecaps' area* is that of a render without the wind's blown "
        "streaks (from Beaufort 7: none up to 13.9 m/s, the sea white at 40 m/s; *blown streaks' "
        "share*, `streaks.blown_coverage`). In display values partial cover reads larger (a pixel a"
        " tenth covered reads as about a fifth): *looks white* is the share of the sea's pixels "
        "over half covered there, as the eye reads the picture.", "", table, "", *pictures, ""]


def _memory(report):
    """§9: memory per vertex."""
    results, md = report.results, report.md
    mem = results["memory"]
    md += ["## 9. Memory per vertex", "",
           "Bytes per vertex of a render-grid rebuild, each size in a fresh Blender process: "
           "the core's peak (its arrays and its passes' buffers, which run "
           "`scratch.CHUNK` vertices at a time; NumPy's allocations through tracemalloc), "
           "and the process's peak resident growth (Linux VmHWM, reset before each step) "
           "for a rebuild that builds the mesh's topology (the first frame at a new "
           "resolution) and for one that reuses it, with what stays resident after each "
           "(the mesh itself: positions, corners, edges, UVs, attributes). The memory "
           "check (`memory.py`) refuses a grid whose measured need exceeds the memory the "
           "system has free, before anything is allocated.", "",
           _table(mem, [("grid", "resolution", ""), ("vertices", "vertices", ",d"),
                        ("core peak", "core", ".0f"),
                        ("new topology: peak", "topology", ".0f"),
                        ("held after", "topology_held", ".0f"),
                        ("same topology: peak", "rebuild", ".0f"),
                        ("held after", "rebuild_held", ".0f")]), ""]


def _storm(report):
    """§13: what the storm's work costs, against the sea before it (tools/bench/storm_bench.py)."""
    storm = report.results["storm"]
    for r in storm["ratios"]:
        if r["what"] == "this tree / baseline" and r["variant"].startswith("frame 257"):
            camera = r["variant"].split("camera ")[-1]
            report.targets.append(Target(
                f"A gale's frame (257², camera {camera}) ≤ 1.3× the sea's before the storm",
                f"{r['ratio']:.2f}×", r["ratio"] <= 1.3,
                f"**A gale's frame, camera {camera}.** The grid's columns and rows follow the "
                "screen (waves to the horizon), so more vertices are near and detailed, each "
                "with more bands to sample (the main bands' halves, their foam calibrated at "
                "ten more levels); the spray adds its puffs (with / without below); the residual "
                "foam's past samples are kept " + (
                    "on canonical cameras' grids (past_grid.py; the camera dollies 2 m a frame "
                    "along its heading), made anew at each 8 m step of their lattice."
                    if camera == "moving" else "on its grid: a frame makes the newest.")))
        if r["what"] == "with stage B / without":
            report.targets.append(Target(
                "A gale rendered with its residual foam (stage B) ≤ 1.1× without it",
                f"{r['ratio']:.2f}×", r["ratio"] <= 1.1,
                "**Stage B's render.** Its past samples' foam cues at the frame's points, and "
                "two more noises in the water group."))
    report.md += [
        "## 13. The storm's cost: a gale against the sea before it", "",
        f"Beaufort 8 from 5 m up (4° down), this tree beside commit {storm['baseline']} (the "
        "last before the storm's work: whitecaps alone, no residual foam or streaks, the grid "
        "spread evenly over the projector's span), each in a Blender process of its own, the "
        "two alternated. Per frame: frame_set on a 257² grid, each frame a time of its own, "
        "the camera still and dollying 2 m a frame, the foam's calibrations made in the frame "
        "(no worker beside it). Rendered: a frame as a farm renders it, alone (a time no "
        "earlier frame made: its sea, foam calibrations and residual past made in it), EEVEE "
        "960×540, 16 samples, after a render compiled the shaders; this tree's alternately "
        "with and without its residual foam (stage B: the per-vertex residual not made, the "
        "water group's residual and streak noises left out), and without its spray (spray.py; "
        "per frame too). `tools/bench/storm_bench.py`.", "",
        _table(storm["rows"], [("variant", "variant", ""), ("tree", "tree", ""),
                               ("ms", "ms", ".1f"), ("p10 ms", "p10", ".1f"),
                               ("CPU ms", "cpu", ".1f"), ("n", "n", "d")]), "",
        _table(storm["ratios"], [("variant", "variant", ""), ("ratio", "what", ""),
                                 ("median", "ratio", ".2f"), ("p10", "ratio_p10", ".2f")]), ""]


def _strip(report):
    """A storm building over a shot (tools/storm_strip.py), after section 12's forces."""
    strip = report.results["strip"]
    steps = ", ".join(f"{r['time']:g} s: {r['wind']:.1f} m/s (force {r['force']})"
                      for r in strip["rows"])
    report.md += [
        "### A storm building", "",
        "The wind keyed from Beaufort 3 to 9 over ten seconds (force 9's fetch and choppiness), "
        "blowing toward the camera from 30° left of its view, the sun behind the camera, the "
        f"sky keyed at each shot to the wind's cloud, from 20 m up (8° down), left to right in "
        f"time: {steps}. `tools/storm_strip.py`.", "",
        f"![A storm building, Beaufort 3 to 9 in ten seconds]({strip['path']})", ""]
