"""Each specimen's signed local curvature, recomputed with its row's settings.

The table holds totals, not the per-vertex field the pictures are coloured by,
so each file is read again and ariaDNE computed with the row's bandwidth,
cutoff, distance, sign rule and method.  Several files are shared among
worker processes (``spawn``: numba's threading layers are not fork-safe), one
numba thread each; a file that cannot be read or measured gives a one-line
reason instead of a field, and a worker that dies costs only the files it had.
"""

from __future__ import annotations

import signal
import warnings
from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass
from multiprocessing import get_context

import numpy as np

from ..ariadne import ariaDNE
from ..mesh import load_mesh

#: Fewer files than this are computed in this process (starting workers costs seconds).
POOL_FROM = 12


@dataclass(frozen=True)
class Field:
    """A cleaned mesh and its signed local curvature per vertex."""

    vertices: np.ndarray
    faces: np.ndarray
    values: np.ndarray


def reason(exc: BaseException) -> str:
    """A one-line reason for a file that could not be measured."""
    if isinstance(exc, FileNotFoundError):
        return "file not found"
    if isinstance(exc, OSError):
        return f"cannot read the file: {exc.strerror or exc}"
    text = str(exc).strip().splitlines()
    return text[0] if text else type(exc).__name__


def measure_field(path: str, options: dict) -> Field | str:
    """The field of the mesh in `path` (ariaDNE with `options`), or why there is none."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # its row has said it already
            mesh = load_mesh(path)
            result = ariaDNE(mesh, **options)
    except (Exception, MemoryError) as exc:
        return reason(exc)
    return Field(
        np.asarray(result.mesh.vertices, dtype=np.float64),
        np.asarray(result.mesh.faces, dtype=np.int64),
        np.asarray(result.local_curvature, dtype=np.float64),
    )


def _start_worker() -> None:
    """One numba thread; Ctrl-C is the parent's to handle (it stops the workers)."""
    import numba

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    numba.set_num_threads(1)


class Workers:
    """Worker processes for both steps of a report, or none; a context manager.

    Parameters
    ----------
    jobs : int
        Processes to start; with 1, or fewer than :data:`POOL_FROM` tasks,
        none is started and everything runs in this process.
    tasks : int
        How many files there are.
    """

    def __init__(self, jobs: int, tasks: int):
        self.pool = None
        self.jobs = 1
        if jobs > 1 and tasks >= POOL_FROM:
            self.jobs = min(jobs, tasks)
            self.pool = ProcessPoolExecutor(
                self.jobs, mp_context=get_context("spawn"), initializer=_start_worker
            )

    def __enter__(self) -> Workers:
        return self

    def __exit__(self, *exc) -> None:
        if self.pool is not None:
            self.pool.shutdown(cancel_futures=True)

    def map(self, function, calls: Sequence[tuple], died) -> list:
        """``function(*call)`` for each call, in order; ``died(call)`` where a worker died."""
        if self.pool is None:
            return [function(*call) for call in calls]
        futures = [self.pool.submit(function, *call) for call in calls]
        results = []
        for call, future in zip(calls, futures, strict=True):
            try:
                results.append(future.result())
            except BrokenProcessPool:
                results.append(died(call))
        return results


def measure_fields(tasks: Sequence[tuple[str, dict]], workers: Workers) -> list[Field | str]:
    """:func:`measure_field` of each ``(path, options)``, on `workers`."""
    return workers.map(
        measure_field, tasks, lambda call: "the worker process measuring it died (out of memory?)"
    )
