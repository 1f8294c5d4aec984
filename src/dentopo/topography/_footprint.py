"""The footprint area of a crown as doolkit 1.42.2's ``area2d`` computes it (convex hull only).

TEMPORARY: this module implements only ``hull="convex"`` and raises
``NotImplementedError`` for ``"concave"``; the concaveman port replaces it.

doolkit's convex footprint: the vertices' (x, y), exact duplicate rows
dropped, ``grDevices::chull`` on them (unshifted, unrounded), and the
shoelace area of the hull ring.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.spatial import ConvexHull, QhullError

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
    try:
        convex = ConvexHull(points)
    except QhullError as exc:
        raise ValueError(
            "the footprint has no area: the vertices' x-y positions lie on one line"
        ) from exc
    ring = points[convex.vertices]
    return FootprintResult(area=shoelace(ring), hull=hull, ring=ring)
