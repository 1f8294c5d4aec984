"""Writing PLY files for tests: any format, any property types, counts declared at will.

The files are written byte by byte here (not by trimesh), so that a test can
make exactly the file it needs: truncated, with header counts that disagree
with the body, with NaN coordinates or negative indices, with polygons.
"""

from __future__ import annotations

import numpy as np

#: PLY scalar type names and the numpy type each stands for.
PLY_TYPES = {
    "char": "i1",
    "uchar": "u1",
    "short": "i2",
    "ushort": "u2",
    "int": "i4",
    "uint": "u4",
    "float": "f4",
    "double": "f8",
    "int8": "i1",
    "uint8": "u1",
    "int16": "i2",
    "uint16": "u2",
    "int32": "i4",
    "uint32": "u4",
    "float32": "f4",
    "float64": "f8",
}


def ply_bytes(
    vertices,
    faces,
    *,
    fmt: str = "ascii",
    vertex_type: str = "double",
    count_type: str = "uchar",
    index_type: str = "int",
    index_name: str = "vertex_indices",
    vertex_extra: dict | None = None,
    face_extra: dict | None = None,
    declared_vertices: int | None = None,
    declared_faces: int | None = None,
    comments: tuple[str, ...] = ("written by tests/plyfile.py",),
    newline: str = "\n",
) -> bytes:
    """A PLY file holding `vertices` and `faces` (a list of index sequences, any lengths).

    ``vertex_extra`` / ``face_extra`` map extra scalar property names to
    ``(ply_type, values)``; they are written after x, y, z (after the index
    list).  ``declared_*`` override the counts the header states.
    """
    vertices = np.asarray(vertices, dtype=np.float64)
    faces = [list(map(int, face)) for face in faces]
    vertex_extra = vertex_extra or {}
    face_extra = face_extra or {}
    n_v = len(vertices) if declared_vertices is None else declared_vertices
    n_f = len(faces) if declared_faces is None else declared_faces
    header = ["ply", f"format {fmt} 1.0", *(f"comment {c}" for c in comments)]
    header += [f"element vertex {n_v}"]
    header += [f"property {vertex_type} {axis}" for axis in "xyz"]
    header += [f"property {kind} {name}" for name, (kind, _) in vertex_extra.items()]
    header += [f"element face {n_f}", f"property list {count_type} {index_type} {index_name}"]
    header += [f"property {kind} {name}" for name, (kind, _) in face_extra.items()]
    header += ["end_header"]
    head = (newline.join(header) + newline).encode("ascii")
    if fmt == "ascii":
        rows = []
        for i, v in enumerate(vertices):
            extra = [_text(values[i]) for _, values in vertex_extra.values()]
            rows.append(" ".join([*map(_text, v), *extra]))
        for i, face in enumerate(faces):
            extra = [_text(values[i]) for _, values in face_extra.values()]
            rows.append(" ".join(map(str, [len(face), *face, *extra])))
        return head + (newline.join(rows) + newline).encode("ascii")
    order = {"binary_little_endian": "<", "binary_big_endian": ">"}[fmt]
    parts = [head]
    vertex_dtype = np.dtype(
        [(axis, order + PLY_TYPES[vertex_type]) for axis in "xyz"]
        + [(name, order + PLY_TYPES[kind]) for name, (kind, _) in vertex_extra.items()]
    )
    table = np.zeros(len(vertices), dtype=vertex_dtype)
    for j, axis in enumerate("xyz"):
        table[axis] = vertices[:, j]
    for name, (_, values) in vertex_extra.items():
        table[name] = values
    parts.append(table.tobytes())
    count = np.dtype(order + PLY_TYPES[count_type])
    index = np.dtype(order + PLY_TYPES[index_type])
    for i, face in enumerate(faces):
        parts.append(np.array([len(face)], dtype=count).tobytes())
        parts.append(np.array(face, dtype=index).tobytes())
        for kind, values in face_extra.values():
            parts.append(np.array([values[i]], dtype=order + PLY_TYPES[kind]).tobytes())
    return b"".join(parts)


def _text(value) -> str:
    value = float(value)
    return str(int(value)) if value.is_integer() and abs(value) < 2**53 else repr(value)


def write_ply(path, vertices, faces, **options):
    """Write :func:`ply_bytes` to `path`; return the path."""
    path.write_bytes(ply_bytes(vertices, faces, **options))
    return path


def obj_text(vertices, faces) -> str:
    """An OBJ file: ``v`` lines (NaN and infinity as Python writes them), 1-based ``f`` lines."""
    lines = [f"v {' '.join(_text(c) for c in v)}" for v in np.asarray(vertices, dtype=float)]
    lines += ["f " + " ".join(str(i + 1) for i in face) for face in faces]
    return "\n".join(lines) + "\n"
