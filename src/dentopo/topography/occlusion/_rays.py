"""PCV's exact method: one ray per vertex and direction, cast by Embree (``embreex``), no pixels.

:func:`lit_counts_rays` counts, for each vertex, the light directions from which
it is seen: direction ``d`` lights vertex ``v`` when ``d`` leaves ``v`` on the
outer side of the surface (the side its faces' normals point to: the caller
passes the faces wound outward) and the ray ``v + t d``, ``t > 0``, meets no
face.  A direction tangent to the surface counts as lit (on a plane facing up
every direction with ``z >= 0`` is lit); a direction going into the surface
counts as not lit, even where the ray would leave an open mesh through its
opening (a crown's cervical hole): the light cannot pass through the crown.

How a ray leaves its own vertex.  The ray starts a little above the vertex,
along its angle-weighted normal (each face's unit normal weighted by its angle
at the vertex), by :data:`OFFSET` of the bounding box's diagonal.  From there
the faces around the vertex stop exactly the directions that go into the
surface: at a concave vertex (a groove's floor, a bowl's bottom) the start lies
inside the free cone of directions, which is convex, so a ray stays in it if
and only if its direction does; at a convex vertex (a cusp, a crest) the start
lies outside the cone of the material, and a ray meets that cone if and only
if its direction points into it (at a saddle, nearly so).  Moving the viewpoint
by 4e-6 of the diagonal changes only the directions that graze an obstacle:
within 4e-6 / r radian of it, r its distance as a fraction of the diagonal (a
256-ray partition's directions are some 0.15 radian apart).  Nothing is
absolute: the mesh is centred on its bounding box and divided by its diagonal
before anything else, so the counts do not change with translation or scale
(up to rounding).

Single precision.  Embree stores coordinates and rays in float32 (24 bits):
after the normalisation a coordinate is below 1 and rounded by at most 6e-8,
and Embree's intersection test adds a few such units.  :data:`OFFSET` is 64
such units (2**-18): measured on tilted, shifted and scaled planes and
V-grooves, rays 0.05 to 3 degrees off a face or a groove's wall came out right
for every offset from 2**-26 to 2**-14, and wrong for some at 2**-12 (the
offset itself then decides grazing rays); 2**-18 is in the middle.  The scene
is built in Embree's robust mode (watertight: a ray through an edge or a vertex
shared by two faces does not slip between them; about a quarter more time).

Speed and memory: the rays are cast one direction at a time, each call taking
every vertex (or :data:`CHUNK_VERTICES` of them), so memory is that of a few
copies of the vertex array whatever the number of directions (never ``n * k``
rays at once).  embreex casts single rays in a loop that holds the GIL: one
core, some 4.7 million rays a CPU second (a 20,000-face crown at 236 directions:
0.5 s).

"""

from __future__ import annotations

import numpy as np

from ..._optional import EXACT_OCCLUSION
from ...mesh._validate import check_finite, check_indices

#: How far above its vertex a ray starts, as a fraction of the bounding box's diagonal: 64
#: float32 units of the normalised coordinates (below 1), well above Embree's rounding.
OFFSET = 2.0**-18

#: The most faces whose normals are summed at once: bounds the temporary arrays.
CHUNK_FACES = 1 << 16

#: The most vertices cast in one call (one direction at a time): bounds the temporary arrays.
CHUNK_VERTICES = 1 << 20


def lit_counts_rays(vertices: np.ndarray, faces: np.ndarray, directions: np.ndarray) -> np.ndarray:
    """For each vertex, how many of `directions` light it: its ray meets no face.

    Parameters
    ----------
    vertices : (n, 3) float
        The mesh's vertices (not modified).
    faces : (m, 3) int
        Its triangles, wound outward (their normals point out of the material).
    directions : (k, 3) float
        Unit vectors: where the light comes from (the ray from a vertex goes
        towards ``d``).

    Returns
    -------
    (n,) int64
        The number of directions, from 0 to ``k``, that light each vertex (see
        the module's description for the definition).  A vertex in no face
        has no surface to go into: every direction whose ray meets no face
        lights it.

    Raises
    ------
    ValueError
        If a shape is wrong, a coordinate or direction is not finite, a face
        index is out of range, or a direction is not a unit vector.
    MissingExtraError
        If embreex is not installed.
    """
    EXACT_OCCLUSION.require()  # before anything, whatever the mesh
    vertices, faces, directions = _checked(vertices, faces, directions)
    n, k = len(vertices), len(directions)
    counts = np.zeros(n, dtype=np.int64)
    if n == 0 or k == 0:
        return counts
    if len(faces) == 0:
        counts[:] = k
        return counts
    low, high = vertices.min(axis=0), vertices.max(axis=0)
    diagonal = float(np.linalg.norm(high - low))
    if not diagonal > 0:  # every vertex at one point: no face has an area to stop a ray
        counts[:] = k
        return counts
    points = (vertices - (low + high) / 2) / diagonal
    origins = ray_origins(points, faces).astype(np.float32)
    scene = _scene(points, faces)
    rays32 = directions.astype(np.float32)
    for start in range(0, n, CHUNK_VERTICES):
        chunk = origins[start : start + CHUNK_VERTICES]
        lit = counts[start : start + CHUNK_VERTICES]
        for j in range(k):
            # one direction for the whole chunk: embreex reuses a single row
            lit += scene.run(chunk, rays32[j : j + 1], query="OCCLUDED") == -1
    return counts


