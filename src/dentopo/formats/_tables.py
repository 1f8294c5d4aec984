"""Output files: result tables (CSV, JSON) and per-vertex files (PLY, CSV).

Every file is written atomically: into a temporary file in the same
directory, then renamed over the target with ``os.replace``, so that a run that
fails or is interrupted never leaves a half-written file and never clobbers an
existing one.  Tables can be read back (``--resume``) with their types.
"""

from __future__ import annotations

import csv
import json
import math
import os
from collections.abc import Iterable

from ..ariadne import SCALAR_FIELDS
from ._atomic import atomic_write

#: Columns of a results table, in order, with the library's names.
COLUMNS = ("file", *SCALAR_FIELDS, "seconds", "status", "error")

#: Output formats by file extension.
FORMATS = {".csv": "csv", ".json": "json"}

_INTEGER_COLUMNS = frozenset({"vertices", "faces"})
_TEXT_COLUMNS = frozenset({"file", "distance_type", "sign_method", "method", "status", "error"})


def output_format(path: str | os.PathLike) -> str:
    """``"csv"`` or ``"json"`` from the extension of `path` (case-insensitive).

    Raises
    ------
    ValueError
        For any other extension.
    """
    ext = os.path.splitext(os.fspath(path))[1].lower()
    if ext not in FORMATS:
        raise ValueError(
            f"cannot tell the output format of {os.fspath(path)!r}: "
            f"use one of the extensions {', '.join(FORMATS)}"
        )
    return FORMATS[ext]


def _csv_cell(value) -> str:
    if value is None:
        return ""
    if isinstance(value, float):
        return repr(value)  # shortest string that reads back to the same float
    return str(value)


def _json_value(value):
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def write_table(path: str | os.PathLike, records: Iterable[dict]) -> None:
    """Write result records to a CSV or JSON file (format from the extension), atomically.

    Parameters
    ----------
    path : str or path-like
        ``.csv``: a header row with :data:`COLUMNS`, missing values empty.
        ``.json``: a list of objects with the same keys, missing values null.
    records : iterable of dict
        Rows with (at least) the keys in :data:`COLUMNS`.
    """
    fmt = output_format(path)
    rows = [{name: record.get(name) for name in COLUMNS} for record in records]

    def write(stream):
        if fmt == "csv":
            writer = csv.writer(stream, lineterminator="\n")
            writer.writerow(COLUMNS)
            writer.writerows([_csv_cell(row[name]) for name in COLUMNS] for row in rows)
        else:
            data = [{k: _json_value(v) for k, v in row.items()} for row in rows]
            json.dump(data, stream, indent=1, ensure_ascii=False, allow_nan=False)
            stream.write("\n")

    atomic_write(path, write)


def _typed(name: str, text):
    if text is None or text == "":
        return None
    if name in _TEXT_COLUMNS:
        return str(text)
    if name in _INTEGER_COLUMNS:
        return int(text)
    return float(text)


def read_table(path: str | os.PathLike) -> list[dict]:
    """Read a table written by :func:`write_table` back into typed records.

    Raises
    ------
    ValueError
        If the file is not such a table (wrong format or missing columns).
    """
    path = os.fspath(path)
    fmt = output_format(path)
    with open(path, encoding="utf-8", newline="") as stream:
        if fmt == "csv":
            raw = list(csv.DictReader(stream))
            header = set(raw[0]) if raw else set(COLUMNS)
        else:
            try:
                raw = json.load(stream)
            except json.JSONDecodeError as exc:
                raise ValueError(f"{path!r} is not valid JSON: {exc}") from exc
            if not isinstance(raw, list) or not all(isinstance(r, dict) for r in raw):
                raise ValueError(f"{path!r} does not hold a list of result rows")
            header = set().union(*raw) if raw else set(COLUMNS)
    missing = [name for name in ("file", "status") if name not in header]
    if missing:
        raise ValueError(f"{path!r} is not a dentopo results table (no {', '.join(missing)})")
    try:
        return [{name: _typed(name, row.get(name)) for name in COLUMNS} for row in raw]
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{path!r} has a malformed value: {exc}") from exc
