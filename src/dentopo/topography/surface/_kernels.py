"""Compiled per-face and per-edge passes shared by the topography metrics.

Each kernel is a single loop over faces or edges that replaces a chain of
numpy temporaries.  Every floating-point operation is the one the numpy code
it replaces performs, in the same order and precision (no fused multiply-add,
no reassociation), so the numbers are bit for bit those of the numpy
formulas written beside each kernel.  Transcendental functions (``arccos``,
``arctan2``) stay in numpy: a compiled library's result may differ in the
last bit, and a whole-degree slope or an aspect bin could then change.

Kernels write into arrays the caller allocates, where a returned array would
be boxed with a little Python code (see :mod:`dentopo.mesh._topology`).
"""

from __future__ import annotations

import math

import numpy as np

from ..._jit import njit
from ...mesh._faces import _sorted3, corner_cross, normalise_rows


def readonly(array: np.ndarray) -> np.ndarray:
    """A read-only view of `array` (no copy), for a kernel's input.

    numba compiles a kernel once for writable and once more for read-only
    arrays (a Surface's are read-only); passing every input read-only keeps
    it to one compilation on a fresh install.
    """
    view = array.view()
    view.flags.writeable = False
    return view


@njit(cache=True)
def face_cross_norm(vertices, faces, cross, norm):
    """``cross = (v2 - v1) x (v3 - v1)`` and ``norm = |cross|`` of every face.

    As ``face_cross`` and ``np.linalg.norm(cross, axis=1)`` compute them.
    """
    for f in range(faces.shape[0]):
        i, j, k = faces[f, 0], faces[f, 1], faces[f, 2]
        cx, cy, cz = corner_cross(vertices, i, j, k)
        cross[f, 0] = cx
        cross[f, 1] = cy
        cross[f, 2] = cz
        norm[f] = math.sqrt(cx * cx + cy * cy + cz * cz)


@njit(cache=True)
def unit_normals(vertices, faces, normals):
    """Unit face normals as ``Morpho::facenormals``: a zero normal stays zero.

    The numbers of ``cross / np.where(norm > 0, norm, 1.0)[:, None]`` with
    ``cross`` and ``norm`` of :func:`face_cross_norm`, without the temporaries.
    """
    for f in range(faces.shape[0]):
        i, j, k = faces[f, 0], faces[f, 1], faces[f, 2]
        cx, cy, cz = corner_cross(vertices, i, j, k)
        norm = math.sqrt(cx * cx + cy * cy + cz * cz)
        if not norm > 0.0:
            norm = 1.0
        normals[f, 0] = cx / norm
        normals[f, 1] = cy / norm
        normals[f, 2] = cz / norm


@njit(cache=True)
def horizontal_ratio(normals, ratio):
    """``sqrt(nx^2 + ny^2) / sqrt(nx^2 + ny^2 + nz^2)`` per row (NaN for a zero normal).

    The numbers of the numpy expression in ``slope._doolkit._horizontal_ratio``.
    """
    for f in range(normals.shape[0]):
        nx, ny, nz = normals[f, 0], normals[f, 1], normals[f, 2]
        horizontal = nx * nx + ny * ny
        length = math.sqrt(horizontal + nz * nz)
        # 0 / 0 is numpy's NaN (numba would raise)
        ratio[f] = math.nan if length == 0.0 else math.sqrt(horizontal) / length


@njit(cache=True)
def single_precision_areas(vertices32, faces, area):
    """Face areas in single precision, as molaR's reader computes them.

    ``tri = vertices32[faces]``; the float32 cross product of
    ``tri[:, 1] - tri[:, 0]`` and ``tri[:, 2] - tri[:, 0]`` (as ``np.cross``),
    the float32 sum of its squares, its float32 square root, then
    ``float64(root) / 2``.
    """
    for f in range(faces.shape[0]):
        i, j, k = faces[f, 0], faces[f, 1], faces[f, 2]
        cx, cy, cz = corner_cross(vertices32, i, j, k)
        root = np.sqrt(cx * cx + cy * cy + cz * cz)
        area[f] = np.float64(root) / 2.0


