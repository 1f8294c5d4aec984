"""Relief index on the exact projected footprint: never needs an alpha, defined for every crown.

RFI compares a crown's 3D surface area with the area of its footprint.  The field writes it
two ways: Boyer's log form ``ln(sqrt(A3) / sqrt(A2))`` (molaR's ``RFI``, doolkit's
``rfi_boyer``) and Ungar's ratio ``A3 / A2`` (MorphoTester's, doolkit's ``rfi_ungar``);
``ungar = exp(2 * boyer)``.  The peers differ in the footprint ``A2``: molaR's alpha-convex
hull of the vertices (which needs an alpha, and fails at its default on most of the shared
crowns), doolkit's concave hull of them, MorphoTester's rendered outline counted in pixels.
Here ``A2`` is the exact projected footprint
(:func:`dentopo.topography.projected_footprint`: the union of the triangles seen from
above, each point once), and ``A3`` the 3D area molaR's RFI uses (single precision per
face), so that the log form differs from molaR's only by its footprint.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from ..._html_repr import result_html
from ..footprint._projected import projected_result, projected_surface
from ..surface._orientation import Orientation

#: The table fields of :class:`ProjectedRFIResult` (batch columns), in order.
PROJECTED_RFI_FIELDS = (
    "rfi_projected",
    "rfi_projected_ungar",
    "projected_area_3d",
    "projected_area_2d",
)


@dataclass(frozen=True)
class ProjectedRFIResult:
    """Relief index of one crown on its exact projected footprint, in both forms.

    Attributes
    ----------
    rfi : float
        Boyer's log form, ``ln(sqrt(area_3d) / sqrt(area_2d))`` (as molaR's RFI).
    rfi_ungar : float
        Ungar's ratio, ``area_3d / area_2d`` (as MorphoTester's RFI and doolkit's
        ``rfi_ungar``); ``exp(2 * rfi)``.
    area_3d : float
        Total face area, mesh units squared, as molaR's RFI computes it (single precision
        per face, after molaR's cleaning).
    area_2d : float
        The exact projected footprint's area (:func:`dentopo.topography.projected_footprint`).
    vertices, faces : int
        Vertex and face counts of the cleaned mesh.
    n_holes : int
        Holes of the footprint (a pit open through the crown).
    orientation : Orientation or None
        Which way the crown points and whether it was turned before measuring.
    """

    rfi: float
    rfi_ungar: float
    area_3d: float
    area_2d: float
    vertices: int
    faces: int
    n_holes: int = 0
    orientation: Orientation | None = field(default=None, compare=False)

    def to_dict(self) -> dict:
        """The table fields (:data:`PROJECTED_RFI_FIELDS`) as a plain dict."""
        return {
            "rfi_projected": self.rfi,
            "rfi_projected_ungar": self.rfi_ungar,
            "projected_area_3d": self.area_3d,
            "projected_area_2d": self.area_2d,
        }

    def _repr_html_(self) -> str:
        """A compact table for notebooks: values, settings, arrays summarised."""
        return result_html(self)


def projected_rfi(mesh, *, orient: str = "auto") -> ProjectedRFIResult:
    """Relief index on the exact projected footprint, in Boyer's and Ungar's forms.

    ``A3`` is the 3D area molaR's RFI uses (per face in single precision, after molaR's
    cleaning); ``A2`` the area of the union of the triangles projected on the occlusal plane
    (:func:`dentopo.topography.projected_footprint`).  No alpha, no hull, no raster: the
    number exists for every open crown, where molaR's RFI needs an alpha and fails at its
    default on 8 of the 13 shared crowns.  Where molaR's RFI has a value there, the log form
    differs from it by -0.002 to +0.014 (+0.029 at alpha 0.075 on one crown, whose alpha hull
    bridges the outline's concavities; a hull also fills an open pit); the ratio is 1.1 to
    5.7 % above MorphoTester's, whose outline is counted in pixels with a stroke around it.

    The crown is prepared and oriented as :func:`dentopo.topography.rfi` does: occlusal plane
    x-y, crown pointing to +z (turned with ``orient="auto"``).  A closed surface (no open
    base) is measured as it lies, with molaR's RFI's warning.

    Parameters
    ----------
    mesh : trimesh.Trimesh, str, path-like, (vertices, faces), or Surface
        The crown.  Never modified.
    orient : {"auto", "as-is"}, default "auto"
        As :func:`dentopo.topography.rfi`.

    Returns
    -------
    ProjectedRFIResult

    Raises
    ------
    dentopo.topography.ProjectedFootprintError
        When every face is vertical (the footprint has no area).
    TypeError, ValueError
        For an unusable mesh or parameter.

    Warns
    -----
    UserWarning
        When the crown is measured pointing to -z (``orient="as-is"``), or is flat or closed.

    References
    ----------
    Boyer DM (2008). Relief index of second mandibular molars is a correlate of diet among
    prosimian primates and other euarchontan mammals. J Hum Evol 55:1118-1137.

    Ungar PS, M'Kirera F (2003). A solution to the worn tooth conundrum in primate
    functional anatomy. PNAS 100:3874-3877.

    Examples
    --------
    >>> from dentopo.samples import tooth
    >>> result = projected_rfi(tooth(rings=16))
    >>> sorted(result.to_dict())
    ['projected_area_2d', 'projected_area_3d', 'rfi_projected', 'rfi_projected_ungar']
    """
    surface = projected_surface(mesh, orient)
    surface.warn_orientation()
    footprint = projected_result(surface)
    area_3d = float(surface.single_precision_areas().sum())
    area_2d = footprint.area
    return ProjectedRFIResult(
        rfi=float(math.log(math.sqrt(area_3d) / math.sqrt(area_2d))),
        rfi_ungar=float(area_3d / area_2d),
        area_3d=area_3d,
        area_2d=area_2d,
        vertices=footprint.vertices,
        faces=footprint.faces,
        n_holes=footprint.n_holes,
        orientation=surface.orientation,
    )
