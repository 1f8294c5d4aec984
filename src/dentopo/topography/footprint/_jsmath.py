"""V8's arithmetic for the concaveman port: fdlibm's ``Math.log`` and ``Math.exp``, exact
orientation (robust-orientation), the point-in-quadrilateral test and the monotone convex hull,
in the JavaScript's order of operations (see :mod:`._concaveman` for why every last bit matters).

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

from ..._jit import njit

_INF = math.inf

# --------------------------------------------------------------------------------------------
# fdlibm's log and exp (V8's Math.log and Math.exp), for positive finite normal arguments


_TWO52 = 4503599627370496.0  # 2**52


@njit(cache=True, inline="always")
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


@njit(cache=True, inline="always")
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


@njit(cache=True, inline="always")
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


@njit(cache=True, inline="always")
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


@njit(cache=True, inline="always")
def _exact_orient_sign(ax, ay, bx, by, cx, cy):
    """Sign of ``(ay - cy)(bx - cx) - (ax - cx)(by - cy)`` in exact arithmetic."""
    # = ay bx - ay cx - cy bx - ax by + ax cy + cx by
    e = np.empty(16)
    n = np.int64(0)  # not a literal 0: one compilation of _grow, not two
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


@njit(cache=True, inline="always")
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


@njit(cache=True, inline="always")
def _before(fx, fy, i, j):
    """(x, y, index) of i before that of j."""
    if fx[i] != fx[j]:
        return fx[i] < fx[j]
    if fy[i] != fy[j]:
        return fy[i] < fy[j]
    return i < j


@njit(cache=True, inline="always")
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
    for i in range(hull.shape[0]):  # not out[:k] = hull: see _concaveman._list_edge
        out[i] = hull[i]
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
    for j in range(nl):  # not hull[:nl] = ...: see _concaveman._list_edge
        hull[j] = lower[j]
    k = nl
    for j in range(nu - 2, 0, -1):
        hull[k] = upper[j]
        k += 1
    return hull
