"""Batches: ariaDNE over many mesh files, in parallel, resumable, locally or on Dask.

One bad file never stops a batch: its record says ``status="error"`` and gives
the reason.  Files are processed in worker processes (``jobs``) or on an
existing Dask distributed cluster (``scheduler``); the records always come back
in the sorted order of the files and do not depend on how they were computed.

When meshes run side by side (several processes, or a cluster) each uses one
numba thread, so that the cores are not oversubscribed; a single process uses
numba's default.  Records do not depend on either choice (tests/test_batch.py
checks ``jobs=2`` against ``jobs=1`` bit for bit).

Local workers are a pool of our own (:mod:`._pool`) that survives the death of
a worker: only the file that worker held gets an error row.  In this process,
Ctrl-C and SIGTERM raise :class:`Interrupted` (:mod:`._interrupts`).

This module plans and runs a batch; the settings are :mod:`._settings`'s, the
computation of one file :mod:`._task`'s, which previous rows are kept
:mod:`._resume`'s.
"""

from __future__ import annotations

import os
import warnings
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import replace

from .._optional import DASK
from ..formats import (
    DEFAULT_PER_VERTEX_FORMATS,
    OUTPUT_SUFFIX,
    PerVertexOptions,
    per_vertex_names,
    read_table,
    replaced_files,
)
from ._inputs import find_mesh_files
from ._interrupts import Interrupted, guard_interrupts
from ._pool import run_pool
from ._result import BatchResult
from ._resume import merge_records, relabel_resumed, resumable_files
from ._settings import Settings, check_extras, make_settings
from ._task import Outcome, PhaseCallback, Task, compute_task, error_reason, error_record
from ._warmup import warm_up, warm_up_wanted

#: ``progress(done, total, record)`` is called after each file.
ProgressCallback = Callable[[int, int, dict], None]


