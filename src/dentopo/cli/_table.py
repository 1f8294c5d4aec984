"""The summary table printed on stdout when no ``--output`` is given.

On a terminal it is a `rich` table (status in colour, long cells folded to the
width).  Otherwise (a pipe, a file) it stays plain text that scripts can parse:
one header line and one line per file, columns aligned with spaces, no
box-drawing characters, no colour, no escape codes, and rich is not imported.
"""

from __future__ import annotations

import os
import sys

from ..formats import METRIC_KEYS
from ..topography import ORIENTED
from ._progress import is_terminal

#: Columns of the table printed on stdout when no --output is given.
TABLE_COLUMNS = (
    "file",
    "dne",
    "positive_dne",
    "negative_dne",
    "surface_area",
    "vertices",
    "faces",
    "seconds",
    "status",
    "error",
)

#: The summary columns of each metric (``opcr`` and the rest of the metrics' values are in
#: the --output table).
METRIC_SUMMARY = {
    "ariadne": ("dne", "positive_dne", "negative_dne", "surface_area", "vertices", "faces"),
    "classic": ("classic_dne",),
    "rfi": ("rfi", "alpha"),
    "opcr": ("opcr",),
    "opc": ("opc",),
    "slope": ("slope",),
    "arc": ("arc",),
    "relief_index": ("rfi_boyer",),
    "footprint": ("area2d",),
}


def table_columns(metrics=("ariadne",)) -> tuple[str, ...]:
    """The columns of the summary printed for `metrics`."""
    if tuple(metrics) == ("ariadne",):
        return TABLE_COLUMNS
    columns = ["file"]
    for metric in metrics:  # a metric's main value: its first column unless named above
        columns += METRIC_SUMMARY.get(metric, METRIC_KEYS[metric][:1])
    if ORIENTED.intersection(metrics):
        columns.append("orientation")
    return (*columns, "seconds", "status", "error")


#: Columns aligned to the left (the others hold numbers and are aligned right).
_LEFT = ("file", "status", "error", "orientation")


def _format(value) -> str:
    if value is None:
        return ""
    if isinstance(value, float):
        return f"{value:.6g}"
    return str(value)


def _aligned(cells: list[list[str]], left: list[bool]) -> str:
    """Rows of text cells (header first) as aligned lines; `left` per column, else right."""
    widths = [max(len(row[i]) for row in cells) for i in range(len(left))]
    lines = []
    for row in cells:
        line = "  ".join(
            cell.ljust(w) if is_left else cell.rjust(w)
            for cell, w, is_left in zip(row, widths, left, strict=True)
        )
        lines.append(line.rstrip() + "\n")
    return "".join(lines)


def plain_table(records: list[dict], columns: tuple[str, ...] = TABLE_COLUMNS) -> str:
    """The table as aligned plain text, one line per row (header first)."""
    cells = [list(columns)] + [[_format(r.get(c)) for c in columns] for r in records]
    return _aligned(cells, [name in _LEFT for name in columns])


def _common_directory(files: list[str]) -> str:
    """The deepest directory holding every file ("" if none, or only the root)."""
    directories = [os.path.dirname(os.path.abspath(f)) for f in files]
    try:
        common = os.path.commonpath(directories) if directories else ""
    except ValueError:  # different drives (Windows)
        return ""
    return "" if common == os.path.dirname(common) else common


def rich_table(records: list[dict], shown: tuple[str, ...] = TABLE_COLUMNS):
    """The table as a :class:`rich.table.Table`, for people at a terminal.

    Files are shown relative to the directory that holds them all, named in
    the title; the error column only when a file failed; numbers are never
    cut short (they fold on a narrow terminal).
    """
    from rich import box
    from rich.table import Table
    from rich.text import Text

    files = [str(r.get("file") or "") for r in records]
    common = _common_directory(files)
    columns = [c for c in shown if c != "error" or any(r.get("error") for r in records)]
    table = Table(
        box=box.SIMPLE_HEAVY,
        show_edge=False,
        header_style="bold",
        title=f"in {common}{os.sep}" if common else None,
        title_justify="left",
        title_style="dim",
        collapse_padding=True,
    )
    for name in columns:
        header = name
        if name in _LEFT:
            table.add_column(header, overflow="fold", min_width=12 if name == "file" else None)
        else:  # numbers are never cut or folded: the other columns give way
            width = max([len(_format(r.get(name))) for r in records] + [1])
            table.add_column(header, justify="right", no_wrap=True, min_width=width)
    for record, file in zip(records, files, strict=True):
        cells = []
        for name in columns:
            if name == "file":
                shown = os.path.relpath(os.path.abspath(file), common) if common else file
                cells.append(Text(shown))
            elif name == "status":
                ok = record.get("status") == "ok"
                cells.append(Text(_format(record.get(name)), style="green" if ok else "bold red"))
            else:
                cells.append(Text(_format(record.get(name))))
        table.add_row(*cells)
    return table


def print_table(
    records: list[dict], *, file=None, console=None, columns: tuple[str, ...] = TABLE_COLUMNS
) -> None:
    """Print the table of `records` on `file` (default stdout).

    A rich table when `console` is given (drawn on it) or `file` is a
    terminal; aligned plain text otherwise.  A terminal too narrow for the
    numbers gets lines as wide as they need (the terminal wraps them), never
    cut numbers.
    """
    stream = sys.stdout if file is None else file
    if console is None and is_terminal(stream):
        from rich.console import Console

        console = Console(file=stream)
    if console is None:
        stream.write(plain_table(records, columns))
        stream.flush()
        return
    from rich.console import Console
    from rich.measure import Measurement

    table = rich_table(records, columns)
    needed = Measurement.get(console, console.options.update_width(1_000_000), table).minimum
    if needed > console.width:
        console = Console(
            file=console.file,
            width=needed,
            force_terminal=console.is_terminal,
            color_system=console.color_system,
        )
    console.print(table)


def print_layout(records: list[dict], columns) -> None:
    """The table in another column layout (``--columns``), aligned, on stdout."""
    cells = [list(columns.header)] + [
        [columns.text(value) for value in row] for row in columns.rows(records)
    ]
    sys.stdout.write(_aligned(cells, [column.kind == "text" for column in columns.columns]))
