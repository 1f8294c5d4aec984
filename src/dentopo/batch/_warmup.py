"""A batch's kernels compiled before its meshes: once per machine, on the cores it was given.

numba compiles each kernel on its first call and keeps it in its cache, so a
fresh install's first run spends most of its time compiling.  Left to
themselves, the worker processes of a ``jobs > 1`` run would each compile the
same kernels (twice the work on two cores, and slower than one process).
:func:`warm_up` instead computes the batch's metrics, with its settings, on the
bundled sample crown first: in this process for one job, or in processes of
its own for more, the metrics shared among them by their compile times, so
that the workers find every kernel in the cache.

A stamp in numba's cache records each metric whose kernels were compiled, for
this version of dentopo's sources, this numba and this processor: a warm run
reads a few file names and starts nothing.  A mesh can still take a path the
sample did not (a million vertices run some kernels in parallel that a small
crown runs on one thread): that kernel is compiled where it is first called,
and the batch says so (:attr:`Outcome.compiled <dentopo.batch.Outcome>`).
"""

from __future__ import annotations

import hashlib
import os
import time
import warnings
from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, replace
from multiprocessing import get_context

from ..topography import DOOLKIT_METRICS, MOLAR_METRICS, MORPHOTESTER_METRICS
from ._settings import Settings

#: CPU seconds a fresh install spends compiling the kernels of each metric (one core of
#: this two-core machine, measured with an empty cache, metric by metric in the order of
#: ``--metrics all``: what a metric shares with one before it is counted once, with the
#: first).  The estimate said before compiling; a parallel warm-up takes about its largest group.
COMPILE_SECONDS = {
    "ariadne": 6.5,  # the kernel sums, the eigen-solvers and ariaDNE's sign
    "classic": 3.0,  # with molaR's surface preparation, which the molaR metrics share
    "rfi": 7.0,  # molaR's footprint: the certified Delaunay sweep and the alpha hull
    "opcr": 0.5,
    "opc": 0.5,
    "slope": 0.5,
    "arc": 1.0,
    "doolkit_slope": 1.0,
    "angularity": 0.5,
    "relief_index": 8.5,  # doolkit's footprint: concaveman and its R-tree
    "inclination": 0.5,
    "doolkit_opc": 1.0,
    "doolkit_opcr": 0.5,
    "doolkit_arc": 0.5,
    "doolkit_dne": 0.5,
    "relief_rate": 0.5,
    "shape_index": 0.5,
    "footprint": 0.5,
    "hypsodonty": 0.5,
    "morphotester_dne": 1.0,
    "morphotester_rfi": 0.5,
    "morphotester_opcr": 0.5,
    "rfi_projected": 1.0,
    "pcv": 2.5,
}

#: ``DENTOPO_WARMUP=0`` in the environment: a batch compiles nothing before its meshes (each
#: compiles what it needs as it goes, in each worker), as before there was a warm-up.
WARMUP_ENV = "DENTOPO_WARMUP"


def warm_up_wanted() -> bool:
    """Whether a batch compiles its kernels before its meshes (unless ``DENTOPO_WARMUP=0``)."""
    return os.environ.get(WARMUP_ENV, "").strip() != "0"


#: What every metric compiles first (reading and cleaning the mesh), in each process.
SHARED_SECONDS = 4.5


def estimated_seconds(metrics: Sequence[str], processes: int = 1) -> float:
    """Seconds (wall) a fresh install takes to compile the kernels of `metrics`."""
    groups = metric_groups(metrics, processes)
    return max((SHARED_SECONDS + sum(_cost(m) for m in group) for group in groups), default=0.0)


def _cost(metric: str) -> float:
    return COMPILE_SECONDS.get(metric, 1.0)


