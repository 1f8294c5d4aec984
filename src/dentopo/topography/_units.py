"""doolkit's unit: what its definitions assume (millimetres) and when that matters.

Six of doolkit 1.42.2's metrics depend on the unit of the coordinates, not
only on the crown's shape:

- ``footprint`` (``area2d``) and ``relief_index`` (Ungar's and Boyer's, which
  divide by it) draw the concave footprint on coordinates rounded to 4
  decimals (0.1 micrometre in millimetres);
- ``shape_index`` and ``hypsodonty`` round lengths to 2 decimals (10
  micrometres in millimetres);
- ``doolkit_arc``: the VCG library's curvature is 0 at a vertex whose area is
  at most float32's epsilon (1.2e-7 square units: a tiny area in
  millimetres, every vertex's area in metres);
- ``angularity`` puts each vertex's slope in degrees as its z beside x and y
  in the mesh's unit: any change of unit changes it.

doolkit assumes millimetres.  A batch given the mesh's unit
(:class:`dentopo.batch.TopographyOptions` ``unit``) measures these metrics on
the crown rescaled to millimetres, giving doolkit's numbers for the same crown
in millimetres (its lengths and areas back in the mesh's unit).  Without it,
the coordinates are taken as millimetres, and each metric warns
(:class:`UnitWarning`) where its rounding or threshold moves its value by
more than :data:`MATERIAL` on this crown, or raises where it makes the value
meaningless.
"""

from __future__ import annotations

import math
import warnings
from numbers import Real

#: The metrics whose value depends on the unit of the coordinates (doolkit's definitions).
UNIT_DEPENDENT = (
    "angularity",
    "relief_index",
    "doolkit_arc",
    "shape_index",
    "footprint",
    "hypsodonty",
)

#: Millimetres in one unit, by the unit's name.
UNITS = {"um": 1e-3, "µm": 1e-3, "micron": 1e-3, "mm": 1.0, "cm": 10.0, "m": 1e3, "in": 25.4}

#: A rounding (or threshold) that can move a value by more than this fraction is warned about.
MATERIAL = 0.005

#: How a warning tells what to do (the library's words; the command shows ``--unit``).
FIX = "doolkit assumes millimetres (give the mesh's unit: unit='m', unit='um', ...)"


class UnitWarning(UserWarning):
    """A doolkit metric's unit-dependent definition moves its value on this crown."""


def millimetres_per_unit(unit) -> float | None:
    """The length of one mesh unit in millimetres, or None for ``unit=None`` (not said).

    `unit` is a name of :data:`UNITS` (``"um"``, ``"mm"``, ``"cm"``, ``"m"``,
    ``"in"``, any case) or a positive finite number of millimetres.

    Raises
    ------
    TypeError, ValueError
        Naming the accepted units.
    """
    if unit is None:
        return None
    if isinstance(unit, str):
        factor = UNITS.get(unit.strip().lower())
        if factor is None:
            try:
                factor = float(unit)
            except ValueError:
                raise ValueError(
                    f"unit must be one of {', '.join(UNITS)} or millimetres per unit; got {unit!r}"
                ) from None
        unit = factor
    if isinstance(unit, bool) or not isinstance(unit, Real):
        raise TypeError(f"unit must be a unit's name or a number; got {type(unit).__name__}")
    value = float(unit)
    if not (math.isfinite(value) and value > 0):
        raise ValueError(f"unit must be a positive finite number of millimetres; got {unit!r}")
    return value


def warn(metric: str, text: str, stacklevel: int = 3) -> None:
    """A :class:`UnitWarning` ``"metric: text; doolkit assumes millimetres: ..."``."""
    warnings.warn(f"{metric}: {text}; {FIX}", UnitWarning, stacklevel=stacklevel)


def rounding_change(exact: float, rounded: float) -> float:
    """The relative change rounding made (0 for an exact 0; 1 when it rounded to 0)."""
    if exact == 0.0:
        return 0.0 if rounded == 0.0 else math.inf
    return abs(rounded - exact) / abs(exact)
