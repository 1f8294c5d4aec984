"""The alpha-convex hull of RFI's footprint points as a list of arcs, and molaR's tests on it.

molaR draws RFI's footprint with the R package ``alphahull``'s alpha-convex
hull (``ahull``): the complement of the union of every open disc of radius
alpha that holds none of the points.  Its boundary is a list of circular arcs
of radius alpha, and molaR decides whether an alpha will do by looking at that
list (see :func:`dentopo.topography.rfi`).  This module builds the list from
the facts recorded in ``TOPOGRAPHY.md`` (it is not a port of ``alphahull``):

* **Arcs.**  A Delaunay edge whose empty radius-alpha disc lies on exactly one
  side carries an arc: of its two triangles, exactly one has a circumradius
  above alpha (outside the convex hull counts as above).  Such an edge is
  always on the alpha shape's boundary (the distances from its ends to the
  points of its Voronoi edge run from at most alpha to above alpha); an edge
  free on both sides (dangling or bridging) carries none.  When neither side
  is above alpha the edge is on the alpha shape only if the larger
  circumradius equals alpha; it then carries an arc, free on that side.  The
  arc is the minor arc of the radius-alpha circle through the edge's ends
  whose centre lies on the free side, directed so that the region is on its
  right (clockwise around the region).
* **Trimming.**  Where arc A ends at a point p and arc B starts there, on the
  two sides of one wedge of the region at p (B is the arc met first turning
  counter-clockwise around p from A), the two circles cross a second time at
  ``q = centre_A + centre_B - p`` (equal radii).  If q lies on B's arc (on the
  far side of B's chord from B's centre), both arcs are re-ended at q, a new
  point numbered after the sample points: the two empty discs overlap over
  the wedge's tip.
* **Degenerate arcs.**  The alpha-extreme points (convex-hull vertices and
  every vertex of a triangle with circumradius above alpha) that end no arc
  are listed as arcs from the point to itself.

Then, as molaR tests the list: **S** (some arc has equal ends, or some point
starts two arcs) and **F** (some arc end lies strictly inside one of the
triangles fanned from the last point over the arcs, with molaR's barycentric
formula in double precision; :func:`fan_test`).

The triangulation is computed once (:class:`AlphaHull`); each alpha is one
compiled pass over its edges (:meth:`AlphaHull.arcs`).

References
----------
Pateiro-Lopez B, Rodriguez-Casal A (2010). Generalizing the convex hull of a
sample: the R package alphahull. J Stat Softw 34(5).
https://doi.org/10.18637/jss.v034.i05
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.spatial import QhullError

from ..._jit import njit
from ...mesh._topology import stable_order
from ..surface import _kernels
from ._delaunay import delaunay

#: :func:`fan_test`'s answers.
FAN_CLEAR, FAN_INSIDE, FAN_UNDEFINED = 0, 1, 2

#: fan_test's filter: points and triangle corners within this share of the
#: points' reach from O are tested against everything; the angular margin
#: around each triangle's wedge (radians), far above the rounding of molaR's
#: formula for anything farther out (about 1e-8 radians).
_NEAR_O = 1e-3
_MARGIN = 1e-6
#: Wedges wider than pi less this (O almost on the chord) are tested against every point.
_WIDE = 1e-3
#: A float64's bits but the sign's: xor'ed into a negative float's bits, they sort as it does.
_ALL_BUT_SIGN = np.int64(0x7FFFFFFFFFFFFFFF)


@njit(cache=True, inline="always")
def _side(points, i, j, k):
    """Twice the signed area of (i, j, k): positive if k lies left of i -> j."""
    return (points[j, 0] - points[i, 0]) * (points[k, 1] - points[i, 1]) - (
        points[j, 1] - points[i, 1]
    ) * (points[k, 0] - points[i, 0])


@njit(cache=True)
def edge_table(points, simplices, neighbors, radius, edges, r_left, r_right, on_hull):
    """Every Delaunay edge once, with the circumradii of the triangles on its two sides.

    Edge: side k of triangle t (opposite its vertex k), from the triangle with
    the lower index or the only one, as ``(i, j)`` with t on its left (the
    vertex order of `simplices` does not matter; a flat triangle takes the
    side its neighbour does not); ``r_left`` is that triangle's circumradius,
    ``r_right`` the other's, or infinity on the convex hull, whose vertices
    are flagged in `on_hull`.  Returns the number of edges written.
    """
    count = 0
    for t in range(simplices.shape[0]):
        for k in range(3):
            o = neighbors[t, k]
            if o != -1 and o < t:
                continue
            i = simplices[t, (k + 1) % 3]
            j = simplices[t, (k + 2) % 3]
            side = _side(points, i, j, simplices[t, k])
            if side == 0 and o != -1:
                apex = simplices[o, 0] + simplices[o, 1] + simplices[o, 2] - i - j
                side = -_side(points, i, j, apex)
            if side < 0:
                i, j = j, i
            edges[count, 0] = i
            edges[count, 1] = j
            r_left[count] = radius[t]
            if o == -1:
                r_right[count] = np.inf
                on_hull[i] = True
                on_hull[j] = True
            else:
                r_right[count] = radius[o]
            count += 1
    return count


@njit(cache=True, inline="always")
def _cross(ax, ay, bx, by):
    return ax * by - ay * bx


@njit(cache=True)
def hull_arcs(
    alpha, points, edges, r_left, r_right, simplices, radius, on_hull, start, end, centre, extra
):
    """The arcs of the alpha-convex hull at `alpha` (see the module), into the arrays.

    `start`, `end` receive the arcs' end indices (new points numbered from
    ``len(points)``, their coordinates in `extra`), `centre` the centres of
    the first `arcs` (non-degenerate) ones.  Returns ``(arcs, total, new,
    pinch, isolated)``: the non-degenerate arcs, all arcs with the degenerate
    ones after them, the new points, and a point that starts two arcs and an
    alpha-extreme point that ends none (-1 if there is none).
    """
    n = points.shape[0]
    k = 0
    for e in range(edges.shape[0]):
        above_l = r_left[e] > alpha
        above_r = r_right[e] > alpha
        if above_l and above_r:
            continue  # free on both sides: dangling or bridging
        if above_l != above_r:
            free_left = above_l
        elif max(r_left[e], r_right[e]) == alpha:
            free_left = r_left[e] >= r_right[e]
        else:
            continue  # inside the region
        if free_left:
            s, t = edges[e, 0], edges[e, 1]
        else:
            s, t = edges[e, 1], edges[e, 0]
        dx = points[t, 0] - points[s, 0]
        dy = points[t, 1] - points[s, 1]
        length = math.hypot(dx, dy)
        half = 0.5 * length
        h = math.sqrt(max(alpha * alpha - half * half, 0.0))
        # the centre on the left of s -> t, the free side
        centre[k, 0] = 0.5 * (points[s, 0] + points[t, 0]) - h * dy / length
        centre[k, 1] = 0.5 * (points[s, 1] + points[t, 1]) + h * dx / length
        start[k] = s
        end[k] = t
        k += 1

    # the arcs at each point, out (2a) and in (2a + 1)
    degree = np.zeros(n + 1, dtype=np.int64)
    for a in range(k):
        degree[start[a] + 1] += 1
        degree[end[a] + 1] += 1
    for p in range(n):
        degree[p + 1] += degree[p]
    fill = degree[:n].copy()
    slots = np.empty(2 * k, dtype=np.int64)
    for a in range(k):
        slots[fill[start[a]]] = 2 * a
        fill[start[a]] += 1
        slots[fill[end[a]]] = 2 * a + 1
        fill[end[a]] += 1

    new_start = start[:k].copy()
    new_end = end[:k].copy()
    new = 0
    order = np.empty(0, dtype=np.int64)
    for p in range(n):
        lo, hi = degree[p], degree[p + 1]
        size = hi - lo
        if size < 2:
            continue
        if size == 2:
            first, second = slots[lo], slots[lo + 1]
            if first % 2 == second % 2:
                continue  # two arcs in (or out): not a wedge
            pairs = 1
        else:
            # the wedges: each in-arc with the next arc counter-clockwise around p, the arcs
            # in the order of their angles (ties, which two edges of a triangulation cannot
            # make, in slot order); sorted as integers, by the sort compiled anyway (numba's
            # float argsort is 1 s more on a fresh install): a float's bits, the negative
            # ones with all but the sign flipped, order as the float does (-0 taken as +0)
            angles = np.empty(size)
            bits = angles.view(np.int64)
            keys = np.empty(size, dtype=np.int64)
            for m in range(size):
                a = slots[lo + m] // 2
                other = end[a] if slots[lo + m] % 2 == 0 else start[a]
                angles[m] = (
                    math.atan2(points[other, 1] - points[p, 1], points[other, 0] - points[p, 0])
                    + 0.0
                )
                keys[m] = bits[m] if bits[m] >= 0 else bits[m] ^ _ALL_BUT_SIGN
            order = np.empty(size, dtype=np.int64)
            stable_order(keys, order)
            pairs = size
        for m in range(pairs):
            if size == 2:
                arc_in = slots[lo] if slots[lo] % 2 == 1 else slots[lo + 1]
                arc_out = slots[lo] if slots[lo] % 2 == 0 else slots[lo + 1]
            else:
                arc_in = slots[lo + order[m]]
                arc_out = slots[lo + order[(m + 1) % size]]
                if arc_in % 2 == 0 or arc_out % 2 == 1:
                    continue
            a_in, b_out = arc_in // 2, arc_out // 2
            qx = centre[a_in, 0] + centre[b_out, 0] - points[p, 0]
            qy = centre[a_in, 1] + centre[b_out, 1] - points[p, 1]
            b = end[b_out]
            bx = points[b, 0] - points[p, 0]
            by = points[b, 1] - points[p, 1]
            side_q = _cross(bx, by, qx - points[p, 0], qy - points[p, 1])
            side_c = _cross(
                bx, by, centre[b_out, 0] - points[p, 0], centre[b_out, 1] - points[p, 1]
            )
            if (side_q > 0 and side_c < 0) or (side_q < 0 and side_c > 0):
                extra[new, 0] = qx
                extra[new, 1] = qy
                new_end[a_in] = n + new
                new_start[b_out] = n + new
                new += 1

    starts = np.zeros(n, dtype=np.int64)
    on_arc = np.zeros(n, dtype=np.bool_)
    pinch = -1
    for a in range(k):
        start[a] = new_start[a]
        end[a] = new_end[a]
        if start[a] < n:
            starts[start[a]] += 1
            on_arc[start[a]] = True
            if starts[start[a]] == 2 and pinch < 0:
                pinch = start[a]
        if end[a] < n:
            on_arc[end[a]] = True
    extreme = on_hull.copy()
    for t in range(simplices.shape[0]):
        if radius[t] > alpha:
            extreme[simplices[t, 0]] = True
            extreme[simplices[t, 1]] = True
            extreme[simplices[t, 2]] = True
    total = k
    isolated = -1
    for p in range(n):
        if extreme[p] and not on_arc[p]:
            start[total] = p
            end[total] = p
            total += 1
            if isolated < 0:
                isolated = p
    return k, total, new, pinch, isolated


@njit(cache=True, inline="always")
def _inside(px, py, bx, by, cx, cy, ox, oy):
    """molaR's test: (px, py) strictly inside the triangle (O, B, C); 1, 0, or 2 (undefined).

    ``D = (yB-yC)(xO-xC) + (xC-xB)(yO-yC)``, ``l1 = [(yB-yC)(x-xC) + (xC-xB)(y-yC)] / D``,
    ``l2 = [(yC-yO)(x-xC) + (xO-xC)(y-yC)] / D``, ``l3 = 1 - l1 - l2``; inside if all
    three are above 0.  A comparison with NaN is R's missing value: the test is
    undefined (2) unless another coordinate is surely not above 0.
    """
    d = (by - cy) * (ox - cx) + (cx - bx) * (oy - cy)
    l1 = ((by - cy) * (px - cx) + (cx - bx) * (py - cy)) / d
    l2 = ((cy - oy) * (px - cx) + (ox - cx) * (py - cy)) / d
    l3 = 1.0 - l1 - l2
    undefined = False
    for value in (l1, l2, l3):
        if math.isnan(value):
            undefined = True
        elif not value > 0:
            return 0
    return 2 if undefined else 1


@njit(cache=True)
def fan_test(xy, start, end, ox, oy):
    """molaR's fan test on arcs (`start`, `end` index `xy`): FAN_INSIDE if some arc end
    lies strictly inside some triangle (O, start, end), FAN_UNDEFINED if some arc's
    ``D`` is 0 (R stops on a missing value: the arc's own ends are tested), else
    FAN_CLEAR.

    Every pair (arc end, triangle) that could be inside is tested with
    :func:`_inside`: a point far enough from O is tested only against the
    triangles whose wedge at O (widened by ``_MARGIN``) holds its direction,
    found by binning the directions; points and triangles near O, and wedges
    of almost pi, are tested against everything.
    """
    k = start.shape[0]
    for a in range(k):
        b, c = start[a], end[a]
        d = (xy[b, 1] - xy[c, 1]) * (ox - xy[c, 0]) + (xy[c, 0] - xy[b, 0]) * (oy - xy[c, 1])
        if d == 0:
            return 2
    if k == 0:
        return 0
    # the tested points: every arc end, once
    tested = np.zeros(xy.shape[0], dtype=np.bool_)
    for a in range(k):
        tested[start[a]] = True
        tested[end[a]] = True
    points = np.flatnonzero(tested)
    reach = 0.0
    for p in points:
        reach = max(reach, abs(xy[p, 0] - ox), abs(xy[p, 1] - oy))
    near = _NEAR_O * reach
    bins = max(64, k)
    width = 2.0 * math.pi / bins
    low = np.empty(k, dtype=np.int64)
    high = np.empty(k, dtype=np.int64)
    everything = np.zeros(k, dtype=np.bool_)
    registered = 0
    for a in range(k):
        b, c = start[a], end[a]
        rb = math.hypot(xy[b, 0] - ox, xy[b, 1] - oy)
        rc = math.hypot(xy[c, 0] - ox, xy[c, 1] - oy)
        tb = math.atan2(xy[b, 1] - oy, xy[b, 0] - ox)
        tc = math.atan2(xy[c, 1] - oy, xy[c, 0] - ox)
        turn = tc - tb
        if turn > math.pi:
            turn -= 2.0 * math.pi
        elif turn < -math.pi:
            turn += 2.0 * math.pi
        if min(rb, rc) < near or abs(turn) > math.pi - _WIDE:
            everything[a] = True
            continue
        lo = min(tb, tb + turn) - _MARGIN
        hi = max(tb, tb + turn) + _MARGIN
        low[a] = math.floor((lo + math.pi) / width)
        high[a] = math.floor((hi + math.pi) / width)
        if high[a] - low[a] + 1 >= bins:
            high[a] = low[a] + bins - 1
        registered += high[a] - low[a] + 1
    if registered > 64 * k:  # wedges overlapping everywhere: test every pair
        for a in range(k):
            everything[a] = True
        registered = 0
    counts = np.zeros(bins + 1, dtype=np.int64)
    for a in range(k):
        if not everything[a]:
            for m in range(low[a], high[a] + 1):
                counts[m % bins + 1] += 1
    for m in range(bins):
        counts[m + 1] += counts[m]
    fill = counts[:bins].copy()
    members = np.empty(registered, dtype=np.int64)
    for a in range(k):
        if not everything[a]:
            for m in range(low[a], high[a] + 1):
                members[fill[m % bins]] = a
                fill[m % bins] += 1
    wide = np.flatnonzero(everything)
    for p in points:
        px, py = xy[p, 0], xy[p, 1]
        if math.hypot(px - ox, py - oy) < near:
            for a in range(k):
                b, c = start[a], end[a]
                if _inside(px, py, xy[b, 0], xy[b, 1], xy[c, 0], xy[c, 1], ox, oy) == 1:
                    return 1
            continue
        m = math.floor((math.atan2(py - oy, px - ox) + math.pi) / width) % bins
        for slot in range(counts[m], counts[m + 1]):
            a = members[slot]
            b, c = start[a], end[a]
            if _inside(px, py, xy[b, 0], xy[b, 1], xy[c, 0], xy[c, 1], ox, oy) == 1:
                return 1
        for a in wide:
            b, c = start[a], end[a]
            if _inside(px, py, xy[b, 0], xy[b, 1], xy[c, 0], xy[c, 1], ox, oy) == 1:
                return 1
    return 0


@njit(cache=True)
def chain(start, end, size, order):
    """The arcs head to tail around each loop, into `order`; each loop from its lowest start.

    Loops are taken in the order of their lowest start index (the point
    indices are below `size`); arcs that do not chain (their start starts
    another arc too) follow the loops in their own order.
    """
    k = start.shape[0]
    starts = np.zeros(size, dtype=np.int64)
    by_start = np.full(size, -1, dtype=np.int64)
    for a in range(k):
        starts[start[a]] += 1
        by_start[start[a]] = a
    used = np.zeros(k, dtype=np.bool_)
    count = 0
    by_lowest = np.empty(k, dtype=np.int64)  # np.argsort(start, kind="stable"), compiled once
    stable_order(start, by_lowest)  # for every kernel that sorts (numba's mergesort: 1 s more)
    for first in by_lowest:
        if used[first] or starts[start[first]] != 1:
            continue
        arc = first
        while arc >= 0 and not used[arc]:
            used[arc] = True
            order[count] = arc
            count += 1
            arc = by_start[end[arc]] if starts[end[arc]] == 1 else -1
    for a in range(k):
        if not used[a]:
            order[count] = a
            count += 1


@dataclass(frozen=True)
class Arcs:
    """The alpha-convex hull's boundary at one alpha, as molaR sees it.

    Attributes
    ----------
    alpha : float
    start, end : (k,) int
        Each arc's end indices, clockwise around the region; points from
        ``n`` on are new (trimmed) points, and degenerate arcs (one point to
        itself) come last.
    xy : (n + new, 2) float
        The scaled points and the new points after them.
    centre : (arcs, 2) float
        The centres of the non-degenerate arcs (the first `arcs` ones).
    arcs, new : int
        Non-degenerate arcs and new points.
    pinch, isolated : int
        A point starting two arcs and an alpha-extreme point on no arc, or -1.
    """

    alpha: float
    start: np.ndarray
    end: np.ndarray
    xy: np.ndarray
    centre: np.ndarray
    arcs: int
    new: int
    pinch: int
    isolated: int

    @property
    def structural(self) -> bool:
        """molaR's S: some arc has equal ends, or some point starts two arcs."""
        return self.pinch >= 0 or self.isolated >= 0


class AlphaHull:
    """The alpha-convex hulls of a 2D point set: its Delaunay triangulation, kept for every alpha.

    Parameters
    ----------
    points : (n, 2) float
        Distinct points, not all on one line.
    """

    def __init__(self, points: np.ndarray):
        points = np.ascontiguousarray(points, dtype=np.float64)
        self.points = points
        self.n = len(points)
        try:
            simplices, neighbors = delaunay(points)
        except QhullError as exc:
            raise ValueError(
                "the footprint has no area: the vertices' x-y positions lie on one line"
            ) from exc
        simplices = np.ascontiguousarray(simplices, dtype=np.int64)
        neighbors = np.ascontiguousarray(neighbors, dtype=np.int64)
        ux, uy = np.empty(len(simplices)), np.empty(len(simplices))
        _kernels.circumcentres(points, simplices, ux, uy)
        self.simplices = simplices
        self.radius = np.hypot(ux, uy)
        most = 3 * len(simplices)
        edges = np.empty((most, 2), dtype=np.int64)
        r_left, r_right = np.empty(most), np.empty(most)
        self.on_hull = np.zeros(self.n, dtype=bool)
        count = edge_table(
            points, simplices, neighbors, self.radius, edges, r_left, r_right, self.on_hull
        )
        self.edges = edges[:count]
        self.r_left = r_left[:count]
        self.r_right = r_right[:count]

    def arcs(self, alpha: float) -> Arcs:
        """The arcs of the alpha-convex hull at `alpha` (see the module)."""
        most = len(self.edges) + self.n
        start = np.empty(most, dtype=np.int64)
        end = np.empty(most, dtype=np.int64)
        centre = np.empty((len(self.edges), 2))
        extra = np.empty((len(self.edges), 2))
        arcs, total, new, pinch, isolated = hull_arcs(
            float(alpha),
            self.points,
            self.edges,
            self.r_left,
            self.r_right,
            self.simplices,
            self.radius,
            self.on_hull,
            start,
            end,
            centre,
            extra,
        )
        return Arcs(
            alpha=float(alpha),
            start=start[:total],
            end=end[:total],
            xy=np.vstack([self.points, extra[:new]]),
            centre=centre[:arcs],
            arcs=arcs,
            new=new,
            pinch=pinch,
            isolated=isolated,
        )

    def fan(self, arcs: Arcs) -> int:
        """molaR's fan test on `arcs` from the last point (:func:`fan_test`)."""
        origin = self.points[-1]
        return int(fan_test(arcs.xy, arcs.start, arcs.end, float(origin[0]), float(origin[1])))
