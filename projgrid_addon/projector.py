"""The projector (thesis §2.3.2, §2.4 steps 3-6, §2.4.1, §2.4.2, §2.5, App. A).

The projector is a second camera whose post-perspective space holds the grid. It is kept above
S_upper (plus the user's elevation, §2.5), never rolled, and aimed so that every point of
V_visible projected onto S_base lies inside its front half-space with a margin, which is what rules
out backfiring (§2.3.2). A camera below S_base is handled by symmetry: only the distance to S_base
and the view vector mirrored into the lower half-space are used (§2.4.1).
"""

from dataclasses import dataclass

import numpy as np

from .camera import view_matrix

UP = np.array([0.0, 0.0, 1.0])
# Every projected point of V_visible stays this angle (rad) inside the projector's front half-space.
MARGIN_ANGLE = 0.01
# Method 1 alone once |view_z| >= 1 / METHOD1_GAIN; blended with method 2 towards the horizon.
METHOD1_GAIN = 8.0
# Method 2 aims at a point this many projector heights ahead.
METHOD2_DISTANCE = 8.0
# Relative widening of the range so rays exactly on the screen edge still meet the mesh.
RANGE_MARGIN = 1e-5
# Standing back from a sea that reaches under a low camera (`_standing_back`).
STEEPEST = np.radians(45.0)
STAND_BACK = 3.0

# The grid's columns and rows (`Projector.spacing`): this share spread evenly over the span,
# the rest as the camera's screen covers it; the span sampled this finely for it, along these
# lines, within this margin of the screen's edges, and tending to even under SEEN of screen.
OFF_SCREEN = 0.1
SPACING_SAMPLES = 257
SEEN = 0.05
SCREEN_EDGE = 0.1
LINES = np.linspace(0.05, 0.95, 7)  # the columns (then rows) whose screen length is summed

# Normalised projections: only x/w and y/w matter to the grid (M_range absorbs field of view, aspect
# and lens shift): NDC (x, y) is the point's camera-space (x, y) over its distance (perspective) or
# as it is (orthographic), so the ray through NDC (x, y) runs along x right + y up + forward.
_PERSPECTIVE = np.array([[1.0, 0, 0, 0], [0, 1.0, 0, 0], [0, 0, 0, 1.0], [0, 0, -1.0, 0]])
_ORTHOGRAPHIC = np.array([[1.0, 0, 0, 0], [0, 1.0, 0, 0], [0, 0, -1.0, 0], [0, 0, 0, 1.0]])


NEAR_EYE = 1e-3  # of the span's farthest reach (w) from the eye: nearer, a point's NDC is noise


def _on_screen(a, b):
    """How much screen each segment a -> b ((..., 2) NDC each) covers: its length, weighted at
    its middle by a window that is 1 inside the screen and falls to 0 over SCREEN_EDGE on
    either side of its edges, so it changes continuously as the segments move, even along an
    edge (a plane seen edge-on there)."""
    mid, d = 0.5 * (a + b), b - a
    with np.errstate(invalid="ignore", over="ignore"):
        window = np.prod(np.clip((1.0 + SCREEN_EDGE - np.abs(mid)) / (2.0 * SCREEN_EDGE), 0.0,
                                 1.0), axis=-1)
        length = np.hypot(d[..., 0], d[..., 1])
    return np.where(np.isfinite(window) & np.isfinite(length), window * length, 0.0)


def _spread(s, t, seen):
    """Grid coordinates at even steps `s` over [0, 1], of density OFF_SCREEN even plus the
    rest as `seen` (per interval of the samples `t`), tending to even where little is seen
    (SEEN): (coordinates, their derivative in s)."""
    total = seen.sum() + SEEN
    density = (1.0 - OFF_SCREEN) * seen / total + (
        OFF_SCREEN + (1.0 - OFF_SCREEN) * SEEN / total) / len(seen)
    cdf = np.concatenate([[0.0], np.cumsum(density)])
    cdf /= cdf[-1]
    out = np.interp(s, cdf, t)
    return out, np.gradient(out, s)


def _horizontal(v):
    return np.array([v[0], v[1], 0.0])


