"""A port of mapbox's concaveman 1.1 (JavaScript) that returns the same ring, point for point.

concaveman (Vladimir Agafonkin, Mapbox) draws a concave hull: it starts from
the convex hull and, edge by edge in first-in first-out order, bends an edge
inward through the nearest point left inside, when that point is close enough
(``concavity``), nearer to this edge than to the two neighbouring ones, and
joining it crosses no edge of the outline.  doolkit's concave footprint is
that JavaScript library (the 1.1 series, with rbush, tinyqueue,
monotone-convex-hull-2d, point-in-polygon and robust-orientation) run in V8
from R.  Which point is taken when several are equally near depends on the
order in which the library walks its R-tree and its binary heap, so this port
rebuilds both exactly as the JavaScript does:

- the point R-tree (rbush, 16 entries a node) is bulk-loaded with rbush's OMT
  packing: its Floyd-Rivest selection (quickselect) and the same stack of
  sub-ranges, with V8's ``Math.log`` and ``Math.exp`` (the fdlibm functions,
  ported in ``_jsmath``, since the C library's may differ in the last bit and
  a selection bound is a ``floor``), so leaves hold the same points in the same
  order; points are removed as rbush removes them (empty nodes dropped,
  boxes recomputed up the path), which keeps the tree the JavaScript's;
- the candidate search pops a copy of tinyqueue's binary heap (same sift-up and
  sift-down, ties kept where tinyqueue keeps them), pushing a node's children
  in their stored order;
- every distance is the library's formula, evaluated in the same order in
  double precision (no fused multiply-add, no reassociation), and the
  orientation tests are exact (robust-orientation's filtered determinant,
  with an exact expansion where the filter cannot decide);
- the JavaScript's second R-tree, of the outline's edges, is not needed: the
  intersection test only asks whether any edge whose box meets the query's box
  crosses, which does not depend on the order the edges are searched in.  The
  edges are kept in a grid of cells (an entry in every cell an edge's box
  meets), which finds every such edge; it compiles in a fraction of the time
  rbush's insertion and split heuristics took (about 2 s on a fresh install).

Points are identified by their index, as the JavaScript identifies them by
object: two input points with equal coordinates stay two points.

Licences
--------
concaveman, rbush, tinyqueue, quickselect: ISC License, Copyright (c) 2016,
Mapbox (concaveman) and Copyright (c) 2016, Vladimir Agafonkin (rbush,
tinyqueue, quickselect):

    Permission to use, copy, modify, and/or distribute this software for any
    purpose with or without fee is hereby granted, provided that the above
    copyright notice and this permission notice appear in all copies.

    THE SOFTWARE IS PROVIDED "AS IS" AND THE AUTHOR DISCLAIMS ALL WARRANTIES
    WITH REGARD TO THIS SOFTWARE INCLUDING ALL IMPLIED WARRANTIES OF
    MERCHANTABILITY AND FITNESS. IN NO EVENT SHALL THE AUTHOR BE LIABLE FOR
    ANY SPECIAL, DIRECT, INDIRECT, OR CONSEQUENTIAL DAMAGES OR ANY DAMAGES
    WHATSOEVER RESULTING FROM LOSS OF USE, DATA OR PROFITS, WHETHER IN AN
    ACTION OF CONTRACT, NEGLIGENCE OR OTHER TORTIOUS ACTION, ARISING OUT OF OR
    IN CONNECTION WITH THE USE OR PERFORMANCE OF THIS SOFTWARE.

monotone-convex-hull-2d, robust-orientation (Mikola Lysenko): MIT License.
point-in-polygon (James Halliday): MIT License.  The segment-to-segment
distance is Dan Sunday's (geomalgorithms.com), as concaveman ports it.

Its R-tree is ``_rbush``, V8's arithmetic (fdlibm's ``log`` and ``exp``, exact orientation,
the monotone convex hull) ``_jsmath``, each with its licence.

May import: nothing of dentopo but :mod:`dentopo._jit`.
"""

from __future__ import annotations

import math

import numpy as np

from ..._jit import njit
from ._jsmath import _fast_convex_hull, _orient
from ._rbush import _load, _remove

_INF = math.inf


# --------------------------------------------------------------------------------------------
# concaveman's outline helpers


@njit(cache=True, inline="always")
def _sq_dist(x0, y0, x1, y1):
    dx = x0 - x1
    dy = y0 - y1
    return dx * dx + dy * dy


