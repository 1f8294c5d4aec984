"""The bounding-volume hierarchy of the winding number (:mod:`._winding`) over the triangles.

The mesh's triangles, long ones and needles cut (:mod:`._strips`), in k-d order
(``_ordered_triangles``), and the hierarchy over them (``_tree``): nodes that
halve their range of triangles at the median along the longest side of their
centroids' box, built level by level in compiled passes (a level a call, so that
Python reacts to Ctrl-C and SIGTERM between calls), each node a 64-byte record
of its area-weighted centre (float64), its radius rounded up and its far-field
terms (float32): the summed area vector and the symmetric part of its first
moment, which ``_winding._far_field`` reads.
"""

from __future__ import annotations

import numpy as np

from .._jit import in_threads, njit
from ._strips import _edge_extremes, _long_strips, _strip

#: Triangles per leaf of the hierarchy.
LEAF_SIZE = 4


#: Columns of a node's record in ``_tree``: its centre (float64), then, as float32 in the
#: same 64 bytes, its radius, summed area vector and the symmetric part of its first moment.
_CENTRE = 3
_RADIUS, _DIPOLE, _MOMENT = 6, 7, 10  # float32 columns (twice the float64 ones)
# (``_winding._far_field``, compiled and cached, reads them as constants: numba's cache of
# that module does not notice a change here, so edit ``_winding.py`` too if they change)


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


#: Items (triangles) a compiled call of the build (``_kd_order``, ``_summarise``) goes
#: through, in whole levels: each level's nodes together hold every item once, so a level
#: is about a tenth of a second on 2.6M faces, and Python reacts to Ctrl-C and SIGTERM
#: between calls.  A small mesh's levels go in one call: each call costs about 70 us
#: whatever its size (13 levels of a 8,000-face crown, three passes: 2.6 ms of its 30).
ITEMS_PER_CALL = 2_000_000


def _by_levels(level, items: int, per_call: int | None, call, reverse: bool = False) -> None:
    """``call(a, b)`` over the nodes ``a:b`` of every level of the hierarchy.

    In compiled calls of `per_call` levels (by default as many levels of `items` items as
    ``ITEMS_PER_CALL`` allows, at least one), Python reacting to Ctrl-C between them.
    Below ``PARALLEL_BUILD`` items a call takes its levels' nodes at once (the kernel takes
    them in the order its pass needs: a parent before its children top down, after them
    bottom up, the nodes being numbered level by level); above, level by level (the
    deepest first with `reverse`), each level's nodes cut among numba's threads (each node
    owns its rows and its record: the result depends neither on the slices nor on the
    threads).
    """
    count = len(level) - 1
    if per_call is None:
        per_call = ITEMS_PER_CALL // max(1, items)
    per_call = max(1, int(per_call))
    starts = range(0, count, per_call)
    for first in reversed(starts) if reverse else starts:
        last = min(count, first + per_call)
        if items < PARALLEL_BUILD:
            call(int(level[first]), int(level[last]))
            continue
        for depth in range(last - 1, first - 1, -1) if reverse else range(first, last):
            in_threads(int(level[depth]), int(level[depth + 1]), call)


def _kd_order(centres, link, lo, hi, level, perm, per_call=None):
    """Split each inner node's items at its middle along the longest side of their box.

    Rows of `centres` are moved and `perm` alike, level by level, in calls of
    `per_call` levels (``ITEMS_PER_CALL``; the nodes of a level are
    independent, so the order does not depend on the slices).
    """
    _by_levels(
        level,
        len(centres),
        per_call,
        lambda a, b: _kd_nodes(centres, link, lo, hi, perm, a, b),
    )


