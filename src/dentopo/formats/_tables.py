"""Result tables: file formats, and writing, reading and converting a table.

A table is written in a *layout* (which columns, under which names, in which
order; :data:`~._layouts.LAYOUTS`, in ``_layouts``) and a *format* (how the
cells are stored; one :class:`TableFormat` per file suffix in :data:`FORMATS`,
here).  Adding a format or a layout is one entry in these registries;
:func:`write_table` and :func:`read_table` find them there.

Every file is written atomically (a temporary file in the same directory,
renamed over the target), so that a run that fails or is interrupted never
leaves a half-written table and never clobbers an existing one.  Every format
reads back with its types: numbers keep full double precision (the shortest
text that reads back to the same float in CSV and TSV, real numbers in JSON
and Excel), missing values are empty cells (``null`` in JSON).

Text that a spreadsheet would run (OWASP's "CSV injection"): in CSV and TSV,
a text cell (a file name, an error message, any text column) that begins with
``=``, ``+``, ``-``, ``@``, a tab or a carriage return is written with an
apostrophe in front (``'=HYPERLINK(...).ply``), so that Excel and LibreOffice
show it as text instead of evaluating it.  A text cell that begins with an
apostrophe gets one more, so the rule can be undone without ambiguity: in a
CSV or TSV written here, a data cell that begins with an apostrophe had one
added, and :func:`read_table` (and so ``--resume`` and the report) removes
exactly one; every name reads back as it was.  Numbers and the header are
never changed.  Other readers see the apostrophe: the R and MATLAB bridges
remove it as :func:`read_table` does; ``pandas.read_csv`` keeps it.  Excel
workbooks store text as text cells (never formulas), and JSON, which no
spreadsheet evaluates, the raw text: neither is changed.  A file name that is
not valid UTF-8 (held by Python with surrogates, as :func:`os.fsdecode` gives
it) is written as its bytes in CSV and TSV, as ``\\udcXX`` escapes in JSON
(both read back exactly) and with U+FFFD in its place in Excel.
"""

from __future__ import annotations

import csv
import json
import math
import os
import re
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, replace

from .._optional import EXCEL, Feature
from ._atomic import atomic_write
from ._layouts import LAYOUTS, Layout, layout

# --- formats ---------------------------------------------------------------------------------

#: ``write(stream, header, rows, text)``: `rows` hold typed cells, `text` turns a cell into text.
Writer = Callable[[object, Sequence[str], list[list], Callable[[object], str]], None]
#: ``read(path) -> (header, rows)``: rows are dicts keyed by header, cells as stored.
Reader = Callable[[str], tuple[list[str], list[dict]]]


@dataclass(frozen=True)
class TableFormat:
    """How a table is stored in a file with one suffix.

    Attributes
    ----------
    name : str
        ``"csv"``, ``"tsv"``, ``"json"``, ``"xlsx"``.
    suffix : str
        The file suffix, with the dot, lower case.
    binary : bool
        Whether the file is written in binary mode (else UTF-8 text).
    write : callable
        ``write(stream, header, rows, text)``.
    read : callable
        ``read(path) -> (header, rows)``.
    description : str
        One line for the documentation.
    requires : Feature, optional
        The optional dependency the format needs (see :meth:`check_available`).
    """

    name: str
    suffix: str
    binary: bool
    write: Writer
    read: Reader
    description: str = ""
    requires: Feature | None = None

    def check_available(self) -> None:
        """Raise :class:`~dentopo._optional.MissingExtraError` if its dependency is missing."""
        if self.requires is not None:
            self.requires.require()


#: How a text cell may begin that a spreadsheet would take for a formula (OWASP), and the
#: apostrophe that neutralises them (so a cell beginning with one gets another).
_FORMULA_STARTS = ("=", "+", "-", "@", "\t", "\r", "'")


def _neutralised(cell: str) -> str:
    """A text cell as written to CSV and TSV: an apostrophe first if it could run as a formula."""
    return "'" + cell if cell.startswith(_FORMULA_STARTS) else cell


def _restored(cell):
    """A CSV or TSV cell as it was before :func:`_neutralised`."""
    return cell[1:] if isinstance(cell, str) and cell.startswith("'") else cell


def _delimited_writer(delimiter: str) -> Writer:
    def write(stream, header, rows, text):
        writer = csv.writer(stream, delimiter=delimiter, lineterminator="\n")
        # csv quotes a cell holding a line terminator only: with "\n" a bare "\r" would end
        # the row when read back; a row with one is written by a writer that quotes it
        crlf = csv.writer(stream, delimiter=delimiter, lineterminator="\r\n")
        writer.writerow(header)
        for row in rows:
            line = [_neutralised(cell) if isinstance(cell, str) else text(cell) for cell in row]
            (crlf if any("\r" in cell for cell in line) else writer).writerow(line)

    return write


