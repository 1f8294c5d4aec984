"""One file of a batch: its task, its computation and its record.

:class:`Task` says where to read a file, what to call it and where its
per-vertex and per-face files go; :func:`compute_task` reads it, prepares it
(if the batch has a protocol), measures it and writes those files, and never
raises for a bad file: its :class:`Outcome` holds a record that says what went
wrong (:func:`error_reason`, :func:`error_record`).  This is what a worker
process or a Dask worker runs.
"""

from __future__ import annotations

import os
import time
import warnings
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from functools import partial

from .._optional import MissingExtraError
from ..formats import (
    COLUMNS,
    PROTOCOL_KEY,
    PerVertexOptions,
    naming_the_file,
    per_vertex_paths,
    record_source,
    write_per_face,
    write_per_vertex,
)
from ..mesh import load_mesh
from ..prepare import Protocol
from ..topography import MORPHOTESTER_METRICS
from ._errors import failure_reason
from ._measure import Measurement, measure_mesh, read_as_morphotester
from ._settings import Settings

_MAX_REASON = 500


@dataclass(frozen=True)
class Task:
    """One file of a batch: where to read it, what to call it, where its outputs go."""

    index: int
    file: str  # as shown in the table
    path: str  # as opened (absolute for remote workers)
    per_vertex_dir: str | None = None
    per_vertex_name: str | None = None
    keep_result: bool = False
    per_vertex: PerVertexOptions = field(default_factory=PerVertexOptions)  # formats, colours
    keys: tuple[str, ...] = COLUMNS  # the record's keys (an error row has them all, empty)


@dataclass(frozen=True)
class Outcome:
    """What computing one task produced (``result`` only if it was asked for)."""

    index: int
    record: dict
    warnings: tuple[str, ...] = ()
    result: object = None
    compiled: float = 0.0  # seconds spent compiling kernels for it (not in its record)


def error_reason(exc: BaseException) -> str:
    """A one-line reason for a failed file, for the ``error`` column."""
    if isinstance(exc, FileNotFoundError):
        reason = "file not found"
    elif isinstance(exc, IsADirectoryError):
        reason = "is a directory, not a mesh file"
    elif isinstance(exc, PermissionError):
        reason = f"unreadable: {exc.strerror or exc}"
    elif isinstance(exc, OSError):
        reason = f"unreadable: {exc}"
    elif isinstance(exc, MemoryError):
        reason = "out of memory"
    elif isinstance(exc, (ValueError, TypeError, MissingExtraError)):
        reason = str(exc)
    else:
        reason = f"{type(exc).__name__}: {exc}"
    reason = " ".join(reason.split()) or type(exc).__name__
    return reason if len(reason) <= _MAX_REASON else reason[: _MAX_REASON - 3] + "..."


def error_record(
    file: str, reason: str, seconds: float | None = None, keys: Iterable[str] = COLUMNS
) -> dict:
    """A table row for a file that failed: numbers empty, ``status="error"``."""
    record = dict.fromkeys(keys)
    record.update(file=file, seconds=seconds, status="error", error=reason)
    return record


#: ``on_phase(file, phase)`` is called as each phase of one mesh starts (see ``ariaDNE``).
PhaseCallback = Callable[[str, str], None]


