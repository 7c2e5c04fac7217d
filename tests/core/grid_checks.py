"""Camera poses and the properties every grid must have (used by the stability suite)."""

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from projgrid_addon import Camera, HeightField, build_grid, grid_topology, snapped_origin
from projgrid_addon.camera import FRUSTUM_EDGES, orthographic, perspective, view_matrix
from projgrid_addon.projector import heading_vector
from projgrid_addon.spectral_field import SpectralField
from projgrid_addon.spectrum import SeaState


@dataclass
class Pose:
    height: float = 10.0  # above the water level
    pitch: float = -10.0  # degrees, + looks up
    yaw: float = 0.0
    roll: float = 0.0
    fov: float = 50.0  # degrees, vertical
    ortho_scale: float = 0.0  # > 0: orthographic camera of this width
    near: float = 0.1
    far: float = 1e4
    distance: float = 0.0  # from the world origin, horizontally
    bearing: float = 0.0  # direction of that offset, degrees
    aspect: float = 16 / 9
    shift_x: float = 0.0
    shift_y: float = 0.0
    level: float = 0.0
    amplitude: float = 0.5
    octaves: int = 6
    roughness: float = 0.5
    time: float = 0.0
    elevation: float = 0.0
    resolution: tuple = (17, 33)
    method: str = "fast"  # of the height field
    choppiness: float = 0.0
    wind_direction: float = 0.0  # radians
    wind_speed: float = 0.0  # > 0: the spectral sea at this wind instead of the noise

    def camera(self):
        p, y, r = np.radians([self.pitch, self.yaw, self.roll])
        forward = np.array([np.cos(p) * np.sin(y), np.cos(p) * np.cos(y), np.sin(p)])
        right0 = np.array([np.cos(y), -np.sin(y), 0.0])
        up0 = np.cross(right0, forward)
        right = np.cos(r) * right0 + np.sin(r) * up0
        up = np.cross(right, forward)
        b = np.radians(self.bearing)
        eye = np.array([self.distance * np.cos(b), self.distance * np.sin(b),
                        self.level + self.height])
        view = view_matrix(eye, right, up, forward)
        shift = (self.shift_x, self.shift_y)
        if self.ortho_scale > 0:
            proj = orthographic(self.ortho_scale, self.aspect, self.near, self.far, shift)
        else:
            proj = perspective(np.radians(self.fov), self.aspect, self.near, self.far, shift)
        return Camera(view, proj)

    def height_field(self):
        if self.wind_speed > 0.0:
            return _spectral(self.wind_speed, self.wind_direction, self.choppiness)
        return HeightField(amplitude=self.amplitude, wave_scale=40.0, octaves=self.octaves,
                           roughness=self.roughness, speed=1.0, seed=7, method=self.method,
                           choppiness=self.choppiness, wind_direction=self.wind_direction)

    def build(self, camera=None, **kw):
        camera = camera or self.camera()
        kw.setdefault("origin", snapped_origin(camera, self.level))
        return camera, build_grid(camera, self.height_field(), level=self.level, time=self.time,
                                  resolution=self.resolution, projector_elevation=self.elevation,
                                  **kw)


@lru_cache(maxsize=16)
def _spectral(wind_speed, wind_direction, choppiness):
    return SpectralField(SeaState(wind_speed=wind_speed, wind_direction=wind_direction),
                         choppiness=choppiness, seed=7)


# The worst error-to-tolerance ratio each property has seen since the dict was last cleared
# (a ratio above 1 fails it). Recorded before each assertion; tools/stress.py reads it per pose.
RATIOS = {}


def record(check, ratios):
    """Note the worst of `ratios` (error / tolerance, > 1 failing) under `check`."""
    worst = float(np.max(ratios, initial=0.0))
    RATIOS[check] = max(RATIOS.get(check, worst), worst)


def _ratio(excess, tol):
    """excess / tol, where tol may be 0: 0 for no excess, inf for any."""
    return np.divide(excess, tol, out=np.where(excess > 0, np.inf, 0.0), where=tol > 0)


def _ulp32(a):
    return np.finfo(np.float32).eps * np.maximum(np.abs(a), 1.0)


def triangles(result, quads=None):
    """(T, 3, 3) float64 world-space triangles of the grid's `quads` (default all; each quad split
    along 0-2)."""
    q = grid_topology(*result.resolution)
    if quads is not None:
        q = q[quads]
    p = result.positions[q].astype(np.float64) + result.origin  # (F, 4, 3)
    return np.concatenate([p[:, [0, 1, 2]], p[:, [0, 2, 3]]])


