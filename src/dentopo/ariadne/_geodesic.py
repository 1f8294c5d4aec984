"""Geodesic kernel sums: compiled shortest-path searches, bounded by the kernel's radius.

For every vertex ``s`` the sums need the shortest-path distance ``d`` along
mesh edges to each vertex ``j`` within the kernel's radius: its weight
``exp(-d**2 / h**2)`` (libm's ``exp``, as ``np.exp``) and its moments
relative to the source, ``w (x_j - x_s)`` and ``w (x_j - x_s)(x_j -
x_s)^T``.  The sources are searched in groups of ``LANES`` consecutive
vertices (a spatial order keeps them close together): one search over the
edge graph (CSR, edge lengths as weights) carries the group's distances side
by side, so that the walk through the graph and the queue are shared by the
group, and only the vertices within the radius of one of them are touched.
The memory is linear in the number of vertices (a few arrays of ``n`` and two
of ``n * LANES`` per thread); no distance outlives its group.

The distances are those of ``scipy.sparse.csgraph.dijkstra(graph,
limit=radius)`` bit for bit.  Floating-point addition is monotone, so a
search that stops only where no edge can shorten any distance (Dijkstra, or
the label-correcting search of ``_search``, whatever order it takes the
vertices in) ends, for every vertex, at the least over all paths of the
path's edge lengths added up from the source; and the radius bounds the
paths as scipy's ``limit`` does (a vertex at exactly the radius is in).
The sums are added in the order the group's search first reached the
vertices, which depends on the group alone: the result depends neither on
the number of threads nor on how the caller slices the groups.

Kernels write into arrays of the caller and return nothing (see
``dentopo.ariadne._kernel._run_sums``: a returned array is boxed by a little
Python code, where a Ctrl-C that arrived during the loop would crash the
caller), and :func:`geodesic_sums` calls them in slices of about
``SECONDS_PER_CALL``, so that Python reacts to Ctrl-C between them.

May import: nothing of dentopo but ``.._jit`` (``_kernel`` imports this module).
"""

from __future__ import annotations

import math
import time

import numba
import numpy as np

from .._jit import njit, prange

#: Wall seconds one call of the compiled kernel should take: Python reacts to Ctrl-C
#: between calls, not during one.
SECONDS_PER_CALL = 0.15

#: Sources searched together (the lanes of one search; see ``_search``).
LANES = 16

#: Width of the search's buckets in mean edge lengths (see ``buckets``) ...
BUCKET_EDGES = 2.0
#: ... and the most buckets its ring holds.
MAX_BUCKETS = 4096

#: Groups of sources per thread in the first call, before the time per group is known.
FIRST_GROUPS_PER_THREAD = 2


@njit(cache=True)
def _enqueue(v, b, bucket, head, nxt, prv):
    """Put vertex `v` into bucket `b` (taking it out of the one it was in, if any)."""
    old = bucket[v]
    if old >= 0:
        p = prv[v]
        q = nxt[v]
        if p >= 0:
            nxt[p] = q
        else:
            head[old] = q
        if q >= 0:
            prv[q] = p
    q = head[b]
    nxt[v] = q
    prv[v] = -1
    if q >= 0:
        prv[q] = v
    head[b] = v
    bucket[v] = b


