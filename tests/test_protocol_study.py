"""The protocol study: every metric against face count, smoothing and noise, and its command."""

from __future__ import annotations

import csv
import math

import numpy as np
import pytest

from dentopo import Protocol, ProtocolError, prepare, protocol_study, write_protocol_study
from dentopo.batch import _measure
from dentopo.cli import main
from dentopo.cli._study import robustness_main
from dentopo.samples import tooth
from dentopo.study import (
    PROTOCOL_STUDY_COLUMNS,
    QUANTITIES,
    SUMMARY_COLUMNS,
    protocol_study_files,
    refine,
)
from dentopo.topography import METRICS

PNG = b"\x89PNG\r\n\x1a\n"
FEW = ("ariadne", "classic", "rfi", "opcr", "slope", "arc", "doolkit_dne")


@pytest.fixture(scope="module")
def crown():
    return tooth(rings=10)  # 331 vertices, 600 faces


@pytest.fixture(scope="module")
def study(crown):
    return protocol_study(
        crown, faces=(300, 600, 1200), smoothing=(0, 5), noise=(0, 1e-3), metrics=FEW
    )


def _rows(study, axis, level):
    return [row for row in study.rows if row["axis"] == axis and row["level"] == level]


def test_the_axes_make_the_right_meshes(crown, study):
    base = study.meshes["crown", "base", ""]
    assert np.array_equal(base.faces, crown.faces) and np.allclose(base.vertices, crown.vertices)
    # decimated through the protocol's decimate step, within 1 %
    low = study.meshes["crown", "faces", 300]
    assert abs(len(low.faces) - 300) <= 3
    expected = prepare(crown, Protocol(orient="none", clean=False, faces=300))
    assert np.array_equal(low.faces, expected.faces)
    assert np.array_equal(low.vertices, expected.vertices)
    # refined above the crown's count: the same surface, the count reached
    high = study.meshes["crown", "faces", 1200]
    assert len(high.faces) in (1200, 1201)
    v, f = refine(np.asarray(crown.vertices), np.asarray(crown.faces), 1200)
    assert np.array_equal(high.vertices, v) and np.array_equal(high.faces, f)
    assert high.area == pytest.approx(crown.area, rel=1e-12)
    # the crown's own count, no smoothing, no noise: the base itself
    for axis, level in (("faces", 600), ("smoothing", 0), ("noise", 0.0)):
        same = study.meshes["crown", axis, level]
        assert np.array_equal(same.vertices, base.vertices), (axis, level)
        assert np.array_equal(same.faces, base.faces), (axis, level)
    # smoothing through the protocol's smooth step; noise moves every vertex, not the faces
    smooth = study.meshes["crown", "smoothing", 5]
    expected = prepare(
        crown, Protocol(orient="none", clean=False, smooth="taubin", smooth_iterations=5)
    )
    assert np.array_equal(smooth.vertices, expected.vertices)
    assert not np.array_equal(smooth.vertices, base.vertices)
    noisy = study.meshes["crown", "noise", 1e-3]
    assert np.array_equal(noisy.faces, base.faces)
    step = (noisy.vertices - base.vertices) / math.sqrt(base.area)
    assert np.std(step) == pytest.approx(1e-3, rel=0.1)


def test_relative_change_is_zero_at_the_base_and_measured_elsewhere(study):
    for axis, level in (("base", ""), ("faces", 600), ("smoothing", 0), ("noise", 0.0)):
        for row in _rows(study, axis, level):
            if row["value"] is not None:
                assert row["value"] == row["base_value"]
                assert row["relative_change"] == 0.0, row
    moved = [r for r in _rows(study, "smoothing", 5) if r["quantity"] == "dne"]
    [row] = moved
    assert row["relative_change"] == pytest.approx(row["value"] / row["base_value"] - 1)
    assert row["relative_change"] != 0.0
    # the same numbers as the batch measures on that mesh
    mesh = study.meshes["crown", "smoothing", 5]
    record = _measure.measure_mesh(mesh, FEW).record
    for row in _rows(study, "smoothing", 5):
        if row["value"] is not None:
            assert row["value"] == record[row["quantity"]], row["quantity"]


def test_every_metric_is_present_or_missing_with_its_reason(crown):
    small = tooth(rings=6)
    study = protocol_study(small, faces=(100,), smoothing=(3,), noise=(1e-3,), metrics="all")
    assert study.metrics == METRICS
    levels = [("base", ""), ("faces", 100), ("smoothing", 3), ("noise", 1e-3)]
    for axis, level in levels:
        rows = _rows(study, axis, level)
        assert [r["quantity"] for r in rows] == [q for m in METRICS for q in QUANTITIES[m]]
        for row in rows:
            assert set(row) == set(PROTOCOL_STUDY_COLUMNS)
            if row["error"] is None:
                assert isinstance(row["value"], float) and isinstance(row["base_value"], float)
            else:
                assert row["value"] is None or row["base_value"] is None
                assert row["relative_change"] is None
                assert isinstance(row["error"], str) and len(row["error"]) > 10


