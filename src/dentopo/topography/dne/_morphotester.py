"""Dirichlet normal energy as MorphoTester 1.1.1 computes it.

MorphoTester (Winchester 2016; GPL-2) is reproduced from a description of its method
(``docs/MORPHOTESTER.md`` of the shared data), never from its code.  It reproduces every
digit of MorphoTester's published sample results and the values of its unit tests.  The
normals, boundary faces and fairing it shares with MorphoTester's RFI and OPCR are in
:mod:`..surface._morphotester`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..._html_repr import result_html
from ...mesh import as_arrays
from .._parameters import check_morphotester_dne_options
from ..surface import _morphotester as mt

#: MorphoTester's condition-number limit: a face whose first fundamental form has a 2-norm
#: condition number above it gets zero energy.
CONDITION_MAX = 1e5

#: MorphoTester's "implicit fair smooth": iterations and step.
SMOOTH_ITERATIONS = 3
SMOOTH_STEP = 0.1

#: Scalar fields (:meth:`MorphoTesterDNEResult.to_dict`), in the order of output tables.
MORPHOTESTER_DNE_FIELDS = (
    "dne",
    "n_faces",
    "n_outliers",
    "n_ill_conditioned",
    "n_boundary",
    "condition_check",
    "outliers",
    "percentile",
    "smooth",
)


@dataclass(frozen=True)
class MorphoTesterDNEResult:
    """MorphoTester 1.1.1's DNE for one mesh.

    Per-face arrays (read-only) follow the faces as given: MorphoTester drops or merges
    nothing.

    Attributes
    ----------
    dne : float
        The sum of ``face_quantity``, rounded to 3 decimals as MorphoTester rounds
        (Python 2: ties away from zero).
    dne_unrounded : float
        The same sum, unrounded.
    n_faces : int
    condition_check : bool
    outliers : {"energy", "energy_area"} or None
    percentile : float
    smooth : bool
        The settings used (see :func:`morphotester_dne`).
    threshold : float
        The percentile of the ranked values above which a face is an outlier (nan when
        ``outliers`` is None).
    face_energy : (m,) float
        Energy density ``e`` of each face after the zeroing rules (duplicate corners,
        condition check, boundary faces).
    face_density : (m,) float
        ``e`` before the boundary rule (MorphoTester's unit tests quote it).
    face_area : (m,) float
        The area MorphoTester records: ``sqrt(det G) / 2``, or 1 for a face zeroed by the
        duplicate-corner or condition rule (its energy is 0, so it never counts).
    face_quantity : (m,) float
        ``q = e * A`` after outlier removal; ``dne`` is their sum.
    boundary, ill_conditioned, duplicate, outlier : (m,) bool
        Boundary faces ("leg" rule), faces zeroed by the condition check, faces with two
        coincident corners, and faces removed as outliers.
    """

    dne: float
    dne_unrounded: float
    n_faces: int
    condition_check: bool
    outliers: str | None
    percentile: float
    smooth: bool
    threshold: float
    face_energy: np.ndarray = field(repr=False, compare=False)
    face_density: np.ndarray = field(repr=False, compare=False)
    face_area: np.ndarray = field(repr=False, compare=False)
    face_quantity: np.ndarray = field(repr=False, compare=False)
    boundary: np.ndarray = field(repr=False, compare=False)
    ill_conditioned: np.ndarray = field(repr=False, compare=False)
    duplicate: np.ndarray = field(repr=False, compare=False)
    outlier: np.ndarray = field(repr=False, compare=False)

    def __post_init__(self):
        for name in (
            "face_energy",
            "face_density",
            "face_area",
            "face_quantity",
            "boundary",
            "ill_conditioned",
            "duplicate",
            "outlier",
        ):
            getattr(self, name).flags.writeable = False

    @property
    def n_outliers(self) -> int:
        """Faces removed as outliers."""
        return int(np.count_nonzero(self.outlier))

    @property
    def n_ill_conditioned(self) -> int:
        """Faces zeroed by the condition check."""
        return int(np.count_nonzero(self.ill_conditioned))

    @property
    def n_boundary(self) -> int:
        """Boundary faces."""
        return int(np.count_nonzero(self.boundary))

    def to_dict(self) -> dict:
        """The scalar fields (:data:`MORPHOTESTER_DNE_FIELDS`) as a plain dict."""
        return {name: getattr(self, name) for name in MORPHOTESTER_DNE_FIELDS}

    def _repr_html_(self) -> str:
        """A compact table for notebooks: values, settings, arrays summarised."""
        return result_html(self, histogram="face_quantity")


def percentile_linear(values: np.ndarray, percentile: float) -> float:
    """The `percentile` of `values` with linear interpolation (numpy's default rule).

    Sorted ascending (a NaN sorts last), position ``percentile / 100 * (n - 1)``,
    interpolated between the two neighbouring values.
    """
    ordered = np.sort(values)
    position = percentile / 100.0 * (len(ordered) - 1)
    low = int(np.floor(position))
    high = min(low + 1, len(ordered) - 1)
    fraction = position - low
    a, b = ordered[low], ordered[high]
    if fraction == 0.0:
        return float(a)
    return float(a + (b - a) * fraction)


def face_energy(
    vertices: np.ndarray, faces: np.ndarray, normals: np.ndarray, *, condition_check: bool
):
    """MorphoTester's per-face energy density ``e`` and area ``A``, and the zeroed faces.

    Returns ``(e, A, duplicate, ill_conditioned)``: faces with two coincident corners,
    and (condition check on) faces whose ``G`` has a 2-norm condition number above
    :data:`CONDITION_MAX`, get ``e = 0`` and ``A = 1``.

    Raises
    ------
    ValueError
        With the condition check off, for a face (without coincident corners) whose ``G``
        is singular (``det G <= 0`` as computed: collinear corners): MorphoTester aborts
        there with an error.
    """
    p0, p1, p2 = vertices[faces[:, 0]], vertices[faces[:, 1]], vertices[faces[:, 2]]
    duplicate = (p0 == p1).all(axis=1) | (p1 == p2).all(axis=1) | (p0 == p2).all(axis=1)
    b1, b2 = p1 - p0, p2 - p0
    g11 = np.einsum("ij,ij->i", b1, b1)
    g12 = np.einsum("ij,ij->i", b1, b2)
    g21 = np.einsum("ij,ij->i", b2, b1)
    g22 = np.einsum("ij,ij->i", b2, b2)
    det = g11 * g22 - g12 * g21
    ill = np.zeros(len(faces), dtype=bool)
    if condition_check:
        check = np.flatnonzero(~duplicate)
        gram = np.stack([np.stack([g11, g12], -1), np.stack([g21, g22], -1)], -2)[check]
        with np.errstate(divide="ignore", invalid="ignore"):
            cond = np.linalg.cond(gram)
        ill[check] = ~(cond <= CONDITION_MAX)
    else:
        singular = np.flatnonzero(~duplicate & ~(det > 0))
        if len(singular):
            raise ValueError(
                f"DNE without the condition check: face {singular[0]}'s first fundamental "
                f"form is singular (collinear corners; {len(singular)} such faces); "
                "MorphoTester aborts here with an error; turn the condition check on"
            )
    zero = duplicate | ill
    n0, n1, n2 = normals[faces[:, 0]], normals[faces[:, 1]], normals[faces[:, 2]]
    c1, c2 = n1 - n0, n2 - n0
    f11 = np.einsum("ij,ij->i", c1, c1)
    f12 = np.einsum("ij,ij->i", c1, c2)
    f21 = np.einsum("ij,ij->i", c2, c1)
    f22 = np.einsum("ij,ij->i", c2, c2)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        # trace(G^-1 F) with the explicit inverse [[g22, -g12], [-g21, g11]] / det
        i11, i12, i21, i22 = g22 / det, -g12 / det, -g21 / det, g11 / det
        energy = i11 * f11 + i12 * f21 + i21 * f12 + i22 * f22
        area = 0.5 * np.sqrt(det)
    energy[zero] = 0.0
    area[zero] = 1.0
    return energy, area, duplicate, ill


def dne_quantities(
    density: np.ndarray,
    area: np.ndarray,
    boundary: np.ndarray,
    outliers: str | None,
    percentile: float,
):
    """Steps 5 to 7: boundary zeros, ``q = e A``, outlier removal.

    Returns ``(energy, quantity, outlier, threshold)``: ``e`` with the boundary faces
    zeroed, ``q`` after outlier removal, the outlier faces (ranked value above the
    `percentile` of all faces' values, or NaN) and the percentile (nan without outliers).
    """
    energy = np.where(boundary, 0.0, density)
    with np.errstate(invalid="ignore", over="ignore"):
        quantity = energy * area
    outlier = np.zeros(len(energy), dtype=bool)
    threshold = float("nan")
    if outliers is not None:
        ranked = energy if outliers == "energy" else quantity
        threshold = percentile_linear(ranked, percentile)
        with np.errstate(invalid="ignore"):
            outlier = (ranked > threshold) | np.isnan(ranked)
        quantity = np.where(outlier, 0.0, quantity)
    return energy, quantity, outlier, threshold


def morphotester_dne(
    mesh,
    *,
    condition_check: bool = True,
    outliers: str | None = "energy",
    percentile: float = 99.9,
    smooth: bool = False,
) -> MorphoTesterDNEResult:
    """Dirichlet normal energy as MorphoTester 1.1.1 computes it.

    1. **Mesh**: as given, no cleaning of any kind (no vertex merged, no face dropped).
       Read a PLY file with ``read_ply(path, exact_text=True)`` to parse ASCII
       coordinates as MorphoTester does (float64 from the text): the third decimal
       depends on it.
    2. **Smoothing** (``smooth=True``, MorphoTester's "implicit fair smooth"): 3
       solves of ``(I - 0.1 L) X_new = X``, ``L`` its cotangent operator built once from
       the input vertices (cotangents from the arccos of each angle, as it computes
       them), nothing pinned.  MorphoTester factorises ``I - 0.1 L`` by Cholesky; where
       that matrix is not positive definite it prints a Cholesky error and reports no
       DNE: this raises a ``ValueError`` naming the cause (nearly degenerate faces).
       Only DNE uses the smoothed vertices.
    3. **Normals**: unit face normals, vertex normals the unweighted sum of the unit
       normals of the faces using the vertex, normalised (vectors shorter than machine
       epsilon left as they are).
    4. **Energy** per face: ``G`` and ``F`` of the edges and normal differences from the
       first corner; ``e = trace(G^-1 F)``, ``A = sqrt(det G) / 2``.  A face with two
       coincident corners, and (``condition_check``) a face whose ``G`` has a 2-norm
       condition number above 1e5, gets ``e = 0`` (and a recorded area of 1).
    5. **Boundary**: ``e = 0`` on faces owning an edge that one face contains ("leg").
    6. **Outliers** (``outliers``): the `percentile` (linear interpolation) of ``e``
       (``"energy"``) or of ``q = e A`` (``"energy_area"``) over all faces, zeros
       included; faces above it get ``q = 0``.
    7. ``dne`` = the sum of ``q``, rounded to 3 decimals (Python 2's rounding).

    The defaults are those of MorphoTester's published sample results (outlier type
    Energy, 99.9); its GUI's default outlier type is Energy x area
    (``outliers="energy_area"``).

    Parameters
    ----------
    mesh : trimesh.Trimesh, str, path-like, or (vertices, faces)
        Never modified.
    condition_check : bool, default True
        MorphoTester's condition-number check.  Off, a face with collinear corners is an
        error (MorphoTester aborts).
    outliers : {"energy", "energy_area"} or None, default "energy"
        What the outlier percentile ranks; None: no outlier removal.
    percentile : float, default 99.9
        In (0, 100].
    smooth : bool, default False
        MorphoTester's implicit fair smoothing before DNE.

    Raises
    ------
    ValueError
        For a bad option, a mesh without faces or with non-finite coordinates, a
        smoothing system that is not positive definite, a singular face with the
        condition check off, every face a boundary face (nothing to measure), or a
        non-finite DNE (naming the faces).
    """
    condition_check, outliers, percentile, smooth = check_morphotester_dne_options(
        condition_check, outliers, percentile, smooth
    )
    vertices, faces = as_arrays(mesh)
    mt.check_mesh(vertices, faces, "MorphoTester's DNE")
    if smooth:
        vertices = mt.implicit_fairing(
            vertices, faces, iterations=SMOOTH_ITERATIONS, step=SMOOTH_STEP, cotangents="arccos"
        )
    _, normals, _ = mt.normals(vertices, faces, vote=False)  # DNE is blind to the vote
    density, area, duplicate, ill = face_energy(
        vertices, faces, normals, condition_check=condition_check
    )
    boundary = mt.boundary_faces(faces)
    if boundary.all():
        raise ValueError(
            f"MorphoTester's DNE has no face to measure: all {len(faces)} faces are boundary "
            "faces (each owns an edge no other face contains), and their energy is zeroed"
        )
    energy, quantity, outlier, threshold = dne_quantities(
        density, area, boundary, outliers, percentile
    )
    with np.errstate(invalid="ignore", over="ignore"):
        total = float(np.sum(quantity))
    if not np.isfinite(total):
        bad = np.flatnonzero(~np.isfinite(quantity))
        raise ValueError(
            f"MorphoTester's DNE is not finite: {len(bad)} faces have a non-finite energy "
            f"(face {bad[0]} first: nearly collinear corners); turn the condition check or "
            "the outlier removal on"
        )
    return MorphoTesterDNEResult(
        dne=mt.py2_round(total, 3),
        dne_unrounded=total,
        n_faces=len(faces),
        condition_check=condition_check,
        outliers=outliers,
        percentile=percentile,
        smooth=smooth,
        threshold=threshold,
        face_energy=energy,
        face_density=density,
        face_area=area,
        face_quantity=quantity,
        boundary=boundary,
        ill_conditioned=ill,
        duplicate=duplicate,
        outlier=outlier,
    )
