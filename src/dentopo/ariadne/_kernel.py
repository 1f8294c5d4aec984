"""Gaussian-kernel weighted moments: the only neighbourhood sums ariaDNE needs.

For every vertex i and weights ``w_ij = exp(-d_ij**2 / h**2)`` (kept where
``w_ij > cutoff``) this module computes

* ``weight``      ``S0_i = sum_j w_ij``
* ``first``       ``sum_j w_ij (x_j - x_i)``                (n, 3)
* ``second``      ``sum_j w_ij (x_j - x_i)(x_j - x_i)^T``   (n, 3, 3)
* ``count``       the number of neighbours ``j`` (i itself included), exact up to
                  ``COUNTED_UP_TO`` (larger counts are given as that number)

from which the weighted covariance ``C_i = second / S0`` and the weighted
centroid ``g_i = x_i + first / S0`` follow.  No n x n matrix is formed: rows are
processed in spatially compact blocks, each against the vertices within the
kernel's effective radius.  Euclidean: a compiled, vectorised loop over long
runs of Morton-ordered points within reach, accumulating relative to each
vertex (no cancellation); up to ``PAIRED_VERTICES`` vertices each pair is
computed once and added to both of its vertices (``_half_sums``), above that
each vertex's row in full (``_run_sums``, in linear memory).  Both add every
vertex's terms in an order that does not depend on the number of threads.
Geodesic: shortest-path searches over the sparse edge graph, bounded by the
radius, accumulating relative to each vertex (``dentopo.ariadne._geodesic``).
Precomputed: blocks of rows, with moments accumulated relative to the block's
centre so that cancellation is limited to the block's extent.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numba
import numpy as np

from .._jit import in_threads, njit, prange
from ..mesh import spatial_order
from ._exp import exp_neg
from ._geodesic import geodesic_sums
from ._parameters import check_bandwidth, check_cutoff

if TYPE_CHECKING:
    from scipy.sparse import csr_matrix

#: With cutoff 0, weights beyond this many bandwidths are below 1e-16 of the
#: largest (exp(-6.1**2) = 6.7e-17) and cannot change a double-precision sum.
FULL_RADIUS_IN_BANDWIDTHS = 6.1

#: Number of rows handled together; bounds the temporary block matrices.
BLOCK_ROWS = 128


@dataclass(frozen=True)
class KernelMoments:
    """Per-vertex kernel-weighted sums, relative to each vertex (see module doc)."""

    weight: np.ndarray
    first: np.ndarray
    second: np.ndarray
    count: np.ndarray

    @property
    def covariance(self) -> np.ndarray:
        """Weighted covariance about each vertex, ``second / weight``, shape (n, 3, 3)."""
        return self.second / self.weight[:, None, None]

    def centroid(self, points: np.ndarray) -> np.ndarray:
        """Weighted centroid of each vertex's neighbourhood, shape (n, 3)."""
        return points + self.first / self.weight[:, None]


def kernel_radius(bandwidth: float, cutoff: float) -> float:
    """Distance beyond which a neighbour's weight is zero or cannot matter."""
    if cutoff > 0:
        return float(bandwidth * np.sqrt(-np.log(cutoff)))
    return float(bandwidth * FULL_RADIUS_IN_BANDWIDTHS)


def _accumulate(out, rows, cols, sq_dist, points, bandwidth, cutoff, radius):
    """Add one block's weighted moments into ``out`` (weight, first, second, count)."""
    weight, first, second, count = out
    w = np.exp(-sq_dist / bandwidth**2)
    if cutoff > 0:
        w[w <= cutoff] = 0.0
    count[rows] = np.count_nonzero((w > 0) & (sq_dist <= radius**2), axis=1)
    centre = points[rows].mean(axis=0)
    y = points[cols] - centre
    yi = points[rows] - centre
    a0 = w.sum(axis=1)
    a1 = w @ y
    outer = (y[:, :, None] * y[:, None, :]).reshape(len(cols), 9)
    a2 = (w @ outer).reshape(len(rows), 3, 3)
    weight[rows] = a0
    first[rows] = a1 - a0[:, None] * yi
    cross = a1[:, :, None] * yi[:, None, :]
    second[rows] = (
        a2
        - cross
        - cross.transpose(0, 2, 1)
        + a0[:, None, None] * (yi[:, :, None] * yi[:, None, :])
    )


