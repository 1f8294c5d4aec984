"""Result tables' column layouts: which columns, under which names, in which order.

The record keys each metric fills (:data:`METRIC_KEYS`, :func:`record_keys`),
the :class:`Column` and :class:`Layout` that say how a table names and orders
them and how a cell reads back with its type, and the four layouts found by
name in one registry, :data:`LAYOUTS`: ``dentopo`` (every column, the
library's names), ``signdne`` (the published signDNE 0.1.4 CLI's), ``molar``
(molaR_Batch's), ``doolkit`` (doolkit 1.42's) and ``morphotester`` (MorphoTester
1.1.1's results file, its numbers printed as it prints them).  Adding a layout is one
entry in the registry; :func:`layout` finds it.  How the cells are stored in a
file (CSV, TSV, JSON, Excel) and the writing and reading of a table are in
``_tables``.
"""

from __future__ import annotations

import os
import re
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field, replace

from ..ariadne import SCALAR_FIELDS
from ..topography import (
    BIN_KEYS,
    CLASSIC_KEYS,
    DOOLKIT_BASE_KEYS,
    DOOLKIT_BIN_KEYS,
    DOOLKIT_METRICS,
    DOOLKIT_ROTATION_KEYS,
    METRICS,
    MORPHOTESTER_BASE_KEYS,
    MORPHOTESTER_METRICS,
    MORPHOTESTER_ROTATION_KEYS,
    ORIENTED,
    UNIT_DEPENDENT,
    check_metrics,
    rotation_key,
)

#: The column of the preparation protocol a row's mesh was prepared with (``--prepare``):
#: ``Protocol.label``, ``"name digest12"``; empty for a mesh measured as read.
PROTOCOL_KEY = "protocol"
#: Columns of a results table of ariaDNE (the default metric), in order, with the library's names.
COLUMNS = ("file", *SCALAR_FIELDS, PROTOCOL_KEY, "seconds", "status", "error", "warnings")

#: The record keys each metric fills, in table order (OPCR also fills one key per rotation,
#: :func:`~dentopo.topography.rotation_key`, right after ``opcr``).
METRIC_KEYS = {
    "ariadne": SCALAR_FIELDS,
    "classic": tuple(CLASSIC_KEYS.values()),
    "rfi": ("rfi", "area_3d", "area_2d", "alpha"),
    "opcr": ("opcr",),
    "opc": ("opc", *BIN_KEYS),
    "slope": ("slope",),
    "arc": ("arc", "arc_positive", "arc_negative"),
    # doolkit's, under the names of doolkit's table (prefixed dk_ where molaR has the name)
    "doolkit_slope": ("slope_mean",),
    "angularity": ("angularity_mean",),
    "relief_index": ("rfi_ungar", "rfi_boyer", "rfi_guy"),
    "inclination": ("inclin_mean",),
    "doolkit_opc": ("dk_opc", *DOOLKIT_BIN_KEYS),
    "doolkit_opcr": ("dk_opcr", *DOOLKIT_ROTATION_KEYS),
    "doolkit_arc": ("arc_mean", "arc_pos_mean", "arc_neg_mean"),
    "doolkit_dne": ("dne_total", "dne_total_unrounded"),
    "relief_rate": ("rrate_below_median",),
    "shape_index": ("shape_formfactor", "shape_elongation", "shape_k"),
    "footprint": ("area2d", "area2d_convex"),
    "hypsodonty": ("hypso_hypsodonty", "hypso_height", "hypso_length", "hypso_width"),
    "morphotester_dne": ("mt_dne",),
    "morphotester_rfi": ("mt_rfi", "mt_surface_area", "mt_outline_area"),
    "morphotester_opcr": ("mt_opcr", *MORPHOTESTER_ROTATION_KEYS),
    "rfi_projected": (
        "rfi_projected",
        "rfi_projected_ungar",
        "projected_area_3d",
        "projected_area_2d",
    ),
    "pcv": ("pcv", "pcv_area"),
}
#: Settings columns of the topography metrics (ariaDNE's are among its own keys).
SETTING_KEYS = {
    "classic": ("dne_outliers", "dne_boundary", "dne_kappa"),
    "rfi": ("rfi_alpha", "find_alpha"),
    "opcr": ("opcr_steps", "opcr_step", "min_faces", "min_area"),
    "opc": ("min_faces", "min_area"),
    "arc": ("arc_boundary", "arc_range_low", "arc_range_high"),
    # doolkit's metrics whose definitions assume millimetres: the meshes' unit, if given
    # (millimetres per unit; empty: taken as millimetres)
    **dict.fromkeys(UNIT_DEPENDENT, ("mm_per_unit",)),
    "morphotester_dne": ("mt_condition_check", "mt_outliers", "mt_percentile", "mt_smooth"),
    "morphotester_rfi": ("mm_per_unit",),
    "morphotester_opcr": ("mt_min_patch",),
    "pcv": ("pcv_rays", "pcv_hemisphere", "pcv_method"),
}
#: Columns of the metrics that assume the crown points to +z: what was found and done, and
#: the ``orient`` setting.
ORIENTATION_KEYS = ("orientation", "orient")
#: Columns that end every row (``warnings``: what the computation warned about, if anything).
END_KEYS = ("seconds", "status", "error", "warnings")

