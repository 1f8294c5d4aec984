"""Reading a mesh file, and turning any accepted mesh input into validated arrays."""

from __future__ import annotations

import os

import numpy as np
import trimesh


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
