"""The layering holds: the core runs without Blender, and the imports run one way,
panels -> operators -> shaders -> projgrid_addon, with no circle (imports inside functions
count: hiding one there does not make it go away)."""

import ast
import os
import subprocess
import sys

import pytest

from tools.package import ROOT

# The extension's folders, lowest layer first; a module imports its own layer's and lower ones.
LAYERS = ("projgrid_addon", "shaders", "operators", "panels")
MAX_LINES = 400


def modules():
    """{dotted name: path} of every module of the extension (the root package is "")."""
    found = {"": os.path.join(ROOT, "__init__.py")}
    for layer in LAYERS:
        for folder, _, files in os.walk(os.path.join(ROOT, layer)):
            package = os.path.relpath(folder, ROOT).replace(os.sep, ".")
            for name in files:
                if name.endswith(".py"):
                    found[package if name == "__init__.py" else f"{package}.{name[:-3]}"] = (
                        os.path.join(folder, name))
    return found


MODULES = modules()
CORE_MODULES = sorted(m for m in MODULES if m.startswith("projgrid_addon"))


def imports(name):
    """Every module `name` imports (relative imports written out from the repository root),
    as far as it is one of ours or a top-level name of another package."""
    path = MODULES[name]
    tree = ast.parse(open(path).read(), path)
    package = name.split(".") if path.endswith("__init__.py") else name.split(".")[:-1]
    package = [p for p in package if p]
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found |= {alias.name for alias in node.names}
        elif isinstance(node, ast.ImportFrom):
            base = package[:len(package) - node.level + 1] if node.level else []
            module = ".".join(base + ([node.module] if node.module else []))
            for alias in node.names:
                full = f"{module}.{alias.name}" if module else alias.name
                found.add(full if full in MODULES else module)
    return found


def ours(found):
    return {m for m in found if m in MODULES}


def layer(name):
    return LAYERS.index(name.split(".")[0]) if name else len(LAYERS)


GRAPH = {name: ours(imports(name)) - {name} for name in MODULES}


@pytest.mark.parametrize("module", CORE_MODULES)
def test_every_core_module_imports_and_runs_without_bpy(module):
    """Each core module on its own, with bpy blocked from import (a stray `import bpy` in any
    of them fails here, not only in the package's __init__)."""
    code = (f"import sys; sys.modules['bpy'] = None; sys.modules['mathutils'] = None; "
            f"import {module}; "
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
def test_the_core_imports_nothing_of_blenders(module):
    assert not {m for m in imports(module) if m.split(".")[0] in ("bpy", "mathutils")}


@pytest.mark.parametrize("module", sorted(MODULES))
def test_no_arrow_back_up(module):
    """A module imports its own layer's modules and lower ones only."""
    assert not {m for m in GRAPH[module] if layer(m) > layer(module)}


def test_no_import_circle():
    """No module reaches itself through the imports of ours (Tarjan's strongly connected
    components: every one is a single module)."""
    index, low, stack, on_stack, circles = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in GRAPH[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                circles.append(sorted(component))

    for v in sorted(GRAPH):
        if v not in index:
            visit(v)
    assert not circles


def test_a_circle_is_found():
    """The circle check above can fail: a made-up graph with one is caught."""
    global GRAPH
    kept = GRAPH
    GRAPH = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": set()}
    try:
        with pytest.raises(AssertionError):
            test_no_import_circle()
    finally:
        GRAPH = kept


@pytest.mark.parametrize("module", sorted(m for m in MODULES if m.count(".") == 1
                                          and m.startswith("operators.")))
def test_an_operator_calls_the_layer_below_not_another_operator(module):
    """One operator per file; what two operators share lives in the Blender layer beneath them
    (operators/bridge/), not in one of them."""
    assert not {m for m in GRAPH[module] if m.count(".") == 1 and m.startswith("operators.")}


@pytest.mark.parametrize("name", sorted(f for f in os.listdir(os.path.join(ROOT, "shaders"))
                                        if f.endswith(".py")))
def test_shaders_build_node_trees_and_write_nothing_per_frame(name):
    """The node-tree builders import the core's constants and formulas at most, never the
    Blender layer above them."""
    found = imports(f"shaders.{name[:-3]}" if name != "__init__.py" else "shaders")
    assert not {m for m in found if m.startswith(("operators", "panels"))}


def source_files():
    """Every Python file of the project: the extension's, its tests' and its tools'."""
    skip = {".git", "dist", "out", "__pycache__"}
    for folder, dirs, files in os.walk(ROOT):
        dirs[:] = [d for d in dirs if d not in skip and not d.startswith(".")]
        for name in files:
            if name.endswith(".py"):
                yield os.path.relpath(os.path.join(folder, name), ROOT)


@pytest.mark.parametrize("path", sorted(source_files()))
def test_no_source_file_over_400_lines(path):
    """Each file holds one job a reader can take in."""
    with open(os.path.join(ROOT, path)) as f:
        assert sum(1 for _ in f) <= MAX_LINES


def test_the_manifest_claims_the_oldest_blender_tested():
    """blender_version_min is the oldest Blender the tests run on (requirements/blender-*.txt):
    the code may use anything that version has (4.4's action slots, say)."""
    import glob
    import re
    import tomllib

    with open(os.path.join(ROOT, "blender_manifest.toml"), "rb") as f:
        claimed = tomllib.load(f)["blender_version_min"]
    tested = []
    for path in glob.glob(os.path.join(ROOT, "requirements", "*.txt")):
        tested += re.findall(r"^bpy==(\d+)\.(\d+)", open(path).read(), re.M)
    oldest = min((int(a), int(b)) for a, b in tested)
    assert claimed == f"{oldest[0]}.{oldest[1]}.0"