def test_a_metric_that_fails_on_one_mesh_is_missing_there_only(crown, monkeypatch):
    original = _measure._TOPOGRAPHY["slope"]

    def fragile(surface, options):
        if len(surface.faces) > 1000:
            raise ValueError("too many faces for this test")
        return original(surface, options)

    monkeypatch.setitem(_measure._TOPOGRAPHY, "slope", fragile)
    study = protocol_study(crown, faces=(1200,), smoothing=(5,), noise=(), metrics=["slope"])
    [failed] = _rows(study, "faces", 1200)
    assert failed["value"] is None and failed["relative_change"] is None
    assert "too many faces for this test" in failed["error"]
    assert failed["base_value"] is not None
    [kept] = _rows(study, "smoothing", 5)
    assert kept["error"] is None and kept["value"] is not None


def test_a_value_that_is_not_a_number_is_missing_with_its_reason(crown, monkeypatch):
    class NotANumber:
        def to_dict(self):
            return {"slope_mean": float("nan")}

    original = _measure._TOPOGRAPHY["doolkit_slope"]

    def sometimes(surface, options):
        return NotANumber() if len(surface.faces) > 1000 else original(surface, options)

    monkeypatch.setitem(_measure._TOPOGRAPHY, "doolkit_slope", sometimes)
    study = protocol_study(
        crown, faces=(1200,), smoothing=(), noise=(0,), metrics=["doolkit_slope"]
    )
    [row] = _rows(study, "faces", 1200)
    assert row["value"] is None and row["relative_change"] is None
    assert row["error"] == "slope_mean is nan on this mesh"
    [kept] = _rows(study, "noise", 0.0)
    assert kept["error"] is None and kept["relative_change"] == 0.0


def test_a_perturbation_that_cannot_be_made_names_its_level(crown, monkeypatch):
    from dentopo.study import _protocol_study

    def broken(*args, **kwargs):
        raise RuntimeError("no refinement today")

    monkeypatch.setattr(_protocol_study, "refine", broken)
    study = protocol_study(crown, faces=(300, 1200), smoothing=(), noise=(), metrics=["ariadne"])
    for row in _rows(study, "faces", 1200):
        assert row["value"] is None and row["faces"] is None
        assert row["error"] == "faces=1200: no refinement today"
    assert all(row["error"] is None for row in _rows(study, "faces", 300))


def test_the_callers_meshes_are_never_modified(crown):
    vertices, faces = crown.vertices.copy(), crown.faces.copy()
    arrays = (vertices.copy(), faces.copy())
    given = (arrays[0].copy(), arrays[1].copy())
    protocol_study(
        {"a": crown, "b": arrays},
        faces=(300, 1200),
        smoothing=(3,),
        noise=(1e-3,),
        metrics=["ariadne"],
    )
    assert np.array_equal(crown.vertices, vertices) and np.array_equal(crown.faces, faces)
    assert np.array_equal(arrays[0], given[0]) and np.array_equal(arrays[1], given[1])


def test_several_crowns_and_the_summary(crown):
    other = tooth(rings=8)
    study = protocol_study(
        {"ten": crown, "eight": other},
        faces=(300,),
        smoothing=(0, 5),
        noise=(),
        metrics=["ariadne", "rfi"],
    )
    assert study.crowns == ("ten", "eight")
    summary = study.summary()
    assert all(set(row) == set(SUMMARY_COLUMNS) for row in summary)
    for row in summary:
        changes = [
            r["relative_change"]
            for r in study.rows
            if (r["axis"], r["level"], r["quantity"])
            == (row["axis"], row["level"], row["quantity"])
        ]
        finite = [c for c in changes if c is not None]
        assert row["crowns"] == len(finite) and row["missing"] == len(changes) - len(finite)
        if finite:
            assert row["median_relative_change"] == pytest.approx(np.median(finite))
            assert row["min_relative_change"] == min(finite)
            assert row["max_relative_change"] == max(finite)
        else:
            assert row["median_relative_change"] is None
    [zero] = [
        r for r in summary if (r["axis"], r["level"], r["quantity"]) == ("smoothing", 0, "dne")
    ]
    assert zero["median_relative_change"] == 0.0 and zero["crowns"] == 2