@njit(cache=True)
def _search(
    first,
    lanes,
    indptr,
    indices,
    lengths,
    radius,
    inv_step,
    dist,
    bucket,
    head,
    nxt,
    prv,
    visited,
    seen,
):
    """Distances from sources ``first`` to ``first + lanes - 1``, up to `radius`, into `dist`.

    ``dist[v, c]`` becomes the distance of ``v`` from source ``first + c``
    (inf beyond the radius).  One search for the `lanes` sources together: a
    vertex is expanded for all of them at once, each of its edges relaxing
    the lanes side by side.  The queue holds each vertex once, in bucket
    ``int(d * inv_step)`` of the least distance ``d`` improved since it was
    last expanded (never behind the bucket being emptied, nor beyond the
    ring's reach ahead of it): doubly linked lists in a ring of buckets
    (``head``, ``nxt``, ``prv``; ``bucket[v]`` is ``v``'s slot in the ring,
    -1 when ``v`` is not queued), emptied in order, each until no vertex is
    left in it, until no vertex is queued.  A vertex
    is expanded again whenever one of its lanes improved: a label-correcting
    search, which ends where no edge can shorten any lane's distance, and so
    at each lane's least over all paths, exactly as Dijkstra (see the module
    docstring).  Nearby sources sweep the mesh at about the same pace, so a
    vertex is expanded less than twice on average for all of them.

    The vertices reached go to ``seen[:count]``, in the order they were first
    reached (and are marked in `visited`); returns the count.  On entry
    `dist` must be inf, `visited` 0, `bucket` and `head` -1 everywhere;
    `bucket` and `head` are so again on return.
    """
    n_seen = 0
    for c in range(lanes):
        s = first + c
        dist[s, c] = 0.0
        visited[s] = 1
        seen[n_seen] = s
        n_seen += 1
        _enqueue(s, 0, bucket, head, nxt, prv)
    queued = lanes
    ring = head.shape[0]
    last = ring - 1.0
    k = 0  # the bucket being emptied, in slot k % ring
    while queued > 0:
        slot = k % ring
        while head[slot] >= 0:
            u = head[slot]
            q = nxt[u]
            head[slot] = q
            if q >= 0:
                prv[q] = -1
            bucket[u] = -1
            queued -= 1
            for e in range(indptr[u], indptr[u + 1]):
                v = indices[e]
                length = lengths[e]
                best = np.inf
                for c in range(LANES):
                    nd = dist[u, c] + length
                    old = dist[v, c]
                    better = (nd < old) & (nd <= radius)
                    dist[v, c] = nd if better else old
                    best = min(best, nd if better else np.inf)
                if best < np.inf:
                    if visited[v] == 0:
                        visited[v] = 1
                        seen[n_seen] = v
                        n_seen += 1
                    # bucket k at the earliest, k + ring - 1 at the latest (the ring's reach)
                    t = best * inv_step - k
                    b = k + (np.int64(t) if t < last else ring - 1) if t > 0 else k
                    if bucket[v] < 0:
                        queued += 1
                        _enqueue(v, b % ring, bucket, head, nxt, prv)
                    elif b < k + (bucket[v] - slot) % ring:
                        _enqueue(v, b % ring, bucket, head, nxt, prv)
        k += 1
    return n_seen


@njit(cache=True, parallel=True)
def _geodesic_sums(
    first_group,
    stop_group,
    threads,
    indptr,
    indices,
    lengths,
    xs,
    ys,
    zs,
    h2,
    cutoff,
    radius,
    inv_step,
    ring,
    sums,
    count,
):
    """Sums of the sources of groups `first_group` to ``stop_group - 1`` into `sums` and `count`.

    Group ``g`` is the sources ``g * LANES`` to ``g * LANES + LANES - 1`` (the
    last one may be shorter), searched together by ``_search``; then each
    source's terms are added in the order its group's search first reached
    the vertices, relative to the source: ``sums[s]`` (10 sums) and
    ``count[s]``.  Thread ``k`` of `threads` takes the groups ``first_group +
    k``, ``first_group + k + threads``, ... (neighbouring groups, in a spatial
    order, have about the same work), with scratch arrays of its own: a
    source's sums depend on its group alone.  Writes into arrays of the
    caller and returns nothing (see the module docstring).
    """
    n = xs.shape[0]
    for k in prange(threads):
        dist = np.full((n, LANES), np.inf)
        bucket = np.full(n, -1, np.int64)
        head = np.full(ring, -1, np.int64)
        nxt = np.empty(n, np.int64)
        prv = np.empty(n, np.int64)
        visited = np.zeros(n, np.uint8)
        seen = np.empty(n, np.int64)
        near = np.empty((LANES, n))
        px = np.empty(n)
        py = np.empty(n)
        pz = np.empty(n)
        for g in range(first_group + k, stop_group, threads):
            first = g * LANES
            lanes = min(LANES, n - first)
            reached = _search(
                first,
                lanes,
                indptr,
                indices,
                lengths,
                radius,
                inv_step,
                dist,
                bucket,
                head,
                nxt,
                prv,
                visited,
                seen,
            )
            # the reached vertices' distances, lane by lane, and positions, compacted in the
            # order they were reached (the lanes' loops below then read memory in order), and
            # the scratch arrays made ready for the next group
            for m in range(reached):
                j = seen[m]
                for c in range(LANES):
                    near[c, m] = dist[j, c]
                    dist[j, c] = np.inf
                visited[j] = 0
                px[m] = xs[j]
                py[m] = ys[j]
                pz[m] = zs[j]
            for c in range(lanes):
                s = first + c
                x0 = xs[s]
                y0 = ys[s]
                z0 = zs[s]
                s0 = s1x = s1y = s1z = 0.0
                sxx = sxy = sxz = syy = syz = szz = 0.0
                kept = 0
                lane = near[c]
                for m in range(reached):
                    d = lane[m]
                    if d <= radius:
                        w = math.exp(-(d * d) / h2)  # libm's exp, as np.exp
                        if w > cutoff:
                            dx = px[m] - x0
                            dy = py[m] - y0
                            dz = pz[m] - z0
                            wx = w * dx
                            wy = w * dy
                            wz = w * dz
                            s0 += w
                            s1x += wx
                            s1y += wy
                            s1z += wz
                            sxx += wx * dx
                            sxy += wx * dy
                            sxz += wx * dz
                            syy += wy * dy
                            syz += wy * dz
                            szz += wz * dz
                            kept += 1
                sums[s, 0] = s0
                sums[s, 1] = s1x
                sums[s, 2] = s1y
                sums[s, 3] = s1z
                sums[s, 4] = sxx
                sums[s, 5] = sxy
                sums[s, 6] = sxz
                sums[s, 7] = syy
                sums[s, 8] = syz
                sums[s, 9] = szz
                count[s] = kept


