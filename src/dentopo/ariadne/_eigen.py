"""The bending at each vertex: eigen-decomposition of its 3 x 3 weighted covariance.

A compiled cyclic Jacobi solver, one matrix at a time, on several threads over the
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

from .._jit import in_threads, njit

#: Jacobi sweeps at most; a 3 x 3 matrix converges in about four.
MAX_SWEEPS = 50


@njit(inline="always")
def _rotation(app, aqq, apq):
    """``s``, ``tau`` and ``h`` of the Jacobi rotation that zeroes ``apq`` (Rutishauser)."""
    theta = (aqq - app) / (2.0 * apq)
    if abs(theta) > 1e150:  # theta**2 would overflow
        t = 0.5 / theta
    else:
        t = 1.0 / (abs(theta) + np.sqrt(theta * theta + 1.0))
        if theta < 0.0:
            t = -t
    c = 1.0 / np.sqrt(t * t + 1.0)
    s = t * c
    return s, s / (1.0 + c), t * apq


@njit(inline="always")
def _turn(g, f, s, tau):
    """A pair of entries ``(x_p, x_q)`` after the rotation."""
    return g - s * (f + g * tau), f + s * (g - f * tau)


@njit(inline="always")
def _zero(app, aqq, apq, g, f, v0p, v0q, v1p, v1q, v2p, v2q):
    """The entries after zeroing ``apq``, and whether that took a rotation.

    ``apq`` too small to change either diagonal entry it couples (``|a_pp| +
    100 |a_pq| == |a_pp|``, and the same for ``a_qq``) is set to zero;
    otherwise a rotation zeroes it, turning the diagonal pair, ``(g, f)`` (the
    third row's entries in columns p and q) and the vectors' columns p and q.
    """
    t = 100.0 * abs(apq)
    if abs(app) + t == abs(app) and abs(aqq) + t == abs(aqq):
        return app, aqq, 0.0, g, f, v0p, v0q, v1p, v1q, v2p, v2q, False
    s, tau, h = _rotation(app, aqq, apq)
    g, f = _turn(g, f, s, tau)
    v0p, v0q = _turn(v0p, v0q, s, tau)
    v1p, v1q = _turn(v1p, v1q, s, tau)
    v2p, v2q = _turn(v2p, v2q, s, tau)
    return app - h, aqq + h, 0.0, g, f, v0p, v0q, v1p, v1q, v2p, v2q, True


def _bending(covariance, normals, out):
    """``out[i] = lambda / trace`` of ``covariance[i]`` (see ``bending``).

    A cyclic Jacobi solver on the six entries of the matrix and the nine of
    its eigenvectors held in registers: rotations zero ``a01``, ``a02`` and
    ``a12`` in turn (Rutishauser's formulas), sweep after sweep until every
    off-diagonal entry is zero or negligible (``|a_pp| + 100 |a_pq| ==
    |a_pp|``, and the same for ``a_qq``: it is then set to zero), at most
    ``MAX_SWEEPS``.  Writes into ``out`` and returns nothing (see
    ``dentopo.ariadne._kernel._run_sums``).
    """
    for i in range(covariance.shape[0]):
        a00 = covariance[i, 0, 0]
        a01 = covariance[i, 0, 1]
        a02 = covariance[i, 0, 2]
        a11 = covariance[i, 1, 1]
        a12 = covariance[i, 1, 2]
        a22 = covariance[i, 2, 2]
        v00, v01, v02 = 1.0, 0.0, 0.0
        v10, v11, v12 = 0.0, 1.0, 0.0
        v20, v21, v22 = 0.0, 0.0, 1.0
        for _ in range(MAX_SWEEPS):
            done = True
            if a01 != 0.0:  # p, q = 0, 1 (the third index: 2)
                a00, a11, a01, a02, a12, v00, v01, v10, v11, v20, v21, turned = _zero(
                    a00, a11, a01, a02, a12, v00, v01, v10, v11, v20, v21
                )
                done = done and not turned
            if a02 != 0.0:  # p, q = 0, 2 (the third index: 1)
                a00, a22, a02, a01, a12, v00, v02, v10, v12, v20, v22, turned = _zero(
                    a00, a22, a02, a01, a12, v00, v02, v10, v12, v20, v22
                )
                done = done and not turned
            if a12 != 0.0:  # p, q = 1, 2 (the third index: 0)
                a11, a22, a12, a01, a02, v01, v02, v11, v12, v21, v22, turned = _zero(
                    a11, a22, a12, a01, a02, v01, v02, v11, v12, v21, v22
                )
                done = done and not turned
            if done:
                break
        lams = (a00, a11, a22)
        nx, ny, nz = normals[i, 0], normals[i, 1], normals[i, 2]
        dots = (
            abs(v00 * nx + v10 * ny + v20 * nz),
            abs(v01 * nx + v11 * ny + v21 * nz),
            abs(v02 * nx + v12 * ny + v22 * nz),
        )
        # the three eigenpairs by ascending eigenvalue (a stable sort, as eigh's order)
        k0, k1, k2 = 0, 1, 2
        if lams[k1] < lams[k0]:
            k0, k1 = k1, k0
        if lams[k2] < lams[k1]:
            k1, k2 = k2, k1
            if lams[k1] < lams[k0]:
                k0, k1 = k1, k0
        best = -1.0
        pick = 0.0
        trace = 0.0
        for col in (k0, k1, k2):
            lam = lams[col]
            trace += lam
            if dots[col] > best:  # strictly: a tie keeps the first, as argmax does
                best = dots[col]
                pick = lam
        out[i] = pick / trace if trace > 0 else 0.0


#: The compiled loop, without the GIL: from this many vertices on, slices of the rows on
#: numba's threads (``dentopo._jit.in_threads``: a pool kept from call to call, so a slice
#: costs tens of microseconds; normal.ply's 4,050 solves, 1.5 ms on one thread, take 0.8
#: on two).  One compiled kernel for both: a ``prange`` copy of it compiled in 0.9 s more
#: on a fresh install, for the same bits (each row is solved alone).
_bending_compiled = njit(cache=True, nogil=True)(_bending)
PARALLEL_VERTICES = 2_048


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
    in_threads(
        0,
        len(out),
        lambda a, b: _bending_compiled(covariance[a:b], normals[a:b], out[a:b]),
        threads_from=PARALLEL_VERTICES,
    )
    return out
