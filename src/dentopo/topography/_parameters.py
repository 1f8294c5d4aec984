"""Checks of the topography metrics' parameters, shared by the metrics and the batch settings.

Each returns the value as the metric uses it, or raises naming the parameter:
``TypeError`` for the wrong kind of value, ``ValueError`` for one out of range.
"""

from __future__ import annotations

from numbers import Integral, Real

import numpy as np


def check_int(name: str, value, *, low: int, high: int | None = None) -> int:
    """An integer (not a bool) of at least `low` (and at most `high`, when given)."""
    if isinstance(value, bool) or not isinstance(value, Integral):
        raise TypeError(f"{name} must be an integer; got {type(value).__name__}")
    if value < low:
        raise ValueError(f"{name} must be at least {low}; got {value!r}")
    if high is not None and value > high:
        raise ValueError(f"{name} must be at most {high}; got {value!r}")
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


#: Classic DNE's outlier percentage: the highest energies discarded are outliers, a minority
#: of the faces, so at most half (the cut at or above the median; at 100 no face was left and
#: DNE was 0.0).  A mesh whose faces the cut leaves no energy to measure is an error of the
#: metric, whatever the percentage (see :func:`dentopo.topography.classic_dne`).
OUTLIERS_RANGE = (0.0, 50.0)


def check_outliers(name: str, value) -> float:
    """Classic DNE's outlier percentage, in :data:`OUTLIERS_RANGE`, as a float."""
    if isinstance(value, bool) or not isinstance(value, Real):
        raise TypeError(f"{name} must be a real number; got {type(value).__name__}")
    value = float(value)
    low, high = OUTLIERS_RANGE
    if not (np.isfinite(value) and low <= value <= high):
        raise ValueError(
            f"{name} is a percentage and must lie in [{low:g}, {high:g}] (outliers are at most "
            f"half the faces); got {value!r}"
        )
    return value


#: OPCR's rotations: at most one a degree, all distinct and within one turn (``steps * step``
#: at most 360 degrees; molaR's 8 of 5.625 make 45, one OPC direction bin).  A step of 0
#: gave eight identical rotations (and eight columns of one name); a million steps, a table
#: of a million columns built before any file was read.
MAX_OPCR_STEPS = 360


def check_opcr_options(steps, step, names=("opcr_steps", "opcr_step")) -> tuple[int, float]:
    """OPCR's rotation count (1 to 360) and step (degrees, > 0, ``steps * step <= 360``)."""
    if isinstance(steps, bool) or not isinstance(steps, Integral):
        raise TypeError(f"{names[0]} must be an integer; got {type(steps).__name__}")
    if not 1 <= steps <= MAX_OPCR_STEPS:
        raise ValueError(f"{names[0]} must lie in [1, {MAX_OPCR_STEPS}]; got {steps!r}")
    steps = int(steps)
    if isinstance(step, bool) or not isinstance(step, Real):
        raise TypeError(f"{names[1]} must be a real number; got {type(step).__name__}")
    step = float(step)
    if not (np.isfinite(step) and 0.0 < step <= 360.0 / steps):
        raise ValueError(
            f"{names[1]} must lie in (0, 360 / {names[0]}] degrees, here (0, {360.0 / steps:g}] "
            f"(the rotations distinct, within one turn); got {step!r}"
        )
    return steps, step


def check_classic_options(outliers, boundary, kappa) -> tuple[float, str, float]:
    """Classic DNE's outlier percentage (in [0, 50]), boundary rule and kappa (finite)."""
    outliers = check_outliers("dne_outliers", outliers)
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


#: MorphoTester's outlier types: by energy density (its published results) or energy x area
#: (its GUI's default); None: no outlier removal.
MORPHOTESTER_OUTLIERS = ("energy", "energy_area")


def check_morphotester_dne_options(
    condition_check, outliers, percentile, smooth
) -> tuple[bool, str | None, float, bool]:
    """MorphoTester's DNE options as it uses them, or a ValueError naming the first wrong one.

    `condition_check`, `smooth`: True or False; `outliers`: ``"energy"``,
    ``"energy_area"`` or None (``"off"`` and ``"energy-area"`` are read too, as the
    command line writes them); `percentile`: in (0, 100].
    """
    for name, flag in (("condition_check", condition_check), ("smooth", smooth)):
        if not isinstance(flag, (bool, np.bool_)):
            raise ValueError(f"{name} must be True or False; got {flag!r}")
    if isinstance(outliers, str):
        outliers = {"off": None, "energy-area": "energy_area"}.get(outliers, outliers)
    if outliers is not None and outliers not in MORPHOTESTER_OUTLIERS:
        raise ValueError(
            f"outliers must be one of {', '.join(MORPHOTESTER_OUTLIERS)} or off; got {outliers!r}"
        )
    if isinstance(percentile, (bool, np.bool_)) or not isinstance(percentile, Real):
        raise ValueError(f"percentile must be a number in (0, 100]; got {percentile!r}")
    if not (np.isfinite(float(percentile)) and 0.0 < float(percentile) <= 100.0):
        raise ValueError(f"percentile must be a number in (0, 100]; got {percentile!r}")
    return bool(condition_check), outliers, float(percentile), bool(smooth)


def check_min_patch(value) -> int:
    """MorphoTester's OPCR minimum patch: a whole number of faces, 0 or more (not a bool)."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, Integral) or value < 0:
        raise ValueError(f"min_patch must be a whole number of faces, 0 or more; got {value!r}")
    return int(value)


def check_morphotester_options(
    condition_check, outliers, percentile, smooth, min_patch
) -> tuple[bool, str | None, float, bool, int]:
    """MorphoTester's options (:func:`check_morphotester_dne_options`, :func:`check_min_patch`)."""
    dne = check_morphotester_dne_options(condition_check, outliers, percentile, smooth)
    return (*dne, check_min_patch(min_patch))


#: How PCV decides that a vertex is lit from a direction.
PCV_METHODS = ("cloudcompare", "exact")


def check_pcv_options(rays, hemisphere, method) -> tuple[int, bool, str]:
    """PCV's options as it uses them, or an error naming the first wrong one.

    `rays`: an integer of at least 1 (the light directions asked for); `hemisphere`:
    True or False; `method`: one of :data:`PCV_METHODS`.
    """
    rays = check_int("rays", rays, low=1)
    if not isinstance(hemisphere, (bool, np.bool_)):
        raise ValueError(f"hemisphere must be True or False; got {hemisphere!r}")
    return rays, bool(hemisphere), check_choice("method", method, PCV_METHODS)
