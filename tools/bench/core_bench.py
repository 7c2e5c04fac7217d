"""Benchmarks of the bpy-free core: height field paths, octaves, precision, vertex efficiency and
geometric accuracy against the exact surface (per-pixel rays)."""

import time
from dataclasses import dataclass

import numpy as np

from projgrid_addon import Camera, HeightField, build_grid, grid_topology, snapped_origin
from projgrid_addon.band_limit import lod_for_spacing
from projgrid_addon.camera import perspective, view_matrix

# The fixed shots: (name, camera height, pitch, vertical fov) looking along +Y.
SHOTS = (
    ("low grazing", 2.0, -2.0, 40.0),
    ("mid height", 20.0, -15.0, 50.0),
    ("looking down", 50.0, -90.0, 60.0),
    ("telephoto horizon", 10.0, -0.5, 5.0),
)
ASPECT = 16 / 9
WAVES = {"amplitude": 0.5, "wave_scale": 40.0, "octaves": 8, "roughness": 0.5, "seed": 0}


def camera(height, pitch, fov, x=0.0, y=0.0, far=2e4):
    p = np.radians(pitch)
    forward = np.array([0.0, np.cos(p), np.sin(p)])
    right = np.array([1.0, 0.0, 0.0])
    up = np.cross(right, forward)
    view = view_matrix((x, y, height), right, up, forward)
    return Camera(view, perspective(np.radians(fov), ASPECT, 0.1, far))


def timed(fn, repeats):
    """Median seconds of `fn()` over `repeats` calls (after one warm-up)."""
    fn()
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return float(np.median(times))


@dataclass(frozen=True)
class Timing:
    """Seconds per call of one variant: the median, the 10th percentile (what the work costs
    when the shared machine leaves the process alone) and the median CPU time of the process
    (wall time lost to other processes does not count in it)."""

    median: float
    p10: float
    cpu: float

    def ms(self, per=1.0):
        """The row fields in milliseconds (per `per` units of work)."""
        return {"ms": self.median * 1e3 / per, "p10_ms": self.p10 * 1e3 / per,
                "cpu_ms": self.cpu * 1e3 / per}


def interleaved(variants, repeats):
    """A Timing per variant, measured round-robin so load changes hit all alike."""
    for fn in variants.values():
        fn()
    wall = {name: [] for name in variants}
    cpu = {name: [] for name in variants}
    for _ in range(repeats):
        for name, fn in variants.items():
            start, start_cpu = time.perf_counter(), time.process_time()
            fn()
            wall[name].append(time.perf_counter() - start)
            cpu[name].append(time.process_time() - start_cpu)
    return {name: Timing(float(np.median(wall[name])), float(np.percentile(wall[name], 10)),
                         float(np.median(cpu[name]))) for name in variants}


def height_field_paths(repeats=7):
    """Fast texture path vs exact gradient noise: time per million points and error vs bound."""
    rng = np.random.default_rng(5)
    x, y = rng.uniform(-2e3, 2e3, (2, 200_000))
    exact_hf = HeightField(method="exact", **WAVES)
    exact = exact_hf.heights(x, y, 7.0)
    rows = []
    variants = {"exact": lambda: exact_hf.heights(x, y, 7.0)}
    fields = {}
    for texels in (2, 4, 8):
        hf = HeightField(method="fast", texels=texels, **WAVES)
        fields[texels] = hf
        variants[f"fast, {texels} texels/cell"] = (lambda hf=hf: hf.heights(x, y, 7.0))
    times = interleaved(variants, repeats)
    for name, timing in times.items():
        if name == "exact":
            err = np.zeros(1)
        else:
            hf = fields[int(name.split(", ")[1].split()[0])]
            err = np.abs(hf.heights(x, y, 7.0) - exact) / exact_hf.bound
        per_million = {k.replace("ms", "ms_per_million"): v
                       for k, v in timing.ms(per=len(x) / 1e6).items()}
        rows.append({"path": name, **per_million,
                     "rms_error": float(np.sqrt(np.mean(err**2))), "max_error": float(err.max())})
    return rows