@njit(cache=True, inline="always")
def _update_box(p, node_p, nxt, s_box, node):
    i = node_p[node]
    j = node_p[nxt[node]]
    s_box[node, 0] = min(p[i, 0], p[j, 0])
    s_box[node, 1] = min(p[i, 1], p[j, 1])
    s_box[node, 2] = max(p[i, 0], p[j, 0])
    s_box[node, 3] = max(p[i, 1], p[j, 1])


@njit(cache=True)
def _list_edge(p, node_p, nxt, s_box, edge, version, grid, side, cells, entries, count):
    """Put `edge` (its box, and an entry for it in every cell its box meets) into the grid.

    `grid` is ``(x_lo, y_lo, cells per unit of x, of y)``, `cells` (side * side,) the first
    entry of each cell, `entries` (k, 3) int64 rows ``(edge, its version, next entry)``;
    returns `entries` (a larger copy when they were full) and the number in use.
    """
    _update_box(p, node_p, nxt, s_box, edge)
    i0 = _cell(s_box[edge, 0], grid[0], grid[2], side)
    i1 = _cell(s_box[edge, 2], grid[0], grid[2], side)
    j0 = _cell(s_box[edge, 1], grid[1], grid[3], side)
    j1 = _cell(s_box[edge, 3], grid[1], grid[3], side)
    need = count + (i1 - i0 + 1) * (j1 - j0 + 1)
    if need > entries.shape[0]:
        larger = np.empty((max(need, 2 * entries.shape[0]), 3), dtype=np.int64)
        # element by element: an array assignment compiles numba's shape-mismatch message
        # (more than a second on a fresh install)
        for k in range(count):
            for c in range(3):
                larger[k, c] = entries[k, c]
        entries = larger
    for j in range(j0, j1 + 1):
        for i in range(i0, i1 + 1):
            cell = j * side + i
            entries[count, 0] = edge
            entries[count, 1] = version[edge]
            entries[count, 2] = cells[cell]
            cells[cell] = count
            count += 1
    return entries, count


@njit(cache=True, inline="always")
def _cell(x, lo, per_unit, side):
    """The grid column (or row) of coordinate `x`: non-decreasing in `x`, so that two boxes
    that meet share a cell."""
    return min(side - 1, int((x - lo) * per_unit))


# --------------------------------------------------------------------------------------------
# concaveman's distances


@njit(cache=True, inline="always")
def _sq_seg_dist(px, py, x, y, x2, y2):
    """Squared distance from (px, py) to the segment (x, y)-(x2, y2)."""
    dx = x2 - x
    dy = y2 - y
    if dx != 0.0 or dy != 0.0:
        t = ((px - x) * dx + (py - y) * dy) / (dx * dx + dy * dy)
        if t > 1.0:
            x = x2
            y = y2
        elif t > 0.0:
            x += dx * t
            y += dy * t
    dx = px - x
    dy = py - y
    return dx * dx + dy * dy


@njit(cache=True)
def _sq_seg_seg_dist(x0, y0, x1, y1, x2, y2, x3, y3):
    """Squared distance between two segments (Dan Sunday's, as concaveman writes it)."""
    ux = x1 - x0
    uy = y1 - y0
    vx = x3 - x2
    vy = y3 - y2
    wx = x0 - x2
    wy = y0 - y2
    a = ux * ux + uy * uy
    b = ux * vx + uy * vy
    c = vx * vx + vy * vy
    d = ux * wx + uy * wy
    e = vx * wx + vy * wy
    big_d = a * c - b * b
    s_d = big_d
    t_d = big_d
    if big_d == 0.0:
        s_n = 0.0
        s_d = 1.0
        t_n = e
        t_d = c
    else:
        s_n = b * e - c * d
        t_n = a * e - b * d
        if s_n < 0.0:
            s_n = 0.0
            t_n = e
            t_d = c
        elif s_n > s_d:
            s_n = s_d
            t_n = e + b
            t_d = c
    if t_n < 0.0:
        t_n = 0.0
        if -d < 0.0:
            s_n = 0.0
        elif -d > a:
            s_n = s_d
        else:
            s_n = -d
            s_d = a
    elif t_n > t_d:
        t_n = t_d
        if (-d + b) < 0.0:
            s_n = 0.0
        elif -d + b > a:
            s_n = s_d
        else:
            s_n = -d + b
            s_d = a
    sc = 0.0 if s_n == 0.0 else s_n / s_d
    tc = 0.0 if t_n == 0.0 else t_n / t_d
    cx = (1.0 - sc) * x0 + sc * x1
    cy = (1.0 - sc) * y0 + sc * y1
    cx2 = (1.0 - tc) * x2 + tc * x3
    cy2 = (1.0 - tc) * y2 + tc * y3
    dx = cx2 - cx
    dy = cy2 - cy
    return dx * dx + dy * dy


