"""Writing our meshes: the grid's topology once per resolution, then positions and per-vertex
attributes through the fast attribute path."""

import numpy as np

from ...shaders import water
from .. import corner_uv, grid_topology

UV_MAP = "ProjectorUV"


def empty(mesh):
    """Our mesh emptied (never left half-written)."""
    if len(mesh.vertices) or len(mesh.polygons):
        mesh.clear_geometry()
        mesh.update()


def write_attribute(mesh, name, values):
    """Our per-vertex float attribute `name` set to `values`, or removed when None (so a branch
    another ocean keeps unmuted cannot show stale values)."""
    if values is None:
        if name in mesh.attributes:
            mesh.attributes.remove(mesh.attributes[name])
        return
    if name not in mesh.attributes:
        mesh.attributes.new(name, "FLOAT", "POINT")
    mesh.attributes[name].data.foreach_set("value", values)


def set_topology(mesh, nx, ny, flipped=False):
    """Replace the mesh's geometry by an nx x ny grid of quads, counter-clockwise seen from
    above in the mesh's own space, or clockwise if `flipped` (an ocean object mirrored by a
    negative scale, so its faces are counter-clockwise, facing up, in the world)."""
    quads = grid_topology(nx, ny)
    if flipped:
        quads = np.ascontiguousarray(quads[:, ::-1])
    faces = len(quads)
    mesh.clear_geometry()
    mesh.vertices.add(nx * ny)
    mesh.loops.add(quads.size)
    mesh.polygons.add(faces)
    mesh.loops.foreach_set("vertex_index", quads.ravel())
    del quads
    mesh.polygons.foreach_set("loop_start", np.arange(0, 4 * faces, 4, dtype=np.int32))
    mesh.polygons.foreach_set("use_smooth", np.ones(faces, dtype=bool))
    mesh.update(calc_edges=True)
    uv = mesh.uv_layers.new(name=UV_MAP)
    uv.data.foreach_set("uv", corner_uv(nx, ny, flipped).ravel())
    if water.LOD_ATTRIBUTE not in mesh.attributes:
        mesh.attributes.new(water.LOD_ATTRIBUTE, "FLOAT", "POINT")


def write_grid(mesh, result, to_local, foam, caustics):
    """A GridResult and its per-vertex fields (None: none) into our mesh, positions taken into
    the object's space by `to_local`. The topology is built when the resolution or the mirroring
    changed; a failure part-way leaves the mesh empty, not half-written."""
    if not result.visible:
        empty(mesh)
        return
    nx, ny = result.resolution
    flipped = np.linalg.det(to_local) < 0.0
    try:
        if (len(mesh.vertices) != nx * ny or len(mesh.polygons) != (nx - 1) * (ny - 1)
                or (mesh.loops[1].vertex_index != 1) != flipped):
            set_topology(mesh, nx, ny, flipped)
        positions = result.positions
        if not np.array_equal(to_local, np.eye(3)):
            positions = (positions @ to_local.T.astype(np.float32)).astype(np.float32)
        mesh.attributes["position"].data.foreach_set("vector", positions.ravel())
        lod = np.minimum(result.lod, np.float32(64.0))  # finite for the shader
        mesh.attributes[water.LOD_ATTRIBUTE].data.foreach_set("value", lod)
        write_attribute(mesh, water.FOAM_ATTRIBUTE, foam)
        write_attribute(mesh, water.CAUSTIC_ATTRIBUTE, caustics)
        mesh.update()
        mesh.vertices[0].co = mesh.vertices[0].co  # refresh the bounding box after the fast path
    except BaseException:
        empty(mesh)
        raise
