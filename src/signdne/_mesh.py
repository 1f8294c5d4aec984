"""Mesh input: reading, validation, cleaning and normalisation.

Everything that turns what a caller hands us (a ``trimesh.Trimesh``, a path, or
``(vertices, faces)`` arrays) into the cleaned, unit-area working copy that the
curvature computation uses.  The caller's object is never modified: all work is
done on copies.
"""

from __future__ import annotations

import os
from dataclasses import dataclass

import numpy as np
import trimesh

from ._closure import boundary_edges, orient_consistently

#: Faces whose height is below this (in the mesh's own units) are dropped.
DEGENERATE_HEIGHT = 1e-8


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


def load_mesh(path: str | os.PathLike) -> trimesh.Trimesh:
    """Read a triangle mesh from a file as ``trimesh.load`` does by default.

    Parameters
    ----------
    path : str or path-like
        A file in any format trimesh reads (PLY, OBJ, STL, OFF, GLB, ...).
        Scenes with several meshes are concatenated.

    Returns
    -------
    trimesh.Trimesh
        The mesh, with duplicate vertices merged (trimesh's default).

    Raises
    ------
    FileNotFoundError
        If the file does not exist.
    ValueError
        If the file cannot be read, or holds no triangle mesh.
    """
    path = os.fspath(path)
    if not os.path.exists(path):
        raise FileNotFoundError(f"mesh file not found: {path!r}")
    if os.path.isdir(path):
        raise ValueError(f"{path!r} is a directory, not a mesh file")
    if os.path.getsize(path) == 0:
        raise ValueError(f"mesh file is empty: {path!r}")
    try:
        loaded = trimesh.load(path)
    except PermissionError:
        raise
    except Exception as exc:  # trimesh raises many types for corrupt files
        raise ValueError(f"could not read mesh file {path!r}: {exc}") from exc
    if isinstance(loaded, trimesh.Scene):
        geometries = [g for g in loaded.geometry.values() if isinstance(g, trimesh.Trimesh)]
        if not geometries:
            raise ValueError(f"{path!r} holds no triangle mesh")
        loaded = geometries[0] if len(geometries) == 1 else trimesh.util.concatenate(geometries)
    if not isinstance(loaded, trimesh.Trimesh):
        raise ValueError(
            f"{path!r} holds a {type(loaded).__name__}, not a triangle mesh (no faces)"
        )
    return loaded


def as_arrays(mesh) -> tuple[np.ndarray, np.ndarray]:
    """Return validated ``(vertices, faces)`` copies from any accepted mesh input.

    Parameters
    ----------
    mesh : trimesh.Trimesh, str, path-like, or (vertices, faces)
        The mesh.

    Returns
    -------
    vertices : (n, 3) float64
    faces : (m, 3) int64

    Raises
    ------
    TypeError
        If `mesh` is of an unsupported type.
    ValueError
        If the arrays are empty, non-finite, not triangles, or index out of range.
    """
    if isinstance(mesh, (str, os.PathLike)):
        mesh = load_mesh(mesh)
    if isinstance(mesh, trimesh.Trimesh):
        vertices, faces = mesh.vertices, mesh.faces
    elif isinstance(mesh, trimesh.PointCloud):
        raise ValueError("a point cloud has no faces: ariaDNE needs a triangle mesh")
    elif isinstance(mesh, (tuple, list)) and len(mesh) == 2:
        vertices, faces = mesh
    else:
        raise TypeError(
            "mesh must be a trimesh.Trimesh, a path to a mesh file, or a "
            f"(vertices, faces) pair; got {type(mesh).__name__}"
        )
    try:
        vertices = np.array(vertices, dtype=np.float64, copy=True)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"vertices must be numeric: {exc}") from exc
    faces_in = np.asarray(faces)
    if vertices.size == 0:
        raise ValueError("the mesh is empty: it has no vertices")
    if vertices.ndim != 2 or vertices.shape[1] != 3:
        raise ValueError(f"vertices must have shape (n, 3); got {vertices.shape}")
    if len(vertices) < 4:
        raise ValueError(f"the mesh has {len(vertices)} vertices; at least 4 are needed")
    if not np.all(np.isfinite(vertices)):
        bad = int(np.count_nonzero(~np.isfinite(vertices).all(axis=1)))
        raise ValueError(f"{bad} vertices have non-finite (NaN or infinite) coordinates")
    if faces_in.size == 0:
        raise ValueError("the mesh has no faces (a point cloud): a triangle mesh is needed")
    if faces_in.ndim != 2 or faces_in.shape[1] != 3:
        raise ValueError(f"faces must be triangles, shape (m, 3); got {faces_in.shape}")
    if not np.issubdtype(faces_in.dtype, np.integer):
        if not np.issubdtype(faces_in.dtype, np.floating) or not np.all(
            np.isfinite(faces_in) & (faces_in == np.round(faces_in))
        ):
            raise TypeError(f"faces must hold integer vertex indices; got {faces_in.dtype}")
    faces = faces_in.astype(np.int64, copy=True)
    if faces.min() < 0 or faces.max() >= len(vertices):
        raise ValueError(
            f"face indices must lie in [0, {len(vertices) - 1}]; "
            f"found {int(faces.min())}..{int(faces.max())}"
        )
    return vertices, faces


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


def clean(vertices: np.ndarray, faces: np.ndarray) -> trimesh.Trimesh:
    """Clean a mesh as the published computation does, on a private copy.

    Fills trivially small holes (trimesh ``fill_holes``: three- and four-edge
    holes), drops faces whose height is below ``DEGENERATE_HEIGHT``, drops
    duplicate faces, drops non-finite values and unreferenced vertices.

    Raises
    ------
    ValueError
        If nothing usable is left.
    """
    mesh = trimesh.Trimesh(vertices=vertices, faces=faces, process=False)
    if _may_have_small_holes(faces, len(vertices)):
        mesh.fill_holes()
    mesh.update_faces(mesh.nondegenerate_faces(height=DEGENERATE_HEIGHT))
    mesh.update_faces(mesh.unique_faces())
    mesh.remove_infinite_values()
    mesh.remove_unreferenced_vertices()
    if len(mesh.faces) == 0:
        raise ValueError("cleaning left the mesh empty: every face is degenerate")
    if len(mesh.vertices) < 4:
        raise ValueError(f"cleaning left {len(mesh.vertices)} vertices; at least 4 are needed")
    return mesh


def vertex_areas(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """One third of the total area of the faces around each vertex, shape (n,)."""
    tri = vertices[faces]
    face_area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
    # bincount adds in input order, as np.add.at does (same rounding), but fast
    return np.bincount(
        faces.ravel(), weights=np.repeat(face_area / 3.0, 3), minlength=len(vertices)
    )


def vertex_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Unit vertex normals: normalised sum of the unit normals of incident faces."""
    tri = vertices[faces]
    face_normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
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
    cleaned = clean(vertices, faces)
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
