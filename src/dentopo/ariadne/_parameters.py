"""The numeric parameters of ariaDNE and the ranges where the computation is defined.

The kernel is ``exp(-d**2 / h**2)`` on the unit-area scale: the mesh is
translated to its mean and scaled to area 1, so its coordinates and distances
are of order 1 (0.5 to 2 across for a tooth crown).  The computation needs,
as finite, non-zero float64 numbers: ``1 / h**2`` (the exact sums; at
``h = 1e-155`` it overflowed to inf, ``0 * inf`` gave NaN and the NaN indexed
the exponential's table out of bounds: a segmentation fault), ``h**2`` and
``h**4`` (the fast transform's derivative factors), the kernel's radius
squared (up to ``(27.3 h)**2`` with the smallest cutoff) and the Fourier mode
counts, which grow as ``(extent / h)**3`` and are compared with their cap
before any array is made.  ``h**4`` bounds the range first, at about
``1e77``; ``BANDWIDTH_RANGE``, ``[1e-50, 1e50]``, keeps 27 orders of magnitude
of margin on both sides, and spans every bandwidth that can mean anything
on a unit-area surface: at ``1e-50`` no two distinct vertices of any stored
mesh see each other (every curvature is 0, with a warning), and at ``1e50``
every weight is exactly 1.  Within the range the work is bounded by the
number of vertices whatever ``h`` is (the exact sums visit at most every
pair, the fast transform refuses grids above ``MAX_MODES``, and the sign's
refinement has a work budget).

``cutoff`` is a weight threshold in ``[0, 1)``: 0 keeps every weight, and a
cutoff of 1 or more would drop them all, a vertex's own included.  Every value
in the range is safe: the radius ``h * sqrt(-log(cutoff))`` is at most
``27.3 h`` even for the smallest subnormal cutoff.
"""

from __future__ import annotations

from numbers import Real

import numpy as np

#: Closed range of accepted bandwidths (unit-area scale); see the module docstring.
BANDWIDTH_RANGE = (1e-50, 1e50)


def check_number(name, value, *, low, high, low_open, high_open):
    """`value` as a float if it is a real number in the interval, else TypeError/ValueError.

    The message names the parameter and the interval: ``"NAME must lie in [LOW, HIGH);
    got VALUE"``.
    """
    if isinstance(value, bool) or not isinstance(value, Real):
        raise TypeError(f"{name} must be a real number; got {type(value).__name__}")
    value = float(value)
    ok = bool(np.isfinite(value))
    ok = ok and (value > low if low_open else value >= low)
    ok = ok and (value < high if high_open else value <= high)
    if not ok:
        lb = "(" if low_open else "["
        hb = ")" if high_open else "]"
        raise ValueError(f"{name} must lie in {lb}{low:g}, {high:g}{hb}; got {value!r}")
    return value


def check_bandwidth(bandwidth) -> float:
    """The bandwidth as a float, or ValueError/TypeError naming its range ``BANDWIDTH_RANGE``."""
    low, high = BANDWIDTH_RANGE
    return check_number("bandwidth", bandwidth, low=low, high=high, low_open=False, high_open=False)


def check_cutoff(cutoff) -> float:
    """The cutoff as a float, or ValueError/TypeError naming its range ``[0, 1)``."""
    return check_number("cutoff", cutoff, low=0, high=1, low_open=False, high_open=True)