def quads_near_rays(camera, result, n, tol=1e-6):
    """Indices of the quads a ray through the n x n `screen_points` could meet.

    The projection of a hit point is the ray's screen point, so a quad wholly in front of the
    camera can only be met if its NDC bounding box contains one of those points; the others are
    skipped (for 2049^2 vertices that leaves a few hundred quads of four million).
    """
    c = camera.clip(result.positions.astype(np.float64) + result.origin)
    w = c[:, 3]
    front = w > 0
    # Screen position in units of the ray spacing: ray k sits at integer k.
    xy = (c[:, :2] / np.where(front, w, 1.0)[:, None] + 1.0) * ((n - 1) / 2.0)
    q = grid_topology(*result.resolution)
    boxes = xy[q]  # (F, 4, 2)
    first = np.maximum(np.ceil(boxes.min(axis=1) - tol), 0)
    last = np.minimum(np.floor(boxes.max(axis=1) + tol), n - 1)
    covers = np.all(first <= last, axis=1)
    return np.flatnonzero(covers | ~front[q].all(axis=1))


def ray_hits(origins, ends, tris, tol=1e-7, chunk=100_000):
    """For each segment origin->end, whether it meets any triangle (Moeller-Trumbore, vectorised
    over rays and a chunk of triangles at a time)."""
    hits = np.zeros(len(origins), dtype=bool)
    for i in range(0, len(tris), chunk):
        todo = ~hits
        if not todo.any():
            break
        hits[todo] = _ray_hits(origins[todo], ends[todo], tris[i:i + chunk], tol)
    return hits


def _ray_hits(origins, ends, tris, tol):
    d = (ends - origins)[:, None, :]
    e1 = (tris[:, 1] - tris[:, 0])[None]
    e2 = (tris[:, 2] - tris[:, 0])[None]
    pv = np.cross(d, e2)
    det = np.sum(e1 * pv, axis=-1)
    ok = det != 0
    inv = 1.0 / np.where(ok, det, 1.0)
    tv = origins[:, None, :] - tris[None, :, 0]
    u = np.sum(tv * pv, axis=-1) * inv
    qv = np.cross(tv, e1)
    v = np.sum(qv * d, axis=-1) * inv
    s = np.sum(e2 * qv, axis=-1) * inv
    hit = ok & (u >= -tol) & (v >= -tol) & (u + v <= 1 + tol) & (s >= 0) & (s <= 1)
    return hit.any(axis=1)


def screen_points(n=7):
    """An n x n grid of NDC points including the screen edges and corners."""
    t = np.linspace(-1.0, 1.0, n)
    x, y = np.meshgrid(t, t)
    return np.column_stack([x.ravel(), y.ravel()])


def check_coverage(camera, result, level, bound, n=7):
    """Rays crossing the whole displaceable volume within the clip range hit the mesh; rays whose
    clipped segment stays outside the volume do not.

    The volume is the slab the mesh's vertices lie in when that is thinner than the bound: rays
    from a camera inside the bound's slab cross it too, so a gap near the camera shows.
    """
    if result.visible and len(result.positions):
        reach = np.abs(result.positions[:, 2].astype(np.float64) + result.origin[2] - level).max()
        bound = min(bound, float(reach))
    ndc = screen_points(n)
    near, far = camera.rays(ndc)
    lo, hi = level - bound, level + bound
    zn, zf = near[:, 2], far[:, 2]
    # Decided with a slack, so no ray is classed by the rounding of its end points.
    slack = 1e-9 * (1.0 + np.abs(near).max() + np.abs(far).max()) + 1e-6 * bound
    lo, hi = lo - slack, hi + slack
    crossing = ((zn > hi) & (zf < lo)) | ((zn < lo) & (zf > hi))
    outside = ((zn > hi) & (zf > hi)) | ((zn < lo) & (zf < lo))
    if not result.visible:
        assert not crossing.any(), "not visible, but a screen ray crosses the volume"
        return
    tris = triangles(result, quads_near_rays(camera, result, n))
    hit = np.zeros(len(ndc), dtype=bool)
    test = crossing | outside
    hit[test] = ray_hits(near[test], far[test], tris)
    miss = crossing & ~hit
    assert not miss.any(), f"coverage: {np.count_nonzero(miss)} crossing rays miss the mesh"
    assert not (outside & hit).any(), "rays that miss the volume hit the mesh"


