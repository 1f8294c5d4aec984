"""The smooth step: Laplacian, Taubin, HC (trimesh's filters) or implicit fairing.

``laplacian``, ``taubin`` and ``hc`` are trimesh's own filters
(:func:`trimesh.smoothing.filter_laplacian`, ``filter_taubin``,
``filter_humphrey``: Vollmer, Mencl & Müller 1999's umbrella-operator
filters), called with ``step`` as their first parameter (``lamb``, ``lamb``,
``alpha``) and ``mu`` as their second (Taubin's ``nu``, HC's ``beta``), with
trimesh's defaults (:data:`SMOOTHERS`).  One departure: the Laplacian filter
runs with ``volume_constraint=False``.  trimesh's default rescales the mesh
about its centre of mass after every pass to restore its volume, but an open
crown has no volume (the value trimesh computes for it depends on where the
origin lies), and the rescaling would move the base it is asked to keep.

``implicit`` is implicit fairing (Desbrun, Meyer, Schröder & Barr 1999,
"Implicit fairing of irregular meshes using diffusion and curvature flow"):
each iteration solves ``(I - step * L) X_new = X`` with scipy.sparse, ``L``
the cotangent (curvature-flow) operator.  It follows what MorphoTester
(Winchester 2016) does, described from its source and written anew here: ``L``
has off-diagonal entries ``L[i, j] = cot(a) + cot(b)``, the cotangents of the
two angles facing edge ``ij`` (one on a boundary edge; a degenerate angle
counts 0), and diagonal ``L[i, i] = -sum_j L[i, j]``; it is neither divided by
vertex areas nor normalised by its row sums, is built once from the input
mesh, and the same factorisation serves every iteration; no volume is
restored.  MorphoTester's defaults are 3 iterations of step 0.1 (our
``SMOOTHERS``).  The operator and the solve live in
:mod:`dentopo.topography.surface._morphotester`, beside MorphoTester's DNE that smooths
with them.  MorphoTester factorises ``I - step * L`` by Cholesky and stops with an
error when it is not positive definite; so does this (a ``ValueError`` naming the
cause), never a silent fallback.  With the cotangents computed stably, as here
(``dot / |cross|``), ``-L`` is a sum of one positive semi-definite matrix per face
(obtuse ones too: it is twice the P1 finite-element stiffness matrix), so the system is
positive definite up to rounding and the error needs nearly degenerate faces;
MorphoTester's own cotangents (from the arccos of each angle) lose that on nearly
degenerate faces, which is why it fails on meshes this smooths.  Cotangents have no
unit, so ``step`` means the same at any mesh unit: smoothing a mesh scaled by 1000
gives the smoothed mesh scaled by 1000 (tested); being unnormalised, the operator's
strength follows the mesh's resolution (as MorphoTester's does), which is why it is
applied after decimation.

The open boundary (a crown's cervical base) is pinned by default
(``pin_boundary=True``): its vertices do not move, so the base outline that
orient and crop produced, and that decimation kept, is still the outline after
smoothing.  Unpinned, every filter here pulls the boundary inwards (trimesh's
umbrella operator averages a boundary vertex over its one-sided ring,
MorphoTester's operator likewise).  Measured on the shared 8,000-face crowns
(``normal``, ``noise1``; ``high``, 20,000 faces, alike), in mean edge lengths,
unpinned base vertices move: implicit fairing (3 iterations, step 0.1) 0.41 on
average (0.60 at most), four times the whole mesh's average move of 0.10;
Laplacian (10 passes, 0.5) 1.31 (1.75); Taubin (10, 0.5/0.5) 0.37 (0.74);
HC (10, 0.1/0.5) 0.52 (0.90).  The shipped ``morphotester-smooth`` protocol
sets ``pin_boundary = false``, as MorphoTester does not pin.  With
``pin_boundary=False`` the filters are exactly trimesh's (and MorphoTester's)
as they are; pinned, trimesh's filters run with trimesh's own pinned operator
(``laplacian_calculation(mesh, pinned_vertices=...)``), and implicit fairing
keeps the pinned rows of its system as identity rows.

A filter that diverges is an error, never a mesh: the protocol keeps every
parameter in its method's range (:data:`~dentopo.prepare._protocol.SMOOTH_LIMITS`,
at most :data:`~dentopo.prepare._protocol.MAX_SMOOTH_ITERATIONS` passes), and
within it Laplacian smoothing cannot diverge; Taubin's and HC's filters still
can for some pairs of parameters (Taubin with step 0.1 and mu 1 grows the
sample tooth 1e13-fold in 100 passes).  So the result is checked: non-finite
coordinates, or a mesh grown more than :data:`GROWTH` times in size (no
smoothing grows a mesh: Taubin's slight inflation is a fraction of a percent),
raise a ``ValueError`` naming the method and its parameters.
"""

from __future__ import annotations

import math

import numpy as np
import trimesh

from ..mesh import boundary_edges
from ..topography.surface._morphotester import (  # noqa: F401 (cotangent_operator: re-exported)
    cotangent_operator,
    implicit_fairing,
)
from ._protocol import SMOOTHERS
from ._result import Outcome

#: A smoothed mesh whose size (the largest side of its bounding box) is more than this many
#: times the input's has diverged.
GROWTH = 10.0


def _extent(vertices: np.ndarray) -> float:
    with np.errstate(over="ignore", invalid="ignore"):
        return float(np.max(np.ptp(vertices, axis=0))) if len(vertices) else 0.0


