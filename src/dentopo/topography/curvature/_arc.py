"""Area-relative curvature (ARC), as molaR 6.0's ``ARC`` and doolkit 1.42.2's ``arc`` compute it.

Both take, per face, the discrete mean curvature of the VCG library (Meyer et
al.'s cotangent Laplacian over the mixed Voronoi area, in single precision:
:mod:`._vcg`) at the face's vertex of largest magnitude, divide it by
``2.4481 / sqrt(A)`` (their "hemisphere" constant; a hemisphere of area A
actually has ``1/r = 2.5066 / sqrt(A)``, but the constant is reproduced as it
is), zero the faces at the border and cut the 1 % tails.  They differ in the
order of those steps and in the cut: molaR sets the tail faces to 0, doolkit
clamps them to the quantiles; molaR rescales the mesh to its centroid size
100 first, doolkit measures the mesh as read.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from numbers import Real

import numpy as np
import trimesh

from ..._html_repr import result_html
from .. import _units
from .._lazy import LazyMesh
from ..surface import _vcg
from ..surface._molar import molar_face_areas, molar_scale, prepare_surface

#: Scalar fields of molaR's ARC, in the order of output tables.
ARC_FIELDS = ("arc", "arc_positive", "arc_negative")

#: Scalar fields of doolkit's arc, in the order of output tables.
DOOLKIT_ARC_FIELDS = ("arc_mean", "arc_pos_mean", "arc_neg_mean")

#: molaR's and doolkit's normalising constant: ARC = H / (HEMISPHERE / sqrt(area)).
HEMISPHERE = 2.4481

#: molaR's ``BoundaryDiscard`` choices, lower case.
ARC_BOUNDARY = _vcg.BORDER_RULES


@dataclass(frozen=True)
class ARCResult:
    """molaR's area-relative curvature for one mesh.

    Per-face arrays follow the faces of the cleaned mesh (faces of zero area
    dropped, then unused vertices; neither reorders faces).

    Attributes
    ----------
    arc : float
        Mean of ``face_arc`` over all faces (the zeroed ones included).
    arc_positive : float
        Mean of the values ``>= 0`` (zeroed faces count here); NaN if none.
    arc_negative : float
        Mean of the values ``< 0``; NaN if none.
    vertices, faces : int
        Vertex and face counts of the cleaned mesh.
    boundary : str
        Which border faces were zeroed (``"vertex"``, ``"leg"`` or ``"none"``).
    range : tuple of float
        The quantile probabilities of the cut.
    boundary_faces : int
        Faces zeroed at the border.
    cut_faces : int
        Faces (of the others) zeroed for lying below the lower or above the upper quantile.
    face_arc : (m,) float64
        Each face's final value (after zeroing): its curvature divided by
        ``2.4481 / sqrt(A)`` on the rescaled mesh.
    mesh : trimesh.Trimesh
        The cleaned mesh the per-face arrays refer to, in its own units (a copy).
    """

    arc: float
    arc_positive: float
    arc_negative: float
    vertices: int
    faces: int
    boundary: str
    range: tuple
    boundary_faces: int
    cut_faces: int
    face_arc: np.ndarray = field(repr=False, compare=False)
    mesh: trimesh.Trimesh = field(default=LazyMesh(), repr=False, compare=False)

    def to_dict(self) -> dict:
        """The scalar table fields as a plain dict (``ARC_FIELDS``)."""
        return {name: getattr(self, name) for name in ARC_FIELDS}

    def _repr_html_(self) -> str:
        """A compact table for notebooks: values, settings, arrays summarised."""
        return result_html(self, histogram="face_arc")


@dataclass(frozen=True)
class DoolkitARCResult:
    """doolkit's area-relative curvature (``arc``) for one mesh.

    Attributes
    ----------
    arc_mean : float
        Mean of ``face_arc`` over all faces (border zeros included).
    arc_pos_mean : float
        Mean of the values ``>= 0`` (the border zeros count here); NaN if none.
    arc_neg_mean : float
        Mean of the values ``< 0``; NaN if none.
    vertices, faces : int
        Vertex and face counts of the mesh used.
    range : tuple of float
        As given: quantile probabilities, or absolute limits (see :func:`doolkit_arc`).
    border_faces : int
        Faces with a vertex on the border (zeroed).
    clipped_faces : int
        Faces whose value was clamped to a limit.
    face_arc : (m,) float64
        Each face's final value, in doolkit's ARC units.
    mesh : trimesh.Trimesh
        The mesh the per-face arrays refer to (a copy).
    """

    arc_mean: float
    arc_pos_mean: float
    arc_neg_mean: float
    vertices: int
    faces: int
    range: tuple
    border_faces: int
    clipped_faces: int
    face_arc: np.ndarray = field(repr=False, compare=False)
    mesh: trimesh.Trimesh = field(default=LazyMesh(), repr=False, compare=False)

    def to_dict(self) -> dict:
        """The scalar table fields as a plain dict (``DOOLKIT_ARC_FIELDS``)."""
        return {name: getattr(self, name) for name in DOOLKIT_ARC_FIELDS}

    def _repr_html_(self) -> str:
        """A compact table for notebooks: values, settings, arrays summarised."""
        return result_html(self, histogram="face_arc")


def check_range(value, *, probabilities: bool) -> tuple[float, float]:
    """ARC's ``range``: two finite real numbers, lower < upper (in [0, 1] if `probabilities`)."""
    if isinstance(value, (str, bytes)) or not hasattr(value, "__len__"):
        raise TypeError(f"range must be two numbers (lower, upper); got {type(value).__name__}")
    if len(value) != 2:
        raise ValueError(f"range must be two numbers (lower, upper); got {len(value)}")
    ends = []
    for end in value:
        if isinstance(end, (bool, np.bool_)) or not isinstance(end, Real):
            raise TypeError(f"range must hold real numbers; got {type(end).__name__}")
        end = float(end)
        if not math.isfinite(end):
            raise ValueError(f"range must hold finite numbers; got {end!r}")
        ends.append(end)
    lower, upper = ends
    if not lower < upper:
        raise ValueError(f"range must be (lower, upper) with lower < upper; got {tuple(ends)}")
    if probabilities and not (0.0 <= lower and upper <= 1.0):
        raise ValueError(f"range must hold quantile probabilities in [0, 1]; got {tuple(ends)}")
    return lower, upper


