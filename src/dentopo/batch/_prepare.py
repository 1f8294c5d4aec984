"""Batches of preparation: raw scans to prepared crowns, a mesh file and a record each.

:func:`plan_preparation` names each input's outputs below one folder,
mirroring the input folders' tree: a folder given is the root of its files
(``raw/a/t.ply`` given as ``raw/`` goes to ``OUT/a/t.ply``), a file given
goes to the top (``OUT/t.ply``), a glob's files below the folder before its
first wildcard.  Two inputs that would land on the same name get a short hash
of their path appended, as the per-vertex files do.  :func:`prepare_task`
prepares one file (never raising for a bad file), :func:`run_preparation`
runs tasks here or in the local pool (:func:`run_pool`).  The outputs of one
file do not depend on how many run side by side.
"""

from __future__ import annotations

import glob
import hashlib
import os
import time
import warnings
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass, field, replace

from ..formats import RECORD_SUFFIX, read_record, safe_folder, sha256_file, write_prepared
from ..mesh import load_mesh
from ._errors import failure_reason
from ._interrupts import Interrupted, guard_interrupts
from ._pool import run_pool

#: The suffix of a prepared crown's mesh file.
MESH_SUFFIX = ".ply"

#: The suffix of a preview picture.
PREVIEW_SUFFIX = ".png"


@dataclass(frozen=True)
class PrepareTask:
    """One file to prepare: where to read it and where its outputs go.

    Attributes
    ----------
    index : int
    file : str
        The input as the user gave it (recorded, shown).
    path : str
        Where it is opened.
    name : str
        Its outputs' path below the output folder, without suffix (``a/tooth``).
    output : str
        The output folder.
    preview : str or None
        The preview folder, if previews are drawn.
    """

    index: int
    file: str
    path: str
    name: str
    output: str
    preview: str | None = None

    @property
    def mesh_path(self) -> str:
        return os.path.join(self.output, self.name + MESH_SUFFIX)

    @property
    def record_path(self) -> str:
        return os.path.join(self.output, self.name + RECORD_SUFFIX)

    @property
    def preview_path(self) -> str | None:
        if self.preview is None:
            return None
        return os.path.join(self.preview, self.name + PREVIEW_SUFFIX)

    def outputs(self) -> list[str]:
        """Every file the task writes."""
        found = [self.mesh_path, self.record_path]
        return found + ([self.preview_path] if self.preview is not None else [])


@dataclass(frozen=True)
class PrepareOutcome:
    """What preparing one file did: a status (``ok``, ``error``, ``skipped``) and its effects."""

    index: int
    file: str
    status: str
    error: str | None = None
    seconds: float | None = None
    warnings: tuple[str, ...] = ()
    faces: tuple[int, int] | None = None  # before and after
    details: dict = field(default_factory=dict)

    @property
    def record(self) -> dict:
        """A progress row (``file``, ``status``, ``error``, ``seconds``)."""
        return {
            "file": self.file,
            "status": self.status,
            "error": self.error,
            "seconds": self.seconds,
        }


def _glob_root(pattern: str) -> str:
    """The folder of a glob pattern before its first wildcard (``scans`` of ``scans/**/*.ply``)."""
    parts = pattern.split(os.sep)
    kept = []
    for part in parts[:-1]:
        if glob.has_magic(part):
            break
        kept.append(part)
    return os.sep.join(kept) if kept else os.curdir


def input_roots(inputs: Iterable[str | os.PathLike]) -> list[str]:
    """The folders given (and the folders of the globs given), absolute: their files' roots.

    A file given by name is no root for others: it goes to the top of the
    output folder unless a folder given holds it.
    """
    roots = []
    for item in inputs:
        path = os.fspath(item)
        if os.path.isdir(path):
            root = path
        elif os.path.lexists(path) or not glob.has_magic(path):
            continue
        else:
            root = _glob_root(path)
        roots.append(os.path.normpath(os.path.abspath(root)))
    return roots


