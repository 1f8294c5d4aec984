"""The Delaunay triangulation of RFI's footprint points: compiled, certified, or qhull's.

RFI's alpha shape needs the Delaunay triangulation of a few thousand 2D
points; qhull (``scipy.spatial.Delaunay``) spends most of RFI's time on it.
:func:`delaunay` first builds it with a compiled sweep (points added in order
of their distance from a seed triangle's circumcentre, each joined to the
hull edges it sees, then edges flipped until locally Delaunay), then
*certifies* the result with Shewchuk's error bounds: every triangle strictly
counter-clockwise, every interior edge strictly locally Delaunay, the hull
strictly convex, every point used, the halfedges consistent.  A triangulation
that passes is the Delaunay triangulation, and a unique one (no four points
on one circle within the bound), so it is the one qhull would return, up to
the order of triangles and of their vertices.  Anything the bounds cannot
decide (near-cocircular or near-collinear points, a point the sweep could
not place) falls back to qhull.

The triangles are returned as qhull returns them: ``simplices`` (t, 3) and
``neighbors`` (t, 3), ``neighbors[t, k]`` the triangle across the side
opposite vertex k, -1 on the hull.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import Delaunay

from ..._jit import njit
from ...mesh._topology import stable_order

#: Shewchuk's static error bounds of the orientation and in-circle determinants.
_EPS = np.ldexp(1.0, -53)
_CCW_BOUND = (3.0 + 16.0 * _EPS) * _EPS
_INCIRCLE_BOUND = (10.0 + 96.0 * _EPS) * _EPS

# The one-line helpers are inlined into their callers (``inline="always"``): compiled on
# their own, each took about 0.07 s on a fresh install, some twice (numba compiled them
# once more for the literal arguments of a call, such as ``_add(..., -1, -1, -1)``).


@njit(cache=True, inline="always")
def _orient(points, a, b, c):
    """Twice the signed area of (a, b, c): positive counter-clockwise."""
    return (points[b, 0] - points[a, 0]) * (points[c, 1] - points[a, 1]) - (
        points[b, 1] - points[a, 1]
    ) * (points[c, 0] - points[a, 0])


@njit(cache=True, inline="always")
def _orient_certain(points, a, b, c):
    """+1 or -1 if (a, b, c) is surely counter-clockwise or clockwise, else 0."""
    left = (points[a, 0] - points[c, 0]) * (points[b, 1] - points[c, 1])
    right = (points[a, 1] - points[c, 1]) * (points[b, 0] - points[c, 0])
    det = left - right
    bound = _CCW_BOUND * (abs(left) + abs(right))
    if det > bound:
        return 1
    if -det > bound:
        return -1
    return 0


@njit(cache=True)
def _incircle(points, a, b, c, d, certain):
    """Positive if d lies inside the circle of the counter-clockwise (a, b, c).

    With `certain`, 0 where the sign is not certain (Shewchuk's bound).
    """
    adx = points[a, 0] - points[d, 0]
    ady = points[a, 1] - points[d, 1]
    bdx = points[b, 0] - points[d, 0]
    bdy = points[b, 1] - points[d, 1]
    cdx = points[c, 0] - points[d, 0]
    cdy = points[c, 1] - points[d, 1]
    bdxcdy, cdxbdy = bdx * cdy, cdx * bdy
    cdxady, adxcdy = cdx * ady, adx * cdy
    adxbdy, bdxady = adx * bdy, bdx * ady
    alift = adx * adx + ady * ady
    blift = bdx * bdx + bdy * bdy
    clift = cdx * cdx + cdy * cdy
    det = alift * (bdxcdy - cdxbdy) + blift * (cdxady - adxcdy) + clift * (adxbdy - bdxady)
    if not certain:
        return det
    permanent = (
        (abs(bdxcdy) + abs(cdxbdy)) * alift
        + (abs(cdxady) + abs(adxcdy)) * blift
        + (abs(adxbdy) + abs(bdxady)) * clift
    )
    bound = _INCIRCLE_BOUND * permanent
    if det > bound:
        return 1.0
    if -det > bound:
        return -1.0
    return 0.0


@njit(cache=True, inline="always")
def _nxt(e):
    return e - e % 3 + (e + 1) % 3


@njit(cache=True, inline="always")
def _prv(e):
    return e - e % 3 + (e + 2) % 3


@njit(cache=True, inline="always")
def _link(halfedges, a, b):
    halfedges[a] = b
    if b >= 0:
        halfedges[b] = a


@njit(cache=True)
def _legalize(points, triangles, halfedges, hull_tri, start, stack):
    """Flip edges from halfedge `start` on until every one checked is locally Delaunay.

    A halfedge a (X to Y) of triangle (X, Y, P) whose twin b (Y to X) lies
    in (Y, X, Q) is flipped when Q is inside the circle of (X, Y, P): the
    triangles become (Q, Y, P) and (P, X, Q) in the same slots, and the two
    far edges (Q, Y) and (X, Q) are checked in turn.
    """
    depth = 0
    a = start
    while True:
        b = halfedges[a]
        if (
            b < 0
            or _incircle(
                points,
                triangles[a],
                triangles[_nxt(a)],
                triangles[_prv(a)],
                triangles[_prv(b)],
                np.bool_(False),  # a literal False would compile it once more
            )
            <= 0
        ):
            if depth == 0:
                return
            depth -= 1
            a = stack[depth]
            continue
        ap = _prv(a)
        bn, bp = _nxt(b), _prv(b)
        p = triangles[ap]
        q = triangles[bp]
        twin_bp = halfedges[bp]
        twin_ap = halfedges[ap]
        triangles[a] = q
        triangles[b] = p
        _link(halfedges, a, twin_bp)
        _link(halfedges, b, twin_ap)
        _link(halfedges, ap, bp)
        if twin_bp < 0:
            hull_tri[q] = a
        if twin_ap < 0:
            hull_tri[p] = b
        if depth == len(stack):
            return  # pathological: certification will refuse the result
        stack[depth] = bn
        depth += 1


@njit(cache=True, inline="always")
def _add(triangles, halfedges, count, i, j, k, a, b, c):
    t = 3 * count
    triangles[t] = i
    triangles[t + 1] = j
    triangles[t + 2] = k
    _link(halfedges, t, a)
    _link(halfedges, t + 1, b)
    _link(halfedges, t + 2, c)
    return t


@njit(cache=True, inline="always")
def _pseudo_angle(dx, dy):
    """A number in [0, 1) that grows with the angle of (dx, dy); 0 for (0, 0)."""
    size = abs(dx) + abs(dy)
    if size == 0.0:  # a point on the seed circle's centre: the sweep then gives up
        return 0.0
    p = dx / size
    return (3.0 - p if dy > 0 else 1.0 + p) / 4.0


#: Points the sweep adds per compiled call (``_insert``): a few tenths of a second at most, so
#: that Python reacts to Ctrl-C and SIGTERM between calls.  The result does not depend on it.
INSERTIONS_PER_CALL = 65_536

#: Halfedges (or triangles) ``_certify_edges`` (``_certify_triangles``) checks per call.
CHECKS_PER_CALL = 1_048_576


@njit(cache=True)
def _seed(
    points, triangles, halfedges, order, hull_next, hull_prev, hull_tri, hull_hash, state, centre
):
    """Start the sweep: the seed triangle, the points' order, the hull; 0, or -1 if it failed.

    Everything the insertions need next is left in the caller's arrays:
    ``state`` = (triangles so far, hull start), ``centre`` = the seed
    triangle's circumcentre, ``order`` the points by distance from it.
    """
    n = points.shape[0]
    lo_x = hi_x = points[0, 0]  # numpy's min and max, by a loop: numba's compile for a
    lo_y = hi_y = points[0, 1]  # column (a strided array) took 0.35 s on a fresh install
    for i in range(1, n):
        x = points[i, 0]
        y = points[i, 1]
        if x < lo_x:
            lo_x = x
        if x > hi_x:
            hi_x = x
        if y < lo_y:
            lo_y = y
        if y > hi_y:
            hi_y = y
    cx, cy = (lo_x + hi_x) / 2.0, (lo_y + hi_y) / 2.0
    i0, best = 0, np.inf
    for i in range(n):
        d = (points[i, 0] - cx) ** 2 + (points[i, 1] - cy) ** 2
        if d < best:
            i0, best = i, d
    i1, best = -1, np.inf
    for i in range(n):
        if i != i0:
            d = (points[i, 0] - points[i0, 0]) ** 2 + (points[i, 1] - points[i0, 1]) ** 2
            if d < best and d > 0:
                i1, best = i, d
    i2, best = -1, np.inf
    for i in range(n):
        if i == i0 or i == i1:
            continue
        bx, by = points[i1, 0] - points[i0, 0], points[i1, 1] - points[i0, 1]
        qx, qy = points[i, 0] - points[i0, 0], points[i, 1] - points[i0, 1]
        d = 2.0 * (bx * qy - by * qx)
        if d == 0:
            continue
        bb, qq = bx * bx + by * by, qx * qx + qy * qy
        ux, uy = (qy * bb - by * qq) / d, (bx * qq - qx * bb) / d
        r = ux * ux + uy * uy
        if r < best:
            i2, best = i, r
    if i1 < 0 or i2 < 0:
        return -1
    if _orient(points, i0, i1, i2) < 0:
        i1, i2 = i2, i1
    bx, by = points[i1, 0] - points[i0, 0], points[i1, 1] - points[i0, 1]
    qx, qy = points[i2, 0] - points[i0, 0], points[i2, 1] - points[i0, 1]
    d = 2.0 * (bx * qy - by * qx)
    bb, qq = bx * bx + by * by, qx * qx + qy * qy
    cx = points[i0, 0] + (qy * bb - by * qq) / d
    cy = points[i0, 1] + (bx * qq - qx * bb) / d

    distance = np.empty(n)
    for i in range(n):
        distance[i] = (points[i, 0] - cx) ** 2 + (points[i, 1] - cy) ** 2
        if distance[i] == 0.0:
            return -1  # a point on the seed's circumcentre (rounding): qhull decides
    # nearest first, ties in index order: a distance's bits, read as an integer, sort as
    # the distance does (it is >= 0); the sort the alpha hull compiles anyway, not numba's
    # float quicksort (about 1 s more on a fresh install).  The order cannot change the
    # triangulation that passes the certification: it is unique.
    stable_order(distance.view(np.int64), order)

    size = hull_hash.shape[0]
    hull_next[:] = -1
    hull_prev[:] = -1
    hull_tri[:] = -1
    hull_hash[:] = -1
    hull_next[i0], hull_next[i1], hull_next[i2] = i1, i2, i0
    hull_prev[i1], hull_prev[i2], hull_prev[i0] = i0, i1, i2
    halfedges[:] = -1
    _add(triangles, halfedges, 0, i0, i1, i2, -1, -1, -1)
    hull_tri[i0], hull_tri[i1], hull_tri[i2] = 0, 1, 2
    for v in (i0, i1, i2):
        key = int(_pseudo_angle(points[v, 0] - cx, points[v, 1] - cy) * size) % size
        hull_hash[key] = v
    state[0] = 1  # triangles
    state[1] = i0  # hull start
    state[2], state[3], state[4] = i0, i1, i2
    centre[0], centre[1] = cx, cy
    return 0


@njit(cache=True)
def _insert(
    points,
    triangles,
    halfedges,
    order,
    first,
    stop,
    hull_next,
    hull_prev,
    hull_tri,
    hull_hash,
    stack,
    state,
    centre,
):
    """Add the points ``order[first:stop]`` (see ``_seed``); the triangles so far, or -1."""
    cx, cy = centre[0], centre[1]
    i0, i1, i2 = state[2], state[3], state[4]
    count = state[0]
    hull_start = state[1]
    size = hull_hash.shape[0]
    capacity = triangles.shape[0] // 3

    for position in range(first, stop):
        p = order[position]
        if p == i0 or p == i1 or p == i2:
            continue
        key = int(_pseudo_angle(points[p, 0] - cx, points[p, 1] - cy) * size) % size
        start = -1
        for j in range(size):
            candidate = hull_hash[(key + j) % size]
            if candidate >= 0 and hull_next[candidate] >= 0:
                start = candidate
                break
        if start < 0:
            start = hull_start
        start = hull_prev[start]
        e = start
        while True:
            q = hull_next[e]
            if _orient(points, e, q, p) < 0:
                break
            e = q
            if e == start:
                return -1  # p sees no hull edge: the sweep cannot place it
        v, w = e, hull_next[e]
        if count == capacity:
            return -1
        t = _add(triangles, halfedges, count, v, p, w, -1, -1, hull_tri[v])
        count += 1
        hull_tri[v] = t
        hull_tri[p] = t + 1
        hull_next[v], hull_prev[p], hull_next[p], hull_prev[w] = p, v, w, p
        _legalize(points, triangles, halfedges, hull_tri, t + 2, stack)
        # forward: hull edges n -> q that p sees
        n_ = w
        while True:
            q = hull_next[n_]
            if not _orient(points, n_, q, p) < 0:
                break
            if count == capacity:
                return -1
            t = _add(triangles, halfedges, count, n_, p, q, hull_tri[p], -1, hull_tri[n_])
            count += 1
            hull_tri[p] = t + 1
            hull_next[p], hull_prev[q] = q, p
            hull_next[n_], hull_prev[n_] = -1, -1
            _legalize(points, triangles, halfedges, hull_tri, t + 2, stack)
            n_ = q
        # backward: hull edges q -> e that p sees
        e = v
        while True:
            q = hull_prev[e]
            if not _orient(points, q, e, p) < 0:
                break
            if count == capacity:
                return -1
            t = _add(triangles, halfedges, count, q, p, e, -1, hull_tri[e], hull_tri[q])
            count += 1
            hull_tri[q] = t
            hull_next[q], hull_prev[p] = p, q
            hull_next[e], hull_prev[e] = -1, -1
            _legalize(points, triangles, halfedges, hull_tri, t + 2, stack)
            e = q
        hull_start = p
        hull_hash[key] = p
        key_e = int(_pseudo_angle(points[e, 0] - cx, points[e, 1] - cy) * size) % size
        hull_hash[key_e] = e
        state[0] = count
        state[1] = hull_start
    return count


def _sweep(points, triangles, halfedges, per_call=None):
    """Build the triangulation; the number of triangles, or -1 if the sweep failed.

    Points are added `per_call` at a time (``INSERTIONS_PER_CALL``): the
    sweep's whole state lives in arrays, so each compiled call resumes where
    the last one stopped, and the triangles are the same for any `per_call`.
    """
    per_call = INSERTIONS_PER_CALL if per_call is None else max(1, int(per_call))
    n = points.shape[0]
    order = np.empty(n, dtype=np.int64)
    hull_next = np.empty(n, dtype=np.int64)
    hull_prev = np.empty(n, dtype=np.int64)
    hull_tri = np.empty(n, dtype=np.int64)
    hull_hash = np.empty(max(int(np.ceil(np.sqrt(n))), 1), dtype=np.int64)
    stack = np.empty(4096, dtype=np.int64)
    state = np.zeros(5, dtype=np.int64)
    centre = np.zeros(2)
    hull = (hull_next, hull_prev, hull_tri, hull_hash)
    if _seed(points, triangles, halfedges, order, *hull, state, centre) < 0:
        return -1
    count = int(state[0])
    for first in range(0, n, per_call):
        stop = min(n, first + per_call)
        count = _insert(
            points, triangles, halfedges, order, first, stop, *hull, stack, state, centre
        )
        if count < 0:
            return -1
    return count


@njit(cache=True)
def _certify_edges(points, triangles, halfedges, first, stop, used):
    """Halfedges ``first:stop`` consistent and surely locally Delaunay: their hull edges, or -1.

    Marks the points they start from in ``used``.
    """
    hull_edges = 0
    for e in range(first, stop):
        used[triangles[e]] = True
        b = halfedges[e]
        if b < 0:
            hull_edges += 1
            continue
        if (
            halfedges[b] != e
            or triangles[b] != triangles[_nxt(e)]
            or triangles[_nxt(b)] != (triangles[e])
        ):
            return -1
        if (
            e < b
            and _incircle(
                points,
                triangles[e],
                triangles[_nxt(e)],
                triangles[_prv(e)],
                triangles[_prv(b)],
                np.bool_(True),
            )
            >= 0
        ):
            return -1
    return hull_edges


@njit(cache=True)
def _certify_triangles(points, triangles, first, stop):
    """Whether the triangles ``first:stop`` are surely counter-clockwise."""
    for t in range(first, stop):
        a, b, c = triangles[3 * t], triangles[3 * t + 1], triangles[3 * t + 2]
        if _orient_certain(points, a, b, c) <= 0:
            return False
    return True


@njit(cache=True)
def _certify_hull(points, triangles, halfedges, count, used, hull_edges):
    """Every point used, Euler's count, and the hull one loop turning surely left."""
    n = points.shape[0]
    for i in range(n):
        if not used[i]:
            return False
    if count != 2 * n - 2 - hull_edges:
        return False
    after = np.full(n, -1, dtype=np.int64)
    first = -1
    for e in range(3 * count):
        if halfedges[e] < 0:
            if after[triangles[e]] >= 0:
                return False
            after[triangles[e]] = triangles[_nxt(e)]
            first = triangles[e]
    v, steps = first, 0
    while True:
        w = after[v]
        if w < 0 or _orient_certain(points, v, w, after[w]) <= 0:
            return False
        v = w
        steps += 1
        if v == first:
            break
        if steps > hull_edges:
            return False
    return steps == hull_edges


def _certified(points, triangles, halfedges, count, per_call=None):
    """Whether the triangles are surely the unique Delaunay triangulation of all the points.

    Checked in compiled calls of `per_call` (``CHECKS_PER_CALL``) halfedges or
    triangles each, so that Python reacts to a signal between them.
    """
    per_call = CHECKS_PER_CALL if per_call is None else max(1, int(per_call))
    used = np.zeros(points.shape[0], dtype=np.bool_)
    hull_edges = 0
    for first in range(0, 3 * count, per_call):
        stop = min(3 * count, first + per_call)
        found = _certify_edges(points, triangles, halfedges, first, stop, used)
        if found < 0:
            return False
        hull_edges += found
    for first in range(0, count, per_call):
        if not _certify_triangles(points, triangles, first, min(count, first + per_call)):
            return False
    return bool(_certify_hull(points, triangles, halfedges, count, used, hull_edges))


def delaunay(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The Delaunay triangulation of distinct 2D points: ``(simplices, neighbors)``.

    Compiled and certified (see the module), else qhull's.  The compiled
    steps run in calls of a few tenths of a second at most, so a Ctrl-C or
    SIGTERM is raised between them (qhull, the fallback, is one C call and
    reacts only when it returns).

    Raises
    ------
    scipy.spatial.QhullError
        From qhull, when the points span no area.
    """
    points = np.ascontiguousarray(points, dtype=np.float64)
    n = len(points)
    if n >= 3:
        most = max(2 * n - 5, 1)
        triangles = np.empty(3 * most, dtype=np.int64)
        halfedges = np.empty(3 * most, dtype=np.int64)
        count = _sweep(points, triangles, halfedges)
        if count > 0 and _certified(points, triangles, halfedges, count):
            simplices = triangles[: 3 * count].reshape(count, 3)
            across = halfedges[: 3 * count].reshape(count, 3)
            # neighbors[t, k]: across the side opposite vertex k, halfedge 3t + (k + 1) % 3
            neighbors = np.where(across < 0, -1, across // 3)[:, [1, 2, 0]]
            return simplices, neighbors
    tri = Delaunay(points)
    return tri.simplices, tri.neighbors
