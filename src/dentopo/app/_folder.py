"""The folder the app works on: its meshes, each read once for its size and a thumbnail.

The meshes are found as the command finds them (:func:`dentopo.batch.find_mesh_files`:
hidden entries and the tool's own outputs skipped), less the app's output folder
and anything whose real path leaves the folder (a symlink out of it is not
listed, and so never opened).  A mesh's group is its first subfolder (``""`` at
the top), as the collection report groups by folder.  The folder is scanned
again every few seconds while the page asks (a file copied in shows up), but only
if something changed: a walk of the tree with one ``stat`` per entry (inode,
size, times) is compared with the last scan's (25 ms for 5,000 files where the
scan, which resolves every path, takes 0.4-2 s).  A file whose name is not valid
UTF-8 is listed with that error and not opened (the page could not name it back).

One background thread reads each mesh in turn (:func:`dentopo.load_mesh`): its
vertex and face counts, or the reason it cannot be read, and a small occlusal
thumbnail, drawn with matplotlib's Agg canvas (thread-safe without pyplot; VTK's
off-screen renderer is not safe off the main thread) from the report's camera,
faces lit from the upper left.  Thumbnails are cached in the output
folder under ``.app/thumbnails``, keyed by the file's path, size and time.
"""

from __future__ import annotations

import hashlib
import io
import os
import stat
import threading
import time
import warnings
from dataclasses import dataclass

import numpy as np

from ..batch import error_reason, find_mesh_files
from ..formats import atomic_write
from ..mesh import load_mesh
from ..report import report_camera
from ._security import inside, relative_to

#: Seconds between scans of the folder while the page asks for its state.
RESCAN_SECONDS = 5.0
#: Thumbnail width and height, pixels.
THUMBNAIL_PIXELS = 160
#: The thumbnail's light, in the camera's axes (right, up, towards the viewer).
LIGHT = np.array([-0.45, 0.55, 0.70]) / np.linalg.norm([-0.45, 0.55, 0.70])
#: Faces drawn in a thumbnail at most (larger meshes are decimated for the picture only).
THUMBNAIL_FACES = 20_000


@dataclass
class MeshEntry:
    """One mesh of the folder, as the page lists it."""

    path: str  # relative to the folder, "/"-separated
    real: str  # the real path opened
    group: str
    bytes: int
    vertices: int | None = None
    faces: int | None = None
    error: str | None = None
    thumbnail: str | None = None  # the cached picture, once drawn
    inspected: bool = False

    def to_json(self) -> dict:
        """What the page is told of it (the real path stays in the server)."""
        return {
            "path": self.path,
            "group": self.group,
            "bytes": self.bytes,
            "vertices": self.vertices,
            "faces": self.faces,
            "error": self.error,
            "thumbnail": self.thumbnail is not None,
        }


#: The error of a mesh whose file name is not valid UTF-8.
NOT_UNICODE = "its file name is not valid UTF-8 text: rename the file to open it here"


def _is_unicode(text: str) -> bool:
    try:
        text.encode("utf-8")
    except UnicodeEncodeError:
        return False
    return True


def group_of(path: str) -> str:
    """A mesh's group: its first folder below the app's folder, or ``""``."""
    head, _, rest = path.partition("/")
    return head if rest else ""


class Folder:
    """The meshes below `root` (the output folder `output` left out), read in the background."""

    def __init__(self, root: str, output: str):
        self.root = os.path.realpath(root)
        self.output = os.path.realpath(output)
        self._lock = threading.Lock()
        self._entries: dict[str, MeshEntry] = {}
        self._thread: threading.Thread | None = None
        self._stop = threading.Event()
        self._scanned = 0.0
        self._signature = b""
        self.scan()

    def signature(self) -> bytes:
        """A digest of the tree below the folder: each entry's name, inode, size and times.

        Hidden entries and the output folder are left out, as the scan leaves them out; a
        symlinked folder counts by its own times (its files are listed only if they lie in the
        folder, where they are walked anyway).
        """
        digest = hashlib.blake2b(digest_size=16)
        waiting = [self.root]
        while waiting:
            here = waiting.pop()
            try:
                with os.scandir(here) as found:
                    items = sorted(found, key=lambda e: e.name)
            except OSError as exc:
                digest.update(f"{here}\0{exc.errno}\n".encode("utf-8", "surrogateescape"))
                continue
            for item in items:
                if item.name.startswith(".") or item.path == self.output:
                    continue
                try:
                    info = item.stat()
                    key = (info.st_ino, info.st_size, info.st_mtime_ns, info.st_ctime_ns)
                except OSError as exc:
                    info, key = None, exc.errno
                digest.update(f"{item.path}\0{key}\n".encode("utf-8", "surrogateescape"))
                if info is not None and stat.S_ISDIR(info.st_mode) and not item.is_symlink():
                    waiting.append(item.path)
        return digest.digest()

    def scan(self) -> None:
        """List the meshes again (new files appear, removed ones go); inspect the new ones."""
        signature = self.signature()  # before: a change made during the scan is seen next time
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # a format that cannot be read: not listed
            found = find_mesh_files([self.root]).files
        entries = {}
        for path in found:
            real = os.path.realpath(path)
            if os.path.commonpath([real, self.root]) != self.root:
                continue  # a symlink out of the folder
            if os.path.commonpath([real, self.output]) == self.output:
                continue  # the app's own outputs
            relative = relative_to(self.root, os.path.abspath(path))
            try:
                size = os.stat(real).st_size
            except OSError:
                continue
            old = self._entries.get(relative)
            if old is not None and old.bytes == size and old.real == real:
                entries[relative] = old
            else:
                entries[relative] = MeshEntry(relative, real, group_of(relative), size)
                if not _is_unicode(relative):
                    entries[relative].error = NOT_UNICODE
                    entries[relative].inspected = True
        with self._lock:
            self._entries = entries
            self._scanned = time.monotonic()
            self._signature = signature
        self._start()

    def refresh(self, seconds: float = RESCAN_SECONDS) -> None:
        """Scan again if the last scan is older than `seconds` and the tree has changed."""
        if time.monotonic() - self._scanned > seconds:
            if self.signature() == self._signature:
                self._scanned = time.monotonic()
            else:
                self.scan()

    def entries(self) -> list[MeshEntry]:
        """The meshes, sorted by path."""
        with self._lock:
            return [self._entries[k] for k in sorted(self._entries)]

    def entry(self, relative: str) -> MeshEntry:
        """The mesh at `relative`; ``KeyError`` if it is not one of the folder's meshes.

        The path is checked first (:func:`inside`): a path out of the folder is
        :class:`PathRefusedError`, whether or not such a file exists.
        """
        inside(self.root, relative)
        with self._lock:
            return self._entries[relative]

    @property
    def pending(self) -> bool:
        """Whether some mesh is still being read."""
        return any(not e.inspected for e in self.entries())

    def _start(self) -> None:
        if self._thread is not None and self._thread.is_alive():
            return
        self._thread = threading.Thread(target=self._inspect_all, name="dentopo-app-folder")
        self._thread.daemon = True
        self._thread.start()

    def close(self) -> None:
        self._stop.set()

    def _inspect_all(self) -> None:
        while not self._stop.is_set():
            waiting = [e for e in self.entries() if not e.inspected]
            if not waiting:
                return
            for entry in waiting:
                if self._stop.is_set():
                    return
                inspect(entry, os.path.join(self.output, ".app", "thumbnails"))


