"""The collection: the table's rows, their files, their groups and the columns held.

A table is read with :func:`dentopo.formats.read_table` (any layout it knows:
dentopo's, the published signDNE CLI's, molaR_Batch's) or given as records.
A row's ``file`` is looked for as written (relative to the working directory,
as the ``dentopo`` command records it), then relative to the table's
directory, and a bare base name (molaR's layout keeps only those) anywhere
below the table's directory where it is found once.

Groups come from the folders: each file's folder relative to the files' common
root (files directly in the root form one group named after the root), or
from a CSV with columns ``file`` and ``group``.
"""

from __future__ import annotations

import csv
import math
import os
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field

from ..formats import PROTOCOL_KEY, read_table
from ..prepare import Protocol, ProtocolError, load_protocol, named_protocols
from ._columns import ARIADNE_SETTINGS, ORIENTATION, ReportColumn, orientation_mark, report_columns

#: The group of the specimens a groups file does not name.
UNGROUPED = "(ungrouped)"


@dataclass
class Specimen:
    """One row of the table.

    Attributes
    ----------
    index : int
        Its position in the table.
    file : str
        The ``file`` cell, as written.
    path : str or None
        Where the file was found, or None.
    name : str
        The file's base name.
    group : str
        The group it belongs to.
    record : dict
        The row (typed values, a private copy).
    problem : str or None
        Why it has no picture (file not found, unreadable, ariaDNE failed), or None.
    """

    index: int
    file: str
    path: str | None
    name: str
    group: str = ""
    record: dict = field(default_factory=dict, repr=False)
    problem: str | None = None

    @property
    def status(self) -> str:
        """The row's status (``ok``, ``partial``, ``error``)."""
        return str(self.record.get("status") or "ok")

    @property
    def error(self) -> str:
        """The row's error cell (empty when there is none)."""
        return str(self.record.get("error") or "")

    @property
    def warnings(self) -> str:
        """The row's warnings cell (empty when there is none)."""
        return str(self.record.get("warnings") or "")

    @property
    def orientation(self) -> str:
        """The row's ``orientation`` cell (empty when there is none)."""
        return str(self.record.get(ORIENTATION) or "")

    @property
    def mark(self) -> str | None:
        """``"closed"`` or ``"turned"`` from its orientation cell, or None."""
        return orientation_mark(self.record.get(ORIENTATION))

    @property
    def protocol_label(self) -> str | None:
        """The row's ``protocol`` cell (the label of the protocol it was prepared with), or None."""
        value = self.record.get(PROTOCOL_KEY)
        if value is None or (isinstance(value, float) and math.isnan(value)) or value == "":
            return None
        return str(value)

    def ariadne_options(self) -> dict:
        """The keyword arguments of :func:`dentopo.ariaDNE` this row was computed with."""
        options = {}
        for key, default in ARIADNE_SETTINGS.items():
            value = self.record.get(key)
            if value is None or (isinstance(value, float) and math.isnan(value)):
                value = default
            options[key] = value
        if options["distance_type"] == "precomputed":  # no matrix to hand: the straight line
            options["distance_type"] = "euclidean"
        return options


def read_records(table) -> tuple[list[dict], str | None]:
    """The rows of `table` (a path, or records) and the table's directory (None for records)."""
    if isinstance(table, (str, os.PathLike)):
        path = os.fspath(table)
        if not os.path.isfile(path):
            raise ValueError(f"no results table at {path!r}")
        return read_table(path), os.path.dirname(os.path.abspath(path))
    if isinstance(table, Mapping) or not isinstance(table, Iterable):
        raise TypeError(
            f"table must be a path to a results table or a sequence of records (dicts); "
            f"got {type(table).__name__}"
        )
    records = [dict(row) for row in table]
    for row in records:
        if not isinstance(row.get("file"), str):
            raise ValueError("every record needs a 'file' (str), as read_table returns them")
    return records, None


#: At most this many entries of the table's directory tree are looked through for base names.
SEARCH_LIMIT = 200_000


