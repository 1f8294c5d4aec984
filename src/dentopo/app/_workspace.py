"""What the app knows of one folder: its meshes, protocols, run, results, pictures and exports.

Everything lives in the output folder (``FOLDER/dentopo-app`` unless chosen),
so that closing the tab or stopping the server loses nothing and reopening the
folder shows what is done:

* ``protocol.toml``: the folder's preparation protocol (every mesh without its own);
  ``protocols/REL.toml``: a mesh's own; ``.app/prepare.json``: whether runs prepare;
* ``results.csv`` (and its journal while a run goes): the command's table;
* ``.app/run.json``: the last run's options (the maps are drawn with them);
* ``.app/maps/``, ``.app/thumbnails/``: pictures, cached;
* ``report.html``: the collection report; ``prepared/``: the prepared meshes,
  each with its ``.prepare.json``, and the protocols they were made with.

Measuring, preparing and the report are done by the command in a child process
(:mod:`._jobs`); maps by the app's warm picture worker (:mod:`._pictures`), as the
command draws them; previews of a preparation and the tables' exports are the
library's, in this process.
"""

from __future__ import annotations

import hashlib
import io
import json
import math
import os
import threading
import zipfile
from dataclasses import dataclass, fields

import numpy as np

try:  # Python 3.11+
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - Python 3.10 (tomli: a dependency there)
    import tomli as tomllib

from ..ariadne import (
    DISTANCE_TYPES,
    METHODS,
    check_bandwidth,
    check_cutoff,
    check_distance_type,
    check_method,
)
from ..batch import OUTPUT_FOLDER_MARK, available_cores, make_settings
from ..formats import (
    COLUMNS,
    METRIC_KEYS,
    PROTOCOL_KEY,
    SETTING_KEYS,
    atomic_write,
    convert_table,
    journal_path,
    read_journal,
    read_table,
)
from ..prepare import DECIMATORS, SMOOTHERS, Protocol, ProtocolError, read_protocol
from ..sign import SIGN_METHODS, check_sign_method
from ..topography import GROUPS, METRICS, check_metrics
from ._errors import AppError
from ._folder import NOT_UNICODE, Folder, MeshEntry
from ._jobs import Job
from ._pictures import MAPS, Drawing, PictureWorker, map_request
from ._preview import preview
from ._progress import RunProgress, resumed_rows
from ._security import PathRefusedError, inside, relative_to

#: The results table, in the output folder.
TABLE = "results.csv"
#: The output folder's name inside the app's folder, unless another is chosen.
OUTPUT_NAME = "dentopo-app"
#: The table exports: format -> (suffix, MIME type).
EXPORTS = {
    "csv": (".csv", "text/csv"),
    "tsv": (".tsv", "text/tab-separated-values"),
    "xlsx": (".xlsx", "application/vnd.openxmlformats-officedocument.spreadsheetml.sheet"),
}


_MARK_TEXT = (
    "dentopo app writes into this folder. The dentopo command, searching a folder for meshes,\n"
    "skips a subfolder holding this file, so that the prepared meshes here are not measured\n"
    "again as scans.\n"
)


def _check_fields(data, kind, not_an_object: str, field: str) -> None:
    """That the page's `data` is an object of `kind`'s fields only (:class:`AppError` if not)."""
    if not isinstance(data, dict):
        raise AppError(not_an_object)
    unknown = sorted(set(data) - {f.name for f in fields(kind)})
    if unknown:
        raise AppError(f"unknown {field} {unknown[0]!r}")


