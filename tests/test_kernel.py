"""The exact kernel sums equal brute-force sums over every pair."""

from __future__ import annotations

import numpy as np
import pytest

from dentopo.ariadne._kernel import euclidean_moments, exp_table, kernel_radius


def brute_force(points, bandwidth, cutoff):
    diff = points[None, :, :] - points[:, None, :]  # x_j - x_i
    sq = (diff**2).sum(-1)
    weight = np.exp(-sq / bandwidth**2)
    keep = (weight > cutoff) & (sq <= kernel_radius(bandwidth, cutoff) ** 2)
    weight = np.where(keep, weight, 0.0)
    return (
        weight.sum(1),
        np.einsum("ij,ijk->ik", weight, diff),
        np.einsum("ij,ijk,ijl->ikl", weight, diff, diff),
        keep.sum(1),
    )


@pytest.mark.parametrize(
    ("bandwidth", "cutoff"), [(0.08, 0.0), (0.03, 0.0), (0.2, 0.0), (0.08, 0.3)]
)
def test_kernel_sums_equal_brute_force(bandwidth, cutoff):
    rng = np.random.default_rng(7)
    points = rng.normal(size=(700, 3)) * [0.5, 0.3, 0.1]
    moments = euclidean_moments(points, bandwidth, cutoff)
    weight, first, second, count = brute_force(points, bandwidth, cutoff)
    np.testing.assert_allclose(moments.weight, weight, rtol=1e-13)
    np.testing.assert_allclose(moments.first, first, rtol=1e-12, atol=1e-15 * np.abs(first).max())
    np.testing.assert_allclose(
        moments.second, second, rtol=1e-12, atol=1e-15 * np.abs(second).max()
    )
    np.testing.assert_array_equal(moments.count, count)


def test_inline_exponential_is_within_a_few_ulps():
    """The kernel's table-times-polynomial exponential against libm, over its whole range."""
    steps = 16
    t = np.linspace(0.0, 37.3, 400_001)
    table = exp_table(37.3)
    m = np.floor(t * steps)
    r = (m - t * steps) / steps
    poly = sum(r**k / np.prod(np.arange(1, k + 1)) for k in range(11))
    ours = table[m.astype(int)] * poly
    assert np.max(np.abs(ours / np.exp(-t) - 1)) < 5e-16
