"""Tolerances relative to the mesh's own size: merging coincident vertices, degenerate faces.

trimesh judges "the same vertex" and "a degenerate face" in absolute units
(``tol.merge = 1e-8``): a tooth measured in metres had its real vertices merged
together, one measured in nanometres overflowed the rounding, and DNE depended
on the units.  Here both are measured against the mesh's **length scale**: the
median length of its faces' edges (edges of zero length left out).  A median is
robust: a stray vertex a million sizes away, or a few huge faces, do not move it.

* **Merging**: coordinates are rounded to a grid of spacing
  ``MERGE_SPACING * length scale`` laid from the median vertex (so moving the
  mesh moves the grid with it), and vertices on the same grid point become one.
  On the meshes of the published study (median edge 0.02 to 1.3 mesh units)
  this merges exactly what trimesh's ``merge_vertices`` merged.
* **Degenerate faces**: a face is dropped when its oriented bounding box (its
  two heights over the edges from its first corner, as trimesh measures it) is
  not above ``DEGENERATE_HEIGHT * length scale``.

With a typical median edge of 0.1 units both equal trimesh's 1e-8 units.
"""

from __future__ import annotations

import numpy as np

from ._faces import high_faces

#: Grid spacing for merging coincident vertices, in median edge lengths.
MERGE_SPACING = 1e-7

#: Faces not higher than this many median edge lengths are degenerate.
DEGENERATE_HEIGHT = 1e-7


#: Faces sampled (evenly through the face list) for the length scale of a large mesh.
SAMPLED_FACES = 100_000


def length_scale(vertices: np.ndarray, faces: np.ndarray) -> float:
    """The mesh's length scale: the median length of its faces' edges, zero lengths left out.

    On a mesh of more than ``SAMPLED_FACES`` faces, the edges of that many faces
    taken evenly through the face list (the same ones at any scale or position).

    Parameters
    ----------
    vertices : (n, 3) float
    faces : (m, 3) int

    Returns
    -------
    float
        0.0 when no face has an edge of positive, finite length.
    """
    vertices = np.asarray(vertices, dtype=np.float64)
    faces = np.asarray(faces)
    if len(faces) == 0:
        return 0.0
    if len(faces) > SAMPLED_FACES:
        faces = faces[np.linspace(0, len(faces) - 1, SAMPLED_FACES).astype(np.int64)]
    # each coordinate of each corner gathered on its own (contiguous arrays), and the
    # lengths as np.linalg.norm computes them, (dx*dx + dy*dy) + dz*dz: the same bits,
    # several times faster than norm over an (m, 3, 3) array of the corners
    lengths = np.empty((3, len(faces)))
    for axis in range(3):
        coordinate = np.ascontiguousarray(vertices[:, axis])
        a, b, c = (np.take(coordinate, faces[:, k]) for k in range(3))
        for edge, (head, tail) in enumerate(((a, c), (b, a), (c, b))):
            step = head - tail
            if axis == 0:
                np.multiply(step, step, out=lengths[edge])
            else:
                lengths[edge] += step * step
    lengths = np.sqrt(lengths).ravel()
    lengths = lengths[(lengths > 0) & np.isfinite(lengths)]
    return float(np.median(lengths)) if len(lengths) else 0.0


def merge_vertices(
    vertices: np.ndarray, faces: np.ndarray, *, scale: float | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Merge coincident vertices and drop those in no face, as trimesh's default loading does.

    Vertices on the same point of a grid of spacing ``MERGE_SPACING * scale``
    (laid from the median vertex) become the first of them; the kept vertices
    stay in their order.

    Parameters
    ----------
    vertices : (n, 3) float
        Finite coordinates.
    faces : (m, 3) int
        Indices into `vertices`, in range.
    scale : float, optional
        The length scale; :func:`length_scale` by default.

    Returns
    -------
    vertices : (k, 3) float64
        A new array.
    faces : (m, 3) int64
        A new array.
    """
    vertices = np.asarray(vertices, dtype=np.float64)
    faces = np.asarray(faces, dtype=np.int64)
    n = len(vertices)
    if len(faces) == 0:
        return vertices[:0].copy(), faces.reshape(0, 3).copy()
    referenced = np.zeros(n, dtype=bool)
    referenced[faces] = True
    used = np.flatnonzero(referenced)
    points = vertices[used]
    if scale is None:
        scale = length_scale(vertices, faces)
    spacing = MERGE_SPACING * scale
    if spacing > 0 and np.isfinite(spacing):
        keys = np.round((points - np.median(points, axis=0)) / spacing)
    else:  # no edge of positive length: only exact duplicates are one vertex
        keys = points
    order, starts = _groups(keys)
    if starts.all() and len(used) == n:
        return vertices.copy(), faces.copy()  # nothing to merge, nothing unused
    group = np.cumsum(starts) - 1
    first = order[starts]  # lowest index of each group
    by_first = np.argsort(first)  # groups in the order of their first vertex
    rank = np.empty(len(first), dtype=np.int64)
    rank[by_first] = np.arange(len(first))
    new_index = np.zeros(n, dtype=np.int64)
    new_index[used[order]] = rank[group]
    return vertices[used[first[by_first]]], new_index[faces]


def _groups(keys: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A stable order that puts equal rows of `keys` together, and where each group starts.

    Sorts one number per row (a fixed combination of the three, equal for equal
    rows); rows that share the number but differ (a rare collision) fall back
    to sorting the rows themselves.
    """
    combined = keys[:, 0] * 0.7548776662466927 + keys[:, 1] * 0.5698402909980532 + keys[:, 2]
    order = np.argsort(combined, kind="stable")
    ordered = combined[order]
    starts = np.ones(len(order), dtype=bool)
    starts[1:] = ordered[1:] != ordered[:-1]
    same = np.flatnonzero(~starts)  # rows equal in the combination to the one before
    if len(same) and np.any(keys[order[same]] != keys[order[same - 1]]):
        order = np.lexsort(keys.T[::-1])  # a collision: sort the rows (stable)
        ordered = keys[order]
        starts[1:] = np.any(ordered[1:] != ordered[:-1], axis=1)
    return order, starts


def nondegenerate_faces(
    vertices: np.ndarray, faces: np.ndarray, *, scale: float | None = None
) -> np.ndarray:
    """Which faces are higher than ``DEGENERATE_HEIGHT * scale`` (trimesh's measure).

    A face ``(a, b, c)`` is kept when the edges ``ab`` and ``ac`` are longer than
    the height and so are the face's heights over them (``2 * area / length``):
    trimesh's ``nondegenerate_faces(height)`` with the height relative to the mesh
    (computed in one compiled pass, see ``_faces.high_faces``).

    Parameters
    ----------
    vertices : (n, 3) float
    faces : (m, 3) int
    scale : float, optional
        The length scale; :func:`length_scale` by default.

    Returns
    -------
    (m,) bool
    """
    if scale is None:
        scale = length_scale(vertices, faces)
    return high_faces(vertices, faces, DEGENERATE_HEIGHT * scale)
