"""Gaussian-kernel weighted moments: the only neighbourhood sums ariaDNE needs.

For every vertex i and weights ``w_ij = exp(-d_ij**2 / h**2)`` (kept where
``w_ij > cutoff``) this module computes

* ``weight``      ``S0_i = sum_j w_ij``
* ``first``       ``sum_j w_ij (x_j - x_i)``                (n, 3)
* ``second``      ``sum_j w_ij (x_j - x_i)(x_j - x_i)^T``   (n, 3, 3)
* ``count``       the number of neighbours ``j`` (i itself included)

from which the weighted covariance ``C_i = second / S0`` and the weighted
centroid ``g_i = x_i + first / S0`` follow.  No n x n matrix is formed: rows are
processed in spatially compact blocks, each against the vertices within the
kernel's effective radius.  Euclidean: a compiled loop over a uniform grid of
cells as wide as the radius, accumulating relative to each vertex (no
cancellation).  Geodesic and precomputed: blocks of rows (Dijkstra bounded by
the radius on the sparse edge graph), with moments accumulated relative to the
block's centre so that cancellation is limited to the block's extent.
"""

from __future__ import annotations

from dataclasses import dataclass

import numba
import numpy as np
from numba import njit, prange
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

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


def spatial_order(points: np.ndarray) -> np.ndarray:
    """A permutation that puts nearby points next to each other (Morton order)."""
    lo = points.min(axis=0)
    span = float(np.max(points.max(axis=0) - lo)) or 1.0
    q = ((points - lo) / span * 1023).astype(np.uint64)
    code = np.zeros(len(points), dtype=np.uint64)
    for bit in range(10):
        for axis in range(3):
            code |= ((q[:, axis] >> np.uint64(bit)) & np.uint64(1)) << np.uint64(3 * bit + axis)
    return np.argsort(code, kind="stable")


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


#: Upper bound on the number of grid cells; coarser cells beyond it.
MAX_GRID_CELLS = 2_000_000


# The 13 neighbouring cells "after" a cell, so that each pair of cells is visited once.
_HALF_NEIGHBOURHOOD = np.array(
    [
        (dx, dy, dz)
        for dx in (-1, 0, 1)
        for dy in (-1, 0, 1)
        for dz in (-1, 0, 1)
        if (dx, dy, dz) > (0, 0, 0)
    ],
    dtype=np.int64,
)


