"""The decimate step: quadric edge collapse to a face count.

SKELETON (first version: fast-simplification, to be finished: boundary kept, within 1 %).
"""

from __future__ import annotations

import numpy as np

from ._result import Outcome


def run(vertices: np.ndarray, faces: np.ndarray, *, faces_target: int, method: str) -> Outcome:
    import fast_simplification  # a dependency; imported here, when a mesh is decimated

    if faces_target >= len(faces):
        return Outcome(vertices, faces, details={"faces_reached": len(faces)})
    v, f = fast_simplification.simplify(
        vertices.astype(np.float32), faces.astype(np.int32), 1.0 - faces_target / len(faces)
    )
    return Outcome(
        np.asarray(v, np.float64), np.asarray(f, np.int64), details={"faces_reached": len(f)}
    )
