"""Per-face measures in compiled single passes: degenerate and duplicate faces, vertex sums.

Each function here computes exactly what a numpy expression of whole arrays
computes (the same operations in the same order, so the same bits), in one
pass over the faces without ``(m, 3, 3)`` intermediates: on a mesh of
millions of faces the numpy forms spend most of their time and memory
gathering ``vertices[faces]``.  The numpy form each one reproduces is given in
its docstring; tests/test_large_mesh_paths.py checks that the bits agree.

Sums into vertices run in one fixed order (as ``numpy.bincount`` adds them),
so the results do not depend on threads.  Arrays are allocated by the caller
(a returned array would be boxed with a little Python code, where a Ctrl-C
that arrived meanwhile would be raised and crash the caller).
"""

from __future__ import annotations

import numpy as np

from .._jit import njit
from ._topology import FEW_CORNERS, corners_by_vertex, has_long_group, stable_order


@njit(cache=True, inline="always")
def corner_cross(vertices, i, j, k):  # pragma: no cover
    """``(v_j - v_i) x (v_k - v_i)`` as three numbers, in the precision of `vertices`.

    As ``np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])`` computes it
    for the face ``(i, j, k)``: the same operations in the same order (the
    kernels that inline it are compiled without ``fastmath``).
    """
    ax = vertices[j, 0] - vertices[i, 0]
    ay = vertices[j, 1] - vertices[i, 1]
    az = vertices[j, 2] - vertices[i, 2]
    bx = vertices[k, 0] - vertices[i, 0]
    by = vertices[k, 1] - vertices[i, 1]
    bz = vertices[k, 2] - vertices[i, 2]
    return ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx


@njit(cache=True, inline="always")
def normalise_rows(rows):  # pragma: no cover
    """Each row of the (n, 3) `rows` divided by its length, in place; a zero row stays zero."""
    for v in range(rows.shape[0]):
        x, y, z = rows[v, 0], rows[v, 1], rows[v, 2]
        length = np.sqrt(x * x + y * y + z * z)
        if length > 0:
            rows[v, 0] = x / length
            rows[v, 1] = y / length
            rows[v, 2] = z / length
        else:
            rows[v, 0] = 0.0
            rows[v, 1] = 0.0
            rows[v, 2] = 0.0


@njit(cache=True)
def _high_faces(vertices, faces, height, keep):  # pragma: no cover
    for f in range(faces.shape[0]):
        i, j, k = faces[f, 0], faces[f, 1], faces[f, 2]
        ax = vertices[j, 0] - vertices[i, 0]
        ay = vertices[j, 1] - vertices[i, 1]
        az = vertices[j, 2] - vertices[i, 2]
        bx = vertices[k, 0] - vertices[i, 0]
        by = vertices[k, 1] - vertices[i, 1]
        bz = vertices[k, 2] - vertices[i, 2]
        dx = vertices[k, 0] - vertices[j, 0]
        dy = vertices[k, 1] - vertices[j, 1]
        dz = vertices[k, 2] - vertices[j, 2]
        cx = ay * dz - az * dy
        cy = az * dx - ax * dz
        cz = ax * dy - ay * dx
        area = np.sqrt(cx * cx + cy * cy + cz * cz) / 2.0
        high = True
        for length in (
            np.sqrt(ax * ax + ay * ay + az * az),
            np.sqrt(bx * bx + by * by + bz * bz),
        ):
            box = 0.0
            if length > height:
                box = (area * 2) / length
            high = high and box > height
        keep[f] = high


def high_faces(vertices: np.ndarray, faces: np.ndarray, height: float) -> np.ndarray:
    """Which faces are higher than `height` over both edges from their first corner.

    The numpy form (trimesh's ``nondegenerate_faces`` measure)::

        tri = vertices[faces]
        a, b = tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
        area = np.sqrt((np.cross(a, tri[:, 2] - tri[:, 1]) ** 2).sum(axis=1)) / 2.0
        keep = all over (a, b): box > height, where
            length = (edge**2).sum(axis=1) ** 0.5
            box = (area * 2) / length where length > height, else 0

    Parameters
    ----------
    vertices : (n, 3) float
    faces : (m, 3) int
    height : float

    Returns
    -------
    (m,) bool
    """
    keep = np.empty(len(faces), dtype=np.bool_)
    _high_faces(_floats(vertices), _indices(faces), float(height), keep)
    return keep


@njit(cache=True)
def _first_faces(faces, keep, start, corner, first):  # pragma: no cover
    for f in range(faces.shape[0]):
        first[f] = keep[f]
        if not keep[f]:
            continue
        p, q, r = _sorted3(faces[f, 0], faces[f, 1], faces[f, 2])
        if start[p + 1] - start[p] > FEW_CORNERS:
            continue  # a long group: sorted below
        for i in range(start[p], start[p + 1]):
            g = corner[i] // 3
            if g >= f:
                break  # the corners of a vertex are in face order
            if keep[g]:
                s, t, u = _sorted3(faces[g, 0], faces[g, 1], faces[g, 2])
                if s == p and t == q and u == r:
                    first[f] = False
                    break