_INTEGER_COLUMNS = frozenset(
    {
        "vertices",
        "faces",
        "opc",
        *BIN_KEYS,
        "opcr_steps",
        "min_faces",
        "n_vertices",
        "n_faces",
        "dk_opc",
        *DOOLKIT_BIN_KEYS,
        *DOOLKIT_ROTATION_KEYS,
        *MORPHOTESTER_BASE_KEYS,
        *MORPHOTESTER_ROTATION_KEYS,
        "mt_min_patch",
        "pcv_rays",
    }
)
_TEXT_COLUMNS = frozenset(
    {
        "file",
        "distance_type",
        "sign_method",
        "method",
        "status",
        "error",
        "warnings",
        "orientation",
        "orient",
        "dne_boundary",
        "arc_boundary",
        "mt_outliers",
        "pcv_method",
        PROTOCOL_KEY,
    }
)
_BOOL_COLUMNS = frozenset({"find_alpha", "mt_condition_check", "mt_smooth", "pcv_hemisphere"})
_ROTATION = re.compile(r"opc_(-?[0-9.]+(?:e[-+]?[0-9]+)?)$")


def record_keys(metrics=("ariadne",), rotations: Sequence[float] = ()) -> tuple[str, ...]:
    """A record's keys for `metrics` (see :data:`METRIC_KEYS`), `rotations` of OPCR, in order.

    ``file``, each metric's values, the orientation columns (if a metric
    needs it), the settings of the topography metrics, ``protocol`` (the
    preparation protocol, empty without one), then ``seconds``, ``status``,
    ``error`` and ``warnings``.
    """
    metrics = check_metrics(metrics)
    keys = ["file"]
    for metric in metrics:
        if metric in DOOLKIT_METRICS:
            keys += DOOLKIT_BASE_KEYS  # once, before the first of doolkit's metrics
        if metric in MORPHOTESTER_METRICS:
            keys += MORPHOTESTER_BASE_KEYS  # once, before the first of MorphoTester's
        keys += METRIC_KEYS[metric]
        if metric == "opcr":
            keys += [rotation_key(degrees) for degrees in rotations]
    if ORIENTED.intersection(metrics):
        keys.append("orientation")
    for metric in metrics:
        keys += SETTING_KEYS.get(metric, ())
    if ORIENTED.intersection(metrics):
        keys.append("orient")
    keys.append(PROTOCOL_KEY)
    keys += END_KEYS
    return tuple(dict.fromkeys(keys))


_ALL_KEYS = frozenset(record_keys(METRICS))


def known_key(name: str) -> bool:
    """Whether `name` is a record key of some metric (or a rotation's OPC)."""
    return name in _ALL_KEYS or _ROTATION.match(name) is not None


