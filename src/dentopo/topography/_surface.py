"""The surface every topography metric measures, prepared as molaR prepares it.

molaR reads a mesh and cleans it (faces of zero area dropped, then vertices no
face uses); every metric then works on face normals and areas from the faces'
stored vertex order, and some on coordinates rescaled by molaR's "centroid
size".  These shared pieces live here so that the metrics agree on them.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
import trimesh

from ..mesh import as_arrays
from ._orientation import Orientation, orient_vertices

#: molaR rescales a mesh so that its size measure is this.
SIZE_TARGET = 100.0


@dataclass(frozen=True)
class Surface:
    """A cleaned mesh and its per-face geometry (arrays are private copies).

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
    """

    vertices: np.ndarray
    faces: np.ndarray
    cross: np.ndarray
    area: np.ndarray
    normals: np.ndarray
    dropped_faces: int = 0
    orientation: Orientation | None = None

    def warn_orientation(self, stacklevel: int = 3) -> None:
        """Warn (``UserWarning``) if the crown is measured pointing to -z."""
        message = None if self.orientation is None else self.orientation.warning()
        if message is not None:
            warnings.warn(message, UserWarning, stacklevel=stacklevel)

    @property
    def total_area(self) -> float:
        """The 3D surface area, mesh units."""
        return float(self.area.sum())

    def trimesh(self) -> trimesh.Trimesh:
        """The cleaned mesh as a ``trimesh.Trimesh`` (not processed: faces as stored)."""
        return trimesh.Trimesh(self.vertices, self.faces, process=False)


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
    mesh : trimesh.Trimesh, str, path-like, or (vertices, faces)
        Never modified.
    orient : {"as-is", "auto"}, optional
        For the metrics that assume the crown points to +z: find which way it
        points (:func:`find_orientation`, recorded in ``Surface.orientation``)
        and, with ``"auto"``, turn a crown pointing to -z first.  None: the
        orientation is not looked at.

    Raises
    ------
    TypeError, ValueError
        For an unusable mesh, or one with no face of non-zero area.
    """
    vertices, faces = as_arrays(mesh)
    cross = face_cross(vertices, faces)
    norm = np.linalg.norm(cross, axis=1)
    keep = norm > 0
    if not keep.any():
        raise ValueError("the mesh has no face of non-zero area")
    dropped = int(len(faces) - keep.sum())
    if dropped:
        faces, cross, norm = faces[keep], cross[keep], norm[keep]
    vertices, faces = drop_unused(vertices, faces)
    area = 0.5 * norm
    orientation = None
    if orient is not None:
        vertices, orientation = orient_vertices(vertices, faces, orient, area)
        if orientation.turned:  # the same numbers, two of them negated (exactly)
            cross = face_cross(vertices, faces)
    return Surface(
        vertices=vertices,
        faces=faces,
        cross=cross,
        area=area,
        normals=cross / norm[:, None],
        dropped_faces=dropped,
        orientation=orientation,
    )


def molar_face_areas(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Face areas as molaR's mesh reader computes them: in single precision.

    molaR's reader (vcglib, through Rvcg) stores coordinates as 32-bit floats
    and computes each face's area there: the edge vectors, their cross product
    and its norm in single precision.  RFI's 3D area and the weights of the
    mean slope are these areas (as float64, summed in double precision); they
    differ from double-precision areas by about 1e-9 relative on a typical
    crown, more for coordinates far from the origin.
    """
    tri = vertices.astype(np.float32)[faces]
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    double_area = np.sqrt((cross * cross).sum(axis=1, dtype=np.float32))
    return double_area.astype(np.float64) / 2


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