def locate(file: str, table_dir: str | None) -> str | None:
    """Where `file` is: as written, else relative to the table's directory; None if nowhere."""
    candidates = [file]
    if table_dir is not None and not os.path.isabs(file):
        candidates.append(os.path.join(table_dir, file))
    for candidate in candidates:
        if os.path.isfile(candidate):
            return candidate
    return None


def files_below(root: str, names: set[str]) -> dict[str, str]:
    """``base name -> path`` of the files called one of `names` under `root`, found once only.

    For tables that keep only base names (molaR's layout) beside the folders of
    the meshes.  A name found twice is left out (which file is meant cannot be
    told); the walk stops after :data:`SEARCH_LIMIT` entries.
    """
    found: dict[str, str | None] = {}
    seen = 0
    for folder, directories, files in os.walk(root):
        directories[:] = sorted(d for d in directories if not d.startswith("."))
        seen += len(directories) + len(files)
        for name in files:
            if name in names:
                found[name] = None if name in found else os.path.join(folder, name)
        if seen > SEARCH_LIMIT:
            break
    return {name: path for name, path in found.items() if path is not None}


def folder_groups(files: Sequence[str]) -> list[str]:
    """Each file's folder relative to the files' common root; the root's name for files in it."""
    if not files:
        return []
    folders = [os.path.dirname(os.path.abspath(f)) for f in files]
    root = os.path.commonpath(folders)
    root_name = os.path.basename(root) or "(root)"
    groups = []
    for folder in folders:
        relative = os.path.relpath(folder, root)
        groups.append(root_name if relative == os.curdir else relative.replace(os.sep, "/"))
    return groups


def read_groups(path: str | os.PathLike) -> dict[str, str]:
    """``file -> group`` from a CSV with columns ``file`` and ``group`` (any case, any order).

    Raises
    ------
    ValueError
        If the file cannot be read as such a CSV.
    """
    path = os.fspath(path)
    try:
        with open(path, newline="", encoding="utf-8-sig") as stream:
            reader = csv.reader(stream)
            header = [cell.strip().lower() for cell in next(reader, [])]
            if "file" not in header or "group" not in header:
                raise ValueError(f"groups file {path!r} needs columns 'file' and 'group'")
            at_file, at_group = header.index("file"), header.index("group")
            mapping = {}
            for line, row in enumerate(reader, start=2):
                if not any(cell.strip() for cell in row):
                    continue
                if len(row) <= max(at_file, at_group):
                    raise ValueError(f"groups file {path!r}, line {line}: too few cells")
                mapping[row[at_file].strip()] = row[at_group].strip() or UNGROUPED
    except OSError as exc:
        raise ValueError(f"cannot read groups file {path!r}: {exc.strerror or exc}") from exc
    except (UnicodeDecodeError, csv.Error) as exc:
        raise ValueError(f"groups file {path!r} is not a CSV: {exc}") from exc
    return mapping


def match_groups(
    specimens: Sequence[Specimen], mapping: Mapping[str, str], base: str | None
) -> list[str]:
    """The group of each specimen from ``file -> group``, by path first, then by base name.

    A mapping's file matches a specimen when both name the same file (paths
    relative to `base`, the groups file's directory, compared absolute), or
    else when its base name is the specimen's base name.  Specimens matched by
    neither are :data:`UNGROUPED`.
    """
    by_path, by_name = {}, {}
    for file, group in mapping.items():
        if base is not None and not os.path.isabs(file):
            by_path[os.path.normpath(os.path.join(base, file))] = group
        by_path[os.path.normpath(os.path.abspath(file))] = group
        by_name.setdefault(os.path.basename(file), group)
    groups = []
    for specimen in specimens:
        keys = {os.path.normpath(os.path.abspath(specimen.file))}
        if specimen.path is not None:
            keys.add(os.path.normpath(os.path.abspath(specimen.path)))
        found = next((by_path[k] for k in keys if k in by_path), None)
        if found is None:
            found = by_name.get(specimen.name, UNGROUPED)
        groups.append(found)
    return groups


