"""Mesh input: reading, validation, cleaning and normalisation.

Everything that turns what a caller hands us (a ``trimesh.Trimesh``, a path, or
``(vertices, faces)`` arrays) into the cleaned, unit-area working copy that the
curvature computation uses.  The caller's object is never modified: all work is
done on copies.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import trimesh

from ._faces import first_faces, vertex_areas, vertex_normals
from ._read import as_arrays
from ._tolerance import length_scale, nondegenerate_faces
from ._topology import boundary_edges, orient_consistently


@dataclass(frozen=True)
class PreparedMesh:
    """A cleaned mesh and the derived quantities every later stage needs.

    Attributes
    ----------
    mesh : trimesh.Trimesh
        The cleaned mesh, in the caller's units (a private copy).
    points : (n, 3) float
        Vertices translated to their mean and scaled to unit total area.
    vertex_area_raw : (n,) float
        One third of the area of the faces using each vertex, in mesh units.
    vertex_area : (n,) float
        The same after scaling, so that it sums to one.
    normals : (n, 3) float
        Unit vertex normals: the normalised sum of incident unit face normals,
        after orienting the faces consistently (a no-op for the usual,
        consistently oriented mesh; it rescues meshes with flipped faces).
    scale : float
        The factor that maps mesh units to the unit-area scale.
    """

    mesh: trimesh.Trimesh
    points: np.ndarray
    vertex_area_raw: np.ndarray
    vertex_area: np.ndarray
    normals: np.ndarray
    scale: float


def _may_have_small_holes(faces: np.ndarray, n_vertices: int) -> bool:
    """False when trimesh's ``fill_holes`` provably adds nothing (it is slow on big meshes).

    ``fill_holes`` caps the 3- and 4-edge cycles of a cycle basis of the boundary
    edges.  If every boundary component is one simple loop (every boundary
    vertex on exactly two boundary edges) of at least 5 edges, the basis holds
    only those loops and nothing is added.
    """
    edges = boundary_edges(faces, n_vertices)
    if len(edges) == 0:
        return False  # watertight
    if len(edges) < 3:
        return True  # trimesh's own special case: let it decide
    degree = np.bincount(edges.ravel(), minlength=n_vertices)
    if np.any(degree[degree > 0] != 2):
        return True
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    graph = coo_matrix((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(n_vertices,) * 2)
    _, label = connected_components(graph, directed=False)
    loop_size = np.bincount(label[edges[:, 0]])
    return bool(np.any((loop_size > 0) & (loop_size < 5)))


def clean(vertices, faces) -> trimesh.Trimesh:
    """Clean a mesh as the published computation does, on a private copy.

    Fills trivially small holes (trimesh ``fill_holes``: three- and four-edge
    holes), drops degenerate faces (not higher than ``DEGENERATE_HEIGHT``
    median edge lengths: relative to the mesh, so the units do not matter),
    drops duplicate faces and unreferenced vertices.  The input is validated
    first (see :func:`as_arrays`): non-finite coordinates and indices outside
    the vertices are errors, never dropped.

    Raises
    ------
    ValueError
        If the input is invalid, or nothing usable is left.
    """
    return _clean(*as_arrays((vertices, faces)))


def _clean(vertices: np.ndarray, faces: np.ndarray) -> trimesh.Trimesh:
    """:func:`clean` for arrays that :func:`as_arrays` has validated.

    trimesh's steps (``fill_holes``, ``update_faces(nondegenerate_faces)``,
    ``update_faces(unique_faces())``, ``remove_unreferenced_vertices``) with
    the same result, in linear compiled passes (see ``_faces``).
    """
    scale = length_scale(vertices, faces)
    if _may_have_small_holes(faces, len(vertices)):
        filled = trimesh.Trimesh(vertices=vertices, faces=faces, process=False)
        filled.fill_holes()
        vertices = np.asarray(filled.vertices, dtype=np.float64)
        faces = np.asarray(filled.faces, dtype=np.int64)
    keep = nondegenerate_faces(vertices, faces, scale=scale)
    faces = faces[first_faces(faces, keep, len(vertices))]
    vertices, faces = _referenced(vertices, faces)
    if len(faces) == 0:
        raise ValueError("cleaning left the mesh empty: every face is degenerate")
    if len(vertices) < 4:
        raise ValueError(f"cleaning left {len(vertices)} vertices; at least 4 are needed")
    return trimesh.Trimesh(vertices=vertices, faces=faces, process=False)


def _referenced(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The vertices some face uses, in order, and the faces renumbered (trimesh's way)."""
    referenced = np.zeros(len(vertices), dtype=bool)
    referenced[faces] = True
    if referenced.all():
        return vertices, faces
    inverse = np.zeros(len(vertices), dtype=np.int64)
    inverse[referenced] = np.arange(np.count_nonzero(referenced))
    return vertices[referenced], inverse[faces]


def prepare(mesh) -> PreparedMesh:
    """Validate, clean and normalise any accepted mesh input (see `as_arrays`)."""
    vertices, faces = as_arrays(mesh)
    cleaned = _clean(vertices, faces)
    v = np.asarray(cleaned.vertices, dtype=np.float64)
    # vertex normals need neighbouring faces to agree; a no-op for consistent meshes
    f = orient_consistently(np.asarray(cleaned.faces, dtype=np.int64), len(v))
    area_raw = vertex_areas(v, f)
    total = float(area_raw.sum())
    if not total > 0:
        raise ValueError("the mesh has zero surface area")
    scale = 1.0 / np.sqrt(total)
    points = (v - v.mean(axis=0)) * scale
    return PreparedMesh(
        mesh=cleaned,
        points=points,
        vertex_area_raw=area_raw,
        vertex_area=area_raw / total,
        normals=vertex_normals(v, f),
        scale=float(scale),
    )
