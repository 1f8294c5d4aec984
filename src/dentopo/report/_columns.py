"""The table's columns as the page shows them: metrics by family, each with its unit.

Which columns are metrics, and of which family, comes from the package's own
lists, so that a metric added there is grouped here without a second list:
the record keys of each metric (:data:`dentopo.formats.METRIC_KEYS`), the
tools' sets of metrics (:data:`dentopo.topography.GROUPS`: molaR's, doolkit's,
MorphoTester's), the metrics of no earlier tool (``OWN_METRICS``: each a family
of its own), the OPC bins and rotations, and the settings columns
(:data:`dentopo.formats.SETTING_KEYS` and ariaDNE's).  The families in order:
ariaDNE, molaR, doolkit, MorphoTester, the projected footprint's RFI, PCV; then
``other``, any column the package does not know (a future metric's, or one
added by hand: shown and, when it holds numbers, charted, never dropped), and
``mesh``, the vertex and face counts (shown, not charted).

Settings (bandwidth, ``pcv_rays`` ...) and the row's own columns (file,
orientation, protocol, seconds, status, error, warnings) are not metrics.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass

from ..formats import METRIC_KEYS, SETTING_KEYS, record_keys
from ..topography import (
    ALL,
    BIN_KEYS,
    DOOLKIT_BASE_KEYS,
    DOOLKIT_BIN_KEYS,
    DOOLKIT_METRICS,
    DOOLKIT_ROTATION_KEYS,
    GROUPS,
    METRICS,
    MORPHOTESTER_BASE_KEYS,
    MORPHOTESTER_METRICS,
    MORPHOTESTER_ROTATION_KEYS,
    ORIENTED,
)

#: ariaDNE's settings columns and their defaults (for a table that does not hold them).
ARIADNE_SETTINGS = {
    "bandwidth": 0.08,
    "cutoff": 0.0,
    "distance_type": "euclidean",
    "sign_method": "centroid",
    "method": "auto",
}

#: The column saying which way each crown pointed and what was done about it.
ORIENTATION = "orientation"

#: Settings columns: ariaDNE's, the topography metrics', and the ``orient`` rule.
SETTINGS = tuple(
    dict.fromkeys(
        (*ARIADNE_SETTINGS, *(k for keys in SETTING_KEYS.values() for k in keys), "orient")
    )
)

#: Vertex and face counts of the mesh each tool read: shown in the table, not charted.
COUNTS = ("vertices", "faces", "n_vertices", "n_faces", *MORPHOTESTER_BASE_KEYS)

#: Family ids of the columns the package does not know, and of the mesh counts.
OTHER, MESH = "other", "mesh"

#: How the page names each family (a family missing here is named by its id).
FAMILY_LABELS = {
    "ariadne": "ariaDNE (signDNE)",
    "molar": "molaR 6.0",
    "doolkit": "doolkit 1.42",
    "morphotester": "MorphoTester 1.1.1",
    "rfi_projected": "projected footprint (RFI)",
    "pcv": "PCV (ambient occlusion)",
    OTHER: "other columns",
    MESH: "mesh (vertex and face counts)",
}

#: Labels of the columns shown with a name other than their key.
LABELS = {
    "dne": "ariaDNE",
    "positive_dne": "ariaDNE +",
    "negative_dne": "ariaDNE \u2212",
    "classic_dne": "classic DNE",
    "classic_convex_dne": "classic DNE convex",
    "classic_concave_dne": "classic DNE concave",
    "rfi": "RFI",
    "rfi_projected": "RFI, projected footprint",
    "opcr": "OPCR",
    "opc": "OPC",
    "slope": "slope",
    "arc": "ARC",
    "pcv": "PCV",
}

#: Short names for the scatter matrix's axes, where ten of them share the width.
SHORT_LABELS = {
    "dne": "aDNE",
    "positive_dne": "aDNE+",
    "negative_dne": "aDNE\u2212",
    "classic_dne": "cDNE",
    "classic_convex_dne": "cDNE+",
    "classic_concave_dne": "cDNE\u2212",
    "rfi": "RFI",
    "rfi_projected": "RFIp",
    "opcr": "OPCR",
    "opc": "OPC",
    "arc": "ARC",
    "pcv": "PCV",
    "slope_mean": "dkSlope",
    "angularity_mean": "dkAngul",
    "rfi_ungar": "dkRFIu",
    "rfi_boyer": "dkRFIb",
    "rfi_guy": "dkRFIg",
    "inclin_mean": "dkIncl",
    "dk_opc": "dkOPC",
    "dk_opcr": "dkOPCR",
    "arc_mean": "dkARC",
    "dne_total": "dkDNE",
    "rrate_below_median": "dkRrate",
    "shape_formfactor": "dkShapeF",
    "area2d": "dkArea2d",
    "hypso_hypsodonty": "dkHypso",
    "mt_dne": "mtDNE",
    "mt_rfi": "mtRFI",
    "mt_opcr": "mtOPCR",
}

#: The columns' units: ``"°"`` for angles, ``"unit"`` and ``"unit²"`` for lengths and areas in
#: the meshes' own unit, ``"patches"`` for OPC's counts, ``""`` for a ratio, an energy, a mean
#: curvature, a fraction.  Every metric column of :data:`dentopo.formats.METRIC_KEYS` is here
#: (the tests hold it so); a column missing here is shown without a unit.
UNITS = {
    **dict.fromkeys(
        (
            "opcr",
            "opc",
            *BIN_KEYS,
            "dk_opc",
            "dk_opcr",
            *DOOLKIT_BIN_KEYS,
            *DOOLKIT_ROTATION_KEYS,
            "mt_opcr",
            *MORPHOTESTER_ROTATION_KEYS,
        ),
        "patches",
    ),
    **dict.fromkeys(("slope", "slope_mean", "angularity_mean", "inclin_mean"), "\u00b0"),
    **dict.fromkeys(
        (
            "surface_area",
            "positive_surface_area",
            "negative_surface_area",
            "classic_convex_area",
            "classic_concave_area",
            "area_3d",
            "area_2d",
            "area3d",
            "area2d",
            "area2d_convex",
            "mt_surface_area",
            "mt_outline_area",
            "projected_area_3d",
            "projected_area_2d",
        ),
        "unit\u00b2",
    ),
    **dict.fromkeys(("hypso_height", "hypso_length", "hypso_width"), "unit"),
    "alpha": "molaR's scaled units",
    **dict.fromkeys(
        (
            "dne",
            "positive_dne",
            "negative_dne",
            "classic_dne",
            "classic_convex_dne",
            "classic_concave_dne",
            "rfi",
            "arc",
            "arc_positive",
            "arc_negative",
            "rfi_ungar",
            "rfi_boyer",
            "rfi_guy",
            "arc_mean",
            "arc_pos_mean",
            "arc_neg_mean",
            "dne_total",
            "dne_total_unrounded",
            "rrate_below_median",
            "shape_formfactor",
            "shape_elongation",
            "shape_k",
            "hypso_hypsodonty",
            "mt_dne",
            "mt_rfi",
            "rfi_projected",
            "rfi_projected_ungar",
            "pcv",
            "pcv_area",
        ),
        "",
    ),
}

#: ariaDNE's sign split: key columns beside each metric's first (the pictures show the sign).
SIGNED = ("positive_dne", "negative_dne")

#: At most this many metrics are ticked for the scatter matrix at first.
SPLOM_TICKED = 10

_ROTATION = re.compile(r"opc_-?[0-9.]+(?:e[-+]?[0-9]+)?$")


def is_rotation(key: str) -> bool:
    """Whether `key` is the OPC of one of OPCR's rotations (``opc_0``, ``opc_5.625`` ...)."""
    return _ROTATION.match(key) is not None


