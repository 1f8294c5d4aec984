"""The app's maps, drawn by one warm worker process instead of a new command each.

A map is the picture ``dentopo MESH --metrics M --color-by C --screenshot FILE``
draws: the mesh measured by the batch's own :func:`dentopo.batch.compute_task`
(with the run's settings, and the mesh's protocol when runs prepare), then
drawn by the same :mod:`dentopo.figures` function with the same arguments and
provenance, so the PNG is the command's, byte for byte
(``tests/test_app_pictures.py`` compares them).  Started as a command, each map
cost a new interpreter: 1 s of imports, numba's kernels loaded from the cache,
VTK's first window: 3 s a map; drawn here, half a second.

:class:`PictureWorker` keeps one such process, ``python -c "...serve()"``,
started in the background when the server starts (:meth:`PictureWorker.warm`:
the imports, numba's kernels of the maps, a first small picture of each) and fed one picture
at a time over its standard input (one JSON line per request, one line back
per answer, on a copy of its standard output: anything a library prints goes
to its standard error, which is kept for the log).  A picture that fails is
an answer (its one-line reason, shown on the page), and the worker goes on; a
worker that dies (a crash, the out-of-memory killer, a ``kill``) costs the
picture it was drawing, whose reason says so, and the next picture starts a
new one.  The worker runs in a session of its own (a Ctrl-C meant for the
server is not its) and is stopped with the server; a server killed outright
closes its pipe, and the worker, reading the end of its input, exits too.
Runs are not drawn here: they stay the command itself (:mod:`._jobs`).
"""

from __future__ import annotations

import collections
import json
import os
import subprocess
import sys
import threading
import warnings
from dataclasses import dataclass, field

#: The maps the page shows: name -> (the metric computed, the command's --color-by).
MAPS = {
    "curvature": ("ariadne", "local_curvature"),
    "slope": ("slope", "slope"),
    "opc": ("opc", "opc"),
    "arc": ("arc", "arc"),
}
#: The maps' size in pixels (the command's ``--size 900,760``).
MAP_SIZE = (900, 760)
#: The run's options a map is drawn with (ariaDNE's; the metric is the map's).
MAP_SETTINGS = ("bandwidth", "cutoff", "distance_type", "sign_method", "method")
#: Longest reason of a failed picture (one line).
MAX_REASON = 300
#: Seconds the worker is given to leave when the server stops, before it is killed.
STOP_SECONDS = 5.0
#: Lines of the worker's standard error kept (a crash's last words, for the log).
LOG_LINES = 50
#: What the worker runs: a ``-c`` program, without the current folder (``-c`` puts it first on
#: the path: a file of the user's could take the place of a module the worker imports).
WORKER_CODE = (
    "import sys\n"
    "if sys.path[:1] == ['']: del sys.path[0]\n"
    "from dentopo.app._pictures import serve\n"
    "serve()\n"
)


def map_request(root: str, relative: str, name: str, settings: dict, prepare, target: str):
    """What the worker is asked to draw: the map `name` of the mesh `relative` below `root`,
    with ariaDNE's `settings` (the run's) and the protocol file `prepare` (or None)."""
    metric, color_by = MAPS[name]
    return {
        "path": os.path.join(root, *relative.split("/")),
        "title": relative.rsplit("/", 1)[-1],  # the name the command was given, as it shows it
        "metric": metric,
        "color_by": color_by,
        "settings": {k: v for k, v in settings.items() if k in MAP_SETTINGS},
        "prepare": prepare,
        "target": target,
        "size": list(MAP_SIZE),
    }


class PictureError(Exception):
    """A picture that cannot be drawn: its one-line reason."""


@dataclass
class Drawing:
    """One picture asked for, drawn by the worker into `target`.

    ``state`` goes ``waiting``, ``drawing``, then ``done`` or ``failed`` (with
    ``error``, one line); ``retry`` says that it failed because the worker
    died, not because of the mesh (asking again draws it again).
    """

    target: str | None
    request: dict
    state: str = "waiting"
    error: str | None = None
    retry: bool = False
    finished: threading.Event = field(default_factory=threading.Event, repr=False)

    def running(self) -> bool:
        return self.state in ("waiting", "drawing")

    def wait(self, timeout: float | None = None) -> bool:
        return self.finished.wait(timeout)


def one_line(text: str) -> str:
    """`text` on one short line."""
    text = " ".join(str(text).split())
    return text if len(text) <= MAX_REASON else text[: MAX_REASON - 1] + "\u2026"