def check_result(camera, result, level, bound):
    """Every property of one grid except coverage and popping (which need more than the result)."""
    nx, ny = result.resolution
    if not result.visible:
        assert result.positions.shape == (0, 3) and result.efficiency == 0.0
        return
    n = nx * ny
    assert result.positions.shape == (n, 3) and result.positions.dtype == np.float32
    assert result.normals.shape == (n, 3) and result.uv.shape == (n, 2)
    for name in ("positions", "normals", "uv"):
        assert np.all(np.isfinite(getattr(result, name))), f"{name} not finite"
    assert not np.any(np.isnan(result.lod))
    assert 0.0 <= result.efficiency <= 1.0

    world = result.positions.astype(np.float64) + result.origin
    # The projector's grid on S_base: the points before a choppy displacement moved them.
    flat = world if result.base is None else np.column_stack(
        [result.base[0].ravel(), result.base[1].ravel(), world[:, 2]])
    # Heights inside the displaceable volume (up to float32 rounding of the stored coordinate).
    dz = np.abs(world[:, 2] - level)
    tol = bound * (1 + 1e-6) + 2 * _ulp32(result.positions[:, 2])
    record("height", dz / tol)
    assert np.all(dz <= tol), "height > bound"

    # No backfiring: every vertex comes from an intersection in front of the projector. The
    # homogeneous w of the corner intersections is affine over the grid, so positive corners mean
    # positive everywhere; the stored vertices agree up to their float32 rounding.
    pr = result.projector
    if not pr.orthographic:
        corners = pr.corner_points(level)
        assert np.all(corners[:, 3] > 0), "backfiring: a grid corner lies behind the projector"
        base = flat.copy()
        base[:, 2] = level
        depth = (base - pr.position) @ pr.forward
        slack = 4 * _ulp32(np.abs(result.positions).max(axis=1))
        record("backfiring", -depth / slack)
        behind = np.count_nonzero(depth <= -slack)
        assert behind == 0, f"backfiring: {behind} vertices behind"

    # Consistent winding: every flat triangle is counter-clockwise seen from above, but for
    # triangles smaller than the float32 rounding of their coordinates.
    q = grid_topology(nx, ny)
    p = flat[:, :2]
    ulp = _ulp32(np.abs(result.positions[:, :2]).max(axis=1))
    for tri in ([0, 1, 2], [0, 2, 3]):
        a, b, c = p[q[:, tri[0]]], p[q[:, tri[1]]], p[q[:, tri[2]]]
        cross = (b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0]
        edges = np.abs(b - a).max(axis=1) + np.abs(c - a).max(axis=1)
        rounding = 4 * ulp[q[:, tri]].max(axis=1) * edges
        tol = 1e-9 * edges**2 + rounding
        record("winding", _ratio(-cross, tol))
        assert np.all(cross >= -tol), "winding flips"

    # Normals: unit length, pointing up.
    length = np.linalg.norm(result.normals, axis=1)
    record("unit normals", np.abs(length - 1.0) / 2e-5)  # allclose: atol 1e-5 + rtol 1e-5 * 1
    assert np.allclose(length, 1.0, atol=1e-5), "normals not unit"
    if result.base is None:  # a choppy surface may fold over: its normals then turn down
        assert np.all(result.normals[:, 2] > 0), "normal pointing down"

    # Corner interpolation equals the per-vertex ray-plane intersection.
    x0, x1, y0, y1 = pr.span
    u = np.tile(np.linspace(0.0, 1.0, nx), ny)  # exact grid coordinates, not the float32 uv
    s = np.repeat(np.linspace(0.0, 1.0, ny), nx)
    uv = np.column_stack([u, s])
    record("uv", np.abs(result.uv - uv) / (1e-7 + 1e-5 * uv))  # allclose's tolerance
    assert np.allclose(result.uv, uv, atol=1e-7)
    # The columns' u and rows' v in the span (Projector.spacing): from 0 to 1, rising.
    for t in result.spacing:
        assert t[0] == 0.0 and t[-1] == 1.0 and np.all(np.diff(t) > 0.0), "spacing"
    u = np.tile(result.spacing[0], ny)
    v = np.repeat(result.spacing[1], nx)
    ndc = np.column_stack([x0 + u * (x1 - x0), y0 + v * (y1 - y0)])
    right, up, back = pr.view[:3, :3]  # rows of a rotation: its exact inverse's columns
    if pr.orthographic:
        start = pr.position + ndc[:, :1] * right + ndc[:, 1:] * up
        direction = np.broadcast_to(-back, start.shape)
    else:
        start = np.broadcast_to(pr.position, (n, 3))
        direction = ndc[:, :1] * right + ndc[:, 1:] * up - back
    t = (level - start[:, 2]) / direction[:, 2]
    exact = start + t[:, None] * direction
    err = np.linalg.norm(exact[:, :2] - flat[:, :2], axis=1)
    reach = np.linalg.norm(exact - pr.position, axis=1)
    tol = 1e-7 * reach + 4 * _ulp32(np.abs(result.positions[:, :2]).max(axis=1))
    record("corner interpolation", err / tol)
    # Not a check: the float64 maths' error (before the float32 storage) against the budget's
    # 1e-7 * reach alone, for the stress report: the world coordinates' own rounding (the
    # float32 storage is at most sqrt(2) / 8 of the tolerance). Under 0.05 but where the
    # projector stands microns from the sea far from the world's origin (654 over 20,000
    # poses: a camera on S_base 1,000 km out, its far clip 7 cm; its rounding, 1e-10 m, is
    # large against a reach of 4e-6 m).
    xy = result.surface[:2] if result.base is None else result.base
    err64 = np.linalg.norm(exact[:, :2] - np.column_stack([a.ravel() for a in xy]), axis=1)
    record("(float64 share of corner)", err64 / (1e-7 * reach))
    assert np.all(err <= tol), f"corner interpolation off by {(err / tol).max():.3g} x tolerance"


