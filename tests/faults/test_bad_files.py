"""Damaged mesh files through the command line: an error row each, never an ``ok`` (issue 14).

Items 1-4: a PLY cut short, header counts that disagree with the body, NaN or
infinite coordinates (PLY and OBJ), negative face indices.  All the files and
one good mesh go to a single ``dentopo FILES -o table.csv`` run (in a subprocess,
see ``faults.harness``): it must exit 1, give each bad file an error row whose
reason names the problem, and still measure the good file.
"""

from __future__ import annotations

import csv

import numpy as np
import pytest

from dentopo.samples import tooth
from faults.harness import dentopo
from plyfile import obj_text, ply_bytes, write_ply


def _crown():
    return tooth(rings=10)  # 331 vertices, 600 faces


def _cut(fmt, fraction=0.7):
    mesh = _crown()
    data = ply_bytes(mesh.vertices, mesh.faces, fmt=fmt)
    return data[: int(len(data) * fraction)]


def _with(vertex=None, face=None, **options):
    mesh = _crown()
    vertices, faces = mesh.vertices.copy(), mesh.faces.copy()
    if vertex is not None:
        vertices[vertex[0], vertex[1]] = vertex[2]
    if face is not None:
        faces[face[0], face[1]] = face[2]
    return ply_bytes(vertices, faces, **options)


def _nan_obj():
    mesh = _crown()
    vertices = mesh.vertices.copy()
    vertices[17] = np.nan
    return obj_text(vertices, mesh.faces).encode()


#: file name -> (its bytes, words its error row must hold)
CASES = {
    "cut ascii.ply": (lambda: _cut("ascii"), ["truncated", "declares 331 vertices and 600 faces"]),
    "cut binary.ply": (
        lambda: _cut("binary_little_endian"),
        ["truncated", "declares 331 vertices and 600 faces"],
    ),
    "fewer faces.ply": (
        lambda: _with(declared_faces=620),
        ["truncated", "declares 331 vertices and 620 faces", "600 faces"],
    ),
    "more vertices.ply": (
        lambda: _with(declared_vertices=300),
        ["declares 300 vertices", "holds 331 vertices"],
    ),
    "nan ascii.ply": (
        lambda: _with(vertex=(17, 0, np.nan)),
        ["1 vertex has non-finite", "vertex 17"],
    ),
    "inf binary.ply": (
        lambda: _with(vertex=(17, 2, np.inf), fmt="binary_big_endian"),
        ["1 vertex has non-finite", "vertex 17"],
    ),
    "nan.obj": (_nan_obj, ["1 vertex has non-finite", "vertex 18"]),
    "negative ascii.ply": (lambda: _with(face=(25, 1, -1)), ["outside [0, 330]", "face 25"]),
    "negative binary.ply": (
        lambda: _with(face=(25, 1, -1), fmt="binary_little_endian"),
        ["outside [0, 330]", "face 25"],
    ),
}


@pytest.fixture(scope="module")
def rows(tmp_path_factory):
    """One ``dentopo`` run over every case and a good mesh: its exit code and rows by name."""
    folder = tmp_path_factory.mktemp("bad files")
    paths = []
    for name, (make, _) in CASES.items():
        (folder / name).write_bytes(make())
        paths.append(str(folder / name))
    mesh = _crown()
    good = write_ply(folder / "good.ply", mesh.vertices, mesh.faces)
    table = folder / "table.csv"
    ran = dentopo(*paths, str(good), "-o", str(table), "-q")
    with table.open(newline="", encoding="utf-8") as handle:
        by_name = {row["file"].rsplit("/", 1)[-1]: row for row in csv.DictReader(handle)}
    return ran, by_name


def test_the_run_exits_1_and_still_measures_the_good_file(rows):
    ran, by_name = rows
    assert ran.returncode == 1, ran.describe()
    assert set(by_name) == {*CASES, "good.ply"}
    assert by_name["good.ply"]["status"] == "ok"
    assert float(by_name["good.ply"]["dne"]) > 0


@pytest.mark.parametrize("name", list(CASES))
def test_a_damaged_file_gets_an_error_row_naming_the_problem(rows, name):
    ran, by_name = rows
    row = by_name[name]
    assert row["status"] == "error", row
    assert row["dne"] == ""
    for word in CASES[name][1]:
        assert word in row["error"], row["error"]
    assert name in ran.stderr  # reported as it happens, too