def compute_task(task: Task, settings: Settings, on_phase: PhaseCallback | None = None) -> Outcome:
    """Compute one file; never raises for a bad file (the record says what went wrong).

    The row's ``seconds`` leave out the time spent compiling kernels (a fresh
    install's first meshes), so that they measure the computation alone.
    """
    import numba

    from .._jit import compile_seconds

    previous_threads = numba.get_num_threads()
    if settings.threads is not None:  # per calling thread: safe in threaded workers
        numba.set_num_threads(min(settings.threads, numba.config.NUMBA_NUM_THREADS))
    start = time.perf_counter()
    compiled = compile_seconds()

    def elapsed() -> float:
        return round(max(0.0, time.perf_counter() - start - (compile_seconds() - compiled)), 4)

    measured = None
    step = "reading"
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                phases = None if on_phase is None else partial(on_phase, task.file)
                mesh = task.path  # ariaDNE alone reads the file itself
                raw = None  # the file as MorphoTester reads it, for its metrics
                if (
                    set(MORPHOTESTER_METRICS).intersection(settings.metrics)
                    and settings.geometry is None
                    and settings.prepare is None
                ):
                    raw = read_as_morphotester(task.path)
                only_read_raw = raw is not None and set(settings.metrics) <= set(
                    MORPHOTESTER_METRICS
                )
                if (
                    settings.geometry is not None
                    or (settings.metrics != ("ariadne",) and not only_read_raw)
                    or settings.prepare is not None
                ):
                    mesh = load_mesh(task.path, geometry=settings.geometry)  # once for all
                if settings.prepare is not None:
                    step = "prepare"
                    if phases is not None:
                        phases("preparing")
                    mesh = prepared_mesh(mesh, settings.prepare)
                step = "measuring"
                measured = measure_mesh(
                    mesh,
                    settings.metrics,
                    ariadne_options=settings.options(),
                    options=settings.topography,
                    reason=error_reason,
                    progress=phases,
                    raw=raw,
                )
                step = "writing the per-vertex files"
                if task.per_vertex_dir is not None and measured.status != "error":
                    _write_per_mesh(task, measured, settings.protocol)
            except Exception as exc:  # one bad file never stops the batch
                seconds = elapsed()
                if isinstance(exc, FileNotFoundError) and os.path.islink(task.path):
                    reason = "unreadable: a broken symbolic link"
                elif isinstance(exc, OSError) and step == "writing the per-vertex files":
                    reason = _output_reason(task, exc)  # an output's fault, not the input's
                else:
                    reason = failure_reason(step, exc, error_reason)
                reason = _shortened(reason)
                record = error_record(task.file, reason, seconds, settings.keys())
                record[PROTOCOL_KEY] = settings.protocol
                measured = None
            else:
                seconds = elapsed()
                if measured.status == "error":  # no metric computed: an error row
                    record = error_record(task.file, measured.error, seconds, settings.keys())
                    measured = None
                else:
                    record = {"file": task.file, **measured.record}
                    record[PROTOCOL_KEY] = settings.protocol  # in table order: before seconds
                    record.update(seconds=seconds, status=measured.status, error=measured.error)
                record[PROTOCOL_KEY] = settings.protocol
    finally:
        numba.set_num_threads(previous_threads)
    messages = tuple(dict.fromkeys(str(w.message) for w in caught))
    record["warnings"] = "; ".join(messages) or None
    return Outcome(
        task.index,
        record,
        messages,
        measured if task.keep_result else None,
        compiled=round(compile_seconds() - compiled, 3),
    )


def prepared_mesh(mesh, protocol: Protocol):
    """`mesh` prepared by `protocol` (:func:`dentopo.prepare`), as a new trimesh.

    The protocol's warnings are issued again prefixed ``prepare:`` (so that a
    row's ``warnings`` say which came from preparing); a step that fails
    raises (the file's error row names it).
    """
    from ..prepare import prepare

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        crown = prepare(mesh, protocol)
    for warning in caught:
        warnings.warn(f"prepare: {warning.message}", warning.category, stacklevel=2)
    return crown.mesh


def _shortened(reason: str) -> str:
    reason = " ".join(reason.split())
    return reason if len(reason) <= _MAX_REASON else reason[: _MAX_REASON - 3] + "..."


def _output_reason(task: Task, exc: OSError) -> str:
    """The row's error when a per-vertex or per-face file cannot be written (a full disk)."""
    why = exc.strerror or str(exc) or type(exc).__name__
    if exc.filename is not None:
        where = f"the per-vertex file {os.fspath(exc.filename)!r}"
    else:
        where = f"the per-vertex files of {task.per_vertex_name!r} in {task.per_vertex_dir!r}"
    return f"cannot write {where}: {why} (an output failed, not the input; rerun to write it)"


def _write_per_mesh(task: Task, measured: Measurement, protocol: str | None = None) -> None:
    """The per-vertex files (ariaDNE) and per-face files (slope, OPC) of one mesh."""
    options = task.per_vertex
    ariadne = measured.results.get("ariadne")
    if ariadne is not None:
        write_per_vertex(
            task.per_vertex_dir,
            task.per_vertex_name,
            ariadne,
            formats=options.formats,
            limits=options.limits,
            percentile=options.percentile,
        )
    faces = {
        metric: measured.results[metric]
        for metric in PER_FACE_METRICS
        if metric in measured.results
    }
    if faces:
        base = os.path.join(task.per_vertex_dir, task.per_vertex_name + ".dentopo.faces.*")
        with naming_the_file(base):
            write_per_face(
                task.per_vertex_dir, task.per_vertex_name, faces, formats=options.formats
            )
    if ariadne is not None or faces:  # which mesh these files are (replaced_per_vertex_files)
        record_source(task.per_vertex_dir, task.per_vertex_name, task.path, protocol)


#: The metrics with per-face files (``NAME.dentopo.faces.*``) in the per-vertex folder.
PER_FACE_METRICS = ("slope", "opc", "opcr")


def planned_per_vertex_files(task: Task, metrics: Iterable[str]) -> list[str]:
    """The per-vertex and per-face files `task` writes if its metrics succeed (none without)."""
    if task.per_vertex_dir is None:
        return []
    metrics = tuple(metrics)
    return per_vertex_paths(
        task.per_vertex_dir,
        task.per_vertex_name,
        task.per_vertex.formats,
        vertices="ariadne" in metrics,
        faces=any(m in metrics for m in PER_FACE_METRICS),
    )
