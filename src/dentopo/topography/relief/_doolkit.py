"""Elevation, relief indices, relief rate, shape index and hypsodonty as doolkit 1.42.2 has them.

Every quantity here follows doolkit's definitions and its precision: face
areas and barycentres come from Rvcg (vcglib) in single precision, the rest
is double precision, and four values are rounded to 2 decimals with R's
``round`` (:func:`r_round`).  The mesh is read as doolkit reads it (see
:mod:`dentopo.topography.slope._doolkit`).

Elevation, the Guy relief index and the relief rate depend on which way the
crown points (doolkit assumes +z and never checks); shape index and
hypsodonty use extents only, which turning the crown upside down (180
degrees about x) does not change.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import trimesh

from ..._html_repr import result_html
from .. import _units
from .._lazy import LazyMesh
from ..footprint._doolkit import check_hull, footprint_result, rounding_text
from ..slope._doolkit import DoolkitMesh, doolkit_mesh
from ..surface._orientation import TURN, Orientation, check_orient

#: Scalar fields, in the order of output tables.
RELIEF_INDEX_FIELDS = ("rfi_ungar", "rfi_boyer", "rfi_guy", "area3d", "area2d")
SHAPE_INDEX_FIELDS = ("shape_formfactor", "shape_elongation", "shape_k")
HYPSODONTY_FIELDS = ("hypso_hypsodonty", "hypso_height", "hypso_length", "hypso_width")


def r_round(x: float, digits: int = 2) -> float:
    """R's ``round(x, digits)`` (R 4.0.0 and later) for ``digits >= 1``.

    R rounds to the nearer of the two candidates ``xd = floor(x * 10^d) / 10^d``
    and ``xu = ceiling(x * 10^d) / 10^d``, each computed in double precision,
    comparing ``(xu - x) - (x - xd)`` in double precision; on an exact tie the
    candidate whose last digit is even.  Python's ``round(x, 2)`` rounds the
    exact binary value of `x` instead.  They agree on exact halves (0.125
    gives 0.12, 0.375 gives 0.38) and differ where the double nearest a
    decimal half is as far from both candidates in double arithmetic: 0.155
    (stored below 0.155) gives 0.16 in R, 0.15 in Python; 0.065 gives 0.06
    in R, 0.07 in Python.  Negative values are
    rounded as their absolute value, the sign restored; NaN and infinities
    are returned as they are.
    """
    x = float(x)
    if not math.isfinite(x):
        return x
    if x < 0:
        return -r_round(-x, digits)
    scale = 10.0**digits
    scaled = scale * x
    low = math.floor(scaled)
    down = low / scale
    up = math.ceil(scaled) / scale
    gap = (up - x) - (x - down)
    return up if gap < 0 or (gap == 0 and low % 2 == 1) else down


# --- results ------------------------------------------------------------------------------


@dataclass(frozen=True)
class ElevationResult:
    """doolkit's face elevations for one mesh (``elev(origin = TRUE)``).

    Attributes
    ----------
    elevation_mean : float
        Plain mean of ``face_elevation``, mesh units.
    vertices, faces : int
        Vertex and face counts of the mesh measured.
    face_elevation : (m,) float64
        Each face's barycentre height above the lowest vertex: ``dkorigin``
        (z minus the lowest z, double precision), then ``vcgBary`` in single
        precision, ``((z1 + z2) + z3) / 3``.
    mesh : trimesh.Trimesh
        The mesh the per-face array refers to (a private copy; turned to +z
        if ``orient="auto"`` turned it).
    orientation : Orientation
        Which way the crown points and whether it was turned before measuring.
    """

    elevation_mean: float
    vertices: int
    faces: int
    face_elevation: np.ndarray = field(repr=False, compare=False)
    mesh: trimesh.Trimesh = field(default=LazyMesh(), repr=False, compare=False)
    orientation: Orientation | None = field(default=None, compare=False)

    def to_dict(self) -> dict:
        """The table field: ``{"elev_mean": ...}``."""
        return {"elev_mean": self.elevation_mean}

    def _repr_html_(self) -> str:
        """A compact table for notebooks: values, settings, arrays summarised."""
        return result_html(self, histogram="face_elevation")


@dataclass(frozen=True)
class ReliefIndexResult:
    """doolkit's three relief indices for one mesh (``rfi`` with Ungar, Boyer and Guy).

    Attributes
    ----------
    rfi_ungar : float
        ``area3d / area2d``, a plain ratio.
    rfi_boyer : float
        ``ln(sqrt(area3d) / sqrt(area2d))``.
    rfi_guy : float
        Gamma: the summed elevation of the faces with slope below 45 degrees
        over that of the faces with slope above 45 (doolkit's area factor is
        the total area for every face, so it cancels).
    area3d : float
        Total area as ``vcgArea``: single-precision face areas summed.
    area2d : float
        Footprint area (``footprint_area(mesh, hull=hull)``).
    hull : str
        The footprint's outline, ``"concave"`` (doolkit's default) or ``"convex"``.
    vertices, faces : int
        Vertex and face counts of the mesh measured.
    face_slope, face_elevation, face_area : (m,) float64
        The per-face quantities used (:func:`doolkit_slope`, :func:`elevation`,
        single-precision areas).
    mesh : trimesh.Trimesh
        The mesh the per-face arrays refer to (a private copy; turned to +z
        if ``orient="auto"`` turned it).
    orientation : Orientation
        Which way the crown points and whether it was turned before measuring.
    """

    rfi_ungar: float
    rfi_boyer: float
    rfi_guy: float
    area3d: float
    area2d: float
    hull: str
    vertices: int
    faces: int
    face_slope: np.ndarray = field(repr=False, compare=False)
    face_elevation: np.ndarray = field(repr=False, compare=False)
    face_area: np.ndarray = field(repr=False, compare=False)
    mesh: trimesh.Trimesh = field(default=LazyMesh(), repr=False, compare=False)
    orientation: Orientation | None = field(default=None, compare=False)

    def to_dict(self) -> dict:
        """The table fields (:data:`RELIEF_INDEX_FIELDS`; ``area2d`` is the `hull` one)."""
        return {name: getattr(self, name) for name in RELIEF_INDEX_FIELDS}

    def _repr_html_(self) -> str:
        """A compact table for notebooks: values, settings, arrays summarised."""
        return result_html(self, histogram="face_slope")


@dataclass(frozen=True)
class ReliefRateResult:
    """doolkit's relief rate of a cropped mesh against the whole (``rrate``).

    Attributes
    ----------
    rrate : float
        ``cropped_relief / uncropped_relief``.
    uncropped_relief, cropped_relief : float
        ``mean(e - min(e))`` of each mesh's face elevations ``e``.
    below_median : bool
        Whether the cropped mesh is the uncropped one's faces of elevation
        below the median (:func:`relief_rate_below_median`).
    vertices, faces : int
        Vertex and face counts of the uncropped mesh.
    cropped_vertices, cropped_faces : int
        Those of the cropped mesh.
    orientation : Orientation
        Which way the uncropped crown points and whether both were turned.
    """

    rrate: float
    uncropped_relief: float
    cropped_relief: float
    below_median: bool
    vertices: int
    faces: int
    cropped_vertices: int
    cropped_faces: int
    orientation: Orientation | None = field(default=None, compare=False)

    def to_dict(self) -> dict:
        """``{"rrate_below_median": ...}`` for the median crop, else ``{"rrate": ...}``."""
        return {"rrate_below_median" if self.below_median else "rrate": self.rrate}

    def _repr_html_(self) -> str:
        """A compact table for notebooks: values, settings, arrays summarised."""
        return result_html(self)


@dataclass(frozen=True)
class ShapeIndexResult:
    """doolkit's shape indices for one mesh (``shape.index``).

    Attributes
    ----------
    formfactor : float
        ``area3d / length**2``.
    elongation : float
        ``2 sqrt(area3d) / (length sqrt(pi))``.
    k : float
        ``pi length**2 / (4 area3d)``.
    area3d : float
        The 3D surface area of the mesh after ``dkorigin`` (``vcgArea``), not
        the footprint.
    length : float
        The y extent rounded to 2 decimals (:func:`hypsodonty`'s ``length``).
    vertices, faces : int
        Vertex and face counts of the mesh measured.
    """

    formfactor: float
    elongation: float
    k: float
    area3d: float
    length: float
    vertices: int
    faces: int

    def to_dict(self) -> dict:
        """The table fields: ``shape_formfactor``, ``shape_elongation``, ``shape_k``."""
        return {
            "shape_formfactor": self.formfactor,
            "shape_elongation": self.elongation,
            "shape_k": self.k,
        }

    def _repr_html_(self) -> str:
        """A compact table for notebooks: values, settings, arrays summarised."""
        return result_html(self)


@dataclass(frozen=True)
class HypsodontyResult:
    """doolkit's hypsodonty and extents for one mesh (``hypso``).

    Attributes
    ----------
    hypsodonty : float
        Unrounded height over unrounded length, rounded to 2 decimals.
    height, length, width : float
        z, y and x extents rounded to 2 decimals (R's ``round``, :func:`r_round`).
    vertices, faces : int
        Vertex and face counts of the mesh measured.
    """

    hypsodonty: float
    height: float
    length: float
    width: float
    vertices: int
    faces: int

    def to_dict(self) -> dict:
        """The table fields (:data:`HYPSODONTY_FIELDS`)."""
        return {
            "hypso_hypsodonty": self.hypsodonty,
            "hypso_height": self.height,
            "hypso_length": self.length,
            "hypso_width": self.width,
        }

    def _repr_html_(self) -> str:
        """A compact table for notebooks: values, settings, arrays summarised."""
        return result_html(self)


# --- the metrics --------------------------------------------------------------------------


def elevation(mesh, *, orient: str = "auto") -> ElevationResult:
    """Face elevations, as doolkit 1.42.2's ``elev(origin = TRUE)`` computes them.

    ``dkorigin`` subtracts the lowest vertex z from every vertex z (double
    precision); ``vcgBary`` rounds the shifted coordinates to single precision
    and takes each face's barycentre there, ``((z1 + z2) + z3) / 3``.  So
    each face gets its barycentre height above the lowest vertex.

    Parameters
    ----------
    mesh : trimesh.Trimesh, str, path-like, (vertices, faces), or Surface
        Read as doolkit reads it (:func:`doolkit_slope`).  Never modified.
    orient : {"auto", "as-is"}, default "auto"
        ``"as-is"`` measures the mesh as it lies (doolkit's behaviour) and
        warns if the crown points to -z; ``"auto"`` (the default) turns such a crown first
        (see :func:`dentopo.topography.find_orientation`).

    Returns
    -------
    ElevationResult

    Warns
    -----
    UserWarning
        When the crown is measured pointing to -z (``orient="as-is"``), or
        when it is flat or closed (never turned).

    Examples
    --------
    >>> import trimesh
    >>> from dentopo.topography import elevation
    >>> float(elevation(trimesh.creation.box()).face_elevation.min())  # the bottom faces
    0.0
    """
    dm = doolkit_mesh(mesh, check_orient(orient))
    dm.warn_orientation()
    per_face = dm.elevation
    return ElevationResult(
        elevation_mean=float(np.mean(per_face)),
        vertices=len(dm.vertices),
        faces=len(dm.faces),
        face_elevation=per_face.copy(),
        mesh=dm.mesh_later(),
        orientation=dm.orientation,
    )


def _gamma(slope: np.ndarray, elev: np.ndarray) -> float:
    gentle = float(np.sum(elev[slope < 45.0]))
    steep = float(np.sum(elev[slope > 45.0]))
    return gentle / steep if steep != 0 else math.nan


def relief_index(mesh, *, hull: str = "concave", orient: str = "auto") -> ReliefIndexResult:
    """Relief indices, as doolkit 1.42.2's ``rfi`` computes them (Ungar, Boyer and Guy).

    * ``area3d``: ``vcgArea``, each face's area in single precision, summed
      in double;
    * ``area2d``: the footprint's area
      (:func:`dentopo.topography.footprint_area` with `hull`);
    * Ungar: ``area3d / area2d``; Boyer: ``ln(sqrt(area3d) / sqrt(area2d))``;
    * Guy (gamma): ``sum(elev[slope < 45]) / sum(elev[slope > 45])`` with
      doolkit's face slope (:func:`doolkit_slope`) and face elevation
      (:func:`elevation`).  doolkit weights both sides by the total area,
      one number for every face, so it cancels; faces of slope exactly 45
      (or NaN, a face of no area) are on neither side.  NaN if no face is
      steeper than 45 degrees.

    Parameters
    ----------
    mesh : trimesh.Trimesh, str, path-like, (vertices, faces), or Surface
        Read as doolkit reads it (:func:`doolkit_slope`).  Never modified.
    hull : {"concave", "convex"}, default "concave"
        The footprint's outline (doolkit's code defaults to concave; its
        manual says convex).
    orient : {"auto", "as-is"}, default "auto"
        ``"as-is"`` measures the mesh as it lies (doolkit's behaviour) and
        warns if the crown points to -z; ``"auto"`` (the default) turns such a crown first
        (see :func:`dentopo.topography.find_orientation`).

    Returns
    -------
    ReliefIndexResult

    Raises
    ------
    TypeError, ValueError
        For an unusable mesh or parameter; ValueError when the footprint has
        zero area (the crown's vertices project onto a line).

    Warns
    -----
    UserWarning
        When the crown is measured pointing to -z (``orient="as-is"``), or
        when it is flat or closed (never turned).
    UnitWarning
        When doolkit's 4-decimal rounding of the footprint can move Ungar's
        index by more than 0.5 % (a crown small in its unit: doolkit assumes
        millimetres).

    References
    ----------
    Ungar P. S., Williamson M. (2000). Exploring the effects of tooth wear on
    functional morphology. Palaeontologia Electronica 3.

    Boyer D. M. (2008). Relief index of second mandibular molars is a
    correlate of diet among prosimian primates and other euarchontan mammals.
    Journal of Human Evolution 55, 1118-1137. doi:10.1016/j.jhevol.2008.08.002

    Examples
    --------
    >>> import trimesh
    >>> from dentopo.topography import relief_index
    >>> result = relief_index(trimesh.creation.box(), hull="convex")
    >>> result.rfi_ungar  # 6 unit squares over a unit square
    6.0
    """
    hull = check_hull(hull)
    dm = doolkit_mesh(mesh, check_orient(orient))
    dm.warn_orientation()
    area3d = dm.area3d
    footprint = footprint_result((dm.vertices, dm.faces), hull, "as-is")
    area2d = float(footprint.area)
    if not area2d > 0.0:
        raise ValueError(
            f"the footprint has zero area: the crown's vertices project onto a line (or a "
            f"point) in x-y{_rounded_away(footprint)}, and Ungar's and Boyer's relief indices "
            "divide by it"
        )
    if footprint.rounding > _units.MATERIAL:
        _units.warn("relief_index", rounding_text(footprint, "rfi_ungar and rfi_boyer's ratio"))
    slope, elev = dm.slope, dm.elevation
    return ReliefIndexResult(
        rfi_ungar=area3d / area2d,
        rfi_boyer=float(np.log(np.sqrt(area3d) / np.sqrt(area2d))),
        rfi_guy=_gamma(slope, elev),
        area3d=area3d,
        area2d=area2d,
        hull=hull,
        vertices=len(dm.vertices),
        faces=len(dm.faces),
        face_slope=slope.copy(),
        face_elevation=elev.copy(),
        face_area=dm.areas.copy(),
        mesh=dm.mesh_later(),
        orientation=dm.orientation,
    )


def _rounded_away(footprint) -> str:
    """`` once rounded to 4 decimals`` if the unrounded ring has an area (a crown too small)."""
    if footprint.hull == "concave" and math.isinf(footprint.rounding):
        return " once doolkit rounds the coordinates to 4 decimals (a crown too small in its unit)"
    return ""


def crop(dm: DoolkitMesh, faces: np.ndarray) -> DoolkitMesh:
    """doolkit's ``dkcrop``: the listed faces in their order, their vertices in index order.

    The vertices the kept faces use keep their increasing index order and are
    renumbered from 0; nothing else is cleaned.
    """
    kept = dm.faces[faces]
    used = np.flatnonzero(np.bincount(kept.ravel(), minlength=len(dm.vertices)))
    remap = np.full(len(dm.vertices), -1, dtype=np.int64)
    remap[used] = np.arange(len(used))
    return DoolkitMesh(dm.vertices[used], remap[kept], dm.orientation)


def _relief(dm: DoolkitMesh) -> float:
    e = dm.elevation
    return float(np.mean(e - e.min()))


def _rate(uncropped: DoolkitMesh, cropped: DoolkitMesh, below_median: bool) -> ReliefRateResult:
    whole, part = _relief(uncropped), _relief(cropped)
    return ReliefRateResult(
        rrate=part / whole if whole != 0 else math.nan,
        uncropped_relief=whole,
        cropped_relief=part,
        below_median=below_median,
        vertices=len(uncropped.vertices),
        faces=len(uncropped.faces),
        cropped_vertices=len(cropped.vertices),
        cropped_faces=len(cropped.faces),
        orientation=uncropped.orientation,
    )


def relief_rate(uncropped, cropped, *, orient: str = "auto") -> ReliefRateResult:
    """Relief rate of a cropped crown, as doolkit 1.42.2's ``rrate(origin = TRUE)`` computes it.

    ``mean(e_c - min(e_c)) / mean(e_u - min(e_u))`` with ``e_u`` and ``e_c``
    the face elevations (:func:`elevation`) of the uncropped and the cropped
    mesh; the origin shifts cancel.  For doolkit's example (the faces below
    the median elevation) see :func:`relief_rate_below_median`.

    Parameters
    ----------
    uncropped, cropped : trimesh.Trimesh, str, path-like, (vertices, faces), or Surface
        The whole crown and a part of it, each read as doolkit reads it.
        Never modified.
    orient : {"auto", "as-is"}, default "auto"
        Found on the uncropped mesh; with ``"auto"`` a crown pointing to -z
        is turned to +z, and the cropped mesh with it (the same rotation).
        ``"as-is"`` warns if it points to -z.

    Returns
    -------
    ReliefRateResult

    Warns
    -----
    UserWarning
        When the uncropped crown is measured pointing to -z
        (``orient="as-is"``), or when it is flat or closed (never turned).
    """
    whole = doolkit_mesh(uncropped, check_orient(orient))
    whole.warn_orientation()
    part = doolkit_mesh(cropped)
    if whole.orientation is not None and whole.orientation.turned:
        part = DoolkitMesh(part.vertices @ TURN.T, part.faces.copy(), whole.orientation)
    return _rate(whole, part, below_median=False)


def relief_rate_below_median(mesh, *, orient: str = "auto") -> ReliefRateResult:
    """The relief rate of the faces below the median elevation (doolkit's ``rrate`` example).

    The table's ``rrate_below_median``: the cropped mesh is ``dkcrop(mesh,
    which(elev(mesh) < median(elev(mesh))))`` (strictly below the median,
    the mean of the two middle values for an even face count; the kept
    faces' vertices in increasing index order, renumbered), then
    :func:`relief_rate` of the mesh and that crop.

    Parameters
    ----------
    mesh : trimesh.Trimesh, str, path-like, (vertices, faces), or Surface
        Never modified.
    orient : {"auto", "as-is"}, default "auto"
        ``"as-is"`` measures the mesh as it lies (doolkit's behaviour) and
        warns if the crown points to -z; ``"auto"`` (the default) turns such a crown first
        (see :func:`dentopo.topography.find_orientation`).

    Returns
    -------
    ReliefRateResult

    Warns
    -----
    UserWarning
        When the crown is measured pointing to -z (``orient="as-is"``), or
        when it is flat or closed (never turned).

    Examples
    --------
    >>> from dentopo.samples import tooth
    >>> 0 < relief_rate_below_median(tooth(rings=16)).rrate < 1
    True
    """
    dm = doolkit_mesh(mesh, check_orient(orient))
    dm.warn_orientation()
    e = dm.elevation
    below = np.flatnonzero(e < np.median(e))
    if len(below) == 0:
        raise ValueError("no face lies below the median elevation: the crown is flat")
    return _rate(dm, crop(dm, below), below_median=True)


def _extents(dm: DoolkitMesh) -> tuple[float, float, float]:
    """Unrounded (height, length, width): z extent after ``dkorigin``, y and x extents."""
    v = dm.origin_vertices
    return (
        float(v[:, 2].max() - v[:, 2].min()),
        float(v[:, 1].max() - v[:, 1].min()),
        float(v[:, 0].max() - v[:, 0].min()),
    )


def hypsodonty(mesh) -> HypsodontyResult:
    """Hypsodonty and extents, as doolkit 1.42.2's ``hypso(origin = TRUE)`` computes them.

    Height, length and width are the z, y and x extents of the vertices
    (doolkit: x bucco-lingual, y mesio-distal, z up), each rounded to 2
    decimals with R's ``round`` (:func:`r_round`); hypsodonty is the
    unrounded height over the unrounded length, rounded the same way.
    Turning the crown upside down does not change them.

    Parameters
    ----------
    mesh : trimesh.Trimesh, str, path-like, (vertices, faces), or Surface
        Read as doolkit reads it (single-precision coordinates).  Never modified.

    Returns
    -------
    HypsodontyResult

    Examples
    --------
    >>> import trimesh
    >>> from dentopo.topography import hypsodonty
    >>> hypsodonty(trimesh.creation.box(extents=(2.0, 1.0, 0.5))).hypsodonty
    0.5
    """
    dm = doolkit_mesh(mesh)
    height, length, width = _extents(dm)
    if not length > 0:
        raise ValueError(
            "the crown's length (its y extent) is 0: no hypsodonty (height over length)"
        )
    extents = {"hypso_height": height, "hypso_length": length, "hypso_width": width}
    rounded = {key: r_round(value) for key, value in extents.items()}
    _warn_rounding("hypsodonty", extents, rounded)
    return HypsodontyResult(
        hypsodonty=r_round(height / length),
        height=rounded["hypso_height"],
        length=rounded["hypso_length"],
        width=rounded["hypso_width"],
        vertices=len(dm.vertices),
        faces=len(dm.faces),
    )


def _warn_rounding(metric: str, exact: dict, rounded: dict) -> None:
    """A UnitWarning naming each value doolkit's 2-decimal rounding moves by more than 0.5 %."""
    said = [
        f"{key} {exact[key]:.4g} becomes {rounded[key]:g}"
        for key in exact
        if _units.rounding_change(exact[key], rounded[key]) > _units.MATERIAL
    ]
    if said:
        _units.warn(metric, f"doolkit rounds lengths to 2 decimals: {', '.join(said)}", 4)


def shape_index(mesh) -> ShapeIndexResult:
    """Shape indices, as doolkit 1.42.2's ``shape.index(origin = TRUE)`` computes them.

    With ``A`` the 3D surface area (not the footprint) of the mesh after
    ``dkorigin`` (the lowest z subtracted from every z; ``vcgArea`` rounds the
    shifted coordinates to single precision and sums single-precision face
    areas, so ``A`` can differ from :func:`relief_index`'s ``area3d`` by
    about 1e-8 relative) and ``L`` the y extent rounded to 2 decimals
    (:func:`hypsodonty`'s ``length``): form factor ``A / L**2``, elongation
    ``2 sqrt(A) / (L sqrt(pi))``, K ``pi L**2 / (4 A)``.  The rounding of
    ``L`` matters on small crowns (0.609 becomes 0.61).

    Parameters
    ----------
    mesh : trimesh.Trimesh, str, path-like, (vertices, faces), or Surface
        Read as doolkit reads it.  Never modified.

    Returns
    -------
    ShapeIndexResult

    Raises
    ------
    ValueError
        If the y extent rounds to 0 (the indices would divide by it).

    Examples
    --------
    >>> import trimesh
    >>> from dentopo.topography import shape_index
    >>> shape_index(trimesh.creation.box()).formfactor  # area 6, length 1
    6.0
    """
    dm = doolkit_mesh(mesh)
    area = dm.origin_area3d
    exact = _extents(dm)[1]
    length = r_round(exact)
    if not length > 0:
        raise ValueError(
            f"the mesh's y extent ({exact:.3g}) rounds to 0 at 2 decimals: no shape index; "
            f"{_units.FIX}"
        )
    # the form factor and K move by the square of the length's rounding
    change = abs((length / exact) ** 2 - 1.0)
    if change > _units.MATERIAL:
        _units.warn(
            "shape_index",
            f"doolkit rounds the crown's length (y extent) to 2 decimals: {exact:.4g} becomes "
            f"{length:g}, which moves shape_formfactor by {change:.2%}",
        )
    return ShapeIndexResult(
        formfactor=area / length**2,
        elongation=2.0 * math.sqrt(area) / (length * math.sqrt(math.pi)),
        k=math.pi * length**2 / (4.0 * area),
        area3d=area,
        length=length,
        vertices=len(dm.vertices),
        faces=len(dm.faces),
    )