def _check_boundary(boundary) -> str:
    if not isinstance(boundary, str):
        raise TypeError(f"boundary must be a string; got {type(boundary).__name__}")
    rule = boundary.lower()
    if rule not in ARC_BOUNDARY:
        raise ValueError(f"boundary must be one of {ARC_BOUNDARY}; got {boundary!r}")
    return rule


def _face_curvature(vertices32: np.ndarray, faces: np.ndarray, normals32=None) -> np.ndarray:
    return _counted_face_curvature(vertices32, faces, normals32)[0]


def _counted_face_curvature(vertices32: np.ndarray, faces: np.ndarray, normals32=None):
    """Each face's curvature, and how many vertices got 0 for an area below float32's epsilon."""
    if normals32 is None:
        normals32 = _vcg.vertex_normals(vertices32, faces)
    values, small = _vcg.mean_curvature(vertices32, faces, normals32, counted=True)
    return _vcg.face_max(values, faces).astype(np.float64), small


#: doolkit's ARC is refused when at least this fraction of the vertices is below the epsilon.
MEANINGLESS = 0.5


def _check_small_areas(small: int, vertices: int, surface) -> None:
    """doolkit's ARC where vertices lost their curvature to float32's epsilon: said, or refused.

    The VCG curvature is 0 at a vertex whose mixed area is at most float32's
    epsilon (about 1.2e-7 square units): nothing at ordinary scales in
    millimetres, every vertex of a crown a few millimetres long in metres.
    """
    if small == 0:
        return
    share = small / vertices
    size = float(np.ptp(surface.vertices, axis=0).max())
    what = (
        f"{small} of {vertices} vertices ({share:.1%}) have a mixed area at most float32's "
        f"epsilon ({_vcg.EPS32:.2g} square units), where doolkit's curvature is 0 (the crown "
        f"is {size:.3g} units across)"
    )
    if share >= MEANINGLESS:
        raise ValueError(f"doolkit's ARC is meaningless at this scale: {what}; {_units.FIX}")
    if share > _units.MATERIAL:
        _units.warn("doolkit_arc", what, stacklevel=4)


