"""Classic DNE (Bunn et al. 2011) with molaR's convex/concave split.

A separate metric from ariaDNE: the Dirichlet energy of the normal map,
computed face by face from the vertex normals of the mesh, as the R package
molaR (Pampush et al.; version 6.0) computes it, including its boundary and
outlier exclusions and its per-face convex/concave classification.  It exists
so that the sign of ariaDNE can be compared honestly with the sign most
dental-topography studies use; every convention below is molaR's, including
the odd ones, because matching its numbers requires them.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from numbers import Real

import numpy as np
import trimesh

from ..._html_repr import result_html
from .._lazy import LazyMesh
from .._parameters import BOUNDARY_RULES, check_choice, check_outliers
from ..surface import _kernels
from ..surface._molar import Surface, molar_scale, prepare_surface
from ..surface._orientation import Orientation, check_orient

BOUNDARY_MODES = BOUNDARY_RULES
OUTLIER_MODES = ("combined", "separate")

#: Faces whose first-fundamental-form matrix has a 1-norm reciprocal condition
#: number below this get zero energy density (molaR's rule).
RCOND_MIN = 1e-5

#: Scalar fields, in the order of output tables.
CLASSIC_FIELDS = (
    "dne",
    "convex_dne",
    "concave_dne",
    "surface_area",
    "convex_area",
    "concave_area",
    "boundary_faces",
    "outlier_faces",
    "vertices",
    "faces",
    "outliers",
    "kappa",
    "boundary",
    "outlier_mode",
)


@dataclass(frozen=True)
class ClassicDNEResult:
    """Classic DNE and molaR's convex/concave split for one mesh.

    Per-face arrays follow the faces of the mesh as given (after dropping
    faces of zero area and unreferenced vertices, as molaR's cleaning does;
    neither reorders faces).

    Attributes
    ----------
    dne : float
        Classic DNE: ``sum(face_energy * rescaled face area)`` over the faces
        that are not excluded.  Invariant to uniform scale.
    convex_dne, concave_dne : float
        The same sum over the non-excluded convex (``face_kappa > kappa``)
        and concave (``face_kappa <= kappa``) faces; they add up to ``dne``.
    surface_area : float
        Total face area, mesh units.
    convex_area, concave_area : float
        Area of *all* convex and concave faces (excluded ones too), mesh units.
    boundary_faces, outlier_faces : int
        Faces excluded as boundary faces, and (of the rest) as outliers.
    vertices, faces : int
        Vertex and face counts of the mesh used.
    outliers, kappa, boundary, outlier_mode
        The settings used.
    face_energy : (m,) float
        Energy density ``trace(G^-1 H)`` of each face on molaR's rescaled mesh
        (units 1/length**2 of that mesh), before exclusions; zero where ``G``
        is ill conditioned.
    face_area : (m,) float
        Face area, mesh units.
    face_dne : (m,) float
        Each face's contribution to ``dne`` (energy density times rescaled
        area; scale-free); zero for excluded faces.
    face_kappa : (m,) float
        molaR's per-face curvature value on the rescaled mesh (1/length).
    excluded : (m,) bool
        True for faces whose energy is set to zero as boundary faces or outliers.
    mesh : trimesh.Trimesh
        The mesh the per-face arrays refer to, in mesh units (a private copy;
        its faces rewound outward if ``orient="auto"`` rewound them).
    orientation : Orientation
        How the faces are wound (and which way the crown points, which
        classic DNE does not depend on: it is never turned), and whether the
        faces were rewound before measuring (``orient="auto"``).
    """

    dne: float
    convex_dne: float
    concave_dne: float
    surface_area: float
    convex_area: float
    concave_area: float
    boundary_faces: int
    outlier_faces: int
    vertices: int
    faces: int
    outliers: float
    kappa: float
    boundary: str
    outlier_mode: str
    face_energy: np.ndarray = field(repr=False, compare=False)
    face_area: np.ndarray = field(repr=False, compare=False)
    face_dne: np.ndarray = field(repr=False, compare=False)
    face_kappa: np.ndarray = field(repr=False, compare=False)
    excluded: np.ndarray = field(repr=False, compare=False)
    mesh: trimesh.Trimesh = field(default=LazyMesh(), repr=False, compare=False)
    orientation: Orientation | None = field(default=None, compare=False)

    @property
    def convex(self) -> np.ndarray:
        """(m,) bool: faces molaR classifies as convex (``face_kappa > kappa``)."""
        return self.face_kappa > self.kappa

    def to_dict(self) -> dict:
        """The scalar fields as a plain dict (one row of a results table)."""
        return {name: getattr(self, name) for name in CLASSIC_FIELDS}

    def _repr_html_(self) -> str:
        """A compact table for notebooks: values, settings, arrays summarised."""
        return result_html(self, histogram="face_dne")


def _check_real(name: str, value, *, low: float, high: float) -> float:
    if isinstance(value, bool) or not isinstance(value, Real):
        raise TypeError(f"{name} must be a real number; got {type(value).__name__}")
    value = float(value)
    if not (np.isfinite(value) and low <= value <= high):
        raise ValueError(f"{name} must lie in [{low}, {high}]; got {value!r}")
    return value


def _check_measured(energy, at_boundary, excluded, boundary: str, outliers: float) -> None:
    """Raise a ValueError if the exclusions leave nothing to measure (DNE would be 0.0).

    Either every face is excluded, or every face with energy is: the outlier cut
    took them all (the boundary faces' zeros count among the densities it ranks).
    A surface whose faces have no energy (a flat plate) measures 0.0, rightly.
    """
    m = len(energy)
    if not excluded.all() and (energy[~excluded] > 0).any():
        return
    if not (energy[~at_boundary] > 0).any() and not excluded.all():
        return  # no energy anywhere the boundary rule leaves: DNE is 0.0
    border = int(np.count_nonzero(at_boundary))
    left = m - border
    what = f"{border} of its {m} faces are boundary faces ({boundary} rule)"
    if left == 0:
        raise ValueError(
            f"classic DNE has no face to measure: {what}, which it excludes; choose "
            "another boundary rule (dne_boundary), or measure a larger surface"
        )
    raise ValueError(
        f"classic DNE has no face to measure: {what}, and discarding the highest "
        f"{outliers:g}% of the energies as outliers discards the other {left} faces' energy; "
        "choose fewer outliers (dne_outliers)"
    )


def energy_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Vertex normals for the energy: normalised unweighted mean of unit face normals.

    A vertex used by exactly one face gets a zero normal, as in molaR; a
    degenerate face contributes a zero normal.
    """
    normals = np.empty_like(vertices)
    _kernels.unit_vertex_sums(vertices, faces, True, normals)
    uses = np.bincount(faces.ravel(), minlength=len(vertices))
    normals[uses == 1] = 0.0
    return normals


def area_weighted_normals(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Vertex normals for kappa: normalised area-weighted sum of face normals.

    This is what molaR's mesh reader (vcglib's normalised per-vertex normals)
    attaches to the mesh, and what molaR's convex/concave test uses.
    """
    normals = np.empty_like(vertices)
    _kernels.unit_vertex_sums(vertices, faces, False, normals)
    return normals


def face_energy_density(
    vertices: np.ndarray, faces: np.ndarray, normals: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Per-face Dirichlet energy density ``trace(G^-1 H)`` and area ``sqrt(det G)/2``.

    For a face with vertices 1, 2, 3: ``a = x2 - x1``, ``b = x3 - x1``,
    ``c = n2 - n1``, ``d = n3 - n1``, ``G = [[a.a, a.b], [a.b, b.b]]``,
    ``H = [[c.c, c.d], [c.d, d.d]]``; the density is
    ``(b.b c.c - 2 a.b c.d + a.a d.d) / det G``.  Zero density where the
    1-norm reciprocal condition number of ``G`` is below ``RCOND_MIN``: for a
    symmetric 2x2 matrix, ``||G||_1 = ||G^-1||_1 * |det G|``, so it is
    ``|det G| / ||G||_1**2`` exactly.
    """
    energy = np.empty(len(faces))
    area = np.empty(len(faces))
    _kernels.energy_density(vertices, faces, normals, RCOND_MIN, energy, area)
    return energy, area


def face_kappa(vertices: np.ndarray, faces: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """molaR's per-face curvature value, ``(k(2,1) + k(3,1) + k(1,2)) / 3``.

    ``k(j, k) = ((n_j - n_k) . (x_j - x_k)) / |x_j - x_k|**2``.  Edge 1-2 is
    counted twice and edge 2-3 not at all: that is molaR's formula.
    """
    values = np.empty(len(faces))
    _kernels.kappa(vertices, faces, normals, values)
    return values


def _boundary_faces(surface: Surface, mode: str) -> np.ndarray:
    faces = surface.faces
    if mode == "none":
        return np.zeros(len(faces), dtype=bool)
    alone = surface.edge_uses() == 1
    if not alone.any():
        return np.zeros(len(faces), dtype=bool)
    m = len(faces)
    if mode == "vertex":
        on_boundary = np.zeros(len(surface.vertices), dtype=bool)
        for k in range(3):  # edge k * m + f runs from faces[f, k] to faces[f, (k + 1) % 3]
            owner = alone[k * m : (k + 1) * m]
            on_boundary[faces[owner, k]] = True
            on_boundary[faces[owner, (k + 1) % 3]] = True
        return on_boundary[faces].any(axis=1)
    # "leg": faces that own a boundary edge (an edge used by one face belongs to that face)
    return alone.reshape(3, m).any(axis=0)


def classic_dne(
    mesh,
    *,
    outliers: float = 0.1,
    kappa: float = 0.0,
    boundary: str = "vertex",
    outlier_mode: str = "combined",
    orient: str = "auto",
) -> ClassicDNEResult:
    """Classic DNE (Bunn et al. 2011) with molaR 6.0's convex/concave split.

    The computation and all its conventions are molaR's (``DNE()`` with
    ``BoundaryDiscard``, ``outliers``, ``kappa`` and ``oex``):

    1. **Mesh.** Files are read with :func:`dentopo.mesh.load_mesh` (duplicate
       vertices merged, as molaR's reader does; a file holding several meshes
       raises: pass ``load_mesh(path, geometry=NAME)``); arrays and meshes are used as
       given, after molaR's cleaning (faces of zero area dropped, then
       vertices no face uses; a face listed twice is measured once unless the
       surface was prepared with ``duplicates="keep"``).  The faces' winding
       is checked (see `orient`); the crown is never turned (nothing here
       depends on which way it points).  The caller's mesh is never modified.
    2. **Size normalisation.** All coordinates are multiplied by
       ``100 / size``, where ``size`` is the root sum of squares, over all
       vertices, of each vertex's coordinates centred on the mean of its *own*
       x, y and z (molaR's per-vertex centring).  Totals do not depend on it;
       ``face_kappa`` and ``face_energy`` magnitudes do.
    3. **Energy normals.** Vertex normal = normalised *unweighted* mean of the
       unit normals of the faces using the vertex; a vertex used by exactly
       one face gets a zero normal.
    4. **Energy density.** For a face with vertices 1, 2, 3: ``a = x2 - x1``,
       ``b = x3 - x1``, ``c = n2 - n1``, ``d = n3 - n1``;
       ``G = [[a.a, a.b], [a.b, b.b]]``, ``H = [[c.c, c.d], [c.d, d.d]]``;
       density ``e = trace(G^-1 H)``, area ``sqrt(det G) / 2``.  If the
       reciprocal condition number of ``G`` in the 1-norm (computed exactly,
       ``|det G| / ||G||_1**2`` for a symmetric 2x2 matrix) is below 1e-5,
       ``e = 0``.
    5. **Boundary exclusion** (``boundary``): ``"vertex"`` zeroes the energy
       of every face touching a vertex on a boundary edge (an edge used by one
       face); ``"leg"`` only faces owning a boundary edge; ``"none"`` nothing.
       A closed mesh has no boundary faces (molaR errors there; we do not).
    6. **Outlier exclusion** (``outliers``, a percentage): ``Q`` is the
       ``(100 - outliers) / 100`` quantile of the densities of all faces
       (boundary zeros included), with R's default rule (type 7, linear
       interpolation, numpy's ``"linear"``); faces with ``e > Q`` get zero
       energy.  ``outlier_mode="separate"`` (molaR's ``oex = 's'``) takes the
       quantile within the convex faces and within the concave faces apart.
    7. **Convex or concave.** With the *area-weighted* vertex normals of
       molaR's reader (normalised sum of unnormalised face normals) on the
       rescaled coordinates, ``k(j, k) = ((n_j - n_k).(x_j - x_k)) /
       |x_j - x_k|**2`` and the face value is
       ``(k(2,1) + k(3,1) + k(1,2)) / 3`` (edge 1-2 twice, edge 2-3 never:
       molaR's formula).  Convex when ``> kappa``, concave when ``<= kappa``.
    8. **Totals.** DNE, convex DNE and concave DNE are sums of ``e * area``
       (rescaled area; the product is scale-free) over the faces left after
       both exclusions; convex and concave areas sum over *all* faces of each
       class, in mesh units.

    Parameters
    ----------
    mesh : trimesh.Trimesh, str, path-like, (vertices, faces), or Surface
        A triangle mesh, open or closed, or one prepared once for several
        metrics (:func:`dentopo.topography.prepare_surface`; measured as
        cleaned, never turned).  Never modified.
    outliers : float, default 0.1
        Percentage of the highest energy densities discarded, in [0, 50]: outliers are
        at most half the faces.  If the boundary rule and the outliers leave no face
        with energy to measure (on a surface that has some), a ValueError says so.
    kappa : float, default 0.0
        Threshold on the face curvature value between concave (``<=``) and
        convex (``>``), on molaR's rescaled mesh.
    boundary : {"vertex", "leg", "none"}, default "vertex"
        Which faces at the mesh boundary are excluded (molaR's ``BoundaryDiscard``).
    outlier_mode : {"combined", "separate"}, default "combined"
        One outlier quantile for all faces, or one per class (molaR's ``oex``).
    orient : {"auto", "as-is"}, default "auto"
        The convex/concave split assumes the faces are wound outward (with
        every face wound inward, the convex and concave parts swap; ``dne``
        does not change).  ``"as-is"`` measures the faces as wound (molaR's
        behaviour) and warns if they are wound inward; ``"auto"`` (the default) rewinds
        such faces first (see :func:`dentopo.topography.find_orientation`).
        The result's ``orientation`` says what was found and done.

    Returns
    -------
    ClassicDNEResult
        Totals, the convex/concave split, and per-face arrays.

    Raises
    ------
    TypeError, ValueError
        For unusable meshes or options; the message names the problem.

    Warns
    -----
    UserWarning
        When faces are wound inward (rewound with ``orient="auto"``).

    References
    ----------
    Bunn J. M., Boyer D. M., Lipman Y., St. Clair E. M., Jernvall J.,
    Daubechies I. (2011). Comparing Dirichlet normal surface energy of tooth
    crowns, a new technique of molar shape quantification for dietary
    inference. American Journal of Physical Anthropology 145(2), 247-261.
    doi:10.1002/ajpa.21489

    Pampush J. D., Winchester J. M., Morse P. E., Vining A. Q., Boyer D. M.,
    Kay R. F. (2016). Introducing molaR: a new R package for quantitative
    topographic analysis of teeth (and other topographic surfaces). Journal of
    Mammalian Evolution 23, 397-412. doi:10.1007/s10914-016-9326-0

    Examples
    --------
    >>> import trimesh
    >>> from dentopo import classic_dne
    >>> result = classic_dne(trimesh.creation.icosphere(subdivisions=3))
    >>> result.concave_dne, result.boundary_faces
    (0.0, 0)
    >>> round(result.dne, 1)  # 8 pi = 25.13 for a sphere, less the top 0.1 % of faces
    25.0
    """
    outliers = check_outliers("outliers", outliers)
    kappa = _check_real("kappa", kappa, low=-np.inf, high=np.inf)
    boundary = check_choice("boundary", boundary, BOUNDARY_MODES)
    outlier_mode = check_choice("outlier_mode", outlier_mode, OUTLIER_MODES)
    orient = check_orient(orient)

    # a Surface given: its cleaned form; rewound if asked, never turned
    surface = prepare_surface(mesh).wound(orient)
    surface.warn_orientation(winding_only=True)
    vertices, faces = surface.vertices, surface.faces

    scaled = vertices * molar_scale(vertices)
    energy, area_scaled = face_energy_density(scaled, faces, energy_normals(scaled, faces))
    values = face_kappa(scaled, faces, area_weighted_normals(scaled, faces))
    convex = values > kappa

    at_boundary = _boundary_faces(surface, boundary)
    kept = np.where(at_boundary, 0.0, energy)
    level = (100.0 - outliers) / 100.0
    outlier = np.zeros(len(faces), dtype=bool)
    groups = (convex, ~convex) if outlier_mode == "separate" else (np.ones_like(convex),)
    for group in groups:
        if group.any():
            q = np.quantile(kept[group], level)  # numpy "linear" == R type 7
            outlier |= group & (kept > q)
    excluded = at_boundary | outlier
    _check_measured(energy, at_boundary, excluded, boundary, outliers)
    face_dne = np.where(excluded, 0.0, energy * area_scaled)

    face_area = surface.area.copy()  # the result's own
    return ClassicDNEResult(
        dne=float(face_dne.sum()),
        convex_dne=float(face_dne[convex].sum()),
        concave_dne=float(face_dne[~convex].sum()),
        surface_area=float(face_area.sum()),
        convex_area=float(face_area[convex].sum()),
        concave_area=float(face_area[~convex].sum()),
        boundary_faces=int(at_boundary.sum()),
        outlier_faces=int((outlier & ~at_boundary).sum()),
        vertices=len(vertices),
        faces=len(faces),
        outliers=outliers,
        kappa=kappa,
        boundary=boundary,
        outlier_mode=outlier_mode,
        face_energy=energy,
        face_area=face_area,
        face_dne=face_dne,
        face_kappa=values,
        excluded=excluded,
        mesh=surface.mesh_later(),
        orientation=surface.orientation,
    )
