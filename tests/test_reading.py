"""Reading mesh files strictly: a damaged file is an error, never a wrong number (issue 14).

Items 1-5: a PLY cut short, header counts that disagree with the body, NaN or
infinite coordinates, negative or out-of-range face indices, and results that
depended on the mesh's units (absolute merge and degeneracy tolerances).  Each
bad file is written byte by byte (``plyfile``) and read through the library;
``tests/faults/test_bad_files.py`` reads the same files through the command line.
"""

from __future__ import annotations

import re

import numpy as np
import pytest
import trimesh

from conftest import MESHES, shared_mesh
from dentopo import ariaDNE, load_mesh
from dentopo.mesh import as_arrays, length_scale, merge_vertices, read_ply
from dentopo.samples import tooth
from plyfile import obj_text, ply_bytes, write_ply

FORMATS = ("ascii", "binary_little_endian", "binary_big_endian")


def crown():
    return tooth(rings=10)  # 331 vertices, 600 faces


def raises(path, *words):
    """`ariaDNE(path)` raises a one-line ValueError naming the file and holding `words`."""
    with pytest.raises(ValueError) as info:
        ariaDNE(str(path))
    message = str(info.value)
    assert "\n" not in message
    assert path.name in message
    for word in words:
        assert word in message, f"{word!r} not in {message!r}"
    return message


# --- item 1: a file cut short ------------------------------------------------------------


@pytest.mark.parametrize("fmt", FORMATS)
@pytest.mark.parametrize("fraction", [0.7, 0.3, 0.999])
def test_a_ply_cut_short_is_an_error_saying_truncated(tmp_path, fmt, fraction):
    mesh = crown()
    data = ply_bytes(mesh.vertices, mesh.faces, fmt=fmt)
    path = tmp_path / "cut.ply"
    path.write_bytes(data[: int(len(data) * fraction)])
    message = raises(path, "truncated", "declares 331 vertices and 600 faces")
    found = re.search(r"ends after (\d+) vertices and (\d+) faces", message)
    assert found, message
    assert (int(found[1]), int(found[2])) < (331, 600)


@pytest.mark.parametrize("row", [100, 331 + 420])
def test_the_found_counts_of_a_cut_ascii_ply_are_its_complete_rows(tmp_path, row):
    mesh = crown()
    data = ply_bytes(mesh.vertices, mesh.faces)
    at = data.index(b"end_header\n") + len(b"end_header\n")
    for _ in range(row):  # past `row` complete rows
        at = data.index(b"\n", at) + 1
    path = tmp_path / "cut.ply"
    path.write_bytes(data[: at + 3])  # and 3 bytes of the next
    found = f"{min(row, 331)} vertices and {max(row - 331, 0)} faces"
    raises(path, "truncated", f"ends after {found}")


# --- item 2: header counts that disagree with the body ------------------------------------


@pytest.mark.parametrize(
    ("declared", "words"),
    [
        # fewer faces in the body than declared: the data ends early
        (
            {"declared_faces": 605},
            ["truncated", "declares 331 vertices and 605 faces", "600 faces"],
        ),
        # more vertices in the body than declared
        ({"declared_vertices": 326}, ["declares 326 vertices", "holds 331 vertices and 600 faces"]),
        # fewer vertices in the body than declared
        ({"declared_vertices": 336}, ["declares 336 vertices", "holds 331 vertices and 600 faces"]),
        # more faces in the body than declared
        (
            {"declared_faces": 590},
            ["declares 331 vertices and 590 faces", "holds 331 vertices and 600"],
        ),
    ],
)
def test_ascii_header_counts_that_disagree_with_the_body_are_an_error(tmp_path, declared, words):
    mesh = crown()
    path = write_ply(tmp_path / "counts.ply", mesh.vertices, mesh.faces, **declared)
    raises(path, *words)


