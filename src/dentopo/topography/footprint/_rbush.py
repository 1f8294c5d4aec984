"""rbush, the R-tree of mapbox's concaveman, in arrays: OMT bulk loading with its Floyd-Rivest
selection, removal, and the node boxes, as the JavaScript builds them (see :mod:`._concaveman`
for why the tree must be the JavaScript's).

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

#: A node's room for children (rbush's insert holds one more than MAX_ENTRIES before a split;
#: the bulk load and removal never do).
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


@njit(cache=True, inline="always")
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


@njit(cache=True, inline="always")
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


@njit(cache=True, inline="always")
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


@njit(cache=True, inline="always")
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
