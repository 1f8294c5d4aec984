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
  ported below, since the C library's may differ in the last bit and a
  selection bound is a ``floor``), so leaves hold the same points in the same
  order; points are removed as rbush removes them (empty nodes dropped,
  boxes recomputed up the path), which keeps the tree the JavaScript's;
- the candidate search pops a copy of tinyqueue's binary heap (same sift-up and
  sift-down, ties kept where tinyqueue keeps them), pushing a node's children
  in their stored order;
- every distance is the library's formula, evaluated in the same order in
  double precision (no fused multiply-add, no reassociation), and the
  orientation tests are exact (robust-orientation's filtered determinant,
  with an exact expansion where the filter cannot decide);
- the segment R-tree is rbush's dynamic tree (insert with its split
  heuristics, remove).  Its structure cannot change the result: the
  intersection test only asks whether any indexed edge crosses, and the edges
  searched are those whose boxes meet the query, in any order.

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

The natural logarithm and exponential are ported from fdlibm (FreeBSD msun
``e_log.c`` and ``e_exp.c``, as V8's ``ieee754`` has them):

    Copyright (C) 1993 by Sun Microsystems, Inc. All rights reserved.
    (e_exp.c: Copyright (C) 2004 by Sun Microsystems, Inc.)
    Developed at SunSoft, a Sun Microsystems, Inc. business.
    Permission to use, copy, modify, and distribute this software is freely
    granted, provided that this notice is preserved.

May import: nothing of dentopo but :mod:`dentopo._jit`.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import njit

#: rbush's node capacity as concaveman builds both trees (``rbush(16)``).
MAX_ENTRIES = 16
#: rbush's minimum fill, ``max(2, ceil(16 * 0.4))``.
MIN_ENTRIES = 7
#: Helpers that only read and write arrays they are given are compiled without numba's
#: reference counting (``_nrt=False``): each array argument would otherwise cost two atomic
#: updates a call, which made up most of the time of the tree operations.

#: A node holds one child more than MAX_ENTRIES just before it is split.
_WIDTH = MAX_ENTRIES + 1

_INF = math.inf

# --------------------------------------------------------------------------------------------
# fdlibm's log and exp (V8's Math.log and Math.exp), for positive finite normal arguments


_TWO52 = 4503599627370496.0  # 2**52


@njit(cache=True)
def _bits(x):
    """The IEEE 754 bits of a finite double, zero or normal, as an int64 (no memory view)."""
    if x == 0.0:
        return 0
    sign = 0
    if x < 0.0:
        sign = 1
        x = -x
    m, e = math.frexp(x)  # x = m 2**e, 1/2 <= m < 1
    mantissa = int(m * (2.0 * _TWO52)) - (1 << 52)
    u = ((e + 1022) << 52) | mantissa
    return u - (1 << 63) if sign else u  # the sign bit set, as a signed integer


@njit(cache=True)
def _from_bits(u):
    """The positive normal double with bits u."""
    exponent = (u >> 52) & 0x7FF
    return math.ldexp(_TWO52 + float(u & 0xFFFFFFFFFFFFF), exponent - 1075)


@njit(cache=True)
def js_log(x):
    """``Math.log(x)`` as V8 computes it (fdlibm's ``__ieee754_log``), for x >= 2**-1022."""
    if not (x >= 2.2250738585072014e-308 and x < _INF):
        return math.log(x)  # not reached by concaveman's arguments (counts of points)
    ln2_hi = 6.93147180369123816490e-01
    ln2_lo = 1.90821492927058770002e-10
    lg1 = 6.666666666666735130e-01
    lg2 = 3.999999999940941908e-01
    lg3 = 2.857142874366239149e-01
    lg4 = 2.222219843214978396e-01
    lg5 = 1.818357216161805012e-01
    lg6 = 1.531383769920937332e-01
    lg7 = 1.479819860511658591e-01
    u = _bits(x)
    hx = (u >> 32) & 0xFFFFFFFF
    lx = u & 0xFFFFFFFF
    k = (hx >> 20) - 1023
    hx &= 0x000FFFFF
    i = (hx + 0x95F64) & 0x100000
    x = _from_bits(((hx | (i ^ 0x3FF00000)) << 32) | lx)  # normalise x or x/2
    k += i >> 20
    f = x - 1.0
    if (0x000FFFFF & (2 + hx)) < 3:  # -2**-20 <= f < 2**-20
        if f == 0.0:
            if k == 0:
                return 0.0
            dk = float(k)
            return dk * ln2_hi + dk * ln2_lo
        r = f * f * (0.5 - 0.33333333333333333 * f)
        if k == 0:
            return f - r
        dk = float(k)
        return dk * ln2_hi - ((r - dk * ln2_lo) - f)
    s = f / (2.0 + f)
    dk = float(k)
    z = s * s
    i = hx - 0x6147A
    w = z * z
    j = 0x6B851 - hx
    t1 = w * (lg2 + w * (lg4 + w * lg6))
    t2 = z * (lg1 + w * (lg3 + w * (lg5 + w * lg7)))
    i |= j
    r = t2 + t1
    if i > 0:
        hfsq = 0.5 * f * f
        if k == 0:
            return f - (hfsq - s * (hfsq + r))
        return dk * ln2_hi - ((hfsq - (s * (hfsq + r) + dk * ln2_lo)) - f)
    if k == 0:
        return f - s * (f - r)
    return dk * ln2_hi - ((s * (f - r) - dk * ln2_lo) - f)


@njit(cache=True)
def js_exp(x):
    """``Math.exp(x)`` as V8 computes it (fdlibm's ``__ieee754_exp``), for |x| < 709."""
    if not (abs(x) < 709.0):
        return math.exp(x)  # not reached by concaveman's arguments
    ln2_hi = 6.93147180369123816490e-01
    ln2_lo = 1.90821492927058770002e-10
    invln2 = 1.44269504088896338700e00
    p1 = 1.66666666666666019037e-01
    p2 = -2.77777777770155933842e-03
    p3 = 6.61375632143793436117e-05
    p4 = -1.65339022054652515390e-06
    p5 = 4.13813679705723846039e-08
    u = _bits(x)
    xsb = 1 if u < 0 else 0
    hx = (u >> 32) & 0x7FFFFFFF
    hi = 0.0
    lo = 0.0
    k = 0
    if hx > 0x3FD62E42:  # |x| > 0.5 ln2
        if hx < 0x3FF0A2B2:  # and |x| < 1.5 ln2
            if xsb == 0:
                hi = x - ln2_hi
                lo = ln2_lo
                k = 1
            else:
                hi = x + ln2_hi
                lo = -ln2_lo
                k = -1
        else:
            k = int(invln2 * x + (0.5 if xsb == 0 else -0.5))  # C's (int): toward zero
            t = float(k)
            hi = x - t * ln2_hi  # exact here
            lo = t * ln2_lo
        x = hi - lo
    elif hx < 0x3E300000:  # |x| < 2**-28
        return 1.0 + x
    t = x * x
    c = x - t * (p1 + t * (p2 + t * (p3 + t * (p4 + t * p5))))
    if k == 0:
        return 1.0 - ((x * c) / (c - 2.0) - x)
    y = 1.0 - ((lo - (x * c) / (2.0 - c)) - hi)
    return y * math.ldexp(1.0, k)


# --------------------------------------------------------------------------------------------
# exact orientation (robust-orientation's orientation3: only its sign is ever used)

_EPSILON = 1.1102230246251565e-16
_ERRBOUND3 = (3.0 + 16.0 * _EPSILON) * _EPSILON
_SPLITTER = 134217729.0  # 2**27 + 1


@njit(cache=True)
def _two_product(a, b):
    x = a * b
    c = _SPLITTER * a
    abig = c - a
    ahi = c - abig
    alo = a - ahi
    d = _SPLITTER * b
    bbig = d - b
    bhi = d - bbig
    blo = b - bhi
    err1 = x - ahi * bhi
    err2 = err1 - alo * bhi
    err3 = err2 - ahi * blo
    return alo * blo - err3, x


@njit(cache=True, _nrt=False)
def _grow(e, n, b):
    """Add b to the nonoverlapping expansion e[:n] (increasing magnitude), exactly."""
    q = b
    m = 0
    for i in range(n):
        x = q + e[i]  # two-sum
        bv = x - q
        av = x - bv
        err = (q - av) + (e[i] - bv)
        q = x
        if err != 0.0:
            e[m] = err
            m += 1
    if q != 0.0:
        e[m] = q
        m += 1
    return m


@njit(cache=True)
def _exact_orient_sign(ax, ay, bx, by, cx, cy):
    """Sign of ``(ay - cy)(bx - cx) - (ax - cx)(by - cy)`` in exact arithmetic."""
    # = ay bx - ay cx - cy bx - ax by + ax cy + cx by
    e = np.empty(16)
    n = 0
    lo, hi = _two_product(ay, bx)
    n = _grow(e, _grow(e, n, lo), hi)
    lo, hi = _two_product(-ay, cx)
    n = _grow(e, _grow(e, n, lo), hi)
    lo, hi = _two_product(-cy, bx)
    n = _grow(e, _grow(e, n, lo), hi)
    lo, hi = _two_product(-ax, by)
    n = _grow(e, _grow(e, n, lo), hi)
    lo, hi = _two_product(ax, cy)
    n = _grow(e, _grow(e, n, lo), hi)
    lo, hi = _two_product(cx, by)
    n = _grow(e, _grow(e, n, lo), hi)
    if n == 0:
        return 0
    return 1 if e[n - 1] > 0.0 else -1


@njit(cache=True)
def _orient(ax, ay, bx, by, cx, cy):
    """Sign (-1, 0, 1) of robust-orientation's ``orient(a, b, c)``.

    Hot helpers take scalars, not arrays: an array argument costs two atomic
    reference-count updates a call.
    """
    left = (ay - cy) * (bx - cx)
    right = (ax - cx) * (by - cy)
    det = left - right
    if left > 0.0:
        if right <= 0.0:
            return 1 if det > 0.0 else (-1 if det < 0.0 else 0)
        s = left + right
    elif left < 0.0:
        if right >= 0.0:
            return 1 if det > 0.0 else (-1 if det < 0.0 else 0)
        s = -(left + right)
    else:
        return 1 if det > 0.0 else (-1 if det < 0.0 else 0)
    tol = _ERRBOUND3 * s
    if det >= tol or det <= -tol:
        return 1 if det > 0.0 else (-1 if det < 0.0 else 0)
    return _exact_orient_sign(ax, ay, bx, by, cx, cy)


# --------------------------------------------------------------------------------------------
# concaveman's convex hull: the 4 extreme points' quadrilateral culls, then a monotone chain


@njit(cache=True)
def _in_quad(x, y, qx, qy):
    """point-in-polygon (ray casting) of (x, y) in the quadrilateral (qx, qy)."""
    inside = False
    j = 3
    for k in range(4):
        xi = qx[k]
        yi = qy[k]
        xj = qx[j]
        yj = qy[j]
        if ((yi > y) != (yj > y)) and (x < (xj - xi) * (y - yi) / (yj - yi) + xi):
            inside = not inside
        j = k
    return inside


@njit(cache=True, _nrt=False)
def _before(fx, fy, i, j):
    """(x, y, index) of i before that of j."""
    if fx[i] != fx[j]:
        return fx[i] < fx[j]
    if fy[i] != fy[j]:
        return fy[i] < fy[j]
    return i < j


@njit(cache=True)
def _stable_xy_order(fx, fy):
    """Indices sorted by x, then y, then index: what a stable sort by (x, y) gives.

    A bottom-up merge sort (the keys are distinct, so any correct sort agrees).
    """
    n = fx.shape[0]
    order = np.arange(n)
    work = np.empty(n, dtype=np.int64)
    width = 1
    while width < n:
        for lo in range(0, n, 2 * width):
            mid = min(lo + width, n)
            hi = min(lo + 2 * width, n)
            i = lo
            j = mid
            for k in range(lo, hi):
                if i < mid and (j >= hi or not _before(fx, fy, order[j], order[i])):
                    work[k] = order[i]
                    i += 1
                else:
                    work[k] = order[j]
                    j += 1
        order, work = work, order
        width *= 2
    return order


@njit(cache=True)
def fast_convex_hull(p, out):
    """concaveman's convex hull of the points (n >= 1) into `out` (room for ``2 n + 3``).

    Returns its length.

    Point indices, not closed.  (A kernel called from Python returns no array:
    numba's boxing of a returned array is where Ctrl-C crashed.)
    """
    hull = _fast_convex_hull(p)
    out[: hull.shape[0]] = hull
    return hull.shape[0]


@njit(cache=True)
def _fast_convex_hull(p):
    n = p.shape[0]
    left = 0
    top = 0
    right = 0
    bottom = 0
    for i in range(n):
        if p[i, 0] < p[left, 0]:
            left = i
        if p[i, 0] > p[right, 0]:
            right = i
        if p[i, 1] < p[top, 1]:
            top = i
        if p[i, 1] > p[bottom, 1]:
            bottom = i
    qx = (p[left, 0], p[top, 0], p[right, 0], p[bottom, 0])
    qy = (p[left, 1], p[top, 1], p[right, 1], p[bottom, 1])
    filtered = np.empty(n + 4, dtype=np.int64)
    filtered[0] = left
    filtered[1] = top
    filtered[2] = right
    filtered[3] = bottom
    nf = 4
    for i in range(n):
        if not _in_quad(p[i, 0], p[i, 1], qx, qy):
            filtered[nf] = i
            nf += 1
    filtered = filtered[:nf]
    # monotone-convex-hull-2d: indices sorted by x then y (a stable sort, as V8's)
    fx = np.empty(nf)
    fy = np.empty(nf)
    for i in range(nf):
        fx[i] = p[filtered[i], 0]
        fy[i] = p[filtered[i], 1]
    order = _stable_xy_order(fx, fy)
    srt = filtered[order]
    lower = np.empty(nf, dtype=np.int64)
    upper = np.empty(nf, dtype=np.int64)
    lower[0] = srt[0]
    lower[1] = srt[1]
    upper[0] = srt[0]
    upper[1] = srt[1]
    nl = 2
    nu = 2
    for i in range(2, nf):
        q = srt[i]
        qx = p[q, 0]
        qy = p[q, 1]
        while nl > 1:
            u = lower[nl - 2]
            v = lower[nl - 1]
            if _orient(p[u, 0], p[u, 1], p[v, 0], p[v, 1], qx, qy) > 0:
                break
            nl -= 1
        lower[nl] = q
        nl += 1
        while nu > 1:
            u = upper[nu - 2]
            v = upper[nu - 1]
            if _orient(p[u, 0], p[u, 1], p[v, 0], p[v, 1], qx, qy) < 0:
                break
            nu -= 1
        upper[nu] = q
        nu += 1
    hull = np.empty(nl + nu - 2, dtype=np.int64)
    hull[:nl] = lower[:nl]
    k = nl
    for j in range(nu - 2, 0, -1):
        hull[k] = upper[j]
        k += 1
    return hull


# --------------------------------------------------------------------------------------------
# rbush: nodes in arrays.  ch[node, :cnt[node]] are the children (item ids in a leaf, node ids
# otherwise), bb[node] = (minX, minY, maxX, maxY), par[node] the parent (-1 for the root),
# where[item] the leaf holding an item (-1 when not in the tree), ibox[item] an item's box.
# meta[0] = root, meta[1] = nodes allocated.


@njit(cache=True)
def _new_tree(capacity, items):
    ch = np.empty((capacity, _WIDTH), dtype=np.int64)
    cnt = np.zeros(capacity, dtype=np.int64)
    leaf = np.ones(capacity, dtype=np.bool_)
    hgt = np.ones(capacity, dtype=np.int64)
    bb = np.empty((capacity, 4))
    par = np.full(capacity, -1, dtype=np.int64)
    where = np.full(items, -1, dtype=np.int64)
    meta = np.zeros(2, dtype=np.int64)
    return ch, cnt, leaf, hgt, bb, par, where, meta


@njit(cache=True, _nrt=False)
def _alloc(cnt, leaf, hgt, bb, par, meta):
    node = meta[1]
    meta[1] += 1
    cnt[node] = 0
    leaf[node] = True
    hgt[node] = 1
    bb[node, 0] = _INF
    bb[node, 1] = _INF
    bb[node, 2] = -_INF
    bb[node, 3] = -_INF
    par[node] = -1
    return node


@njit(cache=True)
def _grow_tree(ch, cnt, leaf, hgt, bb, par, meta, need):
    """The tree's arrays with room for `need` more nodes (the same arrays if there is room)."""
    cap = ch.shape[0]
    if meta[1] + need <= cap:
        return ch, cnt, leaf, hgt, bb, par
    new = max(2 * cap, meta[1] + need)
    ch2 = np.empty((new, _WIDTH), dtype=np.int64)
    ch2[:cap] = ch
    cnt2 = np.zeros(new, dtype=np.int64)
    cnt2[:cap] = cnt
    leaf2 = np.ones(new, dtype=np.bool_)
    leaf2[:cap] = leaf
    hgt2 = np.ones(new, dtype=np.int64)
    hgt2[:cap] = hgt
    bb2 = np.empty((new, 4))
    bb2[:cap] = bb
    par2 = np.full(new, -1, dtype=np.int64)
    par2[:cap] = par
    return ch2, cnt2, leaf2, hgt2, bb2, par2


@njit(cache=True, _nrt=False)
def _calc_bbox(ch, cnt, leaf, bb, ibox, node):
    src = ibox if leaf[node] else bb  # the children's boxes
    x0 = _INF
    y0 = _INF
    x1 = -_INF
    y1 = -_INF
    for k in range(cnt[node]):
        c = ch[node, k]
        x0 = min(x0, src[c, 0])
        y0 = min(y0, src[c, 1])
        x1 = max(x1, src[c, 2])
        y1 = max(y1, src[c, 3])
    bb[node, 0] = x0
    bb[node, 1] = y0
    bb[node, 2] = x1
    bb[node, 3] = y1


@njit(cache=True, _nrt=False)
def _quickselect(items, key, k, left, right, frames):
    """quickselect (Floyd-Rivest) of items[left:right + 1] by key[item], as rbush's.

    The JavaScript recurses once a pass on a narrower range; rows of `frames`
    (scratch, (3, 64) int64: left, right, recursion done) replace the recursion.
    """
    fl = frames[0]
    fr = frames[1]
    fdone = frames[2]
    depth = 0
    fl[0] = left
    fr[0] = right
    fdone[0] = 0
    while depth >= 0:
        left = fl[depth]
        right = fr[depth]
        if right <= left:
            depth -= 1
            continue
        if fdone[depth] == 0 and right - left > 600:
            n = float(right - left + 1)
            m = float(k - left + 1)
            z = js_log(n)
            s = 0.5 * js_exp(2.0 * z / 3.0)
            sd = 0.5 * math.sqrt(z * s * (n - s) / n) * (-1.0 if m - n / 2.0 < 0.0 else 1.0)
            new_left = max(left, math.floor(k - m * s / n + sd))
            new_right = min(right, math.floor(k + (n - m) * s / n + sd))
            fdone[depth] = 1
            depth += 1
            fl[depth] = new_left
            fr[depth] = new_right
            fdone[depth] = 0
            continue
        fdone[depth] = 0
        t = key[items[k]]
        i = left
        j = right
        tmp = items[left]
        items[left] = items[k]
        items[k] = tmp
        if key[items[right]] > t:
            tmp = items[left]
            items[left] = items[right]
            items[right] = tmp
        while i < j:
            tmp = items[i]
            items[i] = items[j]
            items[j] = tmp
            i += 1
            j -= 1
            while key[items[i]] < t:
                i += 1
            while key[items[j]] > t:
                j -= 1
        if key[items[left]] == t:
            tmp = items[left]
            items[left] = items[j]
            items[j] = tmp
        else:
            j += 1
            tmp = items[j]
            items[j] = items[right]
            items[right] = tmp
        if j <= k:
            left = j + 1
        if k <= j:
            right = j - 1
        fl[depth] = left
        fr[depth] = right


@njit(cache=True, _nrt=False)
def _multi_select(items, left, right, n, key, stack, frames):
    """rbush's multiSelect: groups of n, sorted between groups; `stack`, `frames` are scratch."""
    top = 0
    stack[0] = left
    stack[1] = right
    top = 2
    while top > 0:
        right = stack[top - 1]
        left = stack[top - 2]
        top -= 2
        if right - left <= n:
            continue
        mid = left + math.ceil(float(right - left) / n / 2.0) * n
        _quickselect(items, key, mid, left, right, frames)
        stack[top] = left
        stack[top + 1] = mid
        stack[top + 2] = mid
        stack[top + 3] = right
        top += 4


@njit(cache=True)
def _packed_nodes(n):
    """How many nodes rbush's bulk load makes for n items (its splitting arithmetic)."""
    stack_n = np.empty(1024, dtype=np.int64)
    stack_h = np.empty(1024, dtype=np.int64)
    stack_n[0] = n
    stack_h[0] = 0
    top = 1
    nodes = 0
    while top > 0:
        top -= 1
        size = stack_n[top]
        height = stack_h[top]
        nodes += 1
        m = MAX_ENTRIES
        if size <= m:
            continue
        if height == 0:
            height = math.ceil(js_log(float(size)) / js_log(float(m)))
            m = math.ceil(size / float(MAX_ENTRIES) ** (height - 1))
        n2 = math.ceil(size / float(m))
        n1 = n2 * math.ceil(math.sqrt(float(m)))
        for i in range(0, size, n1):
            right2 = min(i + n1 - 1, size - 1)
            for j in range(i, right2 + 1, n2):
                right3 = min(j + n2 - 1, right2)
                stack_n[top] = right3 - j + 1
                stack_h[top] = height - 1
                top += 1
    return nodes


@njit(cache=True)
def _load(points, ibox):
    """rbush's ``load`` of all points (OMT bulk load; inserts below MIN_ENTRIES points)."""
    n = points.shape[0]
    tree = _new_tree(max(_packed_nodes(n), 1) + 1, n)
    ch, cnt, leaf, hgt, bb, par, where, meta = tree
    root = _alloc(cnt, leaf, hgt, bb, par, meta)
    meta[0] = root
    if n < MIN_ENTRIES:
        for item in range(n):  # insert into a single leaf: no split below 16 items
            ch[root, cnt[root]] = item
            cnt[root] += 1
            where[item] = root
        _calc_bbox(ch, cnt, leaf, bb, ibox, root)
        return tree
    items = np.arange(n)
    xkey = points[:, 0].copy()
    ykey = points[:, 1].copy()
    stack = np.empty(4 * 64 + 8, dtype=np.int64)
    frames = np.empty((3, 64), dtype=np.int64)
    # pending nodes: at most 16 children a level wait (and rbush's trees are shallow)
    t_node = np.empty(_WIDTH * 64, dtype=np.int64)
    t_left = np.empty(_WIDTH * 64, dtype=np.int64)
    t_right = np.empty(_WIDTH * 64, dtype=np.int64)
    t_height = np.empty(_WIDTH * 64, dtype=np.int64)
    t_node[0] = root
    t_left[0] = 0
    t_right[0] = n - 1
    t_height[0] = 0
    top = 1
    # each node's ranges are rearranged before its children's, and sibling ranges are disjoint,
    # so building the children in stack order gives the recursion's arrangement
    while top > 0:
        top -= 1
        node = t_node[top]
        left = t_left[top]
        right = t_right[top]
        height = t_height[top]
        size = right - left + 1
        m = MAX_ENTRIES
        if size <= m:
            for k in range(size):
                ch[node, k] = items[left + k]
                where[items[left + k]] = node
            cnt[node] = size
            continue
        if height == 0:
            height = math.ceil(js_log(float(size)) / js_log(float(m)))
            m = math.ceil(size / float(MAX_ENTRIES) ** (height - 1))
        leaf[node] = False
        hgt[node] = height
        n2 = math.ceil(size / float(m))
        n1 = n2 * math.ceil(math.sqrt(float(m)))
        _multi_select(items, left, right, n1, xkey, stack, frames)
        for i in range(left, right + 1, n1):
            right2 = min(i + n1 - 1, right)
            _multi_select(items, i, right2, n2, ykey, stack, frames)
            for j in range(i, right2 + 1, n2):
                right3 = min(j + n2 - 1, right2)
                child = _alloc(cnt, leaf, hgt, bb, par, meta)
                ch[node, cnt[node]] = child
                cnt[node] += 1
                par[child] = node
                t_node[top] = child
                t_left[top] = j
                t_right[top] = right3
                t_height[top] = height - 1
                top += 1
    for node in range(meta[1] - 1, -1, -1):  # children were made after their parents
        _calc_bbox(ch, cnt, leaf, bb, ibox, node)
    return tree


@njit(cache=True, _nrt=False)
def _remove(ch, cnt, leaf, hgt, bb, par, where, meta, ibox, item):
    """rbush's ``remove``: drop the item from its leaf, then condense the path to the root."""
    node = where[item]
    if node < 0:
        return
    k = 0
    while ch[node, k] != item:
        k += 1
    for j in range(k, cnt[node] - 1):
        ch[node, j] = ch[node, j + 1]
    cnt[node] -= 1
    where[item] = -1
    while node >= 0:
        parent = par[node]
        if cnt[node] == 0:
            if parent >= 0:
                k = 0
                while ch[parent, k] != node:
                    k += 1
                for j in range(k, cnt[parent] - 1):
                    ch[parent, j] = ch[parent, j + 1]
                cnt[parent] -= 1
            else:  # rbush's clear(): an empty leaf as the root
                leaf[node] = True
                hgt[node] = 1
                bb[node, 0] = _INF
                bb[node, 1] = _INF
                bb[node, 2] = -_INF
                bb[node, 3] = -_INF
        else:
            _calc_bbox(ch, cnt, leaf, bb, ibox, node)
        node = parent


@njit(cache=True, _nrt=False)
def _dist_bbox(ch, leaf, bb, ibox, node, k, p, out):
    src = ibox if leaf[node] else bb
    out[0] = _INF
    out[1] = _INF
    out[2] = -_INF
    out[3] = -_INF
    for i in range(k, p):
        c = ch[node, i]
        out[0] = min(out[0], src[c, 0])
        out[1] = min(out[1], src[c, 1])
        out[2] = max(out[2], src[c, 2])
        out[3] = max(out[3], src[c, 3])


@njit(cache=True, _nrt=False)
def _sort_children(ch, cnt, leaf, bb, ibox, node, axis):
    """Stable sort of a node's children by their box's min x (axis 0) or min y (axis 1)."""
    src = ibox if leaf[node] else bb
    for i in range(1, cnt[node]):
        c = ch[node, i]
        v = src[c, axis]
        j = i
        while j > 0:
            d = ch[node, j - 1]
            if src[d, axis] > v:
                ch[node, j] = d
                j -= 1
            else:
                break
        ch[node, j] = c


@njit(cache=True, _nrt=False)
def _all_dist_margin(ch, cnt, leaf, bb, ibox, node, m, big_m, axis, lbox, rbox):
    _sort_children(ch, cnt, leaf, bb, ibox, node, axis)
    _dist_bbox(ch, leaf, bb, ibox, node, 0, m, lbox)
    _dist_bbox(ch, leaf, bb, ibox, node, big_m - m, big_m, rbox)
    margin = ((lbox[2] - lbox[0]) + (lbox[3] - lbox[1])) + (
        (rbox[2] - rbox[0]) + (rbox[3] - rbox[1])
    )
    src = ibox if leaf[node] else bb
    for i in range(m, big_m - m):
        c = ch[node, i]
        for j in range(2):
            lbox[j] = min(lbox[j], src[c, j])
            lbox[j + 2] = max(lbox[j + 2], src[c, j + 2])
        margin += (lbox[2] - lbox[0]) + (lbox[3] - lbox[1])
    for i in range(big_m - m - 1, m - 1, -1):
        c = ch[node, i]
        for j in range(2):
            rbox[j] = min(rbox[j], src[c, j])
            rbox[j + 2] = max(rbox[j + 2], src[c, j + 2])
        margin += (rbox[2] - rbox[0]) + (rbox[3] - rbox[1])
    return margin


@njit(cache=True, _nrt=False)
def _split(ch, cnt, leaf, hgt, bb, par, where, meta, ibox, path, level, lbox, rbox):
    node = path[level]
    big_m = cnt[node]
    m = MIN_ENTRIES
    # chooseSplitAxis: sorted by x, then by y; back to x if x's margins are smaller
    x_margin = _all_dist_margin(ch, cnt, leaf, bb, ibox, node, m, big_m, 0, lbox, rbox)
    y_margin = _all_dist_margin(ch, cnt, leaf, bb, ibox, node, m, big_m, 1, lbox, rbox)
    if x_margin < y_margin:
        _sort_children(ch, cnt, leaf, bb, ibox, node, 0)
    # chooseSplitIndex: least overlap, then least area
    min_overlap = _INF
    min_area = _INF
    index = m
    for i in range(m, big_m - m + 1):
        _dist_bbox(ch, leaf, bb, ibox, node, 0, i, lbox)
        _dist_bbox(ch, leaf, bb, ibox, node, i, big_m, rbox)
        overlap = max(0.0, min(lbox[2], rbox[2]) - max(lbox[0], rbox[0])) * max(
            0.0, min(lbox[3], rbox[3]) - max(lbox[1], rbox[1])
        )
        area = (lbox[2] - lbox[0]) * (lbox[3] - lbox[1]) + (rbox[2] - rbox[0]) * (rbox[3] - rbox[1])
        if overlap < min_overlap:
            min_overlap = overlap
            index = i
            min_area = area if area < min_area else min_area
        elif overlap == min_overlap:
            if area < min_area:
                min_area = area
                index = i
    new = _alloc(cnt, leaf, hgt, bb, par, meta)
    for k in range(index, big_m):
        c = ch[node, k]
        ch[new, k - index] = c
        if leaf[node]:
            where[c] = new
        else:
            par[c] = new
    cnt[new] = big_m - index
    cnt[node] = index
    hgt[new] = hgt[node]
    leaf[new] = leaf[node]
    _calc_bbox(ch, cnt, leaf, bb, ibox, node)
    _calc_bbox(ch, cnt, leaf, bb, ibox, new)
    if level > 0:
        parent = path[level - 1]
        ch[parent, cnt[parent]] = new
        cnt[parent] += 1
        par[new] = parent
    else:  # split the root
        root = _alloc(cnt, leaf, hgt, bb, par, meta)
        ch[root, 0] = node
        ch[root, 1] = new
        cnt[root] = 2
        hgt[root] = hgt[node] + 1
        leaf[root] = False
        par[node] = root
        par[new] = root
        _calc_bbox(ch, cnt, leaf, bb, ibox, root)
        meta[0] = root


@njit(cache=True, _nrt=False)
def _insert(ch, cnt, leaf, hgt, bb, par, where, meta, ibox, item, path, lbox, rbox):
    """rbush's ``insert`` of an item at the leaf level (the tree must have room for its splits)."""
    root = meta[0]
    level = hgt[root] - 1
    x0 = ibox[item, 0]
    y0 = ibox[item, 1]
    x1 = ibox[item, 2]
    y1 = ibox[item, 3]
    # chooseSubtree: least enlargement, then least area
    node = root
    depth = 0
    target = -1
    while True:
        path[depth] = node
        depth += 1
        if leaf[node] or depth - 1 == level:
            break
        min_area = _INF
        min_enlargement = _INF
        for k in range(cnt[node]):
            c = ch[node, k]
            area = (bb[c, 2] - bb[c, 0]) * (bb[c, 3] - bb[c, 1])
            enlargement = (max(x1, bb[c, 2]) - min(x0, bb[c, 0])) * (
                max(y1, bb[c, 3]) - min(y0, bb[c, 1])
            ) - area
            if enlargement < min_enlargement:
                min_enlargement = enlargement
                min_area = area if area < min_area else min_area
                target = c
            elif enlargement == min_enlargement:
                if area < min_area:
                    min_area = area
                    target = c
        node = target if target >= 0 else ch[node, 0]
    ch[node, cnt[node]] = item
    cnt[node] += 1
    where[item] = node
    bb[node, 0] = min(bb[node, 0], x0)
    bb[node, 1] = min(bb[node, 1], y0)
    bb[node, 2] = max(bb[node, 2], x1)
    bb[node, 3] = max(bb[node, 3], y1)
    while level >= 0:
        if cnt[path[level]] > MAX_ENTRIES:
            _split(ch, cnt, leaf, hgt, bb, par, where, meta, ibox, path, level, lbox, rbox)
            level -= 1
        else:
            break
    for i in range(level, -1, -1):
        node = path[i]
        bb[node, 0] = min(bb[node, 0], x0)
        bb[node, 1] = min(bb[node, 1], y0)
        bb[node, 2] = max(bb[node, 2], x1)
        bb[node, 3] = max(bb[node, 3], y1)


# --------------------------------------------------------------------------------------------
# concaveman's outline helpers


@njit(cache=True)
def _sq_dist(x0, y0, x1, y1):
    dx = x0 - x1
    dy = y0 - y1
    return dx * dx + dy * dy


@njit(cache=True, _nrt=False)
def _update_box(p, node_p, nxt, s_box, node):
    i = node_p[node]
    j = node_p[nxt[node]]
    s_box[node, 0] = min(p[i, 0], p[j, 0])
    s_box[node, 1] = min(p[i, 1], p[j, 1])
    s_box[node, 2] = max(p[i, 0], p[j, 0])
    s_box[node, 3] = max(p[i, 1], p[j, 1])


# --------------------------------------------------------------------------------------------
# concaveman's distances


@njit(cache=True)
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


@njit(cache=True)
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


@njit(cache=True)
def _crosses(x1, y1, x2, y2, x3, y3, x4, y4):
    """concaveman's intersects() of segments 1-2 and 3-4 (ends told apart by orient > 0)."""
    if (_orient(x1, y1, x2, y2, x3, y3) > 0) == (_orient(x1, y1, x2, y2, x4, y4) > 0):
        return False
    return (_orient(x3, y3, x4, y4, x1, y1) > 0) != (_orient(x3, y3, x4, y4, x2, y2) > 0)


@njit(cache=True)
def concaveman_ring(points, concavity, length_threshold, out):
    """:func:`_concaveman_ring` into `out` (int64, room for ``2 n + 3``): the ring's length."""
    ring = _concaveman_ring(points, concavity, length_threshold)
    out[: ring.shape[0]] = ring
    return ring.shape[0]


@njit(cache=True)
def _concaveman_ring(points, concavity, length_threshold):
    """concaveman(points, concavity, lengthThreshold) as point indices, closed.

    `points` (n, 2) float64, n >= 1, finite.  Returns the ring the JavaScript
    returns, as indices into `points`, its first point repeated at the end.
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

    # the segment R-tree over the outline's edges: edge `node` runs node_p[node] -> its next
    s_box = np.empty((cap, 4))
    s_ch, s_cnt, s_leaf, s_hgt, s_bb, s_par, s_where, s_meta = _new_tree(64, cap)
    s_meta[0] = _alloc(s_cnt, s_leaf, s_hgt, s_bb, s_par, s_meta)
    path = np.empty(64, dtype=np.int64)
    lbox = np.empty(4)
    rbox = np.empty(4)
    for k in range(q_tail):
        node = queue[k]
        _update_box(p, node_p, nxt, s_box, node)
        s_ch, s_cnt, s_leaf, s_hgt, s_bb, s_par = _grow_tree(
            s_ch, s_cnt, s_leaf, s_hgt, s_bb, s_par, s_meta, s_hgt[s_meta[0]] + 2
        )
        _insert(
            s_ch, s_cnt, s_leaf, s_hgt, s_bb, s_par, s_where, s_meta, s_box, node, path,
            lbox, rbox,
        )  # fmt: skip

    scale = 0.0
    for i in range(n):
        scale = max(scale, abs(p[i, 0]), abs(p[i, 1]))
    slack = 64.0 * 2.220446049250313e-16 * scale + 1e-300
    sq_concavity = concavity * concavity
    sq_len_threshold = length_threshold * length_threshold

    # the candidate search's heap (every tree entry is pushed at most once per search)
    heap_cap = meta[1] + n + 1
    hd = np.empty(heap_cap)
    hi = np.empty(heap_cap, dtype=np.int64)
    hp = np.empty(heap_cap, dtype=np.bool_)
    stack = np.empty(_WIDTH * 64, dtype=np.int64)

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
                    stack[0] = s_meta[0]
                    depth = 1
                    while depth > 0 and clear:
                        depth -= 1
                        snode = stack[depth]
                        if not (
                            s_bb[snode, 0] <= x1
                            and s_bb[snode, 1] <= y1
                            and s_bb[snode, 2] >= x0
                            and s_bb[snode, 3] >= y0
                        ):
                            continue
                        s_is_leaf = s_leaf[snode]
                        for k in range(s_cnt[snode]):
                            c = s_ch[snode, k]
                            if not s_is_leaf:  # at most 16 children a level wait
                                stack[depth] = c
                                depth += 1
                            elif (
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
            _remove(s_ch, s_cnt, s_leaf, s_hgt, s_bb, s_par, s_where, s_meta, s_box, node)
            for e in (node, new):
                _update_box(p, node_p, nxt, s_box, e)
                s_ch, s_cnt, s_leaf, s_hgt, s_bb, s_par = _grow_tree(
                    s_ch, s_cnt, s_leaf, s_hgt, s_bb, s_par, s_meta, s_hgt[s_meta[0]] + 2
                )
                _insert(
                    s_ch, s_cnt, s_leaf, s_hgt, s_bb, s_par, s_where, s_meta, s_box, e, path,
                    lbox, rbox,
                )  # fmt: skip

    ring = np.empty(nodes + 1, dtype=np.int64)
    node = last
    k = 0
    while True:
        ring[k] = node_p[node]
        k += 1
        node = nxt[node]
        if node == last:
            break
    ring[k] = node_p[node]
    return ring[: k + 1]