def _empty(n):
    return [np.zeros(n), np.zeros((n, 3)), np.zeros((n, 3, 3)), np.zeros(n, dtype=np.int64)]


#: Vertices per block: rows and candidate runs are built from Morton-ordered blocks.
BLOCK_POINTS = 64


@njit(cache=True)
def _candidate_runs(lo, hi, block_start, radius2, first, stop, fill, run_ptr, run_start, run_end):
    """For blocks ``first`` to ``stop - 1``, the runs of points (Morton order) within reach.

    Blocks whose bounding boxes are within the radius of each other are
    candidates; consecutive candidate blocks are merged into one run, so that
    the kernel loops over a few long ranges of points.  The runs are CSR
    arrays: those of block ``a`` are ``run_start[run_ptr[a]:run_ptr[a + 1]]``
    to the matching ``run_end``.  Two passes: without `fill`, the number of
    runs of block ``a`` goes to ``run_ptr[a + 1]`` (the caller then sums them
    up); with `fill`, the runs go to `run_start` and `run_end`.

    Writes into arrays of the caller and returns nothing: numba boxes a
    returned array with a little Python code, where a Ctrl-C that arrived
    during the loop would be raised and crash the caller (see ``_run_sums``).
    """
    n_blocks = lo.shape[0]
    for a in range(first, stop):
        k = run_ptr[a] if fill else 0
        open_run = False
        for b in range(n_blocks):
            gap2 = 0.0
            for c in range(3):
                g = max(lo[b, c] - hi[a, c], lo[a, c] - hi[b, c], 0.0)
                gap2 += g * g
            if gap2 <= radius2:
                if open_run:
                    if fill:
                        run_end[k - 1] = block_start[b + 1]
                else:
                    if fill:
                        run_start[k] = block_start[b]
                        run_end[k] = block_start[b + 1]
                    k += 1
                    open_run = True
            else:
                open_run = False
        if not fill:
            run_ptr[a + 1] = k