@dataclass(frozen=True)
class RunOptions:
    """What a run computes: the metrics and ariaDNE's settings, workers, and whether to prepare."""

    metrics: tuple[str, ...] = ("ariadne",)
    bandwidth: float = 0.08
    cutoff: float = 0.0
    distance_type: str = "euclidean"
    sign_method: str = "centroid"
    method: str = "auto"
    jobs: int = 1
    prepare: bool = False

    @classmethod
    def from_json(cls, data) -> RunOptions:
        """Options from the page's JSON, every value checked (:class:`AppError` naming it)."""
        _check_fields(data, cls, "the run's options must be an object", "run option")
        values = {**cls().__dict__, **data}
        metrics = values["metrics"]
        if not isinstance(metrics, str) and not (
            isinstance(metrics, (list, tuple)) and all(isinstance(m, str) for m in metrics)
        ):
            raise AppError(f"metrics must be a name or a list of names; got {metrics!r:.80}")
        # the library's own checks, as the command makes them (any case; molaR's and doolkit's
        # names and the sets of metrics expanded, in table order)
        checks = {
            "metrics": check_metrics,
            "bandwidth": check_bandwidth,
            "cutoff": check_cutoff,
            "distance_type": check_distance_type,
            "sign_method": check_sign_method,
            "method": check_method,
        }
        for name, check in checks.items():
            try:
                values[name] = check(values[name])
            except (TypeError, ValueError) as exc:
                raise AppError(str(exc)) from None
        jobs = values["jobs"]
        if isinstance(jobs, bool) or not isinstance(jobs, int) or not 1 <= jobs <= 256:
            raise AppError("jobs must be a whole number from 1")
        if not isinstance(values["prepare"], bool):
            raise AppError("prepare must be true or false")
        return cls(**values)

    def ariadne(self) -> dict:
        """ariaDNE's settings, as keywords."""
        names = ("bandwidth", "cutoff", "distance_type", "sign_method", "method")
        return {name: getattr(self, name) for name in names}

    def arguments(self) -> list[str]:
        """The command's options for these settings."""
        return [
            "--metrics",
            ",".join(self.metrics),
            "--bandwidth",
            repr(self.bandwidth),
            "--cutoff",
            repr(self.cutoff),
            "--distance-type",
            self.distance_type,
            "--sign-method",
            self.sign_method,
            "--method",
            self.method,
        ]

    def to_json(self) -> dict:
        """The options as the page and ``.app/run.json`` hold them."""
        return {**self.__dict__, "metrics": list(self.metrics)}


def protocol_from_json(data) -> Protocol:
    """A :class:`Protocol` from the page's fields (:class:`AppError` naming a wrong one)."""
    _check_fields(
        data, Protocol, "the protocol must be an object of its parameters", "protocol parameter"
    )
    values = {k: (tuple(v) if isinstance(v, list) else v) for k, v in data.items()}
    values.setdefault("name", "app")
    try:
        return Protocol(**values)
    except (ProtocolError, TypeError) as exc:
        raise AppError(str(exc)) from None


