"""Output files: result tables (CSV, JSON) and per-vertex files (PLY, CSV).

Every file is written atomically: into a temporary file in the same
directory, then renamed over the target with ``os.replace``, so that a run that
fails or is interrupted never leaves a half-written file and never clobbers an
existing one.  Tables can be read back (``--resume``) with their types.
"""

from __future__ import annotations

import csv
import functools
import hashlib
import io
import json
import math
import os
import tempfile
from collections.abc import Callable, Iterable, Sequence

import numpy as np

from ._colors import color_scale
from ._inputs import OUTPUT_SUFFIX
from ._result import SCALAR_FIELDS

#: Columns of a results table, in order, with the library's names.
COLUMNS = ("file", *SCALAR_FIELDS, "seconds", "status", "error")

#: Output formats by file extension.
FORMATS = {".csv": "csv", ".json": "json"}

_INTEGER_COLUMNS = frozenset({"vertices", "faces"})
_TEXT_COLUMNS = frozenset({"file", "distance_type", "sign_method", "method", "status", "error"})


def output_format(path: str | os.PathLike) -> str:
    """``"csv"`` or ``"json"`` from the extension of `path` (case-insensitive).

    Raises
    ------
    ValueError
        For any other extension.
    """
    ext = os.path.splitext(os.fspath(path))[1].lower()
    if ext not in FORMATS:
        raise ValueError(
            f"cannot tell the output format of {os.fspath(path)!r}: "
            f"use one of the extensions {', '.join(FORMATS)}"
        )
    return FORMATS[ext]


@functools.cache
def _umask() -> int:
    """The process umask (read once: reading it means setting it briefly)."""
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def atomic_write(
    path: str | os.PathLike, write: Callable[[io.IOBase], None], *, binary: bool = False
) -> None:
    """Write a file atomically: `write` fills a temporary file, which is then renamed.

    The temporary file lives in the target's directory (so that the rename is
    atomic) and is removed if `write` raises; the target is then untouched.
    Text mode is UTF-8 with untranslated newlines.
    """
    path = os.fspath(path)
    directory = os.path.dirname(os.path.abspath(path))
    handle, temporary = tempfile.mkstemp(
        dir=directory, prefix=f".{os.path.basename(path)}.", suffix=".tmp"
    )
    try:
        mode = {"mode": "wb"} if binary else {"mode": "w", "encoding": "utf-8", "newline": ""}
        with os.fdopen(handle, **mode) as stream:
            write(stream)
            stream.flush()
            os.fsync(stream.fileno())
        os.chmod(temporary, 0o666 & ~_umask())  # mkstemp creates 0600
        os.replace(temporary, path)
    except BaseException:
        if os.path.exists(temporary):
            os.unlink(temporary)
        raise


def _csv_cell(value) -> str:
    if value is None:
        return ""
    if isinstance(value, float):
        return repr(value)  # shortest string that reads back to the same float
    return str(value)


def _json_value(value):
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def write_table(path: str | os.PathLike, records: Iterable[dict]) -> None:
    """Write result records to a CSV or JSON file (format from the extension), atomically.

    Parameters
    ----------
    path : str or path-like
        ``.csv``: a header row with :data:`COLUMNS`, missing values empty.
        ``.json``: a list of objects with the same keys, missing values null.
    records : iterable of dict
        Rows with (at least) the keys in :data:`COLUMNS`.
    """
    fmt = output_format(path)
    rows = [{name: record.get(name) for name in COLUMNS} for record in records]

    def write(stream):
        if fmt == "csv":
            writer = csv.writer(stream, lineterminator="\n")
            writer.writerow(COLUMNS)
            writer.writerows([_csv_cell(row[name]) for name in COLUMNS] for row in rows)
        else:
            data = [{k: _json_value(v) for k, v in row.items()} for row in rows]
            json.dump(data, stream, indent=1, ensure_ascii=False, allow_nan=False)
            stream.write("\n")

    atomic_write(path, write)


def _typed(name: str, text):
    if text is None or text == "":
        return None
    if name in _TEXT_COLUMNS:
        return str(text)
    if name in _INTEGER_COLUMNS:
        return int(text)
    return float(text)