@njit(cache=True, inline="always")
def _sq_seg_box_dist(ax, ay, bx, by, x0, y0, x1, y1):
    """Squared distance from the segment a-b to the box (x0, y0, x1, y1), 0 if it reaches in."""
    if (ax >= x0 and ax <= x1 and ay >= y0 and ay <= y1) or (
        bx >= x0 and bx <= x1 and by >= y0 and by <= y1
    ):
        return 0.0
    d1 = _sq_seg_seg_dist(ax, ay, bx, by, x0, y0, x1, y0)
    if d1 == 0.0:
        return 0.0
    d2 = _sq_seg_seg_dist(ax, ay, bx, by, x0, y0, x0, y1)
    if d2 == 0.0:
        return 0.0
    d3 = _sq_seg_seg_dist(ax, ay, bx, by, x1, y0, x1, y1)
    if d3 == 0.0:
        return 0.0
    d4 = _sq_seg_seg_dist(ax, ay, bx, by, x0, y1, x1, y1)
    if d4 == 0.0:
        return 0.0
    return min(d1, d2, d3, d4)


# --------------------------------------------------------------------------------------------
# concaveman


@njit(cache=True, inline="always")
def _crosses(x1, y1, x2, y2, x3, y3, x4, y4):
    """concaveman's intersects() of segments 1-2 and 3-4 (ends told apart by orient > 0)."""
    if (_orient(x1, y1, x2, y2, x3, y3) > 0) == (_orient(x1, y1, x2, y2, x4, y4) > 0):
        return False
    return (_orient(x3, y3, x4, y4, x1, y1) > 0) != (_orient(x3, y3, x4, y4, x2, y2) > 0)


