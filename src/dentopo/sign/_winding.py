"""Inside/outside test: the generalised winding number, exact where it matters.

The winding number of a closed, consistently oriented surface about a point is
1 inside and 0 outside (-1 inside a surface oriented inward).  We evaluate it
with a bounding-volume hierarchy over the triangles (Barill et al. 2018, "Fast
winding numbers for soups and clouds", doi:10.1145/3197517.3201337): a k-d
tree whose nodes split their triangles at the median along the longest side of
their centroids' box (tight clusters: a query near the surface opens few of
them), built level by level in compiled passes, each node a 64-byte record
(centre in float64; radius, rounded up, and far-field terms in float32, whose
rounding is far below the far field's own error):

* near field: every triangle whose cluster is closer than ``FAR_FIELD_RATIO``
  times the cluster's radius contributes its exact float64 solid angle
  (Van Oosterom & Strackee 1983, doi:10.1109/TBME.1983.325207), each
  ``2 atan2(det, den)``; the arguments are added as the argument of the
  product of the ``den + i det`` with a count of the turns, one arctangent
  per query (``_near_product``; the same sum to within a few ulps a term);
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
millions.  Needles (triangles much longer than their shortest edge) that are
not long by that rule, but many, side by side, meet at one vertex (a fan: a
cone's side, a hole's cap, a vertex shared by 1e5 faces) are cut too, into
pieces that halve where queries come near them (``_needle_bounds``): a query
on the fan used to sum most of it exactly (250 s at 1e5 faces, 12 s now).
Queries are processed in spatial order (adaptive, so a
stray vertex does not spoil it), which keeps the parts of the hierarchy they
visit in cache, in parallel, each alone: the values do not depend on the
number of threads.  Everything is O((points + faces) log faces).
"""

from __future__ import annotations

import numba
import numpy as np

from .._jit import njit, prange
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
#: Triangles this many times longer than their shortest edge (needles) are cut
#: where queries come near them (``_needle_bounds``)...
NEEDLE = 32.0
#: ... into pieces no shorter than this many times their width...
NEEDLE_STRIP = 8.0
#: ... halved while a query is closer than this many times a piece's length...
NEEDLE_REACH = 1.0
#: The nearest query is found to within this relative error (``cKDTree.query``'s eps).
NEEDLE_EPS = 1.0
#: ... adding at most this many triangles per triangle of the mesh.
NEEDLE_BUDGET = 32
_FOUR_PI = 4.0 * np.pi


@njit(cache=True, inline="always")
def _turn(x0, y0, z0, x1, y1, z1, x2, y2, z2):
    """Half the solid angle of a triangle as a complex number: its argument.

    ``(re, im)`` with ``atan2(im, re)`` the term of ``_solid_angle`` (before its
    factor 2); ``(0, 0)`` where that term is ``atan2(0, 0) = 0``.
    """
    l0 = np.sqrt(x0 * x0 + y0 * y0 + z0 * z0)
    l1 = np.sqrt(x1 * x1 + y1 * y1 + z1 * z1)
    l2 = np.sqrt(x2 * x2 + y2 * y2 + z2 * z2)
    det = x0 * (y1 * z2 - z1 * y2) - y0 * (x1 * z2 - z1 * x2) + z0 * (x1 * y2 - y1 * x2)
    d01 = x0 * x1 + y0 * y1 + z0 * z1
    d12 = x1 * x2 + y1 * y2 + z1 * z2
    d20 = x2 * x0 + y2 * y0 + z2 * z0
    return l0 * l1 * l2 + d01 * l2 + d12 * l0 + d20 * l1, det


@njit(cache=True, inline="always")
def _solid_angle(x0, y0, z0, x1, y1, z1, x2, y2, z2):
    """The solid angle of a triangle seen from the origin (Van Oosterom and Strackee)."""
    re, im = _turn(x0, y0, z0, x1, y1, z1, x2, y2, z2)
    return 2.0 * np.arctan2(im, re)


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


@njit(cache=True, inline="always")
def _upper(re, im):
    """Whether ``atan2(im, re)`` lies in (0, pi]."""
    return im > 0.0 or (im == 0.0 and re < 0.0)


