"""Watertight closure for the inside test: consistent orientation, holes capped.

The sign test asks whether a point lies inside the closed surface.  An open
mesh (a tooth crown cut at the cervix, a scan with holes) is closed first:

1. Faces are oriented consistently (a breadth-first walk over the face
   adjacency flips faces whose shared edge runs the same way as their
   neighbour's).  Meshes that are already consistent, the usual case, skip this.
2. Every connected set of boundary edges is capped by a fan of triangles around
   one new vertex at the mean of its boundary vertices.  The cap triangles run
   each boundary edge backwards, so the closed surface is consistently oriented.

Both steps are linear in the mesh size: the corners are listed by vertex
(a counting sort), and every edge is found among the few corners of its two
ends by compiled passes; the walk is compiled too.  About 0.1 s for 2M faces.
A vertex of more than ``FEW_CORNERS`` corners (a fan of a million faces on one
vertex, as some scanners leave) has its corners sorted, and its edges are
found by bisection: O(m log degree) instead of the square of its degree.
"""

from __future__ import annotations

import numpy as np

from .._jit import njit


def _directed_edges(faces: np.ndarray) -> np.ndarray:
    faces = np.asarray(faces)
    return np.stack([faces.T.ravel(), faces[:, [1, 2, 0]].T.ravel()], axis=1)


def _edge_keys(edges: np.ndarray, n: int) -> np.ndarray:
    return edges[:, 0].astype(np.int64) * n + edges[:, 1]


def _index_type(count: int):
    return np.int32 if count < 2**31 else np.int64


@njit(cache=True)
def _fill_corners(faces, start, corner, following):  # pragma: no cover
    """Corners ``3 f + c`` grouped by their vertex, ascending within each vertex.

    ``start`` holds ``n + 1`` zeros on entry and the groups' bounds on exit;
    ``corner`` (``3 m`` entries) gets the corners and ``following`` the vertex
    after each in its face (arrays from the caller: a returned array would be
    boxed with a little Python code, where a Ctrl-C that arrived meanwhile
    would be raised and crash the caller).
    """
    m = faces.shape[0]
    for f in range(m):
        for c in range(3):
            start[faces[f, c] + 1] += 1
    for v in range(1, start.shape[0]):
        start[v] += start[v - 1]
    fill = start[:-1].copy()
    for f in range(m):
        for c in range(3):
            v = faces[f, c]
            corner[fill[v]] = 3 * f + c
            following[fill[v]] = faces[f, (c + 1) % 3]
            fill[v] += 1


