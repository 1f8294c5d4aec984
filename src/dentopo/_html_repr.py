"""Results shown in notebooks: the compact HTML tables behind each result's ``_repr_html_``.

Jupyter calls ``_repr_html_`` to show an object; every public result of
dentopo (ariaDNE's, each topography metric's, a batch's, a study's) answers
with :func:`result_html` or :func:`rows_html`.  A result is shown as its table
fields (what :meth:`to_dict` gives, the main value first and in bold), then its
settings and counts, then its arrays as shape, dtype and min/mean/max (never
their values), with a small inline SVG histogram of one per-vertex or per-face
array where the result has one.  Every text is escaped: a file name or a
warning is data, never markup.

May import: nothing of dentopo (every subpackage may import it).
"""

from __future__ import annotations

import dataclasses
import html
import math
import os
from collections.abc import Iterable, Mapping, Sequence

import numpy as np

#: At most this many rows of a table of records are shown (then a count of the rest).
MAX_ROWS = 20

#: At most this many columns of a table of records are shown (then the names of the rest).
MAX_COLUMNS = 12

#: Bins of the inline histogram.
HISTOGRAM_BINS = 24

_STYLE = (
    "<style>"
    ".dentopo-repr{font-family:sans-serif;font-size:12px}"
    ".dentopo-repr table{border-collapse:collapse;margin:2px 0 6px 0}"
    ".dentopo-repr th,.dentopo-repr td{padding:1px 8px;text-align:left;"
    "border-bottom:1px solid rgba(128,128,128,0.25)}"
    ".dentopo-repr td.num{text-align:right;font-variant-numeric:tabular-nums}"
    ".dentopo-repr caption{text-align:left;font-weight:bold;padding:2px 0}"
    ".dentopo-repr .dentopo-section{color:gray;font-style:italic}"
    "</style>"
)


def escape(value: object) -> str:
    """``html.escape(str(value))``: quotes escaped too."""
    return html.escape(str(value), quote=True)


def format_value(value: object) -> str:
    """One cell's text (not yet escaped): floats to 6 significant digits, tuples shortened."""
    if isinstance(value, (bool, np.bool_)):
        return str(bool(value))
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    if isinstance(value, (float, np.floating)):
        return f"{float(value):.6g}"
    if isinstance(value, tuple):
        if len(value) > 8:
            shown = ", ".join(format_value(v) for v in value[:8])
            return f"({shown}, ... {len(value)} in all)"
        return "(" + ", ".join(format_value(v) for v in value) + ")"
    if value is None:
        return "-"
    return str(value)


def _is_number(value: object) -> bool:
    return isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(
        value, (bool, np.bool_)
    )


def _is_scalar(value: object) -> bool:
    if value is None or isinstance(value, (str, bool, int, float, np.generic)):
        return True
    return isinstance(value, tuple) and all(_is_scalar(v) for v in value)


def array_summary(array: np.ndarray) -> str:
    """``"(n,) float64, min 0.1, mean 0.5, max 2"``; the values themselves are never shown."""
    shape = "(" + ", ".join(str(n) for n in array.shape) + ("," if array.ndim == 1 else "") + ")"
    text = f"{shape} {array.dtype}"
    if array.size == 0:
        return text + ", empty"
    if array.dtype == bool:
        return text + f", {int(np.count_nonzero(array))} true"
    if not np.issubdtype(array.dtype, np.number):
        return text
    finite = array[np.isfinite(array)] if np.issubdtype(array.dtype, np.floating) else array
    if finite.size == 0:
        return text + ", no finite values"
    parts = [
        f"min {format_value(finite.min())}",
        f"mean {format_value(float(finite.mean()))}",
        f"max {format_value(finite.max())}",
    ]
    if finite.size < array.size:
        parts.append(f"{array.size - finite.size} not finite")
    return text + ", " + ", ".join(parts)


