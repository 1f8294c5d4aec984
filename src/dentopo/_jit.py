"""numba's ``njit`` and ``prange``, with Ctrl-C held where numba cannot take it.

A kernel is compiled on its first call (on a fresh install; later calls load
numba's cache).  Python runs a signal's handler in the first Python code it
reaches, and two places of numba's are not safe for a ``KeyboardInterrupt``:

* While LLVM compiles, that code is llvmlite's object-cache callback, and an
  exception raised in a ctypes callback is printed as "Exception ignored" and
  dropped: the Ctrl-C was lost and the computation ran to its end.
* While numba loads a kernel from its cache or links one, the code is
  llvmlite's, which hands each LLVM module to the execution engine in two
  steps (the engine takes it, then the module is marked as owned); an
  interrupt between them leaves a module that the garbage collector frees
  while the engine still holds it (a later kernel aborts inside LLVM; a
  "double free detected" as a process exited after a Ctrl-C was probably
  this).  An interrupted compilation was also never written to the cache,
  so that the next run compiled it again.

While numba holds its compiler lock (``numba.core.event``'s
``numba:compiler_lock``: compiling, loading from the cache, linking, saving to
the cache), this module therefore gives SIGINT and SIGTERM a handler that only
records them (where Python handlers are installed, in the main thread), and
hands a recorded signal to the handler that was installed before as the lock
is released: Python's ``KeyboardInterrupt``, or the batch runner's guard.  A
Ctrl-C during a compilation is thus raised when that kernel is compiled and
cached (a few seconds at most), not lost.  The hold listens to numba's events,
so it covers every compilation in the process, a kernel's callees too.

A third place is anywhere: llvmlite's objects free their LLVM resources in
a ``__del__``, whenever the garbage collector runs, and an exception raised
there is dropped too; :mod:`dentopo._signals` sends such a signal again a
moment later.

The compilations are timed too: :func:`compile_seconds` is how long the
calling thread has spent compiling so far (numba raises the event only when a
kernel is really compiled, not when it is loaded from the cache), so that a
batch row's ``seconds`` can leave the compilation out.

May import: nothing of dentopo (every subpackage may import it).
"""

from __future__ import annotations

import importlib
import itertools
import os
import signal
import sys
import threading
import time
from itertools import pairwise

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

# OpenMP's threads sleep as soon as a parallel kernel ends, instead of spinning for a while
# (GNU OpenMP's default) in case another follows.  dentopo's kernels last milliseconds and
# are separated by serial work; a spinning thread then takes a core from that work on a
# machine where another program is running: with one of two cores busy, ariaDNE on a
# 1,000-vertex crown took 23 ms on two threads against 7.6 ms on one (the serial eigen
# step alone 0.4 -> 7.6 ms), and 7.6 ms with sleeping threads.  Waking a sleeping thread
# costs microseconds.  Read when OpenMP is loaded (numba's first parallel kernel); a value
# already in the environment (OMP_WAIT_POLICY=ACTIVE) is left as it is.
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")

__all__ = ["compile_seconds", "in_threads", "lean_numba_typing", "njit", "prange"]

#: The signals held while numba compiles.
HELD = (signal.SIGINT, signal.SIGTERM)

#: The numba event during which they are held: numba's compiler lock, taken to compile a
#: kernel, to load it from the cache or link it, and to save it to the cache.
HELD_DURING = "numba:compiler_lock"


class _HoldSignals(event.Listener):
    """Records `HELD` signals while numba holds its compiler lock, then hands them on."""

    def __init__(self):
        self.depth = 0  # nested holds of the lock (a kernel's callees) in the main thread
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


def _values(self) -> dict:
    """``TargetConfig.values``: every option's value, its default where it is not set."""
    cls = type(self)
    defaults = cls.__dict__.get("_dentopo_defaults")
    if defaults is None:
        defaults = {name: option.default for name, option in cls.options.items()}
        cls._dentopo_defaults = defaults
    values = dict(defaults)
    values.update(self._values)
    return values


def _hash(self) -> int:
    """``TargetConfig.__hash__``: the hash of its sorted option names (what numba's is)."""
    cls = type(self)
    code = cls.__dict__.get("_dentopo_hash")
    if code is None:
        code = hash(tuple(sorted(cls.options)))
        cls._dentopo_hash = code
    return code


