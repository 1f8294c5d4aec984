"""What the command says while numba compiles dentopo's kernels (a fresh install's first run).

numba compiles each kernel on its first call and keeps it in its cache, so a
fresh install's first run spends most of its time compiling, and later runs
none.  The command compiles before its first mesh (:func:`dentopo.batch.warm_up`,
on the sample crown, in as many processes as ``--jobs`` allows) and says so in
two lines: :func:`notice_text` before, with an estimate, and :func:`done_text`
after.  A mesh that takes a path the sample did not compiles the rest itself:
:class:`CompileNotice` says so as it starts (in this process), and
:func:`more_text` after that mesh (in this process or a worker).
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Iterable

from ..batch import WarmUp, estimated_seconds

#: A mesh that spent less than this compiling is not mentioned (loading a kernel is
#: not compiling, but a tiny kernel compiles in a fraction of a second).
MENTION_SECONDS = 0.5


def notice_text(metrics: Iterable[str], processes: int = 1) -> str:
    """``compiling dentopo's kernels for this machine, once (...): about N s``."""
    seconds = estimated_seconds(tuple(metrics), processes)
    rounded = max(5, 5 * round(seconds / 5))
    where = f" in {processes} processes" if processes > 1 else ""
    return (
        f"compiling dentopo's kernels for this machine{where}, once (later runs load them): "
        f"about {rounded} s"
    )


def done_text(warm: WarmUp) -> str:
    """``compiled in N s (...)``, or that numba's cache had them all."""
    if not warm.compiled:
        return f"every kernel was already in numba's cache ({warm.cache})"
    return f"compiled in {warm.seconds:.0f} s, kept in numba's cache ({warm.cache})"


#: What :class:`CompileNotice` says after the compilation before the first mesh.
MORE = "compiling more of dentopo's kernels (a path the sample crown did not take)"


def more_text(file: str, seconds: float) -> str:
    """``FILE: compiled kernels for N s (...)`` after a mesh that compiled some."""
    return (
        f"{file}: compiled kernels for {seconds:.1f} s (a path the sample crown did not take; "
        "kept for later runs)"
    )


class CompileNotice:
    """Calls ``say(text)`` once, at the first kernel compiled while it is entered.

    :meth:`start` registers a numba compile listener and :meth:`stop` removes
    it (or use it as a context manager).
    """

    def __init__(self, text: str, say: Callable[[str], None]):
        self.text = text
        self.say = say
        self.said = False
        self._lock = threading.Lock()
        self._listener = None

    def _started(self) -> None:
        with self._lock:
            if self.said:
                return
            self.said = True
        self.say(self.text)

    def start(self) -> None:
        """Listen to numba's compile events (imports numba, needed to compute anyway)."""
        from numba.core import event

        if self._listener is not None:
            return
        notice = self

        class Listener(event.Listener):
            def on_start(self, event_) -> None:
                notice._started()

            def on_end(self, event_) -> None:
                pass

        self._listener = Listener()
        event.register("numba:compile", self._listener)

    def stop(self) -> None:
        """Stop listening; safe to call more than once."""
        from numba.core import event

        if self._listener is not None:
            event.unregister("numba:compile", self._listener)
            self._listener = None

    def __enter__(self) -> CompileNotice:
        self.start()
        return self

    def __exit__(self, *exc) -> None:
        self.stop()