def _thumbnail_name(entry: MeshEntry) -> str:
    stat = os.stat(entry.real)
    key = f"{entry.real}\0{stat.st_size}\0{stat.st_mtime_ns}".encode("utf-8", "surrogateescape")
    return hashlib.sha256(key).hexdigest()[:32] + ".png"


def inspect(entry: MeshEntry, thumbnails: str) -> None:
    """Read `entry`'s mesh: its counts or its error, and its thumbnail (never raises)."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            mesh = load_mesh(entry.real)
        entry.vertices, entry.faces = len(mesh.vertices), len(mesh.faces)
    except Exception as exc:  # a bad file is data: its reason is shown
        entry.error = error_reason(exc).replace(entry.real, entry.path)  # the name the page shows
        entry.inspected = True
        return
    try:
        target = os.path.join(thumbnails, _thumbnail_name(entry))
        if not os.path.exists(target):
            os.makedirs(thumbnails, exist_ok=True)
            png = draw_thumbnail(np.asarray(mesh.vertices), np.asarray(mesh.faces))
            atomic_write(target, lambda stream: stream.write(png), binary=True)
        entry.thumbnail = target
    except Exception:  # no picture is not an error of the mesh
        entry.thumbnail = None
    entry.inspected = True


def simplified(vertices, faces, target: int) -> tuple[np.ndarray, np.ndarray]:
    """The mesh with at most about `target` faces, for a picture only (quadric edge collapse)."""
    if len(faces) <= target:
        return np.asarray(vertices, dtype=np.float64), np.asarray(faces, dtype=np.int64)
    # writable copies: the simplifier refuses read-only arrays (a prepared crown's)
    vertices = np.array(vertices, dtype=np.float64, order="C")
    faces = np.array(faces, dtype=np.int64, order="C")
    import fast_simplification

    vertices, faces = fast_simplification.simplify(vertices, faces, 1 - target / len(faces))
    return np.asarray(vertices, dtype=np.float64), np.asarray(faces, dtype=np.int64)


def draw_thumbnail(vertices: np.ndarray, faces: np.ndarray, pixels: int = THUMBNAIL_PIXELS):
    """PNG bytes: the mesh seen from the report's occlusal camera, faces shaded."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.collections import PolyCollection
    from matplotlib.figure import Figure

    vertices, faces = simplified(vertices, faces, THUMBNAIL_FACES)
    axes = report_camera(vertices, faces)
    seen = vertices @ axes.T  # right, up, towards the viewer
    tri = seen[faces]
    normals = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    length = np.linalg.norm(normals, axis=1)
    normals = normals / np.where(length > 0, length, 1.0)[:, None]
    normals *= np.where(normals[:, 2] < 0, -1.0, 1.0)[:, None]  # either winding faces the camera
    lit = np.clip(normals @ LIGHT, 0.0, 1.0)  # a light from the upper left, as in a paper figure
    order = np.argsort(tri[:, :, 2].mean(axis=1))  # far faces first, near ones drawn over
    shade = 0.3 + 0.7 * lit[order]
    tooth = np.array([0.91, 0.86, 0.77])
    colors = np.clip(shade[:, None] * tooth, 0, 1)
    figure = Figure(figsize=(1, 1), dpi=pixels)
    FigureCanvasAgg(figure)
    ax = figure.add_axes((0, 0, 1, 1))
    ax.set_axis_off()
    ax.add_collection(
        PolyCollection(tri[order][:, :, :2], facecolors=colors, edgecolors=colors, linewidths=0.2)
    )
    low, high = seen[:, :2].min(axis=0), seen[:, :2].max(axis=0)
    middle, half = (low + high) / 2, (high - low).max() / 2 * 1.05 or 1.0
    ax.set_xlim(middle[0] - half, middle[0] + half)
    ax.set_ylim(middle[1] - half, middle[1] + half)
    ax.set_aspect("equal")
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", facecolor="white")
    return buffer.getvalue()
