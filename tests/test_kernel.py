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


def test_kernel_sums_with_a_stray_point_equal_brute_force():
    # a point far out: the other points' spatial order must stay compact, and
    # the far point sees only itself
    rng = np.random.default_rng(3)
    points = rng.normal(size=(600, 3)) * [0.5, 0.3, 0.1]
    points[17] = [4e5, -3e5, 2e5]
    moments = euclidean_moments(points, 0.05, 0.0)
    weight, _, second, count = brute_force(points, 0.05, 0.0)
    np.testing.assert_allclose(moments.weight, weight, rtol=1e-13)
    np.testing.assert_allclose(moments.second, second, rtol=1e-12, atol=1e-15 * second.max())
    np.testing.assert_array_equal(moments.count, count)
    assert moments.weight[17] == 1.0 and moments.count[17] == 1


def _block_extents(points, order, size=64):
    ordered = points[order]
    return np.array(
        [np.ptp(ordered[i : i + size], axis=0).max() for i in range(0, len(points), size)]
    )


def test_spatial_order_stays_local_with_a_stray_point():
    from dentopo.mesh import spatial_order
    from dentopo.mesh._spatial import _morton_order

    rng = np.random.default_rng(5)
    points = rng.random((5000, 3))
    clean = _block_extents(points, spatial_order(points))
    points[123] = 1e6
    order = spatial_order(points)
    assert np.array_equal(np.sort(order), np.arange(len(points)))
    extents = _block_extents(points, order)
    stray_block = np.flatnonzero(order == 123)[0] // 64
    others = np.delete(extents, stray_block)
    # the uniform Morton order over the bounding box keeps the index order here
    uniform = np.delete(_block_extents(points, _morton_order(points)[0]), stray_block)
    assert np.median(uniform) > 0.5
    assert np.median(others) <= 2 * np.median(clean)


def test_spatial_order_is_plain_morton_without_crowded_cells():
    from dentopo.mesh import spatial_order
    from dentopo.mesh._spatial import _morton_order

    points = np.random.default_rng(6).random((20000, 3))
    assert np.array_equal(spatial_order(points), _morton_order(points)[0])
    same = np.zeros((300, 3))  # identical points: no endless refinement
    assert np.array_equal(np.sort(spatial_order(same)), np.arange(300))
