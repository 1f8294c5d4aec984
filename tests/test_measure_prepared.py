"""Measuring with a protocol: ``compute_batch(prepare=...)``, ``dentopo --prepare``, the report.

Each mesh is prepared in memory (:func:`dentopo.prepare`) and the prepared
crown measured: the row equals measuring ``prepare(...).mesh`` directly, and a
float64 binary PLY of the prepared mesh (what ``dentopo prepare`` writes) gives
the same numbers.  The protocols here keep the pose (``orient="none"``) so that
the tests do not depend on the orient step.
"""

from __future__ import annotations

import csv
import html
import math
import pickle
import shutil
import warnings

import numpy as np
import pytest
import trimesh

from dentopo import Protocol, ProtocolError, ariaDNE, compute_batch, prepare, read_table, slope
from dentopo.batch import make_settings, prepared_mesh, protocol_digest, resumable_files
from dentopo.batch._measure import measure_mesh
from dentopo.cli import main
from dentopo.formats import COLUMNS, METRIC_KEYS, PROTOCOL_KEY, write_table
from dentopo.samples import sample_paths


def tooth() -> str:
    """The bundled sample tooth's file (5,400 faces)."""
    return str(sample_paths()["tooth"])


PROTOCOL = Protocol(name="test-2k", orient="none", faces=2000)
METRICS = ("ariadne", "slope", "opcr", "classic", "arc")


@pytest.fixture
def crowns(tmp_path):
    """Two copies of the sample tooth (5,400 faces) in a folder."""
    folder = tmp_path / "crowns"
    folder.mkdir()
    for name in ("a.ply", "b.ply"):
        shutil.copyfile(tooth(), folder / name)
    return folder


def _metric_keys(record: dict) -> list[str]:
    return [
        key
        for metric in METRICS
        for key in (*METRIC_KEYS[metric], *(k for k in record if k.startswith("opc_")))
        if key in record
    ]


def test_the_protocol_column_sits_before_the_run_columns():
    assert PROTOCOL_KEY in COLUMNS
    assert COLUMNS[COLUMNS.index(PROTOCOL_KEY) :] == (
        PROTOCOL_KEY,
        "seconds",
        "status",
        "error",
        "warnings",
    )
    assert COLUMNS.index("method") < COLUMNS.index(PROTOCOL_KEY)  # after the settings


def test_rows_carry_the_label_and_the_numbers_of_the_prepared_mesh(crowns):
    before = (crowns / "a.ply").read_bytes()
    rows = compute_batch(str(crowns), metrics=METRICS, prepare=PROTOCOL)
    assert [r["status"] for r in rows] == ["ok", "ok"]
    assert all(r[PROTOCOL_KEY] == PROTOCOL.label for r in rows)
    assert PROTOCOL.label.startswith("test-2k ") and len(PROTOCOL.label.split()[1]) == 12
    crown = prepare(str(crowns / "a.ply"), PROTOCOL)
    assert (crowns / "a.ply").read_bytes() == before  # the input file is never touched
    assert 1980 <= len(crown.faces) <= 2020 and rows[0]["faces"] == len(crown.faces)
    assert rows[0]["dne"] == ariaDNE(crown.mesh).dne
    assert rows[0]["slope"] == slope(crown.mesh).slope
    direct = measure_mesh(crown.mesh, METRICS).record
    keys = _metric_keys(rows[0])
    assert len(keys) > 15
    for key in keys:
        assert rows[0][key] == direct[key], key
    raw = compute_batch(str(crowns / "a.ply"), metrics=METRICS)[0]
    assert raw[PROTOCOL_KEY] is None
    assert raw["faces"] == 5400 and raw["dne"] != rows[0]["dne"]


def test_settings_check_the_protocol_once_and_pickle():
    settings = make_settings(prepare=PROTOCOL, metrics=METRICS)
    assert settings.prepare == PROTOCOL and settings.protocol == PROTOCOL.label
    assert pickle.loads(pickle.dumps(settings)) == settings  # for -j and Dask
    assert make_settings(prepare="crown-10k").prepare.name == "crown-10k"
    with pytest.raises(ProtocolError, match="crown-10k"):  # the shipped names are listed
        make_settings(prepare="no-such-protocol")
    with pytest.raises(ProtocolError, match="faces"):
        make_settings(prepare={"decimate": {"faces": 2}})


