"""signdne: ariaDNE and its sign-oriented extension for triangle meshes.

ariaDNE (Shan et al. 2019) measures how curved a surface is, robustly to how it
is meshed; the sign-oriented extension (signDNE) splits it into convex (cusps,
ridges) and concave (valleys, basins) parts.

>>> from signdne import ariaDNE
>>> result = ariaDNE("tooth.ply")             # doctest: +SKIP
>>> result.dne, result.positive_dne, result.negative_dne  # doctest: +SKIP
"""

from ._ariadne import ariaDNE
from ._batch import compute_batch, to_dataframe
from ._classic import ClassicDNEResult, classic_dne
from ._colors import ColorScale, color_scale, diverging_rgb
from ._inputs import find_mesh_files
from ._measure_sign import curvature_measure, curvature_measure_sign, measure_radius
from ._mesh import load_mesh
from ._output import COLUMNS
from ._render import (  # pyvista is imported only when a picture is drawn
    DisplayUnavailableError,
    render_bandwidths,
    render_comparison,
    render_curvature,
    render_panel,
)
from ._result import AriaDNEResult
from ._robustness import (
    BandwidthSweep,
    RobustnessStudy,
    bandwidth_sweep,
    perturb,
    robustness_study,
    sign_agreement,
    write_study,
    write_sweep,
)
from ._version import __version__

__all__ = [
    "COLUMNS",
    "AriaDNEResult",
    "BandwidthSweep",
    "ClassicDNEResult",
    "ColorScale",
    "DisplayUnavailableError",
    "RobustnessStudy",
    "__version__",
    "ariaDNE",
    "bandwidth_sweep",
    "classic_dne",
    "color_scale",
    "compute_batch",
    "curvature_measure",
    "curvature_measure_sign",
    "diverging_rgb",
    "find_mesh_files",
    "load_mesh",
    "measure_radius",
    "perturb",
    "render_bandwidths",
    "render_comparison",
    "render_curvature",
    "render_panel",
    "robustness_study",
    "sign_agreement",
    "to_dataframe",
    "write_study",
    "write_sweep",
]
