"""The main command's output table: checked, locked, journalled, and written at the end.

With ``-o FILE`` a run

1. checks that FILE can be written, before any mesh is computed (exit 2 if not);
2. locks FILE (``.FILE.lock`` beside it, see :class:`dentopo.formats.OutputLock`):
   a second run on the same table says so and waits for the first to finish;
3. adds back the rows of an earlier run on FILE that was killed outright (its
   journal ``FILE.partial.jsonl`` is still there), so that they are never lost;
4. appends each finished row to the journal as it finishes (flushed to the disk);
5. at the end, or when interrupted, writes FILE atomically from the previous
   rows and the new ones, then removes the journal and the lock.

If the table cannot be written (a full disk), FILE is left as it was and the
journal keeps the finished rows for ``--resume``.  ``-o -`` (stdout) and the
table printed on the terminal have no journal and no lock.
"""

from __future__ import annotations

import os
import stat
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

from ..batch import merge_records
from ..formats import (
    Journal,
    Layout,
    OutputLock,
    check_writable,
    journal_path,
    read_journal,
    read_table,
    write_table,
)
from ._progress import counted, say


def writable_problem(path: str, what: str) -> str | None:
    """Why a table cannot be written at `path` (``what`` names the option), or None."""
    try:
        check_writable(path)
    except NotADirectoryError as exc:
        return f"cannot write {what} {path!r}: {exc.filename!r} is not a directory"
    except FileNotFoundError as exc:
        return (
            f"cannot write {what} {path!r}: the directory {exc.filename!r} does not exist "
            "(create it first)"
        )
    except IsADirectoryError:
        return f"{what} {path!r} is a directory; give a file"
    except OSError as exc:
        reason = exc.strerror or str(exc)
        where = exc.filename if exc.filename is not None else os.path.dirname(path)
        return f"cannot write {what} {path!r}: {reason} ({where})"
    return None


def directory_problem(path: str, what: str) -> str | None:
    """Why files cannot be written into the directory `path` (created later if missing)."""
    existing = os.path.abspath(path)
    while not os.path.exists(existing):
        existing = os.path.dirname(existing)
    if not os.path.isdir(existing):
        return f"{what} {path!r}: {existing!r} is not a directory"
    return writable_problem(os.path.join(existing, "probe"), what)


@dataclass(frozen=True)
class Planned:
    """One file (or folder) a run will write, for :func:`output_problem`.

    Attributes
    ----------
    what : str
        How messages name it: ``"--report"``, ``"the per-vertex file of 'a.ply'"``.
    path : str
        Where it goes, as given.
    suffixes : tuple of str
        The suffixes its writer writes (lower case, with the dot); empty: any.
    kind : str
        What is written there (``"an HTML page"``), for the suffix message.
    check : bool
        Check that it can be written (a file; a folder with `folder`).
    folder : bool
        A folder the run writes files into (``--per-vertex``).
    """

    what: str
    path: str
    suffixes: tuple[str, ...] = ()
    kind: str = ""
    check: bool = False
    folder: bool = False


def _or(items) -> str:
    items = list(items)
    return items[0] if len(items) == 1 else ", ".join(items[:-1]) + " or " + items[-1]


class _Identities:
    """Paths resolved (symbolic links, ``..``, the working directory) and their inodes."""

    def __init__(self):
        self._folders: dict[str, str] = {}

    def keys(self, path: str) -> tuple[str, tuple[int, int] | None]:
        """The resolved path of `path`, and its (device, inode) if it exists (hard links)."""
        absolute = os.path.abspath(path)
        folder, name = os.path.split(absolute)
        if folder not in self._folders:  # once per folder: a batch has many files in few folders
            self._folders[folder] = os.path.realpath(folder)
        resolved = os.path.join(self._folders[folder], name) if name else self._folders[folder]
        try:
            status = os.lstat(resolved)
        except OSError:
            return resolved, None
        if stat.S_ISLNK(status.st_mode):
            resolved = os.path.realpath(resolved)
            try:
                status = os.stat(resolved)
            except OSError:
                return resolved, None
        return resolved, (status.st_dev, status.st_ino)