def ray_origins(points: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Where each vertex's rays start: above it along its angle-weighted normal.

    `points` are the normalised coordinates (diagonal 1), the offset
    :data:`OFFSET`; a vertex with no normal (in no face, or only in faces of
    no area) starts at itself.
    """
    return points + OFFSET * angle_weighted_normals(points, faces)


def angle_weighted_normals(points: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Each vertex's unit normal: its faces' unit normals weighted by their angles at it.

    Rows of zeros where the sum vanishes (a vertex in no face, or only in
    faces of no area).  The angle weights depend only on the star's shape,
    not on how finely it is cut: a groove's floor vertex gets the bisector of
    its two walls whatever their triangles' sizes.
    """
    n = len(points)
    sums = np.zeros((n, 3))
    for start in range(0, len(faces), CHUNK_FACES):  # bounds the temporaries' memory
        chunk = faces[start : start + CHUNK_FACES]
        a, b, c = points[chunk[:, 0]], points[chunk[:, 1]], points[chunk[:, 2]]
        cross = np.cross(b - a, c - a)
        norm = np.linalg.norm(cross, axis=1)[:, None]
        unit = np.divide(cross, norm, out=np.zeros_like(cross), where=norm > 0)
        for corner, (p, q, r) in enumerate(((a, b, c), (b, c, a), (c, a, b))):
            angle = _angle(q - p, r - p)
            for axis in range(3):
                sums[:, axis] += np.bincount(chunk[:, corner], angle * unit[:, axis], n)
    length = np.linalg.norm(sums, axis=1)
    return np.divide(sums, length[:, None], out=np.zeros_like(sums), where=length[:, None] > 0)


def _angle(u: np.ndarray, w: np.ndarray) -> np.ndarray:
    """The angle between the rows of `u` and `w` (atan2 of |u x w| and u.w: accurate near 0)."""
    return np.arctan2(np.linalg.norm(np.cross(u, w), axis=1), np.einsum("ij,ij->i", u, w))


def _scene(points: np.ndarray, faces: np.ndarray):
    """An Embree scene of the triangles, committed on its first query (robust mode)."""
    from embreex import mesh_construction, rtcore_scene

    scene = rtcore_scene.EmbreeScene(robust=True)
    mesh_construction.TriangleMesh(
        scene, np.ascontiguousarray(points, dtype=np.float32), faces.astype(np.int32)
    )
    return scene


def _checked(vertices, faces, directions) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The arrays as float64, int64 and float64 copies-or-views, checked; raise ValueError."""
    vertices = np.asarray(vertices, dtype=np.float64)
    faces = np.asarray(faces)
    directions = np.asarray(directions, dtype=np.float64)
    if vertices.ndim != 2 or vertices.shape[1] != 3:
        raise ValueError(f"vertices must be an (n, 3) array, not {vertices.shape}")
    if faces.ndim != 2 or faces.shape[1] != 3:
        raise ValueError(f"faces must be an (m, 3) array, not {faces.shape}")
    if faces.size and not np.issubdtype(faces.dtype, np.integer):
        raise ValueError(f"faces must hold integer indices, not {faces.dtype}")
    if directions.ndim != 2 or directions.shape[1] != 3:
        raise ValueError(f"directions must be a (k, 3) array, not {directions.shape}")
    faces = faces.astype(np.int64, copy=False)
    check_finite(vertices)
    check_indices(faces, len(vertices))
    if len(faces) >= 2**31 or len(vertices) >= 2**31:
        raise ValueError("Embree indexes at most 2**31 - 1 vertices and faces")
    if len(directions):
        if not np.isfinite(directions).all():
            raise ValueError("a light direction has a NaN or infinite coordinate")
        norms = np.linalg.norm(directions, axis=1)
        worst = int(np.argmax(np.abs(norms - 1)))
        if abs(norms[worst] - 1) > 1e-6:
            raise ValueError(
                f"light directions must be unit vectors: direction {worst} has length "
                f"{norms[worst]:.9g}"
            )
    return vertices, faces, directions
