"""Progress of a batch on stderr: a live bar on a terminal, plain lines otherwise.

On a terminal (stderr is a TTY) a `rich` progress bar shows the files done and
the total, the rate (meshes per second), the time left and the current file
with its phase (prepare, kernel, bending, sign, totals).  Otherwise each file
gives one plain line, ``dentopo: [3/10] path: ok (0.12 s)`` (``partial`` and
``error`` rows too, with their reason: every row is counted), and a mesh that
takes longer than :data:`SLOW_MESH_SECONDS` reports its phases; no escape
codes are written, and rich is not even imported.  Errors and warnings about a
file are always written, also with ``--quiet``: one line per file and warning,
the long ones short, their explanation once at the end of the run
(:mod:`._briefs`).  Nothing goes to stdout, which holds only results.
"""

from __future__ import annotations

import os
import sys
import time

from ._briefs import Briefing
from ._streams import write_stderr

PROG = "dentopo"

#: In plain-line progress, phases within a mesh are reported once it has taken this long.
SLOW_MESH_SECONDS = 2.0


def is_terminal(stream) -> bool:
    """Whether `stream` is an open terminal."""
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):  # no isatty, or closed
        return False


def counted(count: int, word: str, plural: str | None = None) -> str:
    """``1 row``, ``2 rows``: `count` and `word`, plural unless one (`plural`: if not ``+s``)."""
    return f"{count} {word if count == 1 else plural or word + 's'}"


def say(message: str) -> None:
    """One plain line ``dentopo: message`` on stderr (dropped if stderr cannot be written)."""
    write_stderr(f"{PROG}: {message}\n")


def _columns():
    """The bar's columns: spinner, bar, done/total, rate, time left, current file."""
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        ProgressColumn,
        SpinnerColumn,
        TextColumn,
    )
    from rich.table import Column
    from rich.text import Text

    class RateColumn(ProgressColumn):
        """Meshes per second since the start (steadier than a moving window)."""

        def render(self, task) -> Text:
            elapsed = task.elapsed or 0.0
            if not task.completed or elapsed <= 0:
                return Text("-- meshes/s", style="progress.data.speed")
            return Text(f"{task.completed / elapsed:.3g} meshes/s", style="progress.data.speed")

    class LeftColumn(ProgressColumn):
        """Time left at the rate so far."""

        def render(self, task) -> Text:
            elapsed = task.elapsed or 0.0
            if not task.completed or elapsed <= 0:
                return Text("-:--:-- left", style="progress.remaining")
            seconds = round((task.total - task.completed) * elapsed / task.completed)
            hours, rest = divmod(seconds, 3600)
            text = f"{hours}:{rest // 60:02d}:{rest % 60:02d} left"
            return Text(text, style="progress.remaining")

    return (
        SpinnerColumn(),
        BarColumn(bar_width=24),
        MofNCompleteColumn(),
        RateColumn(),
        LeftColumn(),
        TextColumn(
            "{task.fields[current]}",
            markup=False,  # file names may hold [brackets]
            table_column=Column(no_wrap=True, overflow="ellipsis", ratio=1),
        ),
    )


class Progress:
    """Progress of `total` files on stderr; see the module docstring.

    Parameters
    ----------
    total : int
        Number of files to compute.
    quiet : bool
        Only errors and warnings, no progress.
    console : rich.console.Console, optional
        Draw on this console as on a terminal (tests); default: a console on
        stderr when stderr is a terminal, plain lines otherwise.
    briefing : Briefing, optional
        Writes the long warnings and errors short, and keeps their explanations
        for :meth:`explain` (default: a new one).
    """

    def __init__(self, total: int, *, quiet: bool, console=None, briefing=None):
        self.total = total
        self.quiet = quiet
        self.briefing = Briefing() if briefing is None else briefing
        self.done = 0
        self.mesh_start = time.perf_counter()
        self._phase_file: str | None = None
        self._console = console
        if console is None and is_terminal(sys.stderr):
            from rich.console import Console

            self._console = Console(stderr=True)
        self._bar = None
        if self._console is not None and not quiet and total:
            from rich.progress import Progress as RichProgress

            self._bar = RichProgress(
                *_columns(),
                console=self._console,
                redirect_stdout=False,  # stdout holds results only
                redirect_stderr=False,
            )
            self._task = self._bar.add_task("", total=total, current="starting")
            self._bar.start()  # at once: the first mesh may take a while

    @property
    def tty(self) -> bool:
        """Whether progress is drawn on a terminal."""
        return self._console is not None

    def message(self, text: str, *, style: str | None = None) -> None:
        """A line about one file (error, warning), always shown, above the bar."""
        if self._console is None:
            say(text)
        else:
            self._console.print(
                f"{PROG}: {text}", style=style, markup=False, highlight=False, soft_wrap=True
            )

    def warning(self, file: str, text: str) -> None:
        """A warning about `file`, one line (a long one short: :mod:`._briefs`), always shown."""
        self.message(f"{file}: warning: {self.briefing(file, text)}")

    def update(self, record: dict) -> None:
        """One file is done: `record` is its table row.

        Every row is counted, whatever its status: a plain line
        ``[3/10] path: partial (0.12 s): reason`` for a row that is not ``ok``
        (always shown; ``path: partial: reason`` without progress), ``[3/10]
        path: ok (0.12 s)`` otherwise.
        """
        self.done += 1
        seconds = record["seconds"]
        timing = "" if seconds is None else f" ({seconds:.2f} s)"
        file, status = record["file"], record["status"]
        counter = f"[{self.done}/{self.total}] "
        shown = self._bar is None and self._console is None and not self.quiet
        if status != "ok":  # "error", or "partial": some metric failed
            reason = self.briefing(file, str(record["error"]))
            lead = counter if shown else ""
            self.message(f"{lead}{file}: {status}{timing if lead else ''}: {reason}", style="red")
        elif shown:
            say(f"{counter}{file}: ok{timing}")
        if self._bar is not None:
            current = f"{os.path.basename(file)}: {status}{timing}"
            self._bar.update(self._task, completed=self.done, current=current)

    def explain(self) -> None:
        """The explanation of each long warning met, once (after the last file's line)."""
        for line in self.briefing.explanations():
            say(line)
        self.briefing = Briefing(self.briefing.briefs)  # said: not again

    def phase(self, file: str, name: str) -> None:
        """A phase of one mesh starts: shown on the bar, or as a line once a mesh is slow."""
        now = time.perf_counter()
        if file != self._phase_file:  # the first phase of a mesh
            self._phase_file = file
            self.mesh_start = now
        elapsed = now - self.mesh_start
        if self._bar is not None:
            self._bar.update(
                self._task, current=f"{os.path.basename(file)}: {name} ({elapsed:.1f} s)"
            )
        elif self._console is None and not self.quiet and elapsed >= SLOW_MESH_SECONDS:
            say(f"{file}: {name} ({elapsed:.1f} s)")

    def close(self) -> None:
        """Stop the bar (left on screen as it ended); safe to call more than once."""
        if self._bar is not None:
            self._bar.stop()
            self._bar = None