@njit(cache=True)
def _near_product(tri, lo, hi, q, re, im, turns):
    """Multiply ``re + i im`` by the complex terms (``_turn``) of ``tri[lo:hi]`` at `q`.

    The sum of the terms' arguments is ``atan2(im, re) + 2 pi turns``: one
    arctangent per query instead of one per triangle.  A product whose
    argument crosses pi counts a turn, decided by the half-plane of the
    product as computed, so the sum stays consistent however it rounds (to
    within a few ulps of each term, like a sum of arctangents).  Returns the
    new ``(re, im, turns)``; the product is rescaled now and then (only its
    argument matters).
    """
    for t in range(lo, hi):
        zr, zi = _turn(
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
        if zr == 0.0 and zi == 0.0:
            continue  # atan2(0, 0) = 0: a vertex at the query
        nr = re * zr - im * zi
        ni = re * zi + im * zr
        up = _upper(re, im)
        if up == _upper(zr, zi):
            # both arguments in (0, pi] (or both in (-pi, 0]): their sum crossed pi
            # (or -pi) if the product lies in the other half and one argument
            # exceeds pi/2 in size (a negative real part)
            if _upper(nr, ni) != up and (re < 0.0 or zr < 0.0):
                turns += 1 if up else -1
        re = nr
        im = ni
        size = abs(re) + abs(im)
        if size < 1e-100 or size > 1e100:
            re /= size
            im /= size
    return re, im, turns


#: Columns of a node's record in ``_tree``: its centre (float64), then, as float32 in the
#: same 64 bytes, its radius, summed area vector and the symmetric part of its first moment.
_CENTRE = 3
_RADIUS, _DIPOLE, _MOMENT = 6, 7, 10  # float32 columns (twice the float64 ones)


def _tree(tri: np.ndarray, leaf_size: int = LEAF_SIZE) -> tuple:
    """The hierarchy over triangles in k-d order (``_ordered_triangles``): its nodes.

    Returns ``(link, nodes, packed)``: ``link[k] = (first child, -1)`` of an inner
    node, ``(lo, hi)``, its range of triangles, of a leaf; ``nodes[k, :3]`` the
    node's area-weighted centre (float64) and ``packed`` the same array seen as
    float32, whose columns ``_RADIUS``, ``_DIPOLE`` (3) and ``_MOMENT`` (6: xx, yy,
    zz, xy, xz, yz) hold the radius (rounded up) and the far-field terms (see
    ``_summarise``): one 64-byte record per node.
    """
    lo, hi, link, level = _shape(len(tri), leaf_size)
    nodes = np.zeros((len(link), 8))
    weight = np.empty(len(link), np.float32)
    _summarise(tri, lo, hi, link, level, nodes, nodes.view(np.float32), weight)
    return link, nodes, nodes.view(np.float32)


def _shape(n: int, leaf_size: int) -> tuple:
    """``lo, hi, link, level`` of the hierarchy over `n` items (see ``_layout``)."""
    count = _node_count(n, leaf_size)
    lo = np.empty(count, np.int64)
    hi = np.empty(count, np.int64)
    link = np.empty((count, 2), np.int64)
    level = np.empty(130, np.int64)
    _layout(n, leaf_size, lo, hi, link, level)
    return lo, hi, link, level[: np.count_nonzero(level >= 0)]


def _node_count(n: int, leaf_size: int) -> int:
    """The number of nodes of ``_layout``'s hierarchy, in O(log n) (each level's
    ranges have at most two sizes)."""
    known: dict[int, int] = {}

    def count(k: int) -> int:
        if k <= leaf_size:
            return 1
        if k not in known:
            known[k] = 1 + count(k // 2) + count(k - k // 2)
        return known[k]

    return count(n)


@njit(cache=True)
def _layout(n, leaf_size, lo, hi, link, level):
    """The shape of the hierarchy: index ranges halved until at most `leaf_size`.

    Nodes are numbered level by level (``level[j]`` the first node of level j,
    then the end, then -1); the two children of a node are consecutive.  The
    arrays are the caller's (a returned array would be boxed with a little
    Python code, where a Ctrl-C that arrived meanwhile would be raised and
    crash the caller; see ``dentopo.ariadne._kernel._run_sums``); returns the
    number of nodes.
    """
    level[:] = -1
    lo[0] = 0
    hi[0] = n
    count = 1
    node = 0
    depth = 0
    level[0] = 0
    end = 1
    while node < count:
        if node == end:
            depth += 1
            level[depth] = node
            end = count
        a = lo[node]
        b = hi[node]
        if b - a > leaf_size:
            mid = (a + b) // 2
            link[node, 0] = count
            link[node, 1] = -1
            lo[count] = a
            hi[count] = mid
            lo[count + 1] = mid
            hi[count + 1] = b
            count += 2
        else:
            link[node, 0] = a
            link[node, 1] = b
        node += 1
    level[depth + 1] = count
    return count


@njit(cache=True)
def _select(centres, perm, axis, a, b, k):
    """Reorder rows ``a:b`` of `centres` (and `perm` alike) so that row `k` is in its place.

    Sorted by ``centres[:, axis]``: quickselect with a median-of-three pivot,
    smaller keys before `k`, larger after.
    """
    left = a
    right = b - 1
    while right > left:
        mid = (left + right) // 2
        x = centres[left, axis]
        y = centres[mid, axis]
        z = centres[right, axis]
        if x > y:
            x, y = y, x
        if y > z:
            y = z
        pivot = max(x, y)
        i = left
        j = right
        while i <= j:
            while centres[i, axis] < pivot:
                i += 1
            while centres[j, axis] > pivot:
                j -= 1
            if i <= j:
                for c in range(3):
                    centres[i, c], centres[j, c] = centres[j, c], centres[i, c]
                perm[i], perm[j] = perm[j], perm[i]
                i += 1
                j -= 1
        if k <= j:
            right = j
        elif k >= i:
            left = i
        else:
            return


#: Levels of the hierarchy are built in parallel only over this many triangles: below,
#: starting the threads (once per level) would cost more than it saves.
PARALLEL_BUILD = 200_000


#: Levels of the hierarchy each compiled call of the build (``_kd_order``, ``_summarise``)
#: does: each level's nodes together hold every item once, so a level is about a tenth
#: of a second on 2.6M faces, and Python reacts to Ctrl-C and SIGTERM between calls.
LEVELS_PER_CALL = 1


def _by_levels(count: int, per_call: int | None, call, reverse: bool = False) -> None:
    """``call(first, last)`` for the levels ``0:count`` in slices of `per_call`."""
    per_call = max(1, int(LEVELS_PER_CALL if per_call is None else per_call))
    starts = range(0, count, per_call)
    for first in reversed(starts) if reverse else starts:
        call(first, min(count, first + per_call))


def _kd_order(centres, link, lo, hi, level, perm, per_call=None):
    """Split each inner node's items at its middle along the longest side of their box.

    Rows of `centres` are moved and `perm` alike, level by level, in calls of
    `per_call` levels (``LEVELS_PER_CALL``; the nodes of a level are
    independent, so the order does not depend on the slices).
    """
    _by_levels(
        len(level) - 1,
        per_call,
        lambda first, last: _kd_levels(centres, link, lo, hi, level, perm, first, last),
    )


@njit(cache=True, parallel=True)
def _kd_levels(centres, link, lo, hi, level, perm, first, last):
    """``_kd_order`` for the levels ``first:last``: the nodes of a level in parallel on
    large meshes (each owns its rows: the order does not depend on the threads).
    Nothing is returned (see ``_layout``).
    """
    parallel = centres.shape[0] >= PARALLEL_BUILD
    for depth in range(first, last):
        if parallel and level[depth + 1] - level[depth] > 1:
            for node in prange(level[depth], level[depth + 1]):
                _kd_split(centres, link, lo, hi, perm, node)
        else:
            for node in range(level[depth], level[depth + 1]):
                _kd_split(centres, link, lo, hi, perm, node)


@njit(cache=True)
def _kd_split(centres, link, lo, hi, perm, node):
    if link[node, 1] >= 0:  # a leaf
        return
    a = lo[node]
    b = hi[node]
    lx = ly = lz = np.inf
    hx = hy = hz = -np.inf
    for i in range(a, b):
        lx = min(lx, centres[i, 0])
        hx = max(hx, centres[i, 0])
        ly = min(ly, centres[i, 1])
        hy = max(hy, centres[i, 1])
        lz = min(lz, centres[i, 2])
        hz = max(hz, centres[i, 2])
    axis = 0
    if hy - ly > hx - lx:
        axis = 1
    if hz - lz > max(hx - lx, hy - ly):
        axis = 2
    _select(centres, perm, axis, a, b, (a + b) // 2)


@njit(cache=True, inline="always")
def _area_vector(tri, t):
    ax = tri[t, 1, 0] - tri[t, 0, 0]
    ay = tri[t, 1, 1] - tri[t, 0, 1]
    az = tri[t, 1, 2] - tri[t, 0, 2]
    bx = tri[t, 2, 0] - tri[t, 0, 0]
    by = tri[t, 2, 1] - tri[t, 0, 1]
    bz = tri[t, 2, 2] - tri[t, 0, 2]
    return 0.5 * (ay * bz - az * by), 0.5 * (az * bx - ax * bz), 0.5 * (ax * by - ay * bx)


@njit(cache=True)
def _sums(tri, a, b, ox, oy, oz, out):
    """Sums over ``tri[a:b]`` about the point ``o``; returns the largest squared distance
    of a vertex from ``o``.

    ``out``: area, area-weighted centre (3; the first vertex if the area is 0),
    summed area vector (3), symmetric part of ``sum (g - c) a^T`` (6: xx, yy, zz,
    xy, xz, yz), with ``g`` each triangle's centroid, ``a`` its area vector and
    ``c`` the centre (summed about ``o``, then shifted).
    """
    total = cx = cy = cz = dx = dy = dz = 0.0
    mxx = myy = mzz = mxy = mxz = myz = 0.0
    r2 = 0.0
    for t in range(a, b):
        for k in range(3):
            ux = tri[t, k, 0] - ox
            uy = tri[t, k, 1] - oy
            uz = tri[t, k, 2] - oz
            r2 = max(r2, ux * ux + uy * uy + uz * uz)
        vx, vy, vz = _area_vector(tri, t)
        area = np.sqrt(vx * vx + vy * vy + vz * vz)
        ex = (tri[t, 0, 0] + tri[t, 1, 0] + tri[t, 2, 0]) / 3.0 - ox
        ey = (tri[t, 0, 1] + tri[t, 1, 1] + tri[t, 2, 1]) / 3.0 - oy
        ez = (tri[t, 0, 2] + tri[t, 1, 2] + tri[t, 2, 2]) / 3.0 - oz
        total += area
        cx += area * ex
        cy += area * ey
        cz += area * ez
        dx += vx
        dy += vy
        dz += vz
        mxx += ex * vx
        myy += ey * vy
        mzz += ez * vz
        mxy += 0.5 * (ex * vy + ey * vx)
        mxz += 0.5 * (ex * vz + ez * vx)
        myz += 0.5 * (ey * vz + ez * vy)
    if total > 0:
        cx /= total
        cy /= total
        cz /= total
    else:
        cx = tri[a, 0, 0] - ox
        cy = tri[a, 0, 1] - oy
        cz = tri[a, 0, 2] - oz
    out[0] = total
    out[1] = cx + ox
    out[2] = cy + oy
    out[3] = cz + oz
    out[4] = dx
    out[5] = dy
    out[6] = dz
    # about the centre: sum (g - c) a^T = sum (g - o) a^T - (c - o) D^T
    out[7] = mxx - cx * dx
    out[8] = myy - cy * dy
    out[9] = mzz - cz * dz
    out[10] = mxy - 0.5 * (cx * dy + cy * dx)
    out[11] = mxz - 0.5 * (cx * dz + cz * dx)
    out[12] = myz - 0.5 * (cy * dz + cz * dy)
    return r2


@njit(cache=True)
def _reach2(tri, a, b, ox, oy, oz):
    """The largest squared distance of a vertex of ``tri[a:b]`` from the point ``o``."""
    r2 = 0.0
    for t in range(a, b):
        for k in range(3):
            ux = tri[t, k, 0] - ox
            uy = tri[t, k, 1] - oy
            uz = tri[t, k, 2] - oz
            r2 = max(r2, ux * ux + uy * uy + uz * uz)
    return r2


@njit(cache=True, inline="always")
def _store(sums, node, nodes, packed):
    nodes[node, 0] = sums[1]
    nodes[node, 1] = sums[2]
    nodes[node, 2] = sums[3]
    for k in range(3):
        packed[node, _DIPOLE + k] = sums[4 + k]
    for k in range(6):
        packed[node, _MOMENT + k] = sums[7 + k]


def _summarise(tri, lo, hi, link, level, nodes, packed, weight, per_call=None):
    """Each node's area-weighted centre, radius, summed area vector and first moment.

    The radius is that of the sphere about the centre holding all the node's
    vertices, rounded up to float32; the first moment of the area vectors about
    the centre, ``M_ij = sum e_i a_j``, enters the far field only through its
    symmetric part.  Bottom up: a leaf's sums from its triangles, an inner
    node's from its children's (``weight``, the caller's float32 array, carries
    their areas; any centre will do, as long as the radius and moments are
    taken about the centre stored); then each level's radii, one
    pass over the triangles.  In calls of `per_call` levels
    (``LEVELS_PER_CALL``): a level needs only the one below it.
    """
    depths = len(level) - 1
    _by_levels(
        depths,
        per_call,
        lambda first, last: _combine_levels(
            tri, lo, hi, link, level, nodes, packed, weight, first, last
        ),
        reverse=True,
    )
    _by_levels(
        depths,
        per_call,
        lambda first, last: _radius_levels(tri, lo, hi, link, level, nodes, packed, first, last),
    )


@njit(cache=True, parallel=True)
def _combine_levels(tri, lo, hi, link, level, nodes, packed, weight, first, last):
    """The sums of the nodes of levels ``first:last``, the deepest first (``_combine``);
    a level's nodes in parallel on large meshes.  Nothing is returned (see ``_layout``).
    """
    parallel = tri.shape[0] >= PARALLEL_BUILD
    for depth in range(last - 1, first - 1, -1):
        if parallel and level[depth + 1] - level[depth] > 1:
            for node in prange(level[depth], level[depth + 1]):
                _combine(tri, lo, hi, link, nodes, packed, weight, node, np.empty(13))
        else:
            sums = np.empty(13)
            for node in range(level[depth], level[depth + 1]):
                _combine(tri, lo, hi, link, nodes, packed, weight, node, sums)


@njit(cache=True, parallel=True)
def _radius_levels(tri, lo, hi, link, level, nodes, packed, first, last):
    """The radii of the inner nodes of levels ``first:last`` (``_inner_radius``).

    Nothing is returned (see ``_layout``).
    """
    parallel = tri.shape[0] >= PARALLEL_BUILD
    for depth in range(first, last):
        if parallel and level[depth + 1] - level[depth] > 1:
            for node in prange(level[depth], level[depth + 1]):
                _inner_radius(tri, lo, hi, link, nodes, packed, node)
        else:
            for node in range(level[depth], level[depth + 1]):
                _inner_radius(tri, lo, hi, link, nodes, packed, node)


@njit(cache=True)
def _combine(tri, lo, hi, link, nodes, packed, weight, node, sums):
    """The sums of `node`: from its triangles (a leaf, with its radius) or its children."""
    if link[node, 1] >= 0:
        a = lo[node]
        _sums(tri, a, hi[node], tri[a, 0, 0], tri[a, 0, 1], tri[a, 0, 2], sums)
        _store(sums, node, nodes, packed)
        weight[node] = sums[0]
        _set_radius(packed, node, _reach2(tri, a, hi[node], sums[1], sums[2], sums[3]))
        return
    first = link[node, 0]
    second = first + 1
    w1 = np.float64(weight[first])
    w2 = np.float64(weight[second])
    area = w1 + w2
    if area > 0:
        cx = (w1 * nodes[first, 0] + w2 * nodes[second, 0]) / area
        cy = (w1 * nodes[first, 1] + w2 * nodes[second, 1]) / area
        cz = (w1 * nodes[first, 2] + w2 * nodes[second, 2]) / area
    else:
        cx = nodes[first, 0]
        cy = nodes[first, 1]
        cz = nodes[first, 2]
    sxx = syy = szz = sxy = sxz = syz = 0.0
    for child in range(first, first + 2):
        ex = nodes[child, 0] - cx
        ey = nodes[child, 1] - cy
        ez = nodes[child, 2] - cz
        dx = np.float64(packed[child, _DIPOLE])
        dy = np.float64(packed[child, _DIPOLE + 1])
        dz = np.float64(packed[child, _DIPOLE + 2])
        # about the new centre: S + sym((c_child - c) D^T)
        sxx += np.float64(packed[child, _MOMENT]) + ex * dx
        syy += np.float64(packed[child, _MOMENT + 1]) + ey * dy
        szz += np.float64(packed[child, _MOMENT + 2]) + ez * dz
        sxy += np.float64(packed[child, _MOMENT + 3]) + 0.5 * (ex * dy + ey * dx)
        sxz += np.float64(packed[child, _MOMENT + 4]) + 0.5 * (ex * dz + ez * dx)
        syz += np.float64(packed[child, _MOMENT + 5]) + 0.5 * (ey * dz + ez * dy)
    weight[node] = area
    nodes[node, 0] = cx
    nodes[node, 1] = cy
    nodes[node, 2] = cz
    for x in range(3):
        packed[node, _DIPOLE + x] = np.float64(packed[first, _DIPOLE + x]) + np.float64(
            packed[second, _DIPOLE + x]
        )
    packed[node, _MOMENT] = sxx
    packed[node, _MOMENT + 1] = syy
    packed[node, _MOMENT + 2] = szz
    packed[node, _MOMENT + 3] = sxy
    packed[node, _MOMENT + 4] = sxz
    packed[node, _MOMENT + 5] = syz


@njit(cache=True)
def _inner_radius(tri, lo, hi, link, nodes, packed, node):
    if link[node, 1] < 0:
        r2 = _reach2(tri, lo[node], hi[node], nodes[node, 0], nodes[node, 1], nodes[node, 2])
        _set_radius(packed, node, r2)


@njit(cache=True, inline="always")
def _set_radius(packed, node, r2):
    """The radius, rounded up to float32."""
    radius = np.float32(np.sqrt(r2))
    if radius < np.sqrt(r2):
        radius = np.nextafter(radius, np.float32(np.inf))
    packed[node, _RADIUS] = radius


@njit(cache=True, inline="always")
def _far_field(nodes, packed, node, qx, qy, qz, ratio, second_order):
    """``(True, term)`` if `node` is far from ``q`` (beyond `ratio` radii), else ``(False, 0)``.

    The far field to second order: the cluster's area vector D and the
    symmetric part S of its first moment about its centre, at r = centre - q:
    D.r/|r|^3 + tr(S)/|r|^3 - 3 r.S.r/|r|^5.
    """
    dx = nodes[node, 0] - qx
    dy = nodes[node, 1] - qy
    dz = nodes[node, 2] - qz
    d2 = dx * dx + dy * dy + dz * dz
    reach = ratio * np.float64(packed[node, _RADIUS])
    if not d2 > reach * reach:
        return False, 0.0
    term = (
        dx * np.float64(packed[node, _DIPOLE])
        + dy * np.float64(packed[node, _DIPOLE + 1])
        + dz * np.float64(packed[node, _DIPOLE + 2])
    )
    if second_order:
        sxx = np.float64(packed[node, _MOMENT])
        syy = np.float64(packed[node, _MOMENT + 1])
        szz = np.float64(packed[node, _MOMENT + 2])
        sxy = np.float64(packed[node, _MOMENT + 3])
        sxz = np.float64(packed[node, _MOMENT + 4])
        syz = np.float64(packed[node, _MOMENT + 5])
        rsr = (
            dx * dx * sxx
            + dy * dy * syy
            + dz * dz * szz
            + 2.0 * (dx * dy * sxy + dx * dz * sxz + dy * dz * syz)
        )
        term += sxx + syy + szz - 3.0 * rsr / d2
    return True, term / (d2 * np.sqrt(d2))


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


#: Fewer queries than this are computed on one thread: starting the threads would cost more.
PARALLEL_QUERIES = 2048


@njit(cache=True, parallel=True)
def _query(tri, link, nodes, packed, queries, ratio, second_order, out, work):
    """Approximate solid angles (4 pi w) at the queries, and each query's work.

    The work is the number of nodes visited plus triangles summed exactly.
    Both go to arrays of the caller (``out``, ``work``); nothing is returned
    (see ``_layout``).  Each query is computed alone: the result does not
    depend on the number of threads.
    """
    n = queries.shape[0]
    n_chunks = min(n, 256)
    if n >= PARALLEL_QUERIES:
        for chunk in prange(n_chunks):
            first = chunk * n // n_chunks
            last = (chunk + 1) * n // n_chunks
            _query_range(
                tri, link, nodes, packed, queries, ratio, second_order, out, work, first, last
            )
    else:
        _query_range(tri, link, nodes, packed, queries, ratio, second_order, out, work, 0, n)


@njit(cache=True)
def _query_range(tri, link, nodes, packed, queries, ratio, second_order, out, work, first, last):
    """``_query`` for the queries ``first:last``."""
    stack = np.empty(256, np.int64)
    for i in range(first, last):
        q = queries[i]
        qx = q[0]
        qy = q[1]
        qz = q[2]
        total = 0.0
        re = 1.0  # the near field's triangles, as a product (``_near_product``)
        im = 0.0
        turns = 0
        visits = 1
        top = 0
        far, term = _far_field(nodes, packed, 0, qx, qy, qz, ratio, second_order)
        if far:
            total += term
        elif link[0, 1] >= 0:
            re, im, turns = _near_product(tri, link[0, 0], link[0, 1], q, re, im, turns)
            visits += link[0, 1] - link[0, 0]
        else:
            stack[0] = 0
            top = 1
        while top > 0:  # inner nodes near the query: their two children
            top -= 1
            child = link[stack[top], 0]
            for node in range(child, child + 2):
                visits += 1
                far, term = _far_field(nodes, packed, node, qx, qy, qz, ratio, second_order)
                if far:
                    total += term
                elif link[node, 1] >= 0:
                    re, im, turns = _near_product(
                        tri, link[node, 0], link[node, 1], q, re, im, turns
                    )
                    visits += link[node, 1] - link[node, 0]
                else:
                    stack[top] = node
                    top += 1
        out[i] = total + 2.0 * (np.arctan2(im, re) + 2.0 * np.pi * turns)
        work[i] = visits


#: (query, triangle) pairs ``_exact_sums`` sums per call and thread: about a tenth of a second,
#: so that Python reacts to Ctrl-C and SIGTERM between calls.
EXACT_PAIRS_PER_CALL = 2_000_000


def _exact(tri: np.ndarray, queries: np.ndarray, per_call: int | None = None) -> np.ndarray:
    """Exact solid angles (4 pi w) at the queries: the sum over every triangle.

    The queries go to ``_exact_sums`` in blocks of `per_call` (by default
    ``EXACT_PAIRS_PER_CALL`` pairs a thread, one query a thread at least); each
    query's sum is its own, so the values do not depend on the blocks.
    """
    if per_call is None:
        threads = numba.get_num_threads()
        per_call = max(threads, EXACT_PAIRS_PER_CALL * threads // max(1, len(tri)))
    per_call = max(1, int(per_call))
    out = np.empty(len(queries))
    for start in range(0, len(queries), per_call):
        part = slice(start, min(len(queries), start + per_call))
        _exact_sums(tri, queries[part], out[part])
    return out


@njit(cache=True, parallel=True)
def _exact_sums(tri, queries, out):
    """``out[i]``: the solid angle of all of `tri` at ``queries[i]``.

    Nothing is returned (see ``_layout``).
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
    returned, see ``_layout``).
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


def _long_strips(
    longest: np.ndarray, shortest: np.ndarray, triangles, queries: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """The triangles much longer than the typical edge, and the strips that replace them.

    `longest` and `shortest` are each triangle's longest and shortest edge;
    ``triangles(rows)`` gives the (k, 3, 3) coordinates of the triangles
    `rows`.  With `queries`, needles (``_needle_bounds``) near them are cut
    too.  Returns the indices of the triangles cut (the long ones, then the
    needles) and their strips (see ``_cut_strips``), each triangle's together.
    """
    target = LONG_TRIANGLE * float(np.median(longest)) if len(longest) else 0.0
    if not target > 0:
        return np.empty(0, np.int64), np.empty((0, 3, 3))
    is_long = longest > target
    long = np.flatnonzero(is_long)
    parts = []
    if len(long):
        parts.append(_strip_bounds(longest[long], target, STRIP_BUDGET * len(longest)))
    needles = np.empty(0, np.int64)
    if queries is not None and len(queries):
        needles = np.flatnonzero(~is_long & (longest > NEEDLE * shortest))
    if len(needles):
        corners = np.ascontiguousarray(triangles(needles), dtype=np.float64)
        pieces, ptr, bounds = _needle_bounds(corners, queries, NEEDLE_BUDGET * len(longest))
        cut_needles = np.flatnonzero(pieces > 1)
        if len(cut_needles) < len(needles):  # the needles far from every query stay whole
            keep = np.repeat(pieces > 1, pieces + 1)
            pieces, bounds = pieces[cut_needles], bounds[keep]
            needles = needles[cut_needles]
        parts.append((pieces, None, bounds))
    if not parts:
        return long, np.empty((0, 3, 3))
    pieces = np.concatenate([part[0] for part in parts])
    bounds = np.concatenate([part[2] for part in parts])
    ptr = np.concatenate([[0], np.cumsum(pieces + 1)])
    rows = np.concatenate([long, needles])
    cut = np.empty((int((2 * pieces - 1).sum()), 3, 3))
    _cut_strips(np.ascontiguousarray(triangles(rows), dtype=np.float64), ptr, bounds, cut)
    return rows, cut


def _needle_bounds(corners: np.ndarray, queries: np.ndarray, allowed: int):
    """Strip counts and CSR fractions (see ``_cut_strips``) for needles near the queries.

    Many needles (triangles ``NEEDLE`` times longer than their shortest edge)
    that meet at one vertex (a fan: the cap of a hole, the side of a cone)
    are each as long as the typical edge of the mesh, which is theirs, and
    every cluster that holds them is as wide as they are long: a query on or
    near the fan would sum all of them exactly (quadratic in the fan's
    size).  Each needle is therefore halved, along its length, where a query
    is closer than ``NEEDLE_REACH`` times a piece's length, down to pieces
    ``NEEDLE_STRIP`` times as long as they are wide: a query then sums a few
    pieces exactly and sees the rest as far field, which takes O(log aspect)
    pieces a needle.  The halving stops when it would add more than `allowed`
    triangles in all.  `corners` holds the needles' (k, 3, 3) coordinates.
    """
    from scipy.spatial import cKDTree

    k = len(corners)
    side = np.stack(
        [((corners[:, (a + 1) % 3] - corners[:, (a + 2) % 3]) ** 2).sum(axis=1) for a in range(3)],
        axis=1,
    )
    best = np.argmin(side, axis=1)  # the apex: opposite the shortest edge (``_cut_strips``)
    rows = np.arange(k)
    apex = corners[rows, best]
    axis = 0.5 * (corners[rows, (best + 1) % 3] + corners[rows, (best + 2) % 3]) - apex
    length = np.sqrt((axis**2).sum(axis=1))
    width = np.sqrt(side[rows, best])  # the shortest edge
    queries = np.asarray(queries, dtype=np.float64)
    owner = rows
    s0 = np.zeros(k)
    s1 = np.ones(k)
    done = []
    added = 0
    while len(owner):
        span = (s1 - s0) * length[owner]
        # the piece at the apex is cut at most twice: a query there is near every needle
        split = (span > NEEDLE_STRIP * width[owner]) & ((s0 > 0) | (s1 > 0.25))
        test = np.flatnonzero(split)
        if len(test) == 0:
            done.append((owner, s0, s1))
            break
        middle = apex[owner[test]] + (0.5 * (s0[test] + s1[test]))[:, None] * axis[owner[test]]
        reach = NEEDLE_REACH * span[test]
        # the queries to within an eighth of the shortest reach: one a grid cell (a few
        # where the pieces are long), so that no search meets many nearly tied ones
        cell = reach.min() / 8.0
        kept = np.unique(np.floor(queries / cell), axis=0)
        finder = cKDTree((kept + 0.5) * cell)
        bound = reach.max() + cell
        found = finder.query(middle, eps=NEEDLE_EPS, distance_upper_bound=bound)[0]
        split[test] = found < reach + cell
        if added + 2 * int(split.sum()) > allowed:
            split[:] = False
        added += 2 * int(split.sum())
        done.append((owner[~split], s0[~split], s1[~split]))
        half = 0.5 * (s0[split] + s1[split])
        owner = np.concatenate([owner[split], owner[split]])
        s0, s1 = np.concatenate([s0[split], half]), np.concatenate([half, s1[split]])
    owner = np.concatenate([part[0] for part in done])
    s0 = np.concatenate([part[1] for part in done])
    s1 = np.concatenate([part[2] for part in done])
    order = np.lexsort((s0, owner))
    owner = owner[order]
    pieces = np.bincount(owner, minlength=k)
    ptr = np.concatenate([[0], np.cumsum(pieces + 1)])
    group = np.concatenate([[0], np.cumsum(pieces)])[owner]  # each piece's needle's first
    bounds = np.empty(ptr[-1])
    bounds[ptr[owner] + np.arange(len(owner)) - group] = s0[order]
    bounds[ptr[1:] - 1] = 1.0
    return pieces, ptr, bounds


def _split_long(tri: np.ndarray) -> np.ndarray:
    """Cut triangles much longer than the typical edge into strips (same surface).

    The other triangles, in their order, then the strips.
    """
    edge = np.stack(
        [np.linalg.norm(tri[:, (a + 1) % 3] - tri[:, a], axis=1) for a in range(3)], axis=1
    )
    long, cut = _long_strips(edge.max(axis=1), edge.min(axis=1), lambda rows: tri[rows])
    if len(long) == 0:
        return tri
    return np.concatenate([np.delete(tri, long, axis=0), cut])


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


def _ordered_triangles(
    vertices: np.ndarray,
    faces: np.ndarray,
    leaf_size: int = LEAF_SIZE,
    queries: np.ndarray | None = None,
) -> np.ndarray:
    """The mesh's triangles, long ones cut (``_split_long``), in the k-d order of ``_tree``.

    With `queries`, needles near them are cut too (``_needle_bounds``).  Built
    once, in that order, from the vertices, the faces and the strips: no copy
    of the mesh's triangles is made before it.
    """
    vertices = np.ascontiguousarray(vertices, dtype=np.float64)
    faces = np.ascontiguousarray(faces, dtype=np.int64)
    longest = np.empty(len(faces))
    shortest = np.empty(len(faces))
    _edge_extremes(vertices, faces, longest, shortest)
    long, cut = _long_strips(longest, shortest, lambda rows: vertices[faces[rows]], queries)
    keep = np.arange(len(faces)) if len(long) == 0 else np.delete(np.arange(len(faces)), long)
    n = len(keep) + len(cut)
    centres = np.empty((n, 3))
    _item_centres(vertices, faces, keep, cut, centres)
    perm = np.arange(n)
    lo, hi, link, level = _shape(n, leaf_size)
    _kd_order(centres, link, lo, hi, level, perm)
    del centres, lo, hi, link, level
    tri = np.empty((n, 3, 3))
    _gather(vertices, faces, keep, cut, perm, tri)
    return tri


@njit(cache=True)
def _edge_extremes(vertices, faces, longest, shortest):
    """``longest[f]``, ``shortest[f]``: the longest and shortest edge of face f.

    Nothing is returned (see ``_layout``).
    """
    for f in range(faces.shape[0]):
        hi = 0.0
        lo = np.inf
        for a in range(3):
            u = faces[f, a]
            v = faces[f, (a + 1) % 3]
            d2 = 0.0
            for x in range(3):
                d2 += (vertices[v, x] - vertices[u, x]) ** 2
            hi = max(hi, d2)
            lo = min(lo, d2)
        longest[f] = np.sqrt(hi)
        shortest[f] = np.sqrt(lo)


@njit(cache=True)
def _item_centres(vertices, faces, keep, cut, out):
    """Three times the centroid of each item: the kept faces, then the strips."""
    n_keep = keep.shape[0]
    for i in range(out.shape[0]):
        for x in range(3):
            if i < n_keep:
                f = keep[i]
                out[i, x] = (
                    vertices[faces[f, 0], x] + vertices[faces[f, 1], x] + vertices[faces[f, 2], x]
                )
            else:
                j = i - n_keep
                out[i, x] = cut[j, 0, x] + cut[j, 1, x] + cut[j, 2, x]


@njit(cache=True)
def _gather(vertices, faces, keep, cut, perm, out):
    """``out[k]``: the triangle of item ``perm[k]`` (a kept face, or a strip)."""
    n_keep = keep.shape[0]
    for k in range(out.shape[0]):
        i = perm[k]
        if i < n_keep:
            for c in range(3):
                v = faces[keep[i], c]
                for x in range(3):
                    out[k, c, x] = vertices[v, x]
        else:
            for c in range(3):
                for x in range(3):
                    out[k, c, x] = cut[i - n_keep, c, x]


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
    if np.size(faces) == 0:  # no surface: winding number 0 everywhere
        value[:] = 0.0
        return value
    tri = _ordered_triangles(vertices, faces, queries=points)
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