def available_cores() -> int:
    """CPU cores this process may use."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def replaced_per_vertex_files(tasks: Sequence[Task]) -> list[tuple[str, str, str | None, str]]:
    """Per-vertex files that `tasks` will replace although another mesh's (another run's).

    Two runs into one per-vertex folder whose meshes share a base name
    (``a/tooth.ply`` and ``b/tooth.ply``) write the same files: the second
    replaces the first's.  Each folder records which mesh each base name was
    written for (:func:`dentopo.formats.record_source`); rewriting the files
    of the same mesh is not listed.

    Returns
    -------
    list of (directory, name, previous, source)
        ``previous`` is the mesh the files were written for, or None if not
        recorded (files of an older version, or not dentopo's).
    """
    by_directory: dict[str, dict[str, str]] = {}
    for task in tasks:
        if task.per_vertex_dir is not None:
            by_directory.setdefault(task.per_vertex_dir, {})[task.per_vertex_name] = task.path
    return [
        (directory, name, previous, source)
        for directory, sources in by_directory.items()
        for name, previous, source in replaced_files(directory, sources)
    ]


def _failed(task: Task, reason: str, seconds: float | None = None) -> Outcome:
    """The outcome of a task whose worker died (or whose result could not travel back)."""
    return Outcome(task.index, error_record(task.file, reason, seconds, task.keys))


def _run_here(
    tasks: Sequence[Task], settings: Settings, on_phase: PhaseCallback | None = None
) -> Iterator[Outcome]:
    """The meshes one after the other in this process, stopped by Ctrl-C or SIGTERM.

    The guard (:mod:`._interrupts`) raises :class:`Interrupted` for SIGTERM
    too.  A mesh whose interrupt was swallowed (trimesh's loader catches
    every exception) is not kept: the interrupt is raised again, as the next
    phase of the mesh starts or as it ends.
    """
    with guard_interrupts() as guard:

        def swallowed() -> None:
            if guard.raised is not None:  # raised in the mesh, and caught by library code
                raise Interrupted(guard.raised)

        def phase(file: str, name: str) -> None:
            swallowed()
            if on_phase is not None:
                on_phase(file, name)

        for task in tasks:
            guard.check()
            guard.raised = None
            outcome = compute_task(task, settings, phase)
            swallowed()  # then its row (an error, or worse) cannot be trusted: stop without it
            yield outcome  # the row is kept before stopping
        guard.check()


def _run_local(
    tasks: Sequence[Task], settings: Settings, jobs: int, on_phase: PhaseCallback | None = None
) -> Iterator[Outcome]:
    if jobs <= 1 or len(tasks) <= 1:
        yield from _run_here(tasks, settings, on_phase)
        return
    workers = min(jobs, len(tasks))
    if warm_up_wanted():
        warm_up(settings, jobs=workers)  # compiled once, here, not in every worker
    if settings.threads is None:  # share the cores among the workers
        settings = replace(settings, threads=max(1, available_cores() // workers))
    yield from run_pool(tasks, compute_task, (settings,), workers=workers, failed=_failed)


def _run_dask(tasks: Sequence[Task], settings: Settings, scheduler) -> Iterator[Outcome]:
    distributed = DASK.require()

    if settings.threads is None:  # a worker runs one task per thread
        settings = replace(settings, threads=1)
    own_client = not isinstance(scheduler, distributed.Client)
    client = distributed.Client(scheduler, set_as_default=False) if own_client else scheduler
    futures = {}
    try:
        submitted = client.map(compute_task, list(tasks), [settings] * len(tasks), pure=False)
        futures = dict(zip(submitted, tasks, strict=True))  # one message for the whole batch
        for future in distributed.as_completed(list(futures), loop=client.loop):
            try:
                yield future.result()
            except Exception as exc:  # the task itself never raises: this is the cluster
                task = futures[future]
                reason = error_reason(exc)
                yield Outcome(task.index, error_record(task.file, reason, keys=task.keys))
    finally:
        client.cancel(list(futures))
        if own_client:
            client.close()


def replaced_message(directory: str, name: str, previous: str | None, source: str) -> str:
    """The warning for per-vertex files of another mesh that are about to be replaced."""
    files = os.path.join(directory, name + OUTPUT_SUFFIX + ".*")
    was = f"written for {previous!r}" if previous else "not recorded as this mesh's"
    return (
        f"per-vertex files {files!r} ({was}) are replaced by those of {source!r}: give each "
        "batch its own per-vertex folder to keep both"
    )


def plan_batch(
    files: Sequence[str],
    settings: Settings,
    *,
    per_vertex_dir: str | os.PathLike | None = None,
    per_vertex: PerVertexOptions | None = None,
    keep_results: bool = False,
    absolute: bool = False,
    batch: Sequence[str] | None = None,
) -> list[Task]:
    """Tasks for `files` (in order): display names, paths to open, output names.

    `per_vertex` says what the files in `per_vertex_dir` are written as
    (formats, colour limits); by default PLY and CSV coloured at the 98th
    percentile of each mesh's ``|local_curvature|``.  The per-vertex base
    names are unique within `batch` (default `files`): pass every file of a
    resumed batch, so that a file keeps its name whichever files are left.
    """
    every = list(files) if batch is None else list(batch)
    unique = dict(zip(every, per_vertex_names(every), strict=True))
    names = [unique[f] if f in unique else per_vertex_names([f])[0] for f in files]
    per_vertex = PerVertexOptions() if per_vertex is None else per_vertex
    directory = None if per_vertex_dir is None else os.path.abspath(os.fspath(per_vertex_dir))
    return [
        Task(
            index=i,
            file=file,
            path=os.path.abspath(file) if absolute else file,
            per_vertex_dir=directory,
            per_vertex_name=name,
            keep_result=keep_results,
            per_vertex=per_vertex,
            keys=settings.keys(),
        )
        for i, (file, name) in enumerate(zip(files, names, strict=True))
    ]


def run_tasks(
    tasks: Sequence[Task],
    settings: Settings,
    *,
    jobs: int = 1,
    scheduler=None,
    on_phase: PhaseCallback | None = None,
) -> Iterator[Outcome]:
    """Compute `tasks`, yielding each outcome as it completes (in any order).

    ``on_phase`` reports the phases within each mesh; it is only called when
    the meshes run one at a time in this process (``jobs=1``, no scheduler).
    Closing the iterator early (or Ctrl-C while iterating) stops the workers.
    A local worker that dies (killed by the out-of-memory killer, say) costs
    only the file it held, whose record says so.
    """
    if scheduler is not None:
        return _run_dask(tasks, settings, scheduler)
    return _run_local(tasks, settings, jobs, on_phase)


def _check_jobs(jobs) -> int:
    if isinstance(jobs, bool) or not isinstance(jobs, int) or jobs < 0:
        raise ValueError(f"jobs must be a non-negative integer (0: all cores); got {jobs!r}")
    return jobs or available_cores()


def compute_batch(
    paths: str | os.PathLike | Iterable[str | os.PathLike],
    *,
    bandwidth: float = 0.08,
    cutoff: float = 0.0,
    distance_type: str = "euclidean",
    sign_method: str = "centroid",
    method: str = "auto",
    jobs: int = 1,
    threads: int | None = None,
    geometry: str | None = None,
    metrics: str | Iterable[str] = ("ariadne",),
    alpha: float = 0.075,
    find_alpha: bool = False,
    opcr_steps: int = 8,
    opcr_step: float = 5.625,
    min_faces: int = 3,
    min_area: float = 0.0,
    dne_outliers: float = 0.1,
    dne_boundary: str = "vertex",
    dne_kappa: float = 0.0,
    arc_boundary: str = "vertex",
    arc_range: tuple[float, float] = (0.01, 0.99),
    orient: str = "auto",
    duplicates: str = "drop",
    prepare=None,
    unit=None,
    mt_condition_check: bool = True,
    mt_outliers: str = "energy",
    mt_percentile: float = 99.9,
    mt_smooth: bool = False,
    mt_min_patch: int = 5,
    pcv_rays: int = 256,
    pcv_hemisphere: bool = True,
    pcv_method: str = "cloudcompare",
    scheduler=None,
    resume_from: str | os.PathLike | Iterable[dict] | None = None,
    per_vertex_dir: str | os.PathLike | None = None,
    per_vertex_formats: str | Iterable[str] = DEFAULT_PER_VERTEX_FORMATS,
    per_vertex_limits: float | tuple[float, float] | None = None,
    per_vertex_percentile: float = 98.0,
    progress: ProgressCallback | None = None,
) -> BatchResult:
    """Compute ariaDNE (and molaR's topography metrics) for many mesh files; one record per file.

    Parameters
    ----------
    paths : path-like or iterable of path-like
        Mesh files, directories (searched recursively for the formats trimesh
        reads; hidden entries skipped) and shell-style glob patterns.  A file
        reached twice is computed once.
    bandwidth, cutoff, distance_type, sign_method, method
        As for :func:`dentopo.ariaDNE`.
    jobs : int, default 1
        Worker processes; 0 uses every core.  Results do not depend on it.
    threads : int, optional
        numba threads per mesh.  By default numba's own choice when one mesh
        runs at a time, and the cores shared out when several do.
    geometry : str, optional
        For files that hold several meshes (GLB/glTF, 3MF, OBJ with several
        objects): the name of the one to measure, or ``"all"`` to join them
        into one surface (see :func:`dentopo.load_mesh`).  By default such a
        file gets an error row listing its meshes; a file without a mesh of
        that name gets an error row too.  Rows are then not resumed.
    metrics : str or iterable of str, default ("ariadne",)
        What each row holds: some of :data:`dentopo.topography.METRICS`
        (``"ariadne"``, molaR's ``"classic"`` (classic DNE), ``"rfi"``,
        ``"opcr"``, ``"opc"``, ``"slope"``, ``"arc"``, and doolkit's), molaR's
        or doolkit's names for them in any case (``"DNE"``, ``"OPCr"``,
        ``"inclin"`` ...), ``"molar"`` or ``"doolkit"`` for each tool's set, or
        ``"all"``.  A metric that fails on a mesh
        leaves its cells empty and names its error; the row keeps the other
        metrics and has ``status="partial"``.
    alpha, find_alpha : float, bool
        As for :func:`dentopo.rfi`.
    opcr_steps, opcr_step, min_faces, min_area : int, float, int, float
        As for :func:`dentopo.opcr` (``steps``, ``step``, ``min_faces``,
        ``min_area``) and :func:`dentopo.opc`.
    dne_outliers, dne_boundary, dne_kappa : float, str, float
        Classic DNE's ``outliers``, ``boundary`` and ``kappa``
        (:func:`dentopo.topography.classic_dne`).
    arc_boundary, arc_range : str, (float, float)
        ARC's ``boundary`` and ``range`` (:func:`dentopo.topography.arc`).
    orient : {"auto", "as-is"}, default "auto"
        ``"auto"`` turns a crown that points to -z (away from its open base)
        before slope, OPC, OPCR, RFI and doolkit's oriented metrics (see
        :func:`dentopo.find_orientation`) and rewinds faces wound inward
        before those and classic DNE; a closed or flat surface is measured
        as it lies, with a warning.  ``"as-is"`` measures it as it is, as
        molaR and doolkit do (their numbers), and warns.
    duplicates : {"drop", "keep"}, default "drop"
        Faces listed more than once: measured once (``"drop"``, as ariaDNE's
        cleaning and the ``faces`` column count them) or as listed by molaR's
        metrics (``"keep"``, molaR's behaviour); warned about either way (see
        :func:`dentopo.topography.prepare_surface`).
    unit : str, float or None, default None
        The meshes' length unit (``"um"``, ``"mm"``, ``"cm"``, ``"m"``, ``"in"``
        or millimetres per unit): doolkit's metrics whose definitions assume
        millimetres (angularity, relief index, doolkit's ARC, shape index,
        footprint, hypsodonty) are measured on the crown in millimetres, their
        lengths and areas given back in the mesh's unit.  None: taken as
        millimetres, and the rows warn where that matters (see
        :class:`dentopo.batch.TopographyOptions`).
    mt_condition_check, mt_outliers, mt_percentile, mt_smooth, mt_min_patch
        MorphoTester's options (:class:`dentopo.batch.TopographyOptions`): its
        DNE's condition-number check, outlier type (``"energy"``,
        ``"energy_area"`` or ``"off"``), percentile and implicit fairing, and its
        OPCR's smallest patch.  Defaults: its published results' settings.
        MorphoTester's metrics measure each PLY file as MorphoTester reads it
        (nothing cleaned, ASCII coordinates as float64 from their text).
    pcv_rays, pcv_hemisphere, pcv_method : int, bool, str
        PCV's light directions and method (:func:`dentopo.topography.pcv`;
        CloudCompare's defaults: 256 directions, the northern hemisphere,
        its depth buffers).
    prepare : Protocol, str or path-like, optional
        A preparation protocol (a :class:`dentopo.Protocol`, the name of a
        shipped one, see :func:`dentopo.prepare.named_protocols`, or a TOML
        file): each mesh is read, prepared in memory with it
        (:func:`dentopo.prepare`: clean, orient, crop, decimate, smooth) and
        the prepared crown measured; its per-vertex files are the prepared
        mesh's.  The protocol is checked before any file; the ``protocol``
        column holds its label (``"name digest12"``), the row's ``warnings``
        the preparation's (``prepare: ...``), and a step that fails (a crop
        that leaves nothing) is that file's error row.  Resumed rows must
        have the same protocol digest.
    scheduler : str or distributed.Client, optional
        Address of a Dask distributed scheduler (``"tcp://host:8786"``) or a
        client: run on that cluster instead of local processes (``jobs`` is
        then ignored).  The files must be readable by the workers under the
        same absolute paths (a shared file system).
    resume_from : path-like or iterable of dict, optional
        A previous output table (or its records): files with an ``ok`` row
        computed with the same settings (bandwidth, cutoff, distance type,
        sign method, and method unless it is ``"auto"``) are not
        computed again, and the previous rows are kept in the result.
    per_vertex_dir : path-like, optional
        Existing directory for each mesh's per-vertex files,
        ``<name>.dentopo.<format>`` (see :func:`dentopo.write_per_vertex`).
        Names are unique within the batch; the directory records which mesh
        each name was written for (``.dentopo-sources.jsonl``), and replacing
        the files of another mesh (another batch's ``tooth.ply``) warns.  A
        file that cannot be written gives that mesh an error row naming it.
    per_vertex_formats : str or iterable of str, default ("ply", "csv")
        Which per-vertex files: some of ``"ply"``, ``"vtp"``, ``"npz"``,
        ``"csv"`` (or one comma-separated string).
    per_vertex_limits : float or (float, float), optional
        Fixed limits ``L`` or ``(-L, L)`` of the per-vertex colours, the same
        for every mesh; by default each mesh's own `per_vertex_percentile`.
    per_vertex_percentile : float, default 98
        The colour limit's percentile of ``|local_curvature|`` otherwise.
    progress : callable, optional
        ``progress(done, total, record)``, called after each file.

    Returns
    -------
    BatchResult
        A ``list`` of dicts, one record per file, sorted by file;
        ``result.to_dataframe()`` makes it a pandas DataFrame in one call
        (columns in table order; ``pandas.DataFrame(result)`` works too), and
        a notebook shows it as a table.  For ariaDNE alone, the keys of
        :data:`dentopo.COLUMNS`: ``file``, the scalar fields of
        :class:`dentopo.AriaDNEResult`, ``seconds``, ``status`` (``"ok"`` or
        ``"error"``) and ``error`` (the reason, or None); other metrics add
        their keys (:func:`dentopo.formats.record_keys`).  Numbers are None
        where they could not be computed.

    Raises
    ------
    ValueError
        If no mesh file is found, or an option is invalid.
    dentopo._optional.MissingExtraError
        An ``ImportError``: a `scheduler` without dask.distributed
        (``pip install 'dentopo[cluster]'``, in a clone ``pip install '.[cluster]'``),
        or ``method="fast"`` without finufft (``pip install 'dentopo[fast]'``, in a
        clone ``pip install '.[fast]'``), before any file is computed.

    Warns
    -----
    UserWarning
        For each file whose computation warned, prefixed with the file name;
        for per-vertex files of another mesh that are replaced.

    Examples
    --------
    >>> from dentopo import compute_batch
    >>> table = compute_batch("scans/", jobs=0).to_dataframe()  # doctest: +SKIP
    >>> table.set_index("file")["dne"]  # doctest: +SKIP
    """
    if isinstance(paths, (str, os.PathLike)):
        paths = [paths]
    found = find_mesh_files(paths)
    if not found.files:
        raise ValueError(
            "no mesh files found" + (f" in {found.unmatched}" if found.unmatched else "")
        )
    jobs = _check_jobs(jobs)
    settings = make_settings(
        bandwidth=bandwidth,
        cutoff=cutoff,
        distance_type=distance_type,
        sign_method=sign_method,
        method=method,
        threads=threads,
        geometry=geometry,
        metrics=metrics,
        alpha=alpha,
        find_alpha=find_alpha,
        opcr_steps=opcr_steps,
        opcr_step=opcr_step,
        min_faces=min_faces,
        min_area=min_area,
        dne_outliers=dne_outliers,
        dne_boundary=dne_boundary,
        dne_kappa=dne_kappa,
        arc_boundary=arc_boundary,
        arc_range=arc_range,
        orient=orient,
        duplicates=duplicates,
        prepare=prepare,
        unit=unit,
        mt_condition_check=mt_condition_check,
        mt_outliers=mt_outliers,
        mt_percentile=mt_percentile,
        mt_smooth=mt_smooth,
        mt_min_patch=mt_min_patch,
        pcv_rays=pcv_rays,
        pcv_hemisphere=pcv_hemisphere,
        pcv_method=pcv_method,
    )
    check_extras(settings, scheduler=scheduler)
    if per_vertex_dir is not None and not os.path.isdir(per_vertex_dir):
        raise ValueError(f"per_vertex_dir {os.fspath(per_vertex_dir)!r} is not a directory")
    per_vertex = PerVertexOptions(
        formats=per_vertex_formats, limits=per_vertex_limits, percentile=per_vertex_percentile
    )
    previous: list[dict] = []
    if resume_from is not None:
        if isinstance(resume_from, (str, os.PathLike)):
            previous = read_table(resume_from) if os.path.exists(resume_from) else []
        else:
            previous = [dict(r) for r in resume_from]
    done = resumable_files(previous, settings)
    previous = relabel_resumed(previous, settings)
    todo = [f for f in found.files if os.path.abspath(f) not in done]

    tasks = plan_batch(
        todo,
        settings,
        per_vertex_dir=per_vertex_dir,
        per_vertex=per_vertex,
        absolute=scheduler is not None,
        batch=found.files,
    )
    for directory, name, previous, source in replaced_per_vertex_files(tasks):
        warnings.warn(
            replaced_message(directory, name, previous, source), UserWarning, stacklevel=2
        )
    records: list[dict | None] = [None] * len(tasks)
    for count, outcome in enumerate(run_tasks(tasks, settings, jobs=jobs, scheduler=scheduler)):
        records[outcome.index] = outcome.record
        for message in outcome.warnings:
            warnings.warn(f"{outcome.record['file']}: {message}", UserWarning, stacklevel=2)
        if progress is not None:
            progress(count + 1, len(tasks), outcome.record)
    return BatchResult(merge_records(previous, records))
