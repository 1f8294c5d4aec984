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
(``_delaunay``).  The curvature-based metrics of molaR and doolkit (ARC,
doolkit's DNE and angularity: ``_arc``, ``_dne_doolkit``, ``_angularity``)
share a float32 emulation of the VCG library's geometry (``_vcg``).

doolkit 1.42.2's metrics, in its definitions and precision: face slope,
inclination and bearing on the mesh as its reader leaves it (``_angles``),
its OPC and OPCR (``_opc_doolkit``), elevation, the Ungar, Boyer and Guy
relief indices, relief rate, shape index and hypsodonty (``_relief``), and
the footprint those relief indices divide by (``_footprint``).

May import: :mod:`dentopo.mesh`.  Nothing from ariadne, figures, formats, batch,
study or cli.
"""

from ._angles import (
    DOOLKIT_SLOPE_FIELDS,
    INCLINATION_FIELDS,
    DoolkitSlopeResult,
    InclinationResult,
    doolkit_slope,
    face_bearing,
    inclination,
)
from ._angularity import ANGULARITY_FIELDS, AngularityResult, angularity
from ._arc import ARC_FIELDS, DOOLKIT_ARC_FIELDS, ARCResult, DoolkitARCResult, arc, doolkit_arc
from ._classic_dne import CLASSIC_FIELDS, ClassicDNEResult, classic_dne
from ._dne_doolkit import DOOLKIT_DNE_FIELDS, DoolkitDNEResult, doolkit_dne
from ._footprint import (
    FOOTPRINT_FIELDS,
    HULLS,
    FootprintResult,
    concave_hull,
    convex_hull,
    footprint_area,
)
from ._metrics import (
    ALIASES,
    ALL,
    BIN_KEYS,
    CLASSIC_KEYS,
    DOOLKIT_BASE_KEYS,
    DOOLKIT_BIN_KEYS,
    DOOLKIT_METRICS,
    DOOLKIT_ROTATION_KEYS,
    GROUPS,
    METRICS,
    MOLAR_METRICS,
    ORIENTED,
    check_metrics,
    metric_names,
    rotation_key,
    rotations,
)
from ._opc import OPC_FIELDS, OPCResult, OPCRResult, opc, opcr
from ._opc_doolkit import DoolkitOPCResult, DoolkitOPCRResult, doolkit_opc, doolkit_opcr
from ._orientation import ORIENT_MODES, Orientation, check_orient, find_orientation, orient_vertices
from ._parameters import (
    BOUNDARY_RULES,
    check_alpha,
    check_arc_options,
    check_choice,
    check_classic_options,
    check_find_alpha,
    check_finite,
    check_int,
    check_min_area,
    check_opcr_options,
)
from ._relief import (
    HYPSODONTY_FIELDS,
    RELIEF_INDEX_FIELDS,
    SHAPE_INDEX_FIELDS,
    ElevationResult,
    HypsodontyResult,
    ReliefIndexResult,
    ReliefRateResult,
    ShapeIndexResult,
    elevation,
    hypsodonty,
    r_round,
    relief_index,
    relief_rate,
    relief_rate_below_median,
    shape_index,
)
from ._rfi import (
    RFI_FIELDS,
    AlphaAdjustmentError,
    FootprintError,
    FootprintWarning,
    RFIResult,
    rfi,
)
from ._slope import SLOPE_FIELDS, SlopeResult, slope
from ._surface import (
    DUPLICATE_MODES,
    Surface,
    check_duplicates,
    molar_face_areas,
    molar_scale,
    prepare_surface,
)
from ._units import UNIT_DEPENDENT, UNITS, UnitWarning, millimetres_per_unit

__all__ = [
    "ALIASES",
    "ALL",
    "ANGULARITY_FIELDS",
    "ARC_FIELDS",
    "BIN_KEYS",
    "BOUNDARY_RULES",
    "CLASSIC_FIELDS",
    "CLASSIC_KEYS",
    "DOOLKIT_ARC_FIELDS",
    "DOOLKIT_BASE_KEYS",
    "DOOLKIT_BIN_KEYS",
    "DOOLKIT_DNE_FIELDS",
    "DOOLKIT_METRICS",
    "DOOLKIT_ROTATION_KEYS",
    "DOOLKIT_SLOPE_FIELDS",
    "DUPLICATE_MODES",
    "FOOTPRINT_FIELDS",
    "GROUPS",
    "HULLS",
    "HYPSODONTY_FIELDS",
    "INCLINATION_FIELDS",
    "METRICS",
    "MOLAR_METRICS",
    "OPC_FIELDS",
    "ORIENTED",
    "ORIENT_MODES",
    "RELIEF_INDEX_FIELDS",
    "RFI_FIELDS",
    "SHAPE_INDEX_FIELDS",
    "SLOPE_FIELDS",
    "UNITS",
    "UNIT_DEPENDENT",
    "ARCResult",
    "AlphaAdjustmentError",
    "AngularityResult",
    "ClassicDNEResult",
    "DoolkitARCResult",
    "DoolkitDNEResult",
    "DoolkitOPCRResult",
    "DoolkitOPCResult",
    "DoolkitSlopeResult",
    "ElevationResult",
    "FootprintError",
    "FootprintResult",
    "FootprintWarning",
    "HypsodontyResult",
    "InclinationResult",
    "OPCRResult",
    "OPCResult",
    "Orientation",
    "RFIResult",
    "ReliefIndexResult",
    "ReliefRateResult",
    "ShapeIndexResult",
    "SlopeResult",
    "Surface",
    "UnitWarning",
    "angularity",
    "arc",
    "check_alpha",
    "check_arc_options",
    "check_choice",
    "check_classic_options",
    "check_duplicates",
    "check_find_alpha",
    "check_finite",
    "check_int",
    "check_metrics",
    "check_min_area",
    "check_opcr_options",
    "check_orient",
    "classic_dne",
    "concave_hull",
    "convex_hull",
    "doolkit_arc",
    "doolkit_dne",
    "doolkit_opc",
    "doolkit_opcr",
    "doolkit_slope",
    "elevation",
    "face_bearing",
    "find_orientation",
    "footprint_area",
    "hypsodonty",
    "inclination",
    "metric_names",
    "millimetres_per_unit",
    "molar_face_areas",
    "molar_scale",
    "opc",
    "opcr",
    "orient_vertices",
    "prepare_surface",
    "r_round",
    "relief_index",
    "relief_rate",
    "relief_rate_below_median",
    "rfi",
    "rotation_key",
    "rotations",
    "shape_index",
    "slope",
]
