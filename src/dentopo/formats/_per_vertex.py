"""Per-vertex output files: each mesh's cleaned vertices with their values, for other tools.

Four formats, each holding the same named arrays (``local_curvature``,
``local_dne``, ``sign``) for the vertices of the cleaned mesh:

``ply``
    Binary PLY with the faces.  The arrays are vertex properties (trimesh keeps
    them in ``mesh.metadata["_ply_raw"]``); ``quality`` (float) repeats
    ``local_curvature`` for MeshLab, which shows it as per-vertex quality; the
    vertices are coloured (``red, green, blue``), which every viewer shows.
``vtp``
    VTK XML PolyData with the arrays as named point arrays (``point_data`` in
    pyvista, the colouring menu in ParaView) and the colours as ``RGB``.
    Written here (base64 binary, uncompressed), so it needs no VTK.
``npz``
    numpy's archive: ``vertices``, ``faces``, the arrays and ``colors``.
``csv``
    One row per vertex: ``vertex, x, y, z, local_curvature, local_dne, sign``,
    numbers in their shortest exact text; no faces.

:func:`read_per_vertex` reads any of them back into a ``trimesh.Trimesh``
whose ``vertex_attributes`` hold the arrays.
"""

from __future__ import annotations

import base64
import contextlib
import csv
import hashlib
import json
import os
import xml.etree.ElementTree as ET
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from numbers import Real
from typing import TYPE_CHECKING

import numpy as np

from ..figures import DEFAULT_PERCENTILE, color_scale
from ._atomic import atomic_write

if TYPE_CHECKING:  # imported where a file is read back (writing needs no Trimesh)
    import trimesh

#: Suffix of the per-vertex files this tool writes (``tooth.dentopo.ply``);
#: such files are never picked up as inputs from a directory.
OUTPUT_SUFFIX = ".dentopo"

#: Per-vertex formats, by name (the name is also the file's extension).
PER_VERTEX_FORMATS = ("ply", "vtp", "npz", "csv")

#: What ``--per-vertex`` writes unless told otherwise: the PLY for viewers, the CSV for tables.
DEFAULT_PER_VERTEX_FORMATS = ("ply", "csv")

#: The ``sign`` array's type: +1 where ``local_dne >= 0`` (counted in positive_dne), else -1.
SIGN_DTYPE = np.int8


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


def per_vertex_formats(formats: str | Iterable[str]) -> tuple[str, ...]:
    """Validated per-vertex formats from ``"ply,vtp"`` or ``["ply", "csv"]`` (order kept).

    Raises
    ------
    ValueError
        For an unknown or empty choice.
    """
    items = [formats] if isinstance(formats, str) else list(formats)
    names = [part.strip().lower() for item in items for part in str(item).split(",")]
    names = [name for name in names if name]
    unknown = [name for name in names if name not in PER_VERTEX_FORMATS]
    if unknown:
        raise ValueError(
            f"unknown per-vertex format {unknown[0]!r}: use {', '.join(PER_VERTEX_FORMATS)}"
        )
    if not names:
        raise ValueError(f"no per-vertex format given: use {', '.join(PER_VERTEX_FORMATS)}")
    return tuple(dict.fromkeys(names))


@dataclass(frozen=True)
class PerVertexOptions:
    """What the per-vertex files of a batch are written as (checked when made).

    Attributes
    ----------
    formats : tuple of str
        Some of :data:`PER_VERTEX_FORMATS` (a ``"ply,vtp"`` string is accepted).
    limits : float or (float, float), optional
        Fixed colour limits ``L`` or ``(-L, L)``, as in the pictures; by
        default each mesh's own `percentile` of ``|local_curvature|``.
    percentile : float, default 98
        The colour limit's percentile when `limits` is None.
    """

    formats: tuple[str, ...] = DEFAULT_PER_VERTEX_FORMATS
    limits: float | tuple[float, float] | None = None
    percentile: float = DEFAULT_PERCENTILE

    def __post_init__(self):
        object.__setattr__(self, "formats", per_vertex_formats(self.formats))
        if self.limits is not None:
            limits = self.limits
            if not isinstance(limits, Real):
                limits = tuple(float(v) for v in limits)
            object.__setattr__(self, "limits", limits)
            color_scale(limits=limits)  # raises for asymmetric or non-positive limits
        else:
            color_scale([1.0], percentile=self.percentile)  # raises for a bad percentile


