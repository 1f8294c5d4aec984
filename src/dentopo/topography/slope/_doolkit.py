"""Face angles as doolkit 1.42.2 computes them: slope, inclination and orientation bearing.

doolkit (Thiery and others, R) measures a crown as ``Rvcg::vcgImport`` reads
it and takes every face angle from ``Morpho::facenormals``: the unit normal of
``(v2 - v1) x (v3 - v1)`` in double precision, a zero normal left at
``(0, 0, 0)``.  Its slope folds up- and down-facing faces together (0 to 90
degrees), its inclination does not (0 to 180), and its orientation is the
compass bearing of the normal's x-y part, which OPC bins.

This module also prepares the mesh as doolkit's reader leaves it
(:class:`DoolkitMesh`), shared with :mod:`._opc_doolkit` and :mod:`._relief`:

* coordinates rounded to single precision (vcglib's ``Coord3f``; a mesh of
  float32 values, as every PLY of the shared data, is unchanged);
* ``clean = TRUE``: vertices with exactly equal coordinates merged (each onto
  its first occurrence), faces then using a vertex twice dropped (vcglib's
  duplicate-vertex removal drops them), faces using the same three vertices
  dropped (the first kept), vertices no face uses dropped, then the rest
  renumbered in their order;
* no face is dropped for having no area: doolkit keeps them (their slope is
  NaN, which makes the mean NaN, as in doolkit).  A :class:`Surface` given in
  place of a mesh is measured as it is, molaR's cleaning (zero-area faces
  dropped) included.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np
import trimesh

from ..._html_repr import result_html
from ...mesh import as_arrays
from .._lazy import LazyMesh, MeshLater
from ..surface import _kernels
from ..surface._molar import Surface, drop_unused, molar_face_areas
from ..surface._orientation import TURN, Orientation, check_orient, find_orientation

#: Scalar fields of doolkit's slope and inclination, in the order of output tables.
DOOLKIT_SLOPE_FIELDS = ("slope_mean",)
INCLINATION_FIELDS = ("inclin_mean",)

#: ``atan2(1, 0)``: doolkit's quarter turn in its bearing expression.
_QUARTER = float(np.arctan2(1.0, 0.0))


# --- the mesh as doolkit reads it ---------------------------------------------------------


def _may_repeat(vertices: np.ndarray) -> bool:
    """False if no two rows of `vertices` are equal (a hash of each row, sorted)."""
    bits = (vertices + 0.0).astype(np.float32).view(np.uint32).astype(np.uint64)  # -0 as +0
    hashed = (
        (bits[:, 0] * np.uint64(0x9E3779B97F4A7C15))
        ^ (bits[:, 1] * np.uint64(0xC2B2AE3D27D4EB4F))
        ^ (bits[:, 2] * np.uint64(0x165667B19E3779F9))
    )
    hashed.sort()
    return bool(np.any(hashed[1:] == hashed[:-1]))


def _merge_equal_vertices(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """`faces` with every vertex index replaced by its first exact duplicate's."""
    if not _may_repeat(vertices):
        return faces
    order = np.lexsort((vertices[:, 2], vertices[:, 1], vertices[:, 0]))
    ordered = vertices[order]
    same = np.all(ordered[1:] == ordered[:-1], axis=1)
    if not same.any():
        return faces
    # runs of equal rows in sorted order: map each to the lowest original index of its run
    run = np.concatenate([[0], np.cumsum(~same)])
    first = np.full(run[-1] + 1, len(vertices), dtype=np.int64)
    np.minimum.at(first, run, order)
    target = np.empty(len(vertices), dtype=np.int64)
    target[order] = first[run]
    return target[faces]


def _drop_duplicate_faces(faces: np.ndarray, n: int) -> np.ndarray:
    """`faces` without the faces using the same three vertices as an earlier one."""
    key = np.sort(faces, axis=1)
    if n < 2**21:
        flat = (key[:, 0] * n + key[:, 1]) * n + key[:, 2]
        ordered = np.sort(flat)
        if not np.any(ordered[1:] == ordered[:-1]):
            return faces
        _, first = np.unique(flat, return_index=True)
    else:  # pragma: no cover - meshes of over two million vertices
        _, first = np.unique(key, axis=0, return_index=True)
    if len(first) == len(faces):
        return faces
    return faces[np.sort(first)]


