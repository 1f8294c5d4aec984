"""The footprint area of a crown as doolkit 1.42.2's ``area2d`` computes it (convex hull only).

TEMPORARY: this module implements only ``hull="convex"`` and raises
``NotImplementedError`` for ``"concave"``; the concaveman port replaces it.

doolkit's convex footprint: the vertices' (x, y), exact duplicate rows
dropped, ``grDevices::chull`` on them (unshifted, unrounded), and the
shoelace area of the hull ring.  Here the hull is Andrew's monotone chain
(duplicates and collinear points on the hull change nothing in the area).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .._jit import njit
from ._angles import doolkit_mesh

#: Footprint outlines.
HULLS = ("concave", "convex")


@dataclass(frozen=True)
class FootprintResult:
    """A crown's footprint on the x-y plane.

    Attributes
    ----------
    area : float
        Shoelace area of ``ring``, mesh units squared.
    hull : str
        ``"convex"`` (or ``"concave"``).
    ring : (k, 2) float64
        The outline's points in order (counter-clockwise), not closed.
    """

    area: float
    hull: str
    ring: np.ndarray = field(repr=False, compare=False)

    def to_dict(self) -> dict:
        """``{"area2d": ...}`` (concave) or ``{"area2d_convex": ...}``."""
        return {"area2d" if self.hull == "concave" else "area2d_convex": self.area}


@njit(cache=True)
def _cross(points, o, a, b):
    return (points[a, 0] - points[o, 0]) * (points[b, 1] - points[o, 1]) - (
        points[a, 1] - points[o, 1]
    ) * (points[b, 0] - points[o, 0])


@njit(cache=True)
def monotone_chain(points, order, hull):
    """Andrew's monotone chain on `points` sorted by (x, y) in `order`: the hull into `hull`.

    Writes the hull's point indices counter-clockwise (collinear points left
    out) and returns how many.
    """
    k = 0
    for p in order:
        while k >= 2 and _cross(points, hull[k - 2], hull[k - 1], p) <= 0:
            k -= 1
        hull[k] = p
        k += 1
    lower = k + 1
    for i in range(order.shape[0] - 2, -1, -1):
        p = order[i]
        while k >= lower and _cross(points, hull[k - 2], hull[k - 1], p) <= 0:
            k -= 1
        hull[k] = p
        k += 1
    return k - 1


def check_hull(hull) -> str:
    """``"concave"`` or ``"convex"``."""
    if not isinstance(hull, str) or hull not in HULLS:
        raise ValueError(f"hull must be one of {HULLS}; got {hull!r}")
    return hull


def shoelace(ring: np.ndarray) -> float:
    """The area enclosed by a closed ring of points (first not repeated), as a positive number."""
    x, y = ring[:, 0], ring[:, 1]
    return float(abs(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)) / 2.0)


def footprint_area(mesh, *, hull: str = "concave") -> FootprintResult:
    """The footprint's area, as doolkit's ``area2d(mesh, method = hull)``.

    Parameters
    ----------
    mesh : trimesh.Trimesh, str, path-like, (vertices, faces), or Surface
        Read as doolkit reads it (single-precision coordinates).  Never modified.
    hull : {"concave", "convex"}, default "concave"
        Only ``"convex"`` is implemented here.

    Raises
    ------
    NotImplementedError
        For ``hull="concave"``.
    ValueError
        For another `hull`, or a footprint of no area.
    """
    hull = check_hull(hull)
    if hull == "concave":
        raise NotImplementedError("the concave footprint (concaveman) is not implemented here")
    points = np.ascontiguousarray(doolkit_mesh(mesh).vertices[:, :2])
    order = np.lexsort((points[:, 1], points[:, 0]))
    index = np.empty(2 * len(points) + 1, dtype=np.int64)
    count = monotone_chain(points, order, index)
    ring = points[index[:count]]
    area = shoelace(ring) if count >= 3 else 0.0
    if not area > 0:
        raise ValueError("the footprint has no area: the vertices' x-y positions lie on one line")
    return FootprintResult(area=area, hull=hull, ring=ring)
