"""The dentopo command's picture options, through ``main([...])``."""

from __future__ import annotations

import re
import sys

import numpy as np
import pytest

from dentopo.cli import main
from dentopo.figures import read_provenance
from dentopo.samples import sample_paths

pytest.importorskip("pyvista", reason="pyvista (the viz extra) is needed to render")
Image = pytest.importorskip("PIL.Image", reason="Pillow is needed to read the PNG")


@pytest.fixture
def tooth_ply():
    return str(sample_paths()["tooth"])


def test_screenshot_with_window_size(tmp_path, tooth_ply):
    png = tmp_path / "tooth.png"
    assert main([tooth_ply, "--screenshot", str(png), "--window-size", "300", "200"]) == 0
    with Image.open(png) as image:
        assert image.size == (300, 200)


def test_html_and_panel(tmp_path, tooth_ply):
    sphere = str(sample_paths()["sphere"])
    page, panel = tmp_path / "tooth.html", tmp_path / "panel.html"
    argv = [tooth_ply, "--html", str(page), "--color-by", "local_dne", "--view", "top"]
    assert main(argv) == 0
    assert "local DNE" in page.read_text()
    assert main([tooth_ply, sphere, "--panel", str(panel), "--limits", "-0.3", "0.3"]) == 0
    text = panel.read_text()
    assert "default-src 'none'" in text and "±0.3 (fixed)" in text
    data = re.search(r'<script type="application/json" id="dentopo-data">(.*?)</script>', text)
    assert data.group(1).count('"label":') == 2


def test_visualize_without_display_says_so(monkeypatch, capsys, tooth_ply):
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    monkeypatch.setattr(sys, "platform", "linux")
    assert main([tooth_ply, "-v"]) == 2  # before computing, with what to use instead
    err = capsys.readouterr().err
    assert "needs a display" in err and "--screenshot" in err and "--html" in err


def test_limits_without_zero_inside_are_refused(tmp_path, capsys, tooth_ply):
    png = tmp_path / "x.png"
    assert main([tooth_ply, "--screenshot", str(png), "--limits", "0.1", "0.3"]) == 2
    assert "zero strictly inside" in capsys.readouterr().err
    assert not png.exists()


def test_asymmetric_limits_are_honoured_in_picture_page_and_per_vertex_colours(tmp_path, tooth_ply):
    png, page, pv = tmp_path / "t.png", tmp_path / "t.html", tmp_path / "pv"
    argv = [tooth_ply, "--screenshot", str(png), "--html", str(page), "--per-vertex", str(pv)]
    assert main([*argv, "--per-vertex-format", "npz", "--limits", "-0.1", "0.3", "-q"]) == 0
    assert read_provenance(png)["parameters"]["limits"] == [-0.1, 0.3]
    assert read_provenance(page)["parameters"]["limits"] == [-0.1, 0.3]
    assert "\u22120.1" in page.read_text() and "0.3 (fixed)" in page.read_text()
    from dentopo.figures import color_scale

    with np.load(pv / "tooth.dentopo.npz") as data:
        k, colours = data["local_curvature"], data["colors"]
    np.testing.assert_array_equal(colours, color_scale(limits=(-0.1, 0.3)).rgb(k))


def test_picture_options(tmp_path, tooth_ply):
    png = tmp_path / "tooth.png"
    argv = [tooth_ply, "--screenshot", str(png), "--size", "1200", "800", "--dpi", "300"]
    argv += ["--view", "front", "--azimuth", "30", "--elevation", "10", "--transparent", "-q"]
    assert main(argv) == 0
    with Image.open(png) as image:
        assert image.size == (1200, 800) and image.mode == "RGBA"
        assert image.info["dpi"][0] == pytest.approx(300, abs=0.5)
        assert image.getpixel((0, 0))[3] == 0
    camera = read_provenance(png)["camera"]
    assert (camera["view"], camera["azimuth"], camera["elevation"]) == ("front", 30.0, 10.0)


def test_default_view_is_occlusal_for_every_picture(tmp_path, tooth_ply):
    png = tmp_path / "opc.png"
    argv = [tooth_ply, "--metrics", "opc", "--color-by", "opc", "--screenshot", str(png), "-q"]
    assert main(argv) == 0
    record = read_provenance(png)
    assert record["metric"] == "opc" and record["camera"]["view"] == "occlusal"
    assert record["input"]["file"] == "tooth.ply" and record["parameters"]["min_faces"] == 3


def test_svg_and_pdf_pictures(tmp_path, tooth_ply):
    svg, pdf = tmp_path / "t.svg", tmp_path / "panel.pdf"
    assert main([tooth_ply, "--screenshot", str(svg), "--size", "400", "300", "-q"]) == 0
    assert "<svg" in svg.read_text()
    assert main([tooth_ply, "--panel", str(pdf), "--size", "400", "300", "-q"]) == 0
    assert pdf.read_bytes().startswith(b"%PDF")


def test_bad_picture_options_are_refused(tmp_path, capsys, tooth_ply):
    assert main([tooth_ply, "--screenshot", str(tmp_path / "x.jpg")]) == 2
    assert ".png, .svg or .pdf" in capsys.readouterr().err
    assert main([tooth_ply, "--screenshot", str(tmp_path / "x.png"), "--view", "sideways"]) == 2
    assert main([tooth_ply, "--screenshot", str(tmp_path / "x.png"), "--dpi", "5"]) == 2
    assert "--dpi" in capsys.readouterr().err
    assert not (tmp_path / "x.png").exists()
