"""The bending at each vertex: eigen-decomposition of its 3 x 3 weighted covariance.

A compiled cyclic Jacobi solver, one matrix at a time, in parallel over the
vertices.  Jacobi rotations are the most accurate way to diagonalise a small
symmetric matrix (eigenvalues to rounding error of the matrix's norm, each
eigenvector to rounding error over its eigenvalue gap, as LAPACK's ``syevd``
behind ``numpy.linalg.eigh``), and doing it in compiled code for 3 x 3
matrices is several times faster than ``eigh`` on a stack of them.

The eigenpairs are sorted by ascending eigenvalue before the choice, as
``eigh`` returns them, so that ties (a zero normal, a normal exactly between
two eigenvectors) go to the same eigenpair as with ``eigh``: the first one.
"""

from __future__ import annotations

import numpy as np

from .._jit import njit, prange

#: Jacobi sweeps at most; a 3 x 3 matrix converges in about four.
MAX_SWEEPS = 50


@njit(inline="always")
def _rotate(a, v, p, q):
    """One Jacobi rotation that zeroes ``a[p, q]`` (Rutishauser's formulas)."""
    apq = a[p, q]
    if apq == 0.0:
        return
    theta = (a[q, q] - a[p, p]) / (2.0 * apq)
    if abs(theta) > 1e150:  # theta**2 would overflow
        t = 0.5 / theta
    else:
        t = 1.0 / (abs(theta) + np.sqrt(theta * theta + 1.0))
        if theta < 0.0:
            t = -t
    c = 1.0 / np.sqrt(t * t + 1.0)
    s = t * c
    tau = s / (1.0 + c)
    h = t * apq
    a[p, p] -= h
    a[q, q] += h
    a[p, q] = 0.0
    a[q, p] = 0.0
    for r in range(3):
        if r != p and r != q:
            g = a[r, p]
            f = a[r, q]
            a[r, p] = g - s * (f + g * tau)
            a[p, r] = a[r, p]
            a[r, q] = f + s * (g - f * tau)
            a[q, r] = a[r, q]
    for r in range(3):
        g = v[r, p]
        f = v[r, q]
        v[r, p] = g - s * (f + g * tau)
        v[r, q] = f + s * (g - f * tau)


@njit(inline="always")
def _jacobi(a, v):
    """Diagonalise the symmetric 3 x 3 ``a`` in place; ``v`` (identity on entry) gets the vectors.

    Off-diagonal entries too small to change either diagonal entry they couple
    are set to zero (the classic test: ``|a_pp| + 100 |a_pq| == |a_pp|``).
    """
    for _ in range(MAX_SWEEPS):
        done = True
        for p, q in ((0, 1), (0, 2), (1, 2)):
            g = 100.0 * abs(a[p, q])
            if g == 0.0:
                continue
            if abs(a[p, p]) + g == abs(a[p, p]) and abs(a[q, q]) + g == abs(a[q, q]):
                a[p, q] = 0.0
                a[q, p] = 0.0
                continue
            done = False
            _rotate(a, v, p, q)
        if done:
            return


def _bending(covariance, normals, work, out):
    """``out[i] = lambda / trace`` of ``covariance[i]`` (see ``bending``).

    ``work`` (n, 2, 3, 3) is scratch space.  Writes into ``out`` and returns
    nothing (see ``dentopo.ariadne._kernel._run_sums``).
    """
    for i in prange(covariance.shape[0]):
        a = work[i, 0]
        v = work[i, 1]
        for r in range(3):
            for c in range(3):
                a[r, c] = covariance[i, r, c]
                v[r, c] = 1.0 if r == c else 0.0
        _jacobi(a, v)
        # the three eigenpairs by ascending eigenvalue (a stable sort, as eigh's order)
        k0, k1, k2 = 0, 1, 2
        if a[k1, k1] < a[k0, k0]:
            k0, k1 = k1, k0
        if a[k2, k2] < a[k1, k1]:
            k1, k2 = k2, k1
            if a[k1, k1] < a[k0, k0]:
                k0, k1 = k1, k0
        best = -1.0
        pick = 0.0
        trace = 0.0
        for col in (k0, k1, k2):
            lam = a[col, col]
            trace += lam
            closeness = abs(
                v[0, col] * normals[i, 0] + v[1, col] * normals[i, 1] + v[2, col] * normals[i, 2]
            )
            if closeness > best:  # strictly: a tie keeps the first, as argmax does
                best = closeness
                pick = lam
        out[i] = pick / trace if trace > 0 else 0.0


#: The compiled loop, serial and parallel: threads pay off from this many vertices on
#: (starting them costs more than 2,000 solves, on a busy machine much more).
_bending_serial = njit(cache=True)(_bending)
_bending_parallel = njit(cache=True, parallel=True)(_bending)
PARALLEL_VERTICES = 50_000


def bending(covariance: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """Local bending ``lambda / trace`` of each symmetric 3 x 3 covariance.

    ``lambda`` is the eigenvalue whose eigenvector is closest in direction (up
    to sign) to the vertex normal; ``trace`` the sum of the three eigenvalues.
    A zero covariance (an isolated vertex) gives 0.

    Parameters
    ----------
    covariance : (n, 3, 3) float
        Symmetric matrices.
    normals : (n, 3) float
        Vertex normals.

    Returns
    -------
    (n,) float
    """
    covariance = np.ascontiguousarray(covariance, dtype=np.float64)
    normals = np.ascontiguousarray(normals, dtype=np.float64)
    out = np.empty(len(covariance))
    solve = _bending_parallel if len(covariance) >= PARALLEL_VERTICES else _bending_serial
    solve(covariance, normals, np.empty((len(covariance), 2, 3, 3)), out)
    return out
