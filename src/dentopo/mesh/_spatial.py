"""Spatial ordering of points, so that nearby points are near each other in memory.

The order is a Morton (Z-order) curve over a 1024-cell grid per axis spanning
the points' bounding box.  A bounding box can be far larger than most of the
points: one stray vertex a million times farther out than the rest puts every
other point into a single grid cell, and a uniform quantisation then orders
them no better than their indices.  So the grid is adaptive: the points of any
cell holding more than ``CELL_POINTS`` of them are ordered again, by a Morton
curve over their own bounding box, and so on (an octree with ``CELL_POINTS``
points per leaf, cut 1024-fold per level).  On ordinary meshes no cell holds
that many points (a few at most, even at millions of vertices), and the order
is the plain Morton order.
"""

from __future__ import annotations

import numpy as np

#: Cells with more points than this are ordered again over their own bounding box.
CELL_POINTS = 64
_BITS = 10
_CELLS = (1 << _BITS) - 1


def _spread(q: np.ndarray) -> np.ndarray:
    """The 10 low bits of `q` (uint64) moved to every third bit: bit ``b`` to ``3 b``."""
    q = (q | (q << np.uint64(16))) & np.uint64(0x030000FF)
    q = (q | (q << np.uint64(8))) & np.uint64(0x0300F00F)
    q = (q | (q << np.uint64(4))) & np.uint64(0x030C30C3)
    return (q | (q << np.uint64(2))) & np.uint64(0x09249249)


def _morton_order(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Stable Morton order over the points' bounding box, and the sorted cell codes.

    A cell's code interleaves its three 10-bit coordinates, bit ``b`` of axis ``a`` at bit
    ``3 b + a`` (spread with masks: a few array operations, not one per bit).
    """
    lo = points.min(axis=0)
    span = float(np.max(points.max(axis=0) - lo)) or 1.0
    q = ((points - lo) / span * _CELLS).astype(np.uint64)
    code = _spread(q[:, 0]) | (_spread(q[:, 1]) << np.uint64(1))
    code |= _spread(q[:, 2]) << np.uint64(2)
    order = np.argsort(code, kind="stable")
    return order, code[order]


def _crowded_cells(codes: np.ndarray) -> list[tuple[int, int]]:
    """``(start, stop)`` of the runs of equal sorted codes longer than ``CELL_POINTS``."""
    if len(codes) <= CELL_POINTS or not (codes[CELL_POINTS:] == codes[:-CELL_POINTS]).any():
        return []  # (sorted codes: a run is longer than CELL_POINTS iff this holds somewhere)
    starts = np.flatnonzero(np.diff(codes)) + 1
    bounds = np.concatenate([[0], starts, [len(codes)]])
    long = np.flatnonzero(np.diff(bounds) > CELL_POINTS)
    return [(int(bounds[k]), int(bounds[k + 1])) for k in long]


def spatial_order(points: np.ndarray) -> np.ndarray:
    """A permutation that puts nearby points next to each other (adaptive Morton order).

    Parameters
    ----------
    points : (n, 3) float
        Finite coordinates.

    Returns
    -------
    (n,) int
        The order; the cost is O(n log n) times the depth of the adaptive grid,
        which is at most a few levels unless the points span many orders of
        magnitude (each level divides the extent by 1023; float64 allows about
        200 at most).
    """
    points = np.asarray(points, dtype=np.float64)
    order, codes = _morton_order(points)
    todo = [(order, start, stop) for start, stop in _crowded_cells(codes)]
    while todo:
        within, start, stop = todo.pop()
        members = within[start:stop]  # a view: reordered in place below
        cell = points[members]
        if not (cell.max(axis=0) > cell.min(axis=0)).any():
            continue  # identical points: any order is as good
        sub, sub_codes = _morton_order(cell)
        members[:] = members[sub]
        todo.extend((members, a, b) for a, b in _crowded_cells(sub_codes))
    return order
