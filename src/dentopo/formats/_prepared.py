"""The files of a prepared crown: ``NAME.ply`` (the mesh) and ``NAME.prepare.json`` (its record).

The mesh is binary little-endian PLY with float64 coordinates and int32
indices, nothing else: measuring the file gives the same numbers as measuring
the prepared mesh in memory (float64 keeps every coordinate exactly), and
:func:`dentopo.mesh.read_ply`, trimesh and MeshLab read it.  Its header holds
no date and no path, so that the same input and protocol give the same bytes.

The record is JSON: dentopo's version, the input (its path as given and the
SHA-256 of its bytes), the protocol (name, digest, every field), each step
with its parameters and effects (:meth:`dentopo.PreparedCrown.to_dict`), and
the mesh file written (its name and SHA-256).  No date or time either.  It is
written after the mesh, so that a record says its mesh is complete
(``dentopo prepare --resume`` relies on it).

Both are written atomically (:func:`atomic_write`), into folders that
:func:`safe_folder` creates below the output folder without following a
symbolic link out of it.
"""

from __future__ import annotations

import hashlib
import json
import math
import os

import numpy as np

from .._version import __version__
from ._atomic import atomic_write

#: The suffix of a prepared crown's record, beside its mesh ``NAME.ply``.
RECORD_SUFFIX = ".prepare.json"

#: The ``format`` entry of a record (bumped if its layout changes incompatibly).
RECORD_FORMAT = "dentopo prepared crown 1"


def prepared_ply_bytes(vertices, faces, *, comment: str | None = None) -> bytes:
    """A binary little-endian PLY of triangles: float64 ``x y z``, int32 ``vertex_indices``.

    Raises
    ------
    ValueError
        If the arrays are not (n, 3) and (m, 3), or an index lies outside the vertices.
    """
    vertices = np.asarray(vertices, dtype=np.float64)
    faces = np.asarray(faces)
    if vertices.ndim != 2 or vertices.shape[1] != 3 or faces.ndim != 2 or faces.shape[1] != 3:
        raise ValueError("a prepared mesh is (n, 3) vertices and (m, 3) triangles")
    if len(faces) and (faces.min() < 0 or faces.max() >= len(vertices)):
        raise ValueError("a prepared mesh's face indices must lie within its vertices")
    if len(vertices) >= 2**31:
        raise ValueError("too many vertices for a PLY file of int32 indices")
    face = np.empty(len(faces), dtype=[("count", "u1"), ("index", "<i4", (3,))])
    face["count"] = 3
    face["index"] = faces
    header = ["ply", "format binary_little_endian 1.0", "comment dentopo prepared mesh"]
    if comment:
        header.append("comment " + " ".join(str(comment).split()))
    header += [
        f"element vertex {len(vertices)}",
        "property double x",
        "property double y",
        "property double z",
        f"element face {len(faces)}",
        "property list uchar int vertex_indices",
        "end_header",
        "",
    ]
    text = "\n".join(header).encode("ascii", "replace")
    return text + np.ascontiguousarray(vertices, dtype="<f8").tobytes() + face.tobytes()


