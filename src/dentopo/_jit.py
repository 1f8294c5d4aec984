"""numba's ``njit`` and ``prange`` for dentopo's kernels, with Ctrl-C held while numba compiles.

A kernel is compiled on its first call (on a fresh install; later calls load
numba's cache).  A Ctrl-C that arrives while LLVM compiles is lost: Python runs
the signal's handler in the first Python code it reaches, which is llvmlite's
object-cache callback, and an exception raised in a ctypes callback is printed
as "Exception ignored" and dropped; the computation then runs to its end.

While a kernel compiles, this module therefore gives SIGINT and SIGTERM a
handler that only records them (where Python handlers are installed, in the
main thread), and hands a recorded signal to the handler that was installed
before as the compilation ends: Python's ``KeyboardInterrupt``, or the batch
runner's guard.  A Ctrl-C during a compilation is thus raised when that kernel
is compiled (a few seconds at most), not lost.

The hold listens to numba's compile events (``numba.core.event``), so it covers
every compilation in the process, a kernel's callees too.

The same events are timed: :func:`compile_seconds` is how long the calling
thread has spent compiling so far (numba raises the event only when a kernel is
really compiled, not when it is loaded from the cache), so that a batch row's
``seconds`` can leave the compilation out.

May import: nothing of dentopo (every subpackage may import it).
"""

from __future__ import annotations

import os
import signal
import threading
import time

import numba
from numba import njit, prange
from numba.core import event

# OpenMP first, then TBB: the layer numba picks anyway where no TBB is installed (the usual
# case), and no warning where another package has loaded an older TBB than numba accepts
# (pymeshlab, the optional ``meshlab`` extra, bundles one: numba then warns that "the TBB
# threading layer is disabled" on its first parallel kernel).  An explicit
# NUMBA_THREADING_LAYER_PRIORITY in the environment is left as it is.
if "NUMBA_THREADING_LAYER_PRIORITY" not in os.environ:
    numba.config.THREADING_LAYER_PRIORITY = ["omp", "tbb", "workqueue"]

__all__ = ["compile_seconds", "njit", "prange"]

#: The signals held while numba compiles.
HELD = (signal.SIGINT, signal.SIGTERM)


class _HoldSignals(event.Listener):
    """Records `HELD` signals from the start of a compilation to its end, then hands them on."""

    def __init__(self):
        self.depth = 0  # nested compilations (a kernel's callees) in the main thread
        self.previous: dict[int, object] = {}
        self.caught: list[int] = []

    def _record(self, signum, frame) -> None:
        if signum not in self.caught:
            self.caught.append(signum)

    def on_start(self, event_) -> None:
        if threading.current_thread() is not threading.main_thread():
            return
        self.depth += 1
        if self.depth > 1:
            return
        for signum in HELD:
            handler = signal.getsignal(signum)
            if callable(handler):  # not SIG_IGN, SIG_DFL or a handler set outside Python
                self.previous[signum] = handler
                signal.signal(signum, self._record)

    def on_end(self, event_) -> None:
        if threading.current_thread() is not threading.main_thread() or self.depth == 0:
            return
        self.depth -= 1
        if self.depth:
            return
        previous, self.previous = self.previous, {}
        caught, self.caught = self.caught, []
        for signum, handler in previous.items():
            signal.signal(signum, handler)
        for signum in caught:
            previous[signum](signum, None)  # e.g. raises KeyboardInterrupt


#: Registered as this module is imported: every kernel module takes ``njit`` from here.
_HOLD = _HoldSignals()
event.register("numba:compile", _HOLD)


class _CompileClock(event.Listener):
    """Seconds each thread spends in outermost compilations (a callee's are inside its caller's)."""

    def __init__(self):
        self.local = threading.local()

    def on_start(self, event_) -> None:
        local = self.local
        depth = getattr(local, "depth", 0)
        if depth == 0:
            local.started = time.perf_counter()
        local.depth = depth + 1

    def on_end(self, event_) -> None:
        local = self.local
        depth = getattr(local, "depth", 0)
        if depth == 0:
            return
        local.depth = depth - 1
        if depth == 1:
            local.total = getattr(local, "total", 0.0) + time.perf_counter() - local.started


_CLOCK = _CompileClock()
event.register("numba:compile", _CLOCK)


def compile_seconds() -> float:
    """Seconds the calling thread has spent compiling kernels since dentopo was imported.

    Only finished compilations count; 0.0 while every kernel has come from
    numba's cache.  The difference between two calls is the compilation time
    between them.
    """
    return getattr(_CLOCK.local, "total", 0.0)
