"""Node groups built once per Blender session. Blender updates a whole node tree after every
node and link added from Python, so a big group's build grows as the square of its size (the
water group's 635 nodes and 933 links: about 2 s, most of Add Ocean's time). The first build
in a process is written to a file of ours in the temporary folder; a later build, in this
file or another one opened since, appends it instead (milliseconds). The groups are functions
of our code alone, which a running process does not change, and the file goes with the
process."""

import atexit
import os
import tempfile

import bpy

_FILES = {}  # (name, version) -> (the file, the group's name in it)


def appended(name, version, tag):
    """A copy of the group `name` of `version` (its `tag` property) built earlier in this
    process, appended to this file, or None where none was kept."""
    kept = _FILES.get((name, version))
    if kept is None or not os.path.exists(kept[0]):
        return None
    path, stored = kept
    with bpy.data.libraries.load(path, link=False) as (_, into):
        into.node_groups = [stored]
    group = into.node_groups[0] if into.node_groups else None
    for library in [lib for lib in bpy.data.libraries  # the file's, once appended: unused
                    if os.path.normpath(bpy.path.abspath(lib.filepath)) == path]:
        bpy.data.libraries.remove(library)
    if group is not None and group.get(tag) != version:
        bpy.data.node_groups.remove(group)
        group = None
    return group


def keep(group, name, version):
    """Keep `group`, just built, for `appended` (a failed write keeps nothing: the next file
    builds it again)."""
    if (name, version) in _FILES:
        return
    handle, path = tempfile.mkstemp(prefix="projgrid-group-", suffix=".blend")
    os.close(handle)
    path = os.path.normpath(path)
    try:
        bpy.data.libraries.write(path, {group}, fake_user=False)
    except (OSError, RuntimeError):
        _remove(path)
        return
    if not _FILES:
        atexit.register(_forget)
    _FILES[name, version] = (path, group.name)


def _remove(path):
    try:
        os.remove(path)
    except OSError:
        pass


def _forget():
    for path, _ in _FILES.values():
        _remove(path)
    _FILES.clear()