def histogram_svg(values: np.ndarray, *, width: int = 240, height: int = 48) -> str:
    """A small inline SVG histogram of the finite `values` (empty string if there are none)."""
    values = np.asarray(values, dtype=float).ravel()
    values = values[np.isfinite(values)]
    if values.size == 0:
        return ""
    low, high = float(values.min()), float(values.max())
    if high <= low:
        high = low + 1.0
    counts, _ = np.histogram(values, bins=HISTOGRAM_BINS, range=(low, high))
    top = max(int(counts.max()), 1)
    bar = width / HISTOGRAM_BINS
    rects = []
    for k, count in enumerate(counts):
        h = (height - 12) * count / top
        rects.append(
            f'<rect x="{k * bar:.1f}" y="{height - 12 - h:.1f}" width="{bar - 1:.1f}" '
            f'height="{h:.1f}" fill="#4c78a8"/>'
        )
    label = escape(f"{format_value(low)} .. {format_value(float(values.max()))}")
    return (
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" '
        f'role="img" aria-label="histogram">{"".join(rects)}'
        f'<text x="0" y="{height - 1}" font-size="10" fill="gray">{label}</text></svg>'
    )


def _describe(value: object) -> str | None:
    """The text of a field that is not a scalar nor an array, or None to leave it out."""
    if dataclasses.is_dataclass(value) and hasattr(value, "to_dict"):
        row = value.to_dict()
        main = next(iter(row.items()), None)
        text = type(value).__name__
        return f"{text} ({main[0]} {format_value(main[1])})" if main else text
    if hasattr(value, "vertices") and hasattr(value, "faces") and hasattr(value, "metadata"):
        name = (value.metadata or {}).get("file_name")
        counts = f"{len(value.vertices)} vertices, {len(value.faces)} faces"
        return (
            f"{type(value).__name__} {name}: {counts}"
            if name
            else (f"{type(value).__name__}: {counts}")
        )
    if isinstance(value, Mapping):
        return f"{len(value)} {'entry' if len(value) == 1 else 'entries'}"
    if isinstance(value, (list, Sequence)) and not isinstance(value, str):
        return f"{len(value)} {'item' if len(value) == 1 else 'items'}"
    text = str(value)
    return text if len(text) <= 200 else text[:200] + "..."


def _rows(items: Iterable[tuple[str, str, bool]], *, bold_first: bool = False) -> str:
    out = []
    for k, (name, text, numeric) in enumerate(items):
        cell = escape(text)
        if bold_first and k == 0:
            cell = f"<b>{cell}</b>"
        css = ' class="num"' if numeric else ""
        out.append(f"<tr><th>{escape(name)}</th><td{css}>{cell}</td></tr>")
    return "".join(out)


def _section(title: str) -> str:
    return f'<tr><td colspan="2" class="dentopo-section">{escape(title)}</td></tr>'


def result_html(result: object, *, histogram: str | None = None) -> str:
    """A result as a compact HTML table.

    Parameters
    ----------
    result : dataclass instance
        Its ``to_dict()`` (if any) gives the values shown first; its other
        fields follow as settings and counts, then arrays (summarised), then
        anything else (a mesh as its counts, a nested result as its main value).
    histogram : str, optional
        The name of an array field drawn as a small inline histogram.
    """
    values = result.to_dict() if hasattr(result, "to_dict") else {}
    fields = [f.name for f in dataclasses.fields(result)]
    settings, arrays, others = [], [], []
    shown = [v for v in values.values() if isinstance(v, float)]
    for name in fields:
        value = getattr(result, name)
        if name in values or (isinstance(value, float) and any(value is v for v in shown)):
            continue  # already a table field, under its table name
        if isinstance(value, np.ndarray):
            arrays.append((name, array_summary(value), False))
        elif _is_scalar(value):
            settings.append((name, format_value(value), _is_number(value)))
        else:
            text = _describe(value)
            if text is not None:
                others.append((name, text, False))
    if not values:  # no table fields: the scalars are the values
        values = {name: getattr(result, name) for name, _, _ in settings}
        settings = []
    body = [
        _rows(((k, format_value(v), _is_number(v)) for k, v in values.items()), bold_first=True)
    ]
    if settings:
        body += [_section("settings and counts"), _rows(settings)]
    if arrays:
        body += [_section("arrays"), _rows(arrays)]
    if others:
        body += [_section("also"), _rows(others)]
    picture = ""
    if histogram is not None:
        array = getattr(result, histogram, None)
        if isinstance(array, np.ndarray) and array.size:
            svg = histogram_svg(array)
            if svg:
                picture = f"<div>{escape(histogram)}</div>{svg}"
    caption = f"<caption>{escape(type(result).__name__)}</caption>"
    return (
        f'<div class="dentopo-repr">{_STYLE}<table>{caption}{"".join(body)}</table>{picture}</div>'
    )


