"""The named result of an ariaDNE computation."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from .._html_repr import result_html
from ..mesh._lazy import LazyMesh

if TYPE_CHECKING:
    import trimesh

#: Scalar fields, in the order of output tables (after ``file``).
SCALAR_FIELDS = (
    "dne",
    "positive_dne",
    "negative_dne",
    "surface_area",
    "positive_surface_area",
    "negative_surface_area",
    "vertices",
    "faces",
    "bandwidth",
    "cutoff",
    "distance_type",
    "sign_method",
    "method",
)


@dataclass(frozen=True)
class AriaDNEResult:
    """ariaDNE and its sign-oriented split for one mesh.

    Per-vertex arrays follow the vertices of the cleaned mesh (``mesh``), which
    keep the input order when cleaning removes nothing.

    Attributes
    ----------
    local_curvature : (n,) float
        Signed local bending: ``k_i = lambda_i / trace(C_i)`` from the weighted
        PCA at vertex i, positive where the surface is convex (cusps, ridges:
        the neighbourhood's weighted centroid lies inside the closed surface),
        negative where it is concave (valleys, basins).  Dimensionless.
    local_dne : (n,) float
        ``local_curvature`` times the vertex area on the unit-area scale.
    dne : float
        ariaDNE, ``sum(|local_dne|)``.
    positive_dne : float
        ``sum(local_dne[local_dne >= 0])``.
    negative_dne : float
        ``-sum(local_dne[local_dne < 0])``, a non-negative magnitude, so that
        ``positive_dne + negative_dne == dne``.
    surface_area : float
        Area of the cleaned mesh, in the mesh's own units squared.
    positive_surface_area, negative_surface_area : float
        Vertex areas (one third of the incident faces' area) summed over the
        vertices counted in ``positive_dne`` and ``negative_dne``, mesh units.
    vertices, faces : int
        Vertex and face counts of the cleaned mesh.
    bandwidth : float
        Kernel bandwidth used (unit-area scale).
    cutoff : float
        Kernel weight cutoff used.
    distance_type : str
        ``"euclidean"``, ``"geodesic"`` or ``"precomputed"``.
    sign_method : str
        How the sign was decided: ``"centroid"`` (weighted centroid inside the
        closed surface, by exact generalised winding number), ``"winding"``
        (the same centroid against the mesh as given, holes open),
        ``"mean_curvature"`` or ``"gaussian_curvature"`` (sign of trimesh's
        discrete curvature measure in a ball of radius ``bandwidth``).
    method : str
        How the Euclidean kernel sums were computed: ``"exact"`` (blocked
        sums over every neighbour within the kernel's reach) or ``"fast"``
        (fast Gauss transform by non-uniform FFT, for large meshes).
    mesh : trimesh.Trimesh
        The cleaned mesh the per-vertex values refer to (a private copy), what
        cleaning changed in ``mesh.metadata["cleaning"]``; built when it is
        first read (trimesh is imported then, not before).
    """

    local_curvature: np.ndarray
    local_dne: np.ndarray
    dne: float
    positive_dne: float
    negative_dne: float
    surface_area: float
    positive_surface_area: float
    negative_surface_area: float
    vertices: int
    faces: int
    bandwidth: float
    cutoff: float
    distance_type: str
    sign_method: str
    mesh: trimesh.Trimesh = field(default=LazyMesh(), repr=False, compare=False)
    method: str = "exact"

    def to_dict(self) -> dict:
        """The scalar fields as a plain dict (one row of a results table)."""
        return {name: getattr(self, name) for name in SCALAR_FIELDS}

    def _repr_html_(self) -> str:
        """A compact table for notebooks: values, settings, arrays summarised."""
        return result_html(self, histogram="local_curvature")
