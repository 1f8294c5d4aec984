"""A journal of finished rows beside an output table, so that a killed run loses none.

While a batch runs, each finished row is appended to ``NAME.partial.jsonl``
beside the table ``NAME`` as one line of JSON, written and ``fsync``-ed at
once (about 0.2 ms a row on a local disk: nothing next to computing a mesh).
The table itself is only written at the end, atomically, from the previous
table and these rows; then the journal is removed.  A run killed outright
(SIGKILL, the machine going down) leaves the journal behind, and the next run
on the same table adds its rows back first (see ``dentopo.cli``), so that only
the rows in flight are lost.  Reading a journal skips a line cut short by such
a kill.

A journal says what it is: its first line is :data:`JOURNAL_HEADER`
(``{"journal": "dentopo", "version": 1}``).  A journal of dentopo 0.x before
that line (rows from the first line on) still reads.  Anything else at the
journal's path is not taken for a killed run's rows: a symbolic link, a
device, a FIFO, a file of other text or JSON (a first line that is neither the
header nor a row) raise :class:`NotAJournalError` naming the path, and the
file is left exactly as it was, never read as rows, removed or appended to.
Files are opened without following links (``O_NOFOLLOW``), and a new journal
is created with ``O_EXCL``.  An empty file (a run killed the instant it
created its journal) holds no rows.

Numbers keep full double precision (JSON holds the shortest text that reads
back to the same float; ``NaN`` and ``Infinity`` as Python's json writes them).
Text is stored as it is (no spreadsheet reads a journal), escaped to ASCII,
so that any file name, a name that is not valid UTF-8 included, reads back
exactly.
"""

from __future__ import annotations

import errno
import json
import os
import stat

from ._layouts import DENTOPO

#: Appended to an output table's name to name its journal.
JOURNAL_SUFFIX = ".partial.jsonl"
#: The first line of every journal: what the file is, and the version of its rows.
JOURNAL_HEADER = {"journal": "dentopo", "version": 1}
_HEADER_LINE = (json.dumps(JOURNAL_HEADER) + "\n").encode("ascii")
#: Never follow a link, never wait on a FIFO (0 where the system lacks them).
_SAFE = getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0)
_FIRST_LINE = 1 << 16  # a first line longer than this is not a journal's


class NotAJournalError(ValueError):
    """The file at a journal's path is not a dentopo journal (it is left untouched)."""

    def __init__(self, path: str, what: str):
        self.path = path
        super().__init__(
            f"{path!r} is {what}, not a dentopo journal: it was left as it is; move it away "
            "(or delete it) and run again (dentopo keeps the rows of a run there until the "
            "table is written)"
        )


def journal_path(output: str | os.PathLike) -> str:
    """The journal of the table `output`: ``<output>.partial.jsonl`` beside it."""
    return os.fspath(output) + JOURNAL_SUFFIX


def _plain(value):
    """numpy scalars as Python numbers (json does not know them)."""
    if hasattr(value, "item"):
        return value.item()
    raise TypeError(f"cannot write {type(value).__name__} to a journal")


def _is_row(raw) -> bool:
    return isinstance(raw, dict) and bool(raw.get("file")) and bool(raw.get("status"))


def _identify(path: str, head: bytes) -> None:
    """Raise NotAJournalError unless `head` (the file's first bytes) begins a journal."""
    if not head or _HEADER_LINE.startswith(head):  # empty, or killed while writing the header
        return
    line = head.split(b"\n", 1)[0]
    try:
        raw = json.loads(line.decode("utf-8"))
    except (UnicodeDecodeError, ValueError):
        raw = None
    if isinstance(raw, dict) and raw.get("journal") == "dentopo":
        version = raw.get("version")
        if version != JOURNAL_HEADER["version"]:
            raise NotAJournalError(path, f"a journal of version {version!r} (a newer dentopo?)")
        return
    if _is_row(raw):  # a journal of an earlier dentopo, without the header
        return
    if len(head) >= _FIRST_LINE and b"\n" not in head:
        raise NotAJournalError(path, "a file whose first line is too long for a journal")
    what = "a file of JSON" if raw is not None else "a file of other content"
    raise NotAJournalError(path, f"{what} (its first line is neither a journal's nor a row)")


