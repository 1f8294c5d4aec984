"""Per-vertex files, each read back with the library it is meant for and with read_per_vertex."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
import trimesh

from dentopo import ariaDNE, color_scale, compute_batch, read_per_vertex, write_per_vertex
from dentopo.cli import main
from dentopo.formats import PER_VERTEX_FORMATS, SOURCES_FILE, PerVertexOptions, per_vertex_formats
from dentopo.samples import tooth

pyvista = pytest.importorskip("pyvista", reason="the VTP and PLY checks read with pyvista (viz)")


@pytest.fixture(scope="module")
def mesh_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("mesh") / "molar.ply"
    tooth(rings=10).export(path)
    return path


@pytest.fixture(scope="module")
def result(mesh_file):
    return ariaDNE(str(mesh_file))


@pytest.fixture(scope="module")
def written(mesh_file, tmp_path_factory):
    """Every format, asked for both ways (repeated and comma-separated)."""
    directory = tmp_path_factory.mktemp("per_vertex")
    args = [str(mesh_file), "--per-vertex", str(directory), "-q"]
    args += ["--per-vertex-format", "ply,vtp", "--per-vertex-format", "NPZ", "--per-vertex-format"]
    assert main([*args, "csv"]) == 0
    return {fmt: directory / f"molar.dentopo.{fmt}" for fmt in PER_VERTEX_FORMATS}


def expected_sign(result):
    return np.where(result.local_dne >= 0, 1, -1)


def default_colors(result):
    return color_scale(result.local_curvature).rgb(result.local_curvature)


def test_every_format_is_written(written):
    assert all(path.exists() for path in written.values())


def test_ply_with_trimesh(written, result):
    ply = trimesh.load(written["ply"], process=False)
    assert np.array_equal(ply.vertices, result.mesh.vertices)
    assert np.array_equal(ply.faces, result.mesh.faces)
    data = ply.metadata["_ply_raw"]["vertex"]["data"]
    assert np.array_equal(data["local_curvature"], result.local_curvature)
    assert np.array_equal(data["local_dne"], result.local_dne)
    assert data["sign"].dtype == np.int8
    assert np.array_equal(data["sign"], expected_sign(result))
    assert data["quality"].dtype == np.float32  # MeshLab's per-vertex quality
    assert np.array_equal(data["quality"], result.local_curvature.astype(np.float32))
    assert np.array_equal(ply.visual.vertex_colors[:, :3], default_colors(result))


def test_ply_colours_with_pyvista(written, result):
    ply = pyvista.read(written["ply"])  # VTK's reader drops the other properties
    assert np.array_equal(ply.points, result.mesh.vertices)
    assert np.array_equal(ply.point_data["RGB"], default_colors(result))


def test_vtp_with_pyvista(written, result):
    vtp = pyvista.read(written["vtp"])
    assert np.array_equal(vtp.points, result.mesh.vertices)
    assert np.array_equal(vtp.regular_faces, result.mesh.faces)
    assert np.array_equal(vtp.point_data["local_curvature"], result.local_curvature)
    assert np.array_equal(vtp.point_data["local_dne"], result.local_dne)
    assert vtp.point_data["sign"].dtype == np.int8
    assert np.array_equal(vtp.point_data["sign"], expected_sign(result))
    assert np.array_equal(vtp.point_data["RGB"], default_colors(result))
    assert vtp.active_scalars_name == "local_curvature"


def test_npz_with_numpy(written, result):
    with np.load(written["npz"], allow_pickle=False) as data:
        assert np.array_equal(data["vertices"], result.mesh.vertices)
        assert np.array_equal(data["faces"], result.mesh.faces)
        assert np.array_equal(data["local_curvature"], result.local_curvature)
        assert np.array_equal(data["local_dne"], result.local_dne)
        assert np.array_equal(data["sign"], expected_sign(result))
        assert np.array_equal(data["colors"], default_colors(result))


def test_csv_with_pandas(written, result):
    # pandas 3 parses floats exactly by default; before, only with float_precision="round_trip"
    exact = {} if int(pd.__version__.split(".")[0]) >= 3 else {"float_precision": "round_trip"}
    table = pd.read_csv(written["csv"], **exact)
    assert list(table.columns) == ["vertex", "x", "y", "z", "local_curvature", "local_dne", "sign"]
    assert np.array_equal(table["vertex"], np.arange(len(result.local_curvature)))
    assert np.array_equal(table[["x", "y", "z"]].to_numpy(), result.mesh.vertices)
    assert np.array_equal(table["local_curvature"], result.local_curvature)  # repr: exact
    assert np.array_equal(table["local_dne"], result.local_dne)
    assert np.array_equal(table["sign"], expected_sign(result))


@pytest.mark.parametrize("fmt", PER_VERTEX_FORMATS)
def test_read_per_vertex_reads_every_format(written, result, fmt):
    mesh = read_per_vertex(written[fmt])
    assert isinstance(mesh, trimesh.Trimesh)
    assert np.array_equal(mesh.vertices, result.mesh.vertices)
    attributes = mesh.vertex_attributes
    assert set(attributes) == {"local_curvature", "local_dne", "sign"}
    assert np.array_equal(attributes["local_curvature"], result.local_curvature)
    assert np.array_equal(attributes["local_dne"], result.local_dne)
    assert attributes["sign"].dtype == np.int8
    assert np.array_equal(attributes["sign"], expected_sign(result))
    if fmt == "csv":  # one row per vertex: no faces, no colours
        assert mesh.faces.shape == (0, 3)
    else:
        assert np.array_equal(mesh.faces, result.mesh.faces)
        assert np.array_equal(mesh.visual.vertex_colors[:, :3], default_colors(result))


def test_the_default_is_ply_and_csv(mesh_file, tmp_path):
    assert main([str(mesh_file), "--per-vertex", str(tmp_path), "-q"]) == 0
    written = sorted(p.name for p in tmp_path.iterdir() if p.name != SOURCES_FILE)
    assert written == ["molar.dentopo.csv", "molar.dentopo.ply"]  # and which mesh they are


def test_colours_follow_limits_and_percentile(mesh_file, result, tmp_path):
    colours = {}
    runs = {"default": [], "wide": ["--limits", "-1", "1"], "p50": ["--percentile", "50"]}
    for name, options in runs.items():
        directory = tmp_path / name
        args = [str(mesh_file), "--per-vertex", str(directory), "--per-vertex-format", "npz"]
        assert main([*args, "-q", *options]) == 0
        with np.load(directory / "molar.dentopo.npz") as data:
            colours[name] = data["colors"]
    k = result.local_curvature
    assert np.array_equal(colours["default"], default_colors(result))
    assert np.array_equal(colours["wide"], color_scale(limits=1.0).rgb(k))
    assert np.array_equal(colours["p50"], color_scale(k, percentile=50).rgb(k))
    assert not np.array_equal(colours["wide"], colours["default"])
    assert not np.array_equal(colours["p50"], colours["default"])


def test_limits_reach_worker_processes(mesh_file, tmp_path):
    other = tmp_path / "premolar.ply"
    tooth(rings=8).export(other)
    records = compute_batch(
        [mesh_file, other],
        jobs=2,
        per_vertex_dir=tmp_path,
        per_vertex_formats=["ply"],
        per_vertex_limits=(-0.05, 0.05),
    )
    assert [r["status"] for r in records] == ["ok", "ok"]
    for path in (mesh_file, other):
        ply = read_per_vertex(tmp_path / f"{path.stem}.dentopo.ply")
        k = ply.vertex_attributes["local_curvature"]
        assert np.array_equal(ply.visual.vertex_colors[:, :3], color_scale(limits=0.05).rgb(k))


@pytest.mark.parametrize(
    ("options", "message"),
    [
        (["--per-vertex-format", "ply"], "needs --per-vertex"),
        (["--per-vertex", "PV", "--per-vertex-format", "stl"], "unknown per-vertex format"),
        (["--per-vertex", "PV", "--limits", "0.1", "0.3"], "zero strictly inside"),
        (["--per-vertex", "PV", "--percentile", "0"], "percentile"),
    ],
)
def test_per_vertex_usage_errors(mesh_file, tmp_path, monkeypatch, capsys, options, message):
    monkeypatch.chdir(tmp_path)
    assert main([str(mesh_file), *options]) == 2
    assert message in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []  # checked before any work


def test_writing_leaves_the_result_alone(result, tmp_path):
    before = (result.local_curvature.copy(), result.local_dne.copy(), result.mesh.vertices.copy())
    paths = write_per_vertex(tmp_path, "m", result, formats=PER_VERTEX_FORMATS, limits=0.1)
    assert list(paths) == list(PER_VERTEX_FORMATS)
    assert np.array_equal(result.local_curvature, before[0])
    assert np.array_equal(result.local_dne, before[1])
    assert np.array_equal(result.mesh.vertices, before[2])


def test_format_names_and_options_are_checked():
    assert per_vertex_formats(["VTP, csv", "vtp"]) == ("vtp", "csv")
    with pytest.raises(ValueError, match="no per-vertex format"):
        per_vertex_formats(" , ")
    assert PerVertexOptions(limits=[-0.2, 0.2]).limits == (-0.2, 0.2)
    with pytest.raises(ValueError, match="positive"):
        PerVertexOptions(limits=0)


def test_read_per_vertex_refuses_what_it_cannot_read(tmp_path):
    with pytest.raises(ValueError, match="per-vertex format"):
        read_per_vertex(tmp_path / "values.xyz")
    bad = tmp_path / "bad.vtp"
    bad.write_text("<VTKFile type='UnstructuredGrid'/>")
    with pytest.raises(ValueError, match="not a VTK PolyData"):
        read_per_vertex(bad)
    table = tmp_path / "t.csv"
    table.write_text("a,b\n1,2\n")
    with pytest.raises(ValueError, match="no x, y, z"):
        read_per_vertex(table)