@dataclass
class Projector:
    """A projector: view (M_pview), normalised projection, and the range of §2.4.2."""

    view: np.ndarray
    proj: np.ndarray
    position: np.ndarray
    forward: np.ndarray
    orthographic: bool
    span: tuple = (-1.0, 1.0, -1.0, 1.0)
    horizon_row: int | None = None  # the grid row (0 or -1) the span stops at the horizon

    @classmethod
    def looking(cls, position, right, up, forward, orthographic):
        proj = _ORTHOGRAPHIC if orthographic else _PERSPECTIVE
        return cls(view_matrix(position, right, up, forward), proj, position, forward,
                   orthographic)

    def with_range(self, points, origin=(0.0, 0.0, 0.0), slack=0.0):
        """A copy whose span covers `points` on S_base (§2.4.2).

        The span is widened by RANGE_MARGIN and by four float32 roundings of the points' coordinates
        relative to `origin` (each coordinate's distance from it plus `slack`, for points whose
        mesh is placed from another origin up to `slack` away), so rays on the screen edge still
        meet the float32 mesh.
        """
        points = np.asarray(points, dtype=np.float64)
        m = self.proj @ self.view
        c = points @ m[:, :3].T + m[:, 3]
        ndc = c[:, :2] / c[:, 3:4]
        rounding = 4.0 * np.finfo(np.float32).eps * (np.abs(points - origin).max(axis=1) + slack)
        # How far NDC moves per metre: d(X/W) = (dX - x dW) / W in perspective, 1 in orthographic.
        if self.orthographic:
            sensitivity = 1.0
        else:
            sensitivity = (1.0 + np.abs(ndc).sum(axis=1)) / np.abs(c[:, 3])
        each = (rounding * sensitivity)[:, None]
        lo, hi = (ndc - each).min(axis=0), (ndc + each).max(axis=0)
        pad = RANGE_MARGIN * (hi - lo) + 1e-12 * (1.0 + np.abs(lo) + np.abs(hi))
        lo, hi = lo - pad, hi + pad
        horizon, row = self.horizon_y, None
        if horizon is not None:  # never pad across the horizon, where rays stop meeting S_base
            top, bottom = ndc[:, 1].max(), ndc[:, 1].min()
            if self.view[1, 2] > 0:
                stop = top + 0.5 * (horizon - top)
                row = -1 if stop < hi[1] else None
                hi[1] = min(hi[1], stop)
            else:
                stop = bottom + 0.5 * (horizon - bottom)
                row = 0 if stop > lo[1] else None
                lo[1] = max(lo[1], stop)
        return Projector(self.view, self.proj, self.position, self.forward, self.orthographic,
                         (lo[0], hi[0], lo[1], hi[1]), row)

    def spacing(self, camera, level, extent, corners, nx, ny):
        """Where the grid's columns and rows fall in the span (§2.4 step 5): (u (nx,), du/ds
        (nx,), v (ny, 1), dv/ds (ny,)) for columns and rows s = 0 .. 1 evenly.

        The span is even in the projector's screen, which stands higher and further back than
        a low camera: most of an even grid would fall where S_base lies under or beside the
        camera's screen, where only the highest crests show. So columns and rows follow the
        camera's own screen: each part of the span gets them as the screen length (NDC) its
        points cover there, and OFF_SCREEN of them are spread evenly over the whole span, so
        every part keeps some (crests from under the screen's edge, the choppy margin). The
        screen length is that of the span's points lifted to three heights, the mean sea and
        half way to the displaceable volume's bounds (`extent`): a camera on the surface sees
        S_base edge-on, the waves about it not; a span the screen hardly sees (under SEEN)
        tends to even. Continuous in the camera (no popping); the whole span stays covered,
        and the grid stays a product of columns and rows, so its corners still interpolate it
        exactly. `corners`: the grid's homogeneous corners on S_base (corner_points)."""
        s_u, s_v = np.linspace(0.0, 1.0, nx), np.linspace(0.0, 1.0, ny)
        if camera.orthographic or self.orthographic or min(nx, ny) < 3:
            return s_u, np.ones(nx), s_v[:, None], np.ones(ny)
        t = np.linspace(0.0, 1.0, SPACING_SAMPLES)
        v, dv = _spread(s_v, t, self._seen(camera, level, extent, corners, LINES[:, None],
                                           t[None, :]))
        across = np.interp(LINES, s_v, v)
        u, du = _spread(s_u, t, self._seen(camera, level, extent, corners, t[None, :],
                                           across[:, None]))
        return u, du, v[:, None], dv

    @staticmethod
    def _seen(camera, level, extent, corners, u, v):
        """The screen length (NDC, `_on_screen`) of the span's lines from (u, v) along the
        sampled axis (the one of length > 1), summed over the lines and three heights (the
        mean sea's counting as much as the other two)."""
        hom = ((1.0 - u) * (1.0 - v))[..., None] * corners[0] + (u * (1.0 - v))[..., None] * \
            corners[1] + ((1.0 - u) * v)[..., None] * corners[2] + (u * v)[..., None] * corners[3]
        seen = 0.0
        for z, weight in ((level - 0.5 * extent.lower, 0.25), (level, 0.5),
                          (level + 0.5 * extent.upper, 0.25)):
            clip = np.stack([hom[..., 0], hom[..., 1], hom[..., 3] * z, hom[..., 3]],
                            axis=-1) @ camera.viewproj.T
            front = clip[..., 3] > 0.0
            with np.errstate(divide="ignore", invalid="ignore"):
                ndc = np.where(front[..., None],
                               clip[..., :2] / np.where(front, clip[..., 3], 1.0)[..., None], 0.0)
            both = front[:, 1:] & front[:, :-1]
            # Points within NEAR_EYE of the span's reach from the eye (w) project with the
            # cancellation of a plane through it: faded out, not trusted.
            w = np.where(front, clip[..., 3], 0.0)
            trust = np.clip(np.minimum(w[:, 1:], w[:, :-1]) / (NEAR_EYE * w.max() + 1e-300),
                            0.0, 1.0)
            seen = seen + weight * np.where(both, trust * _on_screen(ndc[:, :-1], ndc[:, 1:]),
                                            0.0).sum(axis=0)
        return seen

    @property
    def horizon_y(self):
        """NDC y of S_base's horizon for a level perspective projector (None otherwise).

        The ray through NDC (x, y) has direction x right + y up + forward, whose z is
        y up_z + forward_z when the projector is not rolled.
        """
        right_z, up_z = self.view[0, 2], self.view[1, 2]
        if self.orthographic or right_z != 0.0 or up_z == 0.0:
            return None
        return -self.forward[2] / up_z

    def corner_points(self, level):
        """Homogeneous intersections of the four corner lines with S_base (§2.4 step 6, App. A).

        Rows are the grid corners (u, v) = (0, 0), (1, 0), (0, 1), (1, 1). A corner's line is the
        projector's ray through its NDC (x, y) in the span (App. A's line of M_projector's images
        of the grid point at every depth): from the eye along d = x right + y up + forward
        (perspective), or from eye + s, s = x right + y up, along forward f (orthographic). With
        S_base h below the eye, the line meets it at eye + d / w, w = -d_z / h, and at
        eye + s - (h + s_z) / f_z f: both affine in (u, v), so bilinear interpolation of the
        corners is exactly the per-vertex intersection (§3.1.1).

        Taken relative to the eye, no rounding is amplified beyond the ray's own conditioning.
        App. A's form took each line's direction as the difference of its points at two depths
        1 m apart, whose coordinates reach the span's size: an orthographic span of 1e8 m (a 1e9 m
        far clip) lost 0.87 of the 1e-7 of the reach that the stability suite allows the float64
        maths, the perspective form ~1e-16 of the span's NDC over h.
        """
        x0, x1, y0, y1 = self.span
        u, v = np.array([[0.0, 1.0, 0.0, 1.0], [0.0, 0.0, 1.0, 1.0]])[:, :, None]
        x, y = x0 + u * (x1 - x0), y0 + v * (y1 - y0)  # as for a vertex at (u, v)
        right, up, back = self.view[:3, :3]  # rows of a rotation
        h = self.position[2] - level
        c = np.empty((4, 4))
        if self.orthographic:
            s = x * right + y * up
            c[:, :3] = s - ((h + s[:, 2]) / -back[2])[:, None] * -back
            c[:, 3] = 1.0
        else:
            c[:, :3] = x * right + y * up - back
            c[:, 3] = -c[:, 2] / h
        c[:, :3] += c[:, 3:] * self.position
        return c


