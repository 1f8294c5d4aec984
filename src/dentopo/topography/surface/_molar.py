"""The surface every topography metric measures, prepared as molaR prepares it.

molaR reads a mesh and cleans it (faces of zero area dropped, then vertices no
face uses); every metric then works on face normals and areas from the faces'
stored vertex order, and some on coordinates rescaled by molaR's "centroid
size".  These shared pieces live here so that the metrics agree on them.

One step is ours: a face listed again (the same three vertices, in any order
or winding) is dropped by default, so that every metric of a row, and the
``faces`` count ariaDNE's cleaning reports beside them, measure each triangle
once (``duplicates="keep"`` measures the faces as listed, as molaR does).

A :class:`Surface` is prepared once and can be given to every metric in place
of a mesh: what more than one metric needs of it (its boundary edges, the
crown's orientation, the crown turned to +z, molaR's single-precision face
areas) is computed the first time it is asked for and kept with it.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

import numpy as np

from ...mesh import as_arrays
from .._lazy import MeshLater
from .._parameters import check_choice
from . import _kernels
from ._orientation import TURN, Orientation, check_orient, survey

if TYPE_CHECKING:
    import trimesh

#: molaR rescales a mesh so that its size measure is this.
SIZE_TARGET = 100.0

#: ``duplicates``: ``"drop"`` (default: each triangle measured once) or ``"keep"`` (molaR's).
DUPLICATE_MODES = ("drop", "keep")


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
        Faces of non-zero area, in their stored order and vertex order (each
        triangle once unless ``duplicates="keep"``; rewound where they were
        wound inward, in a surface :meth:`oriented` with ``orient="auto"``).
    cross : (m, 3) float64
        ``(v2 - v1) x (v3 - v1)`` of each face.
    area : (m,) float64
        Face areas (half the norm of ``cross``), mesh units.
    normals : (m, 3) float64
        Unit face normals (``cross`` normalised).
    dropped_faces : int
        Faces of zero area that were dropped.
    duplicate_faces : int
        Faces (of non-zero area) that repeat an earlier face's three vertices,
        in any order: dropped with ``duplicates="drop"``, kept with ``"keep"``.
    duplicates : str
        ``"drop"`` or ``"keep"``: what was done with them.
    orientation : Orientation or None
        Which way the crown points and its faces are wound, and whether it was
        turned and rewound (when asked).
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
    duplicate_faces: int = 0
    duplicates: str = "drop"
    orientation: Orientation | None = None
    source: Surface | None = field(default=None, repr=False, compare=False)
    # the surface whose faces (and so edges and areas) this one has, if not its own
    _same_faces: Surface | None = field(default=None, repr=False, compare=False)
    _cache: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    def __post_init__(self):
        # what is computed from the arrays is kept with them: they must not change
        for name in ("vertices", "faces", "cross", "area", "normals"):
            getattr(self, name).flags.writeable = False

    def warn_orientation(self, stacklevel: int = 3, *, winding_only: bool = False) -> None:
        """Warn (``UserWarning``, one per problem) of what the orientation check found.

        A crown measured pointing to -z, a flat surface (no up or down), faces
        wound inward (rewound or not); ``winding_only``: only the last (the
        metrics that do not assume +z, as classic DNE).
        """
        if self.orientation is None:
            return
        for message in self.orientation.messages(winding_only=winding_only):
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
        import trimesh

        return trimesh.Trimesh(self.vertices.copy(), self.faces.copy(), process=False)

    def mesh_later(self) -> MeshLater:
        """What :meth:`trimesh` gives, built when first read (a result's ``mesh``)."""
        return MeshLater(self.vertices, self.faces)

    @property
    def _owner(self) -> Surface:
        """The surface whose faces this one has: its edges and areas are kept there."""
        return self if self._same_faces is None else self._same_faces

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
        owner = self._owner

        def compute():
            m = len(owner.faces)
            group_start = np.empty(3 * m + 1, dtype=np.int64)
            group_edge = np.empty(3 * m, dtype=np.int64)
            groups = _kernels.edge_groups(owner.faces, len(owner.vertices), group_start, group_edge)
            return group_start, group_edge, groups

        return owner._cached("edge_groups", compute)

    def consistent(self) -> bool:
        """Whether no directed edge is run twice (neighbouring faces agree on their winding)."""
        return bool(_kernels.agreeing_winding(self.faces, *self.edge_groups()))

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
        base = self._owner
        return base._cached(
            "single_precision_areas", lambda: molar_face_areas(base.vertices, base.faces)
        ).copy()

    def oriented(self, orient: str) -> Surface:
        """This surface with its orientation found, and put right with ``orient="auto"``.

        ``"auto"`` rewinds the faces found wound inward (reversing their
        vertex order) and turns a crown pointing to -z to +z; ``"as-is"``
        changes nothing.  The orientation is found once
        (:func:`find_orientation`) and the result kept, for either `orient`.
        """
        orient = check_orient(orient)
        base = self.cleaned
        return base._cached(("oriented", orient), lambda: base._orient(orient, turn=True))

    def wound(self, orient: str) -> Surface:
        """As :meth:`oriented`, but never turned: for the metrics that do not assume +z.

        Classic DNE's convex/concave split depends on the winding of the faces
        but not on which way the crown points.
        """
        orient = check_orient(orient)
        base = self.cleaned
        return base._cached(("wound", orient), lambda: base._orient(orient, turn=False))

    def _survey(self) -> tuple[Orientation, np.ndarray]:
        """What :func:`find_orientation` finds, and which faces are wound inward."""
        return self._cached("orientation", self._find_orientation)

    def _find_orientation(self) -> tuple[Orientation, np.ndarray]:
        if not (self.duplicates == "keep" and self.duplicate_faces):
            return survey(
                self.vertices,
                self.faces,
                self.area,
                boundary=self.boundary_edges(),
                consistent=self.consistent(),
                cross=self.cross,
            )
        # repeated faces kept: the surface is that of each triangle once (a triangle and
        # its copy would read as neighbours that disagree), each copy judged by its first
        first, reverse = repeated_faces(self.faces)
        once = first == np.arange(len(self.faces))
        found, inward_once = survey(self.vertices, self.faces[once], self.area[once])
        inward = np.zeros(len(self.faces), dtype=bool)
        inward[once] = inward_once
        inward = inward[first] ^ reverse
        count = int(np.count_nonzero(inward))
        if found.winding in ("outward", "inward", "mixed"):
            winding = "outward" if count == 0 else "inward" if inward.all() else "mixed"
            found = replace(found, winding=winding, inward_faces=count)
        return replace(found, faces=len(self.faces)), inward

    def _rewound(self, inward: np.ndarray) -> Surface:
        """The cleaned surface with the `inward` faces' vertex order reversed (its own edges)."""

        def compute():
            faces = np.where(inward[:, None], self.faces[:, ::-1], self.faces)
            cross = np.empty((len(faces), 3))
            norm = np.empty(len(faces))
            _kernels.face_cross_norm(
                _kernels.readonly(self.vertices), _kernels.readonly(faces), cross, norm
            )
            return Surface(
                vertices=self.vertices,
                faces=faces,
                cross=cross,
                area=0.5 * norm,
                normals=cross / norm[:, None],
                dropped_faces=self.dropped_faces,
                duplicate_faces=self.duplicate_faces,
                duplicates=self.duplicates,
                source=self,
            )

        return self._cached("rewound", compute)

    def _orient(self, orient: str, turn: bool) -> Surface:
        found, inward = self._survey()
        rewind = orient == "auto" and found.wound_inward
        geometry = self._rewound(inward) if rewind else self
        turn = turn and found.turns(orient)
        done = replace(found, turned=turn, rewound=rewind, asked=orient)
        vertices, cross, normals = geometry.vertices, geometry.cross, geometry.normals
        if turn:
            # a proper rotation: the same numbers, two of them negated (exactly)
            vertices = geometry.vertices @ TURN.T
            cross = face_cross(vertices, geometry.faces)
            normals = cross / (2.0 * geometry.area)[:, None]
        return Surface(
            vertices=vertices,
            faces=geometry.faces,
            cross=cross,
            area=geometry.area,
            normals=normals,
            dropped_faces=self.dropped_faces,
            duplicate_faces=self.duplicate_faces,
            duplicates=self.duplicates,
            orientation=done,
            source=self,
            _same_faces=geometry,
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


def check_duplicates(duplicates) -> str:
    """Validate ``duplicates`` (``"drop"`` or ``"keep"``, any case)."""
    return check_choice("duplicates", duplicates, DUPLICATE_MODES)


def repeated_faces(faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """For each face, the first face with its three vertices (in any order), and whether it is
    wound the other way round from that one.

    A face repeats an earlier one where ``first != arange(m)``; the first face
    of each vertex set is the one trimesh's ``unique_faces`` and ariaDNE's
    cleaning keep.  A sort of the faces' sorted vertex triples: O(m log m)
    whatever the vertices' valences.

    Returns
    -------
    first : (m,) int64
    reversed : (m,) bool
    """
    faces = np.asarray(faces)
    m = len(faces)
    first = np.arange(m)
    reverse = np.zeros(m, dtype=bool)
    if m < 2:
        return first, reverse
    faces64 = np.ascontiguousarray(faces, dtype=np.int64)
    n = int(faces64.max()) + 1
    if n < 2**20:  # the sorted triple packed into one integer: one sort instead of three
        packed = np.empty(m, dtype=np.int64)
        _kernels.packed_triples(faces64, n, packed)
        quick = np.sort(packed)  # no repeat (the usual case) is found without the order
        if not (quick[1:] == quick[:-1]).any():
            return first, reverse
        order = np.argsort(packed, kind="stable")  # stable: earlier faces first
        ordered = packed[order]
        same = ordered[1:] == ordered[:-1]
    else:
        key = np.sort(faces64, axis=1)
        order = np.lexsort((key[:, 2], key[:, 1], key[:, 0]))
        ordered = key[order]
        same = np.all(ordered[1:] == ordered[:-1], axis=1)
    if not same.any():
        return first, reverse
    starts = np.r_[True, ~same]
    first[order] = order[np.flatnonzero(starts)][np.cumsum(starts) - 1]  # its group's first
    # the winding's parity: odd permutations of the sorted triple are wound the other way
    a, b, c = faces[:, 0], faces[:, 1], faces[:, 2]
    parity = ((a > b).astype(np.int8) + (a > c) + (b > c)) % 2
    reverse = parity != parity[first]
    return first, reverse


def _warn_duplicates(count: int, reverse: int, total: int, duplicates: str) -> None:
    what = f"{count} of the mesh's {total} faces repeat an earlier face (the same three vertices"
    what += f"; {reverse} of them wound the other way round)" if reverse else ")"
    if duplicates == "drop":
        done = (
            "they were dropped, so that every metric measures each triangle once (the first "
            "listing, and its winding, is kept); duplicates='keep' measures the faces as "
            "listed, as molaR does"
        )
    else:
        done = (
            "they were kept (duplicates='keep', molaR's way): classic DNE, areas and RFI count "
            "them twice and OPC joins no patch across them; duplicates='drop' (the default) "
            "measures each triangle once"
        )
    warnings.warn(f"{what}: {done}", UserWarning, stacklevel=4)


def prepare_surface(mesh, orient: str | None = None, *, duplicates: str = "drop") -> Surface:
    """Read and clean `mesh` as molaR does: zero-area faces dropped, then unused vertices.

    And, by default, faces listed more than once dropped (see `duplicates`).

    Parameters
    ----------
    mesh : Surface, trimesh.Trimesh, str, path-like, or (vertices, faces)
        Never modified.  A :class:`Surface` is used as it is (its
        :attr:`Surface.cleaned` form), not cleaned again (`duplicates` is then
        what it was prepared with).
    orient : {"as-is", "auto"}, optional
        For the metrics that assume the crown points to +z: find which way it
        points and how its faces are wound (:func:`find_orientation`, recorded
        in ``Surface.orientation``) and, with ``"auto"``, rewind faces wound
        inward and turn a crown pointing to -z first (:meth:`Surface.oriented`).
        None: the orientation is not looked at.
    duplicates : {"drop", "keep"}, default "drop"
        A face whose three vertices (in any order, either winding) are those of
        an earlier face repeats it: a second copy of the same triangle.
        ``"drop"`` keeps the first listing only, as ariaDNE's cleaning does
        (so the ``faces`` count of a batch row is what every metric measured);
        ``"keep"`` measures the faces as listed, as molaR does (its classic
        DNE, areas and RFI then count a repeated triangle twice, and its OPC
        joins no patch across it).  Either way a ``UserWarning`` says how
        many there were.

    Raises
    ------
    TypeError, ValueError
        For an unusable mesh or option, or a mesh with no face of non-zero area.
        (Faces too small or too large for single precision are refused by the
        metrics that compute in it, through :func:`molar_face_areas`; classic
        DNE, OPC and ARC measure them right.)

    Warns
    -----
    UserWarning
        When faces repeat earlier faces.
    """
    duplicates = check_duplicates(duplicates)
    if isinstance(mesh, Surface):
        surface = mesh.cleaned
    else:
        vertices, faces = as_arrays(mesh)
        cross = np.empty((len(faces), 3))
        norm = np.empty(len(faces))
        _kernels.face_cross_norm(_kernels.readonly(vertices), _kernels.readonly(faces), cross, norm)
        keep = norm > 0
        kept = int(np.count_nonzero(keep))
        if kept == 0:
            raise ValueError("the mesh has no face of non-zero area")
        dropped = len(faces) - kept
        if dropped:
            faces, cross, norm = faces[keep], cross[keep], norm[keep]
        first, reverse = repeated_faces(faces)
        repeat = first != np.arange(len(faces))
        repeats = int(np.count_nonzero(repeat))
        if repeats:
            _warn_duplicates(repeats, int(np.count_nonzero(reverse)), len(faces), duplicates)
            if duplicates == "drop":
                keep = ~repeat
                faces, cross, norm = faces[keep], cross[keep], norm[keep]
        vertices, faces = drop_unused(vertices, faces)
        surface = Surface(
            vertices=vertices,
            faces=faces,
            cross=cross,
            area=0.5 * norm,
            normals=cross / norm[:, None],
            dropped_faces=dropped,
            duplicate_faces=repeats,
            duplicates=duplicates,
        )
    return surface if orient is None else surface.oriented(orient)


#: Twice a face's area (the norm of its cross product) within which the metrics'
#: single-precision arithmetic (molaR's and doolkit's, which square it in float32) neither
#: underflows nor overflows, with room to spare: the median face must be larger than the
#: first, every face smaller than the second.  A crown in metres or in nanometres is well
#: inside; one scaled by 1e-10 from millimetres gave a slope of 48 instead of 42 and an
#: RFI of 0.55 instead of 1.38, by 1e12 NaN and inf.
SMALLEST_CROSS = 1e-18
LARGEST_CROSS = 1e18


def check_scale(norm: np.ndarray) -> None:
    """Raise a ValueError naming the scale if the faces (``norm``: twice their areas) are
    too small or too large for the metrics' single-precision arithmetic."""
    largest = float(np.max(norm))
    smallest = float(np.min(norm))
    # the median is needed only when the smallest face is too small (the usual crown has none)
    median = smallest if smallest >= SMALLEST_CROSS else float(np.median(norm))
    if median < SMALLEST_CROSS:
        raise ValueError(
            f"the mesh's faces are too small for single-precision arithmetic (median face "
            f"area {median / 2:.3g}): molaR's and doolkit's float32 areas underflow; "
            "rescale the coordinates (to millimetres, say)"
        )
    if not largest <= LARGEST_CROSS:
        raise ValueError(
            f"the mesh's faces are too large for single-precision arithmetic (largest face "
            f"area {largest / 2:.3g}): molaR's and doolkit's float32 areas overflow; "
            "rescale the coordinates (to millimetres, say)"
        )


def molar_face_areas(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Face areas as molaR's mesh reader computes them: in single precision.

    molaR's reader (vcglib, through Rvcg) stores coordinates as 32-bit floats
    and computes each face's area there: the edge vectors, their cross product
    and its norm in single precision.  RFI's 3D area and the weights of the
    mean slope are these areas (as float64, summed in double precision); they
    differ from double-precision areas by about 1e-9 relative on a typical
    crown, more for coordinates far from the origin.

    Raises
    ------
    ValueError
        Faces too small or too large for single precision (``check_scale``).
    """
    area = np.empty(len(faces))
    _kernels.single_precision_areas(
        np.ascontiguousarray(vertices, dtype=np.float32), np.asarray(faces, dtype=np.int64), area
    )
    if len(area):
        check_scale(2.0 * area)  # underflow (zeros) or overflow (inf) in float32
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
    if vertices.dtype == np.float64 and vertices.ndim == 2 and vertices.shape[1] == 3:
        # the row means as numpy's mean(axis=1) computes them, ((x + y) + z) / 3, without
        # its reduction machinery (a quarter of the time; the same numbers)
        mean = ((vertices[:, 0] + vertices[:, 1]) + vertices[:, 2]) / 3.0
        centred = vertices - mean[:, None]
    else:
        centred = vertices - vertices.mean(axis=1, keepdims=True)
    size = float(np.sqrt(np.sum(centred * centred)))
    if not size > 0:
        raise ValueError("the mesh has zero size (all vertices lie on the line x = y = z)")
    return SIZE_TARGET / size