@njit(cache=True)
def _first_faces_long(faces, keep, start, corner, first):  # pragma: no cover
    """``_first_faces`` for the faces whose lowest vertex has many corners (a fan on one
    vertex): sorted by their other two vertices, each run of equal ones in face order (a
    stable sort).  A kernel of its own, called only where there is such a vertex: a crown
    has none, and compiles neither it nor the sort (0.5 s on a fresh install)."""
    n = start.shape[0] - 1
    for p in range(n):
        lo = start[p]
        hi = start[p + 1]
        if hi - lo <= FEW_CORNERS:
            continue
        group = np.empty(hi - lo, np.int64)
        key = np.empty(hi - lo, np.int64)
        count = 0
        for i in range(lo, hi):
            g = corner[i] // 3
            if not keep[g] or (i > lo and corner[i - 1] // 3 == g):
                continue  # dropped, or its corner at p seen already
            s, t, u = _sorted3(faces[g, 0], faces[g, 1], faces[g, 2])
            if s != p:
                continue  # compared at its own lowest vertex
            group[count] = g
            key[count] = t * n + u
            count += 1
        order = np.empty(count, np.int64)
        stable_order(key[:count], order)
        for k in range(1, count):
            if key[order[k]] == key[order[k - 1]]:
                first[group[order[k]]] = False


@njit(cache=True)
def _sorted3(a, b, c):  # pragma: no cover
    if a > b:
        a, b = b, a
    if b > c:
        b, c = c, b
    if a > b:
        a, b = b, a
    return a, b, c


def first_faces(faces: np.ndarray, keep: np.ndarray, n_vertices: int) -> np.ndarray:
    """Which of the kept faces is the first with its three vertices (in any order).

    The mask trimesh's ``unique_faces`` gives on ``faces[keep]``, in the frame
    of all the faces: ``True`` where ``keep`` is and no earlier kept face has
    the same vertex set.  Linear time: each face is compared with the faces
    around its lowest vertex.

    Parameters
    ----------
    faces : (m, 3) int
    keep : (m,) bool
    n_vertices : int

    Returns
    -------
    (m,) bool
    """
    faces = _indices(faces)
    start, corner, _ = corners_by_vertex(faces, n_vertices)
    first = np.empty(len(faces), dtype=np.bool_)
    keep = np.ascontiguousarray(keep, dtype=np.bool_)
    _first_faces(faces, keep, start, corner, first)
    if has_long_group(start):
        _first_faces_long(faces, keep, start, corner, first)
    return first


@njit(cache=True)
def _vertex_areas(vertices, faces, area):  # pragma: no cover
    for f in range(faces.shape[0]):
        i, j, k = faces[f, 0], faces[f, 1], faces[f, 2]
        cx, cy, cz = corner_cross(vertices, i, j, k)
        third = (0.5 * np.sqrt(cx * cx + cy * cy + cz * cz)) / 3.0
        area[i] += third
        area[j] += third
        area[k] += third


def vertex_areas(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """One third of the total area of the faces around each vertex, shape (n,).

    The numpy form::

        tri = vertices[faces]
        face_area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
        np.bincount(faces.ravel(), weights=np.repeat(face_area / 3.0, 3), minlength=n)
    """  # noqa: E501
    vertices = _floats(vertices)
    area = np.zeros(len(vertices))
    _vertex_areas(vertices, _indices(faces), area)
    return area


@njit(cache=True)
def _vertex_normals(vertices, faces, normal):  # pragma: no cover
    # the three corners in turn, each in face order: the order bincount adds in
    for c in range(3):
        for f in range(faces.shape[0]):
            i, j, k = faces[f, 0], faces[f, 1], faces[f, 2]
            cx, cy, cz = corner_cross(vertices, i, j, k)
            length = np.sqrt(cx * cx + cy * cy + cz * cz)
            if length > 0:
                v = faces[f, c]
                normal[v, 0] += cx / length
                normal[v, 1] += cy / length
                normal[v, 2] += cz / length
    normalise_rows(normal)


def vertex_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Unit vertex normals: normalised sum of the unit normals of incident faces.

    The numpy form::

        tri = vertices[faces]
        face_normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        face_normal /= its norm (0 where the norm is 0)
        normal[:, a] = np.bincount(faces.T.ravel(), weights=np.tile(face_normal[:, a], 3))
        normal /= its norm (0 where the norm is 0)

    A face of zero area adds nothing (adding its zero normal changes no bit).
    """
    vertices = _floats(vertices)
    normal = np.zeros((len(vertices), 3))
    _vertex_normals(vertices, _indices(faces), normal)
    return normal


def _floats(vertices) -> np.ndarray:
    return np.ascontiguousarray(vertices, dtype=np.float64)


def _indices(faces) -> np.ndarray:
    return np.ascontiguousarray(faces, dtype=np.int64).reshape(-1, 3)
