"""Blender tests: bpy from PyPI in background mode, the extension installed from its built zip
into a private user directory (as a user installs it), and a fresh empty file for every test."""

import os
import tempfile

# Before bpy is imported: keep the tests away from the real user's extensions and preferences.
USER = tempfile.mkdtemp(prefix="projgrid-user-")
os.environ["BLENDER_USER_RESOURCES"] = USER

import bpy  # noqa: E402
import pytest  # noqa: E402

from tools.demo import MODULE, install  # noqa: E402
from tools.package import build  # noqa: E402

from .helpers import RENDER_RES, add_camera, add_ocean, spectral_sea  # noqa: E402


@pytest.fixture(scope="session")
def extension_zip(tmp_path_factory):
    return build(str(tmp_path_factory.mktemp("dist")))


@pytest.fixture(scope="session", autouse=True)
def extension(extension_zip):
    """The installed extension's package (bl_ext.user_default.projected_grid_ocean)."""
    import importlib

    install(extension_zip)
    bpy.ops.wm.save_userpref()  # so subprocesses (farm workers) start with it enabled
    return importlib.import_module(MODULE)


@pytest.fixture(autouse=True)
def fresh_file(extension):
    bpy.ops.wm.read_homefile(use_empty=True)
    yield
    bpy.ops.wm.read_homefile(use_empty=True)


@pytest.fixture
def bridge(extension):
    """The Blender layer's package (operators.bridge: scene, frame, state, ...)."""
    return extension.operators.bridge


@pytest.fixture
def state(bridge):
    """The runtime state of a surface: `state(obj).message` and the like."""
    return bridge.state.RUNTIME.state


@pytest.fixture
def moving():
    """A spectral ocean seen by a camera that moves over frames 1..3 (the bake tests')."""
    scene = bpy.context.scene
    cam = add_camera(scene)
    obj = add_ocean()
    obj.projgrid.render_resolution_x, obj.projgrid.render_resolution_y = RENDER_RES
    cam.keyframe_insert("location", frame=1)
    cam.location.x += 5.0
    cam.keyframe_insert("location", frame=3)
    scene.frame_start, scene.frame_end = 1, 3
    scene.frame_set(1)
    return scene, obj


@pytest.fixture
def sea():
    """A camera 6 m up looking along +Y a little down, and a spectral ocean at force 5."""
    return spectral_sea()
