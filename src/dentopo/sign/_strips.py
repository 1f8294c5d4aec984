"""Cutting long triangles and needles into strips: the same surface, narrower clusters.

Triangles much longer than the mesh's typical edge (the fans that cap its
holes, the triangles to a stray vertex far away) are cut into strips parallel
to their shortest edge, within a budget (``_strip_bounds``, ``_capped``);
needles meeting at a vertex (a cone's side) are halved where queries come near
them (``_needle_bounds``).  Solid angle is additive, so the winding number is
unchanged up to rounding; the hierarchy (:mod:`._hierarchy`) over the strips has
narrow clusters, and queries near them stay fast (see :mod:`._winding`).
"""

from __future__ import annotations

from typing import NamedTuple

import numba
import numpy as np

from .._jit import njit

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


class Strips(NamedTuple):
    """Triangles to be cut into strips, and how (the strips themselves are made where
    they are used: a cone's needles make millions, 72 bytes each, written once).

    ``corners`` (r, 3, 3): the triangles; ``apexes`` (r,): each one's corner opposite its
    shortest edge; ``ptr`` (r + 1,) and ``bounds``: triangle t's strips run between the
    fractions ``bounds[ptr[t]:ptr[t + 1]]`` of the way from the apex to that edge (0 first,
    1 last); ``first`` (r + 1,): triangle t's strips are items ``first[t]:first[t + 1]``
    (1 + 2 (pieces - 1) triangles); ``row`` (items,): each item's triangle.
    """

    corners: np.ndarray
    apexes: np.ndarray
    ptr: np.ndarray
    bounds: np.ndarray
    first: np.ndarray
    row: np.ndarray

    @property
    def count(self) -> int:
        """The number of strip triangles."""
        return len(self.row)


def strips_of(corners: np.ndarray, ptr: np.ndarray, bounds: np.ndarray) -> Strips:
    """The :class:`Strips` of `corners` cut between `bounds` (CSR `ptr`)."""
    corners = np.ascontiguousarray(corners, dtype=np.float64)
    apexes = np.empty(len(corners), dtype=np.int64)
    _apexes(corners, apexes)
    items = 2 * np.diff(ptr) - 3  # pieces = len - 1; 1 + 2 (pieces - 1) triangles
    first = np.concatenate([[0], np.cumsum(items)]).astype(np.int64)
    row = np.repeat(np.arange(len(corners), dtype=np.int64), items)
    return Strips(corners, apexes, np.asarray(ptr, np.int64), np.asarray(bounds), first, row)


def no_strips() -> Strips:
    """No triangle cut."""
    empty = np.empty(0, dtype=np.int64)
    return Strips(
        np.empty((0, 3, 3)), empty, np.zeros(1, np.int64), np.empty(0), np.zeros(1, np.int64), empty
    )


@njit(cache=True)
def _apexes(corners, out):  # pragma: no cover
    """``out[t]``: the corner of triangle t opposite its shortest edge (the first of equals)."""
    for t in range(corners.shape[0]):
        best = 0
        shortest = np.inf
        for a in range(3):
            b = (a + 1) % 3
            c = (a + 2) % 3
            d = 0.0
            for x in range(3):
                d += (corners[t, b, x] - corners[t, c, x]) ** 2
            if d < shortest:
                shortest = d
                best = a
        out[t] = best


@njit(cache=True, inline="always")
def _strip(corners, apexes, ptr, bounds, first, row, item, out, k):  # pragma: no cover
    """``out[k]``: strip triangle `item`, keeping its triangle's orientation.

    Triangle t's first strip is the apex's corner up to ``s1``; each next one, between
    ``s0`` and ``s1``, is two triangles: ``(va s0, va s1, vb s1)`` and ``(va s0, vb s1,
    vb s0)``, with ``va``, ``vb`` the ends of the shortest edge and each point ``apex + s
    (end - apex)``, coordinate by coordinate.
    """
    t = row[item]
    local = item - first[t]
    apex = apexes[t]
    va = (apex + 1) % 3
    vb = (apex + 2) % 3
    strip = (local + 1) // 2
    s0 = bounds[ptr[t] + strip]
    s1 = bounds[ptr[t] + strip + 1]
    for x in range(3):
        a = corners[t, apex, x]
        at_a0 = a + s0 * (corners[t, va, x] - a)
        at_a1 = a + s1 * (corners[t, va, x] - a)
        at_b0 = a + s0 * (corners[t, vb, x] - a)
        at_b1 = a + s1 * (corners[t, vb, x] - a)
        if local == 0:
            out[k, 0, x] = a
            out[k, 1, x] = at_a1
            out[k, 2, x] = at_b1
        elif local % 2 == 1:
            out[k, 0, x] = at_a0
            out[k, 1, x] = at_a1
            out[k, 2, x] = at_b1
        else:
            out[k, 0, x] = at_a0
            out[k, 1, x] = at_b1
            out[k, 2, x] = at_b0


