"""The robustness study, the bandwidth sweep and their commands."""

from __future__ import annotations

import csv
import dataclasses

import numpy as np
import pytest
import trimesh

from dentopo import (
    ariaDNE,
    bandwidth_sweep,
    classic_dne,
    perturb,
    robustness_study,
    sign_agreement,
    write_study,
    write_sweep,
)
from dentopo.cli import main
from dentopo.cli._study import robustness_main, sweep_main
from dentopo.samples import tooth
from dentopo.study import STUDY_COLUMNS, refine

PNG = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def crown():
    return tooth(rings=10)  # 331 vertices, 600 faces


@pytest.fixture(scope="module")
def study(crown):
    return robustness_study(
        crown, low_faces=300, high_faces=1500, sign_methods=["centroid", "mean_curvature"]
    )


def test_perturbations(crown):
    vertices = crown.vertices.copy()
    meshes = perturb(crown, low_faces=300, high_faces=1500)
    assert list(meshes) == ["normal", "low", "high", "noise1", "noise2", "smooth"]
    assert np.array_equal(crown.vertices, vertices)
    assert abs(len(meshes["low"].faces) - 300) <= 10
    assert len(meshes["high"].faces) in (1500, 1501)
    # noise: sd on the unit-area scale, reproducible with the seed
    unit = np.sqrt(crown.area)
    for name, sd in (("noise1", 1e-3), ("noise2", 2e-3)):
        step = (meshes[name].vertices - crown.vertices) / unit
        assert np.std(step) == pytest.approx(sd, rel=0.1)
    again = perturb(crown, low_faces=300, high_faces=1500)
    other = perturb(crown, low_faces=300, high_faces=1500, seed=1)
    assert np.array_equal(again["noise2"].vertices, meshes["noise2"].vertices)
    assert not np.array_equal(other["noise2"].vertices, meshes["noise2"].vertices)
    # Taubin smoothing moves vertices a little and keeps the faces
    moved = np.linalg.norm(meshes["smooth"].vertices - crown.vertices, axis=1)
    assert 0 < moved.max() < 0.05 * unit
    assert np.array_equal(meshes["smooth"].faces, crown.faces)


def test_refine_keeps_the_surface_and_stays_conforming(sphere):
    vertices, faces = refine(sphere.vertices, sphere.faces, 3000)
    refined = trimesh.Trimesh(vertices, faces, process=False)
    assert len(faces) == 3000
    assert refined.is_watertight and refined.is_winding_consistent
    assert refined.area == pytest.approx(sphere.area, rel=1e-12)
    assert refined.volume == pytest.approx(sphere.volume, rel=1e-12)


def test_sign_agreement(crown):
    result = ariaDNE(crown)
    assert sign_agreement(result, result) == 1.0
    flipped = dataclasses.replace(result, local_dne=-result.local_dne - 1e-9)
    assert sign_agreement(result, flipped) == 0.0
    classic = classic_dne(crown)
    assert sign_agreement(classic, classic) == 1.0
    with pytest.raises(TypeError, match="ClassicDNEResult"):
        sign_agreement(result, classic)


def test_study_rows(study):
    assert study.methods == ["centroid", "mean_curvature", "classic"]
    assert len(study.rows) == 6 * 3
    for row in study.rows:
        assert set(row) == set(STUDY_COLUMNS)
        assert 0.0 <= row["sign_agreement"] <= 1.0
        if row["perturbation"] == "normal":
            assert row["dne_normalised"] == row["sign_agreement"] == 1.0
    # the centroid sign survives a light smoothing almost everywhere
    assert study.row("smooth", "centroid")["sign_agreement"] > 0.9
    # ariaDNE's total is the same for every sign method
    assert study.row("low", "centroid")["dne"] == study.row("low", "mean_curvature")["dne"]


def test_study_with_given_perturbations(crown, tmp_path):
    path = tmp_path / "smoothed.ply"
    trimesh.smoothing.filter_taubin(crown.copy(), iterations=4).export(path)
    given = robustness_study(crown, perturbations={"smoothed": path}, sign_methods=["winding"])
    assert given.perturbations == ["normal", "smoothed"]
    assert given.row("smoothed", "winding")["sign_agreement"] > 0.9
    with pytest.raises(ValueError, match="original"):
        robustness_study(crown, perturbations={"normal": path})
    with pytest.raises(TypeError, match="low_faces"):
        robustness_study(crown, perturbations={"x": path}, low_faces=100)
    with pytest.raises(ValueError, match="sign_methods"):
        robustness_study(crown, sign_methods=["ray"])