@dataclass(frozen=True)
class Column:
    """One column of a layout.

    Attributes
    ----------
    header : str
        The column's name in the file.
    key : str
        The record key (one of :data:`COLUMNS`) whose value it holds.
    kind : str
        ``"text"``, ``"int"``, ``"float"`` or ``"bool"``: how a cell reads back.
    basename : bool
        Write only the base name of a path (molaR's ``File`` column).
    """

    header: str
    key: str
    kind: str
    basename: bool = False


def _kind(key: str) -> str:
    if key in _TEXT_COLUMNS:
        return "text"
    if key in _BOOL_COLUMNS:
        return "bool"
    return "int" if key in _INTEGER_COLUMNS or _ROTATION.match(key) else "float"


#: ``build(metrics, rotations) -> columns`` of a layout whose columns follow the metrics.
Builder = Callable[[tuple[str, ...], tuple[float, ...]], tuple[Column, ...]]
#: ``parse(header) -> columns``: the columns of a file's header this layout knows.
Parser = Callable[[Sequence[str]], tuple[Column, ...]]


@dataclass(frozen=True)
class Layout:
    """Which columns a table has, under which names, and how numbers are written as text.

    Attributes
    ----------
    name : str
        The layout's name (``--columns NAME``).
    columns : tuple of Column
        The columns, in order (of ariaDNE's table, for a layout whose columns
        follow the metrics: see :meth:`for_metrics`).
    required : tuple of str
        Headers a file must have to be read as this layout.
    decimals : int or None
        In text formats (CSV, TSV), numbers with this many decimals
        (``f"{x:.16f}"``); None writes the shortest text that reads back to
        the same float (``repr``).  JSON and Excel always store the numbers.
    failed_rows : bool
        Whether rows of files that failed are written.  A layout without
        them has no status column: every row it holds is ``ok``.
    resumable : bool
        Whether ``--resume`` can read it: it holds the settings of each row.
    description : str
        One line for ``--help``.
    build, parse : callable, optional
        The columns for given metrics, and the columns of a file's header;
        None for a layout with fixed columns.
    metrics : tuple of str
        The metrics whose columns :attr:`columns` holds.
    excluded : tuple of str
        Headers a file of this layout never has (to tell it from another
        layout whose required columns it shares).
    number : callable, optional
        How this layout writes a float as text in CSV and TSV (its tool's own
        printing), in place of :attr:`decimals`.
    """

    name: str
    columns: tuple[Column, ...]
    required: tuple[str, ...]
    decimals: int | None = None
    failed_rows: bool = True
    resumable: bool = True
    description: str = ""
    build: Builder | None = field(default=None, repr=False, compare=False)
    parse: Parser | None = field(default=None, repr=False, compare=False)
    metrics: tuple[str, ...] = ("ariadne",)
    excluded: tuple[str, ...] = ()
    number: Callable[[float], str] | None = field(default=None, repr=False, compare=False)

    @property
    def header(self) -> tuple[str, ...]:
        """The column names, in order."""
        return tuple(column.header for column in self.columns)

    def for_metrics(self, metrics=("ariadne",), rotations: Sequence[float] = ()) -> Layout:
        """This layout with the columns of `metrics` (and of OPCR's `rotations`, degrees)."""
        if self.build is None:
            return self
        metrics = check_metrics(metrics)
        rotations = tuple(float(r) for r in rotations)
        return replace(self, columns=self.build(metrics, rotations), metrics=metrics)

    def rows(self, records: Iterable[dict]) -> list[list]:
        """The cells of `records` in this layout (typed values; None for missing)."""
        return [
            [column_value(record, column) for column in self.columns]
            for record in records
            if self.failed_rows or record.get("status") == "ok"
        ]

    def text(self, value) -> str:
        """A cell as text: empty for None, numbers by :attr:`decimals`."""
        if value is None:
            return ""
        if isinstance(value, float):
            if self.number is not None:
                return self.number(value)
            return repr(value) if self.decimals is None else f"{value:.{self.decimals}f}"
        return str(value)

    def records(self, raw: Iterable[dict], header: Sequence[str] = ()) -> list[dict]:
        """Rows read from a file (keyed by header) as typed records with every key of COLUMNS."""
        raw = list(raw)
        if self.parse is None:
            columns = self.columns
        else:  # the columns the rows hold (a file's header; the keys of journal rows)
            columns = self.parse(header or list(dict.fromkeys(key for row in raw for key in row)))
        records = []
        for row in raw:
            record = dict.fromkeys(COLUMNS)
            if not self.failed_rows:
                record["status"] = "ok"
            for column in columns:
                record[column.key] = _typed(column.kind, row.get(column.header))
            records.append(record)
        return records