class PictureWorker:
    """One long-lived process drawing the app's pictures, one at a time, in order."""

    def __init__(self):
        self._lock = threading.Condition()
        self._queue: collections.deque[Drawing] = collections.deque()
        self._thread: threading.Thread | None = None
        self._process: subprocess.Popen | None = None
        self._closed = False
        self.warmed = threading.Event()
        self.started = 0  # processes started so far
        self.log: collections.deque[str] = collections.deque(maxlen=LOG_LINES)

    @property
    def pid(self) -> int | None:
        """The worker's process id while it runs, else None."""
        process = self._process
        return None if process is None or process.poll() is not None else process.pid

    def warm(self) -> None:
        """Start the worker in the background, and warm it (imports, a first picture)."""
        with self._lock:
            if self._closed or self.warmed.is_set() or self._queue:
                return
            self._queue.append(Drawing(None, {"kind": "warm"}))
            self._start_thread()

    def wait_warm(self, timeout: float | None = None) -> bool:
        """Wait until the worker is warm (True) or `timeout` passes (False)."""
        return self.warmed.wait(timeout)

    def submit(self, drawing: Drawing) -> Drawing:
        """Queue `drawing` (it is drawn after those before it)."""
        with self._lock:
            if self._closed:
                drawing.state, drawing.error = "failed", "the app is stopping"
                drawing.finished.set()
                return drawing
            self._queue.append(drawing)
            self._start_thread()
            self._lock.notify_all()
        return drawing

    def close(self, timeout: float = STOP_SECONDS) -> None:
        """Stop the worker (killed if it does not leave within `timeout`); nothing is left."""
        with self._lock:
            self._closed = True
            waiting = list(self._queue)
            self._queue.clear()
            self._lock.notify_all()
            process = self._process
        for drawing in waiting:
            drawing.state, drawing.error = "failed", "the app is stopping"
            drawing.finished.set()
        if process is not None:
            _stop(process, timeout)
        thread = self._thread
        if thread is not None and thread is not threading.current_thread():
            thread.join(timeout)
        if process is not None:
            _close_pipes(process)

    # -- the thread that talks to the worker ----------------------------------------------------

    def _start_thread(self) -> None:
        if self._thread is None or not self._thread.is_alive():
            self._thread = threading.Thread(target=self._loop, name="dentopo-app-pictures")
            self._thread.daemon = True
            self._thread.start()

    def _loop(self) -> None:
        while True:
            with self._lock:
                while not self._queue and not self._closed:
                    self._lock.wait()
                if self._closed:
                    return
                drawing = self._queue.popleft()
                drawing.state = "drawing"
            try:
                self._ask(drawing.request)
                drawing.state = "done"
            except PictureError as exc:
                drawing.state, drawing.error = "failed", one_line(exc) or "the picture failed"
            except _WorkerStoppedError as exc:
                drawing.state, drawing.error, drawing.retry = "failed", str(exc), True
            except Exception as exc:  # never the thread's end: the next picture is drawn
                reason = one_line(f"the picture worker failed: {type(exc).__name__}: {exc}")
                drawing.state, drawing.error, drawing.retry = "failed", reason, True
            finally:
                if drawing.request.get("kind") == "warm":
                    self.warmed.set()
                drawing.finished.set()

    def _ask(self, request: dict) -> None:
        """Send `request` to the worker (started if needed) and read its answer."""
        process = self._running()
        try:
            process.stdin.write(json.dumps(request) + "\n")
            process.stdin.flush()
            line = process.stdout.readline()
        except (OSError, ValueError):  # the pipe is broken or closed: the worker is gone
            line = ""
        if not line:
            raise _WorkerStoppedError(self._death(process))
        try:
            answer = json.loads(line)
        except ValueError:
            answer = {"error": f"the picture worker answered {line[:80]!r}"}
        if answer.get("error") is not None:
            raise PictureError(answer["error"])

    def _running(self) -> subprocess.Popen:
        with self._lock:
            if self._closed:
                raise _WorkerStoppedError("the app is stopping")
            if self._process is not None:
                if self._process.poll() is None:
                    return self._process
                _close_pipes(self._process)  # died while it waited: replaced
            self._process = subprocess.Popen(
                [sys.executable, "-c", WORKER_CODE],
                stdin=subprocess.PIPE,
                stdout=subprocess.PIPE,
                stderr=subprocess.PIPE,
                text=True,
                encoding="utf-8",
                errors="replace",
                env=_worker_environment(),
                start_new_session=True,  # a Ctrl-C meant for the server is not the worker's
            )
            self.started += 1
            process = self._process
        reader = threading.Thread(target=self._read_errors, args=(process,), daemon=True)
        reader.start()
        return process

    def _read_errors(self, process: subprocess.Popen) -> None:
        with process.stderr:
            for line in process.stderr:
                self.log.append(line.rstrip("\n"))

    def _death(self, process: subprocess.Popen) -> str:
        """Why the worker stopped, once it has (one line)."""
        try:
            code = process.wait(STOP_SECONDS)
        except subprocess.TimeoutExpired:
            process.kill()
            code = process.wait()
        _close_pipes(process)
        with self._lock:
            if self._process is process:
                self._process = None
            if self._closed:
                return "the app is stopping"
        how = f"killed by signal {-code}" if code < 0 else f"exit code {code}"
        return f"the picture worker stopped ({how}) while drawing it: ask again to draw it anew"