def read_as_doolkit(mesh) -> tuple[np.ndarray, np.ndarray]:
    """``(vertices, faces)`` as ``vcgImport(clean = TRUE)`` leaves them (see the module).

    `mesh` is anything :func:`dentopo.mesh.as_arrays` accepts (files through
    :func:`dentopo.mesh.load_mesh`).  Returns new arrays: float64 holding
    float32 values, int64.
    """
    vertices, faces = as_arrays(mesh)
    vertices = vertices.astype(np.float32).astype(np.float64)
    faces = _merge_equal_vertices(vertices, faces)
    twice = (
        (faces[:, 0] == faces[:, 1]) | (faces[:, 1] == faces[:, 2]) | (faces[:, 2] == faces[:, 0])
    )
    if twice.any():
        faces = faces[~twice]
    faces = _drop_duplicate_faces(faces, len(vertices))
    if len(faces) == 0:
        raise ValueError("the mesh has no face with three distinct vertices")
    return drop_unused(vertices, faces)


class DoolkitMesh:
    """A mesh as doolkit measures it, with its per-face quantities computed once.

    Every doolkit metric of this package builds one (:func:`doolkit_mesh`);
    given a :class:`Surface`, the one built for it is kept with it, so that
    the metrics measured on one surface share it.

    Attributes
    ----------
    vertices : (n, 3) float64
        Single-precision values (vcglib's coordinates).
    faces : (m, 3) int64
    orientation : Orientation or None
        Which way the crown points and whether it was turned, when asked.
    """

    def __init__(self, vertices, faces, orientation: Orientation | None = None):
        self.vertices = vertices
        self.faces = faces
        self.orientation = orientation
        self._cache: dict = {}
        vertices.flags.writeable = False
        faces.flags.writeable = False

    def warn_orientation(self, stacklevel: int = 3) -> None:
        """Warn (``UserWarning``, one per problem) of what the orientation check found.

        One warning per problem, as molaR's metrics give them, so that a row
        measured by both says each once (joined, the closed-surface warning was
        written twice: alone, and again with the winding's).
        """
        if self.orientation is None:
            return
        for message in self.orientation.messages():
            warnings.warn(message, UserWarning, stacklevel=stacklevel)

    def cached(self, key, compute):
        """``compute()``, computed the first time `key` is asked for and kept."""
        if key not in self._cache:
            self._cache[key] = compute()
        return self._cache[key]

    def trimesh(self) -> trimesh.Trimesh:
        """The mesh measured, as a ``trimesh.Trimesh`` (faces as stored; a copy)."""
        return trimesh.Trimesh(self.vertices.copy(), self.faces.copy(), process=False)

    def mesh_later(self) -> MeshLater:
        """What :meth:`trimesh` gives, built when first read (a result's ``mesh``)."""
        return MeshLater(self.vertices, self.faces)

    @cached_property
    def normals(self) -> np.ndarray:
        """(m, 3) unit face normals as ``Morpho::facenormals`` (double; zero stays zero)."""
        normals = np.empty((len(self.faces), 3))
        readonly = _kernels.readonly
        _kernels.unit_normals(readonly(self.vertices), readonly(self.faces), normals)
        return normals

    @cached_property
    def slope(self) -> np.ndarray:
        """(m,) doolkit's face slope, degrees (:func:`face_slope`)."""
        return face_slope(self.normals)

    @cached_property
    def inclination(self) -> np.ndarray:
        """(m,) doolkit's face inclination, degrees (:func:`face_inclination`)."""
        return face_inclination(self.normals)

    @cached_property
    def bearing(self) -> np.ndarray:
        """(m,) doolkit's face orientation, degrees in [0, 360] (:func:`face_bearing`)."""
        return face_bearing(self.normals)

    @cached_property
    def areas(self) -> np.ndarray:
        """(m,) face areas as ``vcgArea(perface = TRUE)``: single precision, as float64."""
        return molar_face_areas(self.vertices, self.faces)

    @cached_property
    def area3d(self) -> float:
        """The total area as ``vcgArea``: single-precision face areas summed in double."""
        return float(self.areas.sum())

    @cached_property
    def origin_vertices(self) -> np.ndarray:
        """The vertices after ``dkorigin``: the lowest z subtracted from every z (double)."""
        shifted = self.vertices.copy()
        shifted[:, 2] -= shifted[:, 2].min()
        return shifted

    @cached_property
    def origin_area3d(self) -> float:
        """``vcgArea(dkorigin(mesh))``: :attr:`area3d` of the shifted vertices.

        vcglib rounds the shifted coordinates to single precision again, so
        this differs from :attr:`area3d` by about 1e-8 relative unless the
        shifted values are single-precision numbers too.
        """
        return float(molar_face_areas(self.origin_vertices, self.faces).sum())

    @cached_property
    def elevation(self) -> np.ndarray:
        """(m,) doolkit's face elevation (``elev(origin = TRUE)``), mesh units.

        ``dkorigin`` first subtracts the lowest vertex z from every z (double
        precision); ``vcgBary`` then rounds the shifted z to single precision
        and takes ``((z1 + z2) + z3) / 3`` there.
        """
        shifted = self.origin_vertices[:, 2].astype(np.float32)
        f = self.faces
        bary = ((shifted[f[:, 0]] + shifted[f[:, 1]]) + shifted[f[:, 2]]) / np.float32(3.0)
        return bary.astype(np.float64)


