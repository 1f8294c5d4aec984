"""The paper's robustness study and the bandwidth sweep, with their figures.

``_robustness`` builds the perturbations (decimation, refinement, noise,
smoothing), computes every sign method and classic DNE on each, and writes the
table; ``_figures`` draws its matplotlib figures (imported only when written).

May import: :mod:`dentopo.mesh`, :mod:`dentopo.sign`, :mod:`dentopo.ariadne`,
:mod:`dentopo.topography`, :mod:`dentopo.formats` (atomic writes),
:mod:`dentopo.figures` (the one diverging colour map).  Nothing from batch or
cli.
"""

from ._robustness import (
    METHODS,
    PERTURBATIONS,
    STUDY_COLUMNS,
    STUDY_FILES,
    SWEEP_COLUMNS,
    SWEEP_FILES,
    SWEEP_METHODS,
    BandwidthSweep,
    RobustnessStudy,
    bandwidth_sweep,
    perturb,
    refine,
    robustness_study,
    sign_agreement,
    write_study,
    write_sweep,
)

__all__ = [
    "METHODS",
    "PERTURBATIONS",
    "STUDY_COLUMNS",
    "STUDY_FILES",
    "SWEEP_COLUMNS",
    "SWEEP_FILES",
    "SWEEP_METHODS",
    "BandwidthSweep",
    "RobustnessStudy",
    "bandwidth_sweep",
    "perturb",
    "refine",
    "robustness_study",
    "sign_agreement",
    "write_study",
    "write_sweep",
]