def _short_digest(label: str) -> str:
    return label.rsplit(" ", 1)[-1]


def row_protocols(specimens: Sequence[Specimen], prepare=None) -> dict[str, Protocol]:
    """The protocol of each ``protocol`` label the rows carry, by label.

    A row holds only its protocol's label (``"name digest12"``), so the
    protocol itself comes from `prepare` (a :class:`dentopo.Protocol`, a
    shipped name or a TOML file, or a list of them when rows were prepared
    with several) or from the shipped protocols, matched by digest; the
    label's name is not trusted, the digest is.

    Raises
    ------
    ValueError
        If some label's protocol is neither `prepare` nor shipped (naming the
        label), or `prepare` is the protocol of no row.
    """
    if prepare is None:
        given = []
    elif isinstance(prepare, (list, tuple)):
        given = [load_protocol(item) for item in prepare]
    else:
        given = [load_protocol(prepare)]
    labels = sorted({s.protocol_label for s in specimens if s.protocol_label is not None})
    for protocol in given:
        if not any(_short_digest(x) == protocol.digest[:12] for x in labels):
            held = ", ".join(repr(x) for x in labels) or "none (measured as read)"
            raise ProtocolError(
                f"the protocol given ({protocol.label!r}) is not the one the table's rows were "
                f"prepared with: theirs are {held}"
            )
    candidates = given + list(named_protocols().values())
    by_digest = {}
    for candidate in candidates:
        by_digest.setdefault(candidate.digest[:12], candidate)
    found = {}
    for label in labels:
        protocol = by_digest.get(_short_digest(label))
        if protocol is None:
            raise ProtocolError(
                f"rows of the table were prepared with protocol {label!r}, which is not a "
                "shipped one: give its file (prepare=, --prepare PROTOCOL.toml) to picture "
                "the prepared crowns"
            )
        found[label] = protocol
    return found


def collect(table, *, groups=None) -> tuple[list[Specimen], list[ReportColumn]]:
    """The specimens of `table` with their groups, and the columns the page shows.

    The columns (:func:`._columns.report_columns`) are every column of the
    table but its settings and the row's own (file, status ...): its metrics by
    family, any column the package does not know, the mesh counts.

    Parameters
    ----------
    table : str, path-like or sequence of dict
        A results table, or its records.
    groups : str, path-like or mapping, optional
        A CSV of ``file,group`` or a ``{file: group}`` mapping; by default the
        groups are the folders.
    """
    records, table_dir = read_records(table)
    specimens = []
    for index, record in enumerate(records):
        file = str(record.get("file") or "")
        path = locate(file, table_dir) if file else None
        specimen = Specimen(index, file, path, os.path.basename(file) or f"row {index + 1}")
        specimen.record = record
        if path is None and specimen.status != "error":
            specimen.problem = "file not found" if file else "no file named in the table"
        specimens.append(specimen)
    lost = {s.file for s in specimens if s.path is None and s.file and s.file == s.name}
    if lost and table_dir is not None:  # base names only: look below the table's folder
        below = files_below(table_dir, lost)
        for specimen in specimens:
            if specimen.path is None and specimen.file in below:
                specimen.path = below[specimen.file]
                if specimen.problem == "file not found":
                    specimen.problem = None
    if groups is None:
        names = folder_groups([s.path or s.file for s in specimens])
    elif isinstance(groups, Mapping):
        names = match_groups(specimens, {str(k): str(v) for k, v in groups.items()}, None)
    elif isinstance(groups, (str, os.PathLike)):
        base = os.path.dirname(os.path.abspath(os.fspath(groups)))
        names = match_groups(specimens, read_groups(groups), base)
    else:
        raise TypeError(
            f"groups must be a CSV path or a mapping of file to group; got {type(groups).__name__}"
        )
    for specimen, name in zip(specimens, names, strict=True):
        specimen.group = name
    return specimens, report_columns(records)