def _delimited_reader(delimiter: str) -> Reader:
    def read(path):
        with open(path, encoding="utf-8", errors="surrogateescape", newline="") as stream:
            reader = csv.DictReader(stream, delimiter=delimiter)
            rows = [{name: _restored(cell) for name, cell in row.items()} for row in reader]
            return list(reader.fieldnames or ()), rows

    return read


def _json_value(value):
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


#: Lone surrogates: how Python holds the bytes of a file name that is not UTF-8.
_SURROGATE = re.compile("[\ud800-\udfff]")


def _write_json(stream, header, rows, text) -> None:
    data = [
        {name: _json_value(cell) for name, cell in zip(header, row, strict=True)} for row in rows
    ]
    text = json.dumps(data, indent=1, ensure_ascii=False, allow_nan=False)
    # the raw text (no escaping for spreadsheets), in UTF-8; a name that is not UTF-8 keeps
    # its bytes as JSON's \\udcXX escapes (surrogates occur only inside strings)
    stream.write(_SURROGATE.sub(lambda m: f"\\u{ord(m.group()):04x}", text))
    stream.write("\n")


def _read_json(path):
    with open(path, encoding="utf-8") as stream:
        try:
            raw = json.load(stream)
        except json.JSONDecodeError as exc:
            raise ValueError(f"{path!r} is not valid JSON: {exc}") from exc
    if not isinstance(raw, list) or not all(isinstance(r, dict) for r in raw):
        raise ValueError(f"{path!r} does not hold a list of result rows")
    header = list(dict.fromkeys(key for row in raw for key in row))
    return header, raw


def _write_xlsx(stream, header, rows, text) -> None:
    openpyxl = EXCEL.require()
    from openpyxl.cell.cell import ILLEGAL_CHARACTERS_RE, WriteOnlyCell

    workbook = openpyxl.Workbook(write_only=True)
    sheet = workbook.create_sheet("results")

    def cell(value):
        if isinstance(value, float) and math.isfinite(value):
            # openpyxl writes numbers as "%.16g", which loses the last digit of some doubles:
            # give it the shortest exact text (repr) and mark the cell numeric.
            item = WriteOnlyCell(sheet, value=repr(value))
            item.data_type = "n"
            return item
        if isinstance(value, float):  # Excel has no inf or nan: keep them as text
            return WriteOnlyCell(sheet, value=repr(value))
        if isinstance(value, str):
            value = _SURROGATE.sub("\ufffd", ILLEGAL_CHARACTERS_RE.sub("\ufffd", value))
            item = WriteOnlyCell(sheet, value=value)
            item.data_type = "s"  # a text starting with "=" is text, not a formula
            return item
        return WriteOnlyCell(sheet, value=value)

    sheet.append([cell(name) for name in header])
    for row in rows:
        sheet.append([cell(value) for value in row])
    workbook.save(stream)


def _read_xlsx(path):
    openpyxl = EXCEL.require()
    try:
        workbook = openpyxl.load_workbook(path, read_only=True, data_only=True)
    except Exception as exc:  # zipfile, XML and openpyxl errors: not a workbook we can read
        raise ValueError(f"{path!r} is not an Excel workbook: {exc}") from exc
    try:
        lines = list(workbook.worksheets[0].iter_rows(values_only=True))
    finally:
        workbook.close()
    if not lines:
        return [], []
    names = [None if name is None else str(name) for name in lines[0]]
    rows = [
        {name: value for name, value in zip(names, line, strict=False) if name is not None}
        for line in lines[1:]
        if any(value is not None for value in line)
    ]
    return [name for name in names if name is not None], rows


#: Table formats by file suffix (lower case, with the dot).
FORMATS: dict[str, TableFormat] = {
    fmt.suffix: fmt
    for fmt in (
        TableFormat(
            "csv", ".csv", False, _delimited_writer(","), _delimited_reader(","), "comma-separated"
        ),
        TableFormat(
            "tsv", ".tsv", False, _delimited_writer("\t"), _delimited_reader("\t"), "tab-separated"
        ),
        TableFormat("json", ".json", False, _write_json, _read_json, "a list of objects"),
        TableFormat("xlsx", ".xlsx", True, _write_xlsx, _read_xlsx, "an Excel workbook", EXCEL),
    )
}
_BY_NAME = {fmt.name: fmt for fmt in FORMATS.values()}


def table_format(path: str | os.PathLike) -> TableFormat:
    """The :class:`TableFormat` for the suffix of `path` (case-insensitive).

    Raises
    ------
    ValueError
        For a suffix not in :data:`FORMATS`.
    """
    ext = os.path.splitext(os.fspath(path))[1].lower()
    if ext not in FORMATS:
        raise ValueError(
            f"cannot tell the output format of {os.fspath(path)!r}: "
            f"use one of the extensions {', '.join(FORMATS)}"
        )
    return FORMATS[ext]


def output_format(path: str | os.PathLike) -> str:
    """The name of the format of `path` from its suffix: ``"csv"``, ``"tsv"``, ``"json"``, ...

    Raises
    ------
    ValueError
        For any other extension.
    """
    return table_format(path).name