def _finite(value):
    """`value` with NaN and infinities as None (JSON has neither)."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {k: _finite(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_finite(v) for v in value]
    return value


def prepared_record(
    crown,
    *,
    source: str | None = None,
    mesh_file: str | None = None,
    mesh_sha256: str | None = None,
    geometry: str | None = None,
) -> dict:
    """The ``.prepare.json`` record of `crown` (a :class:`dentopo.PreparedCrown`).

    Parameters
    ----------
    source : str, optional
        The input's path as the user gave it (default: the crown's own ``source``).
    mesh_file, mesh_sha256 : str, optional
        The name and SHA-256 of the mesh file written (``"mesh"`` entry).
    geometry : str, optional
        Which mesh of a file holding several was read (recorded if given).
    """
    body = crown.to_dict()
    if source is not None:
        body["input"]["path"] = source
    if geometry is not None:
        body["input"]["geometry"] = geometry
    record = {"format": RECORD_FORMAT, "dentopo": __version__, **body}
    if mesh_file is not None:
        record["mesh"] = {"file": mesh_file, "sha256": mesh_sha256}
    return _finite(record)


def record_text(record: dict) -> str:
    """The record as JSON text: indented, keys in their order, ASCII (any file name survives)."""
    return json.dumps(record, indent=2, ensure_ascii=True, allow_nan=False) + "\n"


def read_record(path: str | os.PathLike) -> dict:
    """A ``.prepare.json`` record (ValueError if it is not one, OSError if unreadable)."""
    with open(path, "rb") as handle:
        data = handle.read()
    try:
        record = json.loads(data.decode("utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ValueError(f"{os.fspath(path)!r} is not a prepared crown's record: {exc}") from None
    if not isinstance(record, dict) or record.get("format") != RECORD_FORMAT:
        raise ValueError(f"{os.fspath(path)!r} is not a prepared crown's record")
    return record


def _inside(path: str, root: str) -> bool:
    return os.path.commonpath([path, root]) == root


def safe_folder(root: str | os.PathLike, relative: str) -> str:
    """Create the folder `relative` below `root` (both made if missing); its path.

    Every part of `relative` that exists must be a real folder, not a symbolic
    link: a link planted in the output folder must not lead the files out of it.

    Raises
    ------
    ValueError
        If `relative` is absolute or climbs out (``..``), or a part of it is a
        symbolic link or not a folder.
    OSError
        If a folder cannot be created.
    """
    root = os.fspath(root)
    relative = os.path.normpath(relative) if relative else ""
    if relative in ("", "."):
        parts: list[str] = []
    else:
        parts = relative.split(os.sep)
        if os.path.isabs(relative) or parts[0] == os.pardir:
            raise ValueError(f"{relative!r} would lead out of the output folder {root!r}")
    os.makedirs(root, exist_ok=True)
    here = root
    for part in parts:
        here = os.path.join(here, part)
        try:  # made here, or found: a link is not followed by mkdir, and is refused below
            os.mkdir(here)
        except FileExistsError:  # there already, or another worker made it meanwhile
            pass
        if os.path.islink(here):
            raise ValueError(
                f"{here!r} is a symbolic link: files are not written through it (it could "
                f"lead out of {root!r}); remove it or choose another output folder"
            )
        if not os.path.isdir(here):
            raise ValueError(f"{here!r} is not a folder")
    real_root = os.path.realpath(root)
    if not _inside(os.path.realpath(here), real_root):  # pragma: no cover - raced
        raise ValueError(f"{here!r} leads out of the output folder {root!r}")
    return here


def sha256_file(path: str | os.PathLike) -> str:
    """The SHA-256 (hex) of a file's bytes."""
    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        for block in iter(lambda: handle.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def write_prepared(
    crown,
    ply_path: str | os.PathLike,
    record_path: str | os.PathLike | None = None,
    *,
    source: str | None = None,
    geometry: str | None = None,
) -> dict:
    """Write a prepared crown's mesh (PLY) and then its record (JSON), each atomically.

    Parameters
    ----------
    crown : dentopo.PreparedCrown
    ply_path : path-like
        The mesh file (``NAME.ply``).
    record_path : path-like, optional
        The record (default: ``NAME.prepare.json`` beside the mesh).
    source : str, optional
        The input's path as the user gave it (recorded instead of the crown's).
    geometry : str, optional
        Which mesh of the input was read (recorded if given).

    Returns
    -------
    dict
        The record written.
    """
    ply_path = os.fspath(ply_path)
    if record_path is None:
        record_path = os.path.splitext(ply_path)[0] + RECORD_SUFFIX
    comment = f"protocol {crown.protocol.name} {crown.protocol.digest[:12]}"
    data = prepared_ply_bytes(crown.vertices, crown.faces, comment=comment)
    atomic_write(ply_path, lambda stream: stream.write(data), binary=True)
    record = prepared_record(
        crown,
        source=source,
        mesh_file=os.path.basename(ply_path),
        mesh_sha256=hashlib.sha256(data).hexdigest(),
        geometry=geometry,
    )
    text = record_text(record)
    atomic_write(record_path, lambda stream: stream.write(text))
    return record
