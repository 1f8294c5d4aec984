"""A small pool of worker processes that survives the death of a worker.

``concurrent.futures.ProcessPoolExecutor`` marks the whole pool broken when one
worker dies (the out-of-memory killer's SIGKILL, a crash in compiled code), and
every file not yet finished then fails.  Here each worker is a ``spawn``
process with its own pipe and takes one task at a time; the parent waits on
the pipes and on the processes' sentinels.  A worker that dies costs only the
task it held (reported through ``failed(task, reason, seconds)``, e.g. "worker
process killed by SIGKILL (out of memory?)"), and a new worker takes its
place.

Workers ignore SIGINT and SIGTERM from their first instruction (the parent
stops them: a terminal's Ctrl-C and a scheduler's SIGTERM reach the whole
process group) and die with their parent: on Linux through
``prctl(PR_SET_PDEATHSIG, SIGKILL)``, elsewhere through a thread that watches
the parent's pid (which only runs between compiled kernels); an idle worker
also stops when its pipe closes.
"""

from __future__ import annotations

import atexit
import ctypes
import os
import signal
import sys
import threading
import time
import weakref
from collections import deque
from collections.abc import Callable, Iterable, Iterator
from multiprocessing import connection, get_context

from ._interrupts import ignore_interrupts_in_worker, interrupts_ignored

#: Seconds the parent waits for idle workers to stop before killing them.
STOP_SECONDS = 5.0

_PR_SET_PDEATHSIG = 1

_LIVE: weakref.WeakSet = weakref.WeakSet()


@atexit.register
def _kill_live_workers() -> None:  # runs before multiprocessing's own exit handler
    for process in list(_LIVE):  # which would send SIGTERM, ignored, and wait forever
        if process.is_alive():
            process.kill()
            process.join()


def death_reason(exitcode: int | None) -> str:
    """Why a worker stopped, for the ``error`` column of the file it held."""
    if exitcode is None:
        return "worker process vanished"
    if exitcode < 0:
        try:
            name = signal.Signals(-exitcode).name
        except ValueError:
            name = f"signal {-exitcode}"
        hint = " (out of memory?)" if -exitcode == getattr(signal, "SIGKILL", 9) else ""
        return f"worker process killed by {name}{hint}"
    return f"worker process exited unexpectedly (exit code {exitcode})"


def _watch_parent(parent: int) -> None:
    while True:
        time.sleep(1.0)
        if os.getppid() != parent:
            os._exit(1)


def die_with_parent(parent: int) -> None:
    """Make this process die when process `parent` does (see the module docstring)."""
    watch = True
    if sys.platform.startswith("linux"):
        try:
            libc = ctypes.CDLL(None, use_errno=True)
            watch = libc.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0) != 0
        except (OSError, AttributeError):
            watch = True
    if os.getppid() != parent:  # the parent died before that took effect
        os._exit(1)
    if watch:
        threading.Thread(target=_watch_parent, args=(parent,), daemon=True).start()


def _work(conn, function: Callable, args: tuple, parent: int) -> None:
    """A worker's loop: ``function(task, *args)`` for each task received, until None or EOF."""
    ignore_interrupts_in_worker()
    die_with_parent(parent)
    while True:
        try:
            task = conn.recv()
        except (EOFError, OSError):  # the parent is gone
            return
        if task is None:
            return
        result = function(task, *args)
        try:
            conn.send(("ok", result))
        except (BrokenPipeError, EOFError, ConnectionError):
            return
        except Exception as exc:  # the result could not be pickled
            conn.send(("failed", f"cannot send the result back: {type(exc).__name__}: {exc}"))


class _Worker:
    def __init__(self, context, function: Callable, args: tuple):
        self.conn, child = context.Pipe(duplex=True)
        self.process = context.Process(
            target=_work,
            args=(child, function, args, os.getpid()),
            name="dentopo-worker",
            daemon=True,
        )
        with interrupts_ignored():
            self.process.start()
        _LIVE.add(self.process)
        child.close()
        self.task = None
        self.started = 0.0

    def give(self, task) -> None:
        self.task = task
        self.started = time.perf_counter()
        try:
            self.conn.send(task)
        except OSError:  # dead already: its sentinel tells
            pass

    def receive(self):
        """The message waiting on the pipe, or None (nothing, or the worker died)."""
        try:
            if self.conn.poll():
                return self.conn.recv()
        except (EOFError, OSError):
            return None
        except Exception as exc:  # a result that cannot be unpickled here
            return ("failed", f"cannot read the result: {type(exc).__name__}: {exc}")
        return None

    def stop(self, *, kill: bool) -> None:
        if kill or self.task is not None:
            self.process.kill()
        else:
            try:
                self.conn.send(None)
            except OSError:
                pass

    def close(self) -> None:
        self.process.join(STOP_SECONDS)
        if self.process.is_alive():
            self.process.kill()
            self.process.join()
        self.conn.close()
        _LIVE.discard(self.process)


def run_pool(
    tasks: Iterable,
    function: Callable,
    args: tuple,
    *,
    workers: int,
    failed: Callable[[object, str, float | None], object],
) -> Iterator:
    """Yield ``function(task, *args)`` for each task, computed in `workers` processes.

    Results come in the order they finish.  A worker that dies yields
    ``failed(task, reason, seconds)`` for the task it held and is replaced; a
    result that cannot travel back yields ``failed`` too.  Closing the
    iterator early, or an exception while it waits (Ctrl-C), kills the
    workers at once; otherwise they are stopped when the tasks run out.
    `function` and `args` are pickled once per worker, each task once.
    """
    context = get_context("spawn")  # numba's OpenMP threading layer is not fork-safe
    pending = deque(tasks)
    pool: list[_Worker] = []
    finished = False
    try:
        for _ in range(min(workers, len(pending))):
            worker = _Worker(context, function, args)
            pool.append(worker)
            worker.give(pending.popleft())
        while True:
            busy = [w for w in pool if w.task is not None]
            if not busy:
                break
            waiting = [w.conn for w in busy] + [w.process.sentinel for w in busy]
            ready = set(connection.wait(waiting))
            for worker in busy:
                if worker.conn not in ready and worker.process.sentinel not in ready:
                    continue
                message = worker.receive()
                task, seconds = worker.task, round(time.perf_counter() - worker.started, 4)
                if message is not None:
                    worker.task = None
                    kind, value = message
                    yield value if kind == "ok" else failed(task, value, seconds)
                    if pending:
                        worker.give(pending.popleft())
                    continue
                if worker.process.is_alive():
                    continue
                worker.process.join()
                worker.task = None
                pool.remove(worker)
                worker.close()
                yield failed(task, death_reason(worker.process.exitcode), seconds)
                if pending:
                    replacement = _Worker(context, function, args)
                    pool.append(replacement)
                    replacement.give(pending.popleft())
        finished = True
    finally:
        for worker in pool:
            worker.stop(kill=not finished)
        for worker in pool:
            worker.close()