def test_workers_give_the_same_rows(crowns):
    one = compute_batch(str(crowns), metrics=("ariadne", "slope"), prepare=PROTOCOL)
    two = compute_batch(str(crowns), metrics=("ariadne", "slope"), prepare=PROTOCOL, jobs=2)
    strip = ("seconds",)
    assert [{k: v for k, v in r.items() if k not in strip} for r in one] == [
        {k: v for k, v in r.items() if k not in strip} for r in two
    ]


def test_the_callers_mesh_is_never_modified():
    mesh = trimesh.load(tooth(), process=False)
    vertices, faces = mesh.vertices.copy(), mesh.faces.copy()
    prepared = prepared_mesh(mesh, PROTOCOL)
    assert len(prepared.faces) < len(faces)
    np.testing.assert_array_equal(mesh.vertices, vertices)
    np.testing.assert_array_equal(mesh.faces, faces)


def test_a_failing_step_is_one_error_row_and_the_batch_goes_on(crowns):
    (crowns / "big.ply").write_bytes((crowns / "a.ply").read_bytes())
    # a plane far above every crown keeps nothing: the crop step fails (or, until the crop
    # step is written, says it is not): either way that file's row, named
    failing = Protocol(name="too-high", orient="none", crop_plane=(0, 0, 1e6, 0, 0, 1))
    rows = compute_batch(str(crowns), prepare=failing)
    assert [r["status"] for r in rows] == ["error"] * 3
    assert all("crop" in r["error"] for r in rows)
    assert all(r[PROTOCOL_KEY] == failing.label for r in rows)
    mixed = compute_batch([str(crowns / "a.ply"), str(crowns / "missing.ply")], prepare=PROTOCOL)
    assert [r["status"] for r in mixed] == ["ok", "error"]


def test_per_vertex_files_are_of_the_prepared_mesh(crowns, tmp_path):
    import json

    folder = tmp_path / "per_vertex"
    folder.mkdir()
    row = compute_batch(
        str(crowns / "a.ply"), prepare=PROTOCOL, per_vertex_dir=folder, per_vertex_formats="npz"
    )[0]
    (written,) = folder.glob("*.npz")
    with np.load(written) as arrays:
        vertices = arrays["vertices"] if "vertices" in arrays else arrays["points"]
    assert len(vertices) == row["vertices"]
    np.testing.assert_array_equal(
        vertices, ariaDNE(prepare(str(crowns / "a.ply"), PROTOCOL).mesh).mesh.vertices
    )
    (line,) = (folder / ".dentopo-sources.jsonl").read_text(encoding="utf-8").splitlines()
    assert json.loads(line)["protocol"] == PROTOCOL.label


def test_prepare_warnings_go_into_the_row(tmp_path):
    mesh = trimesh.load(tooth(), process=False)
    speck = trimesh.creation.icosphere(subdivisions=1, radius=0.01)
    speck.apply_translation(mesh.bounds[1] + 1.0)
    joined = trimesh.util.concatenate([mesh, speck])
    path = tmp_path / "specked.ply"
    joined.export(path)
    # the clean step keeps the largest piece; a warning of any step lands prefixed
    crown = prepare(str(path), PROTOCOL)
    row = compute_batch(str(path), prepare=PROTOCOL)[0]
    assert row["status"] == "ok" and row["faces"] == len(crown.faces)
    for text in crown.warnings:
        assert f"prepare: {text}" in (row["warnings"] or "")