def read_table(path: str | os.PathLike) -> list[dict]:
    """Read a table written by :func:`write_table` back into typed records.

    Raises
    ------
    ValueError
        If the file is not such a table (wrong format or missing columns).
    """
    path = os.fspath(path)
    fmt = output_format(path)
    with open(path, encoding="utf-8", newline="") as stream:
        if fmt == "csv":
            raw = list(csv.DictReader(stream))
            header = set(raw[0]) if raw else set(COLUMNS)
        else:
            try:
                raw = json.load(stream)
            except json.JSONDecodeError as exc:
                raise ValueError(f"{path!r} is not valid JSON: {exc}") from exc
            if not isinstance(raw, list) or not all(isinstance(r, dict) for r in raw):
                raise ValueError(f"{path!r} does not hold a list of result rows")
            header = set().union(*raw) if raw else set(COLUMNS)
    missing = [name for name in ("file", "status") if name not in header]
    if missing:
        raise ValueError(f"{path!r} is not a signDNE results table (no {', '.join(missing)})")
    try:
        return [{name: _typed(name, row.get(name)) for name in COLUMNS} for row in raw]
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{path!r} has a malformed value: {exc}") from exc


def per_vertex_names(files: Sequence[str]) -> list[str]:
    """Base names for the per-vertex files of `files`, unique within the batch.

    ``scans/tooth.ply`` gives ``tooth``; when two files share a stem, each of
    them gets a short hash of its absolute path appended (``tooth-1a2b3c4d``).
    """
    stems = [os.path.splitext(os.path.basename(f))[0] for f in files]
    counts: dict[str, int] = {}
    for stem in stems:
        counts[stem] = counts.get(stem, 0) + 1
    names = []
    for stem, file in zip(stems, files, strict=True):
        if counts[stem] > 1:
            digest = hashlib.sha1(os.path.abspath(file).encode("utf-8", "surrogatepass"))
            stem = f"{stem}-{digest.hexdigest()[:8]}"
        names.append(stem)
    return names


def write_per_vertex(directory: str | os.PathLike, name: str, result) -> tuple[str, str]:
    """Write one mesh's per-vertex values as ``<name>.signdne.ply`` and ``.csv``.

    The PLY (binary, float64 coordinates) holds the cleaned mesh the values
    refer to; its vertices carry ``local_curvature`` and ``local_dne`` as
    properties and are coloured by the signed curvature on the package's
    diverging scale (red convex, blue concave, grey zero; symmetric limits at
    the 98th percentile of ``|k|``, as in the pictures).
    The CSV has columns ``vertex, x, y, z, local_curvature, local_dne``.

    Returns
    -------
    ply_path, csv_path : str
    """
    directory = os.fspath(directory)
    base = os.path.join(directory, name + OUTPUT_SUFFIX)
    vertices = np.asarray(result.mesh.vertices, dtype=np.float64)
    faces = np.asarray(result.mesh.faces, dtype=np.int32)
    curvature = np.asarray(result.local_curvature, dtype=np.float64)
    local_dne = np.asarray(result.local_dne, dtype=np.float64)

    vertex = np.empty(
        len(vertices),
        dtype=[
            ("x", "<f8"),
            ("y", "<f8"),
            ("z", "<f8"),
            ("red", "u1"),
            ("green", "u1"),
            ("blue", "u1"),
            ("local_curvature", "<f8"),
            ("local_dne", "<f8"),
        ],
    )
    vertex["x"], vertex["y"], vertex["z"] = vertices.T
    vertex["red"], vertex["green"], vertex["blue"] = color_scale(curvature).rgb(curvature).T
    vertex["local_curvature"] = curvature
    vertex["local_dne"] = local_dne
    face = np.empty(len(faces), dtype=[("count", "u1"), ("index", "<i4", (3,))])
    face["count"] = 3
    face["index"] = faces
    header = "\n".join(
        [
            "ply",
            "format binary_little_endian 1.0",
            "comment signdne per-vertex output: signed curvature and local DNE",
            f"element vertex {len(vertex)}",
            "property double x",
            "property double y",
            "property double z",
            "property uchar red",
            "property uchar green",
            "property uchar blue",
            "property double local_curvature",
            "property double local_dne",
            f"element face {len(face)}",
            "property list uchar int vertex_indices",
            "end_header",
            "",
        ]
    )
    ply_path = base + ".ply"
    data = header.encode("ascii") + vertex.tobytes() + face.tobytes()
    atomic_write(ply_path, lambda stream: stream.write(data), binary=True)

    csv_path = base + ".csv"

    def write(stream):
        stream.write("vertex,x,y,z,local_curvature,local_dne\n")
        table = zip(vertices.tolist(), curvature.tolist(), local_dne.tolist(), strict=True)
        for i, ((x, y, z), k, d) in enumerate(table):
            stream.write(f"{i},{x!r},{y!r},{z!r},{k!r},{d!r}\n")

    atomic_write(csv_path, write)
    return ply_path, csv_path
