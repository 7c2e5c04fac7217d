"""V_displaceable and V_visible (thesis §2.2, §2.4.2), and the volumes fitted to the sea's spread.

S_base is z = level with normal +Z; S_upper and S_lower are z = level + upper and level - lower.
"""

from dataclasses import dataclass

import numpy as np

from .camera import FRUSTUM_EDGES

# The fitted volumes, thinnest first: the sea's standard deviation times these, above and below
# S_base (and its choppy displacement's, sideways). A linear sea's heights are Gaussian and a
# crest outreaches 2 sigma at 2 % of points, but only those under the screen's border matter,
# and the range leaves slack there: the border check seldom turns the thinnest down
# (docs/benchmarks.md §5).
FIT_SIGMAS = (2.0, 3.0, 5.0)


@dataclass(frozen=True)
class Extent:
    """How far the surface reaches from S_base: below, above, and sideways (choppy)."""

    lower: float
    upper: float
    side: float = 0.0
    fitted: bool = False  # fitted to the sea's spread, rather than the source's true bounds

    @classmethod
    def true_bounds(cls, source, time):
        """A height source's own bounds at `time` (§2.2): they hold everywhere."""
        bound, side = source.bounds(time)
        return cls(bound, bound, side)

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


def fitted_extents(source, full):
    """The displaceable volumes fitted to the sea's spread, thinnest first (§2.2, §2.4.2).

    The bounds of a height source hold everywhere, so they sum every band's extreme; the sea
    rarely comes near that (a spectral sea's sum is about 11 standard deviations), and a grid
    built for them spends its vertices off the screen. A fitted volume is a guess: the grid built
    from it is kept only if its border is verified to lie outside the screen (`border_outside`).
    The guesses depend on the settings alone (`source.spread`, or its `volume_spread` where it
    has one: a keyed wind's strongest), never on the time: a still camera's grid stays still
    while the waves run through it (a volume sampled from the sea in view changed from frame
    to frame, and the grid swam over the sea).
    """
    height, side = getattr(source, "volume_spread", source.spread)
    for sigmas in FIT_SIGMAS:
        extent = Extent(lower=min(sigmas * height, full.lower),
                        upper=min(sigmas * height, full.upper),
                        side=sigmas * side, fitted=True)  # (the true side varies in time)
        if not full <= extent:
            yield extent