def heading_vector(camera):
    """The unnormalised heading; its length is small only near the singular orientations."""
    f, u = camera.forward, camera.up
    return _horizontal(f) - f[2] * _horizontal(u)


def heading(camera):
    """A horizontal direction for the projector, continuous in the camera's orientation.

    It is the view vector's horizontal part, plus the camera's up vector's horizontal part as the
    view turns vertical, so looking straight down or up the grid follows the screen (any roll).
    No continuous choice exists for every orientation; this one is singular only for an upside-down
    camera pitched about 51.8 degrees, where the fallback below applies.
    """
    f, u = camera.forward, camera.up
    for candidate in (heading_vector(camera), _horizontal(f), _horizontal(u),
                      _horizontal(camera.right)):
        n = np.linalg.norm(candidate)
        if n > 1e-9:
            return candidate / n
    return np.array([0.0, 1.0, 0.0])


def aim_point(camera, level, height):
    """Where the projector looks, as a horizontal offset from the camera (§2.4.1).

    Method 1: where the view vector, mirrored towards S_base if it looks away, meets S_base.
    Method 2: a point METHOD2_DISTANCE * height ahead, dropped onto S_base. The weight of method 1
    is min(1, METHOD1_GAIN |view_z|), so its point, which runs off to infinity at the horizon,
    enters the blend with a bounded product and the aim stays continuous through the horizon.
    """
    f = camera.forward
    fz = abs(f[2])
    h_cam = abs(camera.position[2] - level)
    w = min(1.0, METHOD1_GAIN * fz)
    method1 = h_cam * (METHOD1_GAIN if fz * METHOD1_GAIN <= 1.0 else 1.0 / fz)  # = w * h_cam / fz
    return ((1.0 - w) * METHOD2_DISTANCE * height + method1) * _horizontal(f)


