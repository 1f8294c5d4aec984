"""The surface every topography metric measures, prepared as molaR prepares it.

molaR reads a mesh and cleans it (faces of zero area dropped, then vertices no
face uses); every metric then works on face normals and areas from the faces'
stored vertex order, and some on coordinates rescaled by molaR's "centroid
size".  These shared pieces live here so that the metrics agree on them.

A :class:`Surface` is prepared once and can be given to every metric in place
of a mesh: what more than one metric needs of it (its boundary edges, the
crown's orientation, the crown turned to +z, molaR's single-precision face
areas) is computed the first time it is asked for and kept with it.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np
import trimesh

from ..mesh import as_arrays
from . import _kernels
from ._orientation import TURN, Orientation, check_orient, find_orientation

#: molaR rescales a mesh so that its size measure is this.
SIZE_TARGET = 100.0


@dataclass(frozen=True)
class Surface:
    """A cleaned mesh and its per-face geometry (arrays are private copies).

    Make one with :func:`prepare_surface`; every topography metric accepts it
    in place of a mesh, so that a mesh measured by several metrics is cleaned,
    and its orientation checked, once.  Its arrays are read-only: what is
    computed from them is kept with them.

    Attributes
    ----------
    vertices : (n, 3) float64
    faces : (m, 3) int64
        Faces of non-zero area, in their stored order and vertex order.
    cross : (m, 3) float64
        ``(v2 - v1) x (v3 - v1)`` of each face.
    area : (m,) float64
        Face areas (half the norm of ``cross``), mesh units.
    normals : (m, 3) float64
        Unit face normals (``cross`` normalised).
    dropped_faces : int
        Faces of zero area that were dropped.
    orientation : Orientation or None
        Which way the crown points and whether it was turned (when asked).
    source : Surface or None
        The cleaned surface as given, when this one is it looked at for its
        orientation (and perhaps turned): see :meth:`oriented`.
    """

    vertices: np.ndarray
    faces: np.ndarray
    cross: np.ndarray
    area: np.ndarray
    normals: np.ndarray
    dropped_faces: int = 0
    orientation: Orientation | None = None
    source: Surface | None = field(default=None, repr=False, compare=False)
    _cache: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    def __post_init__(self):
        # what is computed from the arrays is kept with them: they must not change
        for name in ("vertices", "faces", "cross", "area", "normals"):
            getattr(self, name).flags.writeable = False

    def warn_orientation(self, stacklevel: int = 3) -> None:
        """Warn (``UserWarning``) if the crown is measured pointing to -z."""
        message = None if self.orientation is None else self.orientation.warning()
        if message is not None:
            warnings.warn(message, UserWarning, stacklevel=stacklevel)

    @property
    def total_area(self) -> float:
        """The 3D surface area, mesh units."""
        return float(self.area.sum())

    @property
    def cleaned(self) -> Surface:
        """The cleaned surface as given: never turned, no orientation looked at."""
        return self if self.source is None else self.source

    def trimesh(self) -> trimesh.Trimesh:
        """The cleaned mesh as a ``trimesh.Trimesh`` (not processed: faces as stored; a copy)."""
        return trimesh.Trimesh(self.vertices.copy(), self.faces.copy(), process=False)

    def _cached(self, key, compute):
        if key not in self._cache:
            self._cache[key] = compute()
        return self._cache[key]

    def edge_groups(self) -> tuple[np.ndarray, np.ndarray, int]:
        """The directed edges grouped by undirected edge (:func:`_kernels.edge_groups`).

        ``(group_start, group_edge, groups)``: the edges of group g are
        ``group_edge[group_start[g]:group_start[g + 1]]``, edge ``e = k * m + f``
        running from ``faces[f, k]`` to ``faces[f, (k + 1) % 3]``; a boundary
        edge is a group of one.  Computed once, shared with the turned surface.
        """

        def compute():
            m = len(self.faces)
            group_start = np.empty(3 * m + 1, dtype=np.int64)
            group_edge = np.empty(3 * m, dtype=np.int64)
            groups = _kernels.edge_groups(self.faces, len(self.vertices), group_start, group_edge)
            return group_start, group_edge, groups

        return self.cleaned._cached("edge_groups", compute)

    def edge_uses(self) -> np.ndarray:
        """(3m,) int64: for directed edge ``e = k * m + f``, how many faces use its two vertices."""
        group_start, group_edge, groups = self.edge_groups()
        sizes = np.diff(group_start[: groups + 1])
        uses = np.empty(len(group_edge), dtype=np.int64)
        uses[group_edge] = np.repeat(sizes, sizes)
        return uses

    def boundary_edges(self) -> np.ndarray:
        """(k, 2) int64: the directed edges no other face shares (as mesh.boundary_edges)."""
        ends = np.empty((3 * len(self.faces), 2), dtype=np.int64)
        count = _kernels.boundary_ends(self.faces, *self.edge_groups(), ends)
        return ends[:count]

    def single_precision_areas(self) -> np.ndarray:
        """Face areas as molaR's reader computes them (:func:`molar_face_areas`); a copy."""
        # the turned surface's areas are the same numbers: turning negates coordinates exactly
        base = self.cleaned
        return base._cached(
            "single_precision_areas", lambda: molar_face_areas(base.vertices, base.faces)
        ).copy()

    def oriented(self, orient: str) -> Surface:
        """This surface with its orientation found, turned to +z with ``orient="auto"`` if needed.

        The orientation is found once (:func:`find_orientation`) and the
        result kept, for either `orient`.
        """
        orient = check_orient(orient)
        base = self.cleaned
        return base._cached(("oriented", orient), lambda: base._orient(orient))

    def _orient(self, orient: str) -> Surface:
        found = self._cached(
            "orientation",
            lambda: find_orientation(
                self.vertices, self.faces, self.area, boundary=self.boundary_edges()
            ),
        )
        if orient == "auto" and found.points == "-z":
            # a proper rotation: the same numbers, two of them negated (exactly)
            vertices = self.vertices @ TURN.T
            cross = face_cross(vertices, self.faces)
            norm = 2.0 * self.area
            return Surface(
                vertices=vertices,
                faces=self.faces,
                cross=cross,
                area=self.area,
                normals=cross / norm[:, None],
                dropped_faces=self.dropped_faces,
                orientation=Orientation(found.points, found.rule, turned=True),
                source=self,
            )
        return Surface(
            vertices=self.vertices,
            faces=self.faces,
            cross=self.cross,
            area=self.area,
            normals=self.normals,
            dropped_faces=self.dropped_faces,
            orientation=found,
            source=self,
        )


