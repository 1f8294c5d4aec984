"""A run's progress as the page shows it: each file's row, a count that never goes back, and
the command's compile wait.

The rows come from two files the command writes: its journal (each row as it
finishes) while a command runs, then its table when it ends.  Counted from
whichever could be read at each look, the count went back: between the command
writing its table (the journal removed) and the app reading that table, while a
journal was being rewritten or could not be read, and when the journal of an
earlier, killed run was folded into the table as the command started (those
rows counted, then gone).  Here a file's row, once seen, stays (a later one
replaces it), so the count only grows.  Rows the command will not compute again
(``--resume``: reusable rows of the table, as :func:`dentopo.batch.resumable_files`
finds them for each command's settings) are counted from the start, not when
their command ends; the rows of a journal left by an earlier run are not this
run's and are not counted from the journal.  Each state carries the run's
number and a serial, so that the page can drop an answer older than one it has
drawn (two requests can cross).

A fresh install's first run compiles numba's kernels before its first row
(tens of seconds): the command says so in one line on stderr
(``compiling dentopo's kernels for this machine, once: about 30 s``),
which :class:`dentopo.app._jobs.Job` keeps; the state shows it, with the
seconds so far, until a row finishes, a line says compiling is over, or the
command ends.
"""

from __future__ import annotations

import itertools
import os
import threading
import time

#: Runs started in this process (each state names its run).
_RUNS = itertools.count(1)


def _absolute(root: str, rows: list[dict]) -> list[dict]:
    """Copies of `rows` whose ``file`` is absolute (the command's names are the folder's)."""
    return [{**r, "file": os.path.join(root, r["file"])} for r in rows if r.get("file")]


def resumed_rows(root: str, groups: dict, rows: list[dict], settings_of) -> dict[str, dict]:
    """The rows the command will reuse, not compute (its ``--resume``), by file.

    `groups` maps each command's protocol file (or None) to its files, `rows` are the
    table's (and an earlier run's journal's), and ``settings_of(protocol)`` gives a
    command's batch settings (``ValueError`` if they cannot be made: none is reused).
    """
    from ..batch import resumable_files

    by_file = {r.get("file"): r for r in rows if r.get("file")}
    absolute = _absolute(root, list(by_file.values()))
    found = {}
    for protocol, files in groups.items():
        try:
            settings = settings_of(protocol)
        except (OSError, ValueError, TypeError):
            continue
        reusable = resumable_files(absolute, settings)
        for file in files:
            if os.path.join(root, file) in reusable and file in by_file:
                found[file] = by_file[file]
    return found


class RunProgress:
    """The rows of a run's `files` seen so far (`resumed` counted from the start).

    `stale` holds the rows of a journal that was there before the run (an earlier run's,
    killed): seen again as they were, they are not this run's.
    """

    def __init__(self, files: list[str], resumed: dict | None = None, stale: list | None = None):
        self.number = next(_RUNS)
        self.files = list(files)
        self._wanted = set(self.files)
        self.rows: dict[str, dict] = {f: r for f, r in (resumed or {}).items() if f in self._wanted}
        self._stale = {r.get("file"): r for r in stale or ()}
        self._lock = threading.Lock()
        self._serial = 0
        self._compile: tuple | None = None  # (the notice's number, the count when it came)

    def see(self, rows, *, final: bool = False) -> None:
        """Rows read from the journal, or (`final`) from the table a command wrote."""
        with self._lock:
            for row in rows:
                file = row.get("file")
                if file not in self._wanted:
                    continue
                if not final and self._stale.get(file) == row:
                    continue
                self.rows[file] = row

    def state(self, job) -> dict:
        """What the page shows of the run `job` (its files, the count, the compile wait)."""
        with self._lock:
            self._serial += 1
            rows = dict(self.rows)
            serial = self._serial
            compiling = self._compiling(job, len(rows))
        files = {}
        for relative in self.files:
            row = rows.get(relative)
            if row is None:
                files[relative] = {"status": "waiting", "error": None, "warnings": None}
                files[relative]["seconds"] = None
            else:
                files[relative] = {k: row.get(k) for k in ("status", "error", "warnings")}
                files[relative]["seconds"] = row.get("seconds")
        return {
            "run": self.number,
            "serial": serial,
            "state": job.state,
            "total": len(self.files),
            "done": len(rows),
            "compiling": compiling,
            "files": files,
            "log": list(job.log),
            "exit_code": job.exit_code,
            "command": job.command,
        }

    def _compiling(self, job, done: int) -> dict | None:
        notice = job.compiling if job.running() else None
        if notice is None:
            return None
        number, text, since = notice
        if self._compile is None or self._compile[0] != number:
            self._compile = (number, done)
        elif done > self._compile[1]:
            return None  # a row has finished since: the kernels it needed are compiled
        return {"message": text, "seconds": round(max(0.0, time.time() - since))}