class Workspace:
    """The app's state for the folder `root`, kept in the output folder `output`."""

    def __init__(self, root: str, output: str | None = None):
        self.root = os.path.realpath(root)
        if not os.path.isdir(self.root):
            raise AppError(f"not a folder: {root}")
        self._use_output(os.path.realpath(output or os.path.join(self.root, OUTPUT_NAME)))
        self._lock = threading.Lock()
        self._protocol_files: dict[str, tuple] = {}  # path -> (its stat, Protocol or reason)
        self.run: Job | None = None
        self.progress: RunProgress | None = None
        self.pictures: dict[str, Drawing] = {}
        self.drawer = PictureWorker()  # started when the server starts, or at the first map
        self.report: Job | None = None
        self.export: Job | None = None

    # -- the output folder ----------------------------------------------------------------------

    def _use_output(self, output: str, hint: str = "choose another with --output") -> None:
        """Write into `output` from now on (made, and marked as the app's, first)."""
        try:
            os.makedirs(os.path.join(output, ".app"), exist_ok=True)
            mark = os.path.join(output, OUTPUT_FOLDER_MARK)
            if not os.path.exists(mark):  # dentopo FOLDER skips it: prepared copies are no scans
                atomic_write(mark, lambda s: s.write(_MARK_TEXT))
        except OSError as exc:
            raise AppError(
                f"cannot write into the output folder {output}: {exc.strerror or exc} ({hint})"
            ) from None
        old = getattr(self, "folder", None)
        self.output = output
        self.folder = Folder(self.root, output)  # the new output folder's files are not meshes
        self.table = os.path.join(output, TABLE)
        if old is not None:
            old.close()

    def choose_output(self, relative) -> dict:
        """Write into the folder `relative` (below the app's folder) from now on; the state.

        A path from the page is data: it must be a plain relative path whose real path stays
        inside the folder (:func:`inside`: no ``..``, no absolute path, no symlink out), must
        not hold the folder's meshes, and is refused while anything runs.  What was written
        into the folder before stays there (choose it again to see it).
        """
        if not isinstance(relative, str):
            raise AppError("the output folder must be a text: a folder inside the app's folder")
        relative = relative.rstrip("/")  # "results/" is "results"; "/results" stays absolute
        try:
            output = inside(self.root, relative)
        except PathRefusedError as exc:
            raise AppError(f"refused: {exc}", 403) from None
        if os.path.exists(output) and not os.path.isdir(output):
            raise AppError(f"{relative} is a file, not a folder")
        holding = [e.path for e in self.folder.entries() if e.path.startswith(relative + "/")]
        if holding:
            raise AppError(f"{relative} holds meshes of the folder ({holding[0]}): choose another")
        with self._lock:
            jobs = (self.run, self.report, self.export, *self.pictures.values())
            if any(job is not None and job.running() for job in jobs):
                raise AppError("a run, a report, an export or a map is going: wait for it", 409)
            if output != self.output:
                self._use_output(output, "choose another")
                self.run = self.progress = self.report = self.export = None
                self.pictures = {}
        return self.state()

    # -- paths inside the output folder ---------------------------------------------------------

    def _out(self, *parts: str) -> str:
        return os.path.join(self.output, *parts)

    @property
    def protocol_file(self) -> str:
        return self._out("protocol.toml")

    def own_protocol_file(self, relative: str) -> str:
        inside(self.root, relative)  # a checked path: it cannot leave the output folder either
        return self._out("protocols", *relative.split("/")) + ".toml"

    # -- protocols ------------------------------------------------------------------------------

    def read_saved(self, path: str) -> Protocol:
        """A saved protocol file, or :class:`AppError` (409) naming it and why it cannot be read.

        The files are the app's, but an older version, a hand edit or a crash can leave one
        that does not read: the page lists it with this reason and a run or export that would
        use it is refused with it; the page's state never fails because of it.
        """
        problem = _file_problem(path, self._protocol_files)
        if isinstance(problem, Protocol):
            return problem
        shown = relative_to(self.output, path)
        raise AppError(
            f"the saved protocol {shown} cannot be read: {problem} (apply a protocol again to "
            "replace it, or remove it)",
            409,
        )

    def protocol_path(self, relative: str) -> str | None:
        """The file of the protocol a mesh is prepared with (its own, or the folder's), if any."""
        own = self.own_protocol_file(relative)
        if os.path.lexists(own):
            return own
        return self.protocol_file if os.path.lexists(self.protocol_file) else None

    def protocol_for(self, relative: str) -> tuple[Protocol | None, str | None]:
        """The protocol a mesh is prepared with, and its file (AppError if it cannot be read)."""
        path = self.protocol_path(relative)
        return (None, None) if path is None else (self.read_saved(path), path)

    def _own_protocols(self) -> dict[str, str]:
        """Each mesh with its own protocol file: relative path -> the file (one walk)."""
        found = {}
        base = self._out("protocols")
        for here, folders, names in os.walk(base):
            folders.sort()
            for name in names:
                if name.endswith(".toml"):
                    path = os.path.join(here, name)
                    found[relative_to(base, path)[: -len(".toml")]] = path
            for name in folders:  # a folder where a file should be is an unreadable protocol
                if name.endswith(".toml"):
                    path = os.path.join(here, name)
                    found[relative_to(base, path)[: -len(".toml")]] = path
        return found

    @property
    def prepares(self) -> bool:
        """Whether runs prepare each mesh with its protocol before measuring."""
        data = _read_json(self._out(".app", "prepare.json"))
        return isinstance(data, dict) and data.get("prepare") is True

    def set_prepares(self, value: bool) -> None:
        text = json.dumps({"prepare": bool(value)})
        atomic_write(self._out(".app", "prepare.json"), lambda s: s.write(text))

    def save_protocol(self, scope: str, relative: str | None, data) -> None:
        """Save (or with `data` None remove) the folder's protocol or a mesh's own."""
        if scope == "all":
            path = self.protocol_file
        elif scope == "mesh":
            if relative is None:
                raise AppError("a mesh's protocol needs the mesh's path")
            self.mesh(relative)
            path = self.own_protocol_file(relative)
        else:
            raise AppError("scope must be 'all' or 'mesh'")
        if data is None:
            if os.path.exists(path):
                os.unlink(path)
            return
        protocol = protocol_from_json(data)
        text = protocol.to_toml()
        try:  # what is saved must read back as it is: a file that does not stops every run
            back = Protocol.from_mapping(tomllib.loads(text))
        except (ValueError, TypeError) as exc:
            raise AppError(f"this protocol cannot be saved: {exc}") from None
        if back != protocol:
            raise AppError("this protocol cannot be saved: it does not read back as it is")
        os.makedirs(os.path.dirname(path), exist_ok=True)
        atomic_write(path, lambda s: s.write(text))

    def mesh(self, relative) -> MeshEntry:
        """One of the folder's meshes, by relative path (AppError: 403 out of it, 404 unknown)."""
        if not isinstance(relative, str):
            raise AppError("a path must be a text")
        try:
            return self.folder.entry(relative)
        except PathRefusedError as exc:
            raise AppError(f"refused: {exc}", 403) from None
        except KeyError:
            raise AppError("no such mesh in the folder", 404) from None

    # -- the page's state -----------------------------------------------------------------------

    def state(self) -> dict:
        """What the page shows.  Never fails because of a file: one that cannot be read is
        listed with its reason (``protocol_error``, a mesh's ``protocol_error``)."""
        self.folder.refresh()
        folder_protocol = folder_error = None
        if os.path.lexists(self.protocol_file):
            try:
                folder_protocol = self.read_saved(self.protocol_file)
            except AppError as exc:
                folder_error = str(exc)
        own = self._own_protocols()
        meshes = []
        for entry in self.folder.entries():
            item = entry.to_json()
            if entry.path in own:  # (``protocol_error`` only when there is one: 5,000 nulls weigh)
                item["protocol"] = "own"
                try:
                    self.read_saved(own[entry.path])
                except AppError as exc:
                    item["protocol_error"] = str(exc)
            else:
                item["protocol"] = "folder" if os.path.lexists(self.protocol_file) else None
            meshes.append(item)
        return {
            "folder": self.root,
            "output": self.output,
            "output_relative": _relative_inside(self.root, self.output),
            "table": self.table,
            "version": _version(),
            "meshes": meshes,
            "pending": self.folder.pending,
            "protocol": None if folder_protocol is None else folder_protocol.to_dict(),
            "protocol_label": None if folder_protocol is None else folder_protocol.label,
            "protocol_error": folder_error,
            "prepare": self.prepares,
            "choices": {
                "metrics": list(METRICS),
                "metric_groups": {k: list(v) for k, v in GROUPS.items()},
                "orient": ["occlusal", "none"],
                "keep": ["largest", "all"],
                "spin": ["none", "footprint"],
                "decimate": list(DECIMATORS),
                "smooth": list(SMOOTHERS),
                "distance_type": list(DISTANCE_TYPES),
                "sign_method": list(SIGN_METHODS),
                "method": list(METHODS),
                "maps": list(MAPS),
                "exports": list(EXPORTS),
            },
            "defaults": {**RunOptions().to_json(), "jobs": max(1, available_cores() - 1)},
            "last_run": self.last_options().to_json(),
            "run": self.run_state(),
            "results": os.path.exists(self.table),
            "report": os.path.exists(self._out("report.html")),
        }

    # -- the preview of a preparation -----------------------------------------------------------

    def preview(self, relative, data) -> dict:
        """The mesh after clean and orient (for the crop slider) and after the whole protocol."""
        return preview(self.mesh(relative), relative, protocol_from_json(data))

    # -- runs -----------------------------------------------------------------------------------

    def last_options(self) -> RunOptions:
        """The last run's options (the defaults if none, or if their file cannot be read)."""
        try:
            return RunOptions.from_json(_read_json(self._out(".app", "run.json")))
        except Exception:  # a file on disk is data: whatever is wrong with it, the defaults
            return RunOptions()

    def start_run(self, data) -> dict:
        options = RunOptions.from_json(data)
        with self._lock:
            if self.run is not None and self.run.running():
                raise AppError("a run is going: wait for it or cancel it", 409)
            files = [e.path for e in self.folder.entries() if e.error != NOT_UNICODE]
            if not files:
                raise AppError("the folder holds no meshes")
            groups: dict[str | None, list[str]] = {}
            for relative in files:
                path = self.protocol_for(relative)[1] if options.prepare else None
                groups.setdefault(path, []).append(relative)  # (AppError: a file unreadable)
            commands = []
            for path, group in groups.items():
                arguments = ["--output", self.table, "--resume", "--jobs", str(options.jobs)]
                arguments += options.arguments()
                if path is not None:
                    arguments += ["--prepare", path]
                commands.append([*arguments, "--", *group])  # a name is never an option
            text = json.dumps(options.to_json())
            atomic_write(self._out(".app", "run.json"), lambda s: s.write(text))
            self.set_prepares(options.prepare)
            stale = self._journal_rows()  # an earlier run's, killed: the command folds it in
            rows = [*self._table_rows(), *stale]
            before = {r.get("file"): r for r in rows}

            def settings_of(protocol):
                return make_settings(metrics=options.metrics, prepare=protocol, **options.ariadne())

            progress = RunProgress(files, resumed_rows(self.root, groups, rows, settings_of), stale)

            def done(index: int, code: int) -> None:  # a command ended: its rows are the table's
                group = set(commands[index][commands[index].index("--") + 1 :])
                table = [r for r in self._table_rows() if r.get("file") in group]
                if code not in (0, 1):  # stopped: the rows of files not reached are old ones
                    table = [r for r in table if before.get(r["file"]) != r]
                progress.see(table, final=True)

            self.progress = progress
            self.run = Job(commands, self.root, after=done).start()
        return self.run_state()

    def cancel_run(self) -> dict:
        if self.run is not None:
            self.run.cancel()
        return self.run_state()

    def run_state(self) -> dict:
        """The run as the page shows it (:class:`._progress.RunProgress`: never going back)."""
        job, progress = self.run, self.progress
        if job is None or progress is None:
            idle = {"run": 0, "serial": 0, "state": "idle", "total": 0, "done": 0}
            return {
                **idle,
                "compiling": None,
                "files": {},
                "log": [],
                "exit_code": None,
                "command": "",
            }
        if job.running():
            progress.see(self._journal_rows())
        return progress.state(job)

    def _journal_rows(self) -> list[dict]:
        try:
            return read_journal(journal_path(self.table))[0]
        except (OSError, ValueError):
            return []

    def _table_rows(self) -> list[dict]:
        try:
            return read_table(self.table)
        except (OSError, ValueError):
            return []

    def results(self) -> dict:
        """The table's rows (with the rows the journal holds while a run goes)."""
        rows = {r.get("file"): r for r in self._table_rows()}
        if self.run is not None and self.run.running():
            rows.update({r.get("file"): r for r in self._journal_rows()})
        ordered = [rows[k] for k in sorted(rows, key=str)]
        held = {k for row in ordered for k, v in row.items() if v is not None and v != ""}
        order = _column_order()
        columns = [k for k in order if k in held or k in ("file", "status")]
        columns += [
            k for k in dict.fromkeys(k for r in ordered for k in r) if k in held - set(order)
        ]
        return {"columns": columns, "rows": [_json_row(r) for r in ordered]}

    def export_table(self, kind: str) -> tuple[bytes, str, str]:
        """The table as `kind` (csv, tsv, xlsx): its bytes, file name and MIME type."""
        if kind not in EXPORTS:
            raise AppError(f"format must be one of {', '.join(EXPORTS)}")
        if not os.path.exists(self.table):
            raise AppError("no results yet: run the metrics first", 404)
        suffix, mime = EXPORTS[kind]
        source = self.table
        if kind != "csv":  # the CSV is the command's table itself, byte for byte
            source = self._out(".app", "export" + suffix)
            try:
                convert_table(self.table, source)
            except ValueError as exc:
                raise AppError(str(exc)) from None
        with open(source, "rb") as stream:
            return stream.read(), "results" + suffix, mime

    # -- maps, the report, the prepared meshes: the command, in the background -----------------

    def map_picture(self, relative, name) -> str | Drawing:
        """The PNG of a mesh's map (its path), or the drawing of it by the picture worker."""
        if name not in MAPS:
            raise AppError(f"map must be one of {', '.join(MAPS)}")
        entry = self.mesh(relative)
        options = self.last_options()
        protocol, protocol_path = self.protocol_for(relative) if options.prepare else (None, None)
        key = json.dumps(
            [
                entry.real,
                os.stat(entry.real).st_mtime_ns,
                name,
                options.arguments(),
                None if protocol is None else protocol.digest,
            ]
        )
        target = self._out(".app", "maps", hashlib.sha256(key.encode()).hexdigest()[:32] + ".png")
        if os.path.exists(target):
            return target
        with self._lock:
            drawing = self.pictures.get(target)
            if drawing is not None and drawing.running():
                return drawing
            if drawing is not None and drawing.state == "failed":
                if drawing.retry:  # the worker died under it: said once, drawn anew when asked
                    del self.pictures[target]
                return drawing
            os.makedirs(os.path.dirname(target), exist_ok=True)
            request = map_request(
                self.root, relative, name, options.to_json(), protocol_path, target
            )
            drawing = self.drawer.submit(Drawing(target, request))
            self.pictures[target] = drawing
            return drawing

    def start_report(self) -> dict:
        with self._lock:
            if self.report is not None and self.report.running():
                return self.report_state()
            if not os.path.exists(self.table):
                raise AppError("no results yet: run the metrics first", 404)
            arguments = ["report", "--output", self._out("report.html"), "--quiet"]
            for path in self._table_protocol_files():
                arguments += ["--prepare", path]
            arguments += ["--", self.table]
            self.report = Job([arguments], self.root).start()
        return self.report_state()

    def _table_protocol_files(self) -> list[str]:
        """The saved protocol files some row of the table was prepared with."""
        from ..batch import protocol_digest

        digests = {protocol_digest(r.get("protocol")) for r in self._table_rows()} - {None}
        files = [self.protocol_file]
        for here, _, names in os.walk(self._out("protocols")):
            files += [os.path.join(here, n) for n in sorted(names) if n.endswith(".toml")]
        found: dict[str, str] = {}  # short digest -> the first file of that protocol
        for path in files:
            protocol = _file_problem(path, self._protocol_files)
            if not isinstance(protocol, Protocol):
                continue  # not readable: the report is made without it
            digest = protocol.digest[:12]
            if digest in digests:
                found.setdefault(digest, path)
        return list(found.values())

    def report_state(self) -> dict:
        return _job_state(
            self.report, "/output/report.html", os.path.exists(self._out("report.html"))
        )

    def start_export(self) -> dict:
        """Prepare every mesh with its protocol into ``prepared/`` (``dentopo prepare``)."""
        with self._lock:
            if self.export is not None and self.export.running():
                return self.export_state()
            # one command per protocol and subfolder: the command puts a file given by name at
            # the top of its output folder, so each subfolder's go to that subfolder's
            groups: dict[tuple[str, str], list[str]] = {}
            for entry in self.folder.entries():
                if entry.error == NOT_UNICODE:
                    continue  # the page cannot name it, nor the table as the page does
                path = self.protocol_for(entry.path)[1]
                if path is not None:
                    where = os.path.dirname(entry.path)
                    groups.setdefault((path, where), []).append(entry.path)
            if not groups:
                raise AppError("no protocol yet: apply one to all meshes or to a mesh first")
            commands = [
                [
                    "prepare",
                    "--protocol",
                    path,
                    "--output",
                    self._out("prepared", *where.split("/")),
                    "--resume",
                    "--quiet",
                    "--",
                    *files,
                ]
                for (path, where), files in groups.items()
            ]
            self.export = Job(commands, self.root).start()
        return self.export_state()

    def export_state(self) -> dict:
        return _job_state(
            self.export, "/api/export/prepared.zip", os.path.isdir(self._out("prepared"))
        )

    def prepared_zip(self) -> bytes:
        """The prepared meshes, their records and the protocols, as one zip archive."""
        folder = self._out("prepared")
        if not os.path.isdir(folder):
            raise AppError("no prepared meshes yet: export them first", 404)
        buffer = io.BytesIO()
        with zipfile.ZipFile(buffer, "w", zipfile.ZIP_DEFLATED) as archive:
            for base, directory in (("prepared", folder), ("protocols", self._out("protocols"))):
                for here, _, names in os.walk(directory):
                    for name in sorted(names):
                        if name.startswith("."):
                            continue
                        path = os.path.join(here, name)
                        archive.write(path, base + "/" + os.path.relpath(path, directory))
            if os.path.exists(self.protocol_file):
                archive.write(self.protocol_file, "protocol.toml")
        return buffer.getvalue()

    def close(self) -> None:
        """Stop the background work: a run writes the rows it finished."""
        self.folder.close()
        self.drawer.close()
        for job in (self.run, self.report, self.export):
            if job is not None and job.running():
                job.stop()