def write_table(
    path, records: Iterable[dict], *, columns: str | Layout = "dentopo", format: str | None = None
) -> int:
    """Write result records as a table, atomically; the format comes from the suffix.

    Parameters
    ----------
    path : str, path-like or text stream
        A file whose suffix picks the format (:data:`FORMATS`: ``.csv``,
        ``.tsv``, ``.json``, ``.xlsx``), or an open text stream (such as
        ``sys.stdout``), written as CSV unless `format` says otherwise.
    records : iterable of dict
        Rows with (at least) the keys in :data:`COLUMNS`; not modified.
    columns : str or Layout, default "dentopo"
        The layout (:data:`LAYOUTS`): ``"dentopo"``, every column of
        :data:`COLUMNS`; ``"signdne"``, the published signDNE CLI's columns
        (``File, DNE, positive_DNE, ...``, numbers with 16 decimals in text
        formats, failed rows left out).
    format : str, optional
        ``"csv"``, ``"tsv"``, ``"json"`` or ``"xlsx"``, overriding the suffix.

    Returns
    -------
    int
        The number of rows written (failed rows are left out by layouts
        without a status column).

    Raises
    ------
    ValueError
        For an unknown suffix, format or layout, or a binary format (xlsx)
        asked of a text stream.
    dentopo.MissingExtraError
        For ``.xlsx`` without openpyxl (``pip install 'dentopo[excel]'``, in a clone
        ``pip install '.[excel]'``).
    """
    chosen = layout(columns)
    stream = path if hasattr(path, "write") else None
    if format is not None:
        if format not in _BY_NAME:
            raise ValueError(f"unknown table format {format!r}: use one of {', '.join(_BY_NAME)}")
        fmt = _BY_NAME[format]
    else:
        fmt = _BY_NAME["csv"] if stream is not None else table_format(path)
    rows = chosen.rows(records)

    def write(target):
        fmt.write(target, chosen.header, rows, chosen.text)

    if stream is not None:
        if fmt.binary:
            raise ValueError(f"{fmt.name} tables are written to files, not to a text stream")
        write(stream)
    else:
        fmt.check_available()  # a missing extra fails before the temporary file is made
        atomic_write(path, write, binary=fmt.binary)
    return len(rows)


def _detect(header: Sequence[str], path: str) -> Layout:
    names = set(header)
    # the most particular first: a doolkit table has dentopo's required columns too
    for candidate in sorted(LAYOUTS.values(), key=lambda c: -len(c.required)):
        if names.issuperset(candidate.required) and names.isdisjoint(candidate.excluded):
            return candidate
    wanted = " or ".join(f"({', '.join(c.required)})" for c in LAYOUTS.values())
    raise ValueError(f"{path!r} is not a dentopo results table (it needs the columns {wanted})")


def read_table(path: str | os.PathLike, *, columns: str | Layout | None = None) -> list[dict]:
    """Read a table written by :func:`write_table` back into typed records.

    Parameters
    ----------
    path : str or path-like
        A ``.csv``, ``.tsv``, ``.json`` or ``.xlsx`` table.
    columns : str or Layout, optional
        The layout; by default recognised from the header (a table of the
        published signDNE CLI reads too).

    Returns
    -------
    list of dict
        One record per row with every key of :data:`COLUMNS` (None where the
        layout has no such column); text columns as str, ``vertices`` and
        ``faces`` as int, the other numbers as float.  Rows of a layout
        without a status column have ``status="ok"``.

    Raises
    ------
    ValueError
        If the file is not such a table (wrong format, missing columns or a
        malformed value).
    """
    path = os.fspath(path)
    fmt = table_format(path)
    header, raw = fmt.read(path)
    if not header and not raw:  # an empty file: a table with no rows
        return []
    chosen = _detect(header, path) if columns is None else layout(columns)
    missing = [name for name in chosen.required if name not in header]
    if missing:
        raise ValueError(f"{path!r} is not a {chosen.name} results table (no {', '.join(missing)})")
    try:
        return chosen.records(raw, header)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{path!r} has a malformed value: {exc}") from exc


def convert_table(source: str | os.PathLike, target: str | os.PathLike) -> int:
    """Write the table `source` again as `target` (its format from its suffix), atomically.

    The same layout and the same columns, in the same order (a ``.csv`` table
    as ``.tsv`` or ``.xlsx``, say); the rows as :func:`read_table` reads them.

    Returns
    -------
    int
        The number of rows written.

    Raises
    ------
    ValueError
        If `source` is not a results table, or `target`'s suffix is not a format.
    """
    source = os.fspath(source)
    header, raw = table_format(source).read(source)
    if not header and not raw:
        raise ValueError(f"{source!r} is an empty table")
    chosen = _detect(header, source)
    if chosen.parse is not None:
        chosen = replace(chosen, columns=chosen.parse(header))
    records = chosen.records(raw, header)
    return write_table(target, records, columns=chosen)
