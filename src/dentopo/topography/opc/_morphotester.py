"""Orientation patch count rotated (OPCR) as MorphoTester 1.1.1 computes it.

MorphoTester (Winchester 2016; GPL-2) is reproduced from a description of its method
(``docs/MORPHOTESTER.md`` of the shared data), never from its code.  It reproduces every
count of MorphoTester's sample results and unit tests.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy import sparse
from scipy.sparse.csgraph import connected_components

from ..._html_repr import result_html
from ...mesh import as_arrays
from .._parameters import check_min_patch
from ..surface import _morphotester as mt

#: Rotations about z: 8 turns of 5.625 degrees, each applied to the last.
STEPS = 8
STEP = 5.625

#: Aspect bins: 8 of 45 degrees centred on 0, 45, ..., 315 (aspect anticlockwise from +x).
BINS = 8

#: Scalar fields (:meth:`MorphoTesterOPCRResult.to_dict`), in the order of output tables.
MORPHOTESTER_OPCR_FIELDS = (
    "opcr",
    *(f"opc_{STEP * k:g}" for k in range(STEPS)),
    "min_patch",
)


@dataclass(frozen=True)
class MorphoTesterOPCRResult:
    """MorphoTester 1.1.1's OPCR for one mesh.

    Attributes
    ----------
    opcr : float
        The mean of the 8 OPC values, unrounded (a multiple of 0.125).
    opc : tuple of 8 int
        OPC at each rotation.
    rotations : tuple of 8 float
        The rotations, degrees anticlockwise about z: 0, 5.625, ..., 39.375.
    min_patch : int
        The smallest face count of a counted patch.
    face_bins : (m,) int8
        Each face's aspect bin at rotation 0, 0..7 (bin k centred on ``45 k`` degrees
        anticlockwise from +x), -1 for a face in no bin (unit normal with x exactly 0).
        Read-only.
    """

    opcr: float
    opc: tuple[int, ...]
    rotations: tuple[float, ...]
    min_patch: int
    face_bins: np.ndarray = field(repr=False, compare=False)

    def __post_init__(self):
        self.face_bins.flags.writeable = False

    def to_dict(self) -> dict:
        """``opcr``, one ``opc_<degrees>`` per rotation (``opc_5.625``), and ``min_patch``."""
        row = {"opcr": self.opcr}
        for rotation, value in zip(self.rotations, self.opc, strict=True):
            row[f"opc_{rotation:g}"] = value
        row["min_patch"] = self.min_patch
        return row

    def _repr_html_(self) -> str:
        """A compact table for notebooks: values, settings, arrays summarised."""
        return result_html(self)


def aspect(normals: np.ndarray) -> np.ndarray:
    """Degrees in [0, 360) anticlockwise from +x: ``atan2(n_y, n_x)``, negatives + 360."""
    degrees = np.degrees(np.arctan2(normals[:, 1], normals[:, 0]))
    return np.where(degrees < 0, degrees + 360.0, degrees)


def aspect_bin(degrees) -> np.ndarray:
    """The bin of an aspect: ``floor(((degrees + 22.5) mod 360) / 45)``, 0..7.

    Each bin includes its lower edge: 22.5 is bin 1; 337.5 and 360 are bin 0.
    """
    return np.floor(np.mod(np.asarray(degrees, dtype=np.float64) + 22.5, 360.0) / 45.0).astype(
        np.int8
    )


def aspect_bins(normals: np.ndarray) -> np.ndarray:
    """(m,) int8: each face's :func:`aspect_bin`; -1 where ``n_x`` is exactly 0."""
    bins = aspect_bin(aspect(normals))
    bins[normals[:, 0] == 0] = -1
    return bins


def patch_count(
    first: np.ndarray, second: np.ndarray, bins: np.ndarray, min_patch: int
) -> tuple[int, np.ndarray]:
    """OPC: patches of at least `min_patch` faces, and each face's patch size (0: none).

    A patch is a connected set of faces of one bin joined across shared edges
    (`first`, `second`: the adjacent pairs); a face with no neighbour of its bin is in
    no patch, so even a `min_patch` of 0 or 1 never counts a single face.
    """
    m = len(bins)
    same = (bins[first] == bins[second]) & (bins[first] >= 0)
    graph = sparse.coo_matrix(
        (np.ones(int(same.sum()), dtype=np.int8), (first[same], second[same])), shape=(m, m)
    )
    _, labels = connected_components(graph, directed=False)
    sizes = np.bincount(labels)
    counted = int(np.count_nonzero((sizes >= 2) & (sizes >= min_patch)))
    return counted, sizes[labels]


def morphotester_opcr(mesh, *, min_patch: int = 5) -> MorphoTesterOPCRResult:
    """Orientation patch count rotated as MorphoTester 1.1.1 computes it.

    1. The mesh as given (no cleaning), centred on the mean of its vertices.
    2. Eight orientations: turned about z by 5.625 degrees (anticlockwise seen from +z)
       seven times over, each turn applied to the last.
    3. At each: MorphoTester's unit face normals (with its orientation vote, which can
       turn every aspect by 180 degrees and so relabel every bin, never a count); aspect
       ``atan2(n_y, n_x)`` in [0, 360) degrees; bin ``floor(((aspect + 22.5) mod 360) /
       45)``; a face whose normal has x exactly 0 is in no bin (horizontal and degenerate
       faces; the y component is not tested).  Faces sharing an edge (two vertex indices)
       and a bin join a patch; OPC counts the patches of at least `min_patch` faces
       (a single face is never a patch).
    4. OPCR is the mean of the 8 counts, unrounded.

    Parameters
    ----------
    mesh : trimesh.Trimesh, str, path-like, or (vertices, faces)
        Never modified.
    min_patch : int, default 5
        The smallest patch counted, in faces (0 or more).  5 is what MorphoTester's
        published sample results use; its GUI's default is 3.

    Raises
    ------
    ValueError
        For a bad `min_patch`, a mesh without faces or with non-finite coordinates.
    """
    min_patch = check_min_patch(min_patch)
    vertices, faces = as_arrays(mesh)
    mt.check_mesh(vertices, faces, "MorphoTester's OPCR")
    first, second = mt.face_adjacency(faces)
    x = vertices - vertices.mean(axis=0)
    turn = np.radians(STEP)
    cos, sin = np.cos(turn), np.sin(turn)
    counts, rotations, face_bins = [], [], None
    for k in range(STEPS):
        if k:
            x = np.stack([x[:, 0] * cos - x[:, 1] * sin, x[:, 0] * sin + x[:, 1] * cos, x[:, 2]], 1)
        face_normals, _, _ = mt.normals(x, faces)
        bins = aspect_bins(face_normals)
        if face_bins is None:
            face_bins = bins
        counts.append(patch_count(first, second, bins, min_patch)[0])
        rotations.append(STEP * k)
    return MorphoTesterOPCRResult(
        opcr=float(np.mean(counts)),
        opc=tuple(counts),
        rotations=tuple(rotations),
        min_patch=min_patch,
        face_bins=face_bins,
    )
