"""Inside/outside test: the generalised winding number, exact where it matters.

The winding number of a closed, consistently oriented surface about a point is
1 inside and 0 outside (-1 inside a surface oriented inward).  We evaluate it
with a bounding-volume hierarchy over the triangles (Barill et al. 2018, "Fast
winding numbers for soups and clouds", doi:10.1145/3197517.3201337):

* near field: every triangle whose cluster is closer than ``FAR_FIELD_RATIO``
  times the cluster's radius contributes its exact float64 solid angle
  (Van Oosterom & Strackee 1983, doi:10.1109/TBME.1983.325207);
* far field: a cluster contributes its dipole term, whose error is small
  because it is far.

A centroid a hair's breadth from the surface therefore gets the exact solid
angle of the triangles next to it.  Any point whose approximate winding number
is not within ``AMBIGUITY`` of an integer is recomputed by the exact sum over
all triangles, so the decision never rests on the approximation.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

#: A cluster is "far" from a query point beyond this multiple of its radius.
FAR_FIELD_RATIO = 2.0
#: Triangles per leaf of the hierarchy.
LEAF_SIZE = 8
#: Approximate winding numbers farther than this from an integer are recomputed exactly.
AMBIGUITY = 0.2
_FOUR_PI = 4.0 * np.pi


@njit(cache=True, inline="always")
def _solid_angle(x0, y0, z0, x1, y1, z1, x2, y2, z2):
    l0 = np.sqrt(x0 * x0 + y0 * y0 + z0 * z0)
    l1 = np.sqrt(x1 * x1 + y1 * y1 + z1 * z1)
    l2 = np.sqrt(x2 * x2 + y2 * y2 + z2 * z2)
    det = x0 * (y1 * z2 - z1 * y2) - y0 * (x1 * z2 - z1 * x2) + z0 * (x1 * y2 - y1 * x2)
    d01 = x0 * x1 + y0 * y1 + z0 * z1
    d12 = x1 * x2 + y1 * y2 + z1 * z2
    d20 = x2 * x0 + y2 * y0 + z2 * z0
    return 2.0 * np.arctan2(det, l0 * l1 * l2 + d01 * l2 + d12 * l0 + d20 * l1)


@njit(cache=True)
def _triangle_sum(tri, lo, hi, q):
    total = 0.0
    for t in range(lo, hi):
        total += _solid_angle(
            tri[t, 0, 0] - q[0],
            tri[t, 0, 1] - q[1],
            tri[t, 0, 2] - q[2],
            tri[t, 1, 0] - q[0],
            tri[t, 1, 1] - q[1],
            tri[t, 1, 2] - q[2],
            tri[t, 2, 0] - q[0],
            tri[t, 2, 1] - q[1],
            tri[t, 2, 2] - q[2],
        )
    return total


@njit(cache=True)
def _build(tri, leaf_size):
    n_tri = tri.shape[0]
    # halving leaves at least (leaf_size + 1) // 2 triangles per leaf
    cap = 4 * (n_tri // max(1, (leaf_size + 1) // 2) + 1) + 1
    lo = np.empty(cap, np.int64)
    hi = np.empty(cap, np.int64)
    left = np.full(cap, -1, np.int64)
    centre = np.zeros((cap, 3))
    dipole = np.zeros((cap, 3))
    radius = np.zeros(cap)
    lo[0] = 0
    hi[0] = n_tri
    count = 1
    node = 0
    while node < count:
        a = lo[node]
        b = hi[node]
        total_area = 0.0
        for t in range(a, b):
            e1 = tri[t, 1] - tri[t, 0]
            e2 = tri[t, 2] - tri[t, 0]
            cr = 0.5 * np.cross(e1, e2)
            area = np.sqrt(cr[0] ** 2 + cr[1] ** 2 + cr[2] ** 2)
            dipole[node] += cr
            centre[node] += area * (tri[t, 0] + tri[t, 1] + tri[t, 2]) / 3.0
            total_area += area
        if total_area > 0:
            centre[node] /= total_area
        else:
            centre[node] = tri[a, 0]
        r2 = 0.0
        for t in range(a, b):
            for k in range(3):
                d = tri[t, k] - centre[node]
                r2 = max(r2, d[0] ** 2 + d[1] ** 2 + d[2] ** 2)
        radius[node] = np.sqrt(r2)
        if b - a > leaf_size:
            mid = (a + b) // 2
            left[node] = count
            lo[count] = a
            hi[count] = mid
            lo[count + 1] = mid
            hi[count + 1] = b
            count += 2
        node += 1
    return lo[:count], hi[:count], left[:count], centre[:count], dipole[:count], radius[:count]


@njit(cache=True, parallel=True)
def _query(tri, lo, hi, left, centre, dipole, radius, queries, ratio):
    out = np.empty(queries.shape[0])
    for i in prange(queries.shape[0]):
        q = queries[i]
        stack = np.empty(256, np.int64)
        stack[0] = 0
        top = 1
        total = 0.0
        while top > 0:
            top -= 1
            node = stack[top]
            dx = centre[node, 0] - q[0]
            dy = centre[node, 1] - q[1]
            dz = centre[node, 2] - q[2]
            dist = np.sqrt(dx * dx + dy * dy + dz * dz)
            if dist > ratio * radius[node]:
                total += (
                    dx * dipole[node, 0] + dy * dipole[node, 1] + dz * dipole[node, 2]
                ) / dist**3
            elif left[node] < 0:
                total += _triangle_sum(tri, lo[node], hi[node], q)
            else:
                stack[top] = left[node]
                stack[top + 1] = left[node] + 1
                top += 2
        out[i] = total
    return out


@njit(cache=True, parallel=True)
def _exact(tri, queries):
    out = np.empty(queries.shape[0])
    for i in prange(queries.shape[0]):
        out[i] = _triangle_sum(tri, 0, tri.shape[0], queries[i])
    return out


def _ordered_triangles(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    from ._kernel import spatial_order

    tri = np.ascontiguousarray(vertices[faces], dtype=np.float64)
    return np.ascontiguousarray(tri[spatial_order(tri.mean(axis=1))])


def exact_winding_number(vertices: np.ndarray, faces: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Generalised winding number by the exact float64 sum over every triangle.

    O(points x faces): a reference for tests and the fallback for ambiguous points.
    """
    tri = np.ascontiguousarray(vertices[faces], dtype=np.float64)
    return _exact(tri, np.ascontiguousarray(points, dtype=np.float64)) / _FOUR_PI


def winding_number(vertices: np.ndarray, faces: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Generalised winding number of a triangle mesh about each point.

    Parameters
    ----------
    vertices : (n, 3) float
    faces : (m, 3) int
    points : (p, 3) float

    Returns
    -------
    (p,) float
        Near 1 for points inside a closed, outward-oriented surface, near 0
        outside.  Values not within ``AMBIGUITY`` of an integer after the fast
        pass are the exact sum.
    """
    points = np.ascontiguousarray(points, dtype=np.float64)
    tri = _ordered_triangles(vertices, faces)
    tree = _build(tri, LEAF_SIZE)
    value = _query(tri, *tree, points, FAR_FIELD_RATIO) / _FOUR_PI
    unsure = np.abs(value - np.round(value)) > AMBIGUITY
    if unsure.any():
        value[unsure] = _exact(tri, points[unsure]) / _FOUR_PI
    return value


def inside(vertices: np.ndarray, faces: np.ndarray, points: np.ndarray) -> np.ndarray:
    """True where a point lies inside a closed, consistently oriented surface.

    The orientation may be outward or inward (|winding number| > 1/2).
    """
    return np.abs(winding_number(vertices, faces, points)) > 0.5