@njit(cache=True)
def _cut_strips(corners, apexes, ptr, bounds, first, row, out):  # pragma: no cover
    """Every strip triangle, in order, into `out` (nothing is returned, see
    ``_hierarchy._layout``)."""
    for item in range(out.shape[0]):
        _strip(corners, apexes, ptr, bounds, first, row, item, out, item)


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
    needles) and their :class:`Strips`, each triangle's together.
    """
    target = LONG_TRIANGLE * float(np.median(longest)) if len(longest) else 0.0
    if not target > 0:
        return np.empty(0, np.int64), no_strips()
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
        return long, no_strips()
    pieces = np.concatenate([part[0] for part in parts])
    bounds = np.concatenate([part[2] for part in parts])
    ptr = np.concatenate([[0], np.cumsum(pieces + 1)])
    rows = np.concatenate([long, needles])
    return rows, strips_of(triangles(rows), ptr, bounds)


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
        near = owner[test]
        middle = apex[near]
        middle += (0.5 * (s0[test] + s1[test]))[:, None] * axis[near]
        reach = NEEDLE_REACH * span[test]
        # the queries to within an eighth of the shortest reach: one a grid cell (a few
        # where the pieces are long), so that no search meets many nearly tied ones
        cell = reach.min() / 8.0
        finder = cKDTree((_grid_cells(queries, cell) + 0.5) * cell)
        bound = reach.max() + cell
        found = finder.query(
            middle, eps=NEEDLE_EPS, distance_upper_bound=bound, workers=numba.get_num_threads()
        )[0]
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
    pieces = np.bincount(owner, minlength=k)
    ptr = np.concatenate([[0], np.cumsum(pieces + 1)])
    # each needle's pieces' starts in order, then 1: by needle and start, into the slots
    # left between the 1s (in order, so a mask, not an index per slot)
    bounds = np.ones(ptr[-1])
    starts = np.ones(ptr[-1], dtype=bool)
    starts[ptr[1:] - 1] = False
    bounds[starts] = s0[np.lexsort((s0, owner))]
    return pieces, ptr, bounds


def _grid_cells(points: np.ndarray, cell: float) -> np.ndarray:
    """``np.unique(np.floor(points / cell), axis=0)``: the cells of side `cell` that hold
    points, in the same (lexicographic) order, by a sort of the three columns (numpy's
    unique rows sorts them as records: 80 ms for 100,000 points, this 10)."""
    grid = np.floor(points / cell)
    grid = grid[np.lexsort((grid[:, 2], grid[:, 1], grid[:, 0]))]
    fresh = np.ones(len(grid), dtype=bool)
    fresh[1:] = np.any(grid[1:] != grid[:-1], axis=1)
    return grid[fresh]


def _split_long(tri: np.ndarray) -> np.ndarray:
    """Cut triangles much longer than the typical edge into strips (same surface).

    The other triangles, in their order, then the strips.
    """
    edge = np.stack(
        [np.linalg.norm(tri[:, (a + 1) % 3] - tri[:, a], axis=1) for a in range(3)], axis=1
    )
    long, strips = _long_strips(edge.max(axis=1), edge.min(axis=1), lambda rows: tri[rows])
    if len(long) == 0:
        return tri
    cut = np.empty((strips.count, 3, 3))
    _cut_strips(*strips, cut)
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


@njit(cache=True)
def _edge_extremes(vertices, faces, longest, shortest):
    """``longest[f]``, ``shortest[f]``: the longest and shortest edge of face f.

    Nothing is returned (see ``_hierarchy._layout``).
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
