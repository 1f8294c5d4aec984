"""Orientation patch count (OPC) and its rotated mean (OPCR) as molaR 6.0 computes them.

Each face is put in one of eight bins by the compass direction (aspect) its
normal faces in the x-y plane; faces of one bin that meet along an edge form
a patch; OPC counts the patches large enough to matter.  OPCR repeats OPC with
the aspects rotated by a few small angles and averages the counts, which
makes the count less dependent on how the crown happens to be turned.

Every convention below is molaR's (``OPC`` and ``OPCr``), quirks included,
so that the counts match molaR's exactly.  The edge-to-face incidence of a
mesh is computed once; the rotations of OPCR only redo the binning and the
patch labelling.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from ..._html_repr import result_html
from .._lazy import LazyMesh
from .._metrics import rotation_key
from .._metrics import rotations as opcr_rotations
from .._parameters import check_finite, check_int, check_min_area, check_opcr_options
from ..surface import _kernels
from ..surface._molar import Surface, prepare_surface
from ..surface._orientation import Orientation, check_orient

if TYPE_CHECKING:
    import trimesh

#: Number of aspect bins.
BINS = 8

#: Bin breaks ``-pi, -3pi/4, ..., pi``; bin k (1..8) is ``(BREAKS[k-1], BREAKS[k]]``.
BREAKS = np.array(
    [
        -np.pi,
        -3 * np.pi / 4,
        -np.pi / 2,
        -np.pi / 4,
        0.0,
        np.pi / 4,
        np.pi / 2,
        3 * np.pi / 4,
        np.pi,
    ]
)

#: Scalar fields of OPC, in the order of output tables.
OPC_FIELDS = ("opc", *(f"opc_bin{k}" for k in range(1, BINS + 1)))


@dataclass(frozen=True)
class OPCResult:
    """molaR's orientation patch count for one mesh at one rotation.

    Per-face arrays follow the faces of the cleaned mesh (faces of zero area
    dropped, then unused vertices; neither reorders faces); per-patch arrays
    follow the patch labels of ``face_patch``.

    Attributes
    ----------
    opc : int
        Number of counted patches (the sum of ``bin_counts``).
    bin_counts : tuple of 8 int
        Counted patches in each bin, bins 1..8.
    rotation : float
        Degrees the aspects were rotated by, counter-clockwise seen from +z.
    min_faces : int
        Smallest face count of a counted patch (used when ``min_area == 0``).
    min_area : float
        When positive, a patch is counted if its area exceeds this fraction
        of the total surface area (``min_faces`` is then ignored).
    vertices, faces : int
        Vertex and face counts of the cleaned mesh.
    face_bin : (m,) int64
        Each face's aspect bin, 1..8 (see :func:`opc`).
    face_patch : (m,) int64
        Each face's patch label, 0..P-1, numbered in the order of each
        patch's first face.
    patch_bin, patch_faces : (P,) int64
        Each patch's bin and face count.
    patch_area : (P,) float64
        Each patch's area, mesh units.
    patch_counted : (P,) bool
        Whether the patch counts towards ``opc``.
    mesh : trimesh.Trimesh
        The cleaned mesh the per-face arrays refer to (a private copy; turned
        to +z if ``orient="auto"`` turned it).
    orientation : Orientation
        Which way the crown points (``+z``, ``-z`` or ``undetermined``) and
        whether it was turned before measuring (``orient="auto"``).
    """

    opc: int
    bin_counts: tuple[int, ...]
    rotation: float
    min_faces: int
    min_area: float
    vertices: int
    faces: int
    face_bin: np.ndarray = field(repr=False, compare=False)
    face_patch: np.ndarray = field(repr=False, compare=False)
    patch_bin: np.ndarray = field(repr=False, compare=False)
    patch_faces: np.ndarray = field(repr=False, compare=False)
    patch_area: np.ndarray = field(repr=False, compare=False)
    patch_counted: np.ndarray = field(repr=False, compare=False)
    mesh: trimesh.Trimesh = field(default=LazyMesh(), repr=False, compare=False)
    orientation: Orientation | None = field(default=None, compare=False)

    def to_dict(self) -> dict:
        """The table fields: ``opc`` and ``opc_bin1`` .. ``opc_bin8``."""
        row = {"opc": self.opc}
        row.update({f"opc_bin{k}": n for k, n in enumerate(self.bin_counts, start=1)})
        return row

    def _repr_html_(self) -> str:
        """A compact table for notebooks: values, settings, arrays summarised."""
        return result_html(self)


@dataclass(frozen=True)
class OPCRResult:
    """molaR's rotated orientation patch count (OPCR) for one mesh.

    Attributes
    ----------
    opcr : float
        Mean of ``opc_values``, rounded to 2 decimals (half to even on the
        exact binary value, as R's ``round``).
    rotations : tuple of float
        The rotations, degrees: ``0, step, ..., (steps - 1) * step``.
    opc_values : tuple of int
        OPC at each rotation.
    steps : int
    step : float
    min_faces : int
    min_area : float
        The settings used (see :func:`opc`).
    vertices, faces : int
        Vertex and face counts of the cleaned mesh.
    first : OPCResult
        The full OPC result at rotation 0 (per-face bins and patches, for pictures).
    orientation : Orientation
        Which way the crown points (``+z``, ``-z`` or ``undetermined``) and
        whether it was turned before measuring (``orient="auto"``).
    """

    opcr: float
    rotations: tuple[float, ...]
    opc_values: tuple[int, ...]
    steps: int
    step: float
    min_faces: int
    min_area: float
    vertices: int
    faces: int
    first: OPCResult = field(repr=False, compare=False)
    orientation: Orientation | None = field(default=None, compare=False)

    @property
    def mesh(self) -> trimesh.Trimesh:
        """The cleaned mesh the per-face arrays of :attr:`first` refer to."""
        return self.first.mesh

    def to_dict(self) -> dict:
        """The table fields: ``opcr`` and one ``opc_<degrees>`` per rotation (``opc_5.625``)."""
        row = {"opcr": self.opcr}
        for rotation, value in zip(self.rotations, self.opc_values, strict=True):
            row[rotation_key(rotation)] = value
        return row

    def _repr_html_(self) -> str:
        """A compact table for notebooks: values, settings, arrays summarised."""
        return result_html(self)


# --- parameters ---------------------------------------------------------------------------


# --- the computation ----------------------------------------------------------------------


class _Incidence:
    """Which faces share which edges: computed once per mesh, used at every rotation.

    The surface's edge groups (:meth:`Surface.edge_groups`): joins depend on
    how many faces of one bin use an edge.
    """

    def __init__(self, surface: Surface):
        self.group_start, self.group_edge, self.groups = surface.edge_groups()
        self.faces = len(surface.faces)

    def patches(self, face_bin: np.ndarray) -> tuple[int, np.ndarray]:
        """The number of patches and each face's patch, numbered in the order of first faces.

        Two faces of one bin are joined across an edge used by exactly two
        faces of that bin.
        """
        face_patch = np.empty(self.faces, dtype=np.int64)
        count = _kernels.patch_labels(
            self.group_start, self.group_edge, self.groups, face_bin, BINS, face_patch
        )
        return count, face_patch


def face_bins(normals: np.ndarray, rotation: float) -> np.ndarray:
    """molaR's aspect bin (1..8) of each face, with the aspects rotated by `rotation` degrees.

    The normal's x-y part is rotated counter-clockwise, ``x' = x cos r - y sin r``,
    ``y' = x sin r + y cos r`` with ``r = rotation * pi / 180``; the aspect
    ``atan2(y', x')`` falls in bin k when ``BREAKS[k-1] < aspect <= BREAKS[k]``.
    An aspect of exactly ``-pi`` is in no bin: the face takes the bin of the
    next face in storage order that has one, wrapping round to the first
    faces (molaR's behaviour).  If no face has a bin (every aspect is
    ``-pi``), every face gets bin 8, the bin of ``pi``, the same direction.
    """
    r = rotation * np.pi / 180.0
    cos_r, sin_r = np.cos(r), np.sin(r)
    x, y = normals[:, 0], normals[:, 1]
    aspect = np.arctan2(x * sin_r + y * cos_r, x * cos_r - y * sin_r)
    bins = np.searchsorted(BREAKS, aspect, side="left").astype(np.int64)
    missing = np.flatnonzero(bins == 0)
    if len(missing):
        have = np.flatnonzero(bins != 0)
        if len(have) == 0:
            bins[:] = BINS
        else:
            nxt = np.searchsorted(have, missing, side="right") % len(have)
            bins[missing] = bins[have[nxt]]
    return bins


def _opc_of(
    surface: Surface,
    incidence: _Incidence,
    rotation: float,
    min_faces: int,
    min_area: float,
    mesh: trimesh.Trimesh | None,
) -> OPCResult:
    m = len(surface.faces)
    face_bin = face_bins(surface.normals, rotation)
    n_patches, face_patch = incidence.patches(face_bin)
    patch_bin = np.empty(n_patches, dtype=np.int64)
    patch_bin[face_patch] = face_bin
    patch_faces = np.bincount(face_patch, minlength=n_patches).astype(np.int64)
    patch_area = np.bincount(face_patch, weights=surface.area, minlength=n_patches)
    if min_area > 0:
        counted = patch_area > min_area * surface.total_area
    else:
        counted = patch_faces >= min_faces
    bin_counts = np.bincount(patch_bin[counted], minlength=BINS + 1)[1:]
    return OPCResult(
        opc=int(bin_counts.sum()),
        bin_counts=tuple(int(n) for n in bin_counts),
        rotation=rotation,
        min_faces=min_faces,
        min_area=min_area,
        vertices=len(surface.vertices),
        faces=m,
        face_bin=face_bin,
        face_patch=face_patch,
        patch_bin=patch_bin,
        patch_faces=patch_faces,
        patch_area=patch_area,
        patch_counted=counted,
        mesh=surface.mesh_later() if mesh is None else mesh,
        orientation=surface.orientation,
    )


def opc(
    mesh,
    rotation: float = 0.0,
    min_faces: int = 3,
    min_area: float = 0.0,
    *,
    orient: str = "auto",
) -> OPCResult:
    """Orientation patch count, as molaR 6.0's ``OPC`` computes it.

    1. **Mesh.** Files are read with :func:`dentopo.mesh.load_mesh`
       (duplicate vertices merged, as molaR's reader does); then molaR's
       cleaning (faces of zero area dropped, then vertices no face uses).
       The occlusal plane is taken to be the x-y plane, the crown pointing
       to +z (see `orient`).  The caller's mesh is never modified.
    2. **Aspect.** Unit face normal ``n`` from ``(v2 - v1) x (v3 - v1)`` in
       the face's stored vertex order; its x-y part is rotated by `rotation`
       degrees counter-clockwise (``r = rotation * pi / 180``,
       ``x' = x cos r - y sin r``, ``y' = x sin r + y cos r``, applied even
       at 0) and the aspect is ``atan2(y', x')``.
    3. **Bins.** Eight bins ``(a, b]`` with breaks ``-pi, -3pi/4, ..., pi``,
       numbered 1..8 from ``-pi``.  A face whose aspect is exactly ``-pi``
       takes the bin of the next face in storage order that has one,
       wrapping round (molaR's behaviour).  There is no slope threshold:
       faces pointing straight up are binned by their tiny x-y part.
    4. **Patches.** Two faces of one bin are joined when they share an edge
       (the same two vertex indices) used by exactly two faces *of that
       bin*; an edge used by three or more faces of the bin joins nothing.
       A patch is a connected group of joined faces.
    5. **Count.** A patch counts when it has at least `min_faces` faces or,
       if `min_area` is positive, when its area exceeds `min_area` times the
       total surface area.  OPC is the number of counted patches.

    Parameters
    ----------
    mesh : trimesh.Trimesh, str, path-like, (vertices, faces), or Surface
        A triangle mesh, or one prepared once for several metrics
        (:func:`dentopo.topography.prepare_surface`).  Never modified.
    rotation : float, default 0.0
        Degrees to rotate the aspects by (counter-clockwise seen from +z).
    min_faces : int, default 3
        Smallest face count of a counted patch (molaR's ``minimum_faces``);
        0 and 1 both count every patch.
    min_area : float, default 0.0
        When positive, count the patches with area greater than this fraction
        of the total surface area instead (molaR's ``minimum_area``); in [0, 1).
    orient : {"auto", "as-is"}, default "auto"
        The metric assumes the crown points to +z and its faces are wound
        outward.  ``"auto"`` (the default) rewinds faces wound inward and
        turns a crown pointing to -z (away from its open base) first; a flat
        or closed surface is never turned, and is warned about.  ``"as-is"``
        measures the mesh as it lies, as molaR does (use it to reproduce
        molaR's numbers), and warns if the crown points to -z or its faces
        are wound inward.  See :func:`dentopo.topography.find_orientation`;
        either way the result's ``orientation`` says what was found and done.

    Returns
    -------
    OPCResult

    Raises
    ------
    TypeError, ValueError
        For an unusable mesh or parameter; the message names it.

    Warns
    -----
    UserWarning
        When the crown is measured pointing to -z (``orient="as-is"``); when
        its faces are wound inward (rewound or not); when it is flat or closed.

    References
    ----------
    Evans A. R., Wilson G. P., Fortelius M., Jernvall J. (2007). High-level
    similarity of dentitions in carnivorans and rodents. Nature 445, 78-81.
    doi:10.1038/nature05433

    Pampush J. D., Winchester J. M., Morse P. E., Vining A. Q., Boyer D. M.,
    Kay R. F. (2016). Introducing molaR: a new R package for quantitative
    topographic analysis of teeth (and other topographic surfaces). Journal of
    Mammalian Evolution 23, 397-412. doi:10.1007/s10914-016-9326-0

    Examples
    --------
    >>> import trimesh
    >>> from dentopo.topography import opc
    >>> result = opc(trimesh.creation.icosphere(subdivisions=3))
    >>> result.opc == sum(result.bin_counts)
    True
    """
    rotation = check_finite("rotation", rotation)
    min_faces = check_int("min_faces", min_faces, low=0)
    min_area = check_min_area(min_area)
    surface = prepare_surface(mesh, orient=check_orient(orient))
    surface.warn_orientation()
    incidence = _Incidence(surface)
    return _opc_of(surface, incidence, rotation, min_faces, min_area, None)


def opcr(
    mesh,
    steps: int = 8,
    step: float = 5.625,
    min_faces: int = 3,
    min_area: float = 0.0,
    *,
    orient: str = "auto",
) -> OPCRResult:
    """Rotated orientation patch count (OPCR), as molaR 6.0's ``OPCr`` computes it.

    OPC (see :func:`opc`, same `min_faces` and `min_area`) at the rotations
    ``0, step, 2 * step, ..., (steps - 1) * step`` degrees; OPCR is their
    mean rounded to 2 decimals, half to even on the exact binary value (as
    R's ``round``: a mean of 57.125 gives 57.12).  The mesh is prepared and
    its edges indexed once; each rotation redoes only the binning and the
    patches.

    Parameters
    ----------
    mesh : trimesh.Trimesh, str, path-like, (vertices, faces), or Surface
        A triangle mesh, or one prepared once for several metrics
        (:func:`dentopo.topography.prepare_surface`).  Never modified.
    steps : int, default 8
        Number of rotations (molaR's ``Steps``), at least 1.
    step : float, default 5.625
        Degrees between rotations (molaR's ``stepSize``).
    min_faces : int, default 3
    min_area : float, default 0.0
    orient : {"auto", "as-is"}, default "auto"
        As for :func:`opc`.

    Returns
    -------
    OPCRResult

    Raises
    ------
    TypeError, ValueError
        For an unusable mesh or parameter; the message names it.

    Warns
    -----
    UserWarning
        When the crown is measured pointing to -z (``orient="as-is"``); when
        its faces are wound inward (rewound or not); when it is flat or closed.

    References
    ----------
    Evans A. R., Jernvall J. (2009). Patterns and constraints in carnivoran
    and rodent dental complexity and tooth size. Journal of Vertebrate
    Paleontology 29 (suppl.), 92A.

    Pampush J. D., Winchester J. M., Morse P. E., Vining A. Q., Boyer D. M.,
    Kay R. F. (2016). Introducing molaR: a new R package for quantitative
    topographic analysis of teeth (and other topographic surfaces). Journal of
    Mammalian Evolution 23, 397-412. doi:10.1007/s10914-016-9326-0

    Examples
    --------
    >>> import trimesh
    >>> from dentopo.topography import opcr
    >>> result = opcr(trimesh.creation.icosphere(subdivisions=3))
    >>> result.rotations
    (0.0, 5.625, 11.25, 16.875, 22.5, 28.125, 33.75, 39.375)
    >>> sorted(result.to_dict())[:3]
    ['opc_0', 'opc_11.25', 'opc_16.875']
    """
    steps, step = check_opcr_options(steps, step, names=("steps", "step"))
    min_faces = check_int("min_faces", min_faces, low=0)
    min_area = check_min_area(min_area)
    surface = prepare_surface(mesh, orient=check_orient(orient))
    surface.warn_orientation()
    incidence = _Incidence(surface)
    cleaned = surface.mesh_later()
    rotations = opcr_rotations(steps, step)
    results = [_opc_of(surface, incidence, r, min_faces, min_area, cleaned) for r in rotations]
    values = tuple(result.opc for result in results)
    return OPCRResult(
        opcr=round(sum(values) / steps, 2),
        rotations=rotations,
        opc_values=values,
        steps=steps,
        step=step,
        min_faces=min_faces,
        min_area=min_area,
        vertices=len(surface.vertices),
        faces=len(surface.faces),
        first=results[0],
        orientation=surface.orientation,
    )
