"""The crop step: keep what lies above a plane, cutting straddling faces exactly.

The plane (it runs after orient, so "up" is +z):

* ``below=H``: the plane ``z = z_min + H`` (H above the lowest point), normal +z;
* ``fraction=F``: the plane ``z = z_max - F (z_max - z_min)`` (the top F of the
  crown's height), normal +z;
* ``plane=(px, py, pz, nx, ny, nz)``: the plane through the point with that
  normal, in the mesh's coordinates after orient; the side the normal points
  to is kept.

The cut is trimesh's ``trimesh.intersections.slice_faces_plane`` (the function
behind ``slice_plane(..., cap=False)``): the faces wholly on the kept side stay,
the faces that straddle the plane are cut along it into triangles.  Two things
are put right around it:

* trimesh gives every cut face its own new vertices, so that the cut edge
  shared by two faces becomes two coincident vertices (a crack: each face's
  base edges are boundary edges, and the new base is not one loop).  The new
  vertices are put exactly on the plane (moved along the normal by at most
  rounding) and merged with those within ``MERGE`` of the mesh's size (the two
  copies of a cut edge's point differ by rounding only: they are computed
  from the edge's two ends), with the original vertices that lay on the plane.
* trimesh decides which side a vertex is on with an absolute tolerance (1e-8
  mesh units); here a vertex within ``SNAP`` of the mesh's size from the plane
  counts as lying on it (in every unit the same), and is put on it exactly, so
  that the cut leaves no sliver thinner than that, and no vertex of the result
  lies on the removed side.

Pieces that the cut disconnects are all kept (the clean step already chose
the crown); their count is reported (``details["pieces"]``), with the new
base's loops (``details["boundary_loops"]``).  A crop that keeps nothing raises
``ValueError`` naming the plane; one that removes nothing returns the mesh
unchanged (``faces_cut`` 0).
"""

from __future__ import annotations

import numpy as np
import trimesh
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from ._clean import face_pieces
from ._orient import boundary_loops
from ._protocol import ProtocolError, scaled_direction
from ._result import Outcome

#: A vertex within this fraction of the mesh's size (its bounding box diagonal) from the
#: plane lies on it.
SNAP = 1e-9

#: Vertices on the plane within this fraction of the mesh's size of each other are one.
MERGE = 1e-12


def _numbers(values) -> str:
    return "(" + ", ".join(f"{float(x):.6g}" for x in values) + ")"


def crop_plane(vertices: np.ndarray, *, below=None, fraction=None, plane=None):
    """The cutting plane ``(point, unit normal)`` of the parameters (None: no crop asked)."""
    up = np.array([0.0, 0.0, 1.0])
    if plane is not None:
        values = np.asarray(plane, dtype=np.float64).reshape(6)
        try:  # scaled first, as the protocol checks it: its length cannot overflow nor underflow
            normal = np.asarray(scaled_direction("normal", values[3:]), dtype=np.float64)
        except ProtocolError:
            normal = None
        if normal is None or not np.all(np.isfinite(values)):
            raise ValueError(
                f"crop plane must be 6 finite numbers, the normal not 0; got {_numbers(values)}"
            )
        return values[:3].copy(), normal / float(np.linalg.norm(normal))
    z = vertices[:, 2]
    if below is not None:
        height = float(z.min()) + float(below)
        if not np.isfinite(height):
            raise ValueError(f"crop below={float(below):g} puts the plane beyond every number")
        return np.array([0.0, 0.0, height]), up
    if fraction is not None:
        low, high = float(z.min()), float(z.max())
        return np.array([0.0, 0.0, high - float(fraction) * (high - low)]), up
    return None


def _merge_on_plane(vertices: np.ndarray, faces: np.ndarray, on: np.ndarray, radius: float):
    """Merge the vertices flagged `on` lying within `radius` of each other; drop what collapses."""
    index = np.flatnonzero(on)
    pairs = cKDTree(vertices[index]).query_pairs(radius, output_type="ndarray")
    if len(pairs) == 0:
        return vertices, faces, 0
    k = len(index)
    graph = coo_matrix((np.ones(len(pairs), dtype=np.int8), (pairs[:, 0], pairs[:, 1])), (k, k))
    _, label = connected_components(graph, directed=False)
    first = np.full(label.max() + 1, len(vertices), dtype=np.int64)
    np.minimum.at(first, label, index)  # each group's smallest vertex index represents it
    target = np.arange(len(vertices))
    target[index] = first[label]
    faces = target[faces]
    a, b, c = faces.T
    faces = faces[(a != b) & (b != c) & (c != a)]
    used = np.zeros(len(vertices), dtype=bool)
    used[faces] = True
    renumber = np.cumsum(used) - 1
    return vertices[used], renumber[faces], int(len(index) - len(np.unique(first[label])))


