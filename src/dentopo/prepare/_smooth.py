"""The smooth step: Laplacian, Taubin, HC (trimesh's filters) or implicit fairing.

SKELETON (first version: trimesh's filters; implicit fairing to be written).
"""

from __future__ import annotations

import numpy as np
import trimesh

from ._result import Outcome


def run(
    vertices: np.ndarray,
    faces: np.ndarray,
    *,
    method: str,
    iterations: int,
    step: float,
    mu: float | None = None,
) -> Outcome:
    mesh = trimesh.Trimesh(vertices=vertices.copy(), faces=faces.copy(), process=False)
    if method == "laplacian":
        trimesh.smoothing.filter_laplacian(mesh, lamb=step, iterations=iterations)
    elif method == "taubin":
        trimesh.smoothing.filter_taubin(mesh, lamb=step, nu=mu, iterations=iterations)
    elif method == "hc":
        trimesh.smoothing.filter_humphrey(mesh, alpha=step, beta=mu, iterations=iterations)
    else:
        raise NotImplementedError("implicit fairing is not written yet")
    return Outcome(np.asarray(mesh.vertices, np.float64), faces)