@pytest.mark.parametrize("fmt", FORMATS[1:])
@pytest.mark.parametrize(
    "declared",
    [
        {"declared_faces": 605},
        {"declared_faces": 590},
        {"declared_vertices": 326},
        {"declared_vertices": 336},
    ],
)
def test_binary_header_counts_that_disagree_with_the_body_are_an_error(tmp_path, fmt, declared):
    mesh = crown()
    path = write_ply(tmp_path / "counts.ply", mesh.vertices, mesh.faces, fmt=fmt, **declared)
    raises(path, "the header declares")


# --- item 3: non-finite coordinates --------------------------------------------------------


@pytest.mark.parametrize("fmt", FORMATS)
@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
@pytest.mark.parametrize("vertex_type", ["float", "double"])
def test_non_finite_coordinates_in_a_ply_are_an_error(tmp_path, fmt, bad, vertex_type):
    mesh = crown()
    vertices = mesh.vertices.copy()
    vertices[17, 1] = bad
    vertices[40, 0] = bad
    path = write_ply(tmp_path / "nan.ply", vertices, mesh.faces, fmt=fmt, vertex_type=vertex_type)
    raises(path, "2 vertices have non-finite", "vertex 17 ")


def test_non_finite_coordinates_in_an_obj_are_an_error_even_unreferenced(tmp_path):
    mesh = crown()
    vertices = np.vstack([mesh.vertices, [[np.nan, 0.0, 0.0]]])  # the last: in no face
    vertices[17, 2] = np.inf
    path = tmp_path / "nan.obj"
    path.write_text(obj_text(vertices, mesh.faces))
    raises(path, "2 vertices have non-finite", "vertex 18 on line 18")


@pytest.mark.parametrize("bad", [np.nan, np.inf])
def test_non_finite_arrays_and_meshes_are_an_error(bad):
    mesh = crown()
    vertices = mesh.vertices.copy()
    vertices[[5, 9]] = bad
    given = vertices.copy()
    for candidate in [(vertices, mesh.faces), trimesh.Trimesh(vertices, mesh.faces, process=False)]:
        with pytest.raises(ValueError, match=r"2 vertices have non-finite .* vertex 5 "):
            ariaDNE(candidate)
    assert np.array_equal(vertices, given, equal_nan=True)  # the caller's arrays untouched


# --- item 4: face indices outside the vertex array ------------------------------------------


@pytest.mark.parametrize("fmt", FORMATS)
@pytest.mark.parametrize("index", [-1, -331, 331, 5000])
def test_face_indices_outside_the_vertices_are_an_error(tmp_path, fmt, index):
    mesh = crown()
    faces = mesh.faces.copy()
    faces[25, 1] = index
    faces[70, 2] = index
    path = write_ply(tmp_path / "index.ply", mesh.vertices, faces, fmt=fmt)
    raises(
        path, "2 faces have vertex indices outside [0, 330]", f"face 25 ({faces[25, 0]}, {index},"
    )


@pytest.mark.parametrize("index", [-1, 331])
def test_face_indices_outside_the_vertices_are_an_error_for_arrays(index):
    mesh = crown()
    faces = mesh.faces.copy()
    faces[12, 0] = index
    for candidate in [(mesh.vertices, faces), trimesh.Trimesh(mesh.vertices, faces, process=False)]:
        with pytest.raises(
            ValueError, match=r"1 face has vertex indices outside \[0, 330\].*face 12"
        ):
            as_arrays(candidate)


# --- item 5: the result does not depend on the mesh's units -----------------------------------

SCALES = (1e-9, 1e-7, 1e-4, 1.0, 1e3, 1e7, 1e11, 1e12)


def stored(path):
    mesh = trimesh.load(path, process=False)
    return np.asarray(mesh.vertices), np.asarray(mesh.faces)


def check_scales(tmp_path, vertices, faces, scales=SCALES, *, arrays=True):
    """DNE (1e-9 relative) and the cleaned counts are the same at every scale, file or arrays."""
    base = ariaDNE((vertices, faces))
    for scale in scales:
        path = write_ply(
            tmp_path / f"scaled {scale:g}.ply", vertices * scale, faces, fmt="binary_little_endian"
        )
        results = [ariaDNE(str(path))]
        if arrays:
            results.append(ariaDNE((vertices * scale, faces)))
        for result in results:
            assert (result.vertices, result.faces) == (base.vertices, base.faces), scale
            assert result.dne == pytest.approx(base.dne, rel=1e-9, abs=0), scale
            assert result.positive_dne == pytest.approx(base.positive_dne, rel=1e-9, abs=1e-15)


