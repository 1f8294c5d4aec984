"""The compiled sorts that stand in for numba's np.sort and np.argsort (quick to compile).

They must give exactly numpy's answers: the same sorted integers, and the same
stable order (equal keys in their original order), whatever the length.
"""

from __future__ import annotations

import numpy as np
import pytest

from dentopo.mesh._topology import sort_ints, stable_order

LENGTHS = [0, 1, 2, 15, 16, 17, 31, 32, 33, 100, 1000, 4097]


@pytest.mark.parametrize("n", LENGTHS)
@pytest.mark.parametrize("dtype", [np.int32, np.int64])
def test_sort_ints_is_numpys_sort(n, dtype):
    rng = np.random.default_rng(n)
    for high in (3, n + 1, 2**31 - 1):  # many ties, some, almost none
        values = rng.integers(-high, high, size=n).astype(dtype)
        expected = np.sort(values)
        sort_ints(values)
        assert np.array_equal(values, expected)


@pytest.mark.parametrize("n", LENGTHS)
def test_stable_order_is_numpys_stable_argsort(n):
    rng = np.random.default_rng(1000 + n)
    for high in (2, 7, n + 1, 2**62):
        key = rng.integers(0, high, size=n, dtype=np.int64)
        before = key.copy()
        order = np.full(n, -1, dtype=np.int64)
        stable_order(key, order)
        assert np.array_equal(order, np.argsort(key, kind="stable"))
        assert np.array_equal(key, before)  # the keys are not touched


def test_already_sorted_and_reversed_inputs():
    for values in (np.arange(1000, dtype=np.int64), np.arange(1000, dtype=np.int64)[::-1].copy()):
        expected = np.sort(values)
        sort_ints(values)
        assert np.array_equal(values, expected)
