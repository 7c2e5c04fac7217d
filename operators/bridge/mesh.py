"""Writing our meshes: the grid's topology once per resolution, then positions and per-vertex
attributes through the fast attribute path."""

import numpy as np

from ...projgrid_addon import corner_uv, grid_topology
from ...shaders import water

UV_MAP = "ProjectorUV"


def empty(mesh):
    """Our mesh emptied (never left half-written)."""
    if len(mesh.vertices) or len(mesh.polygons):
        mesh.clear_geometry()
        mesh.update()


def write_attribute(mesh, name, values, domain="POINT"):
    """Our attribute `name` on `domain` (per vertex by default) set to `values` ((N,) floats or
    (N, 3) vectors), or removed when None (so a branch another ocean keeps unmuted cannot show
    stale values)."""
    if values is None:
        if name in mesh.attributes:
            mesh.attributes.remove(mesh.attributes[name])
        return
    kind, field = ("FLOAT_VECTOR", "vector") if values.ndim == 2 else ("FLOAT", "value")
    old = mesh.attributes.get(name)
    if old is not None and (old.data_type != kind or old.domain != domain):
        mesh.attributes.remove(old)
    if name not in mesh.attributes:
        mesh.attributes.new(name, kind, domain)
    mesh.attributes[name].data.foreach_set(field, values.ravel())


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


def grid_arrays(result, to_local, foam, caustics, residual=None):
    """What `write_arrays` writes of a GridResult: {name: array}, or None for an empty mesh
    (a bake keeps each frame's so, bake.py)."""
    if not result.visible:
        return None
    positions = result.positions
    if not np.array_equal(to_local, np.eye(3)):
        positions = (positions @ to_local.T.astype(np.float32)).astype(np.float32)
    arrays = {"grid": np.array([*result.resolution, np.linalg.det(to_local) < 0.0]),
              "position": positions,
              water.LOD_ATTRIBUTE: np.minimum(result.lod, np.float32(64.0))}  # finite
    drift = result.drift if foam is not None or residual is not None else None  # foam's
    for name, values in ((water.FOAM_ATTRIBUTE, foam), (water.CAUSTIC_ATTRIBUTE, caustics),
                         (water.RESIDUAL_ATTRIBUTE, residual), (water.DRIFT_ATTRIBUTE, drift)):
        if values is not None:
            arrays[name] = values
    return arrays


def write_arrays(mesh, arrays):
    """`grid_arrays` into our mesh (None: emptied). The topology is built when the resolution
    or the mirroring changed; a failure part-way leaves the mesh empty, not half-written."""
    if arrays is None:
        empty(mesh)
        return
    nx, ny, flipped = (int(v) for v in arrays["grid"])
    try:
        if (len(mesh.vertices) != nx * ny or len(mesh.polygons) != (nx - 1) * (ny - 1)
                or (mesh.loops[1].vertex_index != 1) != bool(flipped)):
            set_topology(mesh, nx, ny, bool(flipped))
        mesh.attributes["position"].data.foreach_set("vector", arrays["position"].ravel())
        mesh.attributes[water.LOD_ATTRIBUTE].data.foreach_set(
            "value", arrays[water.LOD_ATTRIBUTE])
        for name in (water.FOAM_ATTRIBUTE, water.CAUSTIC_ATTRIBUTE, water.RESIDUAL_ATTRIBUTE,
                     water.DRIFT_ATTRIBUTE):
            write_attribute(mesh, name, arrays.get(name))
        mesh.update()
        mesh.vertices[0].co = mesh.vertices[0].co  # refresh the bounding box after the fast path
    except BaseException:
        empty(mesh)
        raise


# A baked puff's triangle: its corners this far (m) from the puff, their mean the puff itself.
PUFF_CORNERS = 1e-3 * np.array([[1.0, 0.0, 0.0], [-0.5, 0.866, 0.0], [-0.5, -0.866, 0.0]],
                               np.float32)


def write_puffs(mesh, local, values, faces=False):
    """The spray's puffs into our mesh: positions `local` (N, 3) float32 and per-puff
    attributes ({name: (N,)}), a vertex each; with `faces`, a small triangle each, centred on
    the puff, the attributes on its face (what a bake writes: USD keeps a mesh's face
    attributes, not a faceless one's point attributes)."""
    n, built = len(local), False
    if faces:
        corners = (local[:, None, :] + PUFF_CORNERS).reshape(-1, 3)
        if len(mesh.polygons) != n or len(mesh.vertices) != 3 * n:
            built = True
            mesh.clear_geometry()
            mesh.vertices.add(3 * n)
            mesh.loops.add(3 * n)
            mesh.polygons.add(n)
            mesh.loops.foreach_set("vertex_index", np.arange(3 * n, dtype=np.int32))
            mesh.polygons.foreach_set("loop_start", np.arange(0, 3 * n, 3, dtype=np.int32))
        mesh.attributes["position"].data.foreach_set("vector", corners.ravel())
    else:
        if len(mesh.vertices) != n or len(mesh.polygons):
            mesh.clear_geometry()
            mesh.vertices.add(n)
        mesh.attributes["position"].data.foreach_set("vector", local.ravel())
    for name, per_puff in values.items():
        write_attribute(mesh, name, per_puff, "FACE" if faces else "POINT")
    mesh.update(calc_edges=built)
