"""Pictures of slope, OPC and the RFI footprint: PNGs, HTML pages, colours, errors.

The inputs are computed here from the face normals with plain numpy (slope in
whole degrees from +z, the aspect bin of ``atan2(n_y, n_x)`` in steps of 45
degrees, patches as connected faces of one bin, the convex hull of the x-y
projection standing in for the footprint): they are only something to draw.
A dome (the upper part of an icosphere) has faces of every aspect, so its OPC
picture must show all eight bin colours.
"""

from __future__ import annotations

import base64
import colorsys
import json
import re
import shutil
import subprocess
import sys

import numpy as np
import pytest
import trimesh
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import ConvexHull

from conftest import (
    OVERFLOW_CHECK,
    capture_layouts,
    layout_problems,
    meshes_outside_their_frames,
    view_region,
)
from dentopo._optional import MissingExtraError
from dentopo.figures import (
    OPC_COLORS,
    DisplayUnavailableError,
    _face_drawing,
    render_footprint,
    render_opc,
    render_slope,
    slope_rgb,
)
from dentopo.figures._topography import BORDER_RGB, OUTLINE_RGB, patch_borders

Image = pytest.importorskip("PIL.Image", reason="Pillow is needed to read the pictures")
try:
    import pyvista  # noqa: F401

    HAVE_PYVISTA = True
except ImportError:
    HAVE_PYVISTA = False
needs_pyvista = pytest.mark.skipif(
    not HAVE_PYVISTA, reason="pyvista (the viz extra) is needed to render PNGs"
)
CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
needs_chromium = pytest.mark.skipif(
    CHROMIUM is None, reason="headless Chromium (Debian package 'chromium') is not installed"
)


# ---------------------------------------------------------------------------
# inputs, computed here


def dome() -> trimesh.Trimesh:
    sphere = trimesh.creation.icosphere(subdivisions=3)
    keep = sphere.triangles_center[:, 2] > -0.3
    mesh = trimesh.Trimesh(sphere.vertices, sphere.faces[keep], process=False)
    mesh.remove_unreferenced_vertices()
    return trimesh.Trimesh(mesh.vertices * [2.0, 1.5, 1.0], mesh.faces, process=False)


def slopes(mesh) -> np.ndarray:
    return np.round(np.degrees(np.arccos(np.clip(mesh.face_normals[:, 2], -1, 1)))).astype(int)


def bins(mesh) -> np.ndarray:
    n = mesh.face_normals
    aspect = np.degrees(np.arctan2(n[:, 1], n[:, 0]))
    return np.clip(np.ceil((aspect + 180.0) / 45.0).astype(int), 1, 8)


def patches(mesh, face_bin) -> np.ndarray:
    pairs = mesh.face_adjacency
    same = pairs[face_bin[pairs[:, 0]] == face_bin[pairs[:, 1]]]
    graph = coo_matrix((np.ones(len(same)), (same[:, 0], same[:, 1])), shape=(len(face_bin),) * 2)
    return connected_components(graph, directed=False)[1]


def hull_outline(mesh) -> np.ndarray:
    xy = np.asarray(mesh.vertices)[:, :2]
    return xy[ConvexHull(xy).simplices]


@pytest.fixture(scope="module")
def inputs():
    mesh = dome()
    face_bin = bins(mesh)
    assert set(face_bin) == set(range(1, 9))  # the dome has every aspect
    return mesh, slopes(mesh), face_bin, patches(mesh, face_bin), hull_outline(mesh)


# ---------------------------------------------------------------------------
# reading pictures


def read_png(path) -> np.ndarray:
    with Image.open(path) as png:
        return np.asarray(png.convert("RGB")).astype(int)