@njit(cache=True)
def _edge_buckets(faces, start, other, edge):
    """The 3m directed edges bucketed by their lower vertex.

    Edge ``e = k * m + f`` runs from ``faces[f, k]`` to ``faces[f, (k + 1) % 3]``
    (the layout of :func:`dentopo.mesh.boundary_edges`).  Bucket ``v`` is
    ``start[v]:start[v + 1]`` of ``other`` (the higher vertex) and ``edge``;
    `start` (n + 1 slots) comes zeroed.
    """
    m = faces.shape[0]
    n_vertices = start.shape[0] - 1
    for k in range(3):
        for f in range(m):
            a, b = faces[f, k], faces[f, (k + 1) % 3]
            start[min(a, b) + 1] += 1
    for v in range(n_vertices):
        start[v + 1] += start[v]
    fill = start[:-1].copy()
    for k in range(3):
        for f in range(m):
            a, b = faces[f, k], faces[f, (k + 1) % 3]
            low = min(a, b)
            p = fill[low]
            other[p] = max(a, b)
            edge[p] = k * m + f
            fill[low] = p + 1


@njit(cache=True)
def edge_groups(faces, n_vertices, group_start, group_edge):
    """The 3m directed edges grouped by their two vertices: one group per undirected edge.

    Edge ``e = k * m + f`` runs from ``faces[f, k]`` to ``faces[f, (k + 1) % 3]``.
    Writes the edges of each group into ``group_edge`` (3m slots) and the
    group boundaries into ``group_start`` (3m + 1 slots); returns the number
    of groups.  A boundary edge is a group of one.
    """
    start = np.zeros(n_vertices + 1, dtype=np.int64)
    other = np.empty(3 * faces.shape[0], dtype=np.int64)
    edge = np.empty(3 * faces.shape[0], dtype=np.int64)
    _edge_buckets(faces, start, other, edge)
    stamp = np.full(n_vertices, -1, dtype=np.int64)
    place = np.empty(n_vertices, dtype=np.int64)
    groups = 0
    group_start[0] = 0
    for v in range(n_vertices):
        lo, hi = start[v], start[v + 1]
        # count the edges to each other vertex, in the order the others first appear
        for p in range(lo, hi):
            o = other[p]
            if stamp[o] != v:
                stamp[o] = v
                place[o] = 0
            place[o] += 1
        end = lo
        for p in range(lo, hi):
            o = other[p]
            if stamp[o] == v:
                stamp[o] = -2 - v  # placed
                size = place[o]
                place[o] = end
                end += size
                groups += 1
                group_start[groups] = end
        for p in range(lo, hi):
            o = other[p]
            group_edge[place[o]] = edge[p]
            place[o] += 1
    return groups


@njit(cache=True)
def border_vertex_flags(faces, flags):
    """Flag the two ends of every edge only one face uses (a border edge) in `flags`.

    The vertices :func:`boundary_ends` gives, without grouping the edges: the
    3m directed edges bucketed by their lower vertex (:func:`_edge_buckets`),
    then in each bucket every higher vertex seen once is a border edge's.
    `flags` (n slots) comes all False.
    """
    n = flags.shape[0]
    start = np.zeros(n + 1, dtype=np.int64)
    other = np.empty(3 * faces.shape[0], dtype=np.int64)
    _edge_buckets(faces, start, other, np.empty(3 * faces.shape[0], dtype=np.int64))
    count = np.empty(n, dtype=np.int64)  # of each higher vertex in the current bucket
    stamp = np.full(n, -1, dtype=np.int64)
    for v in range(n):
        lo, hi = start[v], start[v + 1]
        for p in range(lo, hi):
            o = other[p]
            if stamp[o] != v:
                stamp[o] = v
                count[o] = 0
            count[o] += 1
        for p in range(lo, hi):
            o = other[p]
            if count[o] == 1:
                flags[v] = True
                flags[o] = True


