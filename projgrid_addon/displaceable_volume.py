"""V_displaceable and V_visible (thesis §2.2, §2.4.2).

S_base is z = level with normal +Z; S_upper and S_lower are z = level +- bound.
"""

import numpy as np

from .camera import FRUSTUM_EDGES


def bound_planes(level, bound):
    """Heights of S_lower and S_upper."""
    return level - bound, level + bound


def visible_volume_points(camera, level, bound):
    """World points whose convex hull is V_visible = V_cam ∩ V_displaceable (§2.4.2).

    These are the frustum corners between the bound planes and the intersections of the 12 frustum
    edges with S_upper and S_lower. An empty (0, 3) array means the volume is not in view.
    """
    corners = camera.corners
    planes = np.array(bound_planes(level, bound))[:, None]  # (2, 1)
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