class _WorkerStoppedError(Exception):
    """The worker died (or the app is stopping) before it answered."""


def _stop(process: subprocess.Popen, timeout: float) -> None:
    """End the worker: its input closed (it leaves), then SIGTERM, then SIGKILL."""
    try:
        process.stdin.close()
    except OSError:
        pass
    try:
        process.wait(timeout / 2)
        return
    except subprocess.TimeoutExpired:
        process.terminate()
    try:
        process.wait(timeout / 2)
    except subprocess.TimeoutExpired:
        process.kill()
        process.wait()


def _close_pipes(process: subprocess.Popen) -> None:
    """Close the pipes to and from an ended worker (its standard error: its reader's)."""
    for stream in (process.stdin, process.stdout):
        try:
            stream.close()
        except (OSError, ValueError):
            pass


def _worker_environment() -> dict:
    """The server's environment, with the folder this dentopo is imported from first on the
    path (a relative ``PYTHONPATH`` or an editable checkout found the same dentopo), unless it
    is a site-packages folder, which the worker finds anyway."""
    import site
    import sysconfig

    package = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))  # .../dentopo
    here = os.path.dirname(package)
    paths = sysconfig.get_paths()
    sites = {paths["purelib"], paths["platlib"], *site.getsitepackages()}
    sites.add(site.getusersitepackages())
    environment = {**os.environ, "PYTHONUNBUFFERED": "1"}
    if os.path.realpath(here) not in {os.path.realpath(p) for p in sites}:
        given = os.environ.get("PYTHONPATH")
        environment["PYTHONPATH"] = os.pathsep.join([here, given] if given else [here])
    return environment


# -- the worker process ---------------------------------------------------------------------------


