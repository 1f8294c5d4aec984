"""One row, one surface: every metric of a row measures the triangles ariaDNE's cleaning keeps.

A cap of four faces over a 4-edge open base was filled for ariaDNE (faces 6, area 5.46) while
doolkit's metrics in the same row measured the raw 4 faces (area 3.46), and preparation's
orient step called it closed.  An open base is open whatever its size: cleaning fills a hole
of three or four edges only beside a longer boundary loop (a defect beside the base), the
other metrics measure what ariaDNE measures, and the row says what cleaning changed.  A fin
(a face on an interior edge) is named in the row.
"""

from __future__ import annotations

import csv
import io
import json

import numpy as np
import pytest
import trimesh

from dentopo.samples import sample_paths
from faults.harness import dentopo, python

CAP_VERTICES = [[1, 0, 0], [0, 1, 0], [-1, 0, 0], [0, -1, 0], [0, 0, 1.0]]
CAP_FACES = [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]


def _write(path, vertices, faces) -> str:
    trimesh.Trimesh(np.asarray(vertices), np.asarray(faces), process=False).export(path)
    return str(path)


def _row(*argv) -> dict:
    ran = dentopo(*argv, "-q", "-o", "-")
    assert ran.returncode in (0, 1), ran.describe()
    rows = list(csv.DictReader(io.StringIO(ran.stdout)))
    assert len(rows) == 1, ran.describe()
    return rows[0]


@pytest.fixture(scope="module")
def crown():
    mesh = trimesh.load(sample_paths()["tooth"], process=False)
    return np.asarray(mesh.vertices), np.asarray(mesh.faces)


def test_a_cap_with_a_four_edge_base_is_one_surface_in_its_row(tmp_path):
    cap = _write(tmp_path / "cap.ply", CAP_VERTICES, CAP_FACES)
    row = _row(cap, "--metrics", "ariadne,doolkit_slope,classic")
    assert int(row["faces"]) == int(row["n_faces"]) == 4
    assert float(row["surface_area"]) == pytest.approx(float(row["area3d"]), rel=1e-6)
    assert float(row["surface_area"]) == pytest.approx(4 * 3**0.5 / 2)
    assert "an open boundary of 4 edges was left open" in row["warnings"]
    # every face touches the base: classic DNE has nothing to measure, and says so
    assert row["classic_dne"] == "" and row["status"] == "partial"
    assert "classic DNE has no face to measure" in row["error"]


def test_a_small_hole_beside_the_base_is_filled_for_every_metric(tmp_path, crown):
    vertices, faces = crown
    holed = _write(tmp_path / "holed.ply", vertices, np.delete(faces, 2000, axis=0))
    for metrics in ("ariadne,doolkit_slope,classic", "doolkit_slope"):
        row = _row(holed, "--metrics", metrics)
        assert int(row["n_faces"]) == len(faces), (metrics, row)
        assert "cleaning filled 1 hole of three or four edges (1 face added)" in row["warnings"]
    row = _row(holed, "--metrics", "ariadne,doolkit_slope")
    assert int(row["faces"]) == int(row["n_faces"])
    assert float(row["surface_area"]) == pytest.approx(float(row["area3d"]), rel=1e-6)
    alone = _row(holed)  # ariaDNE alone reads the file itself: the same words
    assert "cleaning filled 1 hole" in alone["warnings"]


def test_a_fin_on_an_interior_edge_is_named_in_the_row(tmp_path, crown):
    vertices, faces = crown
    a, b = faces[1000, :2]
    apex = (vertices[a] + vertices[b]) / 2 + [0, 0, 0.5]
    fin = _write(
        tmp_path / "fin.ply", np.vstack([vertices, apex]), np.vstack([faces, [a, b, len(vertices)]])
    )
    for metrics in ("ariadne", "ariadne,classic,doolkit_slope", "slope"):
        row = _row(fin, "--metrics", metrics)
        assert "1 edge shared by three or more faces (non-manifold" in row["warnings"], metrics
    clean = _row(str(sample_paths()["tooth"]), "--metrics", "ariadne,slope")
    assert "non-manifold" not in (clean["warnings"] or "")


def test_preparation_keeps_a_small_open_base_open():
    code = f"""
import json
import numpy as np
from dentopo.prepare import Protocol, prepare
mesh = (np.array({CAP_VERTICES}), np.array({CAP_FACES}))
result = prepare(mesh, Protocol(name="t", orient="occlusal"))
steps = {{s.name: s for s in result.steps}}
print(json.dumps([steps["clean"].faces_after, steps["orient"].details["rule"]]))
"""
    ran = python(code)
    assert ran.returncode == 0, ran.describe()
    faces, rule = json.loads(ran.stdout.strip().splitlines()[-1])
    assert faces == 4
    assert rule == "open base"