@njit(cache=True, parallel=True)
def _grid_sums(
    points, cell_sorted, cell_start, dims, offsets, chunk_start, inv_h2, cutoff, radius2
):
    """Symmetric pair sums over a cell grid; ``points`` sorted by cell.

    Each pair (i, j) is visited once, from the row of the earlier cell (or the
    smaller index in the same cell): the weight is computed once and added to
    both ends (``second`` about each end is the same outer product).  Rows are
    split into contiguous chunks of equal estimated work, one per thread, each
    accumulating into its own slice of ``acc``; the slices are summed at the end.
    """
    n = points.shape[0]
    n_chunks = chunk_start.shape[0] - 1
    acc = np.zeros((n_chunks, n, 10))
    count = np.zeros((n_chunks, n), np.int64)
    nx, ny, nz = dims[0], dims[1], dims[2]
    for chunk in prange(n_chunks):
        t = np.int64(chunk)
        for i in range(chunk_start[t], chunk_start[t + 1]):
            c = cell_sorted[i]
            cx = c // (ny * nz)
            cy = (c // nz) % ny
            cz = c % nz
            xi = points[i, 0]
            yi = points[i, 1]
            zi = points[i, 2]
            for o in range(offsets.shape[0] + 1):
                if o == offsets.shape[0]:
                    j0 = i + 1
                    j1 = cell_start[c + 1]
                else:
                    bx = cx + offsets[o, 0]
                    by = cy + offsets[o, 1]
                    bz = cz + offsets[o, 2]
                    if bx < 0 or bx >= nx or by < 0 or by >= ny or bz < 0 or bz >= nz:
                        continue
                    b = (bx * ny + by) * nz + bz
                    j0 = cell_start[b]
                    j1 = cell_start[b + 1]
                s0 = s1x = s1y = s1z = 0.0
                sxx = sxy = sxz = syy = syz = szz = 0.0
                cnt = 0
                for j in range(j0, j1):
                    dx = points[j, 0] - xi
                    dy = points[j, 1] - yi
                    dz = points[j, 2] - zi
                    d2 = dx * dx + dy * dy + dz * dz
                    if d2 > radius2:
                        continue
                    w = np.exp(-d2 * inv_h2)
                    if w <= cutoff:
                        continue
                    wx = w * dx
                    wy = w * dy
                    wz = w * dz
                    pxx = wx * dx
                    pxy = wx * dy
                    pxz = wx * dz
                    pyy = wy * dy
                    pyz = wy * dz
                    pzz = wz * dz
                    cnt += 1
                    s0 += w
                    s1x += wx
                    s1y += wy
                    s1z += wz
                    sxx += pxx
                    sxy += pxy
                    sxz += pxz
                    syy += pyy
                    syz += pyz
                    szz += pzz
                    row = acc[t, j]
                    count[t, j] += 1
                    row[0] += w
                    row[1] -= wx
                    row[2] -= wy
                    row[3] -= wz
                    row[4] += pxx
                    row[5] += pxy
                    row[6] += pxz
                    row[7] += pyy
                    row[8] += pyz
                    row[9] += pzz
                own = acc[t, i]
                count[t, i] += cnt
                own[0] += s0
                own[1] += s1x
                own[2] += s1y
                own[3] += s1z
                own[4] += sxx
                own[5] += sxy
                own[6] += sxz
                own[7] += syy
                own[8] += syz
                own[9] += szz
    return acc.sum(axis=0), count.sum(axis=0) + 1  # + 1: each vertex is its own neighbour


def _balanced_chunks(cell_sorted, cell_start, dims, n_chunks):
    """Split the cell-sorted rows into contiguous chunks of about equal pair work."""
    counts = np.diff(cell_start)
    grid = counts.reshape(tuple(dims))
    padded = np.pad(grid, 1)
    half = np.zeros_like(grid)
    nx, ny, nz = dims
    for dx, dy, dz in _HALF_NEIGHBOURHOOD:
        half += padded[1 + dx : 1 + dx + nx, 1 + dy : 1 + dy + ny, 1 + dz : 1 + dz + nz]
    row_cost = (half.ravel() + counts / 2.0 + 1.0)[cell_sorted]
    cumulative = np.cumsum(row_cost)
    targets = cumulative[-1] * np.arange(1, n_chunks) / n_chunks
    inner = np.searchsorted(cumulative, targets)
    return np.concatenate([[0], inner, [len(cell_sorted)]]).astype(np.int64)


def euclidean_moments(points: np.ndarray, bandwidth: float, cutoff: float) -> KernelMoments:
    """Kernel moments with straight-line distances, in linear memory.

    Vertices are binned in a uniform grid whose cells are at least the kernel
    radius wide, so each vertex's neighbours lie in the 27 cells around it.

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
    points = np.ascontiguousarray(points, dtype=np.float64)
    radius = kernel_radius(bandwidth, cutoff)
    lo = points.min(axis=0)
    span = points.max(axis=0) - lo
    cell = radius
    while np.prod(np.floor(span / cell) + 1) > MAX_GRID_CELLS:
        cell *= 2.0
    dims = (np.floor(span / cell) + 1).astype(np.int64)
    ijk = np.minimum(((points - lo) / cell).astype(np.int64), dims - 1)
    cell_of = (ijk[:, 0] * dims[1] + ijk[:, 1]) * dims[2] + ijk[:, 2]
    order = np.argsort(cell_of, kind="stable")
    cell_start = np.searchsorted(cell_of[order], np.arange(int(np.prod(dims)) + 1)).astype(np.int64)
    cell_sorted = cell_of[order]
    chunks = _balanced_chunks(cell_sorted, cell_start, dims, numba.get_num_threads())
    sums, count = _grid_sums(
        np.ascontiguousarray(points[order]),
        cell_sorted,
        cell_start,
        dims,
        _HALF_NEIGHBOURHOOD,
        chunks,
        1.0 / bandwidth**2,
        float(cutoff),
        radius**2,
    )
    sums[:, 0] += 1.0  # the vertex itself: weight 1, zero offset
    moments = np.empty_like(sums)
    moments[order] = sums
    counts = np.empty_like(count)
    counts[order] = count
    second = moments[:, [4, 5, 6, 5, 7, 8, 6, 8, 9]].reshape(-1, 3, 3)
    return KernelMoments(moments[:, 0], moments[:, 1:4], second, counts)


def edge_graph(points: np.ndarray, faces: np.ndarray) -> csr_matrix:
    """Undirected sparse graph of mesh edges weighted by Euclidean edge length."""
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

    Dijkstra runs from each block of source vertices, bounded by the kernel
    radius, so only the vertices it reaches enter the sums.
    """
    n = len(points)
    radius = kernel_radius(bandwidth, cutoff)
    graph = edge_graph(points, faces)
    order = spatial_order(points)
    out = _empty(n)
    block_rows = max(1, min(BLOCK_ROWS, 4_000_000 // max(n, 1)))
    for start in range(0, n, block_rows):
        rows = order[start : start + block_rows]
        dist = dijkstra(graph, directed=False, indices=rows, limit=radius)
        cols = np.flatnonzero(np.isfinite(dist).any(axis=0))
        sq_dist = dist[:, cols] ** 2  # inf ** 2 = inf, exp(-inf) = 0
        _accumulate(out, rows, cols, sq_dist, points, bandwidth, cutoff, radius)
    return KernelMoments(*out)


def precomputed_moments(
    points: np.ndarray, distances: np.ndarray, bandwidth: float, cutoff: float
) -> KernelMoments:
    """Kernel moments from a caller-supplied symmetric (n, n) distance matrix."""
    n = len(points)
    out = _empty(n)
    cols = np.arange(n)
    radius = np.inf if cutoff == 0 else kernel_radius(bandwidth, cutoff)
    for start in range(0, n, BLOCK_ROWS):
        rows = np.arange(start, min(n, start + BLOCK_ROWS))
        sq_dist = np.asarray(distances[rows], dtype=np.float64) ** 2
        _accumulate(out, rows, cols, sq_dist, points, bandwidth, cutoff, radius)
    return KernelMoments(*out)
