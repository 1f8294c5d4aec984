"""rbush, the R-tree of mapbox's concaveman, in arrays: OMT bulk loading with its Floyd-Rivest
selection, insertion with its split heuristics, removal, and the node boxes, as the JavaScript
builds them (see :mod:`._concaveman` for why the tree must be the JavaScript's).

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

May import: nothing of dentopo but :mod:`dentopo._jit`.
"""

from __future__ import annotations

import math

import numpy as np

from ..._jit import njit
from ._jsmath import js_exp, js_log

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
    cnt2 = np.zeros(new, dtype=np.int64)
    leaf2 = np.ones(new, dtype=np.bool_)
    hgt2 = np.ones(new, dtype=np.int64)
    bb2 = np.empty((new, 4))
    par2 = np.full(new, -1, dtype=np.int64)
    # element by element: an array assignment compiles numba's shape-mismatch message
    # (more than a second on a fresh install)
    for i in range(cap):
        for j in range(_WIDTH):
            ch2[i, j] = ch[i, j]
        for j in range(4):
            bb2[i, j] = bb[i, j]
        cnt2[i] = cnt[i]
        leaf2[i] = leaf[i]
        hgt2[i] = hgt[i]
        par2[i] = par[i]
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
    _dist_bbox(ch, leaf, bb, ibox, node, np.int64(0), m, lbox)
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
    x_margin = _all_dist_margin(ch, cnt, leaf, bb, ibox, node, m, big_m, np.int64(0), lbox, rbox)
    y_margin = _all_dist_margin(ch, cnt, leaf, bb, ibox, node, m, big_m, np.int64(1), lbox, rbox)
    if x_margin < y_margin:
        _sort_children(ch, cnt, leaf, bb, ibox, node, np.int64(0))
    # chooseSplitIndex: least overlap, then least area
    min_overlap = _INF
    min_area = _INF
    index = m
    for i in range(m, big_m - m + 1):
        _dist_bbox(ch, leaf, bb, ibox, node, np.int64(0), i, lbox)
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