def per_vertex_arrays(result) -> dict[str, np.ndarray]:
    """The named per-vertex arrays of a result, in the order they are written.

    ``local_curvature`` and ``local_dne`` (float64) as in the result, and
    ``sign`` (int8): +1 where ``local_dne >= 0`` (the vertices counted in
    ``positive_dne``), -1 elsewhere.
    """
    curvature = np.asarray(result.local_curvature, dtype=np.float64)
    local_dne = np.asarray(result.local_dne, dtype=np.float64)
    sign = np.where(local_dne >= 0, 1, -1).astype(SIGN_DTYPE)
    return {"local_curvature": curvature, "local_dne": local_dne, "sign": sign}


# --- writers ---------------------------------------------------------------------------------

_PLY_TYPES = {
    "f8": "double",
    "f4": "float",
    "u1": "uchar",
    "i1": "char",
    "u2": "ushort",
    "i2": "short",
    "u4": "uint",
    "i4": "int",
}


def _ply_bytes(vertices, faces, arrays, colors, comment: str) -> bytes:
    fields = [("x", "<f8"), ("y", "<f8"), ("z", "<f8")]
    fields += [("red", "u1"), ("green", "u1"), ("blue", "u1")]
    fields += [(name, array.dtype.newbyteorder("<").str) for name, array in arrays.items()]
    fields += [("quality", "<f4")]
    vertex = np.empty(len(vertices), dtype=fields)
    vertex["x"], vertex["y"], vertex["z"] = vertices.T
    vertex["red"], vertex["green"], vertex["blue"] = colors.T
    for name, array in arrays.items():
        vertex[name] = array
    vertex["quality"] = arrays["local_curvature"]
    face = np.empty(len(faces), dtype=[("count", "u1"), ("index", "<i4", (3,))])
    face["count"] = 3
    face["index"] = faces
    header = ["ply", "format binary_little_endian 1.0"]
    header += ["comment dentopo per-vertex output: signed curvature and local DNE"]
    header += [f"comment {comment}", f"element vertex {len(vertex)}"]
    for name in vertex.dtype.names:
        kind = vertex.dtype[name].str.lstrip("<>|=")
        header.append(f"property {_PLY_TYPES[kind]} {name}")
    header += [f"element face {len(face)}", "property list uchar int vertex_indices"]
    header += ["end_header", ""]
    return "\n".join(header).encode("ascii") + vertex.tobytes() + face.tobytes()


_VTK_TYPES = {
    "f8": "Float64",
    "f4": "Float32",
    "u1": "UInt8",
    "i1": "Int8",
    "u2": "UInt16",
    "i2": "Int16",
    "u4": "UInt32",
    "i4": "Int32",
    "u8": "UInt64",
    "i8": "Int64",
}
_NUMPY_TYPES = {vtk: np.dtype("<" + kind) for kind, vtk in _VTK_TYPES.items()}


def _vtk_array(array: np.ndarray, name: str | None = None) -> str:
    """One inline ``DataArray``: base64 of a UInt64 byte count followed by the data."""
    array = np.ascontiguousarray(array, dtype=array.dtype.newbyteorder("<"))
    kind = array.dtype.str.lstrip("<>|=")
    data = array.tobytes()
    payload = base64.b64encode(np.uint64(len(data)).tobytes() + data).decode("ascii")
    components = 1 if array.ndim == 1 else array.shape[1]
    attributes = f'type="{_VTK_TYPES[kind]}"'
    if name is not None:
        attributes += f' Name="{name}"'
    if components != 1:
        attributes += f' NumberOfComponents="{components}"'
    return f'<DataArray {attributes} format="binary">{payload}</DataArray>'


