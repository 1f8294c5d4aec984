"""Provenance inside the pictures: the PNG text chunk, the HTML block, ``dentopo info``."""

from __future__ import annotations

import hashlib
import json

import numpy as np
import pytest

from dentopo import ariaDNE, render_curvature, render_panel
from dentopo.cli import main
from dentopo.figures import camera_for, read_provenance, render_slope
from dentopo.samples import sample_paths

pytest.importorskip("pyvista", reason="pyvista (the viz extra) is needed to render")
Image = pytest.importorskip("PIL.Image", reason="Pillow is needed to read the PNG")


@pytest.fixture
def tooth_ply():
    return sample_paths()["tooth"]


def sha256(path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def test_png_from_a_file_names_it_and_its_hash(tmp_path, tooth_ply):
    png = tmp_path / "tooth.png"
    render_curvature(tooth_ply, screenshot=png, window_size=(400, 300), limits=0.25, elevation=20)
    record = read_provenance(png)
    with Image.open(png) as image:  # Pillow reads the same chunk, named dentopo
        assert json.loads(image.text["dentopo"]) == record
    assert record["software"] == "dentopo"
    from dentopo import __version__

    assert record["version"] == __version__
    assert record["metric"] == "local_curvature"
    assert record["input"] == {"file": "tooth.ply", "sha256": sha256(tooth_ply)}
    parameters = record["parameters"]
    assert parameters["bandwidth"] == 0.08 and parameters["method"] in ("exact", "fast")
    assert parameters["limits"] == [-0.25, 0.25]
    result = ariaDNE(tooth_ply)
    camera = camera_for(result.mesh.vertices, result.mesh.faces, elevation=20)
    for key in ("position", "focal_point", "up"):
        np.testing.assert_allclose(record["camera"][key], getattr(camera, key), rtol=1e-12)
    assert record["camera"]["view"] == "occlusal" and record["camera"]["elevation"] == 20


def test_mesh_object_has_no_file_unless_given(tmp_path, tooth, tooth_ply):
    png = tmp_path / "a.png"
    render_curvature(tooth, screenshot=png, window_size=(300, 200))
    assert read_provenance(png)["input"] == {"file": None, "sha256": None}
    render_curvature(tooth, screenshot=png, window_size=(300, 200), source=tooth_ply)
    assert read_provenance(png)["input"]["sha256"] == sha256(tooth_ply)


def test_panel_records_every_mesh(tmp_path, tooth_ply):
    sphere = sample_paths()["sphere"]
    png = tmp_path / "panel.png"
    render_panel([(tooth_ply, None), (sphere, None)], screenshot=png, window_size=(600, 300))
    record = read_provenance(png)
    assert [p["input"]["file"] for p in record["panels"]] == ["tooth.ply", "sphere.ply"]
    assert "input" not in record  # several meshes: only per panel
    assert all("position" in p["camera"] for p in record["panels"])


def test_topography_pictures_record_their_parameters(tmp_path, tooth):
    png = tmp_path / "slope.png"
    slope = np.zeros(len(tooth.faces))
    render_slope(
        tooth, slope, screenshot=png, window_size=(300, 300), parameters={"orient": "auto"}
    )
    record = read_provenance(png)
    assert record["metric"] == "slope" and record["parameters"]["orient"] == "auto"


def test_info_prints_the_json(tmp_path, capsys, tooth_ply):
    png, page = tmp_path / "tooth.png", tmp_path / "tooth.html"
    assert main([str(tooth_ply), "--screenshot", str(png), "--html", str(page), "-q"]) == 0
    capsys.readouterr()
    assert main(["info", str(png)]) == 0
    printed = json.loads(capsys.readouterr().out)
    assert printed["input"] == {"file": "tooth.ply", "sha256": sha256(tooth_ply)}
    assert main(["info", str(page)]) == 0
    from_page = json.loads(capsys.readouterr().out)
    assert from_page["input"] == printed["input"] and from_page["camera"] == printed["camera"]


def test_info_on_a_file_without_provenance_fails_in_one_line(tmp_path, capsys):
    plain = tmp_path / "plain.png"
    Image.new("RGB", (8, 8)).save(plain)
    assert main(["info", str(plain)]) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "no dentopo provenance" in err
    text = tmp_path / "notes.txt"
    text.write_text("hello")
    assert main(["info", str(text)]) == 1
    assert "neither a PNG nor an HTML" in capsys.readouterr().err
    assert main(["info", str(tmp_path / "missing.png")]) == 1
    with pytest.raises(ValueError, match="no dentopo provenance"):
        read_provenance(plain)
