"""The layering holds: the core runs without Blender, the node-tree builders take plain values,
and nothing imports back up (core <- Blender layer -> shaders)."""

import ast
import os
import pkgutil
import subprocess
import sys

import pytest

from tools.package import ROOT

CORE = os.path.join(ROOT, "projgrid_addon")
CORE_MODULES = sorted(m.name for m in pkgutil.iter_modules([CORE]) if not m.ispkg)


def imports(path):
    """Every module a file imports, relative imports written out from the repository root."""
    tree = ast.parse(open(path).read(), path)
    package = os.path.relpath(os.path.dirname(path), ROOT).replace(os.sep, ".").split(".")
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found |= {alias.name for alias in node.names}
        elif isinstance(node, ast.ImportFrom):
            base = package[:len(package) - node.level + 1] if node.level else []
            module = ".".join(base + ([node.module] if node.module else []))
            found |= {module} | {f"{module}.{alias.name}" for alias in node.names}
    return found


@pytest.mark.parametrize("module", CORE_MODULES)
def test_every_core_module_imports_and_runs_without_bpy(module):
    """Each core module on its own, with bpy blocked from import (a stray `import bpy` in any
    of them fails here, not only in the package's __init__)."""
    code = (f"import sys; sys.modules['bpy'] = None; sys.modules['mathutils'] = None; "
            f"import projgrid_addon.{module}; "
            f"assert not any(m.startswith(('bpy', 'mathutils')) and sys.modules[m] "
            f"for m in sys.modules)")
    subprocess.run([sys.executable, "-c", code], cwd=ROOT, check=True)


def test_the_core_runs_a_frame_without_bpy():
    code = ("import sys; sys.modules['bpy'] = None; import numpy as np; "
            "from projgrid_addon import Camera, HeightField, build_grid, look_at, perspective; "
            "from projgrid_addon.spectral_field import SpectralField; "
            "from projgrid_addon.spectrum import SeaState; "
            "c = Camera(look_at((0, 0, 5), (0, 50, 0)), perspective(1.0, 1.5, 0.1, 1e4)); "
            "r = build_grid(c, HeightField(), time=2.0, resolution=(17, 17)); "
            "assert r.visible and HeightField().shader_detail(*r.shader_octaves).scale > 0; "
            "s = SpectralField(SeaState(wind_speed=8.0), choppiness=1.0); "
            "assert build_grid(c, s, time=2.0, resolution=(17, 17)).base is not None")
    subprocess.run([sys.executable, "-c", code], cwd=ROOT, check=True)


@pytest.mark.parametrize("module", CORE_MODULES)
def test_the_core_imports_nothing_of_blenders_or_ours_above_it(module):
    found = imports(os.path.join(CORE, f"{module}.py"))
    upward = {m for m in found if m.split(".")[0] in ("bpy", "mathutils", "shaders",
                                                        "operators", "panels")
              or m.startswith("projgrid_addon.bridge")}
    assert not upward


@pytest.mark.parametrize("name", sorted(f for f in os.listdir(os.path.join(ROOT, "shaders"))
                                        if f.endswith(".py")))
def test_shaders_take_plain_values(name):
    """The node-tree builders import neither the core nor the Blender layer."""
    found = imports(os.path.join(ROOT, "shaders", name))
    assert not {m for m in found if m.startswith(("projgrid_addon", "operators", "panels"))}