def serve() -> None:
    """The worker's loop: one JSON request per line of input, one JSON answer per line."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)  # the server stops it (also in its session)
    signal.signal(signal.SIGTERM, _leave)  # stopped: the picture half drawn is removed
    answers = os.fdopen(os.dup(1), "w", encoding="utf-8", buffering=1)
    os.dup2(2, 1)  # what a library prints goes to the log, never into the answers
    sys.stdout = sys.stderr
    for line in sys.stdin:
        try:
            request = json.loads(line)
            if request.get("kind") == "warm":
                warm_up()
            else:
                draw_map(request)
            answer: dict = {"error": None}
        except PictureError as exc:
            answer = {"error": one_line(exc)}
        except Exception as exc:  # a picture that fails is an answer; the worker goes on
            from ..batch import error_reason

            answer = {"error": one_line(error_reason(exc))}
        answers.write(json.dumps(answer) + "\n")
    # the end of the input: the server closed it, or died


def _leave(signum, frame) -> None:
    raise SystemExit(128 + signum)


def warm_up() -> None:
    """What the first pictures would spend besides their own work: the imports, numba's
    kernels of the four maps (loaded from the cache; compiled on a fresh install, once per
    machine), VTK's first off-screen window and matplotlib's first figures.  Each map is
    drawn once, small, of a small bump."""
    import tempfile

    import numpy as np
    import trimesh

    side = np.linspace(-1.0, 1.0, 16)
    x, y = (a.ravel() for a in np.meshgrid(side, side))
    vertices = np.column_stack([x, y, np.exp(-2.0 * (x * x + y * y)) + 0.1 * x * y])
    corner = np.arange(15)[:, None] + 16 * np.arange(15)[None, :]
    corner = corner.ravel()
    faces = np.concatenate(
        [
            np.column_stack([corner, corner + 1, corner + 17]),
            np.column_stack([corner, corner + 17, corner + 16]),
        ]
    )
    with tempfile.TemporaryDirectory(prefix="dentopo-app-warm-") as folder:
        path = os.path.join(folder, "bump.ply")
        trimesh.Trimesh(vertices, faces, process=False).export(path)
        for name, (metric, color_by) in MAPS.items():
            draw_map(
                {
                    "path": path,
                    "title": "bump.ply",
                    "metric": metric,
                    "color_by": color_by,
                    "settings": {},
                    "prepare": None,
                    "target": os.path.join(folder, name + ".png"),
                    "size": (400, 340),
                }
            )


def draw_map(request: dict) -> None:
    """Draw one map as ``dentopo`` draws it: the metric computed by the batch, then pictured.

    `request`: ``path`` (the mesh), ``title`` (its name as the command is given it), ``metric``
    and ``color_by`` (:data:`MAPS`), ``settings`` (ariaDNE's), ``prepare`` (a protocol file or
    None), ``target`` (the PNG) and ``size``.  The picture is written beside `target` and then
    renamed to it, so that a worker killed half-way leaves no half picture.
    """
    import dentopo.figures as figures

    from ..batch import compute_task, make_settings, plan_batch
    from ..prepare import load_protocol

    metric, color_by = request["metric"], request["color_by"]
    settings = make_settings(metrics=metric, prepare=request["prepare"], **request["settings"])
    task = plan_batch([request["path"]], settings, keep_results=True)[0]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the run's table holds them
        outcome = compute_task(task, settings)
    if outcome.result is None or metric not in outcome.result.results:
        reason = outcome.record.get("error") or "it was not computed"
        raise PictureError(f"nothing to draw ({metric}): {reason}")
    result = outcome.result.results[metric]
    protocol = {}
    if request["prepare"] is not None:  # the picture of the mesh measured: the prepared one
        made = load_protocol(request["prepare"])
        protocol = {"label": made.label, "digest": made.digest, "steps": made.steps()}
    common = {
        "view": figures.DEFAULT_VIEW,
        "azimuth": 0.0,
        "elevation": 0.0,
        "dpi": None,
        "transparent": False,
        "title": request["title"],
        "html": None,
        "interactive": False,
        "source": request["path"],
        "window_size": tuple(request["size"]),
    }
    target = request["target"]
    # the format is the suffix: the picture is drawn into a .png beside the target, then moved
    partial = os.path.join(os.path.dirname(target), f".drawing-{os.getpid()}.png")
    try:
        _render(
            figures,
            metric,
            color_by,
            result,
            settings,
            {**common, "screenshot": partial},
            {"protocol": protocol} if protocol else {},
        )
        os.replace(partial, target)
    finally:
        if os.path.exists(partial):
            os.unlink(partial)


def _render(figures, metric, color_by, result, settings, common, parameters) -> None:
    """The command's call of the picture of `metric` (its arguments, its provenance)."""
    if metric == "ariadne":
        figures.render_curvature(
            result.mesh,
            result,
            field=color_by,
            limits=None,
            percentile=figures.DEFAULT_PERCENTILE,
            **common,
            **({"parameters": parameters} if parameters else {}),
        )
    elif metric == "slope":
        parameters = {"orient": settings.topography.orient, **parameters}
        figures.render_slope(result.mesh, result.face_slope, parameters=parameters, **common)
    elif metric == "opc":
        parameters = {
            "orient": settings.topography.orient,
            "min_faces": settings.topography.min_faces,
            **parameters,
        }
        figures.render_opc(
            result.mesh, result.face_bin, result.face_patch, parameters=parameters, **common
        )
    elif metric == "arc":
        spec = figures.FACE_METRICS["arc"]
        keywords = spec.keywords()
        keywords.update(limits=None, percentile=figures.DEFAULT_PERCENTILE)
        low, high = result.range
        note = (
            f"set to 0: {result.boundary_faces} border faces ({result.boundary} rule), "
            f"{result.cut_faces} beyond the {low:g} and {high:g} quantiles"
        )
        topography = settings.topography
        parameters = {
            "arc_boundary": topography.arc_boundary,
            "arc_range": list(topography.arc_range),
            **parameters,
        }
        figures.render_face_values(
            result.mesh,
            getattr(result, spec.field),
            note=note,
            parameters=parameters,
            **keywords,
            **common,
        )
    else:
        raise PictureError(f"no map of {metric}")
