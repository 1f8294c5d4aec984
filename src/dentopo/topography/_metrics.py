"""The metrics a run can compute, by name, and the record keys each of them fills.

``ariadne`` is ariaDNE with its sign-oriented split (:mod:`dentopo.ariadne`);
the others are molaR 6.0's, doolkit 1.42's and MorphoTester 1.1.1's
dental-topography metrics in this subpackage.  The names are what
``--metrics`` accepts and what a table's columns are grouped by; their order
is the order of the columns (ariaDNE first, then molaR's batch order: classic
DNE, RFI, OPCR, OPC, slope, then ARC, then doolkit's metrics in the order of
doolkit's own table, then MorphoTester's in the order of its own, then those
no earlier tool computes: ``rfi_projected``, the relief index on the exact
projected footprint, and ``pcv``, ambient occlusion).

molaR's and doolkit's own function names are accepted as aliases, in any
case (``DNE``, ``RFI``, ``OPCr``, ``Slope``, ``ARC``; ``inclin``, ``rrate``,
``shape.index``, ``hypso``, ``area2d``).  Where molaR and doolkit use one
name for two different computations (``slope``, ``opc``, ``opcr``, ``arc``,
``dne``, ``rfi``), the name is molaR's and doolkit's is ``doolkit_slope``,
``doolkit_opc`` ... (doolkit's ``rfi`` is ``relief_index``); MorphoTester's
DNE, RFI and OPCR are ``morphotester_dne``, ``morphotester_rfi`` and
``morphotester_opcr``.  ``molar``, ``doolkit`` and ``morphotester`` name each
tool's whole set, ``all`` every metric.
"""

from __future__ import annotations

from collections.abc import Iterable

#: molaR 6.0's metrics (besides ariaDNE, which is ours), in molaR_Batch's order, ARC last.
MOLAR_METRICS = ("classic", "rfi", "opcr", "opc", "slope", "arc")

#: doolkit 1.42's metrics, in the order of doolkit's table's columns.
DOOLKIT_METRICS = (
    "doolkit_slope",
    "angularity",
    "relief_index",
    "inclination",
    "doolkit_opc",
    "doolkit_opcr",
    "doolkit_arc",
    "doolkit_dne",
    "relief_rate",
    "shape_index",
    "footprint",
    "hypsodonty",
)

#: MorphoTester 1.1.1's metrics, in the order of its table's columns (DNE, RFI, OPCR).
MORPHOTESTER_METRICS = ("morphotester_dne", "morphotester_rfi", "morphotester_opcr")

#: Metrics no earlier tool computes: the relief index on the exact projected footprint, and
#: PCV (ambient occlusion) as CloudCompare's qPCV computes it by hand, crown by crown.
OWN_METRICS = ("rfi_projected", "pcv")

#: Every metric, in the order of a table's columns.
METRICS = ("ariadne", *MOLAR_METRICS, *DOOLKIT_METRICS, *MORPHOTESTER_METRICS, *OWN_METRICS)

#: What ``metrics="all"`` computes.
ALL = "all"

#: Names of sets of metrics: each tool's whole set, and everything.
GROUPS = {
    ALL: METRICS,
    "molar": MOLAR_METRICS,
    "doolkit": DOOLKIT_METRICS,
    "morphotester": MORPHOTESTER_METRICS,
}

#: molaR's and doolkit's function names (lower case) for ours.
ALIASES = {
    "dne": "classic",
    "classic_dne": "classic",
    "opcr": "opcr",
    "inclin": "inclination",
    "rrate": "relief_rate",
    "shape.index": "shape_index",
    "hypso": "hypsodonty",
    "area2d": "footprint",
    "doolkit_rfi": "relief_index",
}

#: Metrics that assume the crown points to +z (see :mod:`._orientation`).
ORIENTED = frozenset(
    {
        "rfi",
        "opcr",
        "opc",
        "slope",
        "inclination",
        "doolkit_opc",
        "doolkit_opcr",
        "relief_index",
        "relief_rate",
        "rfi_projected",
        "pcv",
    }
)

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

#: doolkit's OPC (bins numbered from 0 degrees) and OPCR totals: keys prefixed, beside molaR's.
DOOLKIT_BIN_KEYS = tuple(f"dk_opc_bin{k}" for k in range(1, 9))
DOOLKIT_ROTATION_KEYS = tuple(f"dk_opcr_rot{k}" for k in range(8))

#: Keys every row with a doolkit metric holds first (doolkit's table starts with them).
DOOLKIT_BASE_KEYS = ("n_vertices", "n_faces", "area3d")

#: The key every row with a MorphoTester metric holds first: the faces of the mesh as
#: MorphoTester reads it (its "Mesh Face Number"; nothing cleaned).
MORPHOTESTER_BASE_KEYS = ("mt_n_faces",)

#: MorphoTester's OPC at each of its eight rotations (0, 5.625, ..., 39.375 degrees).
MORPHOTESTER_ROTATION_KEYS = tuple(f"mt_opc_rot{k}" for k in range(8))


def rotation_key(degrees: float) -> str:
    """The record key of the OPC at one OPCR rotation: ``opc_0``, ``opc_5.625``, ..."""
    return f"opc_{format(float(degrees), '.7g')}"


def rotations(steps: int, step: float) -> tuple[float, ...]:
    """The OPCR rotations in degrees: ``0, step, ..., (steps - 1) * step`` (never -0.0)."""
    return tuple(k * step + 0.0 for k in range(steps))


def metric_names() -> str:
    """The accepted names, for messages: every metric, then the sets."""
    return f"{', '.join(METRICS)}, or {', '.join(GROUPS)}"


def check_metrics(metrics: str | Iterable[str]) -> tuple[str, ...]:
    """Validated metric names in table order.

    Accepts ``"all"``, ``"molar"``, ``"doolkit"``, a name, an alias of molaR
    or doolkit (:data:`ALIASES`), in any case, a comma list or names.

    Raises
    ------
    TypeError, ValueError
        Naming an unknown metric, or when none is given.
    """
    if isinstance(metrics, str):
        metrics = metrics.split(",")
    try:
        names = [str.lower(name.strip()) for name in metrics]
    except (TypeError, AttributeError):  # not iterable, or an item that is not a string
        raise TypeError(
            f"metrics must be names or a comma-separated string; got {metrics!r}"
        ) from None
    names = [name for name in names if name]
    if not names:
        raise ValueError(f"no metric given: use some of {metric_names()}")
    chosen: set[str] = set()
    for name in names:
        if name in GROUPS:
            chosen.update(GROUPS[name])
            continue
        metric = ALIASES.get(name, name)
        if metric not in METRICS:
            raise ValueError(f"unknown metric {name!r}: use some of {metric_names()}")
        chosen.add(metric)
    return tuple(name for name in METRICS if name in chosen)