@njit(cache=True)
def boundary_ends(faces, group_start, group_edge, groups, ends):
    """The directed edges used by one face, in the order of ``e``, into `ends`; returns how many."""
    m = faces.shape[0]
    alone = np.zeros(3 * m, dtype=np.bool_)
    for g in range(groups):
        if group_start[g + 1] - group_start[g] == 1:
            alone[group_edge[group_start[g]]] = True
    count = 0
    for e in range(3 * m):
        if alone[e]:
            k, f = e // m, e % m
            ends[count, 0] = faces[f, k]
            ends[count, 1] = faces[f, (k + 1) % 3]
            count += 1
    return count


@njit(cache=True, inline="always")  # compiled on its own: twice (a literal -1 at a call)
def _find(parent, x):
    root = x
    while parent[root] != root:
        root = parent[root]
    while parent[x] != root:
        parent[x], x = root, parent[x]
    return root


@njit(cache=True)
def patch_labels(group_start, group_edge, groups, face_bin, bins, face_patch):
    """molaR's patches: faces of one bin joined across an edge two faces of that bin use.

    The groups are :func:`edge_groups`'s.  Writes each face's patch label
    into ``face_patch``, patches numbered in the order of their first face;
    returns the number of patches.
    """
    m = face_bin.shape[0]
    parent = np.arange(m)
    count = np.zeros(bins + 1, dtype=np.int64)
    for g in range(groups):
        lo, hi = group_start[g], group_start[g + 1]
        if hi - lo < 2:
            continue
        if hi - lo == 2:
            a, b = group_edge[lo] % m, group_edge[lo + 1] % m
            if face_bin[a] == face_bin[b]:
                ra, rb = _find(parent, a), _find(parent, b)
                if ra != rb:
                    parent[max(ra, rb)] = min(ra, rb)
            continue
        count[:] = 0
        for p in range(lo, hi):
            count[face_bin[group_edge[p] % m]] += 1
        for bin_ in range(bins + 1):
            if count[bin_] != 2:
                continue
            a = -1
            for p in range(lo, hi):
                f = group_edge[p] % m
                if face_bin[f] != bin_:
                    continue
                if a < 0:
                    a = f
                else:
                    ra, rb = _find(parent, a), _find(parent, f)
                    if ra != rb:
                        parent[max(ra, rb)] = min(ra, rb)
    label = np.full(m, -1, dtype=np.int64)
    patches = 0
    for f in range(m):
        root = _find(parent, f)
        if label[root] < 0:
            label[root] = patches
            patches += 1
        face_patch[f] = label[root]
    return patches


@njit(cache=True)
def unit_vertex_sums(vertices, faces, unit_faces, out):
    """Sum each face's normal into its three vertices, then normalise the sums.

    With ``unit_faces`` each face's cross product is normalised first (a zero
    one stays zero): molaR's energy normals; without, the area-weighted
    normals of its reader.  As ``np.add.at`` over ``faces[:, 0]``, then
    ``faces[:, 1]``, then ``faces[:, 2]`` and a guarded division by the norm.
    """
    m = faces.shape[0]
    normal = np.empty((m, 3))
    for f in range(m):
        i, j, k = faces[f, 0], faces[f, 1], faces[f, 2]
        cx, cy, cz = corner_cross(vertices, i, j, k)
        if unit_faces:
            length = math.sqrt(cx * cx + cy * cy + cz * cz)
            if length > 0:
                cx, cy, cz = cx / length, cy / length, cz / length
            else:
                cx, cy, cz = 0.0, 0.0, 0.0
        normal[f, 0] = cx
        normal[f, 1] = cy
        normal[f, 2] = cz
    out[:] = 0.0
    for c in range(3):
        for f in range(m):
            v = faces[f, c]
            out[v, 0] += normal[f, 0]
            out[v, 1] += normal[f, 1]
            out[v, 2] += normal[f, 2]
    normalise_rows(out)


