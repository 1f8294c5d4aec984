"""Checks of the topography metrics' parameters, shared by the metrics and the batch settings.

Each returns the value as the metric uses it, or raises naming the parameter:
``TypeError`` for the wrong kind of value, ``ValueError`` for one out of range.
"""

from __future__ import annotations

from numbers import Integral, Real

import numpy as np


def check_int(name: str, value, *, low: int) -> int:
    """An integer (not a bool) of at least `low`."""
    if isinstance(value, bool) or not isinstance(value, Integral):
        raise TypeError(f"{name} must be an integer; got {type(value).__name__}")
    if value < low:
        raise ValueError(f"{name} must be at least {low}; got {value!r}")
    return int(value)


def check_finite(name: str, value) -> float:
    """A finite real number (not a bool), as a float."""
    if isinstance(value, bool) or not isinstance(value, Real):
        raise TypeError(f"{name} must be a real number; got {type(value).__name__}")
    value = float(value)
    if not np.isfinite(value):
        raise ValueError(f"{name} must be finite; got {value!r}")
    return value


def check_alpha(alpha) -> float:
    """RFI's alpha: a positive finite real number, as a float."""
    if isinstance(alpha, bool) or not isinstance(alpha, Real):
        raise TypeError(f"alpha must be a real number; got {type(alpha).__name__}")
    value = float(alpha)
    if not (np.isfinite(value) and value > 0):
        raise ValueError(f"alpha must be a positive finite number; got {alpha!r}")
    return value


def check_find_alpha(find_alpha) -> bool:
    """RFI's find_alpha: True or False (numpy's bools too)."""
    if not isinstance(find_alpha, (bool, np.bool_)):
        raise TypeError(f"find_alpha must be True or False; got {type(find_alpha).__name__}")
    return bool(find_alpha)
