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


