"""The adaptive Morton order (dentopo.mesh.spatial_order): its codes and its permutation."""

from __future__ import annotations

import numpy as np
import pytest

from dentopo.mesh import _spatial, spatial_order


def _codes_bit_by_bit(points):
    """The Morton codes as defined: bit ``b`` of axis ``a`` at bit ``3 b + a``."""
    lo = points.min(axis=0)
    span = float(np.max(points.max(axis=0) - lo)) or 1.0
    q = ((points - lo) / span * _spatial._CELLS).astype(np.uint64)
    code = np.zeros(len(points), dtype=np.uint64)
    for bit in range(_spatial._BITS):
        for axis in range(3):
            code |= ((q[:, axis] >> np.uint64(bit)) & np.uint64(1)) << np.uint64(3 * bit + axis)
    return code


@pytest.mark.parametrize("n", [1, 7, 1000])
@pytest.mark.parametrize("scale", [1e-3, 1.0, 1e6])
def test_the_codes_interleave_the_bits_of_the_cells(n, scale):
    points = np.random.default_rng(n).normal(size=(n, 3)) * scale * [1.0, 0.1, 3.0]
    expected = _codes_bit_by_bit(points)
    order, codes = _spatial._morton_order(points)
    np.testing.assert_array_equal(codes, expected[order])
    np.testing.assert_array_equal(order, np.argsort(expected, kind="stable"))


def test_the_order_is_a_permutation_that_keeps_a_stray_point_from_spoiling_it():
    rng = np.random.default_rng(3)
    points = np.vstack([rng.random((500, 3)), [[1e9, 1e9, 1e9]]])
    order = spatial_order(points)
    assert sorted(order.tolist()) == list(range(len(points)))
    # the 500 points in one coarse cell are ordered again: neighbours in the order are near
    steps = np.linalg.norm(np.diff(points[order[order < 500]], axis=0), axis=1)
    unordered = np.linalg.norm(np.diff(points[:500], axis=0), axis=1)
    assert np.median(steps) < np.median(unordered) / 3