def doolkit_mesh(mesh, orient: str | None = None) -> DoolkitMesh:
    """The mesh as doolkit measures it (see the module), oriented as asked.

    Parameters
    ----------
    mesh : Surface, trimesh.Trimesh, str, path-like, or (vertices, faces)
        Never modified.  A :class:`Surface` is measured as it is (its
        coordinates rounded to single precision, as vcglib stores them); the
        result is kept with it.
    orient : {"as-is", "auto"}, optional
        None: the orientation is not looked at.  Otherwise it is found
        (:func:`dentopo.topography.find_orientation`) and, with ``"auto"``, a
        crown pointing to -z is turned to +z (180 degrees about x).
    """
    if orient is not None:
        orient = check_orient(orient)
    if isinstance(mesh, Surface):
        base = mesh.cleaned
        return base._cached(("doolkit", orient), lambda: _from_surface(base, orient))
    vertices, faces = read_as_doolkit(mesh)
    if orient is None:
        return DoolkitMesh(vertices, faces)
    found = find_orientation(vertices, faces, molar_face_areas(vertices, faces))
    if found.turns(orient):
        return DoolkitMesh(vertices @ TURN.T, faces, replace(found, turned=True, asked=orient))
    return DoolkitMesh(vertices, faces, replace(found, asked=orient))


def _from_surface(surface: Surface, orient: str | None) -> DoolkitMesh:
    if orient is not None:
        surface = surface.oriented(orient)
    vertices = surface.vertices.astype(np.float32).astype(np.float64)
    # the surface's faces are read-only already: shared, not copied
    return DoolkitMesh(vertices, surface.faces, surface.orientation)


# --- per-face angles ----------------------------------------------------------------------


def _horizontal_ratio(normals: np.ndarray) -> np.ndarray:
    """``sqrt(nx^2 + ny^2) / |n|``: NaN for a zero normal (never above 1)."""
    ratio = np.empty(len(normals))
    _kernels.horizontal_ratio(_kernels.readonly(np.ascontiguousarray(normals)), ratio)
    return ratio


def face_slope(normals: np.ndarray) -> np.ndarray:
    """doolkit's face slope: ``90 - acos(sqrt(nx^2 + ny^2) / |n|)`` in degrees.

    The angle between the normal and the z axis folded into [0, 90]: 0 for a
    horizontal face whether it faces up or down, 90 for a vertical one.  NaN
    for a zero normal (a face of no area), as in doolkit.
    """
    return 90.0 - np.arccos(_horizontal_ratio(normals)) * (180.0 / np.pi)


