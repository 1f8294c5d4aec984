"""Per-vertex output files: each mesh's cleaned vertices with their values."""

from __future__ import annotations

import hashlib
import os
from collections.abc import Sequence

import numpy as np

from ..figures import color_scale
from ._atomic import atomic_write

#: Suffix of the per-vertex files this tool writes (``tooth.dentopo.ply``);
#: such files are never picked up as inputs from a directory.
OUTPUT_SUFFIX = ".dentopo"


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
    """Write one mesh's per-vertex values as ``<name>.dentopo.ply`` and ``.csv``.

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
            "comment dentopo per-vertex output: signed curvature and local DNE",
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