def test_dne_does_not_depend_on_the_units_generated(tmp_path):
    mesh = tooth(rings=14)
    check_scales(tmp_path, mesh.vertices, mesh.faces)


@pytest.mark.parametrize("name", ["high", "low"])
def test_dne_does_not_depend_on_the_units_shared(tmp_path, name):
    """The meshes of the issue: high at 1e-7 gave 0.0432 (not 0.1192), low at 1e11 0.0332."""
    scales = (1e-9, 1e-7, 1e-3, 1e3, 1e11, 1e12)
    check_scales(tmp_path, *stored(shared_mesh(name)), scales, arrays=False)


def test_a_soup_of_faces_is_merged_at_every_scale(tmp_path):
    """Each face with its own three vertices (as STL stores them) is rejoined, at any size."""
    mesh = crown()
    soup = mesh.vertices[mesh.faces.ravel()]
    faces = np.arange(len(soup)).reshape(-1, 3)
    base = ariaDNE(mesh)
    for scale in SCALES:
        path = write_ply(tmp_path / "soup.ply", soup * scale, faces, fmt="binary_little_endian")
        result = ariaDNE(str(path))
        assert (result.vertices, result.faces) == (331, 600), scale
        assert result.dne == pytest.approx(base.dne, rel=1e-9), scale


def test_merging_far_from_the_origin(tmp_path):
    """A mesh moved far away merges and drops exactly what it did at the origin."""
    mesh = crown()
    soup = mesh.vertices[mesh.faces.ravel()]
    faces = np.arange(len(soup)).reshape(-1, 3)
    base = ariaDNE(mesh)
    for offset in (1e3, -1e5):
        path = write_ply(tmp_path / "far.ply", soup + offset, faces, fmt="binary_little_endian")
        result = ariaDNE(str(path))
        assert (result.vertices, result.faces) == (331, 600), offset
        assert result.dne == pytest.approx(base.dne, rel=1e-6), offset


def test_a_stray_vertex_does_not_make_real_vertices_merge(tmp_path):
    """The length scale is robust: one vertex 1e6 sizes away does not inflate the tolerance."""
    mesh = crown()
    vertices = np.vstack([mesh.vertices, [[2e6, 0.0, 0.0]], mesh.vertices[:50] + 1e-6])
    n = len(mesh.vertices)
    faces = np.vstack([mesh.faces, [[0, 1, n]], [[n + 1 + i, i + 1, i] for i in range(50)]])
    path = write_ply(tmp_path / "stray.ply", vertices, faces, fmt="binary_little_endian")
    assert len(load_mesh(path).vertices) == len(vertices)  # 1e-6 apart: distinct, as in trimesh
    scale = length_scale(vertices, faces)
    assert scale == pytest.approx(length_scale(mesh.vertices, mesh.faces), rel=0.1)


def test_degenerate_faces_are_judged_relative_to_the_mesh():
    """A sliver 1e-9 of an edge high is dropped at every scale; one 1e-4 high is kept.

    Face 0 ``(a, b, c)`` is split at a point ``p`` just off its edge ``ab``: faces
    ``(a, p, c)``, ``(p, b, c)`` and the sliver ``(b, a, p)`` between ``ab`` and ``p``.
    """
    mesh = crown()
    a, b, c = mesh.faces[0]
    ab = mesh.vertices[b] - mesh.vertices[a]
    up = np.cross(ab, mesh.vertices[c] - mesh.vertices[a])
    up /= np.linalg.norm(up)
    n, m = len(mesh.vertices), len(mesh.faces)
    faces = np.vstack([mesh.faces[1:], [[a, n, c], [n, b, c], [b, a, n]]])
    for height, kept in [(1e-9, m + 1), (1e-4, m + 2)]:
        p = mesh.vertices[a] + ab / 2 + height * np.linalg.norm(ab) * up
        vertices = np.vstack([mesh.vertices, p])
        for scale in SCALES:
            result = ariaDNE((vertices * scale, faces))
            assert len(result.mesh.faces) == kept, (height, scale)