def octave_cost(resolutions=((65, 129), (257, 257)), octaves=(0, 1, 2, 4, 6, 8, 12, 16),
                repeats=9):
    """build_grid time against octave count, fast and exact paths (band limit on); 0 octaves is
    the grid alone (projector, corners, interpolation, band limit, packing)."""
    cam = camera(10.0, -8.0, 50.0)
    rows = []
    for res in resolutions:
        for method in ("fast", "exact"):
            variants = {}
            for n in octaves:
                hf = HeightField(method=method, **{**WAVES, "octaves": n})
                variants[n] = (lambda hf=hf, res=res: build_grid(cam, hf, time=3.0,
                                                                 resolution=res))
            for n, timing in interleaved(variants, repeats).items():
                rows.append({"resolution": res, "method": method, "octaves": n,
                             **timing.ms()})
    return rows


def precision(distances=(1e2, 1e3, 1e4, 1e5, 1e6)):
    """float32 vertex error (against the float64 surface) with positions stored relative to the
    world origin and relative to `snapped_origin`, the camera `d` metres from the origin."""
    hf = HeightField(**WAVES)
    rows = []
    for d in distances:
        cam = camera(10.0, -8.0, 50.0, x=d * 0.6, y=d * 0.8)
        for mode, origin in (("world origin", np.zeros(3)),
                             ("snapped origin", snapped_origin(cam, 0.0))):
            r = build_grid(cam, hf, time=3.0, resolution=(65, 129), origin=origin)
            x, y, h = r.surface
            truth = np.column_stack([x.ravel(), y.ravel(), h.ravel()])
            stored = r.positions.astype(np.float64) + r.origin
            err = np.linalg.norm(stored - truth, axis=1)
            reach = np.linalg.norm(truth - cam.position, axis=1)
            near = reach < 100.0
            rows.append({"distance": d, "origin": mode, "max_error_m": float(err.max()),
                         "near_max_error_m": float(err[near].max()) if near.any() else 0.0,
                         "relative_to_reach": float((err / reach).max())})
    return rows


def efficiency(resolution=(65, 129)):
    """Vertex efficiency per shot, and where the vertices outside the frustum are: below the
    screen's bottom edge, beside it, or beyond the far plane."""
    hf = HeightField(**WAVES)
    rows = []
    for name, height, pitch, fov in SHOTS:
        cam = camera(height, pitch, fov)
        r = build_grid(cam, hf, time=3.0, resolution=resolution)
        c = cam.clip(r.positions.astype(np.float64) + r.origin)
        ndc = c[:, :3] / c[:, 3:4]
        rows.append({"shot": name, "efficiency": r.efficiency,
                     "below": float(np.mean(ndc[:, 1] < -1.0)),
                     "beside": float(np.mean(np.abs(ndc[:, 0]) > 1.0)),
                     "beyond_far": float(np.mean(ndc[:, 2] > 1.0))})
    return rows


SEA_SHOTS = (("low, 4 m", 4.0, -4.0, 40.0), ("mid, 20 m", 20.0, -10.0, 50.0),
             ("aerial, 150 m", 150.0, -35.0, 50.0))


def sea_efficiency(forces=(4, 6, 8), frames=96, resolution=(65, 129)):
    """The spectral sea's vertex efficiency with the grid built for the volume fitted to the
    sea's spread, against its true bounds; over `frames` frames at 24 fps from a still camera, the
    share of frames whose fitted volume was kept and how often it changed (the grid then moves
    over the sea: it swims)."""
    from projgrid_addon import SpectralField, sea_state
    from projgrid_addon.displaceable_volume import Extent
    from projgrid_addon.spectrum import SeaState

    rows = []
    for force in forces:
        p = sea_state(force)
        waves = SpectralField(SeaState(wind_speed=p.wind_speed, fetch=p.fetch,
                                       swell_height=p.swell_height,
                                       swell_period=p.swell_period), choppiness=p.choppiness)
        for name, height, pitch, fov in SEA_SHOTS:
            cam = camera(height, pitch, fov)
            fitted, bounded, kept, changes, last = [], [], 0, 0, None
            for frame in range(frames):
                t = frame / 24.0
                r = build_grid(cam, waves, time=t, resolution=resolution)
                fitted.append(r.efficiency)
                kept += r.fitted
                changes += last is not None and r.extent != last
                last = r.extent
                if frame % 12 == 0:
                    full = Extent.true_bounds(waves, t)
                    bounded.append(build_grid(cam, waves, time=t, resolution=resolution,
                                              extent=full).efficiency)
            rows.append({"force": force, "shot": name,
                         "fitted": float(np.median(fitted)), "fitted_min": float(min(fitted)),
                         "bounded": float(np.median(bounded)), "kept": kept / frames,
                         "changes": changes / (frames - 1)})
    return rows