def test_a_base_protocol_of_n_faces(crown):
    study = protocol_study(crown, faces=(300, 400), smoothing=(0,), noise=(), base_faces=400,
                           metrics=["ariadne"])  # fmt: skip
    base = study.meshes["crown", "base", ""]
    assert abs(len(base.faces) - 400) <= 4
    assert study.base == "400 faces"
    for row in _rows(study, "faces", 400) + _rows(study, "smoothing", 0):
        assert row["relative_change"] == 0.0
    [row] = [r for r in _rows(study, "faces", 300) if r["quantity"] == "dne"]
    assert row["base_value"] == study.row("crown", "base", "", "dne")["value"]


@pytest.mark.parametrize(
    ("keywords", "error", "match"),
    [
        ({"faces": (2,)}, ValueError, "at least 4"),
        ({"faces": (300.5,)}, TypeError, "integers"),
        ({"smoothing": (-1,)}, ValueError, "0 or more"),
        ({"noise": (-1e-3,)}, ValueError, "0 or more"),
        ({"noise": (float("nan"),)}, ValueError, "finite"),
        ({"faces": (), "smoothing": (), "noise": ()}, ValueError, "no axis"),
        ({"method": "gaussian"}, ValueError, "method must be one of"),
        ({"method": "laplacian", "mu": 0.5}, ProtocolError, "smooth_mu"),
        ({"metrics": ["bogus"]}, ValueError, "bogus"),
        ({"base_faces": 1}, ValueError, "base_faces"),
        ({"bandwidth": -1.0}, ValueError, "bandwidth"),
        ({"seed": 1.5}, TypeError, "seed"),
        ({"faces": 300}, TypeError, "sequence"),
    ],
)
def test_bad_arguments_are_named(crown, keywords, error, match):
    with pytest.raises(error, match=match):
        protocol_study(crown, **{"metrics": ["ariadne"], **keywords})


def test_write_protocol_study(study, tmp_path):
    pytest.importorskip("matplotlib")
    folder = tmp_path / "out"
    written = write_protocol_study(study, folder)
    assert [p.name for p in written] == list(protocol_study_files(FEW))
    assert [p.name for p in written][2:] == [f"sensitivity_{m}.png" for m in FEW]
    with open(folder / "sensitivity.csv", newline="") as handle:
        rows = list(csv.DictReader(handle))
    assert tuple(rows[0]) == PROTOCOL_STUDY_COLUMNS
    assert len(rows) == len(study.rows)
    missing = [r for r in rows if r["error"]]
    assert all(r["value"] == "" and r["relative_change"] == "" for r in missing)
    with open(folder / "sensitivity_summary.csv", newline="") as handle:
        assert tuple(next(csv.DictReader(handle))) == SUMMARY_COLUMNS
    for path in written[2:]:
        assert path.read_bytes().startswith(PNG)
    assert not [p for p in folder.iterdir() if p.name not in protocol_study_files(FEW)]
    only = write_protocol_study(study, tmp_path / "tables", figures=False)
    assert [p.name for p in only] == ["sensitivity.csv", "sensitivity_summary.csv"]


def test_outputs_are_written_atomically(study, tmp_path, monkeypatch):
    """A write that fails leaves the file as it was, and no temporary file behind."""
    from dentopo.formats import _atomic

    folder = tmp_path / "out"
    folder.mkdir()
    (folder / "sensitivity_summary.csv").write_text("earlier\n")
    real, calls = _atomic.os.fsync, []

    def fsync(fd):
        calls.append(fd)
        if len(calls) == 2:  # the second file: written into its temporary file, not synced
            raise OSError("disk full")
        return real(fd)

    monkeypatch.setattr(_atomic.os, "fsync", fsync)
    with pytest.raises(OSError, match="disk full"):
        write_protocol_study(study, folder, figures=False)
    assert (folder / "sensitivity_summary.csv").read_text() == "earlier\n"
    assert (folder / "sensitivity.csv").read_text().startswith("crown,axis,level")
    assert sorted(p.name for p in folder.iterdir()) == [
        "sensitivity.csv",
        "sensitivity_summary.csv",
    ]


# --- the command


@pytest.fixture()
def crowns(tmp_path, crown):
    folder = tmp_path / "crowns"
    (folder / "b").mkdir(parents=True)
    crown.export(folder / "ten.ply")
    tooth(rings=8).export(folder / "b" / "eight.ply")
    return folder