def test_resume_reuses_a_row_only_for_the_same_digest(tmp_path):
    settings = make_settings(prepare=PROTOCOL)
    plain = make_settings()
    base = {"file": str(tmp_path / "a.ply"), "status": "ok", **settings.options()}
    base.update(dict.fromkeys(METRIC_KEYS["ariadne"], 1.0), **settings.options())
    same = {**base, PROTOCOL_KEY: PROTOCOL.label}
    renamed = {**base, PROTOCOL_KEY: f"another-name {PROTOCOL.digest[:12]}"}
    other = {**base, PROTOCOL_KEY: PROTOCOL.replace(faces=3000).label}
    none = {**base, PROTOCOL_KEY: None}
    assert resumable_files([same], settings) == {str(tmp_path / "a.ply")}
    assert resumable_files([renamed], settings) == {str(tmp_path / "a.ply")}  # the digest
    assert resumable_files([other], settings) == set()
    assert resumable_files([none], settings) == set()
    assert resumable_files([same], plain) == set()
    assert resumable_files([none], plain) == {str(tmp_path / "a.ply")}
    assert protocol_digest(None) is None and protocol_digest("") is None
    assert protocol_digest(PROTOCOL.label) == PROTOCOL.digest[:12]


def _write_protocol(path, protocol: Protocol):
    path.write_text(protocol.to_toml(), encoding="utf-8")
    return str(path)


def test_the_command_measures_prepared_and_resumes_by_protocol(crowns, tmp_path, capsys):
    toml = _write_protocol(tmp_path / "p.toml", PROTOCOL)
    out = tmp_path / "out.csv"
    assert main([str(crowns), "--prepare", toml, "-o", str(out), "-q"]) == 0
    rows = read_table(out)
    assert [r[PROTOCOL_KEY] for r in rows] == [PROTOCOL.label] * 2
    with open(out, newline="", encoding="utf-8") as stream:
        assert PROTOCOL_KEY in next(csv.reader(stream))
    assert rows[0]["dne"] == ariaDNE(prepare(str(crowns / "a.ply"), PROTOCOL).mesh).dne
    capsys.readouterr()
    assert main([str(crowns), "--prepare", toml, "-o", str(out), "--resume"]) == 0
    assert "2 of 2 files already done" in capsys.readouterr().err
    assert main([str(crowns), "-o", str(out), "--resume"]) == 0  # no protocol now: redone
    assert "0 of 2 files already done" in capsys.readouterr().err
    assert [r[PROTOCOL_KEY] for r in read_table(out)] == [None, None]
    assert main([str(crowns), "--prepare", toml, "-o", str(out), "--resume"]) == 0
    assert "0 of 2 files already done" in capsys.readouterr().err  # and back


