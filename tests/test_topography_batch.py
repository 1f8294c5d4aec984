"""Topography metrics in the batch and on the command line: --metrics, --columns molar,
a failing metric, orientation, resume and per-face files."""

from __future__ import annotations

import csv
import math

import numpy as np
import pytest
import trimesh

from conftest import ROBUSTNESS_SET, hemisphere, shared_mesh
from dentopo import compute_batch, read_table
from dentopo.batch import _measure
from dentopo.cli import main
from dentopo.formats import LAYOUTS, layout, record_keys

MOLAR_HEADER = [
    "File",
    "DNE",
    "Convex_DNE",
    "Concave_DNE",
    "Convex_Area",
    "Concave_Area",
    "RFI",
    "3D_Area",
    "2D_Area",
    "Alpha",
    "OPCR",
    *(f"{format(k * 5.625, '.7g')} deg." for k in range(8)),
    "OPC",
    *(f"Bin {k}" for k in range(1, 9)),
    "Slope",
]


@pytest.fixture
def crowns(tmp_path):
    """Two small open crowns pointing to +z and one pointing to -z, as PLY files.

    Measurable by molaR's RFI with its search for an alpha: fine enough for the
    search to end within its 99 hulls (on a 12 x 24 grid the points are too far
    apart in molaR's units), leaning a little so that the vertices' mean is not
    the pole vertex (molaR's duplicate check would drop the appended mean, and
    its fan test from the last point would stop on a missing value), and turned
    about z so that no two vertices share an x or a y value.
    """
    folder = tmp_path / "crowns"
    folder.mkdir()
    up = hemisphere(rings=24, segments=48)
    up.vertices[:, 2] *= 0.6
    up.vertices[:, 0] += 0.05 * up.vertices[:, 2]
    up.apply_transform(trimesh.transformations.rotation_matrix(0.1234567, [0, 0, 1]))
    bumpy = up.copy()
    bumpy.vertices[:, 2] += 0.05 * np.sin(5 * bumpy.vertices[:, 0]) * bumpy.vertices[:, 2]
    down = up.copy()
    down.vertices[:] = down.vertices @ np.diag([1.0, -1.0, -1.0])
    for name, mesh in (("a_up", up), ("b_bumpy", bumpy), ("c_down", down)):
        mesh.export(folder / f"{name}.ply")
    return folder


def _rows(path):
    with open(path, newline="") as handle:
        return list(csv.reader(handle))


def test_molar_columns_in_molar_order(crowns, tmp_path, capsys):
    out = tmp_path / "t.csv"
    code = main(
        [
            str(crowns),
            "--metrics",
            "all",
            "--columns",
            "molar",
            "--find-alpha",
            "-o",
            str(out),
            "-q",
        ]
    )
    assert code == 0, capsys.readouterr().err
    header, *rows = _rows(out)
    assert header[: len(MOLAR_HEADER)] == MOLAR_HEADER
    assert header[len(MOLAR_HEADER) :] == [
        "ARC",
        "ARC_positive",
        "ARC_negative",
        "ariaDNE",
        "positive_ariaDNE",
        "negative_ariaDNE",
        "orientation",
        "status",
        "error",
        "warnings",
    ]
    assert [row[0] for row in rows] == ["a_up.ply", "b_bumpy.ply", "c_down.ply"]  # base names
    records = read_table(out)  # molaR's layout reads back into records
    assert [r["status"] for r in records] == ["ok"] * 3
    assert records[0]["opc"] == sum(records[0][f"opc_bin{k}"] for k in range(1, 9))
    assert records[2]["orientation"] == "points -z, turned to +z"  # by default


def test_molar_columns_default_to_molar_batch_metrics(crowns, tmp_path):
    out = tmp_path / "t.csv"
    code = main([str(crowns / "a_up.ply"), "--columns", "molar", "--find-alpha", "-o", str(out)])
    assert code == 0
    header = _rows(out)[0]
    assert "OPC" not in header and "Bin 1" not in header  # molaR_Batch leaves OPC off
    assert {"DNE", "RFI", "OPCR", "Slope", "ariaDNE"} <= set(header)


def test_metrics_pick_the_columns(crowns, tmp_path):
    out = tmp_path / "t.csv"
    assert main([str(crowns), "--metrics", "slope,opc", "-o", str(out), "-q"]) == 0
    header = _rows(out)[0]
    assert header == list(record_keys(("opc", "slope")))
    assert "dne" not in header and "rfi" not in header
    assert "orientation" in header and "min_faces" in header