def face_cross(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """``(v2 - v1) x (v3 - v1)`` for every face."""
    v1 = vertices[faces[:, 0]]
    a = vertices[faces[:, 1]] - v1
    b = vertices[faces[:, 2]] - v1
    # the components as np.cross computes them, without its overhead
    cross = np.empty_like(a)
    cross[:, 0] = a[:, 1] * b[:, 2] - a[:, 2] * b[:, 1]
    cross[:, 1] = a[:, 2] * b[:, 0] - a[:, 0] * b[:, 2]
    cross[:, 2] = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    return cross


def drop_unused(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Drop the vertices no face uses (faces keep their order)."""
    used = np.flatnonzero(np.bincount(faces.ravel(), minlength=len(vertices)))
    if len(used) == len(vertices):
        return vertices, faces
    remap = np.full(len(vertices), -1, dtype=np.int64)
    remap[used] = np.arange(len(used))
    return vertices[used], remap[faces]


def prepare_surface(mesh, orient: str | None = None) -> Surface:
    """Read and clean `mesh` as molaR does: zero-area faces dropped, then unused vertices.

    Parameters
    ----------
    mesh : Surface, trimesh.Trimesh, str, path-like, or (vertices, faces)
        Never modified.  A :class:`Surface` is used as it is (its
        :attr:`Surface.cleaned` form), not cleaned again.
    orient : {"as-is", "auto"}, optional
        For the metrics that assume the crown points to +z: find which way it
        points (:func:`find_orientation`, recorded in ``Surface.orientation``)
        and, with ``"auto"``, turn a crown pointing to -z first
        (:meth:`Surface.oriented`).  None: the orientation is not looked at.

    Raises
    ------
    TypeError, ValueError
        For an unusable mesh, or one with no face of non-zero area.
    """
    if isinstance(mesh, Surface):
        surface = mesh.cleaned
    else:
        vertices, faces = as_arrays(mesh)
        cross = np.empty((len(faces), 3))
        norm = np.empty(len(faces))
        _kernels.face_cross_norm(vertices, faces, cross, norm)
        keep = norm > 0
        kept = int(np.count_nonzero(keep))
        if kept == 0:
            raise ValueError("the mesh has no face of non-zero area")
        dropped = len(faces) - kept
        if dropped:
            faces, cross, norm = faces[keep], cross[keep], norm[keep]
        vertices, faces = drop_unused(vertices, faces)
        surface = Surface(
            vertices=vertices,
            faces=faces,
            cross=cross,
            area=0.5 * norm,
            normals=cross / norm[:, None],
            dropped_faces=dropped,
        )
    return surface if orient is None else surface.oriented(orient)


def molar_face_areas(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Face areas as molaR's mesh reader computes them: in single precision.

    molaR's reader (vcglib, through Rvcg) stores coordinates as 32-bit floats
    and computes each face's area there: the edge vectors, their cross product
    and its norm in single precision.  RFI's 3D area and the weights of the
    mean slope are these areas (as float64, summed in double precision); they
    differ from double-precision areas by about 1e-9 relative on a typical
    crown, more for coordinates far from the origin.
    """
    area = np.empty(len(faces))
    _kernels.single_precision_areas(
        np.ascontiguousarray(vertices, dtype=np.float32), np.asarray(faces, dtype=np.int64), area
    )
    return area


def molar_scale(vertices: np.ndarray) -> float:
    """molaR's size normalisation factor: ``100 / size``.

    ``size`` centres each vertex's coordinate triple on the mean of its own
    three coordinates (per vertex, not per axis: molaR's quirk) and takes the
    root of the sum of squares over all vertices.

    Raises
    ------
    ValueError
        If the size is zero (every vertex lies on the line x = y = z).
    """
    centred = vertices - vertices.mean(axis=1, keepdims=True)
    size = float(np.sqrt(np.sum(centred**2)))
    if not size > 0:
        raise ValueError("the mesh has zero size (all vertices lie on the line x = y = z)")
    return SIZE_TARGET / size
