"""Relief index (RFI) as MorphoTester 1.1.1 computes it: 3D area over rendered outline area.

MorphoTester (Winchester 2016; GPL-2) is reproduced from a description of its method
(``docs/MORPHOTESTER.md`` of the shared data), never from its code.  RFI is the plain
ratio of the two areas, each first rounded to 3 decimals (not Boyer's log form).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..._html_repr import result_html
from ...mesh import as_arrays
from ..footprint._morphotester import render_outline
from ..surface import _morphotester as mt

#: Scalar fields (:meth:`MorphoTesterRFIResult.to_dict`), in the order of output tables.
MORPHOTESTER_RFI_FIELDS = (
    "rfi",
    "surface_area",
    "outline_area",
    "blue",
    "red",
    "length",
    "scale",
)


@dataclass(frozen=True)
class MorphoTesterRFIResult:
    """MorphoTester 1.1.1's relief index for one mesh.

    Attributes
    ----------
    rfi : float
        ``round(surface_area / outline_area, 3)``, both already rounded (Python 2's
        rounding: ties away from zero).
    surface_area, outline_area : float
        ``S`` and ``P`` rounded to 3 decimals, as printed.
    surface_area_unrounded, outline_area_unrounded : float
        The same unrounded: ``S`` the sum of the face areas, ``P = blue * L**2 / red**2``.
    blue, red : int
        Pixels of the mesh and of the reference line in the raster.
    length : float
        ``L = (ymax - ymin) + 1``, the reference line's length in mesh units.
    scale : float
        Pixels per unit as MorphoTester takes it, ``red / L``.
    """

    rfi: float
    surface_area: float
    outline_area: float
    surface_area_unrounded: float
    outline_area_unrounded: float
    blue: int
    red: int
    length: float
    scale: float
    _image: np.ndarray = field(repr=False, compare=False)

    def image(self) -> np.ndarray:
        """The rendered (600, 800, 4) uint8 RGBA raster (read-only), top row first."""
        return self._image

    def to_dict(self) -> dict:
        """The scalar fields (:data:`MORPHOTESTER_RFI_FIELDS`) as a plain dict."""
        return {name: getattr(self, name) for name in MORPHOTESTER_RFI_FIELDS}

    def _repr_html_(self) -> str:
        """A compact table for notebooks: values, settings, arrays summarised."""
        return result_html(self)


def morphotester_rfi(mesh) -> MorphoTesterRFIResult:
    """Relief index as MorphoTester 1.1.1 computes it.

    - ``S``: the sum of the face areas (half the length of ``(p1 - p0) x (p2 - p0)``),
      rounded to 3 decimals.
    - ``P``: the outline area counted on MorphoTester's matplotlib raster (see
      :mod:`dentopo.topography.footprint._morphotester`): ``blue * L**2 / red**2``,
      rounded to 3 decimals.
    - ``RFI = round(S / P, 3)`` of the rounded areas.

    The mesh is used as given (no cleaning); the raster depends on how the crown lies in
    x-y (turning it about z changes ``P`` a little) and, through the 0.5-unit margins and
    the 1 pt strokes, on the mesh unit: a crown in micrometres and the same crown in
    millimetres do not give the same RFI.

    Parameters
    ----------
    mesh : trimesh.Trimesh, str, path-like, or (vertices, faces)
        Never modified.

    Raises
    ------
    ValueError
        For a mesh without faces or with non-finite coordinates, or without extent in y
        (MorphoTester's ``L = 1`` error) or in x.
    """
    vertices, faces = as_arrays(mesh)
    mt.check_mesh(vertices, faces, "MorphoTester's RFI")
    area = float(np.sum(mt.face_areas(vertices, faces)))
    raster = render_outline(vertices, faces)
    outline = raster.blue * raster.length**2 / raster.red**2
    surface_rounded = mt.py2_round(area, 3)
    outline_rounded = mt.py2_round(outline, 3)
    if not outline_rounded > 0:
        raise ValueError(
            f"MorphoTester's RFI: the outline area rounds to {outline_rounded:g} "
            f"({raster.blue} mesh pixels): the crown is too small in its own units for "
            "MorphoTester's raster"
        )
    return MorphoTesterRFIResult(
        rfi=mt.py2_round(surface_rounded / outline_rounded, 3),
        surface_area=surface_rounded,
        outline_area=outline_rounded,
        surface_area_unrounded=area,
        outline_area_unrounded=outline,
        blue=raster.blue,
        red=raster.red,
        length=raster.length,
        scale=raster.scale,
        _image=raster.image,
    )