def test_merge_vertices_keeps_the_first_of_each_group_in_order():
    vertices = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1e-12, 0], [5, 5, 5], [0, 0, 1.0]])
    faces = np.array([[0, 1, 2], [3, 2, 5], [0, 5, 1]])
    merged_v, merged_f = merge_vertices(vertices, faces)
    assert np.array_equal(merged_v, vertices[[0, 1, 2, 5]])  # 3 joins 1; 4 is in no face
    assert np.array_equal(merged_f, [[0, 1, 2], [1, 2, 3], [0, 3, 1]])


@pytest.mark.parametrize("ext", ["stl", "off", "glb"])
def test_non_finite_coordinates_in_other_formats_are_an_error(tmp_path, ext):
    """trimesh reads them with ``process=False`` (nothing dropped); we check what it read."""
    mesh = crown()
    vertices = mesh.vertices.copy()
    vertices[17] = np.nan
    path = tmp_path / f"nan.{ext}"
    trimesh.Trimesh(vertices, mesh.faces, process=False).export(path)
    raises(path, "non-finite")


# --- our reader reads what trimesh reads ---------------------------------------------------

SHARED = sorted(p.stem for p in MESHES.glob("*.ply")) or ["normal"]


@pytest.mark.parametrize("name", SHARED)
def test_shared_meshes_read_exactly_as_trimesh_loads_them(name):
    """The published values came from ``trimesh.load(path)``: same vertices, same faces."""
    path = shared_mesh(name)
    ours, theirs = load_mesh(path), trimesh.load(path)
    assert np.array_equal(ours.vertices, theirs.vertices)
    assert np.array_equal(ours.faces, theirs.faces)


def variants():
    """PLY files in every layout we read, each one trimesh reads too."""
    base = {"vertex_type": "double"}
    for fmt in FORMATS:
        yield fmt, {**base, "fmt": fmt}
        yield fmt + " float", {"fmt": fmt, "vertex_type": "float"}
        yield fmt + " ushort/uint", {"fmt": fmt, "count_type": "ushort", "index_type": "uint"}
        yield fmt + " uint8/int32", {"fmt": fmt, "count_type": "uint8", "index_type": "int32"}
        yield fmt + " vertex_index", {"fmt": fmt, "index_name": "vertex_index"}
        yield fmt + " extras", {"fmt": fmt, "extras": True}
        yield fmt + " short", {"fmt": fmt, "vertex_type": "short"}
        yield fmt + " quads", {"fmt": fmt, "quads": True}
    yield "ascii crlf", {"newline": "\r\n"}
    yield "ascii polygons", {"polygons": True}


@pytest.mark.parametrize(("label", "options"), list(variants()), ids=[v[0] for v in variants()])
def test_every_ply_layout_reads_as_trimesh_loads_it(tmp_path, label, options):
    mesh = crown()
    options = dict(options)
    vertices, faces = mesh.vertices, mesh.faces.tolist()
    if options.pop("quads", False):
        faces = [[*a[:2], b[1], a[2]] for a, b in zip(faces[::2], faces[1::2], strict=True)]
    if options.pop("polygons", False):  # triangles, quads and a hexagon, mixed
        faces = [faces[0] + [faces[1][2]], *faces[2:], [0, 1, 2, 3, 4, 5], faces[1] + [faces[3][1]]]
    if options.get("vertex_type") == "short":  # integer coordinates: some vertices coincide
        vertices = np.round(vertices * 20)
    if options.pop("extras", False):
        n, m = len(vertices), len(faces)
        options["vertex_extra"] = {
            "red": ("uchar", np.arange(n) % 256),
            "confidence": ("float", np.linspace(0, 1, n)),
        }
        options["face_extra"] = {"quality": ("double", np.arange(m) / 7)}
    path = write_ply(tmp_path / "variant.ply", vertices, faces, **options)
    ours, theirs = load_mesh(path), trimesh.load(path)
    assert np.array_equal(ours.vertices, theirs.vertices)
    assert np.array_equal(ours.faces, theirs.faces)