@pytest.mark.parametrize(
    ("given", "says"),
    [
        ("no-such-protocol", "crown-10k"),  # an unknown name lists the shipped ones
        ("bad.toml", "faces"),  # a wrong parameter, named
    ],
)
def test_a_bad_protocol_exits_2_before_computing(crowns, tmp_path, capsys, given, says):
    (tmp_path / "bad.toml").write_text("[decimate]\nfaces = 2\n", encoding="utf-8")
    out = tmp_path / "out.csv"
    argument = str(tmp_path / given) if given.endswith(".toml") else given
    assert main([str(crowns), "--prepare", argument, "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and says in err[0]
    assert not out.exists()


def _float64_ply(vertices: np.ndarray, faces: np.ndarray) -> bytes:
    """A binary little-endian PLY with double coordinates (as ``dentopo prepare`` writes)."""
    header = (
        "ply\nformat binary_little_endian 1.0\n"
        f"element vertex {len(vertices)}\n"
        "property double x\nproperty double y\nproperty double z\n"
        f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n"
    ).encode("ascii")
    rows = np.zeros(len(faces), dtype=[("n", "u1"), ("v", "<i4", (3,))])
    rows["n"], rows["v"] = 3, faces
    return header + np.asarray(vertices, dtype="<f8").tobytes() + rows.tobytes()


def test_a_float64_ply_of_the_prepared_mesh_gives_the_same_numbers(tmp_path):
    crown = prepare(tooth(), PROTOCOL)
    path = tmp_path / "prepared.ply"
    path.write_bytes(_float64_ply(crown.vertices, crown.faces))
    back = trimesh.load(path, process=False)
    np.testing.assert_array_equal(back.vertices, crown.vertices)  # every bit
    np.testing.assert_array_equal(back.faces, crown.faces)
    in_memory = compute_batch(tooth(), metrics=METRICS, prepare=PROTOCOL)[0]
    from_file = compute_batch(str(path), metrics=METRICS)[0]
    keys = _metric_keys(in_memory)
    assert len(keys) > 15
    for key in keys:
        assert in_memory[key] == from_file[key], key
    assert from_file[PROTOCOL_KEY] is None

    # trimesh's own PLY export (5.x) writes float32 coordinates even with
    # encoding="binary": the rounded crown measures differently, so a prepared
    # mesh must not be saved that way
    exported = trimesh.exchange.ply.export_ply(crown.mesh, encoding="binary")
    assert b"property float x" in exported.split(b"end_header", 1)[0]
    (tmp_path / "single.ply").write_bytes(exported)
    single = compute_batch(str(tmp_path / "single.ply"))[0]
    assert single["dne"] != in_memory["dne"]


# --- the report ------------------------------------------------------------------------------


def _report_extras():
    pytest.importorskip("plotly", reason="the report needs the report extra (plotly)")
    pytest.importorskip("pyvista", reason="the report's thumbnails need the viz extra (pyvista)")


def _payload_faces(page: str) -> list[int]:
    """The face count of each specimen's 3D view (the page's data block)."""
    import json
    import re

    block = re.search(r'<script type="application/json" id="report-data">(.*?)</script>', page)
    assert block is not None
    meshes = json.loads(block.group(1))["meshes"]
    return [meshes[key]["m"] for key in sorted(meshes, key=int)]


def test_the_report_shows_the_protocol_and_prepared_pictures(tmp_path):
    _report_extras()
    from dentopo import write_report

    folder = tmp_path / "c"
    folder.mkdir()
    shutil.copyfile(tooth(), folder / "a.ply")
    named = PROTOCOL.replace(name="<b>lab & co</b>")
    toml = _write_protocol(tmp_path / "p.toml", named)
    rows = compute_batch(str(folder), prepare=named)
    table = tmp_path / "t.csv"
    write_table(table, rows)
    with pytest.raises(ProtocolError, match="not a shipped one"):  # the table holds only a label
        write_report(table, tmp_path / "r.html", jobs=1)
    with pytest.raises(ProtocolError, match="not the one"):
        write_report(table, tmp_path / "r.html", jobs=1, prepare=PROTOCOL.replace(faces=3000))
    summary = write_report(table, tmp_path / "r.html", jobs=1, prepare=toml)
    assert summary.pictured == 1
    page = (tmp_path / "r.html").read_text(encoding="utf-8")
    assert "<b>lab & co</b>" not in page
    assert html.escape("<b>lab & co</b>") in page
    assert named.digest in page
    assert "decimate" in page and "faces=2000" in page
    assert _payload_faces(page) == [rows[0]["faces"]]  # the prepared crown, not 5,400 faces

    plain = tmp_path / "plain.csv"
    write_table(plain, compute_batch(str(folder)))
    write_report(plain, tmp_path / "p.html", jobs=1)
    other = (tmp_path / "p.html").read_text(encoding="utf-8")
    assert named.digest not in other and _payload_faces(other) == [5400]


def test_the_commands_report_pictures_the_prepared_crowns(tmp_path, capsys):
    _report_extras()
    folder = tmp_path / "c"
    folder.mkdir()
    shutil.copyfile(tooth(), folder / "a.ply")
    toml = _write_protocol(tmp_path / "p.toml", PROTOCOL)
    out, page = tmp_path / "t.csv", tmp_path / "r.html"
    assert main([str(folder), "--prepare", toml, "-o", str(out), "--report", str(page), "-q"]) == 0
    text = page.read_text(encoding="utf-8")
    assert PROTOCOL.digest in text
    assert _payload_faces(text) == [read_table(out)[0]["faces"]]
    assert main(["report", str(out), "-o", str(tmp_path / "again.html"), "-q"]) == 2
    assert "not a shipped one" in capsys.readouterr().err
    assert main(["report", str(out), "-o", str(tmp_path / "again.html"), "--prepare", toml]) == 0


def test_no_warning_escapes_a_prepared_batch(crowns):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # compute_batch re-issues per file; none here
        rows = compute_batch(str(crowns / "a.ply"), prepare=PROTOCOL)
    assert rows[0]["warnings"] is None
    assert not math.isnan(rows[0]["dne"])