@njit(cache=True)
def concaveman_ring(points, concavity, length_threshold, out):
    """concaveman(points, concavity, lengthThreshold) as point indices, closed.

    `points` (n, 2) float64, n >= 1, finite.  Writes the ring the JavaScript returns
    into `out` (int64, room for ``2 n + 3``), as indices into `points`, its first point
    repeated at the end; returns its length.  Into the caller's array: a returned array
    is boxed with a little Python code, where a Ctrl-C that arrived meanwhile would be
    raised (see ``dentopo.ariadne._kernel._run_sums``); and not through a wrapper that
    copies it, which compiled the whole search a second time (1.2 s on a fresh install).
    """
    p = points
    n = p.shape[0]
    concavity = max(0.0, concavity)
    hull = _fast_convex_hull(p)
    ibox = np.empty((n, 4))
    for i in range(n):
        ibox[i, 0] = p[i, 0]
        ibox[i, 1] = p[i, 1]
        ibox[i, 2] = p[i, 0]
        ibox[i, 3] = p[i, 1]
    ch, cnt, leaf, hgt, bb, par, where, meta = _load(p, ibox)

    # the outline: a doubly linked list of nodes, node_p[node] its point
    cap = n + hull.shape[0] + 1
    node_p = np.full(cap, -1, dtype=np.int64)
    prv = np.full(cap, -1, dtype=np.int64)
    nxt = np.full(cap, -1, dtype=np.int64)
    queue = np.empty(2 * cap + hull.shape[0], dtype=np.int64)
    q_head = 0
    q_tail = 0
    nodes = 0
    last = -1
    for k in range(hull.shape[0]):
        q = hull[k]
        _remove(ch, cnt, leaf, hgt, bb, par, where, meta, ibox, q)
        node = nodes
        nodes += 1
        node_p[node] = q
        if last < 0:
            prv[node] = node
            nxt[node] = node
        else:
            nxt[node] = nxt[last]
            prv[node] = last
            prv[nxt[last]] = node
            nxt[last] = node
        last = node
        queue[q_tail] = node
        q_tail += 1

    # the outline's edges (edge `node` runs node_p[node] -> its next) in a grid of cells over
    # the points' box, about 4 points a cell: an edge has an entry in every cell its box
    # meets, so that every edge whose box meets a query's box has one in a cell the query's
    # box meets.  An edge taken out of the outline gets a new version; its old entries are
    # dropped as the queries meet them.  (The JavaScript keeps the edges in an R-tree;
    # which edges are searched, in which order, cannot change the result: the search only
    # asks whether any crosses.)
    x_lo = x_hi = p[0, 0]
    y_lo = y_hi = p[0, 1]
    for i in range(1, n):
        x_lo = min(x_lo, p[i, 0])
        x_hi = max(x_hi, p[i, 0])
        y_lo = min(y_lo, p[i, 1])
        y_hi = max(y_hi, p[i, 1])
    side = max(1, int(math.sqrt(n) / 2.0))
    grid = np.empty(4)
    grid[0] = x_lo
    grid[1] = y_lo
    # cells per unit; 0 (one column or row) for a flat box, or one too wide for a double
    grid[2] = side / (x_hi - x_lo) if x_hi > x_lo else 0.0
    grid[3] = side / (y_hi - y_lo) if y_hi > y_lo else 0.0
    cells = np.full(side * side, -1, dtype=np.int64)
    entries = np.empty((4 * n + 64, 3), dtype=np.int64)
    count = np.int64(0)  # not a literal 0: one compilation of _list_edge, not two
    version = np.zeros(cap, dtype=np.int64)
    s_box = np.empty((cap, 4))
    for k in range(q_tail):
        entries, count = _list_edge(
            p, node_p, nxt, s_box, queue[k], version, grid, side, cells, entries, count
        )

    scale = max(abs(x_lo), abs(x_hi), abs(y_lo), abs(y_hi))  # the largest |coordinate|
    slack = 64.0 * 2.220446049250313e-16 * scale + 1e-300
    sq_concavity = concavity * concavity
    sq_len_threshold = length_threshold * length_threshold

    # the candidate search's heap (every tree entry is pushed at most once per search)
    heap_cap = meta[1] + n + 1
    hd = np.empty(heap_cap)
    hi = np.empty(heap_cap, dtype=np.int64)
    hp = np.empty(heap_cap, dtype=np.bool_)

    while q_head < q_tail:
        node = queue[q_head]
        q_head += 1
        a = node_p[node]
        b = node_p[nxt[node]]
        sq_len = _sq_dist(p[a, 0], p[a, 1], p[b, 0], p[b, 1])
        if sq_len < sq_len_threshold:
            continue
        if sq_concavity > 0.0:
            max_sq_len = sq_len / sq_concavity
        elif sq_len > 0.0:
            max_sq_len = _INF
        else:
            max_sq_len = math.nan
        # findCandidate(tree, prev.p, a, b, next.next.p, maxSqLen, segTree)
        pa = node_p[prv[node]]
        pd = node_p[nxt[nxt[node]]]
        ax = p[a, 0]
        ay = p[a, 1]
        bx = p[b, 0]
        by = p[b, 1]
        sx0 = min(ax, bx)
        sy0 = min(ay, by)
        sx1 = max(ax, bx)
        sy1 = max(ay, by)
        far = max_sq_len * (1.0 + 1e-9)
        found = -1
        hn = 0
        tnode = meta[0]
        while tnode >= 0:
            is_leaf = leaf[tnode]
            for k in range(cnt[tnode]):
                c = ch[tnode, k]
                if is_leaf:
                    dist = _sq_seg_dist(p[c, 0], p[c, 1], ax, ay, bx, by)
                else:
                    # a node whose box is, by the gap between the boxes less `slack` (more
                    # than the rounding error of any computed distance), farther than the
                    # limit would be skipped by the exact distance too: skip it unmeasured
                    gx = max(bb[c, 0] - sx1, sx0 - bb[c, 2]) - slack
                    gy = max(bb[c, 1] - sy1, sy0 - bb[c, 3]) - slack
                    if gx > 0.0 or gy > 0.0:
                        gx = max(gx, 0.0)
                        gy = max(gy, 0.0)
                        if gx * gx + gy * gy > far:
                            continue
                    dist = _sq_seg_box_dist(ax, ay, bx, by, bb[c, 0], bb[c, 1], bb[c, 2], bb[c, 3])
                if dist > max_sq_len:
                    continue
                # tinyqueue's push (sift up); written out here, as every heap step below:
                # a helper taking the heap's arrays would cost atomic reference counts a call
                pos = hn
                while pos > 0:
                    parent = (pos - 1) >> 1
                    if dist - hd[parent] >= 0.0:
                        break
                    hd[pos] = hd[parent]
                    hi[pos] = hi[parent]
                    hp[pos] = hp[parent]
                    pos = parent
                hd[pos] = dist
                hi[pos] = c
                hp[pos] = is_leaf
                hn += 1
            while True:
                if hn == 0:
                    tnode = -1
                    break
                top = hi[0]
                top_dist = hd[0]
                top_point = hp[0]
                # tinyqueue's pop (sift down) of the top, a point or the next node to open
                hn -= 1
                if hn > 0:
                    dist = hd[hn]
                    ident = hi[hn]
                    is_point = hp[hn]
                    pos = 0
                    half = hn >> 1
                    while pos < half:
                        left = 2 * pos + 1
                        best = left
                        if left + 1 < hn and hd[left + 1] - hd[left] < 0.0:
                            best = left + 1
                        if hd[best] - dist >= 0.0:
                            break
                        hd[pos] = hd[best]
                        hi[pos] = hi[best]
                        hp[pos] = hp[best]
                        pos = best
                    hd[pos] = dist
                    hi[pos] = ident
                    hp[pos] = is_point
                if not top_point:
                    tnode = top
                    break
                q = top
                qx = p[q, 0]
                qy = p[q, 1]
                d0 = _sq_seg_dist(qx, qy, p[pa, 0], p[pa, 1], p[a, 0], p[a, 1])
                d1 = _sq_seg_dist(qx, qy, p[b, 0], p[b, 1], p[pd, 0], p[pd, 1])
                if not (top_dist < d0 and top_dist < d1):
                    continue
                # noIntersections(a, q) and noIntersections(b, q): no edge of the outline
                # whose box meets the segment's box crosses it
                clear = True
                for end in range(2):
                    e0 = a if end == 0 else b
                    ex = p[e0, 0]
                    ey = p[e0, 1]
                    x0 = min(ex, qx)
                    y0 = min(ey, qy)
                    x1 = max(ex, qx)
                    y1 = max(ey, qy)
                    i0 = _cell(x0, grid[0], grid[2], side)
                    i1 = _cell(x1, grid[0], grid[2], side)
                    j0 = _cell(y0, grid[1], grid[3], side)
                    j1 = _cell(y1, grid[1], grid[3], side)
                    for j in range(j0, j1 + 1):
                        for i in range(i0, i1 + 1):
                            cell = j * side + i
                            before = -1
                            at = cells[cell]
                            while at >= 0:
                                c = entries[at, 0]
                                following = entries[at, 2]
                                if entries[at, 1] != version[c]:  # a removed edge's: drop it
                                    if before < 0:
                                        cells[cell] = following
                                    else:
                                        entries[before, 2] = following
                                    at = following
                                    continue
                                before = at
                                at = following
                                if (
                                    s_box[c, 0] <= x1
                                    and s_box[c, 1] <= y1
                                    and s_box[c, 2] >= x0
                                    and s_box[c, 3] >= y0
                                ):
                                    p1 = node_p[c]
                                    q1 = node_p[nxt[c]]
                                    if (
                                        p1 != q
                                        and q1 != e0
                                        and _crosses(
                                            p[p1, 0], p[p1, 1], p[q1, 0], p[q1, 1], ex, ey, qx, qy
                                        )
                                    ):
                                        clear = False
                                        break
                            if not clear:
                                break
                        if not clear:
                            break
                    if not clear:
                        break
                if clear:
                    found = q
                    break
            if found >= 0:
                break
        if (
            found >= 0
            and min(
                _sq_dist(p[found, 0], p[found, 1], p[a, 0], p[a, 1]),
                _sq_dist(p[found, 0], p[found, 1], p[b, 0], p[b, 1]),
            )
            <= max_sq_len
        ):
            # connect a and b through the point: two new edges for the queue
            new = nodes
            nodes += 1
            node_p[new] = found
            nxt[new] = nxt[node]
            prv[new] = node
            prv[nxt[node]] = new
            nxt[node] = new
            queue[q_tail] = node
            queue[q_tail + 1] = new
            q_tail += 2
            _remove(ch, cnt, leaf, hgt, bb, par, where, meta, ibox, found)
            version[node] += 1  # its old entries: the edge now ends at the new point
            for e in (node, new):
                entries, count = _list_edge(
                    p, node_p, nxt, s_box, e, version, grid, side, cells, entries, count
                )

    node = last
    k = 0
    while True:
        out[k] = node_p[node]
        k += 1
        node = nxt[node]
        if node == last:
            break
    out[k] = node_p[node]
    return k + 1