def buckets(lengths: np.ndarray, radius: float) -> tuple[float, int]:
    """``1 / width`` of the search's buckets and the number of them in its ring.

    A bucket is ``BUCKET_EDGES`` mean edges wide: wider ones expand more
    vertices again (they are taken out in no particular order within a
    bucket), narrower ones cost the scan of more of them.  The ring holds the
    buckets an edge can reach ahead of the one being emptied (the longest edge
    within the radius), ``MAX_BUCKETS`` at most: a vertex further ahead waits
    in the ring's last bucket.  Neither changes the distances, only the work.
    """
    mean = float(lengths.mean()) if len(lengths) else 0.0
    width = BUCKET_EDGES * mean if mean > 0 else 1.0
    longest = min(float(lengths.max()) if len(lengths) else 0.0, radius)
    return 1.0 / width, int(min(MAX_BUCKETS, np.floor(longest / width) + 2))


def geodesic_sums(
    indptr: np.ndarray,
    indices: np.ndarray,
    lengths: np.ndarray,
    points: np.ndarray,
    bandwidth: float,
    cutoff: float,
    radius: float,
) -> tuple[np.ndarray, np.ndarray]:
    """Geodesic kernel sums of every vertex: ``sums`` (n, 10) and ``count`` (n,).

    The graph is the CSR arrays of a symmetric edge graph (``indptr``,
    ``indices``, ``lengths``) over `points`, which should be in a spatial
    order: groups of ``LANES`` consecutive vertices are searched together,
    and the closer they are, the less the search does.  A neighbour ``j`` of
    ``s`` is a vertex at a shortest-path distance ``d <= radius`` whose weight
    ``exp(-d**2 / bandwidth**2)`` is above `cutoff`.  Sums as in
    ``dentopo.ariadne._kernel``: the weight, the first moment (x, y, z) and
    the second (xx, xy, xz, yy, yz, zz), relative to ``s``.  The groups go
    to the compiled kernel in slices of about ``SECONDS_PER_CALL`` (timed as
    they go), so that Python reacts to Ctrl-C between them; the slices do not
    change the sums.
    """
    points = np.ascontiguousarray(points, dtype=np.float64)
    n = len(points)
    xs, ys, zs = (np.ascontiguousarray(points[:, k]) for k in range(3))
    indptr = np.ascontiguousarray(indptr, dtype=np.int64)
    indices = np.ascontiguousarray(indices, dtype=np.int64)
    lengths = np.ascontiguousarray(lengths, dtype=np.float64)
    sums = np.zeros((n, 10))
    count = np.zeros(n, np.int64)
    h2 = float(bandwidth) ** 2
    inv_step, ring = buckets(lengths, radius)
    groups = -(-n // LANES)
    threads = numba.get_num_threads()
    per_call = FIRST_GROUPS_PER_THREAD * threads
    first = 0
    while first < groups:
        stop = min(groups, first + per_call)
        started = time.perf_counter()
        _geodesic_sums(
            first,
            stop,
            min(threads, stop - first),
            indptr,
            indices,
            lengths,
            xs,
            ys,
            zs,
            h2,
            float(cutoff),
            radius,
            inv_step,
            ring,
            sums,
            count,
        )
        seconds = time.perf_counter() - started
        # the next slice: about SECONDS_PER_CALL at this slice's pace, at most twice as long
        pace = SECONDS_PER_CALL / max(seconds, 1e-6)
        per_call = max(threads, min(2 * per_call, int(per_call * pace)))
        first = stop
    return sums, count
