"""dentopo: dental topography for triangle meshes.

ariaDNE (Shan et al. 2019) measures how curved a surface is, robustly to how it
is meshed; its sign-oriented extension (Hjerrild et al., signDNE) splits it
into convex (cusps, ridges) and concave (valleys, basins) parts.  Classic DNE,
mean slope, OPC, OPCR and RFI are computed as molaR 6.0 computes them
(:mod:`dentopo.topography`).

The package is layered; each subpackage's docstring says what it holds and
what it may import, and the arrows run one way, from the bottom up:
``mesh`` < ``sign`` < ``ariadne`` < ``topography`` < ``prepare`` < ``figures`` < ``formats``
< ``batch`` < ``study`` < ``cli``.

>>> from dentopo import ariaDNE
>>> result = ariaDNE("tooth.ply")             # doctest: +SKIP
>>> result.dne, result.positive_dne, result.negative_dne  # doctest: +SKIP
"""

from typing import TYPE_CHECKING

from ._lazy_exports import lazy_exports
from ._version import __version__
from .prepare import prepare  # light: the steps load on the first call

if TYPE_CHECKING:  # the real imports, for type checkers and IDEs
    from .ariadne import AriaDNEResult, ariaDNE
    from .batch import BatchResult, compute_batch, find_mesh_files, to_dataframe
    from .figures import (  # pyvista is imported only when a picture is drawn
        ColorScale,
        DisplayUnavailableError,
        color_scale,
        diverging_rgb,
        render_bandwidths,
        render_comparison,
        render_curvature,
        render_face_values,
        render_footprint,
        render_opc,
        render_panel,
        render_slope,
    )
    from .formats import COLUMNS, read_per_vertex, read_table, write_per_vertex, write_table
    from .mesh import load_mesh
    from .prepare import PreparedCrown, PrepareWarning, Protocol, ProtocolError, Step
    from .report import ReportSummary, write_report
    from .sign import curvature_measure, curvature_measure_sign, measure_radius
    from .study import (
        BandwidthSweep,
        ProtocolStudy,
        RobustnessStudy,
        bandwidth_sweep,
        perturb,
        protocol_study,
        robustness_study,
        sign_agreement,
        write_protocol_study,
        write_study,
        write_sweep,
    )
    from .topography import (
        AlphaAdjustmentError,
        ARCResult,
        ClassicDNEResult,
        FootprintError,
        FootprintWarning,
        OPCResult,
        OPCRResult,
        Orientation,
        RFIResult,
        SlopeResult,
        arc,
        classic_dne,
        find_orientation,
        opc,
        opcr,
        rfi,
        slope,
    )

#: Where each public name lives: imported on first use (PEP 562), so that
#: ``import dentopo`` and ``dentopo --version`` do not load numba, scipy and trimesh.
_EXPORTS = {
    "AriaDNEResult": ".ariadne",
    "ariaDNE": ".ariadne",
    "BatchResult": ".batch",
    "compute_batch": ".batch",
    "find_mesh_files": ".batch",
    "to_dataframe": ".batch",
    "ColorScale": ".figures",
    "DisplayUnavailableError": ".figures",
    "color_scale": ".figures",
    "diverging_rgb": ".figures",
    "render_bandwidths": ".figures",
    "render_comparison": ".figures",
    "render_curvature": ".figures",
    "render_face_values": ".figures",
    "render_footprint": ".figures",
    "render_opc": ".figures",
    "render_panel": ".figures",
    "render_slope": ".figures",
    "COLUMNS": ".formats",
    "read_per_vertex": ".formats",
    "read_table": ".formats",
    "write_per_vertex": ".formats",
    "write_table": ".formats",
    "load_mesh": ".mesh",
    "PreparedCrown": ".prepare",
    "PrepareWarning": ".prepare",
    "Protocol": ".prepare",
    "ProtocolError": ".prepare",
    "Step": ".prepare",
    "ReportSummary": ".report",
    "write_report": ".report",
    "curvature_measure": ".sign",
    "curvature_measure_sign": ".sign",
    "measure_radius": ".sign",
    "BandwidthSweep": ".study",
    "RobustnessStudy": ".study",
    "ProtocolStudy": ".study",
    "bandwidth_sweep": ".study",
    "perturb": ".study",
    "protocol_study": ".study",
    "write_protocol_study": ".study",
    "robustness_study": ".study",
    "sign_agreement": ".study",
    "write_study": ".study",
    "write_sweep": ".study",
    "AlphaAdjustmentError": ".topography",
    "ARCResult": ".topography",
    "ClassicDNEResult": ".topography",
    "FootprintError": ".topography",
    "FootprintWarning": ".topography",
    "OPCResult": ".topography",
    "OPCRResult": ".topography",
    "Orientation": ".topography",
    "RFIResult": ".topography",
    "SlopeResult": ".topography",
    "arc": ".topography",
    "classic_dne": ".topography",
    "find_orientation": ".topography",
    "opc": ".topography",
    "opcr": ".topography",
    "rfi": ".topography",
    "slope": ".topography",
}

__all__ = [
    "COLUMNS",
    "ARCResult",
    "AlphaAdjustmentError",
    "AriaDNEResult",
    "BandwidthSweep",
    "BatchResult",
    "ClassicDNEResult",
    "ColorScale",
    "DisplayUnavailableError",
    "FootprintError",
    "FootprintWarning",
    "OPCRResult",
    "OPCResult",
    "Orientation",
    "PrepareWarning",
    "PreparedCrown",
    "Protocol",
    "ProtocolError",
    "ProtocolStudy",
    "RFIResult",
    "ReportSummary",
    "RobustnessStudy",
    "SlopeResult",
    "Step",
    "__version__",
    "arc",
    "ariaDNE",
    "bandwidth_sweep",
    "classic_dne",
    "color_scale",
    "compute_batch",
    "curvature_measure",
    "curvature_measure_sign",
    "diverging_rgb",
    "find_mesh_files",
    "find_orientation",
    "load_mesh",
    "measure_radius",
    "opc",
    "opcr",
    "perturb",
    "prepare",
    "protocol_study",
    "read_per_vertex",
    "read_table",
    "render_bandwidths",
    "render_comparison",
    "render_curvature",
    "render_face_values",
    "render_footprint",
    "render_opc",
    "render_panel",
    "render_slope",
    "rfi",
    "robustness_study",
    "sign_agreement",
    "slope",
    "to_dataframe",
    "write_per_vertex",
    "write_protocol_study",
    "write_report",
    "write_study",
    "write_sweep",
    "write_table",
]


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, __all__)
