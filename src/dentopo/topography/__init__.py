"""Dental topography metrics, laid out by family, each peer's variant a module of its own.

One subpackage per family of metrics; in each, one module per peer tool whose numbers it
reproduces (``_molar``: molaR 6.0; ``_doolkit``: doolkit 1.42.2; ``_morphotester``:
MorphoTester 1.1.1):

- ``dne``: Dirichlet normal energy (molaR's classic DNE with its convex/concave split,
  doolkit's DNE, MorphoTester's; ariaDNE is :mod:`dentopo.ariadne`);
- ``slope``: face slope, inclination and bearing;
- ``curvature``: ARC (molaR's and doolkit's) and doolkit's angularity;
- ``opc``: orientation patch count and its rotated mean (molaR's, doolkit's, MorphoTester's);
- ``relief``: relief index and the other height measures (molaR's RFI with its alpha search,
  doolkit's relief indices, relief rate, shape index, hypsodonty, MorphoTester's RFI, and ours
  on the exact projected footprint, ``_projected``);
- ``footprint``: the outline projected on the occlusal plane (molaR's alpha shape on a
  certified Delaunay triangulation; doolkit's convex or concave hull, a port of concaveman;
  MorphoTester's outline counted in pixels; the exact projected footprint);
- ``occlusion``: PCV, ambient occlusion (CloudCompare's qPCV: its light directions
  ``_directions``, its depth buffers ``_depth``; exact rays through Embree ``_rays``);
- ``surface``: how each tool reads the crown (molaR's surface preparation, the float32 VCG
  emulation), which way it points, and the compiled passes the families share.

The checks of parameters (``_parameters``), units (``_units``) and the registry of metric names
for a batch (``_metrics``, ariaDNE included) sit at this level, shared by every family.  The
public names are those below, all importable from :mod:`dentopo.topography`; the subpackages are
the layout, not the API.

May import: :mod:`dentopo.mesh`.  Nothing from ariadne, figures, formats, batch,
study or cli.
"""

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
    MORPHOTESTER_BASE_KEYS,
    MORPHOTESTER_METRICS,
    MORPHOTESTER_ROTATION_KEYS,
    ORIENTED,
    OWN_METRICS,
    check_metrics,
    metric_names,
    rotation_key,
    rotations,
)
from ._parameters import (
    BOUNDARY_RULES,
    PCV_METHODS,
    check_alpha,
    check_arc_options,
    check_choice,
    check_classic_options,
    check_find_alpha,
    check_finite,
    check_int,
    check_min_area,
    check_morphotester_options,
    check_opcr_options,
    check_pcv_options,
)
from ._units import UNIT_DEPENDENT, UNITS, UnitWarning, millimetres_per_unit
from .curvature._angularity import ANGULARITY_FIELDS, AngularityResult, angularity
from .curvature._arc import (
    ARC_FIELDS,
    DOOLKIT_ARC_FIELDS,
    ARCResult,
    DoolkitARCResult,
    arc,
    doolkit_arc,
)
from .dne._doolkit import DOOLKIT_DNE_FIELDS, DoolkitDNEResult, doolkit_dne
from .dne._molar import CLASSIC_FIELDS, ClassicDNEResult, classic_dne
from .dne._morphotester import (
    MORPHOTESTER_DNE_FIELDS,
    MorphoTesterDNEResult,
    morphotester_dne,
)
from .footprint._doolkit import (
    FOOTPRINT_FIELDS,
    HULLS,
    FootprintResult,
    concave_hull,
    convex_hull,
    footprint_area,
)
from .footprint._projected import (
    PROJECTED_FOOTPRINT_FIELDS,
    ProjectedFootprintError,
    ProjectedFootprintResult,
    projected_footprint,
)
from .occlusion._pcv import PCV_FIELDS, PCVResult, pcv
from .opc._doolkit import DoolkitOPCResult, DoolkitOPCRResult, doolkit_opc, doolkit_opcr
from .opc._molar import OPC_FIELDS, OPCResult, OPCRResult, opc, opcr
from .opc._morphotester import (
    MORPHOTESTER_OPCR_FIELDS,
    MorphoTesterOPCRResult,
    morphotester_opcr,
)
from .relief._doolkit import (
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
from .relief._molar import (
    RFI_FIELDS,
    AlphaAdjustmentError,
    FootprintError,
    FootprintWarning,
    RFIResult,
    rfi,
)
from .relief._morphotester import (
    MORPHOTESTER_RFI_FIELDS,
    MorphoTesterRFIResult,
    morphotester_rfi,
)
from .relief._projected import PROJECTED_RFI_FIELDS, ProjectedRFIResult, projected_rfi
from .slope._doolkit import (
    DOOLKIT_SLOPE_FIELDS,
    INCLINATION_FIELDS,
    DoolkitSlopeResult,
    InclinationResult,
    doolkit_slope,
    face_bearing,
    inclination,
)
from .slope._molar import SLOPE_FIELDS, SlopeResult, slope
from .surface._molar import (
    DUPLICATE_MODES,
    Surface,
    check_duplicates,
    molar_face_areas,
    molar_scale,
    prepare_surface,
)
from .surface._orientation import (
    ORIENT_MODES,
    Orientation,
    check_orient,
    find_orientation,
    orient_vertices,
)

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
    "MORPHOTESTER_BASE_KEYS",
    "MORPHOTESTER_DNE_FIELDS",
    "MORPHOTESTER_METRICS",
    "MORPHOTESTER_OPCR_FIELDS",
    "MORPHOTESTER_RFI_FIELDS",
    "MORPHOTESTER_ROTATION_KEYS",
    "OPC_FIELDS",
    "ORIENTED",
    "ORIENT_MODES",
    "OWN_METRICS",
    "PCV_FIELDS",
    "PCV_METHODS",
    "PROJECTED_FOOTPRINT_FIELDS",
    "PROJECTED_RFI_FIELDS",
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
    "MorphoTesterDNEResult",
    "MorphoTesterOPCRResult",
    "MorphoTesterRFIResult",
    "OPCRResult",
    "OPCResult",
    "Orientation",
    "PCVResult",
    "ProjectedFootprintError",
    "ProjectedFootprintResult",
    "ProjectedRFIResult",
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
    "check_morphotester_options",
    "check_opcr_options",
    "check_orient",
    "check_pcv_options",
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
    "morphotester_dne",
    "morphotester_opcr",
    "morphotester_rfi",
    "opc",
    "opcr",
    "orient_vertices",
    "pcv",
    "prepare_surface",
    "projected_footprint",
    "projected_rfi",
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