def test_the_command_on_a_folder_of_crowns(crowns, tmp_path, capsys):
    out = tmp_path / "study"
    code = main(
        ["robustness", str(crowns), "-o", str(out), "--faces", "300,1200",
         "--smooth-iterations", "0,5", "--noise", "none", "--metrics", "ariadne,rfi",
         "--no-figures"]
    )  # fmt: skip
    captured = capsys.readouterr()
    assert code == 0, captured.err
    assert captured.out.splitlines()[0].split("\t") == list(SUMMARY_COLUMNS)
    with open(out / "sensitivity.csv", newline="") as handle:
        rows = list(csv.DictReader(handle))
    assert {r["crown"] for r in rows} == {"ten", "eight"}
    assert {(r["axis"], r["level"]) for r in rows} == {
        ("base", ""), ("faces", "300"), ("faces", "1200"), ("smoothing", "0"), ("smoothing", "5")
    }  # fmt: skip
    assert {r["metric"] for r in rows} == {"ariadne", "rfi"}
    assert sorted(p.name for p in out.iterdir()) == ["sensitivity.csv", "sensitivity_summary.csv"]
    assert f"wrote {out / 'sensitivity.csv'}" in captured.err


def test_the_command_with_figures(crowns, tmp_path, capsys):
    pytest.importorskip("matplotlib")
    out = tmp_path / "study"
    code = robustness_main(
        [str(crowns / "ten.ply"), "-o", str(out), "--faces", "300", "--smooth-iterations",
         "none", "--noise", "0,0.001", "--metrics", "slope", "--smooth", "laplacian"]
    )  # fmt: skip
    assert code == 0, capsys.readouterr().err
    assert (out / "sensitivity_slope.png").read_bytes().startswith(PNG)


@pytest.mark.parametrize(
    ("options", "message"),
    [
        (["--faces", "300,x"], "--faces wants face counts"),
        (["--faces", "3"], "--faces wants face counts"),
        (["--faces", "300,,600"], "--faces wants face counts"),
        (["--smooth-iterations", "-1"], "--smooth-iterations wants iteration counts"),
        (["--noise", "-0.1"], "--noise wants sd values"),
        (["--noise", "inf"], "--noise wants sd values"),
        (["--smooth", "median"], "--smooth must be one of"),
        (["--smooth", "laplacian", "--smooth-mu", "0.5"], "--smooth-mu is a parameter"),
        (["--smooth-step", "x"], "--smooth-step wants a number"),
        (["--smooth-step", "0"], "--smooth-step must be above 0"),
        (["--base-faces", "many"], "--base-faces wants a face count"),
        (["--metrics", "ariadne,bogus"], "--metrics wants 'all' or names among"),
        (["--faces", "none", "--smooth-iterations", "none", "--noise", "none"], "nothing to"),
        (["--faces", "300", "--low-faces", "200"], "--low-faces belong to the paper's study"),
        (["--faces", "300", "--sign-method", "centroid"], "--sign-method belong"),
        (["--faces", "300", "--perturbation", "a=b.ply"], "--perturbation belong"),
    ],
)
def test_wrong_values_are_one_line_and_exit_2(crowns, tmp_path, capsys, options, message):
    out = tmp_path / "study"
    code = robustness_main([str(crowns / "ten.ply"), "-o", str(out), "--no-figures", *options])
    err = capsys.readouterr().err
    assert code == 2
    assert err.count("\n") == 1 and err.startswith("dentopo robustness: "), err
    assert message in err
    assert not out.exists()


def test_the_command_refuses_an_output_folder_that_is_an_input(crowns, capsys):
    code = robustness_main([str(crowns), "-o", str(crowns / "ten.ply"), "--faces", "300"])
    assert code == 2
    assert capsys.readouterr().err.count("\n") == 1


def test_the_command_names_an_unreadable_crown(crowns, tmp_path, capsys):
    bad = crowns / "bad.ply"
    bad.write_text("not a mesh")
    code = robustness_main([str(crowns), "-o", str(tmp_path / "o"), "--faces", "300",
                            "--no-figures"])  # fmt: skip
    err = capsys.readouterr().err
    assert code == 1 and "bad.ply" in err and err.count("\n") == 1
    assert not (tmp_path / "o" / "sensitivity.csv").exists()


def test_the_paper_study_is_unchanged_by_default(tmp_path, crown, capsys):
    """Without the new options, ``dentopo robustness`` is the paper's study, as before."""
    path = tmp_path / "crown.ply"
    crown.export(path)
    code = robustness_main(
        [
            str(path),
            "-o",
            str(tmp_path / "p"),
            "--low-faces",
            "300",
            "--high-faces",
            "1200",
            "--sign-method",
            "centroid",
            "--no-figures",
        ]
    )
    assert code == 0, capsys.readouterr().err
    assert sorted(p.name for p in (tmp_path / "p").iterdir()) == ["robustness.csv"]