def _same(a: object, b: object) -> bool:
    if isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b):
        return True
    try:
        return bool(a == b) and type(a) is type(b)
    except (TypeError, ValueError):
        return False


def rows_html(
    rows: Sequence[Mapping],
    *,
    title: str,
    summary: Mapping[str, object] | None = None,
    first: Sequence[str] = (),
    settings: Sequence[str] = (),
) -> str:
    """A table of records (a batch's rows, a study's) as compact HTML.

    At most :data:`MAX_ROWS` rows and :data:`MAX_COLUMNS` columns are shown;
    the rest are counted (and the hidden columns named).  A ``file`` column is
    shown as the file's base name.

    Parameters
    ----------
    rows : sequence of mapping
    title : str
        The caption.
    summary : mapping, optional
        Name -> value pairs shown above the table (counts, settings).
    first : sequence of str
        Columns shown first, when present.
    settings : sequence of str
        Columns that, when they hold one value in every row, are shown once
        above the table instead (as are columns holding one text in every
        row); columns empty in every row are left out.
    """
    keys = list(dict.fromkeys(key for row in rows for key in row))
    summary = dict(summary or {})
    if len(rows) > 1:
        kept = []
        for key in keys:
            values = [row.get(key) for row in rows]
            same = all(_same(v, values[0]) for v in values)
            if key in first or not same:
                kept.append(key)
            elif values[0] is None:
                continue
            elif key in settings or not _is_number(values[0]):
                summary.setdefault(key, values[0])
            else:
                kept.append(key)
        keys = kept
    ordered = [k for k in first if k in keys] + [k for k in keys if k not in first]
    shown, hidden = ordered[:MAX_COLUMNS], ordered[MAX_COLUMNS:]
    parts = [f'<div class="dentopo-repr">{_STYLE}']
    parts.append(f"<table><caption>{escape(title)}</caption>")
    if summary:
        parts.append(_rows((k, format_value(v), _is_number(v)) for k, v in summary.items()))
    parts.append("</table>")
    if rows:
        parts.append("<table><tr>" + "".join(f"<th>{escape(k)}</th>" for k in shown) + "</tr>")
        for row in rows[:MAX_ROWS]:
            cells = []
            for key in shown:
                value = row.get(key)
                if key == "file" and isinstance(value, str):
                    value = os.path.basename(value) or value
                if isinstance(value, float) and math.isnan(value):
                    value = None
                css = ' class="num"' if _is_number(value) else ""
                cells.append(f"<td{css}>{escape(format_value(value))}</td>")
            parts.append("<tr>" + "".join(cells) + "</tr>")
        parts.append("</table>")
        notes = []
        if len(rows) > MAX_ROWS:
            notes.append(f"{len(rows) - MAX_ROWS} more rows")
        if hidden:
            names = ", ".join(hidden[:20]) + (", ..." if len(hidden) > 20 else "")
            notes.append(f"{len(hidden)} more columns: {names}")
        if notes:
            parts.append(f"<div>{escape('; '.join(notes))}</div>")
    parts.append("</div>")
    return "".join(parts)
