"""A small pool of worker processes that survives the death of a worker.

``concurrent.futures.ProcessPoolExecutor`` marks the whole pool broken when one
worker dies (the out-of-memory killer's SIGKILL, a crash in compiled code), and
every file not yet finished then fails.  Here each worker is a ``spawn``
process with its own pipe and takes one task at a time; the parent waits on
the pipes and on the processes' sentinels.  A worker that dies costs only the
task it held (reported through ``failed(task, reason, seconds)``, e.g. "worker
process killed by SIGKILL (out of memory?)"), and a new worker takes its
place.

Workers never run the caller's ``__main__``: ``spawn`` would (it runs a
script's top level again in every child, as ``__mp_main__``), so that a plain
script calling the library without an ``if __name__ == "__main__":`` guard
re-ran itself in each worker, whose start then failed.  The preparation data of
our workers (and only theirs: a thread-local flag set while one starts) leaves
out the main module; a worker imports only what its function and arguments
need, which are unpickled inside the worker so that a failure there is reported
with its cause ("the worker process could not start: ...").  A worker says
"ready" first; one that dies before that cannot start here, and the tasks left
fail with that reason instead of starting worker after worker.

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
import pickle
import signal
import sys
import threading
import time
import weakref
from collections import deque
from collections.abc import Callable, Iterable, Iterator
from multiprocessing import connection, get_context, spawn

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


_STARTING = threading.local()  # .worker is True while this thread starts one of our workers


def _without_main(get_preparation_data: Callable) -> Callable:
    """`get_preparation_data` that leaves out ``__main__`` for the workers started here."""

    def preparation_data(name):
        data = get_preparation_data(name)
        if getattr(_STARTING, "worker", False):
            data.pop("init_main_from_path", None)  # a script: run again as __mp_main__
            data.pop("init_main_from_name", None)  # python -m module: imported again
        return data

    preparation_data.dentopo_without_main = True
    return preparation_data


def _leave_out_main() -> None:
    """Install :func:`_without_main` once (every start method's Popen asks ``spawn`` for it)."""
    if not getattr(spawn.get_preparation_data, "dentopo_without_main", False):
        spawn.get_preparation_data = _without_main(spawn.get_preparation_data)


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


def start_failure(exitcode: int | None) -> str:
    """Why a worker that died before it was ready could not start."""
    if exitcode is not None and exitcode < 0:
        how = death_reason(exitcode).replace("worker process ", "")
    else:
        how = f"exit code {exitcode}"
    return f"the worker process could not start ({how}; its error, if any, is on stderr)"


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


def _one_line(exc: BaseException) -> str:
    text = str(exc).strip().splitlines()
    return f"{type(exc).__name__}: {text[0]}" if text else type(exc).__name__


def _work(conn, payload: bytes, parent: int) -> None:
    """A worker's loop: ``function(task, *args)`` for each task received, until None or EOF.

    `payload` is ``(function, args)`` pickled: unpickled here, so that what
    stops it (a module the worker cannot import) goes back to the parent.
    """
    ignore_interrupts_in_worker()
    die_with_parent(parent)
    try:
        function, args = pickle.loads(payload)
    except Exception as exc:
        conn.send(("broken", f"the worker process could not start: {_one_line(exc)}"))
        return
    conn.send(("ready", None))
    while True:
        try:
            task = conn.recv()
        except (EOFError, OSError):  # the parent is gone
            return
        if task is None:
            return
        try:
            result = function(task, *args)
        except Exception as exc:  # the function's own failures are its to report: a bug
            conn.send(("failed", f"the worker process failed: {_one_line(exc)}"))
            continue
        try:
            conn.send(("ok", result))
        except (BrokenPipeError, EOFError, ConnectionError):
            return
        except Exception as exc:  # the result could not be pickled
            conn.send(("failed", f"cannot send the result back: {type(exc).__name__}: {exc}"))


class _Worker:
    def __init__(self, context, payload: bytes):
        self.conn, child = context.Pipe(duplex=True)
        self.process = context.Process(
            target=_work,
            args=(child, payload, os.getpid()),
            name="dentopo-worker",
            daemon=True,
        )
        _leave_out_main()
        _STARTING.worker = True
        try:
            with interrupts_ignored():
                self.process.start()
        finally:
            _STARTING.worker = False
        _LIVE.add(self.process)
        child.close()
        self.task = None
        self.started = 0.0
        self.ready = False

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
    result that cannot travel back, or an exception out of `function`, yields
    ``failed`` too.  Where no worker can start, each task yields ``failed``
    with the reason.  `function`, `args` and the tasks must be importable
    without the caller's ``__main__`` (module-level functions of a package):
    workers do not run it.  Closing the
    iterator early, or an exception while it waits (Ctrl-C), kills the
    workers at once; otherwise they are stopped when the tasks run out.
    `function` and `args` are pickled once per worker, each task once.
    """
    context = get_context("spawn")  # numba's OpenMP threading layer is not fork-safe
    payload = pickle.dumps((function, args))  # what cannot be pickled fails here, named
    pending = deque(tasks)
    pool: list[_Worker] = []
    finished = False
    started = False  # a worker has said "ready": workers can start here
    cannot_start = None  # why no worker could start, for the tasks left
    try:
        for _ in range(min(workers, len(pending))):
            worker = _Worker(context, payload)
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
                if message is not None and message[0] == "ready":
                    worker.ready = started = True
                    continue
                if message is not None and message[0] != "broken":
                    worker.task = None
                    kind, value = message
                    yield value if kind == "ok" else failed(task, value, seconds)
                    if pending:
                        worker.give(pending.popleft())
                    continue
                if message is None and worker.process.is_alive():
                    continue
                worker.process.join()
                worker.task = None
                pool.remove(worker)
                worker.close()
                if message is not None:  # "broken": it said why it could not start
                    reason = message[1]
                elif worker.ready:
                    reason = death_reason(worker.process.exitcode)
                else:
                    reason = start_failure(worker.process.exitcode)
                yield failed(task, reason, seconds)
                if not worker.ready and not started:
                    cannot_start = reason  # no replacement: it would fail alike
                elif pending:
                    replacement = _Worker(context, payload)
                    pool.append(replacement)
                    replacement.give(pending.popleft())
        while pending and cannot_start is not None:
            yield failed(pending.popleft(), cannot_start, None)
        finished = True
    finally:
        for worker in pool:
            worker.stop(kill=not finished)
        for worker in pool:
            worker.close()