def metric_groups(metrics: Sequence[str], processes: int) -> list[tuple[str, ...]]:
    """`metrics` shared among at most `processes` groups of about equal compile time.

    The largest first, each to the group with the least so far (the greedy rule); a
    family's small metrics (doolkit's, molaR's) stay together where they share kernels.
    """
    metrics = list(dict.fromkeys(metrics))
    if processes <= 1 or len(metrics) <= 1:
        return [tuple(metrics)] if metrics else []
    families: dict[str, list[str]] = {}
    for metric in metrics:
        families.setdefault(_family(metric), []).append(metric)
    parts = []  # the big ones alone, a family's small ones together
    for members in families.values():
        small = [m for m in members if _cost(m) < 2.0]
        parts.extend([m] for m in members if _cost(m) >= 2.0)
        if small:
            parts.append(small)
    parts.sort(key=lambda part: -sum(_cost(m) for m in part))
    groups: list[list[str]] = [[] for _ in range(min(processes, len(parts)))]
    for part in parts:
        min(groups, key=lambda g: sum(_cost(m) for m in g)).extend(part)
    order = {metric: i for i, metric in enumerate(metrics)}
    return [tuple(sorted(g, key=order.__getitem__)) for g in groups if g]


def _family(metric: str) -> str:
    if metric in MOLAR_METRICS:
        return "molar"
    if metric in DOOLKIT_METRICS:
        return "doolkit"
    if metric in MORPHOTESTER_METRICS:
        return "morphotester"
    return metric


@dataclass(frozen=True)
class WarmUp:
    """What :func:`warm_up` did.

    Attributes
    ----------
    compiled : float
        Seconds spent compiling, in all its processes (0.0: every kernel came from
        numba's cache, or every metric's stamp was found).
    seconds : float
        Wall seconds it took.
    processes : int
        Processes it compiled in (0 when nothing was compiled).
    cache : str
        Where numba keeps dentopo's kernels (:func:`kernel_cache`).
    """

    compiled: float
    seconds: float
    processes: int
    cache: str


def kernel_cache() -> str:
    """Where numba keeps dentopo's compiled kernels on this machine, in words.

    ``NUMBA_CACHE_DIR`` if it is set; else numba's choice, usually the
    ``__pycache__`` folders beside dentopo's modules.
    """
    import numba

    if numba.config.CACHE_DIR:
        return os.path.abspath(numba.config.CACHE_DIR)
    root = _stamp_root()
    package = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    if root.startswith(package + os.sep):
        return f"the __pycache__ folders under {package}"
    return root


def _stamp_root() -> str:
    """The folder numba caches dentopo's ariaDNE kernel in (its locator's choice)."""
    from ..ariadne import _kernel

    try:
        return os.path.abspath(_kernel._half_sums._cache._cache_path)
    except AttributeError:  # numba's private layout changed: beside the module
        return os.path.join(os.path.dirname(os.path.abspath(_kernel.__file__)), "__pycache__")


def _fingerprint() -> str:
    """dentopo's sources (names, sizes, times), numba's version and this processor."""
    import llvmlite.binding
    import numba

    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    digest = hashlib.sha256()
    for folder, dirnames, filenames in os.walk(root):
        dirnames[:] = sorted(d for d in dirnames if d != "__pycache__")
        for name in sorted(filenames):
            if name.endswith(".py"):
                stat = os.stat(os.path.join(folder, name))
                digest.update(
                    f"{folder[len(root) :]}/{name}:{stat.st_size}:{stat.st_mtime_ns}".encode()
                )
    digest.update(f"{numba.__version__}|{llvmlite.binding.get_host_cpu_name()}".encode())
    digest.update(str(numba.config.CACHE_DIR).encode())
    return digest.hexdigest()


def _stamp_path(metric: str, settings: Settings, fingerprint: str) -> str:
    """The stamp of `metric`'s kernels with the settings that choose kernels."""
    choice = (
        metric,
        settings.distance_type,
        settings.sign_method,
        settings.method,
        settings.topography.pcv_method,
        settings.prepare is not None,
        fingerprint,
    )
    name = hashlib.sha256(repr(choice).encode()).hexdigest()[:24]
    return os.path.join(_stamp_root(), "dentopo-warm", name)


def missing_metrics(settings: Settings, fingerprint: str | None = None) -> tuple[str, ...]:
    """The metrics of `settings` whose kernels have no stamp (not yet compiled here)."""
    fingerprint = _fingerprint() if fingerprint is None else fingerprint
    return tuple(
        m for m in settings.metrics if not os.path.exists(_stamp_path(m, settings, fingerprint))
    )