def _file_problem(path: str, cache: dict) -> Protocol | str:
    """The protocol in the file `path`, or why it cannot be read (kept while the file is)."""
    try:
        info = os.stat(path)
        key = (info.st_ino, info.st_size, info.st_mtime_ns, info.st_ctime_ns)
    except OSError as exc:
        return exc.strerror or str(exc)
    known = cache.get(path)
    if known is not None and known[0] == key:
        return known[1]
    try:
        found: Protocol | str = read_protocol(path)
    except OSError as exc:
        found = exc.strerror or str(exc)
    except Exception as exc:  # a file on disk is data: whatever its fault, it is a reason
        found = " ".join(str(exc).split()) or type(exc).__name__
        found = found.replace(f"protocol {path} ", "it ")
    cache[path] = (key, found)
    return found


def _read_json(path: str):
    """The JSON in the file `path`, or None if it cannot be read (missing, corrupt, too deep)."""
    try:
        with open(path, encoding="utf-8") as stream:
            return json.load(stream)
    except (OSError, ValueError, RecursionError):
        return None


def _column_order() -> list[str]:
    """The page's columns: the file, its status and warnings, each metric's values (its headline
    first), then the settings and counts; the table itself keeps the command's order."""
    first = ["file", "status", "warnings", "error"]
    headlines = [keys[0] for keys in METRIC_KEYS.values()]
    rest = [k for keys in METRIC_KEYS.values() for k in keys[1:]]
    settings = [k for keys in SETTING_KEYS.values() for k in keys]
    ariadne = ["bandwidth", "cutoff", "distance_type", "sign_method", "method"]
    order = first + headlines + rest + ["vertices", "faces", *ariadne, PROTOCOL_KEY]
    order += [*settings, "orientation", "orient", "seconds"]
    return list(dict.fromkeys(order + list(COLUMNS)))


def _job_state(job: Job | None, url: str, exists: bool) -> dict:
    if job is None:
        return {"state": "done" if exists else "idle", "url": url if exists else None, "log": []}
    return {
        "state": job.state,
        "url": url if job.state == "done" or (exists and not job.running()) else None,
        "log": list(job.log)[-20:],
    }


def _json_row(row: dict) -> dict:
    out = {}
    for key, value in row.items():
        if isinstance(value, float) and not math.isfinite(value):
            value = None
        elif isinstance(value, (np.integer, np.floating)):
            value = value.item()
        out[key] = value
    return out


def _relative_inside(root: str, path: str) -> str | None:
    """`path` relative to `root` if it lies below it (the page's field), else None."""
    return relative_to(root, path) if os.path.commonpath([root, path]) == root != path else None


def _version() -> str:
    from .._version import __version__

    return __version__