def column_value(record: dict, column: Column):
    """The value of `column` in `record` (a path cut to its base name where the column says)."""
    value = record.get(column.key)
    if column.basename and value is not None:
        return os.path.basename(value)
    return value


def _dentopo_columns(metrics, rotations) -> tuple[Column, ...]:
    return tuple(Column(key, key, _kind(key)) for key in record_keys(metrics, rotations))


def _dentopo_parse(header: Sequence[str]) -> tuple[Column, ...]:
    return tuple(Column(name, name, _kind(name)) for name in header if known_key(name))


DENTOPO = Layout(
    name="dentopo",
    columns=_dentopo_columns(("ariadne",), ()),
    required=("file", "status"),
    description="every column, with the library's names (the default; --resume reads it)",
    build=_dentopo_columns,
    parse=_dentopo_parse,
)

#: The columns of the published signDNE 0.1.4 command line, in its order and with its names.
SIGNDNE = Layout(
    name="signdne",
    columns=(
        Column("File", "file", "text"),
        Column("DNE", "dne", "float"),
        Column("positive_DNE", "positive_dne", "float"),
        Column("negative_DNE", "negative_dne", "float"),
        Column("surface_area", "surface_area", "float"),
        Column("positive_surface_area", "positive_surface_area", "float"),
        Column("negative_surface_area", "negative_surface_area", "float"),
    ),
    required=(
        "File",
        "DNE",
        "positive_DNE",
        "negative_DNE",
        "surface_area",
        "positive_surface_area",
        "negative_surface_area",
    ),
    decimals=16,
    failed_rows=False,
    resumable=False,
    description="the published signDNE 0.1.4 CLI's columns and number format; ok rows only",
)

#: molaR_Batch's column names for our record keys, by metric, in its order.
MOLAR_NAMES = {
    "classic": {
        "classic_dne": "DNE",
        "classic_convex_dne": "Convex_DNE",
        "classic_concave_dne": "Concave_DNE",
        "classic_convex_area": "Convex_Area",
        "classic_concave_area": "Concave_Area",
    },
    "rfi": {"rfi": "RFI", "area_3d": "3D_Area", "area_2d": "2D_Area", "alpha": "Alpha"},
    "opcr": {"opcr": "OPCR"},
    "opc": {"opc": "OPC", **{key: f"Bin {k}" for k, key in enumerate(BIN_KEYS, start=1)}},
    "slope": {"slope": "Slope"},
    # molaR_Batch has no ARC column: ours, after molaR's own, under molaR's function's names
    "arc": {"arc": "ARC", "arc_positive": "ARC_positive", "arc_negative": "ARC_negative"},
}
#: ariaDNE's columns after molaR's, under names that cannot be taken for molaR's DNE.
MOLAR_ARIADNE = {
    "dne": "ariaDNE",
    "positive_dne": "positive_ariaDNE",
    "negative_dne": "negative_ariaDNE",
}
MOLAR_END = {
    "orientation": "orientation",
    "status": "status",
    "error": "error",
    "warnings": "warnings",
}


def _molar_rotation_header(key: str) -> str:
    return f"{key[len('opc_') :]} deg."