def _relative(file: str, roots: Sequence[str]) -> str:
    """`file`'s path from the widest root that holds it (its name alone if none does)."""
    absolute = os.path.normpath(os.path.abspath(file))
    holding = [r for r in roots if os.path.commonpath([absolute, r]) == r and absolute != r]
    if holding:
        relative = os.path.relpath(absolute, min(holding, key=len))
        if not relative.startswith(os.pardir + os.sep) and relative != os.pardir:
            return relative
    return os.path.basename(absolute)


def output_names(files: Sequence[str], inputs: Iterable[str | os.PathLike]) -> list[str]:
    """Each file's outputs' path below the output folder, without suffix; unique."""
    roots = input_roots(inputs)
    stems = [os.path.splitext(_relative(f, roots))[0] for f in files]
    counts: dict[str, int] = {}
    for stem in stems:
        key = os.path.normcase(stem)
        counts[key] = counts.get(key, 0) + 1
    names = []
    for stem, file in zip(stems, files, strict=True):
        if counts[os.path.normcase(stem)] > 1:
            digest = hashlib.sha1(os.path.abspath(file).encode("utf-8", "surrogatepass"))
            stem = f"{stem}-{digest.hexdigest()[:8]}"
        names.append(stem)
    return names


def plan_preparation(
    files: Sequence[str],
    inputs: Iterable[str | os.PathLike],
    output: str | os.PathLike,
    *,
    preview: str | os.PathLike | None = None,
) -> list[PrepareTask]:
    """One task per file, its outputs named below `output` (and `preview`)."""
    names = output_names(files, inputs)
    output = os.fspath(output)
    preview = None if preview is None else os.fspath(preview)
    return [
        PrepareTask(index=i, file=file, path=file, name=name, output=output, preview=preview)
        for i, (file, name) in enumerate(zip(files, names, strict=True))
    ]


def is_done(task: PrepareTask, protocol, *, geometry: str | None = None) -> bool:
    """Whether `task`'s outputs are there for this input and protocol (``--resume``).

    Its record exists, names the same input bytes (SHA-256), the same
    protocol digest (and geometry), and its mesh file is there with the
    SHA-256 recorded; a preview asked for must exist too.
    """
    try:
        record = read_record(task.record_path)
        if record.get("protocol", {}).get("digest") != protocol.digest:
            return False
        if record.get("input", {}).get("geometry") != geometry:
            return False
        mesh = record.get("mesh") or {}
        if mesh.get("sha256") is None or not os.path.isfile(task.mesh_path):
            return False
        if task.preview_path is not None and not os.path.isfile(task.preview_path):
            return False
        if record.get("input", {}).get("sha256") != sha256_file(task.path):
            return False
        return sha256_file(task.mesh_path) == mesh["sha256"]
    except (OSError, ValueError, AttributeError):
        return False


def _output_reason(exc: BaseException) -> str:
    why = getattr(exc, "strerror", None) or str(exc) or type(exc).__name__
    where = getattr(exc, "filename", None)
    where = f" {os.fspath(where)!r}" if where is not None else ""
    return f"cannot write{where}: {why} (an output failed, not the input)"


def _reason(exc: BaseException) -> str:
    if isinstance(exc, FileNotFoundError):
        return "file not found"
    if isinstance(exc, IsADirectoryError):
        return "is a directory, not a mesh file"
    if isinstance(exc, OSError):
        return f"unreadable: {exc.strerror or exc}"
    return str(exc)


#: ``render(raw_vertices, raw_faces, crown, path, title)`` draws a preview.
PreviewFunction = Callable[..., None]