def vtp_document(vertices, faces, *, point_data: dict = (), cell_data: dict = ()) -> str:
    """A VTK XML PolyData file of triangles with named point and cell arrays (base64, binary).

    The first array of each kind is marked as its active scalars.
    """
    point_data, cell_data = dict(point_data), dict(cell_data)
    connectivity = np.asarray(faces, dtype=np.int64).ravel()
    offsets = np.arange(3, 3 * len(faces) + 1, 3, dtype=np.int64)
    lines = [
        '<?xml version="1.0"?>',
        '<VTKFile type="PolyData" version="1.0" byte_order="LittleEndian" header_type="UInt64">',
        "<PolyData>",
        f'<Piece NumberOfPoints="{len(vertices)}" NumberOfVerts="0" NumberOfLines="0" '
        f'NumberOfStrips="0" NumberOfPolys="{len(faces)}">',
    ]
    for tag, arrays in (("PointData", point_data), ("CellData", cell_data)):
        if arrays:
            lines.append(f'<{tag} Scalars="{next(iter(arrays))}">')
            lines += [_vtk_array(array, name) for name, array in arrays.items()]
            lines.append(f"</{tag}>")
    lines += [
        "<Points>",
        _vtk_array(np.asarray(vertices, dtype=np.float64), "Points"),
        "</Points>",
        "<Polys>",
        _vtk_array(connectivity, "connectivity"),
        _vtk_array(offsets, "offsets"),
        "</Polys>",
        "</Piece>",
        "</PolyData>",
        "</VTKFile>",
        "",
    ]
    return "\n".join(lines)


def _vtp_text(vertices, faces, arrays, colors) -> str:
    return vtp_document(vertices, faces, point_data={**arrays, "RGB": colors})


def _write_csv(stream, vertices, arrays) -> None:
    writer = csv.writer(stream, lineterminator="\n")
    writer.writerow(["vertex", "x", "y", "z", *arrays])
    columns = [vertices[:, 0], vertices[:, 1], vertices[:, 2], *arrays.values()]
    for i, row in enumerate(zip(*(column.tolist() for column in columns), strict=True)):
        writer.writerow([i, *(repr(value) for value in row)])


def write_per_vertex(
    directory: str | os.PathLike,
    name: str,
    result,
    *,
    formats: str | Iterable[str] = DEFAULT_PER_VERTEX_FORMATS,
    limits=None,
    percentile: float = DEFAULT_PERCENTILE,
) -> dict[str, str]:
    """Write one mesh's per-vertex values as ``<directory>/<name>.dentopo.<format>``.

    Parameters
    ----------
    directory : path-like
        An existing directory.
    name : str
        The files' base name (see :func:`per_vertex_names`).
    result : AriaDNEResult
        The values and the cleaned mesh they refer to; not modified.
    formats : str or iterable of str, default ("ply", "csv")
        Some of :data:`PER_VERTEX_FORMATS` (see the module's docstring).
    limits : float or (float, float), optional
        Fixed colour limits ``L`` or ``(-L, L)`` of the vertex colours (PLY,
        VTP, NPZ), as in :func:`dentopo.color_scale`; by default the
        `percentile` of ``|local_curvature|`` of this mesh.
    percentile : float, default 98
        The colour limit's percentile when `limits` is None.

    Returns
    -------
    dict
        The path written for each format, in the order given.

    Raises
    ------
    ValueError
        For an unknown format or bad colour limits.
    OSError
        If a file cannot be written (a full disk); its ``filename`` is the file.
    """
    formats = per_vertex_formats(formats)
    base = os.path.join(os.fspath(directory), name + OUTPUT_SUFFIX)
    vertices = np.asarray(result.mesh.vertices, dtype=np.float64)
    faces = np.asarray(result.mesh.faces, dtype=np.int64)
    arrays = per_vertex_arrays(result)
    curvature = arrays["local_curvature"]
    scale = color_scale(curvature, limits=limits, percentile=percentile)
    colors = scale.rgb(curvature)
    low, high = scale.limits
    comment = f"colours: local_curvature on a diverging scale from {low!r} (blue) to {high!r} (red)"

    paths = {}
    for fmt in formats:
        path = f"{base}.{fmt}"
        with naming_the_file(path):
            if fmt == "ply":
                data = _ply_bytes(vertices, faces, arrays, colors, comment)
                atomic_write(path, lambda stream, data=data: stream.write(data), binary=True)
            elif fmt == "vtp":
                text = _vtp_text(vertices, faces, arrays, colors)
                atomic_write(path, lambda stream, text=text: stream.write(text))
            elif fmt == "npz":
                mesh = {"vertices": vertices, "faces": faces, **arrays, "colors": colors}
                atomic_write(path, lambda stream, mesh=mesh: np.savez(stream, **mesh), binary=True)
            else:
                atomic_write(path, lambda stream: _write_csv(stream, vertices, arrays))
        paths[fmt] = path
    return paths


