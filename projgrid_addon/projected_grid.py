"""The projected grid algorithm (thesis §2.4) and its per-vertex stage (§3.1.1).

`build_grid` runs the steps in order:
  1. camera                                   -> Camera (camera.py)
  2. V_visible = V_cam ∩ V_displaceable        -> visible_volume_points; none: not visible, stop
     (steps 2 to 6: grid_points.py)
  3. aim the projector                        -> projector.aim_projector (§2.4.1, §2.5)
  4. range matrix from V_visible              -> Projector.with_range (§2.4.2)
  5. grid over [0, 1]^2, columns and rows     -> Projector.spacing, grid_uv / grid_topology
  6. corners on S_base, interpolate the rest   -> Projector.corner_points (App. A), bilinear, /w
  7. displace by f_HF, band-limited           -> HeightField.heights (§1.6, §3.2)
  then normals from the grid neighbours (§3.1.1 step 4) and vertex efficiency (§4.1).
"""

from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np

from .camera import Camera
from .displaceable_volume import Extent, fitted_extents
from .grid_points import grid_points
from .projector import Projector, aim_projector
from .validation import finite, integer, non_negative

MAX_VERTICES = 2**25


@dataclass
class GridResult:
    """One rebuild. Vertex arrays are row-major: index = row * resolution_x + column.

    `uv`, `normals` and `efficiency` are computed on first use: the mesh's UVs are written only
    with its topology, Blender derives its own normals from the faces, and the efficiency is a
    statistic, so a frame pays for none of them.
    """

    positions: np.ndarray  # (N, 3) float32, world space
    surface: tuple  # (x, y, height above level) float64 (ny, nx) arrays, for the normals
    lod: np.ndarray  # (N,) float32, band limit per vertex (band_limit.py)
    visible: bool
    shader_octaves: tuple  # (first, count): octaves the geometry left out, in part or whole
    projector: Projector | None
    resolution: tuple
    origin: np.ndarray  # (3,) float64: world position = origin + positions
    camera: Camera | None = None
    base: np.ndarray | None = None  # (2, ny, nx) float64 grid points on S_base, when displaced
    # sideways (choppy); `surface` then holds the displaced points
    extent: Extent | None = None  # the displaceable volume the grid was built for
    # ((nx,), (ny,)) float64: each column's u and each row's v in the span (Projector.spacing)
    spacing: tuple | None = None
    # (cap, (2, ny, nx) float32): the source's crest sum at band limit `cap` (build_grid's
    # `crest`: the sideways displacement of the waves it keeps), or None
    crest: tuple | None = None
    # (level, projector elevation, aim, wave scale or None): what else the grid's points are a
    # function of (grid_points.grid_points), for another camera's grid (past_grid.py)
    settings: tuple | None = None

    @property
    def fitted(self):
        """Whether the grid was built for a volume fitted to the sea's spread."""
        return self.extent is not None and self.extent.fitted

    @cached_property
    def drift(self):
        """(N, 3) float32: how far the choppy waves moved each vertex sideways from its grid
        point (0 up), where the water it carries came from; None without choppiness."""
        if self.base is None or not self.visible:
            return None
        out = np.zeros((self.base[0].size, 3), np.float32)
        for k in (0, 1):
            np.subtract(self.surface[k], self.base[k], out=out[:, k].reshape(self.base[k].shape),
                        casting="same_kind")
        return out

    @cached_property
    def uv(self):
        """(N, 2) float32 projector-space grid coordinates (§2.4 step 5)."""
        if not self.visible:
            return np.zeros((0, 2), np.float32)
        return grid_uv(*self.resolution)

    def without_surface(self):
        """This result without its float64 surface and base points (24 to 40 bytes a vertex):
        what is kept after the frame for the statistics (the mesh holds the positions)."""
        return replace(self, surface=(), base=None)

    @cached_property
    def efficiency(self):
        """Share of vertices inside the camera frustum (§4.1), computed on first use."""
        if not self.visible:
            return 0.0
        return float(self.camera.in_frustum(self.positions, self.origin).mean())

    @cached_property
    def normals(self):
        """(N, 3) float32 unit normals pointing up (§3.1.1 step 4)."""
        if not self.visible:
            return np.zeros((0, 3), np.float32)
        return grid_normals(*self.surface)


