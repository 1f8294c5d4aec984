"""The dentopo command's picture options, through ``main([...])``."""

from __future__ import annotations

import sys

import pytest

from dentopo.cli import main
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
    assert text.count('"label":') == 2


def test_visualize_without_display_says_so(monkeypatch, capsys, tooth_ply):
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    monkeypatch.setattr(sys, "platform", "linux")
    assert main([tooth_ply, "-v"]) == 1
    assert "no display" in capsys.readouterr().err


def test_asymmetric_limits_are_refused(tmp_path, capsys, tooth_ply):
    png = tmp_path / "x.png"
    assert main([tooth_ply, "--screenshot", str(png), "--limits", "-0.1", "0.3"]) == 2
    assert "symmetric" in capsys.readouterr().err
    assert not png.exists()
