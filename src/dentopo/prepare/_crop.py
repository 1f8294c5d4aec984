"""The crop step: keep what lies above a plane, cutting straddling faces exactly.

SKELETON (to be written).
"""

from __future__ import annotations

import numpy as np

from ._result import Outcome


def run(
    vertices: np.ndarray, faces: np.ndarray, *, below=None, fraction=None, plane=None
) -> Outcome:
    raise NotImplementedError("crop is not written yet")
