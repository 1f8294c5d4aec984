"""Per-face output files: each face's slope, OPC bin and OPC patch, for other tools.

Slope and OPC are face-wise metrics; their values are written beside the
per-vertex files as ``<name>.dentopo.faces.<format>``, on the mesh they were
measured on (molaR's cleaning: faces of zero area dropped; turned to +z if
``orient="auto"`` turned it), in the same four formats:

``ply``
    Binary PLY; the values are face properties (``slope``, ``opc_bin``,
    ``opc_patch``), and ``quality`` repeats the slope for MeshLab.
``vtp``
    VTK XML PolyData with the values as cell arrays (``cell_data`` in
    pyvista, the colouring menu in ParaView).
``npz``
    ``vertices``, ``faces`` and the arrays.
``csv``
    One row per face: ``face, v1, v2, v3`` (0-based vertex indices) and the values.

Which arrays: ``slope`` (whole degrees) when slope was computed; ``opc_bin``
(1..8) and ``opc_patch`` (patch label) when OPC was, or else OPCR's OPC at
rotation 0.
"""

from __future__ import annotations

import csv
import os
from collections.abc import Iterable

import numpy as np

from ._atomic import atomic_write
from ._per_vertex import OUTPUT_SUFFIX, per_vertex_formats, vtp_document

#: The per-face files' suffix after the output suffix: ``tooth.dentopo.faces.ply``.
FACES_SUFFIX = ".faces"

_PLY_TYPES = {"i2": "short", "u1": "uchar", "i4": "int", "f4": "float"}


def per_face_arrays(results: dict) -> dict[str, np.ndarray]:
    """The named per-face arrays of the face-wise results (``{"slope": ..., "opc": ...}``)."""
    arrays = {}
    if "slope" in results:
        arrays["slope"] = np.asarray(results["slope"].face_slope).astype(np.int16)
    first = results["opc"] if "opc" in results else getattr(results.get("opcr"), "first", None)
    if first is not None:
        arrays["opc_bin"] = np.asarray(first.face_bin).astype(np.uint8)
        arrays["opc_patch"] = np.asarray(first.face_patch).astype(np.int32)
    return arrays


def _ply_bytes(vertices, faces, arrays) -> bytes:
    vertex = np.ascontiguousarray(vertices, dtype="<f8")
    fields = [("count", "u1"), ("index", "<i4", (3,))]
    fields += [(name, array.dtype.newbyteorder("<").str) for name, array in arrays.items()]
    if "slope" in arrays:
        fields.append(("quality", "<f4"))
    face = np.empty(len(faces), dtype=fields)
    face["count"] = 3
    face["index"] = faces
    for name, array in arrays.items():
        face[name] = array
    if "slope" in arrays:
        face["quality"] = arrays["slope"]
    header = ["ply", "format binary_little_endian 1.0"]
    header += ["comment dentopo per-face output: slope (degrees), OPC bin and patch"]
    header += [f"element vertex {len(vertex)}"]
    header += ["property double x", "property double y", "property double z"]
    header += [f"element face {len(face)}", "property list uchar int vertex_indices"]
    for name in face.dtype.names[2:]:
        header.append(f"property {_PLY_TYPES[face.dtype[name].str.lstrip('<>|=')]} {name}")
    header += ["end_header", ""]
    return "\n".join(header).encode("ascii") + vertex.tobytes() + face.tobytes()


def _write_csv(stream, faces, arrays) -> None:
    writer = csv.writer(stream, lineterminator="\n")
    writer.writerow(["face", "v1", "v2", "v3", *arrays])
    columns = [faces[:, 0], faces[:, 1], faces[:, 2], *arrays.values()]
    for i, row in enumerate(zip(*(column.tolist() for column in columns), strict=True)):
        writer.writerow([i, *row])


def write_per_face(
    directory: str | os.PathLike,
    name: str,
    results: dict,
    *,
    formats: str | Iterable[str] = ("ply", "csv"),
) -> dict[str, str]:
    """Write one mesh's per-face values as ``<directory>/<name>.dentopo.faces.<format>``.

    Parameters
    ----------
    directory : path-like
        An existing directory.
    name : str
        The files' base name.
    results : dict
        Face-wise results by metric name: some of ``"slope"``
        (:class:`dentopo.SlopeResult`), ``"opc"``, ``"opcr"``; they refer to
        the same mesh.  Not modified.
    formats : str or iterable of str
        Some of ``"ply"``, ``"vtp"``, ``"npz"``, ``"csv"``.

    Returns
    -------
    dict
        The path written for each format (none if no face-wise result was given).
    """
    formats = per_vertex_formats(formats)
    arrays = per_face_arrays(results)
    if not arrays:
        return {}
    mesh = next(iter(results.values())).mesh
    if "opcr" in results and "opc" not in results:
        mesh = results["opcr"].first.mesh
    vertices = np.asarray(mesh.vertices, dtype=np.float64)
    faces = np.asarray(mesh.faces, dtype=np.int64)
    for array_name, array in arrays.items():
        if len(array) != len(faces):
            raise ValueError(f"{array_name} has {len(array)} values for {len(faces)} faces")
    base = os.path.join(os.fspath(directory), name + OUTPUT_SUFFIX + FACES_SUFFIX)
    paths = {}
    for fmt in formats:
        path = f"{base}.{fmt}"
        if fmt == "ply":
            data = _ply_bytes(vertices, faces, arrays)
            atomic_write(path, lambda stream, data=data: stream.write(data), binary=True)
        elif fmt == "vtp":
            text = vtp_document(vertices, faces, cell_data=arrays)
            atomic_write(path, lambda stream, text=text: stream.write(text))
        elif fmt == "npz":
            data = {"vertices": vertices, "faces": faces, **arrays}
            atomic_write(path, lambda stream, data=data: np.savez(stream, **data), binary=True)
        else:
            atomic_write(path, lambda stream: _write_csv(stream, faces, arrays))
        paths[fmt] = path
    return paths