@njit(cache=True, parallel=True, fastmath=True)
def _run_sums(
    xs,
    ys,
    zs,
    block_of,
    run_ptr,
    run_start,
    run_end,
    inv_h2,
    cutoff,
    radius2,
    parts,
    out,
):
    """Kernel sums for vertices ``parts[0]`` to ``parts[-1] - 1`` over the runs of their block.

    The weight ``exp(-d2 / h2)`` is computed inline by ``_exp.exp_neg`` (within
    2 ulps of libm's ``exp``), which LLVM vectorises, unlike a call to ``exp``.
    Pairs beyond the radius or with weight ``<= cutoff`` get weight zero.

    The sums go to ``out[i]`` (weight, first moment, then the second moment's
    xx, xy, xz, yy, yz, zz): an array of the caller.  Nothing is returned,
    because returning new arrays is not safe from Ctrl-C: numba boxes them
    with a little Python code (it unpickles the array type), where a
    KeyboardInterrupt that arrived during the loop is raised; a tuple of
    boxes then holds a NULL, and the caller gets a ``SystemError`` or a
    segmentation fault.  Each vertex's sums depend on that vertex alone, so
    the caller can compute them in slices (and Python then reacts to Ctrl-C
    between slices).  Thread ``k`` computes
    the vertices ``parts[k]`` to ``parts[k + 1] - 1``.
    """
    # one part of rows per thread, of about equal work: numba would give each thread
    # an equal number of rows (parallel_chunksize does not balance them either)
    for part in prange(parts.shape[0] - 1):
        for row in range(parts[part], parts[part + 1]):
            i = np.int64(row)
            a = block_of[i]
            xi = xs[i]
            yi = ys[i]
            zi = zs[i]
            s0 = s1x = s1y = s1z = 0.0
            sxx = sxy = sxz = syy = syz = szz = 0.0
            for run in range(run_ptr[a], run_ptr[a + 1]):
                # fresh accumulators per run: the innermost loop owns its reductions,
                # which LLVM vectorises (carried across the run loop, it does not)
                r0 = r1x = r1y = r1z = 0.0
                rxx = rxy = rxz = ryy = ryz = rzz = 0.0
                # views indexed from 0: numba then knows the index is non-negative and
                # drops its negative-index wraparound, which would turn loads into gathers
                xr = xs[run_start[run] : run_end[run]]
                yr = ys[run_start[run] : run_end[run]]
                zr = zs[run_start[run] : run_end[run]]
                for j in range(xr.shape[0]):
                    dx = xr[j] - xi
                    dy = yr[j] - yi
                    dz = zr[j] - zi
                    d2 = dx * dx + dy * dy + dz * dz
                    w = exp_neg(d2 * inv_h2)
                    keep = (d2 <= radius2) and (w > cutoff)
                    w = w if keep else 0.0
                    wx = w * dx
                    wy = w * dy
                    wz = w * dz
                    r0 += w
                    r1x += wx
                    r1y += wy
                    r1z += wz
                    rxx += wx * dx
                    rxy += wx * dy
                    rxz += wx * dz
                    ryy += wy * dy
                    ryz += wy * dz
                    rzz += wz * dz
                s0 += r0
                s1x += r1x
                s1y += r1y
                s1z += r1z
                sxx += rxx
                sxy += rxy
                sxz += rxz
                syy += ryy
                syz += ryz
                szz += rzz
            out[i, 0] = s0
            out[i, 1] = s1x
            out[i, 2] = s1y
            out[i, 3] = s1z
            out[i, 4] = sxx
            out[i, 5] = sxy
            out[i, 6] = sxz
            out[i, 7] = syy
            out[i, 8] = syz
            out[i, 9] = szz


#: Pairs of points one call of the compiled kernel goes through per thread (about 0.15 s):
#: Python reacts to Ctrl-C between calls, and not during one.
PAIRS_PER_CALL = 1 << 26
#: ... but at least this many blocks per thread, so that the threads share the work evenly.
SLICE_BLOCKS = 4
#: Block pairs whose bounding boxes one call of ``_candidate_runs`` compares (about 0.1 s).
BOX_TESTS_PER_CALL = 1 << 24


#: Meshes up to this many vertices compute each pair once (``_half_sums``); larger ones
#: each row in full (``_run_sums``), in linear memory.
PAIRED_VERTICES = 40_000

#: The pairs of up to ``PAIRED_VERTICES`` vertices are cut into at most this many tasks,
#: one per ``PAIRED_TASK_VERTICES`` vertices and at least two (a number that depends on the
#: mesh alone, not on the threads, so neither do the sums).  Each task has its own column
#: sums, 80 bytes for each vertex from its first row on: fewer tasks on smaller meshes touch
#: less fresh memory, whose first touch costs about 10 microseconds a 4 kB page in a virtual
#: machine (16 tasks on normal.ply, 4,050 vertices: 3.5 MB and 18 ms for the first call's
#: pairs, against 11 ms with 2 tasks and 10 ms once the memory is the process's own).
PAIRED_TASKS = 16
PAIRED_TASK_VERTICES = 2048


