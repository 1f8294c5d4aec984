"""Spatial ordering of points, so that nearby points are near each other in memory."""

from __future__ import annotations

import numpy as np


def spatial_order(points: np.ndarray) -> np.ndarray:
    """A permutation that puts nearby points next to each other (Morton order)."""
    lo = points.min(axis=0)
    span = float(np.max(points.max(axis=0) - lo)) or 1.0
    q = ((points - lo) / span * 1023).astype(np.uint64)
    code = np.zeros(len(points), dtype=np.uint64)
    for bit in range(10):
        for axis in range(3):
            code |= ((q[:, axis] >> np.uint64(bit)) & np.uint64(1)) << np.uint64(3 * bit + axis)
    return np.argsort(code, kind="stable")