def _molar_columns(metrics, rotations) -> tuple[Column, ...]:
    columns = [Column("File", "file", "text", basename=True)]
    for metric in MOLAR_NAMES:
        if metric not in metrics:
            continue
        for key, header in MOLAR_NAMES[metric].items():
            columns.append(Column(header, key, _kind(key)))
            if key == "opcr":
                for degrees in rotations:
                    rkey = rotation_key(degrees)
                    columns.append(Column(_molar_rotation_header(rkey), rkey, "int"))
    if "ariadne" in metrics:
        columns += [Column(header, key, "float") for key, header in MOLAR_ARIADNE.items()]
    for key, header in MOLAR_END.items():
        if key != "orientation" or ORIENTED.intersection(metrics):
            columns.append(Column(header, key, "text"))
    return tuple(columns)


def _molar_parse(header: Sequence[str]) -> tuple[Column, ...]:
    names = {"File": "file", **MOLAR_END}
    for table in (*MOLAR_NAMES.values(), MOLAR_ARIADNE):
        names.update({name: key for key, name in table.items()})
    columns = []
    for name in header:
        if name in names:
            columns.append(Column(name, names[name], _kind(names[name])))
        elif name.endswith(" deg.") and _ROTATION.match("opc_" + name[: -len(" deg.")]):
            columns.append(Column(name, "opc_" + name[: -len(" deg.")], "int"))
    return tuple(columns)


MOLAR = Layout(
    name="molar",
    columns=_molar_columns(METRICS, ()),
    required=("File", "status"),
    resumable=False,
    description="molaR_Batch's columns (File, DNE, ..., RFI, ..., OPCR, ..., Slope; DNE is "
    "classic DNE), then ariaDNE's, orientation, status and error",
    build=_molar_columns,
    parse=_molar_parse,
    metrics=METRICS,
)

#: doolkit's table's names for our record keys where they differ (the rest are doolkit's own).
DOOLKIT_NAMES = {
    "dk_opc": "opc",
    **{key: f"opc_bin{k}" for k, key in enumerate(DOOLKIT_BIN_KEYS, start=1)},
    "dk_opcr": "opcr",
    **{key: f"opcr_rot{k}" for k, key in enumerate(DOOLKIT_ROTATION_KEYS)},
}
DOOLKIT_END = {"status": "status", "error": "error", "warnings": "warnings"}


def _doolkit_columns(metrics, rotations) -> tuple[Column, ...]:
    columns = [Column("file", "file", "text", basename=True)]
    chosen = [metric for metric in DOOLKIT_METRICS if metric in metrics]
    if chosen:
        columns += [Column(key, key, _kind(key)) for key in DOOLKIT_BASE_KEYS]
    for metric in chosen:
        for key in METRIC_KEYS[metric]:
            columns.append(Column(DOOLKIT_NAMES.get(key, key), key, _kind(key)))
    columns += [Column(header, key, "text") for key, header in DOOLKIT_END.items()]
    return tuple(columns)


def _doolkit_parse(header: Sequence[str]) -> tuple[Column, ...]:
    names = {"file": "file", **DOOLKIT_END}
    names.update({key: key for key in DOOLKIT_BASE_KEYS})
    for metric in DOOLKIT_METRICS:
        names.update({DOOLKIT_NAMES.get(key, key): key for key in METRIC_KEYS[metric]})
    return tuple(Column(name, names[name], _kind(names[name])) for name in header if name in names)


DOOLKIT = Layout(
    name="doolkit",
    columns=_doolkit_columns(DOOLKIT_METRICS, ()),
    required=("file", "n_vertices", "n_faces", "status"),
    resumable=False,
    description="doolkit 1.42's table's columns (file, n_vertices, n_faces, area3d, "
    "slope_mean, ..., hypso_width; doolkit's metrics only), then status, error and warnings",
    build=_doolkit_columns,
    parse=_doolkit_parse,
    metrics=DOOLKIT_METRICS,
    excluded=("seconds",),  # a dentopo table of doolkit's metrics has n_vertices too
)

