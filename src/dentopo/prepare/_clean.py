"""The clean step: the published cleaning, then the largest piece by area (or every piece).

Cleaning is :func:`dentopo.mesh.clean` (coincident vertices merged on a grid
relative to the mesh's size, trivially small holes filled, degenerate and
duplicate faces and unreferenced vertices dropped: what every metric does
before it measures).  Scans carry specks and loose shells besides the crown;
with ``keep="largest"`` only the connected piece of largest area is kept (pieces
connected through a shared vertex are one piece).
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from ..mesh import clean, merge_vertices, vertex_areas
from ._result import Outcome


def face_pieces(faces: np.ndarray, n_vertices: int) -> tuple[int, np.ndarray]:
    """How many connected pieces the faces form, and each face's piece ((m,) int)."""
    rows = np.concatenate([faces[:, 0], faces[:, 1]])
    cols = np.concatenate([faces[:, 1], faces[:, 2]])
    graph = coo_matrix((np.ones(len(rows), dtype=np.int8), (rows, cols)), shape=(n_vertices,) * 2)
    count, label = connected_components(graph, directed=False)
    piece = label[faces[:, 0]]
    used = np.unique(piece)
    renumber = np.zeros(count, dtype=np.int64)
    renumber[used] = np.arange(len(used))
    return len(used), renumber[piece]


def largest_piece(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray, int]:
    """The piece of largest area (ties: the first), renumbered; and how many pieces were dropped."""
    count, piece = face_pieces(faces, len(vertices))
    if count <= 1:
        return vertices, faces, 0
    a, b, c = (vertices[faces[:, i]] for i in range(3))
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    keep = piece == int(np.argmax(np.bincount(piece, weights=area, minlength=count)))
    kept = faces[keep]
    used = np.zeros(len(vertices), dtype=bool)
    used[kept] = True
    index = np.cumsum(used) - 1
    return vertices[used], index[kept], count - 1


def run(vertices: np.ndarray, faces: np.ndarray, *, keep: str) -> Outcome:
    """Clean, then keep the largest piece (``keep="largest"``) or all (``"all"``)."""
    merged_vertices, merged_faces = merge_vertices(vertices, faces)
    cleaned = clean(merged_vertices, merged_faces)
    v = np.asarray(cleaned.vertices, dtype=np.float64)
    f = np.asarray(cleaned.faces, dtype=np.int64)
    pieces, _ = face_pieces(f, len(v))
    removed = 0
    removed_area = 0.0
    if keep == "largest" and pieces > 1:
        before = float(vertex_areas(v, f).sum())
        v, f, removed = largest_piece(v, f)
        removed_area = before - float(vertex_areas(v, f).sum())
    details = {
        "merged_vertices": len(vertices) - len(merged_vertices),
        "dropped_faces": len(faces) - len(cleaned.faces),
        "pieces": pieces,
        "removed_area": removed_area,
    }
    return Outcome(v, f, pieces_removed=removed, details=details)
