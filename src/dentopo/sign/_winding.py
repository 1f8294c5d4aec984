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
(``WORK_PER_ITEM`` solid angles per point and triangle, at least ``WORK_MIN``):
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
pieces that halve where queries come near them (``_strips._needle_bounds``): a query
on the fan used to sum most of it exactly (250 s at 1e5 faces, about 10 s of CPU now).
Queries are processed in spatial order (adaptive, so a
stray vertex does not spoil it), which keeps the parts of the hierarchy they
visit in cache, in parallel, each alone: the values do not depend on the
number of threads.  Everything is O((points + faces) log faces).

This module holds the solid angles, the queries and the public functions; the
hierarchy and the triangles in its order are :mod:`._hierarchy`'s, the strips
:mod:`._strips`'.
"""

from __future__ import annotations

import numba
import numpy as np

from .._jit import in_threads, njit, prange
from ..mesh import spatial_order
from ._hierarchy import _DIPOLE, _MOMENT, _RADIUS, _ordered_triangles, _tree

#: A cluster is "far" from a query point beyond this multiple of its radius.
FAR_FIELD_RATIO = 2.0
#: The same for ``inside``, which needs only the nearest integer, not the value.
INSIDE_RATIO = 1.5
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
        _query(tri, tree, queries[part], ratio, second_order, out[part], work[part])
    return out, work


#: Fewer queries than this are computed on one thread: starting the threads would cost more.
#: (The 1,022 queries of ``low``, about 2 us each, take 2.3 ms on one thread and 1.2 on two.)
PARALLEL_QUERIES = 256

#: The queries of a call are cut into this many chunks, which the threads take in turn: a
#: query's cost depends on how near the surface it lies, so equal slices leave one thread
#: waiting for the other (a 1M-vertex crown's queries: 1.68 s wall in two equal slices,
#: 1.53 s in chunks of 8, as with ``prange``; on ``normal`` 2 and 8 cost the same).
QUERY_CHUNKS = 8


def _query(tri, tree, queries, ratio, second_order, out, work):
    """Approximate solid angles (4 pi w) at the queries, and each query's work.

    The work is the number of nodes visited plus triangles summed exactly.  Both go to
    arrays of the caller (``out``, ``work``).  Each query is computed alone: the result
    depends neither on the chunks nor on the threads.  On numba's threads through
    :func:`dentopo._jit.in_threads`, not a ``prange`` loop: a second compilation of the
    loop's body for OpenMP cost 1.1 s on a fresh install.  The same wall time (1M vertices:
    1.52 s both ways; ``normal``'s call within its noise), about 10 % more CPU at 1M.
    """
    link, nodes, packed = tree
    ratio = float(ratio)
    second_order = bool(second_order)
    in_threads(
        0,
        len(queries),
        lambda a, b: _query_range(
            tri, link, nodes, packed, queries, ratio, second_order, out, work, a, b
        ),
        threads_from=PARALLEL_QUERIES,
        chunks=QUERY_CHUNKS,
    )


@njit(cache=True, nogil=True)
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
        turns = np.int64(0)  # not the literal 0: one compilation of _near_product
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

    Nothing is returned (see ``_hierarchy._layout``).
    """
    for i in prange(queries.shape[0]):
        out[i] = _triangle_sum(tri, 0, tri.shape[0], queries[i])


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
