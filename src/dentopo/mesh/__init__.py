"""The input surface: reading a mesh, validating it, cleaning it, and its topology.

Holds what every metric needs before it measures anything: reading a file or
accepting ``(vertices, faces)`` (``_read``; PLY by our strict reader, ``_ply``),
the checks every mesh passes (finite coordinates, face indices in range:
``_validate``), tolerances relative to the mesh's size for merging vertices and
dropping degenerate faces (``_tolerance``), the published cleaning steps and the
unit-area working copy (``_prepare``), per-face measures and vertex sums in
compiled passes (``_faces``), boundaries, consistent and outward orientation and
the capping of holes (``_topology``), and a spatial order of points (``_spatial``).

May import: numpy, scipy, numba, trimesh, and dentopo's private ``_jit`` (numba's
``njit`` with Ctrl-C held while a kernel compiles).  Nothing else of dentopo: it
is the bottom layer.
"""

from ._faces import first_faces
from ._ply import read_ply
from ._prepare import (
    Cleaning,
    Listed,
    PreparedMesh,
    clean,
    clean_listed,
    prepare,
    vertex_areas,
    vertex_normals,
)
from ._read import as_arrays, check_geometry, load_mesh
from ._spatial import spatial_order
from ._tolerance import (
    DEGENERATE_HEIGHT,
    MERGE_SPACING,
    length_scale,
    merge_vertices,
    nondegenerate_faces,
)
from ._topology import boundary_edges, close_holes, orient_consistently, outward_faces

__all__ = [
    "DEGENERATE_HEIGHT",
    "MERGE_SPACING",
    "Cleaning",
    "Listed",
    "PreparedMesh",
    "as_arrays",
    "boundary_edges",
    "check_geometry",
    "clean",
    "clean_listed",
    "close_holes",
    "first_faces",
    "length_scale",
    "load_mesh",
    "merge_vertices",
    "nondegenerate_faces",
    "orient_consistently",
    "outward_faces",
    "prepare",
    "read_ply",
    "spatial_order",
    "vertex_areas",
    "vertex_normals",
]