def _open_existing(path: str, flags: int) -> int:
    """Open the file at `path` if it is a journal (see the module docstring)."""
    try:
        fd = os.open(path, flags | _SAFE)
    except OSError as exc:
        if exc.errno == errno.ELOOP or os.path.islink(path):
            raise NotAJournalError(path, "a symbolic link") from None
        raise
    try:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode):
            raise NotAJournalError(path, "not a regular file")
        _identify(path, os.pread(fd, _FIRST_LINE, 0))
    except BaseException:
        os.close(fd)
        raise
    return fd


class Journal:
    """Finished rows, appended one JSON line at a time and flushed to the disk.

    A new journal is created with its header line; opening an existing
    journal appends to it (after ending a line that a kill cut short, so that
    the next row starts on a line of its own).

    Parameters
    ----------
    path : str or path-like
        The journal's file (see :func:`journal_path`).
    sync : bool, default True
        ``fsync`` after each row, so that a row survives the machine going
        down too; without it, a row survives the process being killed.

    Raises
    ------
    NotAJournalError
        If something that is not a dentopo journal is at `path` (left as it is).
    OSError
        If the journal cannot be created or opened.
    """

    def __init__(self, path: str | os.PathLike, *, sync: bool = True):
        self.path = os.fspath(path)
        self.sync = sync
        self._fd = None
        while self._fd is None:
            try:
                self._fd = os.open(
                    self.path, os.O_RDWR | os.O_CREAT | os.O_EXCL | os.O_APPEND | _SAFE, 0o666
                )
            except FileExistsError:
                try:
                    self._fd = _open_existing(self.path, os.O_RDWR | os.O_APPEND)
                except FileNotFoundError:  # removed meanwhile: create it
                    continue
        try:
            size = os.lseek(self._fd, 0, os.SEEK_END)
            if size == 0:
                self._write(_HEADER_LINE)
            else:
                os.lseek(self._fd, -1, os.SEEK_END)
                if os.read(self._fd, 1) != b"\n":  # writes go to the end (O_APPEND)
                    self._write(b"\n")
        except BaseException:
            os.close(self._fd)
            self._fd = None
            raise

    def _write(self, data: bytes) -> None:
        view = memoryview(data)
        while view:
            view = view[os.write(self._fd, view) :]
        if self.sync:
            os.fsync(self._fd)

    def append(self, record: dict) -> None:
        """Append one row (a record with the keys of :data:`dentopo.COLUMNS`).

        Raises
        ------
        OSError
            If it cannot be written (a full disk, say).
        """
        line = json.dumps(record, ensure_ascii=True, default=_plain) + "\n"
        self._write(line.encode("ascii"))

    def close(self) -> None:
        """Close the file (safe to call more than once)."""
        if self._fd is not None:
            os.close(self._fd)
            self._fd = None

    def remove(self) -> None:
        """Close and delete the journal (its rows are in the table now)."""
        self.close()
        try:
            os.unlink(self.path)
        except FileNotFoundError:
            pass

    def __enter__(self) -> Journal:
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def read_journal(path: str | os.PathLike) -> tuple[list[dict], int]:
    """The rows of a journal, and how many lines could not be read.

    Returns
    -------
    records : list of dict
        Typed records with every key of :data:`dentopo.COLUMNS`, in the order
        they were written (a later row for the same file wins when merged).
    skipped : int
        Lines that are not a row (a line cut short when a run was killed).

    Raises
    ------
    NotAJournalError
        If the file is not a dentopo journal (see the module docstring).
    OSError
        If it cannot be read.
    """
    path = os.fspath(path)
    fd = _open_existing(path, os.O_RDONLY)
    records, skipped = [], 0
    with open(fd, encoding="utf-8", errors="replace") as stream:
        for number, line in enumerate(stream):
            if not line.strip():
                continue
            try:
                raw = json.loads(line)
                if number == 0 and isinstance(raw, dict) and raw.get("journal") == "dentopo":
                    continue  # the header
                if not _is_row(raw):
                    raise ValueError("not a row")
                [record] = DENTOPO.records([raw])
            except (ValueError, TypeError):
                skipped += 1
                continue
            records.append(record)
    return records, skipped