def run(
    vertices: np.ndarray, faces: np.ndarray, *, below=None, fraction=None, plane=None
) -> Outcome:
    """Keep the part of the mesh on the side of the plane its normal points to.

    Parameters
    ----------
    vertices : (n, 3) float
    faces : (m, 3) int
    below : float, optional
        Remove what lies less than this height above the lowest point.
    fraction : float, optional
        Keep the top fraction (0, 1] of the height (z range).
    plane : (6,) float, optional
        ``(px, py, pz, nx, ny, nz)``: keep the side the normal points to.

    Returns
    -------
    Outcome
        ``plane`` the cutting plane ``(point, unit normal)``; ``details``:
        ``faces_cut`` (faces that straddled the plane), ``faces_removed``
        (wholly on the removed side), ``height`` (the plane's height above the
        mesh's lowest point along the normal), ``kept_height`` (the kept part's
        height above the plane), ``pieces`` and ``boundary_loops`` of the result,
        ``merged_vertices`` (copies of cut points merged).

    Raises
    ------
    ValueError
        If the plane keeps nothing (the plane named, in mesh units).
    """
    vertices = np.asarray(vertices, dtype=np.float64)
    faces = np.asarray(faces, dtype=np.int64)
    found = crop_plane(vertices, below=below, fraction=fraction, plane=plane)
    if found is None:
        return Outcome(vertices.copy(), faces.copy(), details={"faces_cut": 0, "height": 0.0})
    point, normal = found
    size = float(np.linalg.norm(np.ptp(vertices, axis=0)))
    snap = SNAP * size
    with np.errstate(over="ignore", invalid="ignore"):
        dots = (vertices - point) @ normal
    if not np.all(np.isfinite(dots)):
        raise ValueError(
            f"the crop plane through {_numbers(point)} with normal {_numbers(normal)} is too "
            "far from the mesh: the vertices' distances to it overflow"
        )
    side = np.sign(dots)
    side[np.abs(dots) <= snap] = 0.0
    corner = side[faces]
    above = (corner > 0).any(axis=1)
    under = (corner < 0).any(axis=1)
    cut = int(np.count_nonzero(above & under))
    removed = int(np.count_nonzero(under & ~above))
    details = {
        "faces_cut": cut,
        "faces_removed": removed,
        "height": float(-dots.min()),
        "kept_height": float(max(dots.max(), 0.0)),
    }
    where = f"the crop plane through {_numbers(point)} with normal {_numbers(normal)} (mesh units)"
    if not above.any():
        # heights along the normal from the origin: from the plane's point, a plane far
        # away leaves nothing of the mesh's own span (1e308 away: -1e308 to -1e308)
        heights = vertices @ normal
        raise ValueError(
            f"{where} removes the whole mesh: every vertex lies on or below it (along the "
            f"normal the mesh spans {float(heights.min()):.6g} to {float(heights.max()):.6g}, "
            f"the plane lies at {float(point @ normal):.6g})"
        )
    if not under.any():
        details.update({"pieces": face_pieces(faces, len(vertices))[0], "merged_vertices": 0})
        details["boundary_loops"] = len(boundary_loops(vertices, faces))
        return Outcome(vertices.copy(), faces.copy(), plane=(point, normal), details=details)
    # trimesh takes the sides from cached_dots (against its own 1e-8): the signs, as found here
    new_vertices, new_faces, _ = trimesh.intersections.slice_faces_plane(
        vertices, faces, plane_normal=normal, plane_origin=point, cached_dots=side
    )
    new_vertices = np.array(new_vertices, dtype=np.float64)
    new_faces = np.asarray(new_faces, dtype=np.int64)
    if len(new_faces) == 0:  # pragma: no cover - a vertex above keeps a face
        raise ValueError(f"{where} removes the whole mesh")
    offset = (new_vertices - point) @ normal
    on = offset <= snap  # the cut points, the vertices on the plane (and none below)
    new_vertices[on] -= offset[on, None] * normal
    # the two copies of a cut point differ by rounding, relative to the coordinates' magnitude
    radius = max(MERGE * size, 64 * np.finfo(float).eps * float(np.abs(new_vertices).max()))
    new_vertices, new_faces, merged = _merge_on_plane(new_vertices, new_faces, on, radius)
    details.update(
        {
            "pieces": face_pieces(new_faces, len(new_vertices))[0],
            "boundary_loops": len(boundary_loops(new_vertices, new_faces)),
            "merged_vertices": merged,
        }
    )
    return Outcome(new_vertices, new_faces, plane=(point, normal), details=details)
