"""How the sign of each vertex is decided: the sign methods of ``ariaDNE``.

ariaDNE's bending is unsigned; the sign-oriented extension gives each vertex
+1 (convex: cusps, ridges) or -1 (concave: valleys, basins).  Four rules are
offered, so that the paper's method can be compared with the alternatives:

``"centroid"`` (default; the paper's method)
    The kernel-weighted centroid of the neighbourhood lies inside the closed
    surface: holes are capped (see ``_closure``) and the exact generalised
    winding number decides (``|w| > 1/2``).
``"winding"``
    The same centroid, tested by the generalised winding number against the
    mesh *as given* (faces consistently oriented, holes left open),
    ``|w| > 1/2``.  For an open crown the winding number of the open surface
    falls smoothly from 1 to 0 across the missing base, so this needs no
    choice of how to cap the holes.
``"mean_curvature"``
    The sign of trimesh's discrete mean curvature measure (Cohen-Steiner and
    Morvan 2003) of the ball of radius ``bandwidth`` about the vertex, on the
    unit-area mesh (the same normalisation as the kernel, so the radius and
    the bandwidth are the same number on the same scale; ``_measure_sign``
    computes it and states the rule).  The faces are oriented consistently
    and outward first (outward = positive volume of the capped surface),
    because the measure's sign follows the orientation.
``"gaussian_curvature"``
    The sign of trimesh's discrete Gaussian curvature measure (the sum of the
    angle defects of the vertices in the same ball).  Orientation-free;
    saddles are negative, and boundary vertices (angle defect near pi) count
    as strongly positive, as trimesh computes them.

A measure of exactly zero (a flat neighbourhood) counts as convex, as a zero
``local_dne`` does in the totals.
"""

from __future__ import annotations

import numpy as np

from ..mesh import close_holes, orient_consistently
from ._measures import curvature_measure
from ._winding import inside, winding_number

SIGN_METHODS = ("centroid", "winding", "mean_curvature", "gaussian_curvature")


def check_sign_method(sign_method) -> str:
    """Validate a sign method name (lower case; any case accepted)."""
    if not isinstance(sign_method, str) or sign_method.lower() not in SIGN_METHODS:
        raise ValueError(f"sign_method must be one of {SIGN_METHODS}; got {sign_method!r}")
    return sign_method.lower()


def convex_vertices(
    sign_method: str,
    points: np.ndarray,
    faces: np.ndarray,
    centroids: np.ndarray,
    bandwidth: float,
) -> np.ndarray:
    """True where a vertex counts as convex (+) under `sign_method`.

    Parameters
    ----------
    sign_method : str
        One of ``SIGN_METHODS``.
    points : (n, 3) float
        The cleaned mesh's vertices on the unit-area scale.
    faces : (m, 3) int
        The cleaned mesh's faces.
    centroids : (n, 3) float
        Kernel-weighted neighbourhood centroids (used by the centroid methods).
    bandwidth : float
        Kernel bandwidth; the curvature methods' ball radius.

    Returns
    -------
    (n,) bool
    """
    sign_method = check_sign_method(sign_method)
    if sign_method == "centroid":
        closed_vertices, closed_faces = close_holes(points, faces)
        return inside(closed_vertices, closed_faces, centroids)
    if sign_method == "winding":
        oriented = orient_consistently(np.asarray(faces, dtype=np.int64), len(points))
        return np.abs(winding_number(points, oriented, centroids)) > 0.5

    # the unit-area mesh: the ball radius, bandwidth * sqrt(area), is the bandwidth itself
    kind = "mean" if sign_method == "mean_curvature" else "gaussian"
    return curvature_measure((points, faces), kind, bandwidth) >= 0