def relative_moves(a, b):
    """How far each vertex moves between results a and b, relative to its distance from a's
    projector (which stays above the volume, so the ratio never degenerates), and the float32
    rounding share of that figure."""
    pa = a.positions.astype(np.float64) + a.origin
    pb = b.positions.astype(np.float64) + b.origin
    reach = np.linalg.norm(pa - a.projector.position, axis=1)
    rounding = 8 * np.finfo(np.float32).eps * (1 + np.abs(a.positions).max(axis=1)) / reach
    return np.linalg.norm(pb - pa, axis=1) / reach, rounding


def heading_margin(camera):
    """|g| of projector.heading before normalising: small only near its unavoidable singularity."""
    return float(np.linalg.norm(heading_vector(camera)))


FRUSTUM_FACES = [[c for c in range(8) if (c >> axis) & 1 == side] for axis in range(3)
                 for side in (0, 1)]


def seen_edge_on(camera, level, bound):
    """Whether the displaceable volume is seen edge-on, to within 1e-6 of the face's or the
    edge's size.

    That is a face or an edge of V_cam lying in S_upper or S_lower (a tilt turns the shared face
    into an edge, so V_visible itself jumps, or near it changes like gap / tilt), or a flat sea
    (bound 0) with a perspective camera on it or an orthographic one looking along it. The
    surface has no area on screen there, so nothing can be seen to pop.
    """
    corners = camera.corners
    z = corners[:, 2]
    floor = 1e-12 * max(1.0, float(np.abs(z).max()))
    for face in FRUSTUM_FACES:
        size = np.ptp(corners[face], axis=0).max()
        tol = 1e-6 * size + floor
        for plane in (level - bound, level + bound):
            if np.all(np.abs(z[face] - plane) <= tol):
                return True
    # An edge of V_cam lying in S_upper or S_lower (a lens shift of exactly 0.5 puts one there;
    # so does a far frustum edge running inside a thin volume): a tilt moves the edge off the
    # plane and V_visible jumps with it, as for a face.
    for a, b in FRUSTUM_EDGES:
        tol = 1e-6 * float(np.linalg.norm(corners[b] - corners[a])) + floor  # as a face's
        for plane in (level - bound, level + bound):
            if abs(z[a] - plane) <= tol and abs(z[b] - plane) <= tol:
                return True
    if bound == 0.0:
        if camera.orthographic:
            return abs(camera.forward[2]) <= 1e-6
        reach = float(np.abs(corners - camera.position).max())
        return abs(camera.position[2] - level) <= 1e-6 * reach
    return False


__all__ = ["Pose", "RATIOS", "record", "relative_moves", "check_coverage", "check_result",
           "seen_edge_on", "heading_margin", "ray_hits", "screen_points", "triangles"]
