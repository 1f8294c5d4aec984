"""Pictures, rendered off-screen: sizes, colours where the field is known, errors.

Pixels are classified as red (R well above B), blue (B well above R) or
neutral grey (R, G, B equal).  The mesh's picture lies between the caption
(top left) and the colour-bar row, so only rows 8% to 70% are examined.
"""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from conftest import capture_layouts, layout_problems, meshes_outside_their_frames, plane_patch
from dentopo import (
    DisplayUnavailableError,
    ariaDNE,
    render_comparison,
    render_curvature,
    render_panel,
)
from dentopo.figures import _render

pv = pytest.importorskip("pyvista", reason="pyvista (the viz extra) is needed to render")
Image = pytest.importorskip("PIL.Image", reason="Pillow is needed to read the PNG")

MARGIN = 40  # channel difference that counts as clearly red or blue


def picture(path) -> np.ndarray:
    """The mesh part of a screenshot, (h, w, 3) int: below the caption, above the bar."""
    with Image.open(path) as png:
        image = np.asarray(png.convert("RGB")).astype(int)
    return image[int(0.08 * image.shape[0]) : int(0.7 * image.shape[0])]


def mesh_pixels(image: np.ndarray) -> np.ndarray:
    return (image < 250).any(axis=2)


def red(image):
    return image[..., 0] - image[..., 2] > MARGIN


def blue(image):
    return image[..., 2] - image[..., 0] > MARGIN


def test_png_has_the_requested_size(tmp_path, tooth):
    path = tmp_path / "tooth.png"
    render_curvature(tooth, screenshot=path, window_size=(320, 240))
    with Image.open(path) as png:
        assert png.size == (320, 240)


