"""The camera from Blender's settings in float64, and the memory a grid needs."""

import numpy as np
import pytest

from projgrid_addon import Camera, HeightField, build_grid, look_at, memory, perspective
from projgrid_addon.camera import blender_projection, rigid_view


def lens_for(fov_x, sensor=36.0):
    return 0.5 * sensor / np.tan(0.5 * fov_x)


def test_perspective_matches_the_field_of_view():
    """A 36 mm sensor fitted horizontally to a 16:9 frame, lens for a 60° horizontal view: the
    same matrix as perspective() with the matching vertical field of view."""
    fov_x = np.radians(60.0)
    fov_y = 2.0 * np.arctan(np.tan(0.5 * fov_x) * 9.0 / 16.0)
    m = blender_projection(False, lens_for(fov_x), 1.0, (36.0, 24.0), "AUTO", (0.1, -0.2),
                           (0.1, 1e4), (1920, 1080), (1.0, 1.0))
    assert np.allclose(m, perspective(fov_y, 16.0 / 9.0, 0.1, 1e4, (0.1, -0.2 * 16 / 9)),
                       rtol=1e-12)


def test_sensor_fit_and_pixel_aspect():
    """AUTO fits the sensor width to the larger side; VERTICAL fits the sensor height to the
    frame's height; a pixel aspect of 2 stretches the frame as twice as many pixels would."""
    args = (False, 50.0, 1.0, (36.0, 24.0))
    tall = blender_projection(*args, "AUTO", (0, 0), (1, 10), (900, 1600), (1.0, 1.0))
    assert np.isclose(tall[1, 1], 2 * 50.0 / 36.0)  # the sensor width spans the height
    vertical = blender_projection(*args, "VERTICAL", (0, 0), (1, 10), (1600, 900), (1.0, 1.0))
    assert np.isclose(vertical[1, 1], 2 * 50.0 / 24.0)
    wide = blender_projection(*args, "AUTO", (0, 0), (1, 10), (800, 900), (2.0, 1.0))
    same = blender_projection(*args, "AUTO", (0, 0), (1, 10), (1600, 900), (1.0, 1.0))
    assert np.allclose(wide, same)


@pytest.mark.parametrize("clip", [(1e-6, 1e9), (0.1, 1e7), (1.0, 1e8), (1e-4, 2e4)])
def test_wide_clip_ranges_keep_finite_far_corners(clip):
    """What float32 loses: the far corners stay finite and at the clip end."""
    m = blender_projection(False, 35.0, 1.0, (36.0, 24.0), "AUTO", (0, 0), clip, (1920, 1080),
                           (1.0, 1.0))
    camera = Camera(look_at((0, 0, 10), (0, 100, 9)), m)
    far = camera.corners[4:]
    assert np.all(np.isfinite(camera.corners))
    depth = -(far - camera.position) @ camera.view[2, :3]
    # The depth row holds (f + n) / (f - n), whose float64 rounding is 1e-16 of f / n.
    assert np.allclose(depth, clip[1], rtol=max(1e-9, 1e-14 * clip[1] / clip[0]))
    f32 = m.astype(np.float32).astype(np.float64)  # what calc_matrix_camera returns
    with np.errstate(all="ignore"):
        try:
            lost = not np.all(np.isfinite(Camera(camera.view, f32).corners))
        except ValueError:
            lost = True
    if clip[1] / clip[0] > 1e8:
        assert lost


def test_orthographic():
    m = blender_projection(True, 50.0, 10.0, (36.0, 24.0), "AUTO", (0.25, 0.0), (0.5, 100.0),
                           (1000, 500), (1.0, 1.0))
    camera = Camera(np.eye(4), m)
    assert camera.orthographic
    xs = camera.corners[:, 0]
    assert np.isclose(xs.min(), -5.0 + 2.5) and np.isclose(xs.max(), 5.0 + 2.5)
    assert np.allclose(np.unique(camera.corners[:, 1]), (-2.5, 2.5))


@pytest.mark.parametrize("args, name", [
    (dict(clip=(1.0, 1.0)), "clip"), (dict(clip=(0.0, 10.0)), "clip"),
    (dict(lens=0.0), "focal length"), (dict(size=(0, 10)), "render size"),
    (dict(sensor_fit="DIAGONAL"), "sensor fit"), (dict(pixel_aspect=(1.0, -1.0)), "aspect"),
])
def test_bad_camera_settings_name_the_setting(args, name):
    kw = dict(orthographic_camera=False, lens=50.0, ortho_scale=1.0, sensor=(36.0, 24.0),
              sensor_fit="AUTO", shift=(0, 0), clip=(0.1, 100.0), size=(64, 36),
              pixel_aspect=(1.0, 1.0))
    with pytest.raises(ValueError, match=name):
        blender_projection(**{**kw, **args})


def test_rigid_view_is_exact_far_from_the_origin_and_ignores_scale():
    world = np.eye(4)
    c, s = np.cos(0.3), np.sin(0.3)
    world[:3, :3] = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]) * 3.0  # scaled by 3
    world[:3, 3] = (2.5e6, -1e6, 12.0)
    view = rigid_view(world)
    assert np.allclose(view[:3, :3] @ view[:3, :3].T, np.eye(3), atol=1e-15)
    assert np.allclose(view @ np.r_[world[:3, 3], 1.0], (0, 0, 0, 1), atol=1e-9)
    with pytest.raises(ValueError, match="scale is zero"):
        rigid_view(np.diag([0.0, 1.0, 1.0, 1.0]))


def test_memory_check_refuses_before_allocating():
    memory.check_grid((257, 513), True, "render", available=10 * 2**30)
    with pytest.raises(ValueError, match=r"a 8193x4095 grid needs about .* GB.*render grid"):
        memory.check_grid((8193, 4095), True, "render", available=4 * 2**30)
    assert memory.grid_bytes((100, 100), True) > memory.grid_bytes((100, 100), False) > 0
    free = memory.available_bytes()
    assert free is None or free > 0


def test_a_large_grid_fits_the_measured_bytes_per_vertex():
    """The core's share of a rebuild (its arrays and its passes' buffers) stays inside the
    budget the memory check assumes for a whole rebuild."""
    import tracemalloc

    camera = Camera(look_at((0, 0, 6), (0, 100, 0)),
                    perspective(np.radians(40), 16 / 9, 0.1, 2e4))
    hf = HeightField()
    build_grid(camera, hf, resolution=(64, 64))  # warm the tiles' caches
    tracemalloc.start()
    n = 1025 * 2049
    build_grid(camera, hf, time=1.0, resolution=(1025, 2049))
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert peak / n < memory.REBUILD_BYTES
