"""Inside/outside test: the generalised winding number, exact where it matters.

The winding number of a closed, consistently oriented surface about a point is
1 inside and 0 outside (-1 inside a surface oriented inward).  We evaluate it
with a bounding-volume hierarchy over the triangles (Barill et al. 2018, "Fast
winding numbers for soups and clouds", doi:10.1145/3197517.3201337):

* near field: every triangle whose cluster is closer than ``FAR_FIELD_RATIO``
  times the cluster's radius contributes its exact float64 solid angle
  (Van Oosterom & Strackee 1983, doi:10.1109/TBME.1983.325207);
* far field: a cluster contributes its dipole term (its summed area vector
  about its area-weighted centre), whose error is small because it is far.
  ``winding_number`` uses ratio 2 (values within about 0.05 of the exact
  sum); ``inside``, which needs only the nearest integer, uses ratio 1.5 with
  the next term of the expansion (the first moment of the area vectors), twice
  as fast: on noisy 120k-vertex crowns its largest error was 0.1, against the
  0.8 that would be needed to round to the wrong integer unnoticed.

A centroid a hair's breadth from the surface therefore gets the exact solid
angle of the triangles next to it.  Any point whose approximate winding number
is not within ``AMBIGUITY`` of an integer is recomputed with far-field ratios
``REFINE_RATIOS`` (more of the sum exact each time; at ratio 64 the far
field's error is far below 0.01) and, if it is still within
``HALF_INTEGER_BAND`` of a half-integer, by the exact sum over all
triangles, so the decision does not rest on the approximation.  The exact,
O(faces) per point, step is thereby kept for the few points where rounding
could go either way (points on the surface itself).  Its work is bounded
(``EXACT_WORK`` solid angles per point and triangle, at least ``EXACT_MIN``):
when very many points lie on the surface (an open patch under ``"winding"``,
or a bandwidth so small that every centroid is its own vertex), the points
closest to a half-integer get the exact sum and the others keep the ratio-64
value, which can put on the wrong side only a point within its error (far
below 0.01) of a half-integer, i.e. on the surface itself.

Long, thin triangles (the fans that cap a mesh's holes) would make every
cluster that holds them wide, and every query near them slow.  Triangles much
longer than the mesh's typical edge are therefore cut into strips parallel to
their shortest edge before the hierarchy is built: the surface, and so the
winding number, is unchanged (solid angle is additive), up to rounding.  The
strips add at most ``STRIP_BUDGET`` triangles per triangle of the mesh: every
triangle gets the strips it needs except the very longest (the few to a stray
vertex far away), which share what is left as fewer, longer strips instead of
millions.  Queries are processed in spatial order (adaptive, so a
stray vertex does not spoil it), which keeps the parts of the hierarchy they
visit in cache.  Everything is O((points + faces) log faces).
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from ..mesh import spatial_order

#: A cluster is "far" from a query point beyond this multiple of its radius.
FAR_FIELD_RATIO = 2.0
#: The same for ``inside``, which needs only the nearest integer, not the value.
INSIDE_RATIO = 1.5
#: Triangles per leaf of the hierarchy.
LEAF_SIZE = 4
#: Approximate winding numbers farther than this from an integer are recomputed exactly.
AMBIGUITY = 0.2
#: Far-field ratios of the second and third passes for ambiguous points.
REFINE_RATIOS = (8.0, 64.0)
#: After the last refinement, values this close to a half-integer get the exact sum.
HALF_INTEGER_BAND = 0.05
#: Each refinement pass (and the exact fallback) may visit at most this many
#: nodes or triangles per point and triangle...
WORK_PER_ITEM = 64
#: ... or this many in all, whichever is more (a few tenths of a second).
WORK_MIN = 4_000_000
#: Points refined together at first; the batch doubles while the budget lasts.
REFINE_BATCH = 256
#: Triangles longer than this many times the median longest edge are cut into strips.
LONG_TRIANGLE = 8.0
#: The strips may add at most this many triangles per triangle of the mesh.
STRIP_BUDGET = 1
#: Beyond that budget, each strip is this many times longer than the one before.
STRIP_GROWTH = 1.5
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


def _tree_capacity(n_tri: int, leaf_size: int) -> int:
    """Nodes a hierarchy over `n_tri` triangles can need.

    Halving leaves at least ``(leaf_size + 1) // 2`` triangles per leaf.
    """
    return 4 * (n_tri // max(1, (leaf_size + 1) // 2) + 1) + 1


def _tree(tri: np.ndarray, leaf_size: int = LEAF_SIZE) -> tuple:
    """The hierarchy of ``_build``: ``lo, hi, left, centre, dipole, moment, radius`` per node."""
    cap = _tree_capacity(len(tri), leaf_size)
    nodes = (
        np.empty(cap, np.int64),  # lo
        np.empty(cap, np.int64),  # hi
        np.full(cap, -1, np.int64),  # left
        np.zeros((cap, 3)),  # centre
        np.zeros((cap, 3)),  # dipole
        np.zeros((cap, 3, 3)),  # moment
        np.zeros(cap),  # radius
    )
    count = _build(tri, leaf_size, *nodes)
    return tuple(array[:count] for array in nodes)


@njit(cache=True)
def _build(tri, leaf_size, lo, hi, left, centre, dipole, moment, radius):
    """Binary hierarchy over the (spatially ordered) triangles, halving index ranges.

    Per node: the area-weighted centre, the summed area vector (its dipole) and
    the radius of the sphere about the centre that holds all its vertices.  The
    nodes go to arrays of the caller (``_tree``), of at least
    ``_tree_capacity`` entries, ``left`` filled with -1 and the sums with 0;
    returns the number of nodes.  (No array is returned: numba boxes one with
    a little Python code, where a Ctrl-C that arrived meanwhile would be raised
    and crash the caller; see ``dentopo.ariadne._kernel._run_sums``.)
    """
    n_tri = tri.shape[0]
    area_vec = np.empty((n_tri, 3))
    area = np.empty(n_tri)
    for t in range(n_tri):
        ax = tri[t, 1, 0] - tri[t, 0, 0]
        ay = tri[t, 1, 1] - tri[t, 0, 1]
        az = tri[t, 1, 2] - tri[t, 0, 2]
        bx = tri[t, 2, 0] - tri[t, 0, 0]
        by = tri[t, 2, 1] - tri[t, 0, 1]
        bz = tri[t, 2, 2] - tri[t, 0, 2]
        area_vec[t, 0] = 0.5 * (ay * bz - az * by)
        area_vec[t, 1] = 0.5 * (az * bx - ax * bz)
        area_vec[t, 2] = 0.5 * (ax * by - ay * bx)
        area[t] = np.sqrt(area_vec[t, 0] ** 2 + area_vec[t, 1] ** 2 + area_vec[t, 2] ** 2)
    lo[0] = 0
    hi[0] = n_tri
    count = 1
    node = 0
    while node < count:
        a = lo[node]
        b = hi[node]
        total_area = 0.0
        cx = cy = cz = 0.0
        dx = dy = dz = 0.0
        for t in range(a, b):
            w = area[t] / 3.0
            cx += w * (tri[t, 0, 0] + tri[t, 1, 0] + tri[t, 2, 0])
            cy += w * (tri[t, 0, 1] + tri[t, 1, 1] + tri[t, 2, 1])
            cz += w * (tri[t, 0, 2] + tri[t, 1, 2] + tri[t, 2, 2])
            dx += area_vec[t, 0]
            dy += area_vec[t, 1]
            dz += area_vec[t, 2]
            total_area += area[t]
        if total_area > 0:
            cx /= total_area
            cy /= total_area
            cz /= total_area
        else:
            cx = tri[a, 0, 0]
            cy = tri[a, 0, 1]
            cz = tri[a, 0, 2]
        centre[node, 0] = cx
        centre[node, 1] = cy
        centre[node, 2] = cz
        dipole[node, 0] = dx
        dipole[node, 1] = dy
        dipole[node, 2] = dz
        r2 = 0.0
        for t in range(a, b):
            for k in range(3):
                d2 = (tri[t, k, 0] - cx) ** 2 + (tri[t, k, 1] - cy) ** 2 + (tri[t, k, 2] - cz) ** 2
                r2 = max(r2, d2)
            # first moment of the area vectors about the centre: M_ij = sum e_i a_j
            ex = (tri[t, 0, 0] + tri[t, 1, 0] + tri[t, 2, 0]) / 3.0 - cx
            ey = (tri[t, 0, 1] + tri[t, 1, 1] + tri[t, 2, 1]) / 3.0 - cy
            ez = (tri[t, 0, 2] + tri[t, 1, 2] + tri[t, 2, 2]) / 3.0 - cz
            for j in range(3):
                moment[node, 0, j] += ex * area_vec[t, j]
                moment[node, 1, j] += ey * area_vec[t, j]
                moment[node, 2, j] += ez * area_vec[t, j]
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
    return count


#: Queries per call of the compiled ``_query`` (a few tenths of a second at most): Python
#: reacts to Ctrl-C between calls.
QUERIES_PER_CALL = 32_768


def _approximate(tri, tree, queries, ratio, second_order):
    """Approximate solid angles (4 pi w) at the queries, and each query's work (``_query``)."""
    n = len(queries)
    out = np.empty(n)
    work = np.zeros(n, np.int64)
    for start in range(0, n, QUERIES_PER_CALL):
        part = slice(start, min(n, start + QUERIES_PER_CALL))
        _query(tri, *tree, queries[part], ratio, second_order, out[part], work[part])
    return out, work


