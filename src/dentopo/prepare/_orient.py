"""The orient step: a rigid motion that puts the crown occlusal side up (+z).

SKELETON (to be written): see the issue's rules; must return ``Outcome`` with
``transform`` (4x4 rigid, det +1) and ``plane`` (the base plane found, open crown).
"""

from __future__ import annotations

import numpy as np

from ._result import Outcome


def run(vertices: np.ndarray, faces: np.ndarray, *, mode: str, up, spin: str) -> Outcome:
    raise NotImplementedError("orient is not written yet")