#: MorphoTester's table's names for our record keys (its results file, ``morphoresults.txt``).
MORPHOTESTER_NAMES = {
    "mt_n_faces": "Mesh Face Number",
    "mt_dne": "DNE",
    "mt_rfi": "RFI",
    "mt_surface_area": "Surface Area",
    "mt_outline_area": "Outline Area",
    "mt_opcr": "OPCR",
}
MORPHOTESTER_END = {"status": "status", "error": "error", "warnings": "warnings"}


def python2_str(value: float) -> str:
    """A float as Python 2's ``str`` prints it, as MorphoTester writes its results.

    Twelve significant digits, and a whole number keeps a trailing ``.0``
    (``68.0``, ``209.485``, ``67.125``); infinities and NaN as Python 2 names them.
    """
    if value != value:
        return "nan"
    if value in (float("inf"), float("-inf")):
        return "inf" if value > 0 else "-inf"
    text = f"{value:.12g}"
    return text if any(c in text for c in ".e") else text + ".0"


def _morphotester_columns(metrics, rotations) -> tuple[Column, ...]:
    columns = [Column("Filename", "file", "text", basename=True)]
    chosen = [metric for metric in MORPHOTESTER_METRICS if metric in metrics]
    if chosen:
        columns += [Column(MORPHOTESTER_NAMES[k], k, _kind(k)) for k in MORPHOTESTER_BASE_KEYS]
    for metric in chosen:
        for key in METRIC_KEYS[metric]:
            if key in MORPHOTESTER_NAMES:
                columns.append(Column(MORPHOTESTER_NAMES[key], key, _kind(key)))
    columns += [Column(header, key, "text") for key, header in MORPHOTESTER_END.items()]
    return tuple(columns)


def _morphotester_parse(header: Sequence[str]) -> tuple[Column, ...]:
    names = {"Filename": "file", **{h: k for k, h in MORPHOTESTER_NAMES.items()}}
    names.update(MORPHOTESTER_END)
    return tuple(Column(name, names[name], _kind(names[name])) for name in header if name in names)


MORPHOTESTER = Layout(
    name="morphotester",
    columns=_morphotester_columns(MORPHOTESTER_METRICS, ()),
    required=("Filename", "Mesh Face Number", "status"),
    resumable=False,
    description="MorphoTester 1.1.1's results columns (Filename, Mesh Face Number, DNE, RFI, "
    "Surface Area, Outline Area, OPCR; its metrics only, numbers printed as it prints them), "
    "then status, error and warnings",
    build=_morphotester_columns,
    parse=_morphotester_parse,
    metrics=MORPHOTESTER_METRICS,
    number=python2_str,
)

#: Column layouts by name; :func:`read_table` recognises a file's layout by its header.
LAYOUTS: dict[str, Layout] = {
    layout.name: layout for layout in (DENTOPO, SIGNDNE, MOLAR, DOOLKIT, MORPHOTESTER)
}


def layout(columns: str | Layout, metrics=None, rotations: Sequence[float] = ()) -> Layout:
    """The :class:`Layout` named `columns` (a Layout is returned as it is).

    With `metrics` (and OPCR's `rotations`), the layout's columns for them.

    Raises
    ------
    ValueError
        For a name not in :data:`LAYOUTS`, or an unknown metric.
    """
    if not isinstance(columns, Layout):
        if columns not in LAYOUTS:
            raise ValueError(f"unknown columns {columns!r}: use one of {', '.join(LAYOUTS)}")
        columns = LAYOUTS[columns]
    return columns if metrics is None else columns.for_metrics(metrics, rotations)


def _typed(kind: str, value):
    if value is None or value == "":
        return None
    if kind == "text":
        return str(value)
    if kind == "bool":
        if isinstance(value, bool):
            return value
        text = str(value).strip().lower()
        if text in ("true", "1", "yes"):
            return True
        if text in ("false", "0", "no"):
            return False
        raise ValueError(f"{value!r} is not true or false")
    if kind == "int":
        if isinstance(value, float) and not value.is_integer():
            raise ValueError(f"{value!r} is not a whole number")
        return int(value)
    return float(value)