@pytest.mark.parametrize("ext", ["stl", "off", "obj", "glb"])
def test_other_formats_read_as_trimesh_loads_them(tmp_path, ext):
    """Read with ``process=False`` and merged by us: the same mesh as trimesh's default."""
    path = tmp_path / f"crown.{ext}"
    crown().export(path)
    ours, theirs = load_mesh(path), trimesh.load(path, force="mesh")
    assert np.array_equal(ours.vertices, theirs.vertices)
    assert np.array_equal(ours.faces, theirs.faces)


@pytest.mark.parametrize("fmt", FORMATS[1:])
def test_binary_polygons_of_mixed_sizes(tmp_path, fmt):
    """trimesh cannot read these (it assumes every face like the first); we read them."""
    mesh = crown()
    faces = mesh.faces.tolist()
    faces = [faces[0] + [faces[1][2]], *faces[2:], [0, 1, 2, 3, 4, 5], faces[1] + [faces[3][1]]]
    text = load_mesh(write_ply(tmp_path / "a.ply", mesh.vertices, faces))
    binary = load_mesh(write_ply(tmp_path / "b.ply", mesh.vertices, faces, fmt=fmt))
    assert np.array_equal(text.vertices, binary.vertices)
    assert np.array_equal(text.faces, binary.faces)


@pytest.mark.parametrize("fmt", FORMATS)
def test_other_elements_and_list_properties_are_skipped(tmp_path, fmt):
    mesh = crown()
    plain = write_ply(tmp_path / "plain.ply", mesh.vertices, mesh.faces, fmt=fmt)
    data = plain.read_bytes()
    head, body = data.split(b"end_header\n", 1)
    n, m = len(mesh.vertices), len(mesh.faces)
    if fmt == "ascii":
        extra_rows = b"".join(b"%d %d 0.5\n" % (i, i + 1) for i in range(4))
    else:
        order = "<" if fmt.endswith("little_endian") else ">"
        extra = np.zeros(4, dtype=[("a", order + "i4"), ("b", order + "i4"), ("w", order + "f4")])
        extra["a"], extra["b"], extra["w"] = range(4), range(1, 5), 0.5
        extra_rows = extra.tobytes()
    head += b"element edge 4\nproperty int vertex1\nproperty int vertex2\nproperty float w\n"
    path = tmp_path / "edges.ply"
    path.write_bytes(head + b"end_header\n" + body + extra_rows)
    ours = load_mesh(path)
    assert (len(ours.vertices), len(ours.faces)) == (n, m)
    assert np.array_equal(ours.vertices, load_mesh(plain).vertices)


@pytest.mark.parametrize("fmt", FORMATS)
def test_a_vertex_list_property_of_varying_length_is_skipped(tmp_path, fmt):
    mesh = crown()
    n = len(mesh.vertices)
    plain = load_mesh(write_ply(tmp_path / "plain.ply", mesh.vertices, mesh.faces, fmt=fmt))
    text = ply_bytes(mesh.vertices, mesh.faces, fmt=fmt)
    head, body = text.split(b"end_header\n", 1)
    head = head.replace(b"property double z\n", b"property double z\nproperty list uchar float w\n")
    if fmt == "ascii":
        lines = body.split(b"\n")
        lines[:n] = [
            line + b" %d" % (i % 3) + b" 0.25" * (i % 3) for i, line in enumerate(lines[:n])
        ]
        body = b"\n".join(lines)
    else:
        order = "<" if fmt.endswith("little_endian") else ">"
        rows = np.frombuffer(body[: n * 24], dtype=order + "f8").reshape(n, 3)
        parts = [
            rows[i].astype(order + "f8").tobytes()
            + bytes([i % 3])
            + np.full(i % 3, 0.25, order + "f4").tobytes()
            for i in range(n)
        ]
        body = b"".join(parts) + body[n * 24 :]
    path = tmp_path / "weights.ply"
    path.write_bytes(head + b"end_header\n" + body)
    ours = load_mesh(path)
    assert np.array_equal(ours.vertices, plain.vertices)
    assert np.array_equal(ours.faces, plain.faces)


