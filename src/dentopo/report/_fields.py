"""Each specimen's signed local curvature, recomputed with its row's settings.

The table holds totals, not the per-vertex field the pictures are coloured by,
so each file is read again and ariaDNE computed with the row's bandwidth,
cutoff, distance, sign rule and method.  Several files are shared among
worker processes (``spawn``: numba's threading layers are not fork-safe), one
numba thread each; a file that cannot be read or measured gives a one-line
reason instead of a field, and a worker that dies costs only the files it had.
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..ariadne import ariaDNE
from ..batch import run_pool
from ..mesh import load_mesh
from ..prepare import Protocol

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


def measure_field(path: str, options: dict, protocol: Protocol | None = None) -> Field | str:
    """The field of the mesh in `path` (ariaDNE with `options`), or why there is none.

    With a `protocol` the mesh is prepared with it first (the row's mesh was:
    its ``protocol`` cell), so that the picture shows the crown measured.
    """
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # its row has said it already
            mesh = load_mesh(path)
            if protocol is not None:
                from ..prepare import prepare

                mesh = prepare(mesh, protocol).mesh
            result = ariaDNE(mesh, **options)
    except (Exception, MemoryError) as exc:
        return reason(exc)
    return Field(
        np.asarray(result.mesh.vertices, dtype=np.float64),
        np.asarray(result.mesh.faces, dtype=np.int64),
        np.asarray(result.local_curvature, dtype=np.float64),
    )


def _call(task: tuple[int, tuple], function) -> tuple[int, object]:
    """In a worker: ``(index, function(*call))`` for ``task = (index, call)``, one numba thread."""
    import numba

    numba.set_num_threads(1)
    index, call = task
    return index, function(*call)


def worker_count(jobs: int, files: int) -> int:
    """Worker processes for a report of `files` files: `jobs`, or 1 (none started).

    Starting workers costs seconds, so fewer than :data:`POOL_FROM` files are
    done in this process.
    """
    return min(jobs, files) if jobs > 1 and files >= POOL_FROM else 1


def run_calls(function, calls: Sequence[tuple], workers: int, died) -> list:
    """``function(*call)`` for each call, in order, on `workers` processes (1: this one).

    The calls go to the batch's pool (:func:`dentopo.batch.run_pool`:
    ``spawn``ed workers that ignore Ctrl-C, die with this process and do not
    run the caller's ``__main__``); where a worker dies or cannot start, its
    call gets ``died(call, reason)`` (the pool's reason: the signal, or why it
    could not start) and the others go on.
    """
    if workers <= 1 or len(calls) <= 1:
        return [function(*call) for call in calls]
    results: list = [None] * len(calls)
    finished = run_pool(
        list(enumerate(calls)),
        _call,
        (function,),
        workers=min(workers, len(calls)),
        failed=lambda task, reason, seconds: (task[0], died(task[1], reason)),
    )
    for index, result in finished:
        results[index] = result
    return results


def measure_fields(tasks: Sequence[tuple], workers: int) -> list[Field | str]:
    """:func:`measure_field` of each ``(path, options[, protocol])``, on `workers` processes."""
    return run_calls(
        measure_field,
        tasks,
        workers,
        lambda call, reason: f"measuring it in a worker failed: {reason}",
    )
