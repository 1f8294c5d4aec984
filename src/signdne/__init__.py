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
from ._inputs import find_mesh_files
from ._mesh import load_mesh
from ._output import COLUMNS
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
    "RobustnessStudy",
    "__version__",
    "ariaDNE",
    "bandwidth_sweep",
    "classic_dne",
    "compute_batch",
    "find_mesh_files",
    "load_mesh",
    "perturb",
    "robustness_study",
    "sign_agreement",
    "to_dataframe",
    "write_study",
    "write_sweep",
]
