"""The files of a prepared crown: the PLY (float64, read back exactly) and the JSON record."""

from __future__ import annotations

import hashlib
import json
import os
import re

import numpy as np
import pytest
import trimesh

import dentopo
from dentopo.formats import (
    RECORD_SUFFIX,
    _prepared,
    prepared_ply_bytes,
    read_record,
    safe_folder,
    write_prepared,
)
from dentopo.mesh import read_ply
from dentopo.samples import tooth


@pytest.fixture(scope="module")
def crown(tmp_path_factory):
    path = tmp_path_factory.mktemp("raw") / "tooth.ply"
    tooth(rings=10).export(path)
    faces = len(trimesh.load(path, process=False).faces)
    return dentopo.prepare(os.fspath(path), orient="none", faces=faces - 40)


def test_ply_reads_back_exactly_with_our_reader_and_trimesh(tmp_path):
    rng = np.random.default_rng(1)
    vertices = rng.normal(size=(50, 3)) * 1e3 + 1e-7  # digits float32 would lose
    faces = rng.integers(0, 50, size=(80, 3))
    path = tmp_path / "m.ply"
    path.write_bytes(prepared_ply_bytes(vertices, faces))
    v, f = read_ply(path)
    assert v.dtype == np.float64 and np.array_equal(v, vertices)
    assert np.array_equal(f, faces)
    mesh = trimesh.load(path, process=False)
    assert np.array_equal(mesh.vertices, vertices) and np.array_equal(mesh.faces, faces)


def test_ply_header_is_plain_and_dated_nowhere():
    data = prepared_ply_bytes(np.eye(3), [[0, 1, 2]], comment="protocol x 0123")
    header = data.split(b"end_header\n")[0].decode("ascii")
    assert header.splitlines()[:2] == ["ply", "format binary_little_endian 1.0"]
    assert "property double x" in header and "property list uchar int vertex_indices" in header
    assert not re.search(r"\d{4}-\d{2}-\d{2}", header)
    assert len(data) == len(header) + len("end_header\n") + 3 * 24 + (1 + 12)


def test_ply_refuses_bad_arrays():
    with pytest.raises(ValueError, match="within its vertices"):
        prepared_ply_bytes(np.eye(3), [[0, 1, 3]])
    with pytest.raises(ValueError, match="triangles"):
        prepared_ply_bytes(np.eye(3), [[0, 1]])


def test_written_mesh_measures_as_the_mesh_in_memory(crown, tmp_path):
    path = tmp_path / "t.ply"
    write_prepared(crown, path)
    v, f = read_ply(path)
    assert np.array_equal(v, crown.vertices) and np.array_equal(f, crown.faces)
    from_file = dentopo.ariaDNE(os.fspath(path))
    in_memory = dentopo.ariaDNE(crown.mesh)
    assert from_file.dne == in_memory.dne
    assert from_file.positive_dne == in_memory.positive_dne


def test_record_names_version_input_protocol_steps_and_mesh(crown, tmp_path):
    path = tmp_path / "t.ply"
    written = write_prepared(crown, path, source="raw/tooth.ply")
    record = read_record(tmp_path / ("t" + RECORD_SUFFIX))
    assert record == written
    assert record["dentopo"] == dentopo.__version__
    assert record["input"] == {"path": "raw/tooth.ply", "sha256": crown.source_sha256}
    with open(crown.source, "rb") as handle:
        assert record["input"]["sha256"] == hashlib.sha256(handle.read()).hexdigest()
    assert record["protocol"]["digest"] == crown.protocol.digest
    assert record["protocol"]["faces"] == crown.protocol.faces
    assert [s["step"] for s in record["steps"]] == ["clean", "decimate"]
    assert record["mesh"] == {
        "file": "t.ply",
        "sha256": hashlib.sha256(path.read_bytes()).hexdigest(),
    }
    text = (tmp_path / ("t" + RECORD_SUFFIX)).read_text()
    assert not re.search(r"\d{4}-\d{2}-\d{2}|\d{2}:\d{2}:\d{2}", text)


def test_same_crown_same_bytes(crown, tmp_path):
    write_prepared(crown, tmp_path / "a.ply", source="x.ply")
    write_prepared(crown, tmp_path / "b.ply", source="x.ply")
    assert (tmp_path / "a.ply").read_bytes() == (tmp_path / "b.ply").read_bytes()
    a = json.loads((tmp_path / "a.prepare.json").read_text())
    b = json.loads((tmp_path / "b.prepare.json").read_text())
    a["mesh"].pop("file"), b["mesh"].pop("file")
    assert a == b


def test_a_failed_record_leaves_no_partial_file(crown, tmp_path, monkeypatch):
    def broken(record):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(_prepared, "record_text", broken)
    with pytest.raises(OSError):
        write_prepared(crown, tmp_path / "t.ply")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["t.ply"]  # no record, no temporary


def test_read_record_refuses_other_json(tmp_path):
    path = tmp_path / "x.prepare.json"
    path.write_text('{"a": 1}')
    with pytest.raises(ValueError, match="not a prepared crown"):
        read_record(path)
    path.write_text("{")
    with pytest.raises(ValueError, match="not a prepared crown"):
        read_record(path)


def test_safe_folder_stays_inside(tmp_path):
    root = tmp_path / "out"
    assert safe_folder(root, "a/b") == os.path.join(root, "a", "b")
    assert (root / "a" / "b").is_dir()
    with pytest.raises(ValueError, match="lead out"):
        safe_folder(root, "../escape")
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    os.symlink(elsewhere, root / "link")
    with pytest.raises(ValueError, match="symbolic link"):
        safe_folder(root, "link/c")
    assert not (elsewhere / "c").exists()


def test_safe_folder_takes_a_folder_another_worker_made_meanwhile(tmp_path, monkeypatch):
    # two workers of `prepare -j N` writing into one new subfolder: the second one's mkdir
    # finds it made between its look and its mkdir (a race that failed a file)
    from dentopo.formats import _prepared

    real_mkdir = os.mkdir

    def raced(path, *args, **kwargs):
        real_mkdir(path, *args, **kwargs)  # the other worker, first
        raise FileExistsError(17, "File exists", path)

    monkeypatch.setattr(_prepared.os, "mkdir", raced)
    root = str(tmp_path / "out")
    assert safe_folder(root, "sub/deep") == os.path.join(root, "sub", "deep")
    assert os.path.isdir(os.path.join(root, "sub", "deep"))
    (tmp_path / "out" / "file").write_text("x")
    with pytest.raises(ValueError, match="not a folder"):
        safe_folder(root, "file/deeper")