def _means(values: np.ndarray) -> tuple[float, float, float]:
    positive = values >= 0
    negative = ~positive
    pos = float(values[positive].mean()) if positive.any() else math.nan
    neg = float(values[negative].mean()) if negative.any() else math.nan
    return float(values.mean()), pos, neg


def arc(mesh, *, boundary: str = "vertex", range=(0.01, 0.99)) -> ARCResult:
    """Area-relative curvature, as molaR 6.0's ``ARC`` computes it.

    1. **Mesh.** Read and cleaned as for every molaR metric (faces of zero
       area dropped, then unused vertices), then scaled about the origin by
       ``100 / size`` (molaR's centroid size, with its quirk:
       :func:`dentopo.topography.molar_scale`) and rounded to float32.
    2. **Per face.** The VCG library's discrete mean curvature of each vertex
       (Meyer et al.'s cotangent Laplacian over the mixed Voronoi area, sign
       + where it points along the vertex normal, in single precision:
       float32 vertex normals recomputed on the scaled mesh); each face takes
       the value of its vertex of largest magnitude.
    3. **Normalised** by dividing by ``2.4481 / sqrt(A)``, ``A`` the total
       area of the scaled mesh (float32 per face, summed in double).
    4. **Border** faces set to 0: ``"vertex"`` every face with a vertex on a
       border edge (an edge only one face uses), ``"leg"`` faces owning a
       border edge, ``"none"`` none.
    5. **Tails.** The type-7 quantiles at ``range`` of all faces (the zeros
       included) are taken once; faces strictly below the lower or above the
       upper one are set to **0**.
    6. ``arc`` is the mean over all faces; ``arc_positive`` the mean of the
       values ``>= 0`` (zeroed faces included), ``arc_negative`` of those ``< 0``.

    Because of the rescaling the result does not depend on uniform scale;
    it does not depend on translation (up to float32 rounding of the
    coordinates) or on vertex and face order.  Turning the crown over (a
    rotation) does not change it; reversing the faces' winding flips the sign.

    Parameters
    ----------
    mesh : trimesh.Trimesh, str, path-like, (vertices, faces), or Surface
        Never modified.
    boundary : {"vertex", "leg", "none"}, default "vertex"
        molaR's ``BoundaryDiscard`` (case-insensitive).
    range : (float, float), default (0.01, 0.99)
        Quantile probabilities of the cut, ``0 <= lower < upper <= 1``.

    Returns
    -------
    ARCResult

    Raises
    ------
    TypeError, ValueError
        For an unusable mesh or parameter; the message names the problem.

    References
    ----------
    Guy F., Gouvard F., Boistel R., Euriat A., Lazzari V. (2013). Prospective
    in (primate) dental analysis through tooth 3D topographical
    quantification. PLoS ONE 8, e66142. doi:10.1371/journal.pone.0066142

    Meyer M., Desbrun M., Schroeder P., Barr A. H. (2003). Discrete
    differential-geometry operators for triangulated 2-manifolds. In
    Visualization and Mathematics III, 35-57.

    Examples
    --------
    >>> import trimesh
    >>> from dentopo.topography import arc
    >>> result = arc(trimesh.creation.icosphere(subdivisions=4))
    >>> round(result.arc, 2)  # sqrt(4 pi) / 2.4481 = 1.45, less the 2 % of faces zeroed
    1.43
    """
    rule = _check_boundary(boundary)
    lower, upper = check_range(range, probabilities=True)
    surface = prepare_surface(mesh)
    faces = surface.faces
    scaled32 = _vcg.to_float32(surface.vertices * molar_scale(surface.vertices))
    total = float(molar_face_areas(scaled32, faces).sum())
    values = _face_curvature(scaled32, faces) / (HEMISPHERE / math.sqrt(total))
    at_border = _vcg.border_faces(surface, rule)
    values[at_border] = 0.0
    low, high = _vcg.quantiles7(values, (lower, upper))
    cut = (values < low) | (values > high)
    values[cut] = 0.0
    mean, pos, neg = _means(values)
    return ARCResult(
        arc=mean,
        arc_positive=pos,
        arc_negative=neg,
        vertices=len(surface.vertices),
        faces=len(faces),
        boundary=rule,
        range=(lower, upper),
        boundary_faces=int(at_border.sum()),
        cut_faces=int((cut & ~at_border).sum()),
        face_arc=values,
        mesh=surface.mesh_later(),
    )


