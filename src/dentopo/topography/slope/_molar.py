"""Mean surface slope as molaR 6.0's ``Slope`` computes it.

Each face's slope is the angle of its unit normal from +z, rounded to whole
degrees with R's ``round`` (half to even); the mesh's slope is the
area-weighted mean of those whole-degree angles.  molaR takes the occlusal
plane to be the x-y plane with the crown pointing to +z and never re-orients
a mesh, so a crown pointing to -z gets slopes above 90 degrees.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from ..._html_repr import result_html
from .._lazy import LazyMesh
from ..surface import _kernels
from ..surface._molar import prepare_surface
from ..surface._orientation import Orientation, check_orient

if TYPE_CHECKING:
    import trimesh

#: Scalar fields, in the order of output tables.
SLOPE_FIELDS = ("slope",)


@dataclass(frozen=True)
class SlopeResult:
    """molaR's mean surface slope for one mesh.

    Per-face arrays follow the faces of the cleaned mesh (faces of zero area
    dropped, then unused vertices; neither reorders faces).

    Attributes
    ----------
    slope : float
        Area-weighted mean of ``face_slope``, degrees, as its absolute value
        (molaR's; the per-face angles are never negative, so it is the mean).
    vertices, faces : int
        Vertex and face counts of the cleaned mesh.
    face_slope : (m,) int64
        Angle between each face's unit normal and +z, in whole degrees
        (R's ``round``: half to even): 0 flat and facing up, 90 vertical,
        above 90 overhanging.
    face_area : (m,) float64
        Face areas, mesh units, as molaR's reader computes them (in single
        precision: :func:`dentopo.topography.molar_face_areas`); the mean's weights.
    mesh : trimesh.Trimesh
        The cleaned mesh the per-face arrays refer to (a private copy; turned
        to +z if ``orient="auto"`` turned it).
    orientation : Orientation
        Which way the crown points (``+z``, ``-z`` or ``undetermined``) and
        whether it was turned before measuring (``orient="auto"``).
    """

    slope: float
    vertices: int
    faces: int
    face_slope: np.ndarray = field(repr=False, compare=False)
    face_area: np.ndarray = field(repr=False, compare=False)
    mesh: trimesh.Trimesh = field(default=LazyMesh(), repr=False, compare=False)
    orientation: Orientation | None = field(default=None, compare=False)

    def to_dict(self) -> dict:
        """The scalar table fields as a plain dict (``{"slope": ...}``)."""
        return {name: getattr(self, name) for name in SLOPE_FIELDS}

    def _repr_html_(self) -> str:
        """A compact table for notebooks: values, settings, arrays summarised."""
        return result_html(self, histogram="face_slope")


def face_slopes(normals: np.ndarray) -> np.ndarray:
    """Whole-degree angle from +z of unit normals: ``round(acos(n_z) * 180 / pi)``.

    ``n_z`` is clipped to [-1, 1] first (a unit normal's component can exceed
    1 by a rounding error); rounding is half to even, as R's ``round``.
    """
    angle = np.arccos(np.clip(normals[:, 2], -1.0, 1.0)) * 180.0 / np.pi
    return np.rint(angle).astype(np.int64)


def slope(mesh, *, orient: str = "auto") -> SlopeResult:
    """Mean surface slope, as molaR 6.0's ``Slope`` computes it.

    1. **Mesh.** Files are read with :func:`dentopo.mesh.load_mesh`
       (duplicate vertices merged, as molaR's reader does); then molaR's
       cleaning (faces of zero area dropped, then vertices no face uses).
       The occlusal plane is taken to be the x-y plane, the crown pointing
       to +z (see `orient`).  The caller's mesh is never modified.
    2. **Per face.** Unit normal ``n`` from ``(v2 - v1) x (v3 - v1)`` in the
       face's stored vertex order; slope ``round(acos(n_z) * 180 / pi)`` in
       whole degrees (half to even).
    3. **Mean.** ``|sum(slope * area) / sum(area)|`` with face areas in mesh
       units (molaR's default ``Guess = FALSE``), computed in single precision
       as molaR's mesh reader computes them; the weighted sum is compensated
       (twice double precision, as R's long-double sum nearly is) and
       sequential, so the mean equals molaR's to the last bit on its reference
       meshes and does not depend on the number of threads.

    The result does not depend on translation, uniform scale or the order of
    vertices and faces; it does depend on orientation.

    Parameters
    ----------
    mesh : trimesh.Trimesh, str, path-like, (vertices, faces), or Surface
        A triangle mesh, or one prepared once for several metrics
        (:func:`dentopo.topography.prepare_surface`).  Never modified.
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
    SlopeResult

    Raises
    ------
    TypeError, ValueError
        For an unusable mesh or `orient`; the message names the problem.

    Warns
    -----
    UserWarning
        When the crown is measured pointing to -z (``orient="as-is"``); when
        its faces are wound inward (rewound or not); when it is flat or closed.

    References
    ----------
    Pampush J. D., Winchester J. M., Morse P. E., Vining A. Q., Boyer D. M.,
    Kay R. F. (2016). Introducing molaR: a new R package for quantitative
    topographic analysis of teeth (and other topographic surfaces). Journal of
    Mammalian Evolution 23, 397-412. doi:10.1007/s10914-016-9326-0

    Examples
    --------
    >>> import trimesh
    >>> from dentopo.topography import slope
    >>> slope(trimesh.creation.box()).slope  # 4 vertical sides, a top (0) and a bottom (180)
    90.0
    """
    surface = prepare_surface(mesh, orient=check_orient(orient))
    surface.warn_orientation()
    return _slope_of(surface)


def _slope_of(surface) -> SlopeResult:
    per_face = face_slopes(surface.normals)
    area = surface.single_precision_areas()
    mean = float(_kernels.compensated_dot(per_face, area) / area.sum())
    return SlopeResult(
        slope=abs(mean),
        vertices=len(surface.vertices),
        faces=len(surface.faces),
        face_slope=per_face,
        face_area=area,
        mesh=surface.mesh_later(),
        orientation=surface.orientation,
    )