def hue_saturation(image: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Hue in degrees and saturation of each pixel (shading scales RGB, keeping both)."""
    rgb = image.reshape(-1, 3) / 255.0
    hs = np.array([colorsys.rgb_to_hsv(*p)[:2] for p in rgb])
    return 360.0 * hs[:, 0], hs[:, 1]


def hue_counts(image: np.ndarray, colours, tolerance: float = 8.0) -> list[int]:
    """Pixels of (nearly) each colour's hue, among clearly coloured pixels."""
    small = image[::2, ::2]
    hue, saturation = hue_saturation(small)
    coloured = saturation > 0.5
    counts = []
    for colour in colours:
        target = 360.0 * colorsys.rgb_to_hsv(*(np.asarray(colour) / 255.0))[0]
        distance = np.abs((hue - target + 180.0) % 360.0 - 180.0)
        counts.append(int((coloured & (distance < tolerance)).sum()))
    return counts


def page_payload(path) -> dict:
    text = path.read_text()
    pattern = r'<script type="application/json" id="dentopo-data">(.*?)</script>'
    data = re.search(pattern, text, re.S)
    return json.loads(data.group(1).replace("<\\/", "</"))


def decode(b64: str, dtype) -> np.ndarray:
    return np.frombuffer(base64.b64decode(b64), dtype=dtype)


def assert_self_contained(path) -> None:
    text = path.read_text()
    assert "default-src 'none'" in text
    code = re.sub(r'<script type="application/json"[^>]*>.*?</script>', "", text, flags=re.S)
    assert not re.search(r"(https?:|//[a-z]|src=|href=|@import|url\()", code, flags=re.I)


# ---------------------------------------------------------------------------
# colours


def test_opc_colours_go_round_the_wheel_in_bin_order():
    hues = [360.0 * colorsys.rgb_to_hsv(*(c / 255.0))[0] for c in OPC_COLORS]
    steps = np.diff(np.r_[hues, hues[0] + 360.0])
    np.testing.assert_allclose(steps, 45.0, atol=1.0)  # bin 8 -> bin 1 too
    assert len({tuple(c) for c in OPC_COLORS}) == 8


def test_slope_scale_runs_dark_to_light_and_clips_overhangs():
    rgb = slope_rgb([0, 30, 60, 90, 120]).astype(int)
    brightness = rgb.sum(axis=1)
    assert (np.diff(brightness[:4]) > 0).all()
    np.testing.assert_array_equal(rgb[3], rgb[4])


# ---------------------------------------------------------------------------
# PNGs


@needs_pyvista
def test_opc_png_shows_all_eight_bins_and_the_borders(monkeypatch, tmp_path, inputs):
    mesh, _, face_bin, face_patch, _ = inputs
    layouts = capture_layouts(monkeypatch, _face_drawing)
    path = tmp_path / "opc.png"
    render_opc(mesh, face_bin, face_patch, screenshot=path, window_size=(900, 600))
    image = read_png(path)
    assert image.shape == (600, 900, 3)
    (layout,) = layouts
    drawing = view_region(layout, image)
    counts = hue_counts(drawing, OPC_COLORS)
    assert min(counts) > 100, counts
    dark = (drawing.max(axis=2) < 70).sum()  # the patch borders
    assert dark > 200, dark
    # a categorical legend: eight bin swatches and the border's, each labelled
    swatches = [np.round(255 * np.array(p.get_facecolor()[:3])) for p in layout.figure.artists]
    np.testing.assert_array_equal(swatches, [*OPC_COLORS, BORDER_RGB])
    words = [t.get_text() for t in layout.texts]
    assert all(any(f"bin {k}:" in w for w in words) for k in range(1, 9))
    box = layout.views[0].get_window_extent(layout.figure.canvas.get_renderer())
    legend = image[round(600 - box.y0) :]  # below the view
    assert min(hue_counts(legend, OPC_COLORS, tolerance=2.0)) > 20  # drawn in the picture
    assert layout_problems(layout) == []


@needs_pyvista
@pytest.mark.parametrize(("size", "dpi"), [((900, 600), None), ((2400, 1700), 600)])
def test_opc_png_layout_holds_at_two_sizes(monkeypatch, tmp_path, inputs, size, dpi):
    mesh, _, face_bin, face_patch, _ = inputs
    layouts = capture_layouts(monkeypatch, _face_drawing)
    path = tmp_path / "opc.png"
    render_opc(mesh, face_bin, face_patch, screenshot=path, window_size=size, dpi=dpi)
    (layout,) = layouts
    assert layout_problems(layout) == []
    assert meshes_outside_their_frames(layout, read_png(path)) == []


@needs_pyvista
def test_opc_png_without_borders_has_no_dark_lines(monkeypatch, tmp_path, inputs):
    mesh, _, face_bin, face_patch, _ = inputs
    layouts = capture_layouts(monkeypatch, _face_drawing)
    path = tmp_path / "opc.png"
    render_opc(mesh, face_bin, face_patch, borders=False, screenshot=path, window_size=(900, 600))
    drawing = view_region(layouts[0], read_png(path))
    assert (drawing.max(axis=2) < 70).sum() < 20


@needs_pyvista
def test_slope_png_is_dark_on_top_and_light_at_the_rim(tmp_path, inputs):
    mesh, face_slope, *_ = inputs
    path = tmp_path / "slope.png"
    render_slope(mesh, face_slope, screenshot=path, window_size=(600, 600))
    image = read_png(path)
    drawing = image[50 : int(0.75 * 600)]  # below the title, above the colour bar
    rows, cols = np.nonzero((drawing < 245).any(axis=2) & (drawing[..., 0] < 245))
    centre = drawing[(rows.min() + rows.max()) // 2, (cols.min() + cols.max()) // 2]
    # the top of the dome is flat: the dark purple end (blue above green)
    assert centre[2] > centre[1] + 40, centre
    # towards the rim the dome is steep: the yellow-green end (green above blue)
    rim = drawing[(rows.min() + rows.max()) // 2, cols.min() + 2 : cols.min() + 6]
    assert (rim[:, 1] > rim[:, 2] + 20).all(), rim
    assert len({tuple(p) for p in drawing[::3, ::3].reshape(-1, 3)}) > 50


@needs_pyvista
@pytest.mark.parametrize("upside_down", [False, True])
def test_footprint_png_shows_the_outline_around_the_mesh(
    monkeypatch, tmp_path, inputs, upside_down
):
    mesh, *_, outline = inputs
    if upside_down:  # seen from -z, the outline is drawn below the mesh, still in sight
        mesh = trimesh.Trimesh(mesh.vertices * [1, -1, -1], mesh.faces, process=False)
        outline = outline * [1, -1]
    layouts = capture_layouts(monkeypatch, _face_drawing)
    path = tmp_path / "footprint.png"
    render_footprint(mesh, outline, screenshot=path, window_size=(600, 600))
    image = view_region(layouts[0], read_png(path))
    red = (np.abs(image - OUTLINE_RGB) < 30).all(axis=2)
    assert red.sum() > 500
    grey = (np.ptp(image, axis=2) < 8) & (image[..., 0] < 240)  # the plain mesh
    rows, cols = np.nonzero(red)
    grey_rows, grey_cols = np.nonzero(grey)
    # the outline encloses the mesh: its extent is the mesh's, a few pixels more
    assert abs(rows.min() - grey_rows.min()) < 12 and abs(rows.max() - grey_rows.max()) < 12
    assert abs(cols.min() - grey_cols.min()) < 12 and abs(cols.max() - grey_cols.max()) < 12
    assert layout_problems(layouts[0]) == []


# ---------------------------------------------------------------------------
# HTML (no extra needed)


def test_slope_page_holds_the_per_face_colours(tmp_path, inputs):
    mesh, face_slope, *_ = inputs
    path = tmp_path / "slope.html"
    render_slope(mesh, face_slope, html=path)
    assert_self_contained(path)
    (record,) = page_payload(path)["meshes"]
    colours = decode(record["colors"], np.uint8).reshape(-1, 3)
    np.testing.assert_array_equal(colours, np.repeat(slope_rgb(face_slope), 3, axis=0))
    assert record["nf"] == len(mesh.faces) and "lines" not in record
    assert "0°" in path.read_text() and "90°" in path.read_text()


def test_opc_page_holds_bin_colours_and_borders(tmp_path, inputs):
    mesh, _, face_bin, face_patch, _ = inputs
    path = tmp_path / "opc.html"
    render_opc(mesh, face_bin, face_patch, html=path)
    assert_self_contained(path)
    (record,) = page_payload(path)["meshes"]
    colours = decode(record["colors"], np.uint8).reshape(-1, 3)
    np.testing.assert_array_equal(colours, np.repeat(OPC_COLORS[face_bin - 1], 3, axis=0))
    pairs = mesh.face_adjacency
    n_borders = int((face_patch[pairs[:, 0]] != face_patch[pairs[:, 1]]).sum())
    assert len(decode(record["lines"], "<f4")) == 6 * n_borders > 0
    assert record["lineColor"] == list(BORDER_RGB)
    text = path.read_text()
    for k in range(1, 9):
        assert f"bin {k}:" in text


def test_footprint_page_holds_the_outline_above_the_mesh(tmp_path, inputs):
    mesh, *_, outline = inputs
    path = tmp_path / "footprint.html"
    render_footprint(mesh, outline, html=path)
    assert_self_contained(path)
    (record,) = page_payload(path)["meshes"]
    lines = decode(record["lines"], "<f4").reshape(-1, 2, 3)
    positions = decode(record["positions"], "<f4").reshape(-1, 3)
    assert len(lines) == len(outline)
    assert (lines[..., 2] > positions[:, 2].max()).all()
    assert record["lineColor"] == list(OUTLINE_RGB)


@needs_chromium
@pytest.mark.parametrize("mode", ["", "#canvas2d"])
def test_opc_page_shows_the_bins_and_borders_in_a_browser(tmp_path, inputs, mode):
    mesh, _, face_bin, face_patch, _ = inputs
    page = tmp_path / "opc.html"
    render_opc(mesh, face_bin, face_patch, html=page)
    shot = tmp_path / "page.png"
    subprocess.run(
        [
            CHROMIUM,
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--no-first-run",
            "--host-resolver-rules=MAP * ~NOTFOUND",
            f"--user-data-dir={tmp_path / 'profile'}",
            "--window-size=800,700",
            f"--screenshot={shot}",
            page.as_uri() + mode,
        ],
        capture_output=True,
        timeout=120,
        check=True,
    )
    drawing = read_png(shot)[30:560]  # above the legend
    assert min(hue_counts(drawing, OPC_COLORS)) > 50
    assert (drawing.max(axis=2) < 70).sum() > 200  # the borders


@needs_chromium
@pytest.mark.parametrize("width", [420, 1200])
def test_opc_page_legend_stays_in_its_box(tmp_path, inputs, width):
    mesh, _, face_bin, face_patch, _ = inputs
    page = tmp_path / "opc.html"
    render_opc(mesh, face_bin, face_patch, html=page, title="a_long_specimen_name_without_spaces")
    checked = tmp_path / "checked.html"
    checked.write_text(page.read_text().replace("</body>", OVERFLOW_CHECK + "</body>"))
    dom = subprocess.run(
        [
            CHROMIUM,
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--no-first-run",
            "--host-resolver-rules=MAP * ~NOTFOUND",
            f"--user-data-dir={tmp_path / 'profile'}",
            f"--window-size={width},700",
            "--dump-dom",
            checked.as_uri(),
        ],
        capture_output=True,
        text=True,
        timeout=120,
        check=True,
    ).stdout
    assert 'data-checked="1"' in dom
    assert re.search(r'data-overflow="([^"]*)"', dom).group(1) == "[]"


# ---------------------------------------------------------------------------
# errors, inputs untouched, extras


def test_bad_arguments_are_refused(tmp_path, inputs):
    mesh, face_slope, face_bin, face_patch, _ = inputs
    html = tmp_path / "x.html"
    with pytest.raises(ValueError, match=r"face_slope must hold one value per face"):
        render_slope(mesh, face_slope[:-1], html=html)
    with pytest.raises(ValueError, match=r"face_slope must lie in \[0, 180\]"):
        render_slope(mesh, face_slope - 5, html=html)
    with pytest.raises(ValueError, match="face_slope holds 1 non-finite"):
        render_slope(mesh, np.where(np.arange(len(face_slope)) == 0, np.nan, face_slope), html=html)
    with pytest.raises(ValueError, match=r"face_bin must hold OPC bins 1 to 8; got 0, 9"):
        render_opc(mesh, np.r_[0, 9, face_bin[2:]], face_patch, html=html)
    with pytest.raises(ValueError, match="face_bin must hold one value per face"):
        render_opc(mesh, face_bin[1:], face_patch, html=html)
    with pytest.raises(ValueError, match="face_bin must hold whole numbers"):
        render_opc(mesh, face_bin + 0.5, face_patch, html=html)
    with pytest.raises(ValueError, match="face_patch must hold one value per face"):
        render_opc(mesh, face_bin, face_patch[:3], html=html)
    with pytest.raises(ValueError, match=r"footprint must hold x-y segments, shape \(k, 2, 2\)"):
        render_footprint(mesh, np.zeros((4, 2, 3)), html=html)
    with pytest.raises(ValueError, match="footprint holds no segments"):
        render_footprint(mesh, np.zeros((0, 2, 2)), html=html)
    with pytest.raises(ValueError, match="nothing to draw"):
        render_slope(mesh, face_slope)
    with pytest.raises(ValueError, match="view"):
        render_opc(mesh, face_bin, face_patch, view="sideways", html=html)
    assert not html.exists()


def test_caller_mesh_and_arrays_are_unchanged(tmp_path, inputs):
    mesh, face_slope, face_bin, face_patch, outline = inputs
    before = [a.copy() for a in (mesh.vertices, mesh.faces, face_slope, face_bin, face_patch)]
    before.append(outline.copy())
    screenshot = {"screenshot": tmp_path / "x.png"} if HAVE_PYVISTA else {}
    render_slope(mesh, face_slope, html=tmp_path / "s.html", **screenshot)
    render_opc(mesh, face_bin, face_patch, html=tmp_path / "o.html", **screenshot)
    render_footprint(mesh, outline, html=tmp_path / "f.html", **screenshot)
    after = [mesh.vertices, mesh.faces, face_slope, face_bin, face_patch, outline]
    for old, new in zip(before, after, strict=True):
        np.testing.assert_array_equal(old, new)


def test_patch_borders_follow_label_changes():
    mesh = trimesh.creation.box()
    label = np.zeros(len(mesh.faces), dtype=int)
    label[mesh.face_normals[:, 2] > 0.5] = 1  # the top square apart
    borders = patch_borders(np.asarray(mesh.vertices), np.asarray(mesh.faces), label)
    assert borders.shape == (4, 2, 3)  # the top square's four sides
    np.testing.assert_allclose(np.abs(borders[..., 2]), 0.5, atol=0.01)


def test_interactive_without_display_says_so(monkeypatch, inputs):
    mesh, face_slope, *_ = inputs
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    monkeypatch.setattr(sys, "platform", "linux")
    if not HAVE_PYVISTA:
        pytest.skip("without pyvista the missing extra is reported first")
    with pytest.raises(DisplayUnavailableError, match="no display"):
        render_slope(mesh, face_slope, interactive=True)


def test_png_without_pyvista_names_the_extra_html_needs_none(monkeypatch, tmp_path, inputs):
    mesh, face_slope, face_bin, face_patch, outline = inputs
    monkeypatch.setitem(sys.modules, "pyvista", None)  # as if not installed
    for draw in (
        lambda **o: render_slope(mesh, face_slope, **o),
        lambda **o: render_opc(mesh, face_bin, face_patch, **o),
        lambda **o: render_footprint(mesh, outline, **o),
    ):
        with pytest.raises(MissingExtraError, match=r"pip install 'dentopo\[viz\]'"):
            draw(screenshot=tmp_path / "x.png", html=tmp_path / "early.html")
        draw(html=tmp_path / "page.html")
    assert not (tmp_path / "x.png").exists() and not (tmp_path / "early.html").exists()
    assert (tmp_path / "page.html").exists()
