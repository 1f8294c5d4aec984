"""The ``dentopo`` command's entry point: dispatch to a subcommand or the main command.

``dentopo NAME ARGS...`` runs the subcommand ``NAME`` (only the first argument is
matched, exactly: a mesh file called like a subcommand is given as ``./NAME``);
anything else is the main command (:mod:`dentopo.cli._compute`).
"""

from __future__ import annotations

import contextlib
import importlib
import signal
import sys
import threading
from collections.abc import Callable, Iterator

from .._optional import MissingExtraError
from .._signals import interrupt
from .._version import __version__
from ._progress import PROG, say
from ._streams import (
    StreamError,
    forget_stderr_failure,
    guarded_stdout,
    silence,
    stderr_failed,
)

# ``dentopo NAME ARGS...`` runs ``SUBCOMMANDS[NAME](ARGS)`` and exits with the integer it
# returns.  A value is a callable ``f(argv: list[str]) -> int`` or, better, a lazy
# ``"module:function"`` string, imported only when that subcommand runs (so that the plain
# command stays fast).
SUBCOMMANDS: dict[str, str | Callable[[list[str]], int]] = {
    "app": "dentopo.cli._app:app_main",
    "info": "dentopo.cli._info:info_main",
    "prepare": "dentopo.cli._prepare:prepare_main",
    "report": "dentopo.cli._report:report_main",
    "robustness": "dentopo.cli._study:robustness_main",
    "sweep": "dentopo.cli._study:sweep_main",
    "warmup": "dentopo.cli._warmup:warmup_main",
}


def _run_subcommand(name: str, argv: list[str]) -> int:
    target = SUBCOMMANDS[name]
    if isinstance(target, str):
        module, _, function = target.partition(":")
        target = getattr(importlib.import_module(module), function)
    return int(target(argv))


def main(argv: list[str] | None = None) -> int:
    """Run the ``dentopo`` command with `argv` (default ``sys.argv[1:]``); the exit code.

    A failed write to stdout ends the command with exit 1 and one line on
    stderr (a closed pipe, ``| head``, quietly with 0); a failed write to
    stderr is dropped and makes the exit code at least 1 (see ``_streams``).
    """
    argv = list(sys.argv[1:] if argv is None else argv)
    forget_stderr_failure()
    with guarded_stdout(), _interrupt_outside_finalizers():
        try:
            code = _main(argv)
        except StreamError as exc:
            if not exc.broken_pipe:
                say(str(exc))
            code = 0 if exc.broken_pipe else 1
    if stderr_failed():
        code = max(code, 1)
    return code


@contextlib.contextmanager
def _interrupt_outside_finalizers() -> Iterator[None]:
    """Ctrl-C raises ``KeyboardInterrupt`` as usual, but not inside a ``__del__`` (see `interrupt`).

    Only where Python's own handler is installed (not where SIGINT is ignored,
    as under ``nohup``, or handled by the caller) and in the main thread.
    """
    if (
        threading.current_thread() is not threading.main_thread()
        or signal.getsignal(signal.SIGINT) is not signal.default_int_handler
    ):
        yield
        return
    signal.signal(signal.SIGINT, interrupt)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, signal.default_int_handler)


def _main(argv: list[str]) -> int:
    if argv == ["--version"]:  # as the main command's parser says it, without loading it
        print(f"{PROG} {__version__}")
        sys.stdout.flush()
        return 0
    try:
        if argv and argv[0] in SUBCOMMANDS:
            code = _run_subcommand(argv[0], argv[1:])
        else:
            from ._compute import compute_main  # numba, scipy, trimesh: only when there is work

            code = compute_main(argv, tuple(SUBCOMMANDS))
        sys.stdout.flush()  # a full stdout is found now, not in Python's flush at exit
        return code
    except MissingExtraError as exc:  # wherever it is found: one line naming the extra
        say(str(exc))
        return 2
    except KeyboardInterrupt:  # wherever it was not caught already: one line, exit 130
        say("interrupted")
        return 130


def run() -> None:
    """Console-script entry point."""
    try:
        code = main()
    except BrokenPipeError:  # not through sys.stdout (e.g. a library printing directly)
        code = 0
    for stream in (sys.stdout, sys.stderr):  # Python's flush at exit must not fail again
        try:
            stream.flush()
        except (OSError, ValueError):
            silence(stream)
    sys.exit(code)