@njit(fastmath=True)
def _row_and_columns(xs, ys, zs, i, a, run_ptr, run_start, run_end, consts, rows, cols, off):
    """The pairs of vertex ``i`` with the points ``j > i`` of block ``a``'s runs.

    Each pair's weight is computed once and its terms go to both ends: summed
    for ``i`` into ``rows[:, i]``, and added to ``cols[:, j - off]`` (the first
    moment with the opposite sign: it is relative to ``j``).
    """
    inv_h2, cutoff, radius2 = consts
    xi = xs[i]
    yi = ys[i]
    zi = zs[i]
    s0 = s1x = s1y = s1z = 0.0
    sxx = sxy = sxz = syy = syz = szz = 0.0
    for run in range(run_ptr[a], run_ptr[a + 1]):
        first = max(run_start[run], i + 1)
        stop = run_end[run]
        if first >= stop:
            continue
        # fresh accumulators per run: the innermost loop owns its reductions,
        # which LLVM vectorises (carried across the run loop, it does not);
        # views indexed from 0: numba then drops its negative-index wraparound
        xr = xs[first:stop]
        yr = ys[first:stop]
        zr = zs[first:stop]
        c0 = cols[0, first - off : stop - off]
        c1x = cols[1, first - off : stop - off]
        c1y = cols[2, first - off : stop - off]
        c1z = cols[3, first - off : stop - off]
        cxx = cols[4, first - off : stop - off]
        cxy = cols[5, first - off : stop - off]
        cxz = cols[6, first - off : stop - off]
        cyy = cols[7, first - off : stop - off]
        cyz = cols[8, first - off : stop - off]
        czz = cols[9, first - off : stop - off]
        r0 = r1x = r1y = r1z = 0.0
        rxx = rxy = rxz = ryy = ryz = rzz = 0.0
        for j in range(xr.shape[0]):
            dx = xr[j] - xi
            dy = yr[j] - yi
            dz = zr[j] - zi
            d2 = dx * dx + dy * dy + dz * dz
            w = exp_neg(d2 * inv_h2)
            keep = (d2 <= radius2) and (w > cutoff)
            w = w if keep else 0.0
            wx = w * dx
            wy = w * dy
            wz = w * dz
            pxx = wx * dx
            pxy = wx * dy
            pxz = wx * dz
            pyy = wy * dy
            pyz = wy * dz
            pzz = wz * dz
            r0 += w
            r1x += wx
            r1y += wy
            r1z += wz
            rxx += pxx
            rxy += pxy
            rxz += pxz
            ryy += pyy
            ryz += pyz
            rzz += pzz
            c0[j] += w
            c1x[j] -= wx
            c1y[j] -= wy
            c1z[j] -= wz
            cxx[j] += pxx
            cxy[j] += pxy
            cxz[j] += pxz
            cyy[j] += pyy
            cyz[j] += pyz
            czz[j] += pzz
        s0 += r0
        s1x += r1x
        s1y += r1y
        s1z += r1z
        sxx += rxx
        sxy += rxy
        sxz += rxz
        syy += ryy
        syz += ryz
        szz += rzz
    rows[0, i] += s0
    rows[1, i] += s1x
    rows[2, i] += s1y
    rows[3, i] += s1z
    rows[4, i] += sxx
    rows[5, i] += sxy
    rows[6, i] += sxz
    rows[7, i] += syy
    rows[8, i] += syz
    rows[9, i] += szz


