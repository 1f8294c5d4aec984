"""The line that says numba is compiling dentopo's kernels (a fresh install's first run).

numba compiles each kernel on its first call and keeps it in its cache, so a
fresh install's first run spends most of its time compiling, and later runs
none.  While the command runs, :class:`CompileNotice` listens to numba's
compile events (raised only for a real compilation, never for a kernel loaded
from the cache) and, at the first one, prints one line saying so, with an
estimate of how long it takes for the metrics asked for.  Kernels compiled in
worker processes (``--jobs`` above 1) are not seen here.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Iterable

from ..topography import DOOLKIT_METRICS, MOLAR_METRICS

#: Seconds of compilation on a fresh install (CPU seconds of numba's compile events, one
#: core of a shared two-core machine; the line says "about"): ariaDNE with its sign (the
#: default, normal.ply or --samples: 27-31 s), molaR's metrics and doolkit's (--metrics
#: all: 88 s in all, concaveman's footprint alone about 25 s).  Each part counts once,
#: when one of its metrics is asked for.
ESTIMATED_SECONDS = {"ariadne": 30, "molar": 20, "doolkit": 40}


def estimated_seconds(metrics: Iterable[str]) -> int:
    """Seconds a fresh install spends compiling the kernels of `metrics` (an estimate)."""
    metrics = set(metrics)
    parts = {
        "ariadne": "ariadne" in metrics,
        "molar": bool(metrics & set(MOLAR_METRICS)),
        "doolkit": bool(metrics & set(DOOLKIT_METRICS)),
    }
    return sum(ESTIMATED_SECONDS[part] for part, used in parts.items() if used)


def notice_text(metrics: Iterable[str]) -> str:
    """``compiling dentopo's kernels for this machine, once: about N s``."""
    seconds = max(10, 10 * int(estimated_seconds(metrics) / 10 + 0.5))
    return f"compiling dentopo's kernels for this machine, once: about {seconds} s"


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