@contextlib.contextmanager
def naming_the_file(path: str):
    """Raise an ``OSError`` met while writing `path` with `path` as its ``filename``.

    A full disk fails in ``write()``, whose ``OSError`` names no file; a message
    can then say which output could not be written.
    """
    try:
        yield
    except OSError as exc:
        if exc.filename is not None:
            raise
        error = OSError(exc.errno, exc.strerror or str(exc) or type(exc).__name__, path)
        raise error from exc


# --- which mesh the files of a folder were written for ----------------------------------------

#: In a per-vertex folder: one JSON line ``{"name": ..., "source": ...}`` each time the files of
#: a base name are written, saying for which mesh file (resolved path); the last line of a name
#: counts; ``"protocol"`` too (its label) when the mesh was prepared before it was measured
#: (``--prepare``), so that the files hold the prepared mesh.  Hidden, so never taken for a mesh.
SOURCES_FILE = ".dentopo-sources.jsonl"

_FACES = ".faces"  # the per-face files' extra suffix (``_per_face.FACES_SUFFIX``)


def per_vertex_paths(
    directory: str | os.PathLike,
    name: str,
    formats: str | Iterable[str] = DEFAULT_PER_VERTEX_FORMATS,
    *,
    vertices: bool = True,
    faces: bool = False,
) -> list[str]:
    """The files written for one mesh, for each format.

    ``NAME.dentopo.FMT`` (`vertices`: ariaDNE's values) and
    ``NAME.dentopo.faces.FMT`` (`faces`: the per-face values of slope and OPC).
    """
    base = os.path.join(os.fspath(directory), name + OUTPUT_SUFFIX)
    formats = per_vertex_formats(formats)
    paths = [f"{base}.{fmt}" for fmt in formats] if vertices else []
    return paths + ([f"{base}{_FACES}.{fmt}" for fmt in formats] if faces else [])


def record_source(
    directory: str | os.PathLike,
    name: str,
    source: str | os.PathLike,
    protocol: str | None = None,
) -> None:
    """Note in `directory`'s :data:`SOURCES_FILE` that the files of `name` are those of `source`.

    With a `protocol` (a preparation protocol's label) the line also says
    that the files hold the mesh prepared from `source` with it (its
    vertices), not the file's own.

    One line appended in one write (``O_APPEND``), so that runs writing into one
    folder at the same time do not mix their lines; a link at its place is not
    followed.

    Raises
    ------
    OSError
        If it cannot be written (named in ``filename``).
    """
    path = os.path.join(os.fspath(directory), SOURCES_FILE)
    entry = {"name": name, "source": os.path.realpath(os.fspath(source))}
    if protocol is not None:
        entry["protocol"] = protocol
    line = json.dumps(entry)
    flags = os.O_WRONLY | os.O_APPEND | os.O_CREAT | getattr(os, "O_NOFOLLOW", 0)
    with naming_the_file(path):
        descriptor = os.open(path, flags, 0o644)
        try:
            os.write(descriptor, (line + "\n").encode("utf-8", "surrogatepass"))
        finally:
            os.close(descriptor)


def recorded_sources(directory: str | os.PathLike) -> dict[str, str]:
    """The mesh each base name's files in `directory` were last written for (:func:`record_source`).

    Unreadable lines (a run killed while appending) are skipped; a missing or
    unreadable record gives an empty mapping.
    """
    path = os.path.join(os.fspath(directory), SOURCES_FILE)
    sources: dict[str, str] = {}
    try:
        with open(path, encoding="utf-8", errors="surrogateescape") as stream:
            for line in stream:
                try:
                    entry = json.loads(line)
                    sources[str(entry["name"])] = str(entry["source"])
                except (ValueError, KeyError, TypeError):
                    continue
    except OSError:
        return {}
    return sources


