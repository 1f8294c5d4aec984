"""Interrupts (Ctrl-C, SIGTERM) that stop a batch at a safe point.

:class:`InterruptGuard` replaces the handlers of the signals it guards with one
that raises :class:`Interrupted` (a KeyboardInterrupt) at once, unless the
guard is *held* (a critical section such as appending a finished row; the
signal is then raised by :meth:`InterruptGuard.check` as it ends).  SIGTERM (a
scheduler's time limit) thereby stops a run like Ctrl-C does.

A Ctrl-C during a compiled kernel needs no care here: the kernels write into
arrays of the caller and return nothing or a number, so the KeyboardInterrupt
is raised cleanly when the kernel returns (numba boxes a returned array with a
little Python code, where the interrupt used to be raised, leaving a NULL in
the result: a ``SystemError`` or a segmentation fault).  The exact ariaDNE
kernel runs in slices of a few tenths of a second, so it is raised promptly.

Raising at once is prompt (a Ctrl-C while a large file is read stops the
reading), but third-party code that catches every exception can swallow it:
trimesh's loader turns it into "string is not a file".  A signal that arrives
in a finalizer (a ``__del__``, where an exception is dropped) is sent again a
moment later (see :mod:`dentopo._signals`).  The guard remembers
what it raised (:attr:`InterruptGuard.raised`), so that the runner can tell
that a mesh was interrupted although it came back, and raise again instead of
keeping a row that cannot be trusted.
"""

from __future__ import annotations

import contextlib
import signal
import threading
from collections.abc import Iterator

from .._signals import deliver_later, in_finalizer


class Interrupted(KeyboardInterrupt):
    """Raised for a guarded signal (SIGINT or SIGTERM) at a safe point.

    A ``KeyboardInterrupt``, so that code that stops on Ctrl-C stops on it too.

    Attributes
    ----------
    signum : int
        The signal that interrupted.
    """

    def __init__(self, signum: int):
        super().__init__(signal.Signals(signum).name)
        self.signum = signum

    @property
    def name(self) -> str:
        """The signal's name, e.g. ``"SIGINT"``."""
        return signal.Signals(self.signum).name


class InterruptGuard:
    """Handlers for `signums` that raise :class:`Interrupted` only where it is safe.

    Use :func:`guard_interrupts` to install one.  Only the main thread can
    install signal handlers; elsewhere the guard installs nothing and never
    raises (Python delivers signals to the main thread anyway).
    """

    def __init__(self, signums: tuple[int, ...]):
        self.signums = tuple(signums)
        self.pending: int | None = None  # the first guarded signal not yet raised
        self.raised: int | None = None  # the last signal raised (see check)
        self.active = False
        self._held = 0
        self._later = 0  # signals deliver_later will send again
        self._previous: dict[int, object] = {}

    def _handler(self, signum, frame) -> None:
        if self._later:  # sent again by deliver_later (or a second Ctrl-C at that moment)
            self._later -= 1
            if self.pending is None:
                return  # raised meanwhile by check() at a safe point
        elif self.pending is None:
            self.pending = signum
        if self._held:
            return  # raised by check() as the critical section ends
        if in_finalizer(frame):  # raised in a __del__, it would be dropped: a moment later
            self._later += 1
            deliver_later(signum)
            return
        self.check()

    def install(self) -> None:
        if threading.current_thread() is not threading.main_thread():
            return
        for signum in self.signums:
            previous = signal.getsignal(signum)
            if previous is signal.SIG_IGN:  # e.g. started in the background with nohup
                continue
            self._previous[signum] = previous
            signal.signal(signum, self._handler)
        self.active = True

    def uninstall(self) -> None:
        for signum, previous in self._previous.items():
            signal.signal(signum, previous if previous is not None else signal.SIG_DFL)
        self._previous.clear()
        self.active = False

    def check(self) -> None:
        """Raise :class:`Interrupted` if a guarded signal arrived (and the guard is not held).

        The signal raised is remembered in :attr:`raised`: code that catches
        every exception (trimesh's loader does) may swallow the interrupt, and
        the caller can then tell (reset it to None first) and raise it again.
        """
        if self.pending is not None and not self._held:
            signum, self.pending = self.pending, None
            self.raised = signum
            raise Interrupted(signum)

    @contextlib.contextmanager
    def held(self) -> Iterator[None]:
        """A critical section: signals arriving now are raised when it ends (by :meth:`check`)."""
        self._held += 1
        try:
            yield
        finally:
            self._held -= 1


_CURRENT: list[InterruptGuard] = []


def current_guard() -> InterruptGuard | None:
    """The innermost installed guard, or None."""
    return _CURRENT[-1] if _CURRENT else None


@contextlib.contextmanager
def guard_interrupts(*signums: int) -> Iterator[InterruptGuard]:
    """Guard `signums` (default SIGINT) for the duration of the block.

    A guarded signal raises :class:`Interrupted` at once, unless the guard is
    held; such a signal is raised by the next :meth:`InterruptGuard.check`, or
    as the block ends.  If a guard covering
    `signums` is installed already, it is reused (so that the command line's
    guard, which also covers SIGTERM, stays in charge).
    """
    signums = signums or (signal.SIGINT,)
    outer = current_guard()
    if outer is not None and outer.active and set(signums) <= set(outer.signums):
        yield outer
        return
    guard = InterruptGuard(signums)
    guard.install()
    _CURRENT.append(guard)
    try:
        yield guard
    finally:
        _CURRENT.remove(guard)
        guard.uninstall()
    guard.check()  # a signal that came where it could not be raised (not after an exception)


#: Signals that worker processes ignore: the parent stops them itself.
WORKER_IGNORED = (signal.SIGINT, signal.SIGTERM)


@contextlib.contextmanager
def interrupts_ignored() -> Iterator[None]:
    """Start processes in this block with SIGINT and SIGTERM ignored from their first instruction.

    Worker processes are started inside it, so that they ignore the Ctrl-C a
    terminal sends to the whole process group, and a scheduler's SIGTERM, from
    their very start (even while importing): the parent stops them itself.
    The signals are blocked meanwhile (a child inherits both the blocked mask
    and the ignored dispositions), so that one arriving here is delivered to
    this process afterwards instead of being lost.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    masks = hasattr(signal, "pthread_sigmask")  # not on Windows
    blocked = signal.pthread_sigmask(signal.SIG_BLOCK, WORKER_IGNORED) if masks else None
    previous = {s: signal.signal(s, signal.SIG_IGN) for s in WORKER_IGNORED}
    try:
        yield
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler if handler is not None else signal.SIG_DFL)
        if masks:
            signal.pthread_sigmask(signal.SIG_SETMASK, blocked)


def ignore_interrupts_in_worker() -> None:
    """In a worker process: ignore SIGINT and SIGTERM (and unblock them, see above)."""
    for signum in WORKER_IGNORED:
        signal.signal(signum, signal.SIG_IGN)
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_UNBLOCK, WORKER_IGNORED)
