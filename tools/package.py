"""Build and validate the extension zip with the extension CLI shipped in the bpy wheel.

Usage: python tools/package.py [output_dir]   (prints the zip's path)
Used by `make package` and by the Blender tests, which install the zip as a user would.
"""

import glob
import os
import subprocess
import sys
import tomllib

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def blender_scripts():
    """The `scripts` directory of the bpy wheel installed for this Python."""
    import importlib.util

    spec = importlib.util.find_spec("bpy")
    if spec is None or not spec.submodule_search_locations:
        raise SystemExit("package: bpy is not installed for this Python (run `make package`)")
    base = list(spec.submodule_search_locations)[0]
    found = sorted(glob.glob(os.path.join(base, "*", "scripts")))
    if not found:
        raise SystemExit(f"package: no scripts directory in {base}")
    return found[-1]


def build(output_dir):
    scripts = blender_scripts()
    cli = os.path.join(scripts, "addons_core", "bl_pkg", "cli", "blender_ext.py")
    tags = os.path.join(scripts, "modules", "_bpy_internal", "extensions", "tags.py")
    with open(os.path.join(ROOT, "blender_manifest.toml"), "rb") as f:
        manifest = tomllib.load(f)
    os.makedirs(output_dir, exist_ok=True)
    zip_path = os.path.join(output_dir, f"{manifest['id']}-{manifest['version']}.zip")
    _run([sys.executable, cli, "build", "--source-dir", ROOT, "--output-filepath", zip_path,
          "--valid-tags", tags])
    _run([sys.executable, cli, "validate", zip_path, "--valid-tags", tags])
    return zip_path


def _run(command):
    done = subprocess.run(command, capture_output=True, text=True)
    if done.returncode:
        raise SystemExit(f"package: {command[2]} failed:\n{done.stdout}{done.stderr}")


if __name__ == "__main__":
    print(build(sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "dist")))