# --- other strict checks of the PLY reader -------------------------------------------------


@pytest.mark.parametrize(
    ("edit", "words"),
    [
        (lambda d: d.replace(b"format ascii", b"format utf8"), "format"),
        (lambda d: d.replace(b"end_header\n", b""), "end_header"),
        (lambda d: d.replace(b"property double x", b"property real x"), "real"),
        (lambda d: d.replace(b"property double x\n", b""), "no property x"),
        (lambda d: d.replace(b"element vertex 331", b"element vertex many"), "many"),
        (lambda d: d.replace(b"element vertex 331", b"element vertex -3"), "-3"),
        (lambda d: d.replace(b"ply\n", b"plyx\n", 1), "not a PLY file"),
        (lambda d: d.replace(b"\n0.1 0 0.396\n", b"\n0.1 0x 0.396\n"), "0x"),
        (lambda d: d.replace(b"\n3 0 1 2\n", b"\n2 0 1\n"), "at least 3"),
    ],
)
def test_a_damaged_header_or_body_is_an_error(tmp_path, edit, words):
    mesh = crown()
    data = ply_bytes(mesh.vertices.round(3), [[0, 1, 2], *mesh.faces[1:].tolist()])
    changed = edit(data)
    assert changed != data
    path = tmp_path / "damaged.ply"
    path.write_bytes(changed)
    raises(path, words)


def test_a_ply_without_faces_is_an_error(tmp_path):
    mesh = crown()
    path = write_ply(tmp_path / "points.ply", mesh.vertices, [])
    raises(path, "no triangle mesh")


def test_reading_never_modifies_the_callers_mesh():
    mesh = crown()
    before = (mesh.vertices.copy(), mesh.faces.copy())
    as_arrays(mesh)
    ariaDNE(mesh)
    assert np.array_equal(mesh.vertices, before[0]) and np.array_equal(mesh.faces, before[1])


# --- the binary reader at scan size (one frombuffer per element) ---------------------------


@pytest.mark.parametrize("fmt", FORMATS[1:])
@pytest.mark.parametrize(("count_type", "index_type"), [("uchar", "int"), ("int", "uint")])
def test_a_binary_scan_with_extra_properties_reads_as_trimesh_loads_it(
    tmp_path, fmt, count_type, index_type
):
    mesh = tooth(rings=60)  # 10,981 vertices
    n, m = len(mesh.vertices), len(mesh.faces)
    rng = np.random.default_rng(0)
    vertex_extra = {
        "nx": ("float", rng.normal(size=n)),
        "red": ("uchar", rng.integers(0, 256, n)),
        "quality": ("double", rng.random(n)),
    }
    face_extra = {"flags": ("int", rng.integers(-5, 5, m)), "w": ("float", rng.random(m))}
    path = write_ply(
        tmp_path / "scan.ply",
        mesh.vertices,
        mesh.faces,
        fmt=fmt,
        count_type=count_type,
        index_type=index_type,
        vertex_extra=vertex_extra,
        face_extra=face_extra,
    )
    ours, theirs = load_mesh(path), trimesh.load(path)
    assert np.array_equal(ours.vertices, theirs.vertices)
    assert np.array_equal(ours.faces, theirs.faces)
    vertices, faces = read_ply(path)  # as stored: nothing merged
    assert np.array_equal(vertices, mesh.vertices) and np.array_equal(faces, mesh.faces)


@pytest.mark.parametrize("fmt", FORMATS[1:])
@pytest.mark.parametrize("count_type", ["uchar", "int"])
def test_a_binary_face_of_fewer_than_three_indices_is_an_error(tmp_path, fmt, count_type):
    mesh = crown()
    faces = [*mesh.faces.tolist(), [0, 1]]
    path = write_ply(tmp_path / "short.ply", mesh.vertices, faces, fmt=fmt, count_type=count_type)
    message = raises(path, "at least 3")
    assert f"face {len(faces) - 1}" in message
