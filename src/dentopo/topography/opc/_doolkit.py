"""Orientation patch count (OPC) and its rotated mean (OPCR) as doolkit 1.42.2 computes them.

doolkit bins each face by the compass bearing of its normal
(:func:`dentopo.topography.face_bearing`: 0 towards +y, clockwise seen from
+z), joins faces of one bin that share an edge, and counts the groups of at
least ``min_size`` faces.  Its counts equal molaR's (:mod:`._opc`) on
manifold meshes; only the numbering of the bins differs (doolkit's bin 1
starts at bearing 0, i.e. +y).

Face adjacency is built as doolkit builds it, from ``vcgGetEdge(unique =
FALSE)``: every face-edge (its two vertex indices, lower first), those not on
the border kept, sorted by (lower vertex, higher vertex), and paired two by
two in that order.  On a manifold mesh each pair is the two faces of one
interior edge.  An edge used by three or more faces is not a border edge, so
its rows are paired two by two like the others: with an odd number of them,
the last is paired with the first row of the next edge, and every pair after
it joins faces that need not share an edge.  This module reproduces that
(rows of one edge in face order, then edge order within a face, as vcglib
lists them; a last unpaired row joins nothing).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import trimesh

from ..._html_repr import result_html
from ..._jit import njit
from .._lazy import LazyMesh
from .._parameters import check_finite, check_int
from ..slope._doolkit import DoolkitMesh, doolkit_mesh
from ..surface._kernels import _find
from ..surface._orientation import Orientation, check_orient

#: doolkit's default number of bins.
DOOLKIT_BINS = 8


# --- kernels ------------------------------------------------------------------------------


@njit(cache=True)
def doolkit_pairs(faces, n_vertices, pairs):
    """doolkit's face-face edges (see the module) into `pairs` (3m/2 rows); returns how many.

    Rows ``(min(a, b), max(a, b), f)`` for edge ``(faces[f, j], faces[f, (j + 1) % 3])``,
    listed face by face; a stable sort by the two vertices (counting sort on
    the lower, insertion sort on the higher within it); rows of an edge used
    once (border) dropped; the rest paired two by two.
    """
    m = faces.shape[0]
    rows = 3 * m
    start = np.zeros(n_vertices + 1, dtype=np.int64)
    for f in range(m):
        for j in range(3):
            a, b = faces[f, j], faces[f, (j + 1) % 3]
            start[min(a, b) + 1] += 1
    for v in range(n_vertices):
        start[v + 1] += start[v]
    fill = start[:-1].copy()
    low = np.empty(rows, dtype=np.int64)
    high = np.empty(rows, dtype=np.int64)
    face = np.empty(rows, dtype=np.int64)
    for f in range(m):
        for j in range(3):
            a, b = faces[f, j], faces[f, (j + 1) % 3]
            lo = min(a, b)
            p = fill[lo]
            low[p] = lo
            high[p] = max(a, b)
            face[p] = f
            fill[lo] = p + 1
    for v in range(n_vertices):
        for p in range(start[v] + 1, start[v + 1]):
            h, g = high[p], face[p]
            q = p
            while q > start[v] and high[q - 1] > h:
                high[q] = high[q - 1]
                face[q] = face[q - 1]
                q -= 1
            high[q] = h
            face[q] = g
    count = 0
    pending = -1
    p = 0
    while p < rows:
        q = p + 1
        while q < rows and low[q] == low[p] and high[q] == high[p]:
            q += 1
        if q - p > 1:
            for r in range(p, q):
                if pending < 0:
                    pending = face[r]
                else:
                    pairs[count, 0] = pending
                    pairs[count, 1] = face[r]
                    count += 1
                    pending = -1
        p = q
    return count


@njit(cache=True)
def bin_patches(pairs, face_bin, face_patch):
    """Faces of one bin (not 0) joined across `pairs`; labels into `face_patch`.

    Patches are numbered in the order of their first face; a face in no bin
    (bin 0) gets -1.  Returns the number of patches.
    """
    m = face_bin.shape[0]
    parent = np.arange(m)
    for e in range(pairs.shape[0]):
        a, b = pairs[e, 0], pairs[e, 1]
        if face_bin[a] != 0 and face_bin[a] == face_bin[b]:
            ra, rb = _find(parent, a), _find(parent, b)
            if ra != rb:
                parent[max(ra, rb)] = min(ra, rb)
    label = np.full(m, -1, dtype=np.int64)
    patches = 0
    for f in range(m):
        if face_bin[f] == 0:
            face_patch[f] = -1
            continue
        root = _find(parent, f)
        if label[root] < 0:
            label[root] = patches
            patches += 1
        face_patch[f] = label[root]
    return patches


@njit(cache=True)
def bin_faces(bearing, edges, face_bin):
    """doolkit's bin of each bearing into `face_bin` (:func:`face_bins`, compiled).

    Bin i (1..bins) is ``edges[i-1] <= b < edges[i]``, or ``b < edges[i] - 360``
    when ``edges[i] >= 360``; the first bin that holds a bearing wins, 0 if none.
    """
    bins = edges.shape[0] - 1
    for f in range(bearing.shape[0]):
        b = bearing[f]
        face_bin[f] = 0
        for i in range(1, bins + 1):
            if edges[i - 1] <= b < edges[i]:
                face_bin[f] = i
                break
        if face_bin[f] == 0:
            for i in range(1, bins + 1):
                if edges[i] >= 360.0 and b < edges[i] - 360.0:
                    face_bin[f] = i
                    break


@njit(cache=True)
def opc_total(pairs, bearing, edges, min_size, face_bin, face_patch):
    """The number of patches of at least `min_size` faces at one set of bin edges."""
    bin_faces(bearing, edges, face_bin)
    patches = bin_patches(pairs, face_bin, face_patch)
    size = np.zeros(patches, dtype=np.int64)
    for f in range(face_patch.shape[0]):
        if face_patch[f] >= 0:
            size[face_patch[f]] += 1
    total = 0
    for p in range(patches):
        if size[p] >= min_size:
            total += 1
    return total


# --- results ------------------------------------------------------------------------------


@dataclass(frozen=True)
class DoolkitOPCResult:
    """doolkit's orientation patch count for one mesh at one rotation (``opc``).

    Per-face arrays follow the faces of the mesh as doolkit reads it (see
    :mod:`dentopo.topography.slope._doolkit`); per-patch arrays follow the labels of
    ``face_patch``.

    Attributes
    ----------
    opc : int
        Number of counted patches (the sum of ``bins``).
    bins : tuple of int
        Counted patches in each bin; bin 1 starts at bearing ``rotation``
        (0 = +y at rotation 0), the next clockwise seen from +z.
    rotation : float
        Degrees added to the bin edges.
    min_size : int
        Smallest face count of a counted patch.
    vertices, faces : int
        Vertex and face counts of the mesh measured.
    face_bearing : (m,) float64
        Each face's orientation, degrees in [0, 360] (:func:`face_bearing`).
    face_bin : (m,) int64
        Each face's bin, 1..bins, or 0 for a face in no bin (see :func:`doolkit_opc`).
    face_patch : (m,) int64
        Each face's patch label, 0..P-1 in the order of each patch's first
        face; -1 for a face in no bin.
    patch_bin, patch_faces : (P,) int64
        Each patch's bin and face count.
    patch_counted : (P,) bool
        Whether the patch counts towards ``opc``.
    mesh : trimesh.Trimesh
        The mesh the per-face arrays refer to (a private copy; turned to +z if
        ``orient="auto"`` turned it).
    orientation : Orientation
        Which way the crown points and whether it was turned before measuring.
    """

    opc: int
    bins: tuple[int, ...]
    rotation: float
    min_size: int
    vertices: int
    faces: int
    face_bearing: np.ndarray = field(repr=False, compare=False)
    face_bin: np.ndarray = field(repr=False, compare=False)
    face_patch: np.ndarray = field(repr=False, compare=False)
    patch_bin: np.ndarray = field(repr=False, compare=False)
    patch_faces: np.ndarray = field(repr=False, compare=False)
    patch_counted: np.ndarray = field(repr=False, compare=False)
    mesh: trimesh.Trimesh = field(default=LazyMesh(), repr=False, compare=False)
    orientation: Orientation | None = field(default=None, compare=False)

    def to_dict(self) -> dict:
        """The table fields: ``opc`` and ``opc_bin1`` .. ``opc_bin<bins>``."""
        row = {"opc": self.opc}
        row.update({f"opc_bin{k}": n for k, n in enumerate(self.bins, start=1)})
        return row

    def _repr_html_(self) -> str:
        """A compact table for notebooks: values, settings, arrays summarised."""
        return result_html(self)


@dataclass(frozen=True)
class DoolkitOPCRResult:
    """doolkit's rotated orientation patch count for one mesh (``opcr``).

    Attributes
    ----------
    opcr : float
        Mean of ``opc_values``, not rounded (doolkit's plain ``mean``; molaR
        rounds to 2 decimals).
    rotations : tuple of float
        The rotations, degrees: ``(j - 1) * 360 / bins**2`` for j = 1..bins.
    opc_values : tuple of int
        OPC at each rotation.
    bins, min_size : int
        The settings used.
    vertices, faces : int
        Vertex and face counts of the mesh measured.
    first : DoolkitOPCResult
        The full OPC result at rotation 0 (per-face bins and patches).
    orientation : Orientation
        Which way the crown points and whether it was turned before measuring.
    """

    opcr: float
    rotations: tuple[float, ...]
    opc_values: tuple[int, ...]
    bins: int
    min_size: int
    vertices: int
    faces: int
    first: DoolkitOPCResult = field(repr=False, compare=False)
    orientation: Orientation | None = field(default=None, compare=False)

    @property
    def mesh(self) -> trimesh.Trimesh:
        """The mesh the per-face arrays of :attr:`first` refer to."""
        return self.first.mesh

    def to_dict(self) -> dict:
        """The table fields: ``opcr`` and ``opcr_rot0`` .. ``opcr_rot<bins - 1>``."""
        row = {"opcr": self.opcr}
        row.update({f"opcr_rot{j}": n for j, n in enumerate(self.opc_values)})
        return row

    def _repr_html_(self) -> str:
        """A compact table for notebooks: values, settings, arrays summarised."""
        return result_html(self)


# --- the computation ----------------------------------------------------------------------


def bin_edges(bins: int, rotation: float) -> np.ndarray:
    """doolkit's bin edges: ``rotation + (i - 1) * 360 / bins`` for i = 1..bins + 1."""
    return rotation + np.arange(bins + 1) * 360.0 / bins