@njit(cache=True)
def energy_density(vertices, faces, normals, rcond_min, energy, area):
    """Per-face ``trace(G^-1 H)`` (zero where ``G`` is ill conditioned) and ``sqrt(det G) / 2``."""
    for f in range(faces.shape[0]):
        i, j, k = faces[f, 0], faces[f, 1], faces[f, 2]
        ax = vertices[j, 0] - vertices[i, 0]
        ay = vertices[j, 1] - vertices[i, 1]
        az = vertices[j, 2] - vertices[i, 2]
        bx = vertices[k, 0] - vertices[i, 0]
        by = vertices[k, 1] - vertices[i, 1]
        bz = vertices[k, 2] - vertices[i, 2]
        cx = normals[j, 0] - normals[i, 0]
        cy = normals[j, 1] - normals[i, 1]
        cz = normals[j, 2] - normals[i, 2]
        dx = normals[k, 0] - normals[i, 0]
        dy = normals[k, 1] - normals[i, 1]
        dz = normals[k, 2] - normals[i, 2]
        gaa = ax * ax + ay * ay + az * az
        gab = ax * bx + ay * by + az * bz
        gbb = bx * bx + by * by + bz * bz
        hcc = cx * cx + cy * cy + cz * cz
        hcd = cx * dx + cy * dy + cz * dz
        hdd = dx * dx + dy * dy + dz * dz
        det = gaa * gbb - gab * gab
        norm1 = max(abs(gaa) + abs(gab), abs(gab) + abs(gbb))
        rcond = abs(det) / (norm1 * norm1) if norm1 > 0 else 0.0
        if rcond >= rcond_min:
            energy[f] = (gbb * hcc - 2.0 * gab * hcd + gaa * hdd) / det
        else:
            energy[f] = 0.0
        area[f] = 0.5 * math.sqrt(max(det, 0.0))


@njit(cache=True, inline="always")
def _k(vertices, normals, j, i):
    dx = vertices[j, 0] - vertices[i, 0]
    dy = vertices[j, 1] - vertices[i, 1]
    dz = vertices[j, 2] - vertices[i, 2]
    length2 = dx * dx + dy * dy + dz * dz
    dot = (normals[j, 0] - normals[i, 0]) * dx
    dot = dot + (normals[j, 1] - normals[i, 1]) * dy
    dot = dot + (normals[j, 2] - normals[i, 2]) * dz
    return dot / length2 if length2 > 0 else 0.0


@njit(cache=True)
def kappa(vertices, faces, normals, out):
    """molaR's per-face curvature value ``(k(2,1) + k(3,1) + k(1,2)) / 3``."""
    for f in range(faces.shape[0]):
        a, b, c = faces[f, 0], faces[f, 1], faces[f, 2]
        total = _k(vertices, normals, b, a) + _k(vertices, normals, c, a)
        out[f] = (total + _k(vertices, normals, a, b)) / 3.0


@njit(cache=True)
def circumcentres(points, simplices, ux, uy):
    """Each triangle's circumcentre relative to its first vertex (the radius is its hypot).

    ``b, c`` are the other two vertices minus the first; ``d = 2 (b x c)``;
    ``ux = (c_y |b|^2 - b_y |c|^2) / d``, ``uy = (b_x |c|^2 - c_x |b|^2) / d``;
    infinite for a flat triangle (``d = 0``, which qhull can return on collinear points).
    """
    for t in range(simplices.shape[0]):
        p, q, r = simplices[t, 0], simplices[t, 1], simplices[t, 2]
        bx = points[q, 0] - points[p, 0]
        by = points[q, 1] - points[p, 1]
        cx = points[r, 0] - points[p, 0]
        cy = points[r, 1] - points[p, 1]
        d = 2.0 * (bx * cy - by * cx)
        if d == 0.0:
            ux[t] = np.inf
            uy[t] = np.inf
            continue
        bb = bx * bx + by * by
        cc = cx * cx + cy * cy
        ux[t] = (cy * bb - by * cc) / d
        uy[t] = (bx * cc - cx * bb) / d


@njit(cache=True)
def face_mean_z(vertices, faces, out):
    """Each face's mean height ``(z1 + z2 + z3) / 3``, as ``vertices[faces, 2].mean(axis=1)``."""
    for f in range(faces.shape[0]):
        out[f] = (
            vertices[faces[f, 0], 2] + vertices[faces[f, 1], 2] + vertices[faces[f, 2], 2]
        ) / 3.0


