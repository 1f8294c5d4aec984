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

Numbers keep full double precision (JSON holds the shortest text that reads
back to the same float; ``NaN`` and ``Infinity`` as Python's json writes them).
"""

from __future__ import annotations

import json
import os

from ._tables import DENTOPO

#: Appended to an output table's name to name its journal.
JOURNAL_SUFFIX = ".partial.jsonl"


def journal_path(output: str | os.PathLike) -> str:
    """The journal of the table `output`: ``<output>.partial.jsonl`` beside it."""
    return os.fspath(output) + JOURNAL_SUFFIX


def _plain(value):
    """numpy scalars as Python numbers (json does not know them)."""
    if hasattr(value, "item"):
        return value.item()
    raise TypeError(f"cannot write {type(value).__name__} to a journal")


class Journal:
    """Finished rows, appended one JSON line at a time and flushed to the disk.

    Opening an existing journal appends to it (after ending a line that a
    kill cut short, so that the next row starts on a line of its own).

    Parameters
    ----------
    path : str or path-like
        The journal's file (see :func:`journal_path`).
    sync : bool, default True
        ``fsync`` after each row, so that a row survives the machine going
        down too; without it, a row survives the process being killed.
    """

    def __init__(self, path: str | os.PathLike, *, sync: bool = True):
        self.path = os.fspath(path)
        self.sync = sync
        self._fd = os.open(self.path, os.O_RDWR | os.O_CREAT | os.O_APPEND, 0o666)
        try:
            if os.lseek(self._fd, 0, os.SEEK_END):
                os.lseek(self._fd, -1, os.SEEK_END)
                if os.read(self._fd, 1) != b"\n":  # writes go to the end (O_APPEND)
                    self._write(b"\n")
        except BaseException:
            os.close(self._fd)
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
        line = json.dumps(record, ensure_ascii=False, default=_plain) + "\n"
        self._write(line.encode("utf-8"))

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
    """
    records, skipped = [], 0
    with open(path, encoding="utf-8", errors="replace") as stream:
        for line in stream:
            if not line.strip():
                continue
            try:
                raw = json.loads(line)
                if not isinstance(raw, dict) or not raw.get("file") or not raw.get("status"):
                    raise ValueError("not a row")
                [record] = DENTOPO.records([raw])
            except (ValueError, TypeError):
                skipped += 1
                continue
            records.append(record)
    return records, skipped
