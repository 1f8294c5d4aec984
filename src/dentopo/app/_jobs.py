"""The app's work, done by the ``dentopo`` command itself, in child processes.

A run from the page *is* the command: :class:`Job` starts ``python -m dentopo
...`` (the same interpreter) with the options the page chose, in the folder, and
writes into the output folder.  So the table is the command's, byte for byte,
with everything the command does for a batch: worker processes, the journal of
finished rows, atomic writes, the output lock, ``--resume``, and Ctrl-C/SIGTERM
writing the rows done.  A cancel is a SIGTERM; a server that dies leaves its
child to finish and write the table (it runs in a session of its own, so a
Ctrl-C meant for the server does not reach it half-way: the server stops it
with SIGTERM and waits).  The page follows the child's progress through the
journal (each finished row, as the command keeps it) and its messages on stderr,
among which the line saying that numba is compiling the kernels (kept as
:attr:`Job.compiling` while it holds; see :mod:`._progress`).

A job runs its commands one after another (a batch whose meshes have their own
protocols is one command per protocol, all into the same table) and stops at
the first that fails to run (exit 2: a usage error).
"""

from __future__ import annotations

import collections
import os
import re
import shlex
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

#: Lines of the children's messages kept for the page.
LOG_LINES = 400
#: Seconds a child is given to write its rows after SIGTERM, before it is killed.
STOP_SECONDS = 60.0
#: How the command's line begins while numba compiles its kernels (a fresh install's first run).
COMPILING = "compiling dentopo's kernels"
#: The command's plain progress line of a finished file (``[3/10] a.ply: ok``).
FINISHED_LINE = re.compile(r"\[\d+/\d+\] ")


def dentopo_command(arguments: Sequence[str]) -> list[str]:
    """The command line that runs ``dentopo ARGUMENTS`` with this interpreter."""
    return [sys.executable, "-m", "dentopo", *arguments]


def shown(arguments: Sequence[str], folder: str) -> str:
    """The command as a user would type it: ``cd FOLDER && dentopo ...`` (shell-quoted)."""
    return f"cd {shlex.quote(folder)} && dentopo {shlex.join(arguments)}"


@dataclass
class Job:
    """Commands (each a list of ``dentopo`` arguments) run one after another in `folder`.

    ``after(index, code)`` is called as each command ends (its index and exit code).
    """

    commands: list[list[str]]
    folder: str
    after: Callable[[int, int], None] | None = None
    state: str = "idle"  # running, cancelling, done, cancelled, failed
    codes: list[int] = field(default_factory=list)
    log: collections.deque = field(default_factory=lambda: collections.deque(maxlen=LOG_LINES))
    started: float | None = None
    ended: float | None = None

    def __post_init__(self):
        #: While a command compiles numba's kernels: (which notice, its text, since when).
        self.compiling: tuple[int, str, float] | None = None
        self._notices = 0
        self._process: subprocess.Popen | None = None
        self._cancelled = False
        self._lock = threading.Lock()
        self._thread: threading.Thread | None = None

    @property
    def command(self) -> str:
        """The commands as a user would type them, one per line."""
        return "\n".join(shown(c, self.folder) for c in self.commands)

    @property
    def exit_code(self) -> int | None:
        """The largest exit code so far (0 all right, 1 some file failed, 2, 130), or None."""
        return max(self.codes) if self.codes else None

    def start(self) -> Job:
        self.state = "running"
        self.started = time.time()
        self._thread = threading.Thread(target=self._run, name="dentopo-app-job", daemon=True)
        self._thread.start()
        return self

    def running(self) -> bool:
        return self.state in ("running", "cancelling")

    def wait(self, timeout: float | None = None) -> None:
        if self._thread is not None:
            self._thread.join(timeout)

    def cancel(self) -> None:
        """Stop: the running command gets SIGTERM (it writes the rows done), no other starts."""
        with self._lock:
            self._cancelled = True
            if self.running():
                self.state = "cancelling"
            process = self._process
        if process is not None and process.poll() is None:
            try:
                process.send_signal(signal.SIGTERM)
            except ProcessLookupError:
                pass

    def stop(self, timeout: float = STOP_SECONDS) -> None:
        """Cancel and wait for the child to write its rows (killed if it takes too long)."""
        self.cancel()
        process = self._process
        if process is not None:
            try:
                process.wait(timeout)
            except subprocess.TimeoutExpired:
                process.kill()
        self.wait(5)

    def _note(self, line: str) -> None:
        """Follow the command's compile notice: from its line until compiling is said to be
        over or a file finishes (a line of its own about compiling, or a progress line)."""
        text = line.removeprefix("dentopo: ")
        if text.startswith(COMPILING):
            self._notices += 1
            self.compiling = (self._notices, text, time.time())
        elif self.compiling is not None and (
            text.startswith("compil") or FINISHED_LINE.match(text)
        ):
            self.compiling = None

    def _run(self) -> None:
        environment = {**os.environ, "PYTHONUNBUFFERED": "1"}
        for index, arguments in enumerate(self.commands):
            with self._lock:
                if self._cancelled:
                    break
                try:
                    self._process = subprocess.Popen(
                        dentopo_command(arguments),
                        cwd=self.folder,
                        stdin=subprocess.DEVNULL,
                        stdout=subprocess.DEVNULL,
                        stderr=subprocess.PIPE,
                        text=True,
                        errors="replace",
                        env=environment,
                        start_new_session=True,
                    )
                except OSError as exc:
                    self.log.append(f"cannot start dentopo: {exc}")
                    self.codes.append(2)
                    break
            with self._process.stderr:
                for line in self._process.stderr:
                    self.log.append(line.rstrip("\n"))
                    self._note(line.strip())
            code = self._process.wait()
            self.compiling = None
            self.codes.append(code)
            if self.after is not None:
                try:
                    self.after(index, code)
                except Exception as exc:  # the job's state must still be set
                    self.log.append(f"{type(exc).__name__}: {exc}")
            if code not in (0, 1):
                break
        self.ended = time.time()
        with self._lock:
            if self._cancelled:
                self.state = "cancelled"
            elif self.codes and max(self.codes) <= 1 and len(self.codes) == len(self.commands):
                self.state = "done"
            else:
                self.state = "failed"