def _compute_sample(settings: Settings) -> float:
    """The sample crown computed with `settings` in this process; seconds spent compiling."""
    from .._jit import compile_seconds
    from ..samples import sample_paths
    from ._task import Task, compute_task

    before = compile_seconds()
    tooth = str(sample_paths()["tooth"])
    compute_task(Task(index=0, file=tooth, path=tooth, keys=settings.keys()), settings)
    extras = []
    if "rfi" in settings.metrics:  # its alpha hull's arcs: the sample's fail at molaR's alpha
        extras.append(_rfi_arcs)
    if "ariadne" in settings.metrics and settings.method == "auto":
        extras.append(_large_mesh_paths)
    for extra in extras:
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # the sample's, not the batch's
                extra(tooth, settings)
        except Exception:  # what ran is compiled; a mesh compiles the rest if it needs it
            pass
    return compile_seconds() - before


def _large_mesh_paths(path: str, settings: Settings) -> None:
    """What ariaDNE runs on a large mesh only: the fast kernel sums (``method="auto"`` from
    20,000 vertices).  (Its eigen-solver on several threads is the same compiled kernel.)"""
    from ..ariadne import ariaDNE

    options = {**settings.options(), "method": "fast"}
    ariaDNE(path, **options)


#: The alpha at which the jittered sample's alpha hull holds (molaR's 0.075 fails on it).
SAMPLE_ALPHA = 0.5


def _rfi_arcs(path: str, settings: Settings) -> None:
    """molaR's RFI on the sample crown made slightly irregular, at an alpha that holds.

    The symmetric sample stops at molaR's alpha before the hull's arcs are chained (as
    many small crowns do, where a real crown goes on): this compiles the rest.
    """
    import numpy as np
    import trimesh

    from ..mesh import load_mesh
    from ._measure import measure_mesh

    mesh = load_mesh(path)
    vertices = np.array(mesh.vertices, dtype=np.float64)
    index = np.arange(len(vertices))
    vertices[:, 0] += 0.01 * np.sin(1.7 * index)  # no symmetry left for the hull to stop at
    vertices[:, 1] += 0.01 * np.cos(2.3 * index)
    irregular = trimesh.Trimesh(vertices, np.array(mesh.faces), process=False)
    options = replace(settings.topography, alpha=SAMPLE_ALPHA, find_alpha=False)
    measure_mesh(irregular, ("rfi",), options=options)


def _compute_in_worker(settings: Settings) -> float:
    """In a warm-up process: one numba thread (the cores are shared among the groups)."""
    import numba

    numba.set_num_threads(1)
    return _compute_sample(settings)


def warm_up(settings: Settings, *, jobs: int = 1, force: bool = False) -> WarmUp:
    """Compile (or find in numba's cache) the kernels a batch with `settings` needs.

    The bundled sample crown is computed with `settings`: in this process if
    `jobs` is 1, else in up to `jobs` processes at once, the metrics shared
    among them (:func:`metric_groups`).  Metrics whose stamp is found are left
    out (all of them: nothing starts), unless `force`.  Per-vertex files and
    the sample's record are not kept; a metric that fails on the sample still
    compiles what it ran.
    """
    started = time.perf_counter()
    fingerprint = _fingerprint()  # of the sources compiled, not of any changed meanwhile
    missing = settings.metrics if force else missing_metrics(settings, fingerprint)
    if not missing:
        return WarmUp(0.0, time.perf_counter() - started, 0, kernel_cache())
    groups = metric_groups(missing, jobs)
    if len(groups) <= 1:
        compiled = _compute_sample(replace(settings, metrics=tuple(missing)))
    else:
        with ProcessPoolExecutor(len(groups), mp_context=get_context("spawn")) as pool:
            calls = [replace(settings, metrics=g) for g in groups]
            compiled = sum(pool.map(_compute_in_worker, calls))
    for metric in missing:
        path = _stamp_path(metric, settings, fingerprint)
        try:
            os.makedirs(os.path.dirname(path), exist_ok=True)
            with open(path, "w", encoding="ascii") as stamp:
                stamp.write(metric + "\n")
        except OSError:  # a read-only cache: compiled each time, as without a stamp
            pass
    return WarmUp(round(compiled, 3), time.perf_counter() - started, len(groups), kernel_cache())