def replaced_files(
    directory: str | os.PathLike, sources: dict[str, str]
) -> list[tuple[str, str | None, str]]:
    """The base names whose files in `directory` were written for another mesh than planned.

    Parameters
    ----------
    directory : path-like
        A per-vertex folder.
    sources : dict
        The mesh file each base name is about to be written for.

    Returns
    -------
    list of (name, previous, source)
        For each name that already has files in `directory`, written for another
        mesh (`previous`, resolved), or whose mesh was not recorded (`previous`
        None: files of an earlier version, or not written by dentopo), sorted
        by name.  Rewriting the files of the same mesh is not listed.
    """
    directory = os.fspath(directory)
    try:
        entries = os.listdir(directory)
    except OSError:
        return []
    present = set()
    endings = [
        f"{OUTPUT_SUFFIX}{faces}.{fmt}" for faces in (_FACES, "") for fmt in PER_VERTEX_FORMATS
    ]
    for entry in entries:
        for ending in endings:
            if entry.endswith(ending):
                present.add(entry[: -len(ending)])
                break
    recorded = recorded_sources(directory) if present else {}
    replaced = []
    for name in sorted(present.intersection(sources)):
        source = os.path.realpath(sources[name])
        previous = recorded.get(name)
        if previous != source:
            replaced.append((name, previous, source))
    return replaced


# --- readers ---------------------------------------------------------------------------------

_PLY_STANDARD = frozenset({"x", "y", "z", "red", "green", "blue", "alpha", "nx", "ny", "nz"})
#: Written for MeshLab only (a float32 copy of local_curvature): not read back as an array.
_PLY_ONLY = frozenset({"quality"})
_DTYPES = {"sign": SIGN_DTYPE}


def _mesh(vertices, faces, attributes: dict, colors=None, path: str = "") -> trimesh.Trimesh:
    vertices = np.asarray(vertices, dtype=np.float64)
    for name, values in attributes.items():
        if len(values) != len(vertices):
            raise ValueError(
                f"{path!r}: {name} has {len(values)} values for {len(vertices)} vertices"
            )
    import trimesh

    return trimesh.Trimesh(
        vertices=vertices,
        faces=faces,
        vertex_colors=colors,
        vertex_attributes=attributes,
        metadata={"file_path": os.path.abspath(path), "file_name": os.path.basename(path)},
        process=False,
    )


def _read_ply(path: str) -> trimesh.Trimesh:
    import trimesh

    loaded = trimesh.load(path, file_type="ply", process=False)
    raw = (loaded.metadata.get("_ply_raw") or {}).get("vertex", {}).get("data")
    attributes = {}
    if raw is not None and raw.dtype.names:
        for name in raw.dtype.names:
            if name not in _PLY_STANDARD and name not in _PLY_ONLY:
                attributes[name] = np.asarray(raw[name]).reshape(len(raw), -1).squeeze(axis=1)
    faces = getattr(loaded, "faces", None)
    colors = None
    visual = getattr(loaded, "visual", None)
    if raw is not None and raw.dtype.names and "red" in raw.dtype.names:
        colors = getattr(visual, "vertex_colors", None)
    elif getattr(loaded, "colors", None) is not None and len(loaded.colors):  # a point cloud
        colors = loaded.colors
    return _mesh(loaded.vertices, faces, attributes, colors, path)


def _decode_vtk(element: ET.Element, header_type: str, path: str) -> np.ndarray:
    kind = element.get("type")
    if kind not in _NUMPY_TYPES:
        raise ValueError(f"{path!r}: unsupported VTK array type {kind!r}")
    dtype = _NUMPY_TYPES[kind]
    components = int(element.get("NumberOfComponents", "1"))
    encoding = element.get("format", "ascii")
    text = (element.text or "").strip()
    if encoding == "ascii":
        values = np.array(text.split(), dtype=np.float64 if dtype.kind == "f" else np.int64)
        values = values.astype(dtype)
    elif encoding == "binary":
        header = np.dtype("<u8" if header_type == "UInt64" else "<u4")
        data = base64.b64decode("".join(text.split()))
        size = int(np.frombuffer(data[: header.itemsize], dtype=header)[0])
        values = np.frombuffer(data[header.itemsize : header.itemsize + size], dtype=dtype)
    else:
        raise ValueError(
            f"{path!r}: VTK data in {encoding!r} form is not read here (open it with pyvista)"
        )
    return values.reshape(-1, components) if components > 1 else values


