"""Dental topography metrics in molaR 6.0's definitions: one module per metric.

Classic DNE with its convex/concave split (``_classic_dne``, molaR's ``DNE``);
mean surface slope (``_slope``, molaR's ``Slope``); orientation patch count and
its rotated mean (``_opc``, molaR's ``OPC`` and ``OPCr``); the relief index with
its alpha-shape footprint and molaR's search for an alpha (``_rfi``, molaR's
``RFI``); doolkit 1.42.2's footprint area, concave or convex (``_footprint``,
doolkit's ``area2d``, its concave hull a port of mapbox's concaveman in
``_concaveman``).  They share molaR's surface preparation (``_surface``) and the
orientation check of the metrics that assume the crown points to +z
(``_orientation``) and the checks of their parameters (``_parameters``);
``_metrics`` names them all, ariaDNE included, for a batch.  Their per-face
and per-edge passes are compiled (``_kernels``), and RFI's Delaunay
triangulation is a compiled, certified sweep with qhull as the fallback
(``_delaunay``).

May import: :mod:`dentopo.mesh`.  Nothing from ariadne, figures, formats, batch,
study or cli.
"""

from ._classic_dne import CLASSIC_FIELDS, ClassicDNEResult, classic_dne
from ._footprint import (
    FOOTPRINT_FIELDS,
    HULLS,
    FootprintResult,
    concave_hull,
    convex_hull,
    footprint_area,
)
from ._metrics import (
    ALL,
    BIN_KEYS,
    CLASSIC_KEYS,
    METRICS,
    ORIENTED,
    check_metrics,
    rotation_key,
    rotations,
)
from ._opc import OPC_FIELDS, OPCResult, OPCRResult, opc, opcr
from ._orientation import ORIENT_MODES, Orientation, check_orient, find_orientation, orient_vertices
from ._parameters import check_alpha, check_find_alpha, check_finite, check_int
from ._rfi import RFI_FIELDS, AlphaAdjustmentError, RFIResult, rfi
from ._slope import SLOPE_FIELDS, SlopeResult, slope
from ._surface import Surface, molar_face_areas, molar_scale, prepare_surface

__all__ = [
    "ALL",
    "BIN_KEYS",
    "CLASSIC_FIELDS",
    "CLASSIC_KEYS",
    "FOOTPRINT_FIELDS",
    "HULLS",
    "METRICS",
    "OPC_FIELDS",
    "ORIENTED",
    "ORIENT_MODES",
    "RFI_FIELDS",
    "SLOPE_FIELDS",
    "AlphaAdjustmentError",
    "ClassicDNEResult",
    "FootprintResult",
    "OPCRResult",
    "OPCResult",
    "Orientation",
    "RFIResult",
    "SlopeResult",
    "Surface",
    "check_alpha",
    "check_find_alpha",
    "check_finite",
    "check_int",
    "check_metrics",
    "check_orient",
    "classic_dne",
    "concave_hull",
    "convex_hull",
    "find_orientation",
    "footprint_area",
    "molar_face_areas",
    "molar_scale",
    "opc",
    "opcr",
    "orient_vertices",
    "prepare_surface",
    "rfi",
    "rotation_key",
    "rotations",
    "slope",
]