def _standing_back(camera, level, bound, height, g, base_points):
    """How far the projector stands back along its heading `g` from above the camera.

    V_visible reaches under a camera that is low against the sea's reach (`bound`), and a projector
    right above it would spend most of its rows on those points. Standing back, it sees none of
    them steeper below it than the camera's steepest view ray or STEEPEST. Fully for a camera up
    to STAND_BACK - 1 times `bound` above the water, fading out by STAND_BACK times, and only
    while the camera looks along `g` (not for one upside down past straight down, whose heading
    points behind its view); under the water by symmetry.
    """
    if camera.orthographic or bound <= 0.0 or len(base_points) == 0:
        return 0.0
    along = float(camera.forward[:2] @ g[:2])
    low = float(np.clip(STAND_BACK - abs(camera.position[2] - level) / bound, 0.0, 1.0)
                * np.clip(4.0 * along, 0.0, 1.0))
    if low == 0.0:
        return 0.0
    rays = camera.corners[4:] - camera.corners[:4]  # steepest toward or away from the water
    steepest = max(float(np.abs(np.arctan2(rays[:, 2], np.hypot(rays[:, 0], rays[:, 1]))).max()),
                   STEEPEST)
    nearest = float(((base_points[:, :2] - camera.position[:2]) @ g[:2]).min())
    return low * max(0.0, height / np.tan(steepest) - nearest)


def aim_projector(camera, level, bound, elevation, base_points):
    """Place and aim the projector for `camera` (§2.4 step 3, §2.4.1, §2.5).

    `base_points` are the V_visible points projected onto S_base; the pitch is kept in the interval
    where none of them is behind or beside the projector.
    """
    # The floor keeps the projector above a zero-thickness sea, at 1e-6 of the frustum's reach so
    # grazing intersections stay well conditioned in float64, and at 1e-7 of the coordinates'
    # size, so the projector's height is not lost in their rounding (a 1 cm frustum 40 m from
    # the origin). The reach is the camera's own (not V_visible's, which jumps when the sea is
    # seen edge-on), so the floor moves smoothly.
    reach = float(np.abs(camera.corners - camera.position).max())
    floor = max(1e-6 * reach, 1e-7 * (abs(level) + float(np.abs(camera.position).max())))
    height = max(abs(camera.position[2] - level), bound + elevation, floor)
    eye = np.array([camera.position[0], camera.position[1], level + height])
    g = heading(camera)
    back = _standing_back(camera, level, bound, height, g, base_points)
    eye[:2] -= back * g[:2]
    right = np.array([g[1], -g[0], 0.0])  # g x UP
    aim = aim_point(camera, level, height) @ g + back
    pitch = np.arctan2(height, aim)  # angle below the horizon, in (0, pi)
    lo, hi = MARGIN_ANGLE, np.pi - MARGIN_ANGLE
    if not camera.orthographic:
        rel = base_points - eye
        d = rel @ g
        rho = np.hypot(d, height)
        phi = np.arctan2(height, d)
        c = np.sin(MARGIN_ANGLE) * np.linalg.norm(rel, axis=1) / rho
        delta = np.arccos(np.minimum(c, 1.0))
        lo = max(lo, float((phi - delta).max()))
        hi = min(hi, float((phi + delta).min()))
    pitch = float(np.clip(pitch, lo, hi)) if lo <= hi else np.pi / 2.0
    forward = np.cos(pitch) * g - np.sin(pitch) * UP
    up = np.sin(pitch) * g + np.cos(pitch) * UP
    return Projector.looking(eye, right, up, forward, camera.orthographic)