def check_resolution(resolution):
    """(nx, ny) as ints >= 2 whose product fits MAX_VERTICES; ValueError naming `resolution`."""
    try:
        nx, ny = resolution
    except (TypeError, ValueError):
        raise ValueError(f"resolution: expected (x, y), got {resolution!r}") from None
    nx = integer("resolution", nx, 2, MAX_VERTICES)
    ny = integer("resolution", ny, 2, MAX_VERTICES)
    if nx * ny > MAX_VERTICES:
        raise ValueError(f"resolution: {nx}x{ny} exceeds {MAX_VERTICES} vertices")
    return nx, ny


def grid_topology(nx, ny):
    """(F, 4) int32 quads, counter-clockwise seen from above S_base (not kept: a mesh needs it
    only when its resolution changes, and a render grid's is 16 bytes a vertex)."""
    idx = np.arange(nx * ny, dtype=np.int32).reshape(ny, nx)
    quads = np.stack(
        [idx[:-1, :-1], idx[:-1, 1:], idx[1:, 1:], idx[1:, :-1]], axis=-1
    ).reshape(-1, 4)
    quads.setflags(write=False)
    return quads


def grid_uv(nx, ny):
    """(N, 2) float32 grid coordinates in [0, 1]^2 (§2.4 step 5)."""
    uv = np.empty((ny, nx, 2), np.float32)
    uv[..., 0] = np.linspace(0, 1, nx)
    uv[..., 1] = np.linspace(0, 1, ny)[:, None]
    return uv.reshape(-1, 2)


def corner_uv(nx, ny, flipped=False):
    """(4 F, 2) float32 grid coordinates at the corners of grid_topology's quads (corner order
    reversed if `flipped`), built without gathering through the quads."""
    uv = np.empty((ny - 1, nx - 1, 4, 2), np.float32)
    u, v = np.linspace(0, 1, nx), np.linspace(0, 1, ny)[:, None]
    order = (3, 2, 1, 0) if flipped else (0, 1, 2, 3)
    for corner, (du, dv) in zip(order, ((0, 0), (1, 0), (1, 1), (0, 1)), strict=True):
        uv[:, :, corner, 0] = u[du:nx - 1 + du]
        uv[:, :, corner, 1] = v[dv:ny - 1 + dv]
    return uv.reshape(-1, 2)


def _empty(resolution, octaves, origin):
    z3 = np.zeros((0, 3), np.float32)
    return GridResult(z3, (), np.zeros(0, np.float32), False, (octaves, 0), None, resolution,
                      origin)


def snapped_origin(camera, level, cell=1024.0):
    """A local origin for float32 positions: the camera's xy snapped to `cell` metres, at `level`.

    Relative to it, vertices near the camera keep sub-millimetre float32 precision however far the
    camera is from the world origin, and the origin itself changes only every `cell` metres.
    """
    xy = np.round(np.asarray(camera.position[:2], dtype=np.float64) / cell) * cell
    return np.array([xy[0], xy[1], level])


def grid_derivative(a, axis, dtype=None):
    """Differences between grid neighbours along `axis` of an (ny, nx) array: central inside,
    one-sided at the borders (the step is one grid cell either way, halved nowhere: callers take
    ratios or directions); of `dtype` if given (taken in `a`'s, then rounded)."""
    out = np.empty(a.shape, a.dtype if dtype is None else dtype)
    cut = [slice(None)] * 2

    def at(s):
        cut[axis] = s
        return tuple(cut)

    for into, (hi, lo) in ((slice(1, -1), (slice(2, None), slice(0, -2))), (0, (1, 0)),
                           (-1, (-1, -2))):
        np.subtract(a[at(hi)], a[at(lo)], out=out[at(into)], casting="same_kind")
    return out


def grid_area(x, y):
    """The signed area a grid cell's step spans, (dP/dj x dP/di)_z of points x, y (rows,
    columns), by `grid_derivative`: positive where the grid is counter-clockwise."""
    return _cross(*(grid_derivative(a, axis) for a, axis in ((x, 1), (y, 0), (x, 0), (y, 1))))


def _cross(x1, y0, x0, y1):
    """x1 y0 - x0 y1 (into x1 * y0's array): a cell's area from its differences (`grid_area`)."""
    out = x1 * y0
    out -= x0 * y1
    return out


