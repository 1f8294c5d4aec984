"""Ctrl-C that lands in a finalizer: sent again a moment later instead of being dropped.

Python runs a signal's handler in whatever Python code runs when the signal
arrives.  If that is a ``__del__`` method (the garbage collector runs them at
any moment; llvmlite's objects free their LLVM resources in one), the
``KeyboardInterrupt`` raised there is printed as "Exception ignored" and
dropped, and the computation runs on as if no Ctrl-C had come.

:func:`interrupt` (the command line's SIGINT handler) and the batch runner's
guard therefore ask :func:`in_finalizer` first and, inside a finalizer, send
the signal again :data:`REDELIVERY_SECONDS` later (:func:`deliver_later`),
to be raised once the finalizer has returned.

May import: nothing of dentopo (every subpackage may import it); no numba, so
that the command's entry point stays light.
"""

from __future__ import annotations

import signal
import threading

__all__ = ["REDELIVERY_SECONDS", "deliver_later", "in_finalizer", "interrupt"]


def in_finalizer(frame) -> bool:
    """Whether `frame` (a signal handler's) or a caller of it runs a ``__del__`` method.

    An exception raised there is printed as "Exception ignored" and dropped.
    """
    while frame is not None:
        if frame.f_code.co_name == "__del__":
            return True
        frame = frame.f_back
    return False


#: How long :func:`deliver_later` waits: longer than a finalizer runs (if one runs longer,
#: the signal lands in it again and is sent once more).
REDELIVERY_SECONDS = 0.01


def _send(signum: int, thread: int) -> None:
    if hasattr(signal, "pthread_kill"):  # to the main thread: it wakes from a blocking call too
        signal.pthread_kill(thread, signum)
    else:  # Windows
        signal.raise_signal(signum)


def deliver_later(signum: int) -> None:
    """Send `signum` to the main thread again in `REDELIVERY_SECONDS` (from a daemon thread)."""
    timer = threading.Timer(REDELIVERY_SECONDS, _send, (signum, threading.main_thread().ident))
    timer.daemon = True
    timer.start()


def interrupt(signum, frame) -> None:
    """A SIGINT handler: Python's own ``KeyboardInterrupt``, but never inside a finalizer.

    Inside a ``__del__`` the signal is sent again a moment later, to be raised
    once the finalizer has returned (raised there, it would be dropped).
    """
    if in_finalizer(frame):
        deliver_later(signum)
        return
    signal.default_int_handler(signum, frame)
