"""ariaDNE and its sign-oriented extension: the paper's pipeline.

In the order ALGORITHM.md gives it: the parameters and their ranges
(``_parameters``); the kernel-weighted sums over neighbours, exact
(``_kernel``: Euclidean, geodesic, precomputed) or as a fast Gauss transform
(``_fastgauss``, FINUFFT); the bending from the weighted covariance (``_eigen``,
a compiled 3 x 3 eigen-solver) and the totals (``_ariadne``, the entry point
:func:`ariaDNE`); the named result (``_result``).

May import: :mod:`dentopo.mesh`, :mod:`dentopo.sign`.  Nothing from topography,
figures, formats, batch, study or cli.
"""

from ._ariadne import DISTANCE_TYPES, ariaDNE, check_distance_type
from ._fastgauss import METHODS, check_method, finufft_available
from ._parameters import BANDWIDTH_RANGE, check_bandwidth, check_cutoff, check_number
from ._result import SCALAR_FIELDS, AriaDNEResult

__all__ = [
    "BANDWIDTH_RANGE",
    "DISTANCE_TYPES",
    "METHODS",
    "SCALAR_FIELDS",
    "AriaDNEResult",
    "ariaDNE",
    "check_bandwidth",
    "check_cutoff",
    "check_distance_type",
    "check_method",
    "check_number",
    "finufft_available",
]
