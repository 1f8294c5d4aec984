"""Dirichlet normal energy as doolkit 1.42.2's ``dne`` computes it.

doolkit's DNE is classic DNE (Bunn et al. 2011) with its own rules: float32
vertex normals from the VCG library, the mesh measured as read (no
rescaling), every face touching the border zeroed, then every face at or
above the 99.9 % quantile of the energies zeroed, and the total rounded to 3
decimals.  It is larger than molaR's (normal.ply: 309.285 against 290.095)
because of those rules.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from numbers import Real

import numpy as np
import trimesh

from ..._html_repr import result_html
from ..._jit import njit
from .._lazy import LazyMesh
from ..surface import _vcg
from ..surface._molar import prepare_surface

#: Scalar fields, in the order of output tables.
DOOLKIT_DNE_FIELDS = ("dne_total", "dne_total_unrounded")

#: MASS::ginv's relative tolerance: singular values at or below it (times the largest) count as 0.
GINV_TOL = math.sqrt(np.finfo(np.float64).eps)


@dataclass(frozen=True)
class DoolkitDNEResult:
    """doolkit's DNE for one mesh.

    Attributes
    ----------
    dne_total : float
        ``round(dne_total_unrounded, 3)`` (doolkit's ``total = TRUE``).
    dne_total_unrounded : float
        ``sum(face_energy * face_area)``.
    vertices, faces : int
        Vertex and face counts of the mesh used.
    range : float
        The quantile probability of the outlier cut.
    border_faces : int
        Faces with a vertex on the border (zeroed).
    outlier_faces : int
        Faces (of the others) zeroed for an energy at or above the quantile.
    face_energy : (m,) float64
        Each face's energy density ``trace(G^+ H)`` after the zeroing (not
        area weighted), in 1/length**2 of the mesh.
    face_area : (m,) float64
        Face areas computed in float32 (``vcgArea``), mesh units.
    mesh : trimesh.Trimesh
        The mesh the per-face arrays refer to (a copy).
    """

    dne_total: float
    dne_total_unrounded: float
    vertices: int
    faces: int
    range: float
    border_faces: int
    outlier_faces: int
    face_energy: np.ndarray = field(repr=False, compare=False)
    face_area: np.ndarray = field(repr=False, compare=False)
    mesh: trimesh.Trimesh = field(default=LazyMesh(), repr=False, compare=False)

    def to_dict(self) -> dict:
        """The scalar table fields as a plain dict (``DOOLKIT_DNE_FIELDS``)."""
        return {name: getattr(self, name) for name in DOOLKIT_DNE_FIELDS}

    def _repr_html_(self) -> str:
        """A compact table for notebooks: values, settings, arrays summarised."""
        return result_html(self, histogram="face_energy")


@njit(cache=True)
def _face_energy(vertices, faces, normals, tol, out):  # pragma: no cover
    for f in range(faces.shape[0]):
        i, j, k = faces[f, 0], faces[f, 1], faces[f, 2]
        uu = uv = vv = 0.0
        aa = ab = bb = 0.0
        for d in range(3):
            u = vertices[j, d] - vertices[i, d]
            v = vertices[k, d] - vertices[i, d]
            a = normals[j, d] - normals[i, d]
            b = normals[k, d] - normals[i, d]
            uu += u * u
            uv += u * v
            vv += v * v
            aa += a * a
            ab += a * b
            bb += b * b
        det = uu * vv - uv * uv
        trace = uu + vv
        # the Gram matrix's singular values are its eigenvalues (it is positive semi-definite)
        root = math.sqrt(max(trace * trace - 4.0 * det, 0.0))
        big, small = 0.5 * (trace + root), 0.5 * (trace - root)
        if small > tol * big and det > 0.0:
            out[f] = (vv * aa - 2.0 * uv * ab + uu * bb) / det
        elif big > 0.0:
            # rank one: G^+ = G / big**2, so trace(G^+ H) = trace(G H) / big**2
            out[f] = (uu * aa + 2.0 * uv * ab + vv * bb) / (big * big)
        else:
            out[f] = 0.0


def face_energy(vertices: np.ndarray, faces: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """Per-face ``trace(G^+ H)`` (double precision), doolkit's ``dne`` energy before zeroing.

    With ``u = p2 - p1``, ``v = p3 - p1``, ``a = n2 - n1``, ``b = n3 - n1``,
    ``G`` and ``H`` the Gram matrices of ``(u, v)`` and ``(a, b)``: for a
    non-degenerate face ``(|v|^2 |a|^2 - 2 (u.v)(a.b) + |u|^2 |b|^2) / det G``
    (equal to the pseudo-inverse form to ~1e-14); where ``G``'s smaller
    singular value is at most ``sqrt(eps)`` times the larger (MASS::ginv's
    tolerance) ``G`` is treated as of rank one, ``trace(G H) / s_max^2``.
    """
    out = np.empty(len(faces))
    _face_energy(
        np.ascontiguousarray(vertices, dtype=np.float64),
        np.asarray(faces, np.int64),
        np.ascontiguousarray(normals, dtype=np.float64),
        GINV_TOL,
        out,
    )
    return out


def _check_level(value) -> float:
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, Real):
        raise TypeError(f"range must be a real number; got {type(value).__name__}")
    value = float(value)
    if not (math.isfinite(value) and 0.0 <= value <= 1.0):
        raise ValueError(f"range must be a quantile probability in [0, 1]; got {value!r}")
    return value


def doolkit_dne(mesh, *, range: float = 0.999) -> DoolkitDNEResult:
    """Dirichlet normal energy, as doolkit 1.42.2's ``dne(mesh, total = TRUE)`` computes it.

    1. **Mesh** as read: coordinates in float32 (vcglib's), faces of zero
       area and unused vertices dropped (the shared reader), no rescaling.
    2. **Vertex normals** from the VCG library, in float32 (area-weighted
       sums of the face cross products, normalised:
       :func:`._vcg.vertex_normals`).
    3. **Per face** ``trace(G^+ H)`` in double precision from those numbers
       (:func:`face_energy`); not area weighted.
    4. **Border** faces (a vertex on a border edge) set to 0; then every
       face whose energy is **at or above** the type-7 quantile at `range`
       of all face energies (the zeros included) set to 0.
    5. ``dne_total_unrounded = sum(energy * area)`` with the float32 face
       areas (``vcgArea``); ``dne_total`` is it rounded to 3 decimals
       (Python's ``round``, correctly rounded on the double's exact value;
       R's ``round`` picks the same decimal for ordinary values).

    DNE does not depend on translation (up to float32 rounding), on vertex
    and face order, or on uniform scale (energy density scales as
    1/length**2, area as length**2).

    Parameters
    ----------
    mesh : trimesh.Trimesh, str, path-like, (vertices, faces), or Surface
        Never modified.
    range : float, default 0.999
        Quantile probability of the outlier cut, in [0, 1].

    Returns
    -------
    DoolkitDNEResult

    Raises
    ------
    TypeError, ValueError
        For an unusable mesh or `range`.

    References
    ----------
    Bunn J. M., Boyer D. M., Lipman Y., St. Clair E. M., Jernvall J.,
    Daubechies I. (2011). Comparing Dirichlet normal surface energy of tooth
    crowns, a new technique of molar shape quantification for dietary
    inference, with previous methods in isolation and in combination.
    American Journal of Physical Anthropology 145, 247-261.

    Examples
    --------
    >>> import trimesh
    >>> from dentopo.topography import doolkit_dne
    >>> result = doolkit_dne(trimesh.creation.icosphere(subdivisions=4))
    >>> round(result.dne_total / (8 * 3.14159265), 2)  # 8 pi for a sphere, less the top 0.1 %
    1.0
    """
    level = _check_level(range)
    surface = prepare_surface(mesh)
    faces = surface.faces
    v32, normals32 = _vcg.surface_normals32(surface)
    energy = face_energy(v32, faces, normals32)
    at_border = _vcg.border_faces(surface, "vertex")
    energy[at_border] = 0.0
    outlier = energy >= _vcg.quantile7(energy, level)
    energy[outlier] = 0.0
    area = surface.single_precision_areas()
    total = float(np.dot(energy, area))
    return DoolkitDNEResult(
        dne_total=round(total, 3),
        dne_total_unrounded=total,
        vertices=len(surface.vertices),
        faces=len(faces),
        range=level,
        border_faces=int(at_border.sum()),
        outlier_faces=int((outlier & ~at_border).sum()),
        face_energy=energy,
        face_area=area,
        mesh=surface.mesh_later(),
    )
