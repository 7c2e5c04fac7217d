"""V_displaceable and V_visible (thesis §2.2, §2.4.2), and the volume fitted to the surface in view.

S_base is z = level with normal +Z; S_upper and S_lower are z = level + upper and level - lower.
"""

from dataclasses import dataclass

import numpy as np

from .camera import FRUSTUM_EDGES

# The fitted volume samples the surface where the screen's border rays cross the true volume:
# BORDER_RAYS rays along each screen edge, each cut by BORDER_PLANES levels between S_lower and
# S_upper.
BORDER_RAYS = 16
BORDER_PLANES = 9
# The fitted extent is the sampled extreme plus this share of the sampled range, rounded up to a
# step of FIT_LADDER so it changes only now and then from frame to frame (the grid would swim).
FIT_MARGIN = 0.25
FIT_LADDER = 2.0 ** 0.25
# and at least this share of the true bound: a thinner volume gains few vertices and would bring
# the projector, which stays above S_upper, close to the water, where its rays graze S_base.
FIT_FLOOR = 0.1


@dataclass(frozen=True)
class Extent:
    """How far the surface reaches from S_base: below, above, and sideways (choppy)."""

    lower: float
    upper: float
    side: float = 0.0
    fitted: bool = False  # fitted to the sea in view, rather than the source's true bounds

    @classmethod
    def true_bounds(cls, source):
        """A prepared height source's own bounds (§2.2): they hold everywhere."""
        return cls(source.bound, source.bound, source.horizontal_bound)

    def __le__(self, other):
        return (self.lower <= other.lower and self.upper <= other.upper
                and self.side <= other.side)


def bound_planes(level, bound, lower=None):
    """Heights of S_lower and S_upper (`bound` above; below too unless `lower` is given)."""
    return level - (bound if lower is None else lower), level + bound


def visible_volume_points(camera, level, bound, lower=None):
    """World points whose convex hull is V_visible = V_cam ∩ V_displaceable (§2.4.2).

    These are the frustum corners between the bound planes and the intersections of the 12 frustum
    edges with S_upper and S_lower. An empty (0, 3) array means the volume is not in view.
    """
    corners = camera.corners
    planes = np.array(bound_planes(level, bound, lower))[:, None]  # (2, 1)
    z = corners[:, 2]
    inside = corners[(z >= planes[0]) & (z <= planes[1])]
    a, b = corners[FRUSTUM_EDGES[:, 0]], corners[FRUSTUM_EDGES[:, 1]]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (planes - a[:, 2]) / (b[:, 2] - a[:, 2])  # (2, 12); inf or NaN on level edges
    hit = (t >= 0.0) & (t <= 1.0)
    edge = np.nonzero(hit)[1]
    p = a[edge] + t[hit][:, None] * (b - a)[edge]
    p[:, 2] = np.broadcast_to(planes, hit.shape)[hit]
    return np.concatenate([inside, p])


def border_points(camera, level, extent):
    """Points on S_base under the screen's border where it crosses the volume of `extent`.

    Where the rays along the screen's edges meet BORDER_PLANES levels between S_lower and S_upper,
    within the clip range: the stretch of sea whose reach decides V_visible.
    """
    t = np.linspace(-1.0, 1.0, BORDER_RAYS, endpoint=False)
    edges = np.concatenate([np.column_stack([t, -np.ones_like(t)]),
                            np.column_stack([np.ones_like(t), t]),
                            np.column_stack([-t, np.ones_like(t)]),
                            np.column_stack([-np.ones_like(t), -t])])
    near, far = camera.rays(edges)
    heights = level + np.linspace(-extent.lower, extent.upper, BORDER_PLANES)[:, None]
    dz = far[:, 2] - near[:, 2]
    with np.errstate(divide="ignore", invalid="ignore"):
        s = (heights - near[:, 2]) / dz  # (planes, rays)
    hit = (s >= 0.0) & (s <= 1.0)  # False where s is NaN
    plane, ray = np.nonzero(hit)
    return (near[ray, :2] + s[plane, ray, None] * (far - near)[ray, :2]).T  # (2, n)


def _ladder(value, ceiling):
    value = max(value, FIT_FLOOR * ceiling)
    if value <= 0.0:
        return 0.0
    return min(ceiling, FIT_LADDER ** np.ceil(np.log(value) / np.log(FIT_LADDER)))


def fitted_extent(camera, level, prepared, time, full):
    """The displaceable volume fitted to the surface around the screen's border (§2.2, §2.4.2).

    The bounds of a height source hold everywhere, so they sum every band's extreme; the sea in
    view rarely comes near that (a spectral sea's sum is about 11 standard deviations). Sampled
    where the border rays cross the full volume, with a margin, the extent is a guess: the grid
    built from it is kept only if its border is verified to lie outside the screen
    (`border_outside`), otherwise the full bounds are used. None when nothing is sampled.
    """
    xy = border_points(camera, level, full)
    if xy.shape[1] == 0:
        return None
    h, d = prepared.displacement(xy, time, None)
    top, bottom = float(h.max()), float(h.min())
    margin = FIT_MARGIN * (top - bottom)
    side = 0.0
    if d is not None:
        reach = np.hypot(d[0], d[1])
        side = _ladder(float(reach.max()) * (1.0 + FIT_MARGIN), full.side)
    return Extent(lower=_ladder(max(0.0, margin - bottom), full.lower),
                  upper=_ladder(max(0.0, top + margin), full.upper), side=side, fitted=True)
