"""The paper's robustness study and the bandwidth sweep, with their figures.

``_protocol_study`` varies the protocol's parameters (face count, smoothing
iterations, noise) and measures every metric of the batch on each mesh against
a base protocol (Spradley et al. 2017's question).  ``_robustness`` builds the
perturbations (decimation, refinement, noise, smoothing), computes every sign
method and classic DNE on each, and writes the table; ``_figures`` draws their
matplotlib figures (imported only when written).

May import: :mod:`dentopo.mesh`, :mod:`dentopo.sign`, :mod:`dentopo.ariadne`,
:mod:`dentopo.topography`, :mod:`dentopo.formats` (atomic writes),
:mod:`dentopo.figures` (the one diverging colour map), :mod:`dentopo.prepare`
(the protocol's decimate and smooth steps) and :mod:`dentopo.batch` (its
measuring of one mesh, so that a study row holds what a table row holds).
Nothing from cli.
"""

from ._protocol_study import (
    AXES,
    PROTOCOL_STUDY_COLUMNS,
    QUANTITIES,
    SUMMARY_COLUMNS,
    ProtocolStudy,
    protocol_study,
    protocol_study_files,
    write_protocol_study,
)
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
    "AXES",
    "METHODS",
    "PERTURBATIONS",
    "PROTOCOL_STUDY_COLUMNS",
    "QUANTITIES",
    "STUDY_COLUMNS",
    "STUDY_FILES",
    "SUMMARY_COLUMNS",
    "SWEEP_COLUMNS",
    "SWEEP_FILES",
    "SWEEP_METHODS",
    "BandwidthSweep",
    "ProtocolStudy",
    "RobustnessStudy",
    "bandwidth_sweep",
    "perturb",
    "protocol_study",
    "protocol_study_files",
    "refine",
    "robustness_study",
    "sign_agreement",
    "write_protocol_study",
    "write_study",
    "write_sweep",
]
