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


#: The boundary rules of classic DNE and ARC (molaR's ``BoundaryDiscard``).
BOUNDARY_RULES = ("vertex", "leg", "none")


def check_choice(name: str, value, choices: tuple[str, ...]) -> str:
    """`value` lower-cased if it is one of `choices` (any case)."""
    if not isinstance(value, str) or value.lower() not in choices:
        raise ValueError(f"{name} must be one of {choices} (any case); got {value!r}")
    return value.lower()


def check_min_area(value) -> float:
    """OPC's ``min_area``: a fraction of the total surface area, in [0, 1)."""
    value = check_finite("min_area", value)
    if not 0.0 <= value < 1.0:
        raise ValueError(
            "min_area is a fraction of the total surface area and must lie in [0, 1); "
            f"got {value!r}"
        )
    return value


def check_classic_options(outliers, boundary, kappa) -> tuple[float, str, float]:
    """Classic DNE's outlier percentage (in [0, 100]), boundary rule and kappa (finite)."""
    outliers = check_finite("dne_outliers", outliers)
    if not 0.0 <= outliers <= 100.0:
        raise ValueError(f"dne_outliers is a percentage and must lie in [0, 100]; got {outliers!r}")
    return (
        outliers,
        check_choice("dne_boundary", boundary, BOUNDARY_RULES),
        check_finite("dne_kappa", kappa),
    )


def check_arc_options(boundary, quantiles) -> tuple[str, tuple[float, float]]:
    """ARC's boundary rule and its two quantiles ``(low, high)``, ``0 <= low < high <= 1``."""
    boundary = check_choice("arc_boundary", boundary, BOUNDARY_RULES)
    try:
        low, high = quantiles
    except (TypeError, ValueError):
        raise TypeError(f"arc_range must be two numbers (low, high); got {quantiles!r}") from None
    low, high = check_finite("arc_range", low), check_finite("arc_range", high)
    if not 0.0 <= low < high <= 1.0:
        raise ValueError(
            f"arc_range must be two quantiles with 0 <= low < high <= 1; got ({low!r}, {high!r})"
        )
    return boundary, (low, high)