@pytest.mark.filterwarnings("ignore:.*the crown points to -z:UserWarning")
@pytest.mark.filterwarnings("ignore:.*is empty. a mean over no faces:UserWarning")  # convex caps
@pytest.mark.filterwarnings("ignore:.*angularity depends on the mesh's unit")  # no --unit
@pytest.mark.filterwarnings("ignore:.*outline area depends on the mesh's unit")  # no --unit
@pytest.mark.filterwarnings("ignore:.*doolkit assumes millimetres")  # sub-millimetre caps
def test_library_batch_matches_the_metric_functions(crowns):
    from dentopo.topography import classic_dne, opc, opcr, rfi, slope

    records = compute_batch(crowns, metrics="all", find_alpha=True)
    for record in records:
        mesh = record["file"]
        assert record["status"] == "ok", record["error"]
        assert record["slope"] == slope(mesh).slope
        assert record["opc"] == opc(mesh).opc
        found = opcr(mesh)
        assert record["opcr"] == found.opcr
        assert [record[f"opc_{format(r, '.7g')}"] for r in found.rotations] == list(
            found.opc_values
        )
        assert record["rfi"] == rfi(mesh, find_alpha=True).rfi
        assert record["classic_dne"] == classic_dne(mesh).dne


def test_one_failing_metric_keeps_the_rest_of_the_row(crowns, tmp_path, monkeypatch, capsys):
    def broken(*args, **kwargs):
        raise ValueError("alpha adjustment required (a test)")

    monkeypatch.setattr(_measure, "rfi", broken)
    out = tmp_path / "t.csv"
    code = main([str(crowns / "a_up.ply"), "--metrics", "all", "--find-alpha", "-o", str(out)])
    assert code == 1  # a row with a missing metric is not ok
    (record,) = read_table(out)
    assert record["status"] == "partial"
    assert record["error"] == "rfi: alpha adjustment required (a test)"
    assert record["rfi"] is None and record["area_2d"] is None
    assert record["dne"] is not None and record["slope"] is not None and record["opc"] is not None
    assert record["rfi_alpha"] == 0.075  # the settings stay


def test_a_crown_pointing_down_is_warned_about_and_turned_when_asked(crowns, tmp_path, capsys):
    out = tmp_path / "t.csv"
    down = str(crowns / "c_down.ply")
    assert main([down, "--metrics", "slope", "--orient", "as-is", "-o", str(out)]) == 0
    err = capsys.readouterr().err
    # the hint names the command's option, not the library's keyword argument
    assert "points to -z" in err and "--orient auto" in err and "orient='auto'" not in err
    (as_is,) = read_table(out)
    assert as_is["orientation"] == "points -z" and as_is["orient"] == "as-is"
    assert "--orient auto" in as_is["warnings"]  # the command's table, the command's words
    assert as_is["slope"] > 90  # meaningless, as molaR's on the paper's crowns

    assert main([down, "--metrics", "slope", "-o", str(out), "-q"]) == 0  # auto: the default
    (turned,) = read_table(out)
    assert turned["orientation"] == "points -z, turned to +z" and turned["orient"] == "auto"
    up = read_table_for(crowns / "a_up.ply", tmp_path)
    assert turned["slope"] == pytest.approx(up["slope"], rel=1e-12)


def read_table_for(path, tmp_path):
    out = tmp_path / "single.csv"
    assert main([str(path), "--metrics", "slope", "-o", str(out), "-q"]) == 0
    return read_table(out)[0]


def test_resume_reuses_rows_holding_every_metric_asked_for(crowns, tmp_path, capsys):
    out = tmp_path / "t.csv"
    files = [str(crowns / "a_up.ply")]
    assert main([*files, "-o", str(out), "-q"]) == 0  # ariaDNE only
    assert main([*files, "--metrics", "ariadne,slope", "-o", str(out), "--resume"]) == 0
    assert "0 of 1 files already done" in capsys.readouterr().err  # slope was missing
    assert main([*files, "--metrics", "slope", "-o", str(out), "--resume"]) == 0
    assert "1 of 1 files already done" in capsys.readouterr().err  # a row of more metrics
    as_is = ["--metrics", "slope", "--orient", "as-is", "-o", str(out), "--resume"]
    assert main([*files, *as_is]) == 0
    assert "0 of 1 files already done" in capsys.readouterr().err  # another setting


def test_per_face_files_hold_slope_and_patches(crowns, tmp_path):
    from dentopo.topography import opc, slope

    folder = tmp_path / "pv"
    mesh = str(crowns / "b_bumpy.ply")
    code = main([mesh, "--metrics", "slope,opc", "--per-vertex", str(folder), "-q",
                 "--per-vertex-format", "ply,vtp,npz,csv"])  # fmt: skip
    assert code == 0
    assert not (folder / "b_bumpy.dentopo.ply").exists()  # no ariaDNE: no per-vertex file
    expected_slope, expected = slope(mesh).face_slope, opc(mesh)
    with np.load(folder / "b_bumpy.dentopo.faces.npz") as data:
        assert np.array_equal(data["slope"], expected_slope)
        assert np.array_equal(data["opc_bin"], expected.face_bin)
        assert np.array_equal(data["opc_patch"], expected.face_patch)
    pyvista = pytest.importorskip("pyvista")
    vtp = pyvista.read(folder / "b_bumpy.dentopo.faces.vtp")
    assert np.array_equal(vtp.cell_data["opc_patch"], expected.face_patch)
    ply = pyvista.read(folder / "b_bumpy.dentopo.faces.ply")
    assert ply.n_cells == len(expected_slope)
    raw = trimesh.load(folder / "b_bumpy.dentopo.faces.ply", process=False)
    face = raw.metadata["_ply_raw"]["face"]["data"]
    assert np.array_equal(face["slope"], expected_slope)
    rows = _rows(folder / "b_bumpy.dentopo.faces.csv")
    assert rows[0] == ["face", "v1", "v2", "v3", "slope", "opc_bin", "opc_patch"]
    assert [int(r[4]) for r in rows[1:]] == expected_slope.tolist()