#: OPC's bins and each rotation's OPC: charted apart, folded away at first.
DETAILS = frozenset(
    (*BIN_KEYS, *DOOLKIT_BIN_KEYS, *DOOLKIT_ROTATION_KEYS, *MORPHOTESTER_ROTATION_KEYS)
)


@dataclass(frozen=True)
class ReportColumn:
    """One column of the table as the page shows it.

    Attributes
    ----------
    key : str
        The record key.
    family : str
        Its family's id (a key of :data:`FAMILY_LABELS`, or a metric's name).
    label, short : str
        Its name on the page, and on the scatter matrix's axes.
    unit : str
        Its unit (``""``: none).
    numeric : bool
        Some row holds a number in it.
    metric : bool
        It is a metric: charted where it holds a number (not a mesh count, not text).
    headline : bool
        Shown in the table's first view (``key metrics``): each metric's first
        column, ariaDNE's sign split, the vertex count.
    detail : bool
        One of OPC's bins or rotations: charted apart, folded away.
    oriented : bool
        Its metric depends on which way the crown points (:data:`ORIENTED`).
    """

    key: str
    family: str
    label: str
    short: str
    unit: str
    numeric: bool
    metric: bool
    headline: bool = False
    detail: bool = False
    oriented: bool = False

    @property
    def charted(self) -> bool:
        """Whether the page draws it: a metric with a number in some row."""
        return self.metric and self.numeric

    @property
    def title(self) -> str:
        """Its label with its unit: ``"slope (°)"``, ``"RFI"``."""
        return f"{self.label} ({self.unit})" if self.unit else self.label


def family_label(family: str) -> str:
    """How the page names a family."""
    return FAMILY_LABELS.get(family, family)


