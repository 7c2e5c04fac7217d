"""The rendering camera (thesis §1.2.2, V_cam of §2.2) in Blender's conventions.

World is Z-up and right-handed; the camera looks down its local -Z with +Y up. `view` maps world to
camera space and `proj` camera to OpenGL clip space, as `Object.calc_matrix_camera` returns it, so
NDC is [-1, 1]^3 with z = -1 on the near plane.
"""

from functools import cached_property

import numpy as np

from .validation import finite, matrix4, positive

# Frustum corners in NDC; bit 0 of the index is x, bit 1 is y, bit 2 is z (near = 0, far = 1).
NDC_CORNERS = np.array(
    [[x, y, z, 1.0] for z in (-1.0, 1.0) for y in (-1.0, 1.0) for x in (-1.0, 1.0)]
)
# The 12 edges of the frustum as pairs of corner indices.
FRUSTUM_EDGES = np.array(
    [(a, a | bit) for bit in (1, 2, 4) for a in range(8) if not a & bit], dtype=np.intp
)


class Camera:
    """A perspective or orthographic camera given by its view and projection matrices."""

    def __init__(self, view, proj):
        self.view, self.inv_view = matrix4("view", view)
        self.proj, self.inv_proj = matrix4("proj", proj)
        row = self.proj[3] / np.abs(self.proj[3]).max()
        if np.abs(row - (0.0, 0.0, -1.0, 0.0)).max() <= 1e-12:
            self.orthographic = False
        elif np.abs(row - (0.0, 0.0, 0.0, 1.0)).max() <= 1e-12:
            self.orthographic = True
        else:
            raise ValueError("proj: neither a perspective nor an orthographic projection")
        self.viewproj = self.proj @ self.view
        axes = self.inv_view[:3, :3]
        lengths = np.linalg.norm(axes, axis=0)
        self.right, self.up, back = (axes / lengths).T
        self.forward = -back
        self.position = self.inv_view[:3, 3] / self.inv_view[3, 3]

    def ndc_to_world(self, ndc):
        """Map (..., 4) homogeneous NDC points to (..., 3) world points.

        Inverting view and projection separately keeps the far plane accurate for clip ranges as
        wide as 1e-4 .. 1e7.
        """
        cam = ndc @ self.inv_proj.T
        world = cam @ self.inv_view.T
        return world[..., :3] / world[..., 3:4]

    @cached_property
    def corners(self):
        """The 8 world-space corners of V_cam, indexed as NDC_CORNERS (read-only)."""
        corners = self.ndc_to_world(NDC_CORNERS)
        corners.setflags(write=False)
        return corners

    def rays(self, ndc_xy):
        """World-space rays through (..., 2) NDC points: near-plane origins and far-plane ends."""
        ndc_xy = np.asarray(ndc_xy, dtype=np.float64)
        ones = np.ones(ndc_xy.shape[:-1] + (1,))
        near = self.ndc_to_world(np.concatenate([ndc_xy, -ones, ones], axis=-1))
        far = self.ndc_to_world(np.concatenate([ndc_xy, ones, ones], axis=-1))
        return near, far

    def clip(self, points):
        """Clip-space coordinates (..., 4) of world points (..., 3)."""
        points = np.asarray(points, dtype=np.float64)
        return points @ self.viewproj[:, :3].T + self.viewproj[:, 3]

    def in_frustum(self, points, origin=None):
        """Boolean mask of points (N, 3) inside V_cam: world points, or points relative to
        `origin` (such as a grid's float32 positions, tested in float32 without a float64 copy).

        Computed as (4, N) rows: NumPy is far slower on (N, 4) arrays.
        """
        points = np.asarray(points)
        dtype = np.float32 if points.dtype == np.float32 else np.float64
        m = self.viewproj
        offset = m[:, 3] if origin is None else m[:, :3] @ np.asarray(origin) + m[:, 3]
        c = m[:, :3].astype(dtype) @ points.reshape(-1, 3).T
        c += offset.astype(dtype)[:, None]
        w = c[3]
        a = np.abs(c[:3])
        return ((w > 0) & (a[0] <= w) & (a[1] <= w) & (a[2] <= w)).reshape(points.shape[:-1])


def view_matrix(position, right, up, forward):
    """The world-to-camera matrix of a camera at `position` with orthonormal axes `right`, `up`
    and `forward` (it looks down its local -Z): rotation rows, then the rigid translation."""
    m = np.eye(4)
    m[0, :3], m[1, :3], m[2, :3] = right, up, -np.asarray(forward, dtype=np.float64)
    m[:3, 3] = -m[:3, :3] @ np.asarray(position, dtype=np.float64)
    return m


def look_at(eye, target, up=(0.0, 0.0, 1.0)):
    """A world-to-camera matrix for a camera at `eye` looking at `target` (for tests and tools)."""
    eye = np.asarray(eye, dtype=np.float64)
    f = np.asarray(target, dtype=np.float64) - eye
    f /= np.linalg.norm(f)
    r = np.cross(f, up)
    if np.linalg.norm(r) < 1e-12:
        r = np.cross(f, (0.0, 1.0, 0.0))
    r /= np.linalg.norm(r)
    return view_matrix(eye, r, np.cross(r, f), f)