def output_problem(
    outputs: Sequence[Planned], inputs: Iterable[tuple[str, str]] = ()
) -> str | None:
    """Why the outputs of a run must not be written, as one line naming the path; or None.

    Every output of one run is checked here, before anything is computed, in
    this order: an output that is one of the `inputs` (``(what, path)``: the
    meshes, a table read) would replace it; two outputs that are one file would
    replace each other (``-o pv/a.dentopo.csv --per-vertex pv``); an output
    whose suffix its writer does not write; an output that cannot be written.
    Paths are compared resolved (symbolic links, relative paths) and by inode
    (hard links).
    """
    identities = _Identities()
    sources: dict[object, tuple[str, str]] = {}
    for what, path in inputs:
        resolved, inode = identities.keys(path)
        sources.setdefault(resolved, (what, path))
        if inode is not None:
            sources.setdefault(inode, (what, path))
    seen: dict[object, Planned] = {}
    for output in outputs:
        resolved, inode = identities.keys(output.path)
        for key in (resolved, inode):
            if key is None:
                continue
            if key in sources:
                what, path = sources[key]
                same = "" if path == output.path else f" {path!r}"
                return (
                    f"{output.what} {output.path!r} is {what}{same}: writing it would replace "
                    "it; choose another file"
                )
            if key in seen and seen[key] is not output:
                first = seen[key]
                return (
                    f"{output.what} {output.path!r} is also {first.what}"
                    + ("" if first.path == output.path else f" {first.path!r}")
                    + ": one would replace the other; choose another file"
                )
        for key in (resolved, inode):
            if key is not None:
                seen.setdefault(key, output)
    for output in outputs:
        ext = os.path.splitext(output.path)[1].lower()
        if output.suffixes and ext not in output.suffixes:
            kind = f" ({output.kind})" if output.kind else ""
            return f"{output.what} {output.path!r} must end in {_or(output.suffixes)}{kind}"
    for output in outputs:
        if output.check:
            check = directory_problem if output.folder else writable_problem
            problem = check(output.path, output.what)
            if problem:
                return problem
    return None


class TableOutput:
    """The table file of one run (see the module docstring).

    Parameters
    ----------
    path : str
        The table.
    columns : Layout
        Its layout.
    quiet : bool
        No messages but problems.
    """

    def __init__(self, path: str, columns: Layout, *, quiet: bool):
        self.path = path
        self.columns = columns
        self.quiet = quiet
        self.journal_path = journal_path(path)
        self.journal: Journal | None = None
        self._lock = OutputLock(path, on_wait=self._waiting)

    def _waiting(self, pid: int | None) -> None:
        who = f" (pid {pid})" if pid else ""
        say(f"{self.path} is being written by another dentopo run{who}: waiting for it to finish")

    def lock(self) -> None:
        """Take the table's lock, waiting for another run to finish with it."""
        self._lock.acquire()

    def recover(self) -> None:
        """Add the rows of an earlier run that was killed (its journal) to the table.

        Safe to interrupt: the table is replaced atomically and the journal
        removed only afterwards (merging again gives the same table).

        Raises
        ------
        NotAJournalError
            If the file at the journal's path is not a dentopo journal (left as it is).
        OSError, ValueError
            If the table or the journal cannot be read, or the table written.
        """
        if not os.path.lexists(self.journal_path):  # a link planted there is refused
            return
        rows, skipped = read_journal(self.journal_path)
        if rows:
            previous = read_table(self.path) if os.path.exists(self.path) else []
            write_table(self.path, merge_records(previous, rows), columns=self.columns)
            if not self.quiet:
                say(
                    f"added {counted(len(rows), 'row')} of an earlier run that was stopped "
                    f"before it finished (kept in {self.journal_path}) to {self.path}"
                )
        if skipped:
            say(
                f"{self.journal_path}: {counted(skipped, 'unreadable line')} skipped (cut short "
                "by a kill)"
            )
        os.unlink(self.journal_path)

    def start_journal(self) -> None:
        """Create the journal that keeps each finished row.

        Raises
        ------
        OSError
            If it cannot be created.
        """
        self.journal = Journal(self.journal_path)

    def record(self, record: dict) -> None:
        """Keep one finished row in the journal (raises OSError on a full disk)."""
        if self.journal is not None:
            self.journal.append(record)

    def write(self, records: list[dict]) -> int:
        """Write the table atomically, then drop the journal; the number of rows written.

        Raises
        ------
        OSError
            If the table cannot be written; it is then left as it was, and the
            journal keeps the rows.
        """
        written = write_table(self.path, records, columns=self.columns)
        self.discard_journal()
        return written

    def discard_journal(self) -> None:
        """Remove the journal: its rows are in the table, or are not wanted there."""
        if self.journal is not None:
            self.journal.remove()
            self.journal = None

    def close(self) -> None:
        """Close the journal (kept if still there) and release the lock."""
        if self.journal is not None:
            self.journal.close()
        self._lock.release()