@njit(cache=True, nogil=True)
def _kd_nodes(centres, link, lo, hi, perm, first, last):
    """``_kd_order`` for the nodes ``first:last``, in order (a parent before its children).
    Nothing is returned (see ``_layout``)."""
    for node in range(first, last):
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
    (``ITEMS_PER_CALL``): a level needs only the one below it.
    """
    _by_levels(
        level,
        len(tri),
        per_call,
        lambda a, b: _combine_nodes(tri, lo, hi, link, nodes, packed, weight, a, b),
        reverse=True,
    )
    _by_levels(
        level,
        len(tri),
        per_call,
        lambda a, b: _radius_nodes(tri, lo, hi, link, nodes, packed, a, b),
    )


@njit(cache=True, nogil=True)
def _combine_nodes(tri, lo, hi, link, nodes, packed, weight, first, last):
    """The sums of the nodes ``first:last`` (``_combine``), the last first (children
    before their parent).  Nothing is returned (see ``_layout``)."""
    sums = np.empty(13)
    for node in range(last - 1, first - 1, -1):
        _combine(tri, lo, hi, link, nodes, packed, weight, node, sums)


@njit(cache=True, nogil=True)
def _radius_nodes(tri, lo, hi, link, nodes, packed, first, last):
    """The radii of the inner nodes among ``first:last`` (``_inner_radius``).

    Nothing is returned (see ``_layout``).
    """
    for node in range(first, last):
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


def _ordered_triangles(
    vertices: np.ndarray,
    faces: np.ndarray,
    leaf_size: int = LEAF_SIZE,
    queries: np.ndarray | None = None,
) -> np.ndarray:
    """The mesh's triangles, long ones cut (:mod:`._strips`), in the k-d order of ``_tree``.

    With `queries`, needles near them are cut too (``_needle_bounds``).  Built
    once, in that order, from the vertices, the faces and the strips: no copy
    of the mesh's triangles is made before it.
    """
    vertices = np.ascontiguousarray(vertices, dtype=np.float64)
    faces = np.ascontiguousarray(faces, dtype=np.int64)
    longest = np.empty(len(faces))
    shortest = np.empty(len(faces))
    _edge_extremes(vertices, faces, longest, shortest)
    long, strips = _long_strips(longest, shortest, lambda rows: vertices[faces[rows]], queries)
    keep = np.arange(len(faces)) if len(long) == 0 else np.delete(np.arange(len(faces)), long)
    n = len(keep) + strips.count
    centres = np.empty((n, 3))
    _item_centres(vertices, faces, keep, *strips, centres)
    perm = np.arange(n)
    lo, hi, link, level = _shape(n, leaf_size)
    _kd_order(centres, link, lo, hi, level, perm)
    del centres, lo, hi, link, level
    tri = np.empty((n, 3, 3))
    in_threads(  # each row alone: the same array on any number of threads
        0,
        n,
        lambda a, b: _gather(vertices, faces, keep, *strips, perm[a:b], tri[a:b]),
        threads_from=PARALLEL_BUILD,
    )
    return tri


@njit(cache=True)
def _item_centres(vertices, faces, keep, corners, apexes, ptr, bounds, first, row, out):
    """Three times the centroid of each item: the kept faces, then the strips
    (:class:`._strips.Strips`, made one at a time)."""
    n_keep = keep.shape[0]
    strip = np.empty((1, 3, 3))
    for i in range(out.shape[0]):
        if i < n_keep:
            f = keep[i]
            for x in range(3):
                out[i, x] = (
                    vertices[faces[f, 0], x] + vertices[faces[f, 1], x] + vertices[faces[f, 2], x]
                )
        else:
            _strip(corners, apexes, ptr, bounds, first, row, i - n_keep, strip, 0)
            for x in range(3):
                out[i, x] = strip[0, 0, x] + strip[0, 1, x] + strip[0, 2, x]


@njit(cache=True, nogil=True)
def _gather(vertices, faces, keep, corners, apexes, ptr, bounds, first, row, perm, out):
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
            _strip(corners, apexes, ptr, bounds, first, row, i - n_keep, out, k)