# --- geometric accuracy: per-pixel rays against the mesh and against the exact surface -------

def pixel_rays(cam, size):
    w, h = size
    xs = (np.arange(w) + 0.5) / w * 2 - 1
    ys = (np.arange(h) + 0.5) / h * 2 - 1
    gx, gy = np.meshgrid(xs, ys)
    near, far = cam.rays(np.column_stack([gx.ravel(), gy.ravel()]))
    d = far - near
    return near, d / np.linalg.norm(d, axis=1, keepdims=True), np.linalg.norm(far - near, axis=1)


def march_exact(hf, origins, dirs, reach, t_time, steps=300, refine=25):
    """Where each ray first meets the exact (all octaves) surface: log-spaced march, then
    bisection. NaN where it does not within its reach."""
    ts = np.geomspace(0.1, 1.0, steps)[None, :] * reach[:, None]
    hit_t = np.full(len(origins), np.nan)
    lo = np.zeros(len(origins))
    prev = np.ones(len(origins), dtype=bool)  # above the surface at t = 0 (camera above)
    for k in range(steps):
        todo = np.isnan(hit_t)
        if not todo.any():
            break
        t = ts[todo, k]
        p = origins[todo] + dirs[todo] * t[:, None]
        above = p[:, 2] > hf.heights(p[:, 0], p[:, 1], t_time)
        crossed = prev[todo] & ~above
        idx = np.flatnonzero(todo)
        hi_t = t
        sel = idx[crossed]
        if sel.size:
            a, b = lo[sel], hi_t[crossed]
            for _ in range(refine):
                m = 0.5 * (a + b)
                q = origins[sel] + dirs[sel] * m[:, None]
                up = q[:, 2] > hf.heights(q[:, 0], q[:, 1], t_time)
                a, b = np.where(up, m, a), np.where(up, b, m)
            hit_t[sel] = 0.5 * (a + b)
        lo[idx] = hi_t
        prev[idx] = above
    return hit_t


def ray_mesh(origins, dirs, positions, quads):
    """First hit distance of each ray with the quad mesh (two triangles per quad), NaN if none:
    mathutils' BVH tree (Blender's own C code)."""
    from mathutils import Vector
    from mathutils.bvhtree import BVHTree

    tris = np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    tree = BVHTree.FromPolygons(positions.tolist(), tris.tolist(), all_triangles=True)
    out = np.full(len(origins), np.nan)
    for i, (o, d) in enumerate(zip(origins, dirs, strict=True)):
        hit = tree.ray_cast(Vector(o), Vector(d))
        if hit[0] is not None:
            out[i] = hit[3]
    return out


FRAME = (1920, 1080)  # screen errors are given in pixels of a full-HD frame


def screen_error(cam, points, hf, t_time):
    """Pixels (of a FRAME-sized image) between each mesh point and the exact surface point at the
    same (x, y), and the vertical error in metres."""
    true = points.copy()
    true[:, 2] = hf.heights(points[:, 0], points[:, 1], t_time)
    px = []
    for p in (points, true):
        c = cam.clip(p)
        ndc = c[:, :2] / c[:, 3:4]
        px.append(ndc * (np.array(FRAME) / 2.0))
    return np.linalg.norm(px[0] - px[1], axis=1), np.abs(points[:, 2] - true[:, 2])


