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

from typing import TYPE_CHECKING

from .._lazy_exports import lazy_exports
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

# Not lazy: these two are named like their family (``slope``, ``opc``), and importing a
# family's module would set the package's attribute of that name to the family.
from .opc._molar import OPC_FIELDS, OPCResult, OPCRResult, opc, opcr
from .slope._molar import SLOPE_FIELDS, SlopeResult, slope

if TYPE_CHECKING:  # the real imports, for type checkers and IDEs
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

#: Where each family's public name lives: imported on its first use (PEP 562), so that a
#: command measuring ariaDNE alone, or reading the metric names, loads no family (nor trimesh
#: and scipy, which they import).
_EXPORTS = {
    "ANGULARITY_FIELDS": ".curvature._angularity",
    "AngularityResult": ".curvature._angularity",
    "angularity": ".curvature._angularity",
    "ARC_FIELDS": ".curvature._arc",
    "DOOLKIT_ARC_FIELDS": ".curvature._arc",
    "ARCResult": ".curvature._arc",
    "DoolkitARCResult": ".curvature._arc",
    "arc": ".curvature._arc",
    "doolkit_arc": ".curvature._arc",
    "DOOLKIT_DNE_FIELDS": ".dne._doolkit",
    "DoolkitDNEResult": ".dne._doolkit",
    "doolkit_dne": ".dne._doolkit",
    "CLASSIC_FIELDS": ".dne._molar",
    "ClassicDNEResult": ".dne._molar",
    "classic_dne": ".dne._molar",
    "MORPHOTESTER_DNE_FIELDS": ".dne._morphotester",
    "MorphoTesterDNEResult": ".dne._morphotester",
    "morphotester_dne": ".dne._morphotester",
    "FOOTPRINT_FIELDS": ".footprint._doolkit",
    "HULLS": ".footprint._doolkit",
    "FootprintResult": ".footprint._doolkit",
    "concave_hull": ".footprint._doolkit",
    "convex_hull": ".footprint._doolkit",
    "footprint_area": ".footprint._doolkit",
    "PROJECTED_FOOTPRINT_FIELDS": ".footprint._projected",
    "ProjectedFootprintError": ".footprint._projected",
    "ProjectedFootprintResult": ".footprint._projected",
    "projected_footprint": ".footprint._projected",
    "PCV_FIELDS": ".occlusion._pcv",
    "PCVResult": ".occlusion._pcv",
    "pcv": ".occlusion._pcv",
    "DoolkitOPCResult": ".opc._doolkit",
    "DoolkitOPCRResult": ".opc._doolkit",
    "doolkit_opc": ".opc._doolkit",
    "doolkit_opcr": ".opc._doolkit",
    "MORPHOTESTER_OPCR_FIELDS": ".opc._morphotester",
    "MorphoTesterOPCRResult": ".opc._morphotester",
    "morphotester_opcr": ".opc._morphotester",
    "HYPSODONTY_FIELDS": ".relief._doolkit",
    "RELIEF_INDEX_FIELDS": ".relief._doolkit",
    "SHAPE_INDEX_FIELDS": ".relief._doolkit",
    "ElevationResult": ".relief._doolkit",
    "HypsodontyResult": ".relief._doolkit",
    "ReliefIndexResult": ".relief._doolkit",
    "ReliefRateResult": ".relief._doolkit",
    "ShapeIndexResult": ".relief._doolkit",
    "elevation": ".relief._doolkit",
    "hypsodonty": ".relief._doolkit",
    "r_round": ".relief._doolkit",
    "relief_index": ".relief._doolkit",
    "relief_rate": ".relief._doolkit",
    "relief_rate_below_median": ".relief._doolkit",
    "shape_index": ".relief._doolkit",
    "RFI_FIELDS": ".relief._molar",
    "AlphaAdjustmentError": ".relief._molar",
    "FootprintError": ".relief._molar",
    "FootprintWarning": ".relief._molar",
    "RFIResult": ".relief._molar",
    "rfi": ".relief._molar",
    "MORPHOTESTER_RFI_FIELDS": ".relief._morphotester",
    "MorphoTesterRFIResult": ".relief._morphotester",
    "morphotester_rfi": ".relief._morphotester",
    "PROJECTED_RFI_FIELDS": ".relief._projected",
    "ProjectedRFIResult": ".relief._projected",
    "projected_rfi": ".relief._projected",
    "DOOLKIT_SLOPE_FIELDS": ".slope._doolkit",
    "INCLINATION_FIELDS": ".slope._doolkit",
    "DoolkitSlopeResult": ".slope._doolkit",
    "InclinationResult": ".slope._doolkit",
    "doolkit_slope": ".slope._doolkit",
    "face_bearing": ".slope._doolkit",
    "inclination": ".slope._doolkit",
    "DUPLICATE_MODES": ".surface._molar",
    "Surface": ".surface._molar",
    "check_duplicates": ".surface._molar",
    "molar_face_areas": ".surface._molar",
    "molar_scale": ".surface._molar",
    "prepare_surface": ".surface._molar",
    "ORIENT_MODES": ".surface._orientation",
    "Orientation": ".surface._orientation",
    "check_orient": ".surface._orientation",
    "find_orientation": ".surface._orientation",
    "orient_vertices": ".surface._orientation",
}

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


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, __all__)