@njit(cache=True)
def compensated_dot(values, weights):
    """``sum(values * weights)`` in twice the working precision (Ogita, Rump and Oishi's Dot2).

    Sequential, so the same at any thread count (a BLAS dot product splits
    long sums between threads); the error-free product and sum terms make it
    as accurate as if computed in quadruple precision and rounded once, which
    is how R's long-double ``sum`` comes to the same double.
    """
    total = 0.0
    error = 0.0
    split = 134217729.0  # 2**27 + 1: Dekker's split of a double into two halves
    for i in range(values.shape[0]):
        x = float(values[i])
        y = weights[i]
        product = x * y
        t = split * x
        x_high = t - (t - x)
        x_low = x - x_high
        t = split * y
        y_high = t - (t - y)
        y_low = y - y_high
        product_error = x_low * y_low - (
            ((product - x_high * y_high) - x_low * y_high) - x_high * y_low
        )
        t = total + product
        z = t - total
        sum_error = (total - (t - z)) + (product - z)
        total = t
        error += sum_error + product_error
    return total + error


@njit(cache=True)
def packed_triples(faces, n, out):  # pragma: no cover
    """Each face's three vertex indices sorted and packed into one integer, ``(a n + b) n + c``.

    Equal keys are equal vertex sets (in any order); `n` is above every index
    and small enough (below 2**21) that the key fits in an int64.
    """
    for f in range(faces.shape[0]):
        a, b, c = _sorted3(faces[f, 0], faces[f, 1], faces[f, 2])
        out[f] = (a * n + b) * n + c


@njit(cache=True)
def agreeing_winding(faces, group_start, group_edge, groups):  # pragma: no cover
    """Whether no directed edge is run twice (see :meth:`Surface.consistent`).

    Directed edge ``e = k * m + f`` runs from ``faces[f, k]`` to
    ``faces[f, (k + 1) % 3]``; in each group of edges on one pair of vertices,
    at most one may run from the lower index to the higher and at most one back.
    """
    m = faces.shape[0]
    for g in range(groups):
        up = 0
        down = 0
        for s in range(group_start[g], group_start[g + 1]):
            e = group_edge[s]
            f, k = e % m, e // m
            if faces[f, k] < faces[f, (k + 1) % 3]:
                up += 1
            else:
                down += 1
        if up > 1 or down > 1:
            return False
    return True


@njit(cache=True)
def closed_volume(points, faces, cross, boundary):  # pragma: no cover
    """Six times the signed volume of the faces closed by a fan over each boundary loop.

    `points` are the vertices about their mean, `cross` the faces'
    ``(v2 - v1) x (v3 - v1)`` from them; each connected set of `boundary`
    edges (a loop) is closed by the triangles ``(b, a, centre)`` of its edges
    ``a -> b``, ``centre`` the mean of the loop's vertices.  Linear in the
    faces and edges (a union-find over the boundary's vertices).
    """
    volume = 0.0
    for f in range(faces.shape[0]):
        i = faces[f, 0]
        volume += points[i, 0] * cross[f, 0] + points[i, 1] * cross[f, 1]
        volume += points[i, 2] * cross[f, 2]
    k = boundary.shape[0]
    if k == 0:
        return volume
    n = points.shape[0]
    parent = np.arange(n)
    for e in range(k):
        a, b = _find(parent, boundary[e, 0]), _find(parent, boundary[e, 1])
        if a != b:
            parent[a] = b
    seen = np.zeros(n, dtype=np.bool_)
    centre = np.zeros((n, 3))
    count = np.zeros(n, dtype=np.int64)
    for e in range(k):
        for j in range(2):
            v = boundary[e, j]
            if not seen[v]:
                seen[v] = True
                r = _find(parent, v)
                count[r] += 1
                for d in range(3):
                    centre[r, d] += points[v, d]
    for e in range(k):
        a, b = boundary[e, 0], boundary[e, 1]
        r = _find(parent, a)
        cx = centre[r, 0] / count[r]
        cy = centre[r, 1] / count[r]
        cz = centre[r, 2] / count[r]
        ax, ay, az = points[a, 0], points[a, 1], points[a, 2]
        # b . (a x c)
        volume += points[b, 0] * (ay * cz - az * cy)
        volume += points[b, 1] * (az * cx - ax * cz)
        volume += points[b, 2] * (ax * cy - ay * cx)
    return volume