def grid_jacobian(base, shift):
    """det(d(base + shift) / d(i, j)) / det(d base / d(i, j)) over a grid: x and y (rows,
    columns) of its points and of their displacement, float32 (`grid_derivative`s: the base's
    taken in double precision, the points may be far off; the rest in single, a Jacobian
    needs no more)."""
    d = grid_derivative
    bx1, by0, bx0, by1 = (d(base[k], axis, np.float32)
                          for k, axis in ((0, 1), (1, 0), (0, 0), (1, 1)))
    sx1, sy0, sx0, sy1 = (d(np.asarray(shift[k], np.float32), axis)
                          for k, axis in ((0, 1), (1, 0), (0, 0), (1, 1)))
    area = _cross(bx1, by0, bx0, by1)
    for moved, step in ((sx1, bx1), (sy0, by0), (sx0, bx0), (sy1, by1)):
        moved += step  # the displaced points' differences
    moved = _cross(sx1, sy0, sx0, sy1)
    return np.divide(moved, area, out=np.ones_like(area), where=area != 0.0)


def grid_normals(x, y, z):
    """Unit normals from the neighbours in u and v (§3.1.1 step 4), on (ny, nx) arrays.

    The z component of cross(dP/du, dP/dv) only depends on the flat grid, which the projector keeps
    counter-clockwise, so the normals point up out of the water whatever the heights.
    """
    d = grid_derivative
    pu, pv = np.stack([d(x, 1), d(y, 1), d(z, 1)]), np.stack([d(x, 0), d(y, 0), d(z, 0)])
    n = np.moveaxis(np.cross(pu, pv, axis=0), 0, -1)
    length = np.linalg.norm(n, axis=-1, keepdims=True)
    flat = length[..., 0] == 0.0
    n = np.divide(n, length, out=np.zeros_like(n), where=~flat[..., None])
    n[flat] = (0.0, 0.0, 1.0)
    return n.reshape(-1, 3).astype(np.float32)


def build_grid(camera, height_field, level=0.0, time=0.0, resolution=(65, 129),
               projector_elevation=0.0, band_limit=True, origin=None, aim=aim_projector,
               extent=None, crest=None):
    """Build the displaced projected grid for `camera` (a Camera or a (view, proj) pair).

    `height_field` is a height source (HeightField, SpectralField): it gives its `bounds(time)`
    (vertical, and of its choppy displacement), their standard deviations (`spread`), and
    `displacement(xy, time, lod, on_grid)`. With a displacement
    sideways, V_visible on S_base is widened by its bound, so the displaced grid still covers the
    screen.

    The grid is first built from the displaceable volumes fitted to the sea's spread
    (`fitted_extents`), the first whose border lies outside the screen (`border_outside`) kept;
    otherwise from the source's true bounds (§2.2), which always cover it. `GridResult.fitted`
    says which; a given `extent` (such as an earlier result's) is used as it is.

    Positions are world space relative to `origin` (default the world origin; see
    `snapped_origin`). `aim` places the projector; it is a parameter so tests can substitute the
    naive projector of §2.3 and show the stability suite catches it. `crest`, a band limit:
    the result's `crest` is (it, the source's crest sum: the sideways displacement of the waves
    it keeps), None from a source without one.
    """
    if not isinstance(camera, Camera):
        camera = Camera(*camera)
    level = finite("level", level)
    time = finite("time", time)
    elevation = non_negative("projector_elevation", projector_elevation)
    nx, ny = check_resolution(resolution)
    hf = height_field
    origin = np.zeros(3) if origin is None else np.asarray(origin, dtype=np.float64)
    if origin.shape != (3,) or not np.all(np.isfinite(origin)):
        raise ValueError(f"origin: expected a finite 3-vector, got {origin!r}")
    args = (camera, hf, level, time, (nx, ny), elevation, band_limit, origin, aim, crest)
    if extent is not None:
        return _grid(*args, extent)
    full = Extent.true_bounds(hf, time)
    for fitted in fitted_extents(hf, full):
        result = _grid(*args, fitted)
        if result.visible and border_outside(camera, result, level):
            return result
    return _grid(*args, full)


# Screen points (NDC) the displaced border must wind around where their rays cross the volume
# from one side to the other: the corners, a little inside, and the centre.
WITNESSES = np.array([(-0.99, -0.99), (0.99, -0.99), (0.99, 0.99), (-0.99, 0.99), (0.0, 0.0)])
SUBDIVIDE = 8  # points per border segment for the border's image around the camera


def winding(loop, point):
    """The winding number of the closed polygon `loop` (n, 2) around `point` (2,)."""
    a = loop - point
    b = np.roll(a, -1, axis=0)
    cross = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    up = (a[:, 1] <= 0.0) & (b[:, 1] > 0.0) & (cross > 0.0)
    down = (a[:, 1] > 0.0) & (b[:, 1] <= 0.0) & (cross < 0.0)
    return int(np.count_nonzero(up)) - int(np.count_nonzero(down))