def perspective(fov_y, aspect, near, far, shift=(0.0, 0.0)):
    """An OpenGL projection matrix like Blender's for a perspective camera (fov in radians)."""
    t = 1.0 / np.tan(fov_y / 2.0)
    m = np.zeros((4, 4))
    m[0, 0], m[1, 1] = t / aspect, t
    m[0, 2], m[1, 2] = 2.0 * shift[0], 2.0 * shift[1]
    m[2, 2] = -(far + near) / (far - near)
    m[2, 3] = -2.0 * far * near / (far - near)
    m[3, 2] = -1.0
    return m


SENSOR_FITS = ("AUTO", "HORIZONTAL", "VERTICAL")


def blender_projection(orthographic_camera, lens, ortho_scale, sensor, sensor_fit, shift, clip,
                       size, pixel_aspect):
    """Blender's camera projection (BKE_camera_params_compute_viewplane and _compute_matrix) in
    float64, from the camera's own settings.

    `Object.calc_matrix_camera` returns the same matrix in float32, whose depth terms round off
    once clip_end / clip_start passes about 1e7: the frustum's far corners become infinite. Here
    the view plane is taken at unit distance, so no term mixes clip_start into the lens.
    `lens` and `sensor` (width, height) are in millimetres, `size` the render size in pixels,
    `pixel_aspect` (x, y); a ValueError names the setting that is out of range.
    """
    near, far = (finite("clip", c) for c in clip)
    if not 0.0 < near < far:
        raise ValueError(f"clip: the camera's clip start ({near:g}) must be above 0 and below "
                         f"its clip end ({far:g})")
    winx, winy = (positive("render size", s) for s in size)
    aspx, aspy = (positive("pixel aspect", a) for a in pixel_aspect)
    if sensor_fit not in SENSOR_FITS:
        raise ValueError(f"sensor fit: must be one of {SENSOR_FITS}, got {sensor_fit!r}")
    ycor = aspy / aspx
    # AUTO fits the sensor width to the larger side of the frame.
    width = sensor[1] if sensor_fit == "VERTICAL" else sensor[0]
    if sensor_fit == "AUTO":
        sensor_fit = "HORIZONTAL" if aspx * winx >= aspy * winy else "VERTICAL"
    viewfac = winx if sensor_fit == "HORIZONTAL" else ycor * winy
    if orthographic_camera:
        pixel = positive("orthographic scale", ortho_scale) / viewfac
    else:
        pixel = positive("sensor size", width) / positive("focal length", lens) / viewfac
    dx, dy = (finite("shift", s) * viewfac for s in shift)
    left, right = pixel * (dx - 0.5 * winx), pixel * (dx + 0.5 * winx)
    bottom, top = pixel * (dy - 0.5 * ycor * winy), pixel * (dy + 0.5 * ycor * winy)
    m = np.zeros((4, 4))
    m[0, 0], m[1, 1] = 2.0 / (right - left), 2.0 / (top - bottom)
    if orthographic_camera:
        m[0, 3] = -(right + left) / (right - left)
        m[1, 3] = -(top + bottom) / (top - bottom)
        m[2, 2], m[2, 3], m[3, 3] = -2.0 / (far - near), -(far + near) / (far - near), 1.0
    else:
        m[0, 2] = (right + left) / (right - left)
        m[1, 2] = (top + bottom) / (top - bottom)
        m[2, 2], m[3, 2] = -(far + near) / (far - near), -1.0
        m[2, 3] = -2.0 * far * near / (far - near)
    return m


def rigid_view(world):
    """The world-to-camera matrix of a camera object's world matrix, scale removed (Blender
    renders from the normalised matrix), inverted exactly in float64."""
    world = np.asarray(world, dtype=np.float64)
    axes = world[:3, :3]
    lengths = np.sqrt((axes * axes).sum(axis=0))
    if not np.all(np.isfinite(world)) or np.any(lengths == 0.0):
        raise ValueError("camera: its scale is zero or its transform is not finite")
    normalised = world.copy()
    normalised[:3, :3] = axes / lengths
    rotation = normalised[:3, :3]
    if np.abs(rotation.T @ rotation - np.eye(3)).max() > 1e-6:  # sheared by a parent's scale
        return np.linalg.inv(normalised)
    return view_matrix(world[:3, 3], rotation[:, 0], rotation[:, 1], -rotation[:, 2])


def orthographic(scale, aspect, near, far, shift=(0.0, 0.0)):
    """An OpenGL projection matrix like Blender's for an orthographic camera of width `scale`."""
    m = np.eye(4)
    m[0, 0], m[1, 1] = 2.0 / scale, 2.0 * aspect / scale
    m[0, 3], m[1, 3] = -2.0 * shift[0], -2.0 * shift[1]
    m[2, 2] = -2.0 / (far - near)
    m[2, 3] = -(far + near) / (far - near)
    return m
