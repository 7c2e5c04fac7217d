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
    lower, upper = bound_planes(level, bound)
    z = corners[:, 2]
    found = [corners[(z >= lower) & (z <= upper)]]
    a, b = corners[FRUSTUM_EDGES[:, 0]], corners[FRUSTUM_EDGES[:, 1]]
    dz = b[:, 2] - a[:, 2]
    safe = np.where(dz == 0.0, 1.0, dz)
    for plane in (lower, upper):
        t = (plane - a[:, 2]) / safe
        hit = (dz != 0.0) & (t >= 0.0) & (t <= 1.0)
        p = a[hit] + t[hit, None] * (b[hit] - a[hit])
        p[:, 2] = plane
        found.append(p)
    return np.concatenate(found)
