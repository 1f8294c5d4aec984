"""The exact kernel sums equal brute-force sums over every pair."""

from __future__ import annotations

import numpy as np
import pytest

from dentopo.ariadne._kernel import COUNTED_UP_TO, euclidean_moments, kernel_radius


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
    np.testing.assert_array_equal(moments.count, np.minimum(count, COUNTED_UP_TO))


def _inline_exponential(t):
    from numba import njit

    from dentopo.ariadne._exp import exp_neg

    @njit
    def each(t, out):
        for i in range(t.shape[0]):
            out[i] = exp_neg(t[i])

    out = np.empty_like(t)
    each(t, out)
    return out


def test_inline_exponential_is_within_two_ulps_of_libm():
    """The kernels' inline exp(-t) against libm's, over every t a weight can have."""
    t = np.concatenate([np.linspace(0.0, 37.3, 400_001), np.linspace(37.3, 708.0, 400_001)])
    t = np.concatenate([t, np.random.default_rng(0).uniform(0, 708, 200_000), [0.5 * np.log(2)]])
    ours, libm = _inline_exponential(t), np.exp(-t)
    assert np.max(np.abs(ours - libm) / np.spacing(libm)) <= 2
    assert _inline_exponential(np.array([0.0]))[0] == 1.0


def test_inline_exponential_beyond_its_range_is_tiny_and_never_nan():
    t = np.array([708.0, 709.0, 745.0, 1e300, np.inf, np.nan])
    ours = _inline_exponential(t)
    assert np.all(ours == np.exp(-708.0))  # 3.3e-308: the smallest it gives
    assert np.all(ours > 0) and np.all(np.isfinite(ours))


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
    np.testing.assert_array_equal(moments.count, np.minimum(count, COUNTED_UP_TO))
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


@pytest.mark.parametrize(("bandwidth", "cutoff"), [(0.05, 0.0), (0.3, 0.3)])
def test_few_neighbours_are_counted_exactly(bandwidth, cutoff):
    # points strewn thinly: counts from 1 to many; those up to COUNTED_UP_TO exact
    rng = np.random.default_rng(21)
    points = rng.random((400, 3)) * [6.0, 6.0, 0.5]
    moments = euclidean_moments(points, bandwidth, cutoff)
    *_, count = brute_force(points, bandwidth, cutoff)
    assert (count <= 3).sum() > 20 and (count > COUNTED_UP_TO).sum() > 20
    np.testing.assert_array_equal(moments.count, np.minimum(count, COUNTED_UP_TO))


def _moments_bits(moments):
    return [
        np.asarray(getattr(moments, name)).tobytes()
        for name in ("weight", "first", "second", "count")
    ]


@pytest.mark.parametrize("cutoff", [0.0, 0.3])
def test_paired_kernel_is_bit_identical_at_any_thread_count_and_call_size(cutoff, monkeypatch):
    import numba

    from dentopo.ariadne import _kernel

    rng = np.random.default_rng(11)
    points = rng.normal(size=(3000, 3)) * [0.5, 0.3, 0.1]
    assert len(points) <= _kernel.PAIRED_VERTICES
    before = numba.get_num_threads()
    runs = []
    try:
        for threads in (1, numba.config.NUMBA_NUM_THREADS, 1):
            numba.set_num_threads(threads)
            runs.append(_moments_bits(euclidean_moments(points, 0.08, cutoff)))
        # many short calls (as for Ctrl-C on a large mesh): the same sums
        monkeypatch.setattr(_kernel, "PAIRS_PER_CALL", 10_000)
        runs.append(_moments_bits(euclidean_moments(points, 0.08, cutoff)))
    finally:
        numba.set_num_threads(before)
    assert all(run == runs[0] for run in runs)


def test_paired_and_row_kernels_agree(monkeypatch):
    """The two exact kernels (pairs once, up to PAIRED_VERTICES; rows in full) agree to rounding."""
    from dentopo.ariadne import _kernel

    rng = np.random.default_rng(12)
    points = rng.normal(size=(1500, 3)) * [0.5, 0.3, 0.1]
    paired = euclidean_moments(points, 0.05, 0.0)
    monkeypatch.setattr(_kernel, "PAIRED_VERTICES", 100)
    rows = euclidean_moments(points, 0.05, 0.0)
    np.testing.assert_array_equal(paired.count, rows.count)
    np.testing.assert_allclose(paired.weight, rows.weight, rtol=1e-14)
    for name in ("first", "second"):
        a, b = getattr(paired, name), getattr(rows, name)
        np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-14 * np.abs(b).max())
    assert not np.array_equal(paired.second, rows.second)  # really two code paths


def test_paired_kernel_with_far_apart_clusters_equals_brute_force():
    # blocks out of each other's reach: the pairs kernel skips them, and each
    # task's columns end where its rows' reach ends
    rng = np.random.default_rng(13)
    points = np.concatenate(
        [rng.normal(size=(400, 3)) * 0.05 + shift for shift in ([0, 0, 0], [5, 0, 0], [0, 7, 0])]
    )
    rng.shuffle(points)
    moments = euclidean_moments(points, 0.05, 0.0)
    weight, first, second, count = brute_force(points, 0.05, 0.0)
    np.testing.assert_allclose(moments.weight, weight, rtol=1e-13)
    np.testing.assert_allclose(moments.first, first, rtol=1e-12, atol=1e-15 * np.abs(first).max())
    np.testing.assert_allclose(moments.second, second, rtol=1e-12, atol=1e-15 * second.max())
    np.testing.assert_array_equal(moments.count, np.minimum(count, COUNTED_UP_TO))


def test_kernel_sums_with_uneven_work_equal_brute_force():
    # a dense cluster and scattered far points: the tasks' rows are cut by their
    # work, some tasks get few rows or none
    rng = np.random.default_rng(14)
    points = np.concatenate([rng.normal(size=(900, 3)) * 0.01, rng.normal(size=(300, 3)) * 50])
    moments = euclidean_moments(points, 0.08, 0.0)
    weight, first, second, count = brute_force(points, 0.08, 0.0)
    np.testing.assert_allclose(moments.weight, weight, rtol=1e-13)
    np.testing.assert_allclose(moments.first, first, rtol=1e-12, atol=1e-15 * np.abs(first).max())
    np.testing.assert_allclose(moments.second, second, rtol=1e-12, atol=1e-15 * second.max())
    np.testing.assert_array_equal(moments.count, np.minimum(count, COUNTED_UP_TO))


def test_no_points_no_sums():
    moments = euclidean_moments(np.zeros((0, 3)), 0.08, 0.0)
    assert moments.weight.shape == (0,) and moments.second.shape == (0, 3, 3)
    assert moments.count.shape == (0,)