@njit(cache=True, parallel=True)
def _query(
    tri, lo, hi, left, centre, dipole, moment, radius, queries, ratio, second_order, out, work
):
    """Approximate solid angles (4 pi w) at the queries, and each query's work.

    The work is the number of nodes visited plus triangles summed exactly.
    Both go to arrays of the caller (``out``, ``work``); nothing is returned
    (see ``_build``).
    """
    n = queries.shape[0]
    n_chunks = min(n, 256)
    for chunk in prange(n_chunks):
        stack = np.empty(256, np.int64)  # one traversal stack per chunk of queries
        for i in range(chunk * n // n_chunks, (chunk + 1) * n // n_chunks):
            q = queries[i]
            stack[0] = 0
            top = 1
            total = 0.0
            visits = 0
            while top > 0:
                top -= 1
                node = stack[top]
                visits += 1
                dx = centre[node, 0] - q[0]
                dy = centre[node, 1] - q[1]
                dz = centre[node, 2] - q[2]
                dist = np.sqrt(dx * dx + dy * dy + dz * dz)
                if dist > ratio * radius[node]:
                    # far field to second order: the cluster's area vector D and
                    # first moment M about its centre, at r = centre - q:
                    # D.r/|r|^3 + tr(M)/|r|^3 - 3 r.M.r/|r|^5
                    inv3 = 1.0 / (dist * dist * dist)
                    term = dx * dipole[node, 0] + dy * dipole[node, 1] + dz * dipole[node, 2]
                    if second_order:
                        m = moment[node]
                        rmr = (
                            dx * (m[0, 0] * dx + m[0, 1] * dy + m[0, 2] * dz)
                            + dy * (m[1, 0] * dx + m[1, 1] * dy + m[1, 2] * dz)
                            + dz * (m[2, 0] * dx + m[2, 1] * dy + m[2, 2] * dz)
                        )
                        term += m[0, 0] + m[1, 1] + m[2, 2] - 3.0 * rmr / (dist * dist)
                    total += term * inv3
                elif left[node] < 0:
                    total += _triangle_sum(tri, lo[node], hi[node], q)
                    visits += hi[node] - lo[node]
                else:
                    stack[top] = left[node]
                    stack[top + 1] = left[node] + 1
                    top += 2
            out[i] = total
            work[i] = visits


def _exact(tri: np.ndarray, queries: np.ndarray) -> np.ndarray:
    """Exact solid angles (4 pi w) at the queries: the sum over every triangle."""
    out = np.empty(len(queries))
    _exact_sums(tri, queries, out)
    return out


@njit(cache=True, parallel=True)
def _exact_sums(tri, queries, out):
    """``out[i]``: the solid angle of all of `tri` at ``queries[i]``.

    Nothing is returned (see ``_build``).
    """
    for i in prange(queries.shape[0]):
        out[i] = _triangle_sum(tri, 0, tri.shape[0], queries[i])


@njit(cache=True)
def _cut_strips(tri, ptr, bounds, out):
    """Cut triangle t into strips parallel to its shortest edge.

    The strips run from the apex (the vertex opposite the shortest edge, at
    ``s = 0``) to that edge (``s = 1``) between the fractions
    ``bounds[ptr[t]:ptr[t + 1]]`` (0 first, 1 last), and keep the triangle's
    orientation: 1 + 2 (pieces - 1) triangles, written to `out` (nothing is
    returned, see ``_build``).
    """
    k = 0
    for t in range(tri.shape[0]):
        count = ptr[t + 1] - ptr[t] - 1
        # apex: the vertex opposite the shortest edge
        best = 0
        shortest = np.inf
        for a in range(3):
            b = (a + 1) % 3
            c = (a + 2) % 3
            d = 0.0
            for x in range(3):
                d += (tri[t, b, x] - tri[t, c, x]) ** 2
            if d < shortest:
                shortest = d
                best = a
        apex = tri[t, best]
        va = tri[t, (best + 1) % 3]
        vb = tri[t, (best + 2) % 3]
        for s in range(count):
            s0 = bounds[ptr[t] + s]
            s1 = bounds[ptr[t] + s + 1]
            p0 = apex + s0 * (va - apex)
            q0 = apex + s0 * (vb - apex)
            p1 = apex + s1 * (va - apex)
            q1 = apex + s1 * (vb - apex)
            if s == 0:
                out[k, 0] = apex
                out[k, 1] = p1
                out[k, 2] = q1
                k += 1
                continue
            out[k, 0] = p0
            out[k, 1] = p1
            out[k, 2] = q1
            out[k + 1, 0] = p0
            out[k + 1, 1] = q1
            out[k + 1, 2] = q0
            k += 2


def _strip_bounds(longest: np.ndarray, target: float, allowed: int):
    """Strip counts and CSR fractions (see ``_cut_strips``) for the long triangles.

    Equal strips of about `target` when they add at most `allowed` triangles
    (always, on ordinary meshes).  Otherwise (long triangles to a stray vertex
    far away) strips that start at `target` next to the shortest edge, which
    lies by the rest of the mesh, and grow by ``STRIP_GROWTH`` towards the
    apex: each strip is then shorter than its distance from that edge, so the
    hierarchy treats it as far field from the mesh, and a triangle a million
    times longer than the edges needs only about 40 strips.  If even those
    are too many, the largest counts are capped (their last strips get longer).
    """
    uniform = np.ceil(np.minimum(longest / target, allowed + 1.0)).astype(np.int64)
    if 2 * int((uniform - 1).sum()) <= allowed:
        pieces = uniform
        ptr = np.concatenate([[0], np.cumsum(pieces + 1)])
        k = np.arange(ptr[-1]) - np.repeat(ptr[:-1], pieces + 1)
        return pieces, ptr, k / np.repeat(pieces, pieces + 1)
    first = np.minimum(target / longest, 1.0)  # the first strip, as a fraction
    growth = STRIP_GROWTH
    wanted = np.ceil(np.log1p((growth - 1.0) / first) / np.log(growth)).astype(np.int64)
    pieces = 1 + _capped(np.maximum(wanted, 1) - 1, allowed // 2)
    ptr = np.concatenate([[0], np.cumsum(pieces + 1)])
    k = np.arange(ptr[-1]) - np.repeat(ptr[:-1], pieces + 1)
    # distance from the shortest edge, as a fraction: 0, f, f (1 + g), ..., then 1
    u = np.repeat(first, pieces + 1) * np.expm1(k * np.log(growth)) / (growth - 1.0)
    u = np.where(k == np.repeat(pieces, pieces + 1), 1.0, np.minimum(u, 1.0))
    # as fractions from the apex, ascending within each triangle
    reverse = np.repeat(ptr[:-1] + ptr[1:] - 1, pieces + 1) - np.arange(ptr[-1])
    return pieces, ptr, 1.0 - u[reverse]


def _split_long(tri: np.ndarray, *, overwrite: bool = False) -> np.ndarray:
    """Cut triangles much longer than the typical edge into strips (same surface).

    With ``overwrite``, ``tri`` itself is reused (each long triangle's first
    strip takes its place), which saves copying a large array.
    """
    edge = np.stack(
        [np.linalg.norm(tri[:, (a + 1) % 3] - tri[:, a], axis=1) for a in range(3)], axis=1
    )
    longest = edge.max(axis=1)
    target = LONG_TRIANGLE * float(np.median(longest))
    if not target > 0:
        return tri
    long = np.flatnonzero(longest > target)
    if len(long) == 0:
        return tri
    pieces, ptr, bounds = _strip_bounds(longest[long], target, STRIP_BUDGET * len(tri))
    strips = 2 * pieces - 1
    cut = np.empty((int(strips.sum()), 3, 3))
    _cut_strips(np.ascontiguousarray(tri[long]), ptr, bounds, cut)
    first = np.concatenate([[0], np.cumsum(strips)[:-1]])
    if not overwrite:
        tri = tri.copy()
    tri[long] = cut[first]
    return np.concatenate([tri, np.delete(cut, first, axis=0)])


def _capped(wanted: np.ndarray, allowed: int) -> np.ndarray:
    """``min(wanted, cap)`` with the largest cap whose total is at most `allowed`.

    Small requests are granted in full; only the largest ones (the triangles
    to a stray vertex far away) get fewer, longer strips.
    """
    if wanted.sum() <= allowed:
        return wanted
    s = np.sort(wanted)
    m = len(s)
    # total if the cap were s[j]: the j smaller requests in full, the rest s[j] each
    totals = np.cumsum(s) - s + s * (m - np.arange(m))
    j = int(np.searchsorted(totals, allowed, side="right")) - 1
    if j < 0:
        return np.minimum(wanted, allowed // m)
    above = m - int(np.searchsorted(s, s[j], side="right"))  # requests a higher cap raises
    return np.minimum(wanted, s[j] + (allowed - totals[j]) // max(above, 1))


def _ordered_triangles(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:

    tri = np.ascontiguousarray(vertices[faces], dtype=np.float64)  # a fresh array: ours
    tri = _split_long(tri, overwrite=True)
    return np.ascontiguousarray(tri[spatial_order(tri.mean(axis=1))])


def exact_winding_number(vertices: np.ndarray, faces: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Generalised winding number by the exact float64 sum over every triangle.

    O(points x faces): a reference for tests and the fallback for ambiguous points.
    """
    tri = np.ascontiguousarray(vertices[faces], dtype=np.float64)
    return _exact(tri, np.ascontiguousarray(points, dtype=np.float64)) / _FOUR_PI


def winding_number(
    vertices: np.ndarray,
    faces: np.ndarray,
    points: np.ndarray,
    *,
    far_field_ratio: float = FAR_FIELD_RATIO,
    second_order: bool = False,
) -> np.ndarray:
    """Generalised winding number of a triangle mesh about each point.

    Parameters
    ----------
    vertices : (n, 3) float
    faces : (m, 3) int
    points : (p, 3) float
    far_field_ratio : float, default ``FAR_FIELD_RATIO``
        Clusters farther than this many radii use their far-field expansion.
    second_order : bool, default False
        Add the first moment of the clusters' area vectors to their dipole term.

    Returns
    -------
    (p,) float
        Near 1 for points inside a closed, outward-oriented surface, near 0
        outside.  Values not within ``AMBIGUITY`` of an integer after the fast
        pass are refined (see the module docstring); those near a half-integer
        are the exact sum.
    """

    points = np.ascontiguousarray(points, dtype=np.float64)
    value = np.empty(len(points))
    if len(points) == 0:
        return value
    tri = _ordered_triangles(vertices, faces)
    tree = _tree(tri)
    order = spatial_order(points)
    value[order] = _approximate(
        tri, tree, np.ascontiguousarray(points[order]), far_field_ratio, second_order
    )[0]
    value /= _FOUR_PI
    budget = _budget(len(points), len(tri))
    for ratio in REFINE_RATIOS:
        unsure = np.flatnonzero(np.abs(value - np.round(value)) > AMBIGUITY)
        if len(unsure) == 0:
            return value
        # closest to a half-integer first, in batches while the budget lasts
        offset = np.abs(value[unsure] - np.floor(value[unsure]) - 0.5)
        unsure = unsure[np.argsort(offset, kind="stable")]
        spent = 0
        start = 0
        batch = REFINE_BATCH
        while start < len(unsure) and spent < budget:
            chosen = unsure[start : start + batch]
            queries = np.ascontiguousarray(points[chosen])
            refined, work = _approximate(tri, tree, queries, ratio, second_order)
            value[chosen] = refined / _FOUR_PI
            spent += int(work.sum())
            start += batch
            batch *= 2
    # what is still ambiguous is genuinely fractional (a point on the surface, or
    # a surface that is not closed); only values near a half-integer, where
    # rounding could go either way, need the exact O(faces) sum
    offset = np.abs(value - np.floor(value) - 0.5)
    half = np.flatnonzero(offset < HALF_INTEGER_BAND)
    affordable = budget // max(1, len(tri))
    if len(half) > affordable:  # e.g. every point on the surface: the closest calls first
        half = half[np.argsort(offset[half], kind="stable")[:affordable]]
    if len(half):
        value[half] = _exact(tri, np.ascontiguousarray(points[half])) / _FOUR_PI
    return value


def _budget(n_points: int, n_triangles: int) -> int:
    """Work each refinement pass may do: ``WORK_PER_ITEM`` per item, at least ``WORK_MIN``."""
    return max(WORK_MIN, WORK_PER_ITEM * (n_points + n_triangles))


def inside(vertices: np.ndarray, faces: np.ndarray, points: np.ndarray) -> np.ndarray:
    """True where a point lies inside a closed, consistently oriented surface.

    The orientation may be outward or inward (|winding number| > 1/2).
    """
    value = winding_number(vertices, faces, points, far_field_ratio=INSIDE_RATIO, second_order=True)
    return np.abs(value) > 0.5