def families() -> dict[str, tuple[str, ...]]:
    """Family id -> its metrics' names, in table order: ariaDNE, each tool's set, then the rest."""
    found: dict[str, tuple[str, ...]] = {"ariadne": ("ariadne",)}
    for name, members in GROUPS.items():
        if name != ALL:
            found[name] = tuple(members)
    placed = {m for members in found.values() for m in members}
    for metric in METRICS:  # those of no tool's set: each a family of its own
        if metric not in placed:
            found[metric] = (metric,)
    return found


def _catalogue() -> dict[str, tuple[str, str | None]]:
    """Every known metric column -> (family, its metric's name), in table order."""
    columns: dict[str, tuple[str, str | None]] = {}
    for family, members in families().items():
        for metric in members:
            if metric in DOOLKIT_METRICS:
                for key in DOOLKIT_BASE_KEYS:
                    columns.setdefault(key, (family, None))
            if metric in MORPHOTESTER_METRICS:
                for key in MORPHOTESTER_BASE_KEYS:
                    columns.setdefault(key, (family, None))
            for key in METRIC_KEYS.get(metric, ()):
                columns.setdefault(key, (family, metric))
    return {
        key: value for key, value in columns.items() if key not in COUNTS and key not in SETTINGS
    }


_CATALOGUE = _catalogue()
_FIRST_KEYS = frozenset(keys[0] for keys in METRIC_KEYS.values() if keys)
#: The columns of a table that are neither metrics, counts nor settings (file, status ...).
ROW_COLUMNS = tuple(
    key
    for key in record_keys(METRICS)
    if key not in _CATALOGUE and key not in COUNTS and key not in SETTINGS
)


def _number(value) -> float | None:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    return float(value) if math.isfinite(value) else None


def _held(value) -> bool:
    """Whether a cell holds something (not None, NaN or empty text)."""
    if value is None or value == "":
        return False
    return not (isinstance(value, float) and math.isnan(value))


def _column(key: str, family: str, metric: str | None, numeric: bool) -> ReportColumn:
    return ReportColumn(
        key=key,
        family=family,
        label=LABELS.get(key, key),
        short=SHORT_LABELS.get(key, key),
        unit=UNITS.get(key, "patches" if is_rotation(key) else ""),
        numeric=numeric,
        metric=family != MESH,
        headline=key in _FIRST_KEYS or key in SIGNED or key == COUNTS[0],
        detail=key in DETAILS or is_rotation(key),
        oriented=metric in ORIENTED,
    )


def report_columns(records: Sequence[dict]) -> list[ReportColumn]:
    """The columns of `records` the page shows, by family, in table order within each.

    Every column some record holds is here except settings and the row's own
    columns (:data:`ROW_COLUMNS`); a column the package does not know is in
    family ``other``, a metric (charted) when some row holds a number in it.
    A column empty in every row is left out when its whole family is (a
    table of another layout, read with the library's columns, holds no
    ariaDNE: :func:`dentopo.read_table` gives them as None), and kept when
    some column of its family has a value (molaR's RFI where its footprint
    failed on every crown, beside molaR's other metrics); an empty mesh count
    is left out.
    """
    present = list(dict.fromkeys(key for row in records for key in row))
    numeric = {key for key in present if any(_number(row.get(key)) is not None for row in records)}
    valued = {key for key in present if any(_held(row.get(key)) for row in records)}
    order = {family: i for i, family in enumerate((*families(), OTHER, MESH))}
    columns = []
    for key in present:
        if key in _CATALOGUE:
            family, metric = _CATALOGUE[key]
        elif is_rotation(key):
            family, metric = "molar", "opcr"
        elif key in COUNTS:
            family, metric = MESH, None
        elif key in SETTINGS or key in ROW_COLUMNS:
            continue
        else:
            family, metric = OTHER, None
        columns.append(_column(key, family, metric, key in numeric))
    filled = {column.family for column in columns if column.key in valued}
    columns = [
        column
        for column in columns
        if column.family in filled and (column.metric or column.key in valued)
    ]
    known = list(_CATALOGUE)

    def rank(column: ReportColumn) -> tuple:
        if column.key in _CATALOGUE:
            at = known.index(column.key)
        elif is_rotation(column.key):  # OPCR's rotations right after it, in their order
            at = known.index("opcr") + 0.5
        else:
            at = len(known)
        return (order[column.family], at)

    return sorted(columns, key=rank)  # stable: unknown columns keep the table's order


def orientation_mark(value) -> str | None:
    """``"closed"`` or ``"turned"`` from a row's ``orientation`` cell, or None.

    The words are looked for within the cell (``-z; closed, as it lies``,
    ``direction undetermined; closed, as it lies``, ``points -z, turned to
    +z``), so that rewording the rest of it keeps the mark; "not turned" is
    not turned.
    """
    if not isinstance(value, str):
        return None
    text = value.lower()
    if re.search(r"\bclosed\b", text):
        return "closed"
    if re.search(r"(?<!not )\bturned\b", text):
        return "turned"
    return None