def face_bins(bearing: np.ndarray, bins: int, rotation: float) -> np.ndarray:
    """doolkit's bin (1..bins) of each face bearing, 0 for none (see :func:`doolkit_opc`)."""
    face_bin = np.empty(len(bearing), dtype=np.int64)
    bin_faces(np.ascontiguousarray(bearing, dtype=np.float64), bin_edges(bins, rotation), face_bin)
    return face_bin


def _pairs(dm: DoolkitMesh) -> np.ndarray:
    def compute():
        pairs = np.empty((3 * len(dm.faces) // 2 + 1, 2), dtype=np.int64)
        count = doolkit_pairs(dm.faces, len(dm.vertices), pairs)
        return pairs[:count].copy()

    return dm.cached("doolkit_pairs", compute)


def _opc_of(dm, pairs, bins, rotation, min_size, mesh) -> DoolkitOPCResult:
    bearing = dm.bearing
    face_bin = face_bins(bearing, bins, rotation)
    face_patch = np.empty(len(face_bin), dtype=np.int64)
    n_patches = bin_patches(pairs, face_bin, face_patch)
    binned = face_patch >= 0
    patch_bin = np.zeros(n_patches, dtype=np.int64)
    patch_bin[face_patch[binned]] = face_bin[binned]
    patch_faces = np.bincount(face_patch[binned], minlength=n_patches).astype(np.int64)
    counted = patch_faces >= min_size
    per_bin = np.bincount(patch_bin[counted], minlength=bins + 1)[1:]
    return DoolkitOPCResult(
        opc=int(per_bin.sum()),
        bins=tuple(int(n) for n in per_bin),
        rotation=rotation,
        min_size=min_size,
        vertices=len(dm.vertices),
        faces=len(dm.faces),
        face_bearing=bearing.copy(),
        face_bin=face_bin,
        face_patch=face_patch,
        patch_bin=patch_bin,
        patch_faces=patch_faces,
        patch_counted=counted,
        mesh=dm.mesh_later() if mesh is None else mesh,
        orientation=dm.orientation,
    )


def _check_rotation(rotation, bins: int) -> float:
    rotation = check_finite("rotation", rotation)
    if rotation > 360.0 / bins:
        raise ValueError(
            f"rotation must be at most 360 / bins = {360.0 / bins!r} degrees (doolkit's bins "
            f"would overlap beyond it); got {rotation!r}"
        )
    return rotation


def doolkit_opc(
    mesh,
    *,
    bins: int = DOOLKIT_BINS,
    min_size: int = 3,
    rotation: float = 0.0,
    orient: str = "auto",
) -> DoolkitOPCResult:
    """Orientation patch count, as doolkit 1.42.2's ``opc`` computes it.

    1. **Mesh and bearings.** Mesh as ``vcgImport`` reads it, unit face
       normals in double precision (see :func:`doolkit_slope`); each face's
       bearing :func:`face_bearing` (0 towards +y, 90 towards +x, clockwise
       seen from +z), in [0, 360].
    2. **Bins.** With edges ``e_i = rotation + (i - 1) * 360 / bins``, bin i
       (1..bins) holds the faces with ``e_i <= bearing < e_(i+1)``; when
       ``e_(i+1) >= 360`` it also holds those with ``bearing < e_(i+1) - 360``
       (the wrap-around).  Comparisons are exact.  A face in none (a bearing
       of exactly 360 at rotation 0, or one left uncovered by a negative
       rotation) is in no patch.  No slope threshold.
    3. **Patches.** Faces of one bin joined along doolkit's face-face edges
       (see :mod:`dentopo.topography.opc._doolkit`: on a manifold mesh, two
       faces sharing an edge; a shared vertex is not enough); a patch is a
       connected group (igraph's components).  Patches of at least
       `min_size` faces count.

    Parameters
    ----------
    mesh : trimesh.Trimesh, str, path-like, (vertices, faces), or Surface
        Never modified.
    bins : int, default 8
        Number of bins, at least 1.
    min_size : int, default 3
        Smallest face count of a counted patch, at least 1 (with 1 a lone
        face counts: doolkit's handling of faces without a same-bin
        neighbour is not described, so this is the plain definition).
    rotation : float, default 0.0
        Degrees added to the bin edges (clockwise seen from +z), at most
        ``360 / bins`` (beyond it doolkit's bins overlap).
    orient : {"auto", "as-is"}, default "auto"
        ``"as-is"`` measures the mesh as it lies (doolkit's behaviour) and
        warns if the crown points to -z; ``"auto"`` (the default) turns such a crown first.

    Returns
    -------
    DoolkitOPCResult

    Raises
    ------
    TypeError, ValueError
        For an unusable mesh or parameter; the message names it.

    Warns
    -----
    UserWarning
        When the crown is measured pointing to -z (``orient="as-is"``), or
        when it is flat or closed (never turned).

    References
    ----------
    Evans A. R., Wilson G. P., Fortelius M., Jernvall J. (2007). High-level
    similarity of dentitions in carnivorans and rodents. Nature 445, 78-81.
    doi:10.1038/nature05433

    Examples
    --------
    >>> import trimesh
    >>> from dentopo.topography import doolkit_opc
    >>> result = doolkit_opc(trimesh.creation.icosphere(subdivisions=3))
    >>> result.opc == sum(result.bins)
    True
    """
    bins = check_int("bins", bins, low=1)
    min_size = check_int("min_size", min_size, low=1)
    rotation = _check_rotation(rotation, bins)
    dm = doolkit_mesh(mesh, check_orient(orient))
    dm.warn_orientation()
    return _opc_of(dm, _pairs(dm), bins, rotation, min_size, None)


def doolkit_opcr(
    mesh, *, bins: int = DOOLKIT_BINS, min_size: int = 3, orient: str = "auto"
) -> DoolkitOPCRResult:
    """Rotated orientation patch count, as doolkit 1.42.2's ``opcr`` computes it.

    :func:`doolkit_opc` at the rotations ``(j - 1) * 360 / bins**2`` degrees,
    j = 1..bins (0, 5.625, ..., 39.375 for 8 bins); OPCR is the plain mean
    of the totals, **not rounded** (molaR's ``OPCr`` rounds to 2 decimals).
    The mesh is read and its face-face edges built once.

    Parameters
    ----------
    mesh : trimesh.Trimesh, str, path-like, (vertices, faces), or Surface
        Never modified.
    bins, min_size, orient
        As for :func:`doolkit_opc`.

    Returns
    -------
    DoolkitOPCRResult

    Raises
    ------
    TypeError, ValueError
        For an unusable mesh or parameter; the message names it.

    Warns
    -----
    UserWarning
        When the crown is measured pointing to -z (``orient="as-is"``), or
        when it is flat or closed (never turned).

    Examples
    --------
    >>> import trimesh
    >>> from dentopo.topography import doolkit_opcr
    >>> doolkit_opcr(trimesh.creation.icosphere(subdivisions=3)).rotations[:3]
    (0.0, 5.625, 11.25)
    """
    bins = check_int("bins", bins, low=1)
    min_size = check_int("min_size", min_size, low=1)
    dm = doolkit_mesh(mesh, check_orient(orient))
    dm.warn_orientation()
    pairs = _pairs(dm)
    rotations = tuple(float((j * 360.0) / bins**2) for j in range(bins))
    first = _opc_of(dm, pairs, bins, rotations[0], min_size, None)
    face_bin = np.empty(len(dm.faces), dtype=np.int64)
    face_patch = np.empty(len(dm.faces), dtype=np.int64)
    values = (first.opc,)
    for r in rotations[1:]:
        total = opc_total(pairs, dm.bearing, bin_edges(bins, r), min_size, face_bin, face_patch)
        values = (*values, int(total))
    return DoolkitOPCRResult(
        opcr=sum(values) / bins,
        rotations=rotations,
        opc_values=values,
        bins=bins,
        min_size=min_size,
        vertices=len(dm.vertices),
        faces=len(dm.faces),
        first=first,
        orientation=dm.orientation,
    )