@njit(cache=True, nogil=True, fastmath=True)
def _half_sums(
    xs,
    ys,
    zs,
    block_of,
    run_ptr,
    run_start,
    run_end,
    task_start,
    col_offset,
    buffer_start,
    part,
    parts,
    inv_h2,
    cutoff,
    radius2,
    rows,
    buffer,
    first_task,
    last_task,
):
    """Each pair ``i < j`` (Morton order) once: part `part` of `parts` of every task's rows.

    ``w_ij = w_ji`` (the same bits: so is the squared distance), so each pair's
    weight is computed once (as in ``_run_sums``: ``_exp.exp_neg``) and
    its terms added to both vertices.  Task ``t`` owns the rows
    ``task_start[t]`` to ``task_start[t + 1] - 1``: their sums over ``j > i``
    go to ``rows[:, i]`` (with the vertex's own weight 1 first), and the terms
    of the pairs for their ``j`` to the task's own columns, ``buffer`` from
    ``buffer_start[t]`` on, a (10, width) array for ``j`` from
    ``col_offset[t]`` on.  Tasks share no sum: ``_gather_sums`` adds the
    columns up in task order, so the sums do not depend on the threads.  The
    rows of each task are split into `parts` consecutive parts, one per call,
    done in order (Python reacts to Ctrl-C between calls): the sums do not
    depend on `parts` either.  A call does the tasks ``first_task:last_task``;
    the threads each take some (:func:`dentopo._jit.in_threads`: one compiled
    function, where a ``prange`` loop compiled its body a second time, 1.7 s on
    a fresh install).

    Writes into ``rows`` and ``buffer`` and returns nothing (see ``_run_sums``).
    """
    consts = (inv_h2, cutoff, radius2)
    for task in range(first_task, last_task):
        off = col_offset[task]
        width = (buffer_start[task + 1] - buffer_start[task]) // 10
        cols = buffer[buffer_start[task] : buffer_start[task + 1]].reshape((10, width))
        size = task_start[task + 1] - task_start[task]
        first = task_start[task] + size * part // parts
        stop = task_start[task] + size * (part + 1) // parts
        for row in range(first, stop):
            i = np.int64(row)
            rows[0, i] += 1.0  # the vertex itself: weight exp(0) = 1, no moment
            a = block_of[i]
            _row_and_columns(xs, ys, zs, i, a, run_ptr, run_start, run_end, consts, rows, cols, off)


@njit(cache=True)
def _gather_sums(task_start, col_offset, buffer_start, buffer, rows):
    """Add every task's columns to ``rows``, in task order (see ``_half_sums``).

    Serial: a few additions per vertex and task, less than starting the threads
    costs on a busy machine.  Writes into ``rows`` and returns nothing.
    """
    for task in range(task_start.shape[0] - 1):
        off = col_offset[task]
        width = (buffer_start[task + 1] - buffer_start[task]) // 10
        base = buffer_start[task]
        for q in range(10):
            column = buffer[base + q * width : base + (q + 1) * width]
            target = rows[q, off : off + width]
            for j in range(width):
                target[j] += column[j]