def _windings(camera, loop, near, far):
    """How often the closed loop of world points (n, 3) winds around each witness ray (its
    `near` and `far` ends, camera.rays of WITNESSES): seen
    along the rays (orthographic), or, from the eye, on the sphere of directions (a sea rising
    over a low camera brings the border behind it, where a screen has no image), mapped
    stereographically from each ray's opposite direction, the border's segments subdivided so
    their arcs stay close to chords."""
    if camera.orthographic:
        c = camera.clip(loop)
        return [winding(c[:, :2] / c[:, 3:], point) for point in WITNESSES]
    ends = np.roll(loop, -1, axis=0)
    f = (np.arange(SUBDIVIDE) / SUBDIVIDE)[:, None, None]
    v = ((1.0 - f) * loop + f * ends).transpose(1, 0, 2).reshape(-1, 3) - camera.position
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    out = []
    for d in (far - near) / np.linalg.norm(far - near, axis=1, keepdims=True):
        e1 = np.cross(d, (1.0, 0.0, 0.0) if abs(d[0]) < 0.9 else (0.0, 1.0, 0.0))
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(d, e1)
        den = 1.0 + v @ d
        if den.min() < 1e-9:  # the border runs through the ray's opposite direction
            return [0] * len(WITNESSES)
        out.append(winding(np.column_stack([v @ e1, v @ e2]) / den[:, None], np.zeros(2)))
    return out


def border_outside(camera, result, level):
    """Whether the grid's border, displaced, lies outside V_cam around the screen: then the grid
    covers the screen as the full volume's would.

    Each border segment must have both ends outside one plane of V_cam (a half-space holds the
    segment between), but for the row the range stops at the horizon; and the border must wind
    around each screen ray that crosses the grid's volume from one side to the other (a border
    wholly above the screen passes the first test and covers nothing; a ray that only leaves the
    volume, from a camera inside it, may pass over the sea)."""
    nx, ny = result.resolution
    p = result.positions.reshape(ny, nx, 3)
    rows = [p[0], p[1:, -1], p[-1, -2::-1], p[-2::-1, 0]]  # a loop: bottom, right, top, left
    exempt = {0: 0, -1: 2}.get(result.projector.horizon_row)
    for i, line in enumerate(rows):
        if i == exempt:
            continue
        c = camera.clip(np.concatenate([rows[i - 1][-1:], line]).astype(np.float64)
                        + result.origin)
        w = c[:, 3:]
        out = np.concatenate([w + c[:, :3], w - c[:, :3]], axis=1) < 0.0
        if not (out[:-1] & out[1:]).any(axis=1).all():
            return False
    near, far = camera.rays(WITNESSES)
    low, high = level - result.extent.lower, level + result.extent.upper
    crossing = (((near[:, 2] > high) & (far[:, 2] < low))
                | ((near[:, 2] < low) & (far[:, 2] > high)))
    loop = np.concatenate(rows).astype(np.float64) + result.origin
    return all(n != 0 for n, c in zip(_windings(camera, loop, near, far), crossing, strict=True)
               if c)


def _grid(camera, hf, level, time, resolution, elevation, band_limit, origin, aim, crest,
          extent):
    """The grid for the displaceable volume of `extent` (§2.4 steps 2 to 7)."""
    nx, ny = resolution
    made = grid_points(camera, level, extent, resolution, elevation, aim, origin,
                       hf.wave_scale if band_limit else None)
    if made is None:
        return _empty((nx, ny), hf.shader_octaves(None)[0], origin)
    projector, u, v, xy, lod = made.projector, made.u, made.v, made.xy, made.lod
    h, d, *crests = hf.displacement(xy, time, lod, on_grid=True, crest=crest)
    base = None
    if d is not None:
        base = xy
        xy = xy + d
    x, y = xy
    positions = np.empty((ny, nx, 3), dtype=np.float32)
    np.subtract(x, origin[0], out=positions[..., 0], casting="same_kind")
    np.subtract(y, origin[1], out=positions[..., 1], casting="same_kind")
    np.add(h, level - origin[2], out=positions[..., 2], casting="same_kind")
    positions = positions.reshape(-1, 3)
    shader = hf.shader_octaves(lod)
    lod = np.full(nx * ny, np.inf, np.float32) if lod is None else lod.reshape(-1)
    return GridResult(positions, (x, y, h), lod, True, shader, projector,
                      (nx, ny), origin, camera, base, extent, (u, v[:, 0]),
                      (crest, crests[0]) if crests and crests[0] is not None else None,
                      (level, elevation, aim, hf.wave_scale if band_limit else None))