def corners_by_vertex(
    faces: np.ndarray, n_vertices: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The corners of every vertex: ``corner[start[v]:start[v + 1]]`` are those at vertex v.

    A corner is ``3 f + c`` (face f, its c-th index), listed in ascending order
    for each vertex, with the vertex that follows it in its face.  Linear time
    (a counting sort).

    Parameters
    ----------
    faces : (m, 3) int
        Indices in ``[0, n_vertices)``.
    n_vertices : int

    Returns
    -------
    start : (n_vertices + 1,) int64
    corner : (3 m,) int32 or int64
    following : (3 m,) int32 or int64
        ``faces[f, (c + 1) % 3]`` for each corner.
    """
    faces = np.ascontiguousarray(faces, dtype=np.int64)
    start = np.zeros(n_vertices + 1, dtype=np.int64)
    corner = np.empty(3 * len(faces), dtype=_index_type(3 * len(faces)))
    following = np.empty(3 * len(faces), dtype=_index_type(n_vertices))
    _fill_corners(faces, start, corner, following)
    return start, corner, following


#: A vertex with more corners than this has them sorted by the vertex that follows
#: (``sort_long_groups``), and an edge at it is looked for by bisection: a fan of a
#: million faces on one vertex (as some scanners leave) then costs O(m log degree),
#: where a scan of the vertex's corners for each of its edges would be quadratic.
FEW_CORNERS = 32


#: Runs this short are sorted by insertion before the merges.
_RUN = 16


@njit(cache=True)
def sort_ints(values):  # pragma: no cover
    """Sort `values` (1-D, integers) in place, ascending: ``values[:] = np.sort(values)``.

    A heap sort: O(n log n) whatever the order, in place, and little code.  Integers
    sort to one array whatever the method, so it need not be stable.  numba's own
    ``np.sort`` takes seconds to compile into each kernel that uses it, on every fresh
    install; this takes a tenth of a second (the merge sort of :func:`stable_order`,
    compiled for a second key type, took 0.4 s).
    """
    n = values.shape[0]
    for top in range(n // 2 - 1, -1, -1):
        _sift_down(values, top, n)
    for end in range(n - 1, 0, -1):
        x = values[0]
        values[0] = values[end]
        values[end] = x
        _sift_down(values, 0, end)


@njit(cache=True, inline="always")
def _sift_down(values, root, end):  # pragma: no cover
    """Restore the max-heap below `root` within ``values[:end]``."""
    x = values[root]
    while True:
        child = 2 * root + 1
        if child >= end:
            break
        if child + 1 < end and values[child + 1] > values[child]:
            child += 1
        if values[child] <= x:
            break
        values[root] = values[child]
        root = child
    values[root] = x


@njit(cache=True)
def stable_order(key, order):  # pragma: no cover
    """``order[:] = np.argsort(key, kind="stable")`` for a 1-D integer `key`; `order` int64.

    A stable merge sort of the indices (equal keys keep their order, so the
    result is the one ``kind="stable"`` gives) over insertion-sorted runs, for
    the reason given in :func:`sort_ints`.
    """
    n = key.shape[0]
    for k in range(n):
        order[k] = k
    for lo in range(0, n, _RUN):
        hi = min(lo + _RUN, n)
        for k in range(lo + 1, hi):
            x = order[k]
            j = k - 1
            while j >= lo and key[order[j]] > key[x]:
                order[j + 1] = order[j]
                j -= 1
            order[j + 1] = x
    if n <= _RUN:
        return
    src = order
    dst = np.empty_like(order)
    width = _RUN
    while width < n:
        for lo in range(0, n, 2 * width):
            mid = min(lo + width, n)
            hi = min(lo + 2 * width, n)
            i = lo
            j = mid
            for k in range(lo, hi):
                if j >= hi or (i < mid and key[src[i]] <= key[src[j]]):
                    dst[k] = src[i]
                    i += 1
                else:
                    dst[k] = src[j]
                    j += 1
        src, dst = dst, src
        width *= 2
    if src is not order:
        for k in range(n):
            order[k] = src[k]


@njit(cache=True)
def _sort_long_groups(start, following):  # pragma: no cover
    """Sort ``following`` within each vertex's group of more than ``FEW_CORNERS`` corners.

    In place; the groups of fewer corners stay in corner order.  Only for the
    callers that use ``following`` alone (``corner`` no longer lines up).
    """
    for v in range(start.shape[0] - 1):
        lo = start[v]
        hi = start[v + 1]
        if hi - lo > FEW_CORNERS:
            sort_ints(following[lo:hi])


@njit(cache=True, inline="always")
def _count_following(start, following, a, b):  # pragma: no cover
    """How many corners of vertex `a` are followed by `b` (``_sort_long_groups`` done)."""
    lo = start[a]
    hi = start[a + 1]
    if hi - lo <= FEW_CORNERS:
        same = 0
        for i in range(lo, hi):
            if following[i] == b:
                same += 1
        return same
    first = lo
    last = hi
    while first < last:  # the first entry >= b
        mid = (first + last) // 2
        if following[mid] < b:
            first = mid + 1
        else:
            last = mid
    stop = first
    last = hi
    while stop < last:  # the first entry > b
        mid = (stop + last) // 2
        if following[mid] <= b:
            stop = mid + 1
        else:
            last = mid
    return stop - first


def _sorted_corners(faces: np.ndarray, n_vertices: int) -> tuple[np.ndarray, np.ndarray]:
    """``start`` and ``following`` of :func:`corners_by_vertex`, long groups sorted."""
    start, _, following = corners_by_vertex(faces, n_vertices)
    if has_long_group(start):  # a crown has none: its kernel then never compiles
        _sort_long_groups(start, following)
    return start, following


def has_long_group(start: np.ndarray) -> bool:
    """Whether some vertex has more than ``FEW_CORNERS`` corners (`start`: the CSR offsets
    of :func:`corners_by_vertex`): only then do the sorted paths for long groups run, and
    compile."""
    return len(start) > 1 and int(np.diff(start).max()) > FEW_CORNERS


@njit(cache=True)
def _any_repeated(start, following):  # pragma: no cover
    """Whether some directed edge occurs twice: a later corner of a vertex with the same next.

    Long groups must be sorted (``_sort_long_groups``): their repeats are neighbours.
    """
    for a in range(start.shape[0] - 1):
        if start[a + 1] - start[a] > FEW_CORNERS:
            for i in range(start[a] + 1, start[a + 1]):
                if following[i] == following[i - 1]:
                    return True
            continue
        for i in range(start[a], start[a + 1]):
            for j in range(i + 1, start[a + 1]):
                if following[i] == following[j]:
                    return True
    return False


@njit(cache=True)
def _alone(faces, start, following, alone):  # pragma: no cover
    """Per directed edge (corner-major), whether no other edge of the faces joins its ends.

    The reverse edge is looked for first: on a surface nearly every edge has
    one, which ends the search early.  Long groups must be sorted
    (``_sort_long_groups``).
    """
    m = faces.shape[0]
    for f in range(m):
        for c in range(3):
            a = faces[f, c]
            b = faces[f, (c + 1) % 3]
            single = a == b or _count_following(start, following, b, a) == 0
            if single:
                single = _count_following(start, following, a, b) == 1
            alone[c * m + f] = single


@njit(cache=True)
def _count_uses(faces, start, following, uses, twice):  # pragma: no cover
    """Per directed edge (corner-major: ``c * m + f``), how many edges of the faces join its ends.

    ``uses`` gets the count of undirected edges between the two ends (either
    direction), ``twice[0]`` whether some directed edge occurs more than once.
    Long groups must be sorted (``_sort_long_groups``).
    """
    m = faces.shape[0]
    for f in range(m):  # face by face: the three edges' ends are near in memory
        for c in range(3):
            a = faces[f, c]
            b = faces[f, (c + 1) % 3]
            same = _count_following(start, following, a, b)
            if same > 1:
                twice[0] = True
            opposite = 0
            if a != b:
                opposite = _count_following(start, following, b, a)
            uses[c * m + f] = same + opposite


def edge_uses(faces: np.ndarray, n_vertices: int) -> tuple[np.ndarray, bool]:
    """How many face edges join the ends of each directed edge, and whether one repeats.

    Parameters
    ----------
    faces : (m, 3) int
    n_vertices : int

    Returns
    -------
    uses : (3 m,) int32
        For the directed edge ``(faces[f, c], faces[f, (c + 1) % 3])`` at
        ``c * m + f`` (the order of :func:`boundary_edges`): the number of
        edges of all faces with the same two ends, in either direction, itself
        included (1: a boundary edge; 2: an edge shared by two faces).
    repeated : bool
        Whether some directed edge occurs more than once (two faces that
        disagree on orientation, or more than two faces on one edge).
    """
    faces = np.ascontiguousarray(faces, dtype=np.int64)
    start, following = _sorted_corners(faces, n_vertices)
    uses = np.empty(3 * len(faces), dtype=np.int32)
    twice = np.zeros(1, dtype=np.bool_)
    _count_uses(faces, start, following, uses, twice)
    return uses, bool(twice[0])


@njit(cache=True)
def _propagate_flips(start, neighbour, same, flip):
    """Breadth-first walk over face adjacency; a face flips if it disagrees with its parent.

    ``neighbour[start[f]:start[f + 1]]`` are the faces sharing an edge with f,
    ``same`` whether that edge runs the same way in both (one must flip).  Each
    connected patch keeps the orientation of its lowest-numbered face.  The
    answer goes to ``flip`` (m falses, from the caller: a returned array would
    be boxed with a little Python code, where a Ctrl-C that arrived meanwhile
    would be raised and crash the caller).
    """
    m = flip.shape[0]
    visited = np.zeros(m, dtype=np.bool_)
    queue = np.empty(m, dtype=np.int64)
    for root in range(m):
        if visited[root]:
            continue
        visited[root] = True
        queue[0] = root
        head = 0
        tail = 1
        while head < tail:
            f = queue[head]
            head += 1
            for e in range(start[f], start[f + 1]):
                g = neighbour[e]
                if not visited[g]:
                    visited[g] = True
                    flip[g] = flip[f] ^ same[e]
                    queue[tail] = g
                    tail += 1


def orient_consistently(faces: np.ndarray, n_vertices: int) -> np.ndarray:
    """Return faces flipped where needed so that neighbours agree on orientation.

    Each connected patch keeps the orientation of its first face.  Edges shared
    by more than two faces are ignored (no consistent orientation exists there).
    """
    m = len(faces)
    start, following = _sorted_corners(faces, n_vertices)
    if not _any_repeated(start, following):
        return faces  # no directed edge used twice: already consistent
    del start, following
    directed = _directed_edges(faces)
    face_of = np.tile(np.arange(m), 3)
    undirected = np.sort(directed, axis=1)
    key = _edge_keys(undirected, n_vertices)
    order = np.argsort(key, kind="stable")
    sorted_key = key[order]
    starts = np.flatnonzero(np.r_[True, sorted_key[1:] != sorted_key[:-1]])
    sizes = np.diff(np.r_[starts, len(key)])
    pairs = starts[sizes == 2]
    a, b = order[pairs], order[pairs + 1]
    # same direction along the shared edge means one of the two faces is flipped
    same = directed[a, 0] == directed[b, 0]
    fa, fb = face_of[a], face_of[b]
    source = np.r_[fa, fb]
    by_face = np.argsort(source, kind="stable")
    start = np.searchsorted(source[by_face], np.arange(m + 1))
    flip = np.zeros(m, dtype=bool)
    _propagate_flips(start, np.r_[fb, fa][by_face], np.r_[same, same][by_face], flip)
    fixed = faces.copy()
    fixed[flip] = fixed[flip][:, ::-1]
    return fixed


def boundary_edges(faces: np.ndarray, n_vertices: int) -> np.ndarray:
    """Directed edges (as they run in their face) that no other face shares, shape (k, 2).

    In the order of the faces' first edges, then their second, then their third.
    """
    faces = np.asarray(faces)
    m = len(faces)
    if m == 0:
        return np.zeros((0, 2), dtype=faces.dtype)
    start, following = _sorted_corners(faces, n_vertices)
    alone = np.empty(3 * m, dtype=np.bool_)
    _alone(np.ascontiguousarray(faces, dtype=np.int64), start, following, alone)
    once = np.flatnonzero(alone)
    corner = once // m
    face = once - corner * m
    return np.column_stack([faces[face, corner], faces[face, (corner + 1) % 3]])


def _consistent_boundary(faces: np.ndarray, n_vertices: int) -> np.ndarray | None:
    """``boundary_edges(faces)`` of consistently oriented faces, or None if they are not.

    In linear time (``_reverse_missing``) instead of sorting the edges: the
    usual case of ``close_holes``.
    """
    faces = np.ascontiguousarray(faces, dtype=np.int64)
    if faces.ndim != 2 or faces.shape[1] != 3 or len(faces) == 0:
        return None
    if faces.min() < 0 or faces.max() >= n_vertices:
        return None  # the general path says what is wrong
    boundary = np.empty(3 * len(faces), dtype=np.bool_)
    # the edges' ends in the index type of corners_by_vertex's (int32 below 2**31 vertices):
    # one compilation of sort_ints serves both
    target = np.empty(3 * len(faces), dtype=_index_type(n_vertices))
    if not _reverse_missing(faces, n_vertices, boundary, target):
        return None
    corner, face = np.divmod(np.flatnonzero(boundary), len(faces))  # e = corner * m + face
    return np.stack([faces[face, corner], faces[face, (corner + 1) % 3]], axis=1)


@njit(cache=True, inline="always")
def first_at_least(values, lo, hi, value):  # pragma: no cover
    """``lo + np.searchsorted(values[lo:hi], value)``: the first index in ``lo:hi`` (sorted
    there) whose value is at least `value`, or `hi` (a binary search of our own: numba's
    ``searchsorted`` compiled in 0.95 s on a fresh install)."""
    while lo < hi:
        mid = (lo + hi) >> 1
        if values[mid] < value:
            lo = mid + 1
        else:
            hi = mid
    return lo


@njit(cache=True)
def _reverse_missing(faces, n, boundary, target):
    """``boundary[e]``: no face has the reverse of directed edge e (the order of
    ``_directed_edges``; an edge from a vertex to itself is its own reverse and
    counts as a boundary, as in ``boundary_edges``).

    Returns False, with `boundary` unfinished, if some directed edge occurs twice
    (faces not consistently oriented).  Each vertex's outgoing edges are sorted,
    so the cost is O(m log(degree)) whatever the degrees.
    """
    m = faces.shape[0]
    start = np.zeros(n + 1, np.int64)
    for f in range(m):
        for a in range(3):
            start[faces[f, a] + 1] += 1
    for v in range(n):
        start[v + 1] += start[v]
    fill = start[:-1].copy()
    for f in range(m):  # target (3 m,): each vertex's outgoing edges' ends, the caller's array
        for a in range(3):
            u = faces[f, a]
            target[fill[u]] = faces[f, (a + 1) % 3]
            fill[u] += 1
    for v in range(n):
        if start[v + 1] - start[v] > 32:
            sort_ints(target[start[v] : start[v + 1]])
        else:  # the usual few: insertion sort, no allocation
            for k in range(start[v] + 1, start[v + 1]):
                x = target[k]
                j = k - 1
                while j >= start[v] and target[j] > x:
                    target[j + 1] = target[j]
                    j -= 1
                target[j + 1] = x
        if start[v + 1] - start[v] > 1:
            for k in range(start[v] + 1, start[v + 1]):
                if target[k] == target[k - 1]:
                    return False
    for f in range(m):
        for a in range(3):
            u = faces[f, a]
            v = faces[f, (a + 1) % 3]
            lo = first_at_least(target, start[v], start[v + 1], u)  # v's first edge to >= u
            found = lo < start[v + 1] and target[lo] == u
            boundary[a * m + f] = u == v or not found
    return True


def smallest_connected(edges: np.ndarray, n_vertices: int) -> np.ndarray:
    """Each vertex's smallest connected vertex (itself if on no edge), through undirected `edges`.

    A label of the connected components in the order of their smallest vertex,
    the order of scipy's ``connected_components`` labels (which number the
    components as a search from vertex 0 up finds them); without scipy, whose
    sparse graphs take 0.25 s to import, for the few boundary edges of a crown.
    Shiloach and Vishkin's way, in numpy passes: each vertex points to the root
    of its tree (a connected vertex no larger than itself); each pass hooks
    every root onto the smallest root next to its tree, then points every
    vertex straight at its root, until no root has a smaller neighbour.
    """
    parent = np.arange(n_vertices)
    if len(edges) == 0:
        return parent
    ends = np.concatenate([edges[:, 0], edges[:, 1]]).astype(np.int64)
    across = np.concatenate([edges[:, 1], edges[:, 0]]).astype(np.int64)
    while True:
        root, other = parent[ends], parent[across]
        lower = other < root
        if not lower.any():
            return parent
        np.minimum.at(parent, root[lower], other[lower])  # hook roots onto smaller ones
        jumped = parent[parent]
        while not np.array_equal(jumped, parent):
            parent, jumped = jumped, jumped[jumped]


def close_holes(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A watertight, consistently oriented version of a mesh for the inside test.

    Parameters
    ----------
    vertices : (n, 3) float
    faces : (m, 3) int

    Returns
    -------
    vertices : (n + h, 3) float
        The input vertices followed by one centre vertex per hole.
    faces : (m + k, 3) int
        The consistently oriented faces followed by the cap triangles.
    """
    n = len(vertices)
    faces = np.asarray(faces)
    edges = _consistent_boundary(faces, n)
    if edges is None:  # not consistently oriented: the general path
        faces = orient_consistently(faces, n)
        edges = boundary_edges(faces, n)
    if len(edges) == 0:
        return vertices, faces
    label = smallest_connected(edges, n)  # ordered as scipy's connected_components labels
    hole = np.unique(label[edges[:, 0]], return_inverse=True)[1]
    n_holes = hole.max() + 1
    on_boundary = np.unique(edges.ravel())
    hole_of_vertex = np.unique(label[on_boundary], return_inverse=True)[1]
    centre = np.zeros((n_holes, 3))
    np.add.at(centre, hole_of_vertex, vertices[on_boundary])
    centre /= np.bincount(hole_of_vertex, minlength=n_holes)[:, None]
    cap = np.column_stack([edges[:, 1], edges[:, 0], n + hole])
    return np.vstack([vertices, centre]), np.vstack([faces, cap])


def outward_faces(points: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Faces oriented consistently, and outward: the capped surface has positive volume."""
    faces = orient_consistently(np.asarray(faces, dtype=np.int64), len(points))
    closed_vertices, closed_faces = close_holes(points, faces)
    tri = closed_vertices[closed_faces]
    volume = np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2])).sum() / 6.0
    return faces if volume >= 0 else faces[:, ::-1].copy()