def check_converged(
    before: np.ndarray, after: np.ndarray, *, method: str, iterations: int, step, mu=None
) -> None:
    """Raise ``ValueError`` naming the parameters if smoothing `before` gave a diverged `after`.

    Diverged: a non-finite coordinate, or a size more than :data:`GROWTH` times the input's.
    """
    grown = _extent(after)
    if np.all(np.isfinite(after)) and np.isfinite(grown):
        size = _extent(before)
        if not grown > GROWTH * size:
            return
        what = f"the mesh grew {grown / size:.3g}-fold" if size > 0 else "the mesh grew"
    else:
        what = "it gave non-finite coordinates"
    given = f"step {step:g}" + ("" if mu is None else f", mu {mu:g}")
    raise ValueError(
        f"{method} smoothing diverged ({what}) with {given} over {iterations} iterations: "
        f"{_REMEDY.get(method, 'take a smaller step')}, or fewer iterations"
    )


#: What to change when a filter diverges.  HC cannot diverge with mu (beta) at least 0.5
#: (every eigenvalue of its iteration is then at most 1 in size, the step in (0, 1]).
_REMEDY = {
    "laplacian": "take a step of at most 1",
    "taubin": "take mu a little above step (Taubin's rule: 1/step - 1/mu between 0 and 0.1)",
    "hc": "take mu of 0.5 or more (HC then cannot diverge)",
}


def boundary_vertices(faces: np.ndarray, n_vertices: int) -> np.ndarray:
    """The vertices on an open boundary (sorted, unique; empty for a closed mesh)."""
    return np.unique(boundary_edges(faces, n_vertices)).astype(np.int64)


def run(
    vertices: np.ndarray,
    faces: np.ndarray,
    *,
    method: str,
    iterations: int,
    step: float,
    mu: float | None = None,
    pin_boundary: bool = True,
) -> Outcome:
    """Smooth the vertices (the faces are kept); see the module docstring for each method.

    Parameters
    ----------
    vertices : (n, 3) float array
    faces : (m, 3) int array
        The mesh (not modified).
    method : {"laplacian", "taubin", "hc", "implicit"}
    iterations : int
        Passes (0: the mesh as it is).
    step : float
        Laplacian's and Taubin's ``lamb``, HC's ``alpha``, implicit fairing's time step.
    mu : float, optional
        Taubin's ``nu``, HC's ``beta`` (None: trimesh's default, 0.5).
    pin_boundary : bool
        Keep the open boundary's vertices where they are (default).

    Raises
    ------
    ValueError
        If a parameter is wrong (named), or implicit fairing's system cannot be solved.
    """
    if method not in SMOOTHERS:
        raise ValueError(f"method must be one of {', '.join(map(repr, SMOOTHERS))}; got {method!r}")
    if isinstance(iterations, bool) or not isinstance(iterations, (int, np.integer)):
        raise ValueError(f"iterations must be a whole number; got {iterations!r}")
    if iterations < 0:
        raise ValueError(f"iterations must be at least 0; got {iterations}")
    if isinstance(step, bool) or not (isinstance(step, (int, float)) and math.isfinite(step)):
        raise ValueError(f"step must be a finite number; got {step!r}")
    if not step > 0:
        raise ValueError(f"step must be above 0; got {step:g}")
    if mu is not None and method not in ("taubin", "hc"):
        raise ValueError(f"mu is a parameter of taubin and hc, not {method}")
    if mu is None:
        mu = SMOOTHERS[method]["mu"]
    iterations = int(iterations)
    pinned = boundary_vertices(faces, len(vertices)) if pin_boundary else np.zeros(0, np.int64)
    details = {"pinned_vertices": len(pinned)}
    if iterations == 0:
        return Outcome(vertices.copy(), faces.copy(), details=details)
    given = {"method": method, "iterations": iterations, "step": step}
    if method == "implicit":
        moved = implicit_fairing(vertices, faces, iterations=iterations, step=step, pinned=pinned)
        check_converged(vertices, moved, **given)
        return Outcome(moved, faces.copy(), details=details)
    with np.errstate(over="ignore", invalid="ignore"):  # a diverging filter: checked below
        moved = _explicit(vertices, faces, method, iterations, step, mu, pinned)
    check_converged(vertices, moved, **given, mu=mu if method in ("taubin", "hc") else None)
    if pin_boundary and len(pinned):
        moved[pinned] = vertices[pinned]  # exactly: the operator keeps them, up to rounding
    return Outcome(moved, faces.copy(), details=details)


def _explicit(vertices, faces, method, iterations, step, mu, pinned) -> np.ndarray:
    """trimesh's `method` filter on a copy of the mesh (with its pinned operator)."""
    mesh = trimesh.Trimesh(vertices=vertices.copy(), faces=faces.copy(), process=False)
    operator = (
        trimesh.smoothing.laplacian_calculation(mesh, pinned_vertices=pinned)
        if len(pinned)
        else None
    )
    if method == "laplacian":
        trimesh.smoothing.filter_laplacian(
            mesh,
            lamb=step,
            iterations=iterations,
            volume_constraint=False,
            laplacian_operator=operator,
        )
    elif method == "taubin":
        trimesh.smoothing.filter_taubin(
            mesh, lamb=step, nu=mu, iterations=iterations, laplacian_operator=operator
        )
    else:
        trimesh.smoothing.filter_humphrey(
            mesh, alpha=step, beta=mu, iterations=iterations, laplacian_operator=operator
        )
    return np.array(mesh.vertices, dtype=np.float64)