def face_inclination(normals: np.ndarray) -> np.ndarray:
    """doolkit's face inclination: 180 minus the normal's angle from +z, in degrees.

    ``90 + e`` with ``e`` the normal's elevation above the x-y plane, which
    is ``90 - s`` for a normal pointing up and ``s - 90`` for one pointing
    down (``s`` the slope of :func:`face_slope`): so ``180 - s`` or ``s``,
    180 facing straight up, 90 vertical, 0 facing straight down.  NaN for a
    zero normal.
    """
    slope = face_slope(normals)
    return np.where(normals[:, 2] < 0, slope, 180.0 - slope)


def face_bearing(normals: np.ndarray) -> np.ndarray:
    """doolkit's face orientation: the compass bearing of the normal's x-y part, degrees.

    ``a = atan2(nx, ny)`` (x first: 0 towards +y, 90 towards +x, clockwise
    seen from +z), ``a + 2 pi`` where ``a < 0``, then doolkit's own conversion
    ``180 * (a - atan2(1, 0)) / pi + 90``, evaluated in that order: it differs
    from ``a * 180 / pi`` in the last bits for many faces, and OPC compares
    bearings with its bin edges exactly.  A horizontal face (``nx = ny = 0``)
    gets exactly 0.  The result lies in [0, 360]: a tiny negative ``a`` plus
    ``2 pi`` can round to ``2 pi``, whose bearing is exactly 360 (doolkit's
    OPC at rotation 0 then puts the face in no bin).
    """
    a = np.arctan2(normals[:, 0], normals[:, 1])
    a = np.where(a < 0, a + 2.0 * np.pi, a)
    return 180.0 * (a - _QUARTER) / np.pi + 90.0


# --- results ------------------------------------------------------------------------------


@dataclass(frozen=True)
class DoolkitSlopeResult:
    """doolkit's mean face slope for one mesh (``slope``).

    Per-face arrays follow the faces of the mesh as doolkit reads it (see
    :mod:`dentopo.topography.slope._doolkit`: exact duplicates merged, faces kept in
    their order).

    Attributes
    ----------
    slope_mean : float
        Plain (unweighted) mean of ``face_slope``, degrees; NaN if a face has
        no area (doolkit's).
    vertices, faces : int
        Vertex and face counts of the mesh measured.
    face_slope : (m,) float64
        Angle between each face normal and the z axis folded into [0, 90]
        (:func:`face_slope`).
    mesh : trimesh.Trimesh
        The mesh the per-face array refers to (a private copy).
    """

    slope_mean: float
    vertices: int
    faces: int
    face_slope: np.ndarray = field(repr=False, compare=False)
    mesh: trimesh.Trimesh = field(default=LazyMesh(), repr=False, compare=False)

    def to_dict(self) -> dict:
        """The table field: ``{"slope_mean": ...}``."""
        return {name: getattr(self, name) for name in DOOLKIT_SLOPE_FIELDS}

    def _repr_html_(self) -> str:
        """A compact table for notebooks: values, settings, arrays summarised."""
        return result_html(self, histogram="face_slope")


@dataclass(frozen=True)
class InclinationResult:
    """doolkit's mean face inclination for one mesh (``inclin``).

    Attributes
    ----------
    inclination_mean : float
        Plain mean of ``face_inclination``, degrees (the ``inclin_mean`` column).
    vertices, faces : int
        Vertex and face counts of the mesh measured.
    face_inclination : (m,) float64
        180 for a face facing straight up, 90 vertical, 0 facing down
        (:func:`face_inclination`).
    mesh : trimesh.Trimesh
        The mesh the per-face array refers to (a private copy; turned to +z
        if ``orient="auto"`` turned it).
    orientation : Orientation
        Which way the crown points and whether it was turned before measuring.
    """

    inclination_mean: float
    vertices: int
    faces: int
    face_inclination: np.ndarray = field(repr=False, compare=False)
    mesh: trimesh.Trimesh = field(default=LazyMesh(), repr=False, compare=False)
    orientation: Orientation | None = field(default=None, compare=False)

    def to_dict(self) -> dict:
        """The table field: ``{"inclin_mean": ...}``."""
        return {"inclin_mean": self.inclination_mean}

    def _repr_html_(self) -> str:
        """A compact table for notebooks: values, settings, arrays summarised."""
        return result_html(self, histogram="face_inclination")