def doolkit_arc(mesh, *, range=(0.01, 0.99)) -> DoolkitARCResult:
    """Area-relative curvature, as doolkit 1.42.2's ``arc`` computes it.

    1. **Mesh** as read (doolkit does not rescale): coordinates in float32,
       vertex normals recomputed in float32 (:func:`._vcg.vertex_normals`).
       Faces of zero area and unused vertices are dropped first (the shared
       reader; Rvcg's import has nothing to drop on ordinary meshes).
    2. **Per face** the VCG discrete mean curvature at the face's vertex of
       largest magnitude, as for :func:`arc`.
    3. **Border** faces (a vertex on a border edge: ``dkborder``) set to 0.
    4. **Clamp**: when both ends of `range` are in [0, 1], values are
       clamped (not zeroed) to the type-7 quantiles at `range` of all faces,
       border zeros included.
    5. **Normalised** by dividing by ``2.4481 / sqrt(A3)``, ``A3`` the total
       area (float32 per face, summed in double: ``vcgArea``).  When either
       end of `range` lies outside [0, 1], step 4 is skipped and the values
       are clamped here, after the division, to ``range`` as absolute limits.
    6. Means as for :func:`arc`: ``arc_pos_mean`` counts the border zeros.

    The result does not depend on translation (up to float32 rounding) or on
    vertex and face order; it is scale dependent only through float32
    (curvature times ``sqrt(A3)`` is scale free), above all its epsilon:
    a vertex whose mixed area is at most 1.2e-7 square units gets curvature
    0, which is nothing in millimetres (doolkit's unit) and every vertex of
    a crown measured in metres.  More than 0.5 % of the vertices below it is
    warned about (:class:`dentopo.topography.UnitWarning`); half or more is
    an error.

    Parameters
    ----------
    mesh : trimesh.Trimesh, str, path-like, (vertices, faces), or Surface
        Never modified.
    range : (float, float), default (0.01, 0.99)
        Quantile probabilities (both in [0, 1]) or absolute limits; lower < upper.

    Returns
    -------
    DoolkitARCResult

    Raises
    ------
    TypeError, ValueError
        For an unusable mesh or `range`; ValueError when half or more of the
        vertices have a mixed area below float32's epsilon (a crown too small
        in its unit: measure it in millimetres).

    Warns
    -----
    UnitWarning
        When more than 0.5 % of the vertices do.

    References
    ----------
    Thiery G., Guy F., Lazzari V. (2019-). doolkit: a toolkit for dental
    topography (R package), version 1.42.2.

    Examples
    --------
    >>> import trimesh
    >>> from dentopo.topography import doolkit_arc
    >>> result = doolkit_arc(trimesh.creation.icosphere(subdivisions=4, radius=3.0))
    >>> round(result.arc_mean, 2)  # 1/r times sqrt(4 pi r^2) / 2.4481, for any r
    1.45
    """
    lower, upper = check_range(range, probabilities=False)
    quantiles = 0.0 <= lower and upper <= 1.0
    surface = prepare_surface(mesh)
    faces = surface.faces
    v32, normals32 = _vcg.surface_normals32(surface)
    values, small = _counted_face_curvature(v32, faces, normals32)
    _check_small_areas(small, len(v32), surface)
    at_border = _vcg.border_faces(surface, "vertex")
    values[at_border] = 0.0
    if quantiles:
        low, high = _vcg.quantiles7(values, (lower, upper))
        clipped = (values < low) | (values > high)
        values = np.clip(values, low, high)
    total = float(surface.single_precision_areas().sum())
    values = values / (HEMISPHERE / math.sqrt(total))
    if not quantiles:
        clipped = (values < lower) | (values > upper)
        values = np.clip(values, lower, upper)
    mean, pos, neg = _means(values)
    return DoolkitARCResult(
        arc_mean=mean,
        arc_pos_mean=pos,
        arc_neg_mean=neg,
        vertices=len(surface.vertices),
        faces=len(faces),
        range=(lower, upper),
        border_faces=int(at_border.sum()),
        clipped_faces=int(clipped.sum()),
        face_arc=values,
        mesh=surface.mesh_later(),
    )
