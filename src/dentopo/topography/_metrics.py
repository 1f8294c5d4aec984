"""The metrics a run can compute, by name, and the record keys each of them fills.

``ariadne`` is ariaDNE with its sign-oriented split (:mod:`dentopo.ariadne`);
the others are molaR 6.0's dental-topography metrics in this subpackage.  The
names are what ``--metrics`` accepts and what a table's columns are grouped
by; their order is the order of the columns (ariaDNE first, then molaR's
batch order: classic DNE, RFI, OPCR, OPC, slope).
"""

from __future__ import annotations

from collections.abc import Iterable

#: Every metric, in the order of a table's columns.
METRICS = ("ariadne", "classic", "rfi", "opcr", "opc", "slope")

#: What ``metrics="all"`` computes.
ALL = "all"

#: Metrics that assume the crown points to +z (see :mod:`._orientation`).
ORIENTED = frozenset({"rfi", "opcr", "opc", "slope"})

#: Record keys of classic DNE in a batch table (its own names prefixed, beside ariaDNE's).
CLASSIC_KEYS = {
    "dne": "classic_dne",
    "convex_dne": "classic_convex_dne",
    "concave_dne": "classic_concave_dne",
    "convex_area": "classic_convex_area",
    "concave_area": "classic_concave_area",
}

#: The eight OPC bin counts' keys.
BIN_KEYS = tuple(f"opc_bin{k}" for k in range(1, 9))


def rotation_key(degrees: float) -> str:
    """The record key of the OPC at one OPCR rotation: ``opc_0``, ``opc_5.625``, ..."""
    return f"opc_{format(float(degrees), '.7g')}"


def rotations(steps: int, step: float) -> tuple[float, ...]:
    """The OPCR rotations in degrees: ``0, step, ..., (steps - 1) * step`` (never -0.0)."""
    return tuple(k * step + 0.0 for k in range(steps))


def check_metrics(metrics: str | Iterable[str]) -> tuple[str, ...]:
    """Validated metric names in table order (``"all"``, a name, a comma list or names).

    Raises
    ------
    TypeError, ValueError
        Naming an unknown metric, or when none is given.
    """
    if isinstance(metrics, str):
        metrics = metrics.split(",")
    try:
        names = [str.lower(name.strip()) for name in metrics]
    except TypeError:
        raise TypeError(
            f"metrics must be names or a comma-separated string; got {metrics!r}"
        ) from None
    names = [name for name in names if name]
    if ALL in names:
        return METRICS
    unknown = [name for name in names if name not in METRICS]
    if unknown:
        raise ValueError(
            f"unknown metric {unknown[0]!r}: use some of {', '.join(METRICS)}, or {ALL}"
        )
    if not names:
        raise ValueError(f"no metric given: use some of {', '.join(METRICS)}, or {ALL}")
    return tuple(name for name in METRICS if name in names)