def quick_compile_flags() -> bool:
    """Let numba compare its compile flags in a dict copy instead of ~40 property reads.

    While numba types a kernel, every call of one of its overloaded functions
    (``np.empty``, ``min``, ...) looks up a cache keyed by the compile flags, whose
    ``__hash__`` and ``__eq__`` build a dict of all the options, each read through a
    Python property: about 3 s of the 46 s of CPU that ``--metrics all`` spent
    compiling on a fresh install (numba 0.68).  The two functions here return the same
    values (the options set, the defaults for the others; the hash of the sorted option
    names, which is what numba's hashes); they are put in only when they give numba's
    own answers on its compile flags.  Returns whether they are in.
    """
    from numba.core import targetconfig
    from numba.core.compiler import Flags

    config = targetconfig.TargetConfig
    if config.values is _values:
        return True
    try:
        probe = Flags()
        probe.nrt = True
        probe.fastmath = True
        if _values(probe) != config.values(probe) or _hash(probe) != config.__hash__(probe):
            return False
    except Exception:  # another numba: keep its own
        return False
    config.values = _values
    config.__hash__ = _hash
    return True


quick_compile_flags()

#: Registered as this module is imported: every kernel module takes ``njit`` from here.
_HOLD = _HoldSignals()
event.register(HELD_DURING, _HOLD)


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


def lean_numba_typing() -> list[str]:
    """Load two parts of numba's typing as they load without cffi and without scipy.

    When numba's typing registries load (at the first kernel of a process), it imports cffi,
    if installed, to type cffi's functions, which builds cffi's C parser (about 60 ms), and
    probes scipy's BLAS for ``np.correlate`` and ``np.convolve`` by importing
    ``scipy.linalg`` (about 80 ms): together 14 % of a warm ``dentopo crown.ply``.  No
    dentopo kernel takes a cffi function or calls those two.  For the command's own process
    only (its main function calls this first): both packages stay importable for every
    other use; only numba's typing of cffi objects is off, and its ``np.correlate`` and
    ``np.convolve`` would use their own loop.  Skips a part whose module is already loaded.
    Returns the parts loaded so.
    """
    parts = (
        ("numba.core.typing.cffi_utils", "cffi"),
        ("numba.np.arraymath", "scipy.linalg.cython_blas"),
    )
    done = []
    for module, hidden in parts:
        if module in sys.modules or hidden in sys.modules:
            continue
        sys.modules[hidden] = None  # type: ignore[assignment]  # its import raises ImportError
        try:
            importlib.import_module(module)
        finally:
            del sys.modules[hidden]
        done.append(module)
    return done


#: The threads of :func:`in_threads`, made on first use (one per core).
_POOL = None
_POOL_LOCK = threading.Lock()


def _forget_pool() -> None:  # a forked child has none of its parent's threads
    global _POOL
    _POOL = None


os.register_at_fork(after_in_child=_forget_pool)


def in_threads(
    first: int, last: int, call, *, threads_from: int = 1, chunks: int | None = None
) -> None:
    """``call(a, b)`` over ``first:last`` cut into one slice per numba thread, on a pool
    (the calling thread does the first).

    For kernels compiled with ``nogil=True`` over parts of their rows: one compiled kernel
    serves one thread and many, where a ``prange`` loop is a second compilation of the
    same body (0.5 to 1.7 s each on a fresh install).  With `chunks`, the rows are cut
    into that many chunks instead, which the threads take in turn as they finish (for
    rows of uneven cost: the winding numbers' queries).  Fewer than `threads_from` items
    (or one thread, or one item) make one slice, run in the calling thread; never more
    slices than items.  Returns when every slice is done; the first error (in the slices'
    order) is raised as soon as it is met, and a Ctrl-C once the calling thread's slice
    is done (the callers keep a call to about a tenth of a second).
    """
    count = last - first
    parts = min(numba.get_num_threads(), count) if count >= threads_from else 1
    if parts <= 1:
        call(first, last)
        return
    global _POOL
    with _POOL_LOCK:
        if _POOL is None:
            from concurrent.futures import ThreadPoolExecutor

            cores = os.cpu_count() or 1
            _POOL = ThreadPoolExecutor(max_workers=cores, thread_name_prefix="dentopo")
        pool = _POOL
    pieces = parts if chunks is None else max(parts, min(int(chunks), count))
    bounds = [first + count * k // pieces for k in range(pieces + 1)]
    if pieces == parts:
        slices = list(pairwise(bounds))
        tasks = [pool.submit(call, a, b) for a, b in slices[1:]]
        own = (call, *slices[0])
    else:
        taken = itertools.count()  # next() on it is atomic: each chunk is taken once

        def worker() -> None:
            for k in iter(taken.__next__, None):
                if k >= pieces:
                    return
                call(bounds[k], bounds[k + 1])

        tasks = [pool.submit(worker) for _ in range(parts - 1)]
        own = (worker,)
    own[0](*own[1:])  # the calling thread takes the first share: one thread fewer to wake
    for done in tasks:
        done.result()
