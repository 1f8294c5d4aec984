"""The compiled 3 x 3 eigen-solver's bending equals numpy's ``eigh`` to rounding error."""

from __future__ import annotations

import numpy as np
import pytest

from dentopo.ariadne._eigen import bending


def eigh_bending(covariance, normals):
    """The bending as ALGORITHM.md states it, through numpy.linalg.eigh."""
    values, vectors = np.linalg.eigh(covariance)
    closeness = np.abs(np.einsum("nij,ni->nj", vectors, normals))
    pick = np.argmax(closeness, axis=1)
    lam = np.take_along_axis(values, pick[:, None], axis=1)[:, 0]
    trace = values.sum(axis=1)
    return np.divide(lam, trace, out=np.zeros_like(lam), where=trace > 0)


def random_covariances(rng, n, spread):
    """Symmetric positive semi-definite matrices with eigenvalues ``spread`` apart (log10)."""
    q, _ = np.linalg.qr(rng.normal(size=(n, 3, 3)))
    values = 10.0 ** rng.uniform(-spread, 0, size=(n, 3))
    return np.einsum("nij,nj,nkj->nik", q, values, q)


def unit(rng, n):
    v = rng.normal(size=(n, 3))
    return v / np.linalg.norm(v, axis=1, keepdims=True)


@pytest.mark.parametrize("spread", [0.5, 3, 8])
def test_random_matrices_agree_with_eigh(spread):
    rng = np.random.default_rng(int(spread * 10))
    covariance = random_covariances(rng, 20_000, spread)
    normals = unit(rng, 20_000)
    ours, theirs = bending(covariance, normals), eigh_bending(covariance, normals)
    # a pick may differ only where two eigenvectors are about equally close to the normal
    vectors = np.linalg.eigh(covariance)[1]
    close = np.sort(np.abs(np.einsum("nij,ni->nj", vectors, normals)), axis=1)
    clear = close[:, 2] - close[:, 1] > 1e-8
    assert clear.mean() > 0.999
    np.testing.assert_allclose(ours[clear], theirs[clear], rtol=0, atol=1e-14)


def test_covariances_of_real_neighbourhoods_agree_with_eigh(tooth):
    from dentopo.ariadne._kernel import euclidean_moments
    from dentopo.mesh import prepare

    prepared = prepare(tooth)
    moments = euclidean_moments(prepared.points, 0.08, 0.0)
    ours = bending(moments.covariance, prepared.normals)
    theirs = eigh_bending(moments.covariance, prepared.normals)
    np.testing.assert_allclose(ours, theirs, rtol=0, atol=1e-14)


def test_degenerate_matrices():
    rng = np.random.default_rng(3)
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    cases = [
        np.zeros((3, 3)),  # an isolated vertex: 0
        np.eye(3) * 2.5,  # every direction an eigenvector
        np.diag([1.0, 1.0, 4.0]),  # a repeated eigenvalue
        q @ np.diag([0.0, 0.0, 3.0]) @ q.T,  # rank one, rotated
        q @ np.diag([0.0, 2.0, 2.0]) @ q.T,  # rank two, repeated, rotated
        q @ np.diag([1e-300, 1.0, 1e300]) @ q.T,  # extreme range
        np.diag([3.0, 1.0, 2.0]) + 1e-30 * (1 - np.eye(3)),  # as good as diagonal
    ]
    normals = unit(rng, len(cases))
    covariance = np.array(cases)
    ours, theirs = bending(covariance, normals), eigh_bending(covariance, normals)
    assert ours[0] == 0.0
    assert ours[1] == pytest.approx(1 / 3, rel=1e-15)
    np.testing.assert_allclose(ours, theirs, rtol=1e-12, atol=1e-15)


def test_ties_go_to_the_smallest_eigenvalue_as_with_eigh():
    # a zero normal is equally close to every eigenvector; a normal exactly
    # between two eigenvectors is equally close to both
    covariance = np.array([np.diag([2.0, 1.0, 3.0]), np.diag([2.0, 1.0, 3.0])])
    normals = np.array([[0.0, 0.0, 0.0], [np.sqrt(0.5), 0.0, np.sqrt(0.5)]])
    ours = bending(covariance, normals)
    np.testing.assert_array_equal(ours, eigh_bending(covariance, normals))
    assert list(ours) == [1 / 6, 2 / 6]


def test_inputs_are_not_modified():
    rng = np.random.default_rng(4)
    covariance = random_covariances(rng, 50, 2)
    normals = unit(rng, 50)
    saved = covariance.copy(), normals.copy()
    bending(covariance, normals)
    np.testing.assert_array_equal(covariance, saved[0])
    np.testing.assert_array_equal(normals, saved[1])


def test_serial_and_parallel_loops_give_the_same_bits(monkeypatch):
    from dentopo.ariadne import _eigen

    rng = np.random.default_rng(5)
    covariance = random_covariances(rng, 3000, 4)
    normals = unit(rng, 3000)
    serial = bending(covariance, normals)
    monkeypatch.setattr(_eigen, "PARALLEL_VERTICES", 0)
    np.testing.assert_array_equal(bending(covariance, normals), serial)