def visible_extent(cam, hf):
    """(x0, x1, y0, y1): the area of the water the camera sees (the projected grid's)."""
    x, y = build_grid(cam, hf, resolution=(65, 129)).surface[:2]
    return x.min(), x.max(), y.min(), y.max()


def world_grid_points(n, extent, wave_scale):
    """x, y of an n x n world-space grid over `extent` = (x0, x1, y0, y1), and its band limit
    (one level of detail from its spacing, band_limit.lod_for_spacing)."""
    x0, x1, y0, y1 = extent
    x, y = np.meshgrid(np.linspace(x0, x1, n), np.linspace(y0, y1, n))
    spacing = max((x1 - x0), (y1 - y0)) / (n - 1)
    return x, y, np.full(x.shape, lod_for_spacing(wave_scale, spacing))


def world_grid(n, hf, t_time, extent):
    """An n x n displaced world-space grid: (positions, quads)."""
    x, y, lod = world_grid_points(n, extent, hf.wave_scale)
    h = hf.heights(x, y, t_time, lod)
    return np.column_stack([x.ravel(), y.ravel(), h.ravel()]), grid_topology(n, n)


def candidate_meshes(cam, hf, t_time, n, extent, tile):
    """{kind: (build, mesh_of)}: how to rebuild each mesh, and its (positions, quads)."""
    res = (n, n)
    return {
        "projected grid": (lambda: build_grid(cam, hf, time=t_time, resolution=res),
                           lambda r: (r.positions.astype(np.float64) + r.origin,
                                      grid_topology(n, n))),
        "world grid": (lambda: world_grid(n, hf, t_time, extent), lambda r: r),
        "fixed tile": (lambda: world_grid(n, hf, t_time,
                                          (-tile / 2, tile / 2, -tile / 2, tile / 2)),
                       lambda r: r),
    }


def accuracy(sizes=(33, 65, 129, 257), world_sizes=(33, 65, 129, 257, 513), image=(96, 54),
             tile=1000.0, repeats=5):
    """Screen-space error against the exact surface for the projected grid, a world grid over the
    visible area, and a fixed tile centred on the world origin (like the Ocean modifier's), at
    several vertex counts (the world grids up to larger ones, so their rebuild times reach the
    projected grid's and errors can be compared at equal time), with each one's rebuild time."""
    hf = HeightField(**WAVES)
    exact = HeightField(method="exact", **WAVES)
    t_time = 3.0
    rows = []
    for name, height, pitch, fov in SHOTS:
        cam = camera(height, pitch, fov)
        origins, dirs, reach = pixel_rays(cam, image)
        t_true = march_exact(exact, origins, dirs, reach, t_time)
        extent = visible_extent(cam, hf)
        for n in sorted(set(sizes) | set(world_sizes)):
            meshes = {k: v for k, v in candidate_meshes(cam, hf, t_time, n, extent, tile).items()
                      if n in (sizes if k == "projected grid" else world_sizes)}
            times = interleaved({k: v[0] for k, v in meshes.items()}, repeats)
            for kind, (build, mesh_of) in meshes.items():
                positions, quads = mesh_of(build())
                t_mesh = ray_mesh(origins, dirs, positions, quads)
                both = ~np.isnan(t_mesh) & ~np.isnan(t_true)
                pts = origins[both] + dirs[both] * t_mesh[both, None]
                px, vertical = screen_error(cam, pts, exact, t_time)
                coverage_miss = float(np.mean(np.isnan(t_mesh) & ~np.isnan(t_true)))
                rows.append({"shot": name, "mesh": kind, "n": n, **times[kind].ms(),
                             "px_mean": float(px.mean()) if px.size else float("nan"),
                             "px_p95": float(np.percentile(px, 95)) if px.size else float("nan"),
                             "m_mean": float(vertical.mean()) if px.size else float("nan"),
                             "along_ray_m": float(np.mean(np.abs(t_mesh[both] - t_true[both])))
                             if px.size else float("nan"),
                             "missed": coverage_miss})
    return rows