@pytest.mark.parametrize(
    "options, message",
    [
        (["--metrics", "curvy"], "unknown metric 'curvy'"),
        (["--metrics", "arc", "--arc-range", "0.5", "0.2"], "arc_range must be two quantiles"),
        (["--metrics", "classic", "--dne-outliers", "101"], "dne_outliers is a percentage"),
        (["--metrics", "opc", "--min-area", "1.5"], "min_area is a fraction"),
        (["--metrics", "rfi", "--alpha", "-1"], "alpha must be a positive"),
        (["--metrics", "opcr", "--opcr-steps", "0"], "opcr_steps must lie in [1, 360]"),
        (["--metrics", "opc", "--min-faces", "-1"], "min_faces must be at least 0"),
        (["--metrics", "slope", "--screenshot", "x.png", "--color-by", "opc"], "add --metrics opc"),
        (["--metrics", "slope", "--screenshot", "x.png"], "ariaDNE, which is not among"),
        (["--columns", "molar", "-o", "t.csv", "--resume"], "resume without --columns molar"),
    ],
)
def test_usage_errors(crowns, tmp_path, monkeypatch, capsys, options, message):
    monkeypatch.chdir(tmp_path)
    assert main([str(crowns / "a_up.ply"), *options]) == 2
    assert message in capsys.readouterr().err


def test_layouts_are_registered():
    assert set(LAYOUTS) == {"dentopo", "signdne", "molar", "doolkit", "morphotester"}
    assert layout("molar", ("classic",)).header == (
        "File",
        *MOLAR_HEADER[1:6],
        "status",
        "error",
        "warnings",
    )


@pytest.mark.parametrize("name", ROBUSTNESS_SET)
def test_a_folder_gives_molar_batch_table(name, molar_topography, tmp_path):
    """``dentopo DIR --metrics all --columns molar --orient as-is``: molaR's numbers, row by row.

    ``--orient as-is`` measures the crowns as molaR did, as they lie (pointing to -z).
    """
    out = tmp_path / "t.csv"
    code = main([str(shared_mesh(name)), "--metrics", "all", "--columns", "molar",
                 "--orient", "as-is", "-o", str(out), "-q"])  # fmt: skip
    ref = molar_topography[name]
    (row,) = [dict(zip(h, r, strict=True)) for h, *rs in [_rows(out)] for r in rs]
    for column in ("ARC", "ARC_positive", "ARC_negative"):  # after molaR's own columns
        assert math.isclose(float(row[column]), float(ref[column]), rel_tol=1e-6)
    close = {"DNE": "DNE", "Convex_DNE": "convex_DNE", "Concave_DNE": "concave_DNE",
             "Convex_Area": "convex_area", "Concave_Area": "concave_area"}  # fmt: skip
    for ours, theirs in close.items():
        assert math.isclose(float(row[ours]), float(ref[theirs]), rel_tol=1e-6)
    assert math.isclose(float(row["Slope"]), float(ref["slope"]), rel_tol=1e-9)
    assert int(row["OPC"]) == int(ref["OPC"])
    assert [int(row[f"Bin {k}"]) for k in range(1, 9)] == [
        int(ref[f"OPC_bin{k}"]) for k in range(1, 9)
    ]
    assert math.isclose(float(row["OPCR"]), float(ref["OPCR"]), rel_tol=1e-12)
    assert [int(row[h]) for h in MOLAR_HEADER[11:19]] == [
        int(ref[f"OPCR_rot{k}"]) for k in range(8)
    ]
    if ref["RFI"] == "NA":  # molaR stopped: "alpha adjustment required"
        assert code == 1 and row["status"] == "partial"
        assert row["RFI"] == "" and row["error"].startswith("rfi: ")
        assert "find_alpha" in row["error"] or "find-alpha" in row["error"]
    else:
        assert code == 0 and row["status"] == "ok"
        for ours, theirs in {"RFI": "RFI", "3D_Area": "area_3d", "2D_Area": "area_2d",
                             "Alpha": "alpha"}.items():  # fmt: skip
            assert math.isclose(float(row[ours]), float(ref[theirs]), rel_tol=1e-9)