def test_write_study(study, tmp_path):
    written = write_study(study, tmp_path / "out")
    assert [p.name for p in written] == [
        "robustness.csv",
        "robustness_signs.png",
        "robustness_totals.png",
    ]
    with open(written[0], newline="") as handle:
        rows = list(csv.DictReader(handle))
    assert len(rows) == len(study.rows)
    assert float(rows[0]["dne"]) == study.rows[0]["dne"]
    for png in written[1:]:
        assert png.read_bytes().startswith(PNG)
    assert not list((tmp_path / "out").glob(".*tmp"))
    only = write_study(study, tmp_path / "csv_only", figures=False)
    assert [p.name for p in only] == ["robustness.csv"]


def test_sweep(crown, tmp_path):
    sweep = bandwidth_sweep(crown, [0.05, 0.1])
    assert sweep.bandwidths == [0.05, 0.1]
    assert sweep.methods == ["centroid", "gaussian_curvature", "mean_curvature"]
    small = [row["dne"] for row in sweep.rows if row["bandwidth"] == 0.05]
    large = [row["dne"] for row in sweep.rows if row["bandwidth"] == 0.1]
    assert len(set(small)) == 1 and large[0] > small[0]
    written = write_sweep(sweep, tmp_path)
    assert [p.name for p in written] == ["sweep.csv", "sweep.png"]
    assert written[1].read_bytes().startswith(PNG)
    with pytest.raises(ValueError, match="bandwidth"):
        bandwidth_sweep(crown, [0.08, -1])


def test_commands(crown, tmp_path, capsys):
    path = tmp_path / "crown.ply"
    crown.export(path)
    code = robustness_main(
        [
            str(path),
            "-o",
            str(tmp_path / "study"),
            "--low-faces",
            "300",
            "--high-faces",
            "1200",
            "--sign-method",
            "centroid",
            "--no-classic",
            "--no-figures",
        ]
    )
    assert code == 0
    assert (tmp_path / "study" / "robustness.csv").exists()
    assert "sign_agreement" in capsys.readouterr().out
    assert sweep_main([str(path), "-b", "0.06", "-o", str(tmp_path), "--no-figures"]) == 0
    # registered as subcommands of the dentopo command
    assert main(["sweep", str(path), "-b", "0.05", "-o", str(tmp_path / "s"), "--no-figures"]) == 0
    assert (tmp_path / "s" / "sweep.csv").exists()
    assert (tmp_path / "sweep.csv").exists()
    bad = robustness_main([str(path), "-o", str(tmp_path), "--perturbation", "nopath"])
    assert bad == 2
    assert robustness_main([str(tmp_path / "missing.ply"), "-o", str(tmp_path)]) == 1


def test_the_study_figures_use_the_packages_one_diverging_map():
    """The README's one colour map (Moreland's cool to warm, zero neutral), not matplotlib's."""
    pytest.importorskip("matplotlib")
    from matplotlib.figure import Figure

    from dentopo.figures import NEUTRAL, diverging_rgb
    from dentopo.study import _figures

    # faces in the view plane (shade 1): each face's colour is the map's colour of its value
    vertices = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [2, 0, 0]], float)
    faces = np.array([[0, 1, 2], [1, 3, 2], [1, 4, 3]])
    values = np.array([-2.0, 0.0, 0.5])
    ax = Figure().subplots()
    _figures.draw_mesh(ax, vertices, faces, values, basis=np.eye(3), limit=1.0)
    [collection] = ax.collections
    drawn = collection.get_facecolors()[:, :3]
    order = np.argsort(vertices[faces][:, :, 2].mean(axis=1), kind="stable")
    expected = diverging_rgb(np.clip(values, -1, 1))[order]
    assert np.allclose(drawn, expected, atol=1e-12)
    assert np.allclose(drawn[list(order).index(1)], NEUTRAL)  # face 1's value is zero

    # the colour bars: the same map, end to end
    bar = _figures.colour_map()
    for t in np.linspace(-1, 1, 21):
        assert np.allclose(bar(0.5 + 0.5 * t)[:3], diverging_rgb(t), atol=0.01), t
    assert np.allclose(bar(0.5)[:3], NEUTRAL, atol=1e-3)