# --- the metrics --------------------------------------------------------------------------


def doolkit_slope(mesh) -> DoolkitSlopeResult:
    """Mean face slope, as doolkit 1.42.2's ``slope`` computes it.

    1. **Mesh.** Read as ``Rvcg::vcgImport(clean = TRUE)`` leaves it
       (coordinates in single precision, exact duplicate vertices merged,
       duplicate faces and unused vertices dropped; see
       :mod:`dentopo.topography.slope._doolkit`).  The caller's mesh is never modified.
    2. **Per face.** Unit normal ``n`` of ``(v2 - v1) x (v3 - v1)`` in double
       precision (``Morpho::facenormals``); slope
       ``90 - acos(sqrt(nx^2 + ny^2) / |n|)`` in degrees: the angle of the
       normal from the z axis folded into [0, 90].
    3. **Mean.** Plain mean over faces (not area weighted).

    Orientation-free: turning the crown upside down gives the same value.  A
    face of no area has slope NaN and makes the mean NaN, as in doolkit
    (prepare a :class:`Surface` to drop such faces first).

    Parameters
    ----------
    mesh : trimesh.Trimesh, str, path-like, (vertices, faces), or Surface
        Never modified.

    Returns
    -------
    DoolkitSlopeResult

    References
    ----------
    Thiery G., Guy F., Lazzari V. (2019). Investigating the dental toolkit of
    primates based on food mechanical properties: feeding action does matter.
    American Journal of Primatology 81, e22974. doi:10.1002/ajp.22974

    Examples
    --------
    >>> import trimesh
    >>> from dentopo.topography import doolkit_slope
    >>> doolkit_slope(trimesh.creation.box()).slope_mean  # 8 vertical faces (90), 4 flat (0)
    60.0
    """
    dm = doolkit_mesh(mesh)
    per_face = dm.slope
    return DoolkitSlopeResult(
        slope_mean=float(np.mean(per_face)),
        vertices=len(dm.vertices),
        faces=len(dm.faces),
        face_slope=per_face.copy(),
        mesh=dm.mesh_later(),
    )


def inclination(mesh, *, orient: str = "auto") -> InclinationResult:
    """Mean face inclination, as doolkit 1.42.2's ``inclin`` computes it.

    Mesh and normals as in :func:`doolkit_slope`.  Each face's inclination is
    180 minus the angle of its unit normal from +z (``90 + e``, ``e`` the
    normal's elevation above the x-y plane): 180 facing straight up, 90
    vertical, 0 facing straight down; the result is the plain mean over faces.
    Orientation-dependent: doolkit assumes the crown points to +z.

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
    InclinationResult

    Raises
    ------
    TypeError, ValueError
        For an unusable mesh or `orient`.

    Warns
    -----
    UserWarning
        When the crown is measured pointing to -z (``orient="as-is"``), or
        when it is flat or closed (never turned).

    Examples
    --------
    >>> import trimesh
    >>> from dentopo.topography import inclination
    >>> inclination(trimesh.creation.box()).inclination_mean  # sides 90, top 180, bottom 0
    90.0
    """
    dm = doolkit_mesh(mesh, check_orient(orient))
    dm.warn_orientation()
    per_face = dm.inclination
    return InclinationResult(
        inclination_mean=float(np.mean(per_face)),
        vertices=len(dm.vertices),
        faces=len(dm.faces),
        face_inclination=per_face.copy(),
        mesh=dm.mesh_later(),
        orientation=dm.orientation,
    )
