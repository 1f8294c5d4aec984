"""Many meshes at once: finding the files, and computing them in parallel.

``_inputs`` turns files, folders and glob patterns into a sorted list of mesh
files; ``_runner`` computes them (one process, a local pool of workers, or a
Dask cluster), one record per file, resumable, one bad file never stopping the
batch: ``_settings`` holds what a batch computes with (checked before any file),
``_task`` the computation of one file and its record (``_measure`` its metrics),
``_resume`` which rows of a previous table are kept.  ``_pool`` is the local
pool, which survives a worker's death;
``_interrupts`` makes Ctrl-C and SIGTERM stop a batch, never inside a critical section;
``_warmup`` compiles a batch's kernels before its meshes (once per machine);
``_prepare`` prepares raw scans (:mod:`dentopo.prepare`) in a batch, a mesh and a record each.

May import: :mod:`dentopo.ariadne`, :mod:`dentopo.sign`, :mod:`dentopo.topography`,
:mod:`dentopo.prepare` (a protocol run on each mesh before it is measured),
:mod:`dentopo.formats`, :mod:`dentopo.samples` (the crown a warm-up computes).  Nothing from
figures, study or cli.
"""

from ._inputs import (
    FORMAT_PACKAGES,
    MESH_EXTENSIONS,
    OUTPUT_FOLDER_MARK,
    FoundInputs,
    find_mesh_files,
    is_own_output,
    is_own_output_folder,
)
from ._interrupts import Interrupted, guard_interrupts
from ._pool import run_pool
from ._prepare import (
    PrepareOutcome,
    PrepareTask,
    is_done,
    output_names,
    plan_preparation,
    prepare_task,
    run_preparation,
)
from ._result import BatchResult, to_dataframe
from ._resume import merge_records, protocol_digest, relabel_resumed, resumable_files
from ._runner import (
    available_cores,
    compute_batch,
    plan_batch,
    replaced_message,
    replaced_per_vertex_files,
    run_tasks,
)
from ._settings import Settings, check_extras, make_settings
from ._task import (
    Outcome,
    Task,
    compute_task,
    error_reason,
    error_record,
    planned_per_vertex_files,
    prepared_mesh,
)
from ._warmup import (
    WarmUp,
    estimated_seconds,
    kernel_cache,
    metric_groups,
    missing_metrics,
    warm_up,
    warm_up_wanted,
)

__all__ = [
    "FORMAT_PACKAGES",
    "MESH_EXTENSIONS",
    "OUTPUT_FOLDER_MARK",
    "BatchResult",
    "FoundInputs",
    "Interrupted",
    "Outcome",
    "PrepareOutcome",
    "PrepareTask",
    "Settings",
    "Task",
    "WarmUp",
    "available_cores",
    "check_extras",
    "compute_batch",
    "compute_task",
    "error_reason",
    "error_record",
    "estimated_seconds",
    "find_mesh_files",
    "guard_interrupts",
    "is_done",
    "is_own_output",
    "is_own_output_folder",
    "kernel_cache",
    "make_settings",
    "merge_records",
    "metric_groups",
    "missing_metrics",
    "output_names",
    "plan_batch",
    "plan_preparation",
    "planned_per_vertex_files",
    "prepare_task",
    "prepared_mesh",
    "protocol_digest",
    "relabel_resumed",
    "replaced_message",
    "replaced_per_vertex_files",
    "resumable_files",
    "run_pool",
    "run_preparation",
    "run_tasks",
    "to_dataframe",
    "warm_up",
    "warm_up_wanted",
]