def test_positive_field_is_red_negative_blue(tmp_path):
    plane = plane_patch(31)
    field = plane.vertices[:, 0] - 0.5  # negative on the left half, positive on the right
    path = tmp_path / "halves.png"
    render_curvature(plane, field=field, view="top", screenshot=path, window_size=(400, 400))
    image = picture(path)
    rows, cols = np.nonzero(mesh_pixels(image))
    left = image[rows.min() : rows.max(), cols.min() : cols.min() + (cols.max() - cols.min()) // 3]
    right = image[rows.min() : rows.max(), cols.max() - (cols.max() - cols.min()) // 3 : cols.max()]
    assert blue(left).mean() > 0.95 and not red(left).any()
    assert red(right).mean() > 0.95 and not blue(right).any()


def test_zero_field_renders_neutral_grey(tmp_path, tooth):
    path = tmp_path / "zero.png"
    render_curvature(tooth, field=np.zeros(len(tooth.vertices)), screenshot=path)
    image = picture(path)
    mesh = image[mesh_pixels(image)]
    assert len(mesh) > 10_000
    assert np.ptp(mesh, axis=1).max() <= 2  # R = G = B: no tint anywhere


def test_tooth_cusps_red_basin_blue(tmp_path, tooth):
    result = ariaDNE(tooth)
    path = tmp_path / "tooth_top.png"
    render_curvature(tooth, result, view="top", screenshot=path, window_size=(500, 500))
    image = picture(path)
    rows, cols = np.nonzero(mesh_pixels(image))
    centre_r, centre_c = (rows.min() + rows.max()) // 2, (cols.min() + cols.max()) // 2
    basin = image[centre_r - 3 : centre_r + 4, centre_c - 3 : centre_c + 4]
    assert blue(basin).all()
    for quadrant in (
        image[rows.min() : centre_r, cols.min() : centre_c],
        image[rows.min() : centre_r, centre_c : cols.max()],
        image[centre_r : rows.max(), cols.min() : centre_c],
        image[centre_r : rows.max(), centre_c : cols.max()],
    ):
        assert red(quadrant).sum() > 100  # one convex cusp per quadrant


def test_panel_shares_one_scale(tmp_path, tooth):
    # the same mesh twice, the second with its field doubled: with a shared
    # scale the second is more saturated, so it has more strongly red pixels
    result = ariaDNE(tooth)
    path = tmp_path / "panel.png"
    fields = [result.local_curvature, 2 * result.local_curvature]
    render_panel(
        [(tooth, result), (tooth, result)],
        field=fields,
        labels=["once", "twice"],
        view="top",
        screenshot=path,
        window_size=(800, 500),
    )
    image = picture(path)
    first, second = image[:, :400], image[:, 400:]
    assert red(second).sum() > 1.3 * red(first).sum()


def test_interactive_without_display_says_so(monkeypatch, tooth):
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    monkeypatch.setattr(sys, "platform", "linux")
    with pytest.raises(DisplayUnavailableError, match="no display"):
        render_curvature(tooth, field=np.zeros(len(tooth.vertices)), interactive=True)


def test_bad_options_are_refused(tmp_path, tooth):
    zero = np.zeros(len(tooth.vertices))
    with pytest.raises(ValueError, match="nothing to draw"):
        render_curvature(tooth, field=zero)
    with pytest.raises(ValueError, match="view"):
        render_curvature(tooth, field=zero, view="sideways", screenshot=tmp_path / "x.png")
    with pytest.raises(ValueError, match="one value per vertex"):
        render_curvature(tooth, field=zero[:-1], screenshot=tmp_path / "x.png")
    with pytest.raises(ValueError, match="field"):
        render_curvature(tooth, field="curvature", screenshot=tmp_path / "x.png")
    with pytest.raises(ValueError, match="labels"):
        render_panel([(tooth, None)], labels=["a", "b"], screenshot=tmp_path / "x.png")


def test_caller_mesh_is_not_modified(tmp_path, tooth):
    vertices, faces = tooth.vertices.copy(), tooth.faces.copy()
    render_curvature(tooth, field=np.zeros(len(vertices)), html=tmp_path / "x.html")
    np.testing.assert_array_equal(tooth.vertices, vertices)
    np.testing.assert_array_equal(tooth.faces, faces)


def test_import_does_not_load_heavy_stacks():
    heavy = ("pyvista", "vtk", "vtkmodules", "matplotlib", "pandas", "dask", "finufft")
    code = f"import sys, dentopo; print([m for m in {heavy!r} if m in sys.modules])"
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    ).stdout
    assert out.strip() == "[]"


# ---------------------------------------------------------------------------
# print-ready layout: measured on the figure that was saved

SIZES = [((640, 480), None), ((1600, 1200), 600)]


def read_rgba(path) -> np.ndarray:
    with Image.open(path) as png:
        return np.asarray(png.convert("RGBA"))


@pytest.mark.parametrize(("size", "dpi"), SIZES)
def test_single_picture_layout_holds(monkeypatch, tmp_path, tooth, size, dpi):
    layouts = capture_layouts(monkeypatch, _render)
    path = tmp_path / "tooth.png"
    render_curvature(tooth, screenshot=path, window_size=size, dpi=dpi, title="sample tooth")
    (layout,) = layouts
    assert layout_problems(layout) == []
    image = read_rgba(path)
    assert image.shape[:2] == size[::-1]
    assert meshes_outside_their_frames(layout, image) == []
    with Image.open(path) as png:
        if dpi is not None:
            assert png.info["dpi"][0] == pytest.approx(dpi, abs=0.5)


@pytest.mark.parametrize(("size", "dpi"), [((1000, 400), None), ((4000, 1600), 600)])
def test_four_panel_layout_holds(monkeypatch, tmp_path, tooth, size, dpi):
    layouts = capture_layouts(monkeypatch, _render)
    result = ariaDNE(tooth)
    path = tmp_path / "panel.png"
    labels = ["a rather long label for a narrow panel", "b", "c", "d" * 120]  # one long word
    render_panel([(tooth, result)] * 4, labels=labels, screenshot=path, window_size=size, dpi=dpi)
    (layout,) = layouts
    assert len(layout.views) == 4
    assert layout_problems(layout) == []
    assert meshes_outside_their_frames(layout, read_rgba(path)) == []


def test_fonts_keep_their_printed_size(monkeypatch, tmp_path, tooth):
    layouts = capture_layouts(monkeypatch, _render)
    zero = np.zeros(len(tooth.vertices))
    for dpi in (150, 600):
        render_curvature(
            tooth, field=zero, screenshot=tmp_path / f"{dpi}.png", window_size=(1600, 1200), dpi=dpi
        )
    heights = []
    for layout in layouts:
        renderer = layout.figure.canvas.get_renderer()
        heights.append(max(t.get_window_extent(renderer).height for t in layout.texts))
    assert heights[1] > 3.5 * heights[0]  # 4 times the pixels per point


def test_sign_map_gets_two_swatches_not_a_colour_bar(monkeypatch, tmp_path, tooth):
    layouts = capture_layouts(monkeypatch, _render)
    render_comparison(tooth, screenshot=tmp_path / "signs.png", window_size=(1200, 500))
    (layout,) = layouts
    assert len(layout.figure.axes) == 3  # the three views, no colour-bar axes
    swatches = [p.get_facecolor()[:3] for p in layout.figure.artists]
    assert len(swatches) == 2
    red, blue = max(swatches, key=lambda c: c[0]), max(swatches, key=lambda c: c[2])
    assert red[0] > red[2] + 0.3 and blue[2] > blue[0] + 0.3
    words = " ".join(t.get_text() for t in layout.texts)
    assert "concave" in words and "convex" in words
    assert layout_problems(layout) == []


def test_svg_and_pdf_keep_the_legend_as_vectors(tmp_path, tooth):
    zero = np.zeros(len(tooth.vertices))
    render_curvature(tooth, field=zero, screenshot=tmp_path / "t.svg", window_size=(500, 400))
    svg = (tmp_path / "t.svg").read_text()
    assert svg.lstrip().startswith("<?xml") and "<svg" in svg
    assert svg.count("<image") == 2  # the 3D view and the colour bar's gradient
    assert svg.count("<path") > 20  # the texts' glyphs and the ticks
    render_curvature(tooth, field=zero, screenshot=tmp_path / "t.pdf", window_size=(500, 400))
    assert (tmp_path / "t.pdf").read_bytes().startswith(b"%PDF")
    with pytest.raises(ValueError, match=r"\.png, \.svg, \.pdf"):
        render_curvature(tooth, field=zero, screenshot=tmp_path / "t.jpg")


def test_transparent_background(tmp_path, tooth):
    path = tmp_path / "t.png"
    render_curvature(tooth, screenshot=path, window_size=(400, 300), transparent=True)
    image = read_rgba(path)
    assert image[0, 0, 3] == 0 and image[-1, -1, 3] == 0
    assert (image[..., 3] == 255).sum() > 5000  # the mesh and the texts are opaque