def prepare_task(
    task: PrepareTask,
    protocol,
    geometry: str | None = None,
    render: PreviewFunction | None = None,
) -> PrepareOutcome:
    """Prepare one file and write its outputs; never raises for a bad file.

    The outcome's ``error`` names the step that failed (reading, a
    preparation step, writing).  An output that cannot be written is named
    as such (the input is not at fault).
    """
    from ..prepare import prepare

    start = time.perf_counter()
    step = "reading"
    crown = None
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            sha = sha256_file(task.path)
            mesh = load_mesh(task.path, geometry=geometry)
            step = "preparing"
            crown = prepare(mesh, protocol)
            crown = replace(crown, source=task.file, source_sha256=sha)
            step = "writing"
            folder = os.path.dirname(task.name)
            safe_folder(task.output, folder)
            write_prepared(
                crown, task.mesh_path, task.record_path, source=task.file, geometry=geometry
            )
            if render is not None:
                step = "drawing the preview"
                safe_folder(task.preview, folder)
                render(mesh.vertices, mesh.faces, crown, task.preview_path, title=task.file)
        except Exception as exc:  # one bad file never stops the batch
            if isinstance(exc, FileNotFoundError) and os.path.islink(task.path):
                reason = "unreadable: a broken symbolic link"
            elif step in ("writing", "drawing the preview") and isinstance(exc, OSError):
                reason = _output_reason(exc)
            elif step == "preparing":
                reason = failure_reason("prepare", exc, _reason)
            else:
                reason = failure_reason(step, exc, _reason)
            if step == "drawing the preview":
                reason = f"preview: {reason}"
            seconds = round(time.perf_counter() - start, 4)
            messages = tuple(dict.fromkeys(str(w.message) for w in caught))
            return PrepareOutcome(
                task.index, task.file, "error", " ".join(reason.split()), seconds, messages
            )
    seconds = round(time.perf_counter() - start, 4)
    messages = tuple(dict.fromkeys(str(w.message) for w in caught))
    faces = (crown.steps[0].faces_before, len(crown.faces)) if crown.steps else None
    return PrepareOutcome(task.index, task.file, "ok", None, seconds, messages, faces)


def remove_temporaries(task: PrepareTask) -> int:
    """Remove the temporary files a worker killed while writing `task`'s outputs left behind.

    Outputs are written to ``.NAME.XXXX.tmp`` beside them and renamed
    (:func:`dentopo.formats.atomic_write`); a process killed in between
    (SIGKILL, the out-of-memory killer, a pool stopped by Ctrl-C) leaves the
    temporary file, never half an output.  Returns how many were removed.
    """
    removed = 0
    for path in task.outputs():
        folder, name = os.path.split(path)
        for temporary in glob.glob(
            os.path.join(glob.escape(folder), glob.escape(f".{name}.") + "*.tmp")
        ):
            try:
                os.unlink(temporary)
                removed += 1
            except OSError:
                pass
    return removed


def _failed(task: PrepareTask, reason: str, seconds: float | None = None) -> PrepareOutcome:
    """The outcome of a task whose worker died (its temporary files removed)."""
    remove_temporaries(task)
    return PrepareOutcome(task.index, task.file, "error", reason, seconds)


def run_preparation(
    tasks: Sequence[PrepareTask],
    protocol,
    *,
    jobs: int = 1,
    geometry: str | None = None,
    render: PreviewFunction | None = None,
) -> Iterator[PrepareOutcome]:
    """Prepare `tasks`, yielding each outcome as it finishes (in any order).

    With ``jobs > 1`` the files are prepared in that many worker processes
    (a worker that dies costs only its file); otherwise here, where Ctrl-C
    and SIGTERM raise :class:`Interrupted` between files and while one is
    prepared (its outputs are written atomically: never half a file).
    `render` must be picklable (a module-level function) for workers.
    """
    if jobs > 1 and len(tasks) > 1:
        finished: set[int] = set()
        running = run_pool(
            tasks,
            prepare_task,
            (protocol, geometry, render),
            workers=min(jobs, len(tasks)),
            failed=_failed,
        )
        try:
            for outcome in running:
                finished.add(outcome.index)
                yield outcome
        finally:  # stopped early (Ctrl-C): the workers are killed, maybe while writing
            running.close()
            for task in tasks:
                if task.index not in finished:
                    remove_temporaries(task)
        return
    with guard_interrupts() as guard:
        for task in tasks:
            guard.check()
            guard.raised = None
            outcome = prepare_task(task, protocol, geometry, render)
            if guard.raised is not None:  # swallowed by library code: the outcome is not kept
                raise Interrupted(guard.raised)
            yield outcome
        guard.check()