def _paired_moments(xs, ys, zs, block_start, runs, inv_h2, cutoff, radius2):
    """``_half_sums`` and ``_gather_sums`` on Morton-ordered points: sums (10, n)."""
    run_ptr, run_start, run_end = runs
    n = len(xs)
    sizes = np.diff(block_start)
    block_of = np.repeat(np.arange(len(sizes)), sizes)
    # the work of each row: its pairs with the later points of its block's runs
    run_block = np.repeat(np.arange(len(sizes)), np.diff(run_ptr))
    after = np.maximum(run_end - np.maximum(run_start, block_start[run_block + 1]), 0)
    reach_after = np.bincount(run_block, weights=after, minlength=len(sizes))
    end_of_runs = np.zeros(len(sizes), np.int64)
    np.maximum.at(end_of_runs, run_block, run_end)
    row_cost = np.repeat(reach_after, sizes) + np.repeat(block_start[1:], sizes) - 1 - np.arange(n)
    total = np.cumsum(row_cost + 1.0)
    tasks = max(1, min(PAIRED_TASKS, n // BLOCK_POINTS, max(2, n // PAIRED_TASK_VERTICES)))
    cuts = np.searchsorted(total, total[-1] * np.arange(1, tasks) / tasks, side="right")
    task_start = np.concatenate([[0], cuts, [n]]).astype(np.int64)
    # the columns a task's rows reach: from its first row to the end of its blocks' runs
    last_block = block_of[np.maximum(task_start[1:] - 1, 0)]
    first_block = block_of[np.minimum(task_start[:-1], n - 1)]
    reach_end = np.array(
        [
            end_of_runs[b0 : b1 + 1].max(initial=t1)  # a task without rows: nothing
            for b0, b1, t1 in zip(first_block, last_block, task_start[1:], strict=True)
        ],
        np.int64,
    )
    col_offset = task_start[:-1].copy()
    width = np.maximum(reach_end - col_offset, 0)
    buffer_start = np.concatenate([[0], np.cumsum(10 * width)]).astype(np.int64)
    buffer = np.zeros(buffer_start[-1])
    rows = np.zeros((10, n))
    pairs = float(row_cost.sum())
    parts = max(1, int(np.ceil(pairs / (PAIRS_PER_CALL * numba.get_num_threads()))))
    for part in range(parts):
        in_threads(
            0,
            len(task_start) - 1,
            lambda a, b, part=part: _half_sums(
                xs,
                ys,
                zs,
                block_of,
                run_ptr,
                run_start,
                run_end,
                task_start,
                col_offset,
                buffer_start,
                part,
                parts,
                inv_h2,
                cutoff,
                radius2,
                rows,
                buffer,
                a,
                b,
            ),
        )
    _gather_sums(task_start, col_offset, buffer_start, buffer, rows)
    return rows


def slices(cost: np.ndarray, budget: float, *, minimum: int = 1) -> list[tuple[int, int]]:
    """Consecutive ``(first, stop)`` ranges of items whose summed `cost` is about `budget`.

    Each range holds at least `minimum` items (one at least), and more while
    their cost stays within the budget; together they cover every item once,
    in order.
    """
    total = np.cumsum(cost, dtype=np.float64)
    minimum = max(1, int(minimum))
    bounds = []
    first = 0
    while first < len(cost):
        before = total[first - 1] if first else 0.0
        stop = int(np.searchsorted(total, before + budget, side="right"))
        stop = min(len(cost), max(stop, first + minimum))
        bounds.append((first, stop))
        first = stop
    return bounds


def balanced_parts(cost: np.ndarray, first: int, stop: int, parts: int) -> np.ndarray:
    """Bounds that cut items `first` to ``stop - 1`` into `parts` ranges of about equal `cost`."""
    total = np.cumsum(cost[first:stop], dtype=np.float64)
    if len(total) == 0:
        return np.array([first, stop], np.int64)
    cuts = np.searchsorted(total, total[-1] * np.arange(1, parts) / parts, side="right")
    return np.concatenate([[first], first + cuts, [stop]]).astype(np.int64)


def candidate_runs(
    lo: np.ndarray, hi: np.ndarray, block_start: np.ndarray, radius2: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``run_ptr, run_start, run_end`` of ``_candidate_runs``, in slices of blocks."""
    n_blocks = len(lo)
    run_ptr = np.zeros(n_blocks + 1, np.int64)
    per_call = max(1, BOX_TESTS_PER_CALL // max(n_blocks, 1))
    ranges = [(a, min(a + per_call, n_blocks)) for a in range(0, n_blocks, per_call)]
    nothing = np.empty(0, np.int64)
    for first, stop in ranges:
        _candidate_runs(lo, hi, block_start, radius2, first, stop, False, run_ptr, nothing, nothing)
    np.cumsum(run_ptr, out=run_ptr)
    run_start = np.empty(run_ptr[-1], np.int64)
    run_end = np.empty(run_ptr[-1], np.int64)
    for first, stop in ranges:
        _candidate_runs(
            lo, hi, block_start, radius2, first, stop, True, run_ptr, run_start, run_end
        )
    return run_ptr, run_start, run_end


#: Neighbour counts are exact up to this number (ariaDNE warns about vertices with
#: 3 or fewer); larger counts are given as this number.
COUNTED_UP_TO = 4


def few_neighbour_counts(points, weight, radius, cap=COUNTED_UP_TO):
    """Neighbour counts within `radius` (self included), exact where they can be below `cap`.

    A vertex with fewer than ``cap`` neighbours has a kernel sum below ``cap``
    (every weight is at most 1), so only those are counted (a k-d tree query);
    the others get ``cap``.  The pair kernels no longer count every pair: only
    the warning about vertices with 3 or fewer neighbours reads the counts.
    """
    count = np.full(len(points), cap, dtype=np.int64)
    maybe = np.flatnonzero(weight < cap + 1e-6)
    if len(maybe):
        from scipy.spatial import cKDTree

        tree = cKDTree(points)
        found = tree.query_ball_point(points[maybe], radius, return_length=True)
        count[maybe] = np.minimum(found, cap)
    return count


def euclidean_moments(points: np.ndarray, bandwidth: float, cutoff: float) -> KernelMoments:
    """Kernel moments with straight-line distances, in linear memory.

    Vertices are put in Morton order and cut into blocks of ``BLOCK_POINTS``;
    each vertex loops over the points of the blocks within reach of its own
    block, merged into long contiguous runs (one run of all the points when
    the kernel reaches across the whole mesh, as it does on a tooth at the
    default bandwidth).  Long runs matter more than pruning the last pairs: the
    loop is vectorised, and short runs waste it.  Sums are accumulated relative
    to the vertex itself (no cancellation).  Up to ``PAIRED_VERTICES`` vertices
    each pair is computed once (``_half_sums``: ``w_ij = w_ji``, about 25% less
    work; a buffer of up to ``PAIRED_TASKS * 80`` bytes per vertex, fewer tasks on
    smaller meshes), above that
    each vertex's row in full (``_run_sums``).  The two add the same terms in
    different orders: they agree to rounding error (about 1e-15 relative).

    Parameters
    ----------
    points : (n, 3) float
        Vertex positions (unit-area scale).
    bandwidth : float
        Kernel bandwidth ``h``.
    cutoff : float
        Weights ``<= cutoff`` are dropped (0 keeps every weight that can
        change a double, i.e. those within ``kernel_radius``).
    """
    bandwidth, cutoff = check_bandwidth(bandwidth), check_cutoff(cutoff)
    points = np.ascontiguousarray(points, dtype=np.float64)
    n = len(points)
    if n == 0:
        return KernelMoments(np.zeros(0), np.zeros((0, 3)), np.zeros((0, 3, 3)), np.zeros(0, int))
    radius = kernel_radius(bandwidth, cutoff)
    order = spatial_order(points)
    ordered = points[order]
    block_start = np.append(np.arange(0, n, BLOCK_POINTS), n).astype(np.int64)
    lo = np.minimum.reduceat(ordered, block_start[:-1], axis=0)
    hi = np.maximum.reduceat(ordered, block_start[:-1], axis=0)
    run_ptr, run_start, run_end = candidate_runs(lo, hi, block_start, radius**2)
    xs, ys, zs = (np.ascontiguousarray(ordered[:, k]) for k in range(3))
    constants = (1.0 / bandwidth**2, float(cutoff), radius**2)
    moments = np.empty((n, 10))
    if n <= PAIRED_VERTICES:
        runs = (run_ptr, run_start, run_end)
        moments[order] = _paired_moments(xs, ys, zs, block_start, runs, *constants).T
    else:
        moments[order] = _row_moments(
            xs, ys, zs, block_start, run_ptr, run_start, run_end, constants
        )
    second = moments[:, [4, 5, 6, 5, 7, 8, 6, 8, 9]].reshape(-1, 3, 3)
    weight = moments[:, 0]
    count = few_neighbour_counts(points, weight, radius, COUNTED_UP_TO)
    return KernelMoments(weight, moments[:, 1:4], second, count)


def _row_moments(xs, ys, zs, block_start, run_ptr, run_start, run_end, constants):
    """``_run_sums`` on Morton-ordered points: sums (n, 10)."""
    n = len(xs)
    block_of = np.repeat(np.arange(len(block_start) - 1), np.diff(block_start))
    sums = np.zeros((n, 10))
    threads = numba.get_num_threads()
    # the work: each row of a block goes through the points of the block's runs
    run_length = np.concatenate([[0], np.cumsum(run_end - run_start)])
    reach = run_length[run_ptr[1:]] - run_length[run_ptr[:-1]]
    sizes = np.diff(block_start)
    row_reach = np.repeat(reach, sizes)
    for first, stop in slices(
        reach * sizes, PAIRS_PER_CALL * threads, minimum=SLICE_BLOCKS * threads
    ):
        parts = balanced_parts(row_reach, block_start[first], block_start[stop], threads)
        _run_sums(xs, ys, zs, block_of, run_ptr, run_start, run_end, *constants, parts, sums)
    return sums


def edge_graph(points: np.ndarray, faces: np.ndarray) -> csr_matrix:
    """Undirected sparse graph of mesh edges weighted by Euclidean edge length."""
    from scipy.sparse import csr_matrix  # only for geodesic distances (0.25 s to import)

    edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    edges = np.unique(np.sort(edges, axis=1), axis=0)
    length = np.linalg.norm(points[edges[:, 0]] - points[edges[:, 1]], axis=1)
    n = len(points)
    graph = csr_matrix((length, (edges[:, 0], edges[:, 1])), shape=(n, n))
    return (graph + graph.T).tocsr()


def geodesic_moments(
    points: np.ndarray, faces: np.ndarray, bandwidth: float, cutoff: float
) -> KernelMoments:
    """Kernel moments with shortest-path distances along mesh edges.

    Compiled searches bounded by the kernel radius (sixteen neighbouring
    sources share one, their distances carried side by side) add the terms of
    the vertices each source reaches, relative to the source (see
    ``dentopo.ariadne._geodesic``): the distances are scipy's
    ``dijkstra(edge_graph(points, faces), limit=radius)`` bit for bit, in
    memory linear in the number of vertices.  The vertices are put in a
    spatial order first, so that each search touches memory nearby.
    """
    bandwidth, cutoff = check_bandwidth(bandwidth), check_cutoff(cutoff)
    points = np.ascontiguousarray(points, dtype=np.float64)
    n = len(points)
    if n == 0:
        return KernelMoments(*_empty(0))
    radius = kernel_radius(bandwidth, cutoff)
    order = spatial_order(points)
    rank = np.empty(n, np.int64)
    rank[order] = np.arange(n)
    faces = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    graph = edge_graph(points[order], rank[faces])
    graph.sort_indices()
    sums = np.empty((n, 10))
    count = np.empty(n, np.int64)
    sums[order], count[order] = geodesic_sums(
        graph.indptr, graph.indices, graph.data, points[order], bandwidth, cutoff, radius
    )
    second = sums[:, [4, 5, 6, 5, 7, 8, 6, 8, 9]].reshape(-1, 3, 3)
    return KernelMoments(sums[:, 0], sums[:, 1:4], second, count)


def precomputed_moments(
    points: np.ndarray, distances: np.ndarray, bandwidth: float, cutoff: float
) -> KernelMoments:
    """Kernel moments from a caller-supplied symmetric (n, n) distance matrix."""
    bandwidth, cutoff = check_bandwidth(bandwidth), check_cutoff(cutoff)
    n = len(points)
    out = _empty(n)
    cols = np.arange(n)
    radius = np.inf if cutoff == 0 else kernel_radius(bandwidth, cutoff)
    for start in range(0, n, BLOCK_ROWS):
        rows = np.arange(start, min(n, start + BLOCK_ROWS))
        sq_dist = np.asarray(distances[rows], dtype=np.float64) ** 2
        _accumulate(out, rows, cols, sq_dist, points, bandwidth, cutoff, radius)
    return KernelMoments(*out)