def _read_vtp(path: str) -> trimesh.Trimesh:
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as exc:
        raise ValueError(f"{path!r} is not VTK XML: {exc}") from exc
    if root.tag != "VTKFile" or root.get("type") != "PolyData":
        raise ValueError(f"{path!r} is not a VTK PolyData file")
    if root.get("compressor"):
        raise ValueError(f"{path!r} is compressed, which is not read here (open it with pyvista)")
    if root.get("byte_order", "LittleEndian") != "LittleEndian":
        raise ValueError(f"{path!r} is big-endian, which is not read here (open it with pyvista)")
    header_type = root.get("header_type", "UInt32")
    piece = root.find("PolyData/Piece")
    if piece is None:
        raise ValueError(f"{path!r} has no PolyData piece")

    def array(element):
        return _decode_vtk(element, header_type, path)

    points = piece.find("Points/DataArray")
    if points is None:
        raise ValueError(f"{path!r} has no points")
    vertices = array(points).reshape(-1, 3)
    faces = None
    polys = {e.get("Name"): e for e in piece.findall("Polys/DataArray")}
    if "connectivity" in polys and "offsets" in polys:
        connectivity, offsets = array(polys["connectivity"]), array(polys["offsets"])
        if not np.array_equal(offsets, np.arange(3, 3 * len(offsets) + 1, 3)):
            raise ValueError(f"{path!r} has polygons that are not triangles")
        faces = connectivity.reshape(-1, 3).astype(np.int64)
    attributes, colors = {}, None
    for element in piece.findall("PointData/DataArray"):
        name = element.get("Name")
        if name == "RGB":
            colors = array(element)
        elif name:
            attributes[name] = array(element).copy()
    return _mesh(vertices, faces, attributes, colors, path)


def _read_npz(path: str) -> trimesh.Trimesh:
    with np.load(path, allow_pickle=False) as data:
        arrays = {name: data[name] for name in data.files}
    if "vertices" not in arrays:
        raise ValueError(f"{path!r} has no vertices array")
    vertices = arrays.pop("vertices")
    faces = arrays.pop("faces", None)
    colors = arrays.pop("colors", None)
    return _mesh(vertices, faces, arrays, colors, path)


def _read_csv(path: str) -> trimesh.Trimesh:
    with open(path, encoding="utf-8", newline="") as stream:
        reader = csv.reader(stream)
        header = next(reader, None)
        rows = list(reader)
    if not header or not {"x", "y", "z"} <= set(header):
        raise ValueError(f"{path!r} is not a per-vertex table (no x, y, z columns)")
    try:
        table = np.array(rows, dtype=np.float64).reshape(len(rows), len(header))
    except ValueError as exc:
        raise ValueError(f"{path!r} has a malformed value: {exc}") from exc
    columns = dict(zip(header, table.T, strict=True))
    vertices = np.column_stack([columns.pop(axis) for axis in ("x", "y", "z")])
    columns.pop("vertex", None)
    attributes = {
        name: values.astype(_DTYPES.get(name, np.float64)) for name, values in columns.items()
    }
    return _mesh(vertices, None, attributes, None, path)


_READERS = {".ply": _read_ply, ".vtp": _read_vtp, ".npz": _read_npz, ".csv": _read_csv}


def read_per_vertex(path: str | os.PathLike) -> trimesh.Trimesh:
    """Read a per-vertex file (PLY, VTP, NPZ or CSV) into a mesh with its named arrays.

    Parameters
    ----------
    path : str or path-like
        A file written by :func:`write_per_vertex` (``--per-vertex``), or
        another file in one of these formats.

    Returns
    -------
    trimesh.Trimesh
        The vertices (and faces; a CSV has none, so the mesh has no faces),
        unprocessed, with ``vertex_attributes`` holding the named arrays
        (``local_curvature``, ``local_dne``, ``sign``) and the vertex colours
        where the file has them.

    Raises
    ------
    ValueError
        For an unknown extension or a file that is not such a table or mesh.
    """
    path = os.fspath(path)
    ext = os.path.splitext(path)[1].lower()
    if ext not in _READERS:
        raise ValueError(
            f"cannot tell the per-vertex format of {path!r}: use one of {', '.join(_READERS)}"
        )
    return _READERS[ext](path)
