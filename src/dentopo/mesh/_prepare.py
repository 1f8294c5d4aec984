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


def _all_unique_and_referenced(faces: np.ndarray, n_vertices: int) -> bool:
    """No two faces on the same three vertices, and every vertex in a face.

    Then trimesh's duplicate-face and unreferenced-vertex removal would change
    nothing, and are skipped (they cost more than the check on a small mesh).
    """
    if n_vertices >= 2**21 or np.bincount(faces.ravel(), minlength=n_vertices).min() == 0:
        return False  # no exact key below, or a vertex in no face
    corners = faces.astype(np.int64)
    low, high = corners.min(axis=1), corners.max(axis=1)
    middle = corners.sum(axis=1) - low - high
    key = np.sort((low * n_vertices + middle) * n_vertices + high)
    return not np.any(key[1:] == key[:-1])


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
    """:func:`clean` for arrays that :func:`as_arrays` has validated."""
    scale = length_scale(vertices, faces)
    mesh = trimesh.Trimesh(vertices=vertices, faces=faces, process=False)
    filled = _may_have_small_holes(faces, len(vertices))
    if filled:
        mesh.fill_holes()
    keep = nondegenerate_faces(mesh.vertices, mesh.faces, scale=scale)
    if filled or not (keep.all() and _all_unique_and_referenced(faces, len(vertices))):
        mesh.update_faces(keep)
        mesh.update_faces(mesh.unique_faces())
        mesh.remove_unreferenced_vertices()
    if len(mesh.faces) == 0:
        raise ValueError("cleaning left the mesh empty: every face is degenerate")
    if len(mesh.vertices) < 4:
        raise ValueError(f"cleaning left {len(mesh.vertices)} vertices; at least 4 are needed")
    return mesh


def _face_cross(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Each face's ``(b - a) x (c - a)``: twice its area times its unit normal."""
    tri = vertices[faces]
    return np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])


def vertex_areas(vertices: np.ndarray, faces: np.ndarray, *, cross=None) -> np.ndarray:
    """One third of the total area of the faces around each vertex, shape (n,).

    `cross` is ``_face_cross(vertices, faces)`` if the caller has it already.
    """
    cross = _face_cross(vertices, faces) if cross is None else cross
    face_area = 0.5 * np.linalg.norm(cross, axis=1)
    # bincount adds in input order, as np.add.at does (same rounding), but fast
    return np.bincount(
        faces.ravel(), weights=np.repeat(face_area / 3.0, 3), minlength=len(vertices)
    )


def vertex_normals(vertices: np.ndarray, faces: np.ndarray, *, cross=None) -> np.ndarray:
    """Unit vertex normals: normalised sum of the unit normals of incident faces.

    `cross` is ``_face_cross(vertices, faces)`` if the caller has it already.
    """
    face_normal = _face_cross(vertices, faces) if cross is None else cross
    length = np.linalg.norm(face_normal, axis=1, keepdims=True)
    face_normal = np.divide(face_normal, length, out=np.zeros_like(face_normal), where=length > 0)
    # the three corners in turn, each in face order: the order np.add.at would add in
    corner = faces.T.ravel()
    normal = np.column_stack(
        [
            np.bincount(corner, weights=np.tile(face_normal[:, a], 3), minlength=len(vertices))
            for a in range(3)
        ]
    )
    length = np.linalg.norm(normal, axis=1, keepdims=True)
    return np.divide(normal, length, out=np.zeros_like(normal), where=length > 0)


def prepare(mesh) -> PreparedMesh:
    """Validate, clean and normalise any accepted mesh input (see `as_arrays`)."""
    vertices, faces = as_arrays(mesh)
    cleaned = _clean(vertices, faces)
    v = np.asarray(cleaned.vertices, dtype=np.float64)
    # vertex normals need neighbouring faces to agree; a no-op for consistent meshes
    f = orient_consistently(np.asarray(cleaned.faces, dtype=np.int64), len(v))
    cross = _face_cross(v, f)
    area_raw = vertex_areas(v, f, cross=cross)
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
        normals=vertex_normals(v, f, cross=cross),
        scale=float(scale),
    )
