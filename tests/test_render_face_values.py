"""Per-face maps of ARC, angularity, inclination and elevation: PNGs, HTML pages, the command.

One renderer (:func:`dentopo.figures.render_face_values`) draws the four,
with the settings of :data:`dentopo.figures.FACE_METRICS`: ARC on the
diverging map centred on 0 with symmetric limits by default, the others on
the sequential map from 0 (angularity to 90 degrees, inclination to 180,
elevation to its largest value).  The inputs are the library's results on
the small sample crown (``tooth(rings=16)``: four cusps around a basin,
pointing to +z), so the colours can be checked against the geometry: the
basin is concave (blue ARC), the cusps convex (red ARC) and highest.
"""

from __future__ import annotations

import json
import re
import shutil
import subprocess

import numpy as np
import pytest

from conftest import (
    OVERFLOW_CHECK,
    capture_layouts,
    layout_problems,
    meshes_outside_their_frames,
    view_region,
)
from dentopo.cli import main
from dentopo.figures import (
    FACE_METRICS,
    NEUTRAL,
    _face_drawing,
    color_scale,
    read_provenance,
    render_face_values,
)
from dentopo.figures._colors import sequential_rgb
from dentopo.figures._face_drawing import MISSING_RGB
from dentopo.samples import sample_paths, tooth
from dentopo.topography import angularity, arc, elevation, inclination

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

FOUR = ("arc", "angularity", "inclination", "elevation")
COMPUTE = {"arc": arc, "angularity": angularity, "inclination": inclination, "elevation": elevation}
#: The documented default scale of each sequential map (None: 0 to the largest value).
SEQUENTIAL = {"angularity": (0.0, 90.0), "inclination": (0.0, 180.0), "elevation": None}


@pytest.fixture(scope="module")
def results():
    mesh = tooth(rings=16)
    return {name: COMPUTE[name](mesh) for name in FOUR}


def values_of(results, name):
    result = results[name]
    return result.mesh, getattr(result, FACE_METRICS[name].field)


def read_png(path) -> np.ndarray:
    with Image.open(path) as png:
        return np.asarray(png.convert("RGB")).astype(int)


def page_colours(path) -> np.ndarray:
    import base64

    text = path.read_text()
    pattern = r'<script type="application/json" id="dentopo-data">(.*?)</script>'
    data = re.search(pattern, text, re.S)
    (record,) = json.loads(data.group(1).replace("<\\/", "</"))["meshes"]
    colours = np.frombuffer(base64.b64decode(record["colors"]), dtype=np.uint8).reshape(-1, 3)
    assert record["nf"] * 3 == len(colours)
    return colours[::3]  # one colour per face, repeated at its three corners


def expected_scale(name, values):
    """The scale the documentation promises, as (low, high)."""
    if name == "arc":
        limit = float(np.percentile(np.abs(values), 98))
        return (-limit, limit)
    return SEQUENTIAL[name] or (0.0, float(values.max()))


# ---------------------------------------------------------------------------
# the settings


def test_face_metrics_name_the_arrays_of_the_results(results):
    for name in FOUR:
        spec = FACE_METRICS[name]
        mesh, values = values_of(results, name)
        assert values.shape == (len(mesh.faces),)  # the arrays follow the result's mesh
        assert spec.diverging is (name == "arc")
    assert FACE_METRICS["angularity"].units == FACE_METRICS["inclination"].units == "degrees"
    assert FACE_METRICS["elevation"].units == "mesh units"
    assert FACE_METRICS["arc"].units == "dimensionless"


# ---------------------------------------------------------------------------
# PNGs


@needs_pyvista
@pytest.mark.parametrize("name", FOUR)
def test_png_layout_mesh_and_colour_bar(monkeypatch, tmp_path, results, name):
    mesh, values = values_of(results, name)
    layouts = capture_layouts(monkeypatch, _face_drawing)
    path = tmp_path / f"{name}.png"
    spec = FACE_METRICS[name]
    render_face_values(
        mesh, values, screenshot=path, window_size=(700, 700), title="tooth", **spec.keywords()
    )
    image = read_png(path)
    assert image.shape == (700, 700, 3)
    (layout,) = layouts
    assert layout_problems(layout) == []
    assert meshes_outside_their_frames(layout, image) == []
    low, high = expected_scale(name, values)
    record = read_provenance(path)
    assert record["metric"] == name
    np.testing.assert_allclose(record["parameters"]["scale"], [low, high])
    assert record["parameters"]["units"] == spec.units
    words = [t.get_text() for t in layout.texts]
    title = next(w for w in words if w.startswith(f"{spec.label} ("))
    assert spec.units in title
    degree = "\u00b0" if spec.units == "degrees" else ""
    if name == "arc":  # symmetric around 0: -L, -L/2, 0, L/2, L
        shown = f"{high:.3g}"
        assert f"\u2212{shown}" in words and shown in words and "0" in words
    else:  # from 0, in the metric's units
        assert f"0{degree}" in words
        if SEQUENTIAL[name]:
            assert f"{high:g}{degree}" in words
    assert len({tuple(p) for p in view_region(layout, image)[::3, ::3].reshape(-1, 3)}) > 50


@needs_pyvista
def test_arc_png_has_a_blue_basin_red_cusps_and_a_neutral_border(monkeypatch, tmp_path, results):
    mesh, values = values_of(results, "arc")
    layouts = capture_layouts(monkeypatch, _face_drawing)
    path = tmp_path / "arc.png"
    render_face_values(mesh, values, screenshot=path, **FACE_METRICS["arc"].keywords())
    drawing = view_region(layouts[0], read_png(path))
    rows, cols = np.nonzero((drawing < 245).any(axis=2))
    centre = np.array([rows.min() + rows.max(), cols.min() + cols.max()]) / 2
    radius = (rows.max() - rows.min()) / 2  # the crown is a disc seen from above
    r, c = np.indices(drawing.shape[:2])
    distance = np.hypot(r - centre[0], c - centre[1]) / radius
    red = drawing[..., 0] - drawing[..., 2] > 60
    blue = drawing[..., 2] - drawing[..., 0] > 60
    basin = distance < 0.25  # concave: negative, blue (its deepest faces zeroed by the cut)
    assert blue[basin].sum() > 5 * red[basin].sum() and blue[basin].sum() > 200
    cusps = (distance > 0.4) & (distance < 0.8)  # the four cusps: convex, positive, red
    assert red[cusps].sum() > 5 * blue[cusps].sum() and red[cusps].sum() > 1000
    rim = (distance > 0.93) & (distance < 0.98)  # the border faces: set to 0, neutral grey
    grey = np.ptp(drawing, axis=2) < 20
    assert grey[rim].mean() > 0.9


@needs_pyvista
@pytest.mark.parametrize(("size", "dpi"), [((500, 380), None), ((2000, 1600), 600)])
def test_png_layout_holds_at_two_sizes(monkeypatch, tmp_path, results, size, dpi):
    mesh, values = values_of(results, "inclination")
    layouts = capture_layouts(monkeypatch, _face_drawing)
    path = tmp_path / "inclination.png"
    keywords = FACE_METRICS["inclination"].keywords()
    render_face_values(mesh, values, screenshot=path, window_size=size, dpi=dpi, **keywords)
    (layout,) = layouts
    assert layout_problems(layout) == []
    assert meshes_outside_their_frames(layout, read_png(path)) == []


@needs_pyvista
def test_svg_and_pdf(tmp_path, results):
    mesh, values = values_of(results, "elevation")
    keywords = FACE_METRICS["elevation"].keywords()
    render_face_values(mesh, values, screenshot=tmp_path / "e.svg", **keywords)
    render_face_values(mesh, values, screenshot=tmp_path / "e.pdf", **keywords)
    assert "<svg" in (tmp_path / "e.svg").read_text()
    assert (tmp_path / "e.pdf").read_bytes().startswith(b"%PDF")


# ---------------------------------------------------------------------------
# HTML (no extra needed)


def test_arc_page_colours_sign_and_zero(tmp_path, results):
    mesh, values = values_of(results, "arc")
    path = tmp_path / "arc.html"
    render_face_values(mesh, values, html=path, **FACE_METRICS["arc"].keywords())
    colours = page_colours(path).astype(int)
    scale = color_scale(values)
    assert scale.limits[0] == -scale.limits[1]  # symmetric by default
    np.testing.assert_array_equal(colours, scale.rgb(values))
    zero = values == 0  # the faces ARC zeroed (border, beyond the quantiles)
    assert zero.sum() > 10
    assert (colours[zero] == np.round(255 * np.array(NEUTRAL)).astype(int)).all()
    strong = np.abs(values) > 0.5 * scale.limit
    assert (colours[strong & (values > 0), 0] > colours[strong & (values > 0), 2] + 60).all()
    assert (colours[strong & (values < 0), 2] > colours[strong & (values < 0), 0] + 60).all()
    text = path.read_text()
    assert "ARC (dimensionless" in text and "98th percentile" in text
    assert read_provenance(path)["parameters"]["map"] == "diverging"


@pytest.mark.parametrize("name", ["angularity", "inclination", "elevation"])
def test_sequential_pages_run_from_zero(tmp_path, results, name):
    mesh, values = values_of(results, name)
    path = tmp_path / f"{name}.html"
    spec = FACE_METRICS[name]
    render_face_values(mesh, values, html=path, **spec.keywords())
    low, high = expected_scale(name, values)
    assert low == 0.0
    expected = np.round(255 * sequential_rgb((values - low) / (high - low))).astype(int)
    np.testing.assert_array_equal(page_colours(path), expected)
    text = path.read_text()
    assert f"{spec.label} ({spec.units}" in text
    np.testing.assert_allclose(read_provenance(path)["parameters"]["scale"], [low, high])


def test_limits_are_honoured(tmp_path, results):
    mesh, values = values_of(results, "arc")
    path = tmp_path / "arc.html"
    keywords = {**FACE_METRICS["arc"].keywords(), "limits": (-2.0, 4.0)}
    render_face_values(mesh, values, html=path, **keywords)
    assert read_provenance(path)["parameters"]["scale"] == [-2.0, 4.0]
    assert "-2 to 4 (fixed)" in path.read_text()  # color_scale's rule
    mesh, values = values_of(results, "elevation")
    keywords = {**FACE_METRICS["elevation"].keywords(), "limits": 2.0}
    render_face_values(mesh, values, html=path, **keywords)
    assert read_provenance(path)["parameters"]["scale"] == [0.0, 2.0]
    np.testing.assert_array_equal(
        page_colours(path), np.round(255 * sequential_rgb(values / 2.0)).astype(int)
    )


def test_nan_faces_are_grey_and_counted(tmp_path, results):
    mesh, values = values_of(results, "inclination")
    values = values.copy()
    values[:5] = np.nan
    path = tmp_path / "i.html"
    render_face_values(mesh, values, html=path, **FACE_METRICS["inclination"].keywords())
    np.testing.assert_array_equal(page_colours(path)[:5], [MISSING_RGB] * 5)
    assert "5 faces without a value in grey" in path.read_text()


def test_values_beyond_a_sequential_scale_are_counted(tmp_path, results):
    mesh, values = values_of(results, "elevation")
    path = tmp_path / "e.html"
    keywords = {**FACE_METRICS["elevation"].keywords(), "limits": (0.0, 0.3)}
    render_face_values(mesh, values, html=path, **keywords)
    assert f"{int((values > 0.3).sum())} faces above 0.3 in the top colour" in path.read_text()


@needs_chromium
@pytest.mark.parametrize("name", FOUR)
def test_page_in_chromium(tmp_path, results, name):
    mesh, values = values_of(results, name)
    page = tmp_path / f"{name}.html"
    render_face_values(mesh, values, html=page, title="tooth", **FACE_METRICS[name].keywords())
    checked = tmp_path / "checked.html"
    checked.write_text(page.read_text().replace("</body>", OVERFLOW_CHECK + "</body>"))
    run = subprocess.run(
        [
            CHROMIUM,
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--no-first-run",
            "--host-resolver-rules=MAP * ~NOTFOUND",
            f"--user-data-dir={tmp_path / 'profile'}",
            "--use-gl=swiftshader",
            "--enable-unsafe-swiftshader",
            "--enable-logging=stderr",
            "--v=0",
            "--window-size=700,700",
            "--dump-dom",
            checked.as_uri(),
        ],
        capture_output=True,
        text=True,
        timeout=120,
        check=True,
    )
    dom, log = run.stdout, run.stderr
    assert 'data-ready="yes"' in re.search(r'<div id="status"[^>]*>', dom).group(0)
    assert not re.search(r"CONSOLE.*(Uncaught|Error|Refused)", log), log
    assert re.search(r'data-overflow="([^"]*)"', dom).group(1) == "[]"


# ---------------------------------------------------------------------------
# errors, inputs untouched


def test_bad_arguments_are_refused(tmp_path, results):
    mesh, values = values_of(results, "arc")
    html = tmp_path / "x.html"
    keywords = FACE_METRICS["arc"].keywords()
    with pytest.raises(ValueError, match=r"ARC values must hold one value per face"):
        render_face_values(mesh, values[:-1], html=html, **keywords)
    with pytest.raises(ValueError, match="1 infinite values"):
        render_face_values(mesh, np.r_[np.inf, values[1:]], html=html, **keywords)
    with pytest.raises(ValueError, match="no number"):
        render_face_values(mesh, np.full_like(values, np.nan), html=html, **keywords)
    with pytest.raises(ValueError, match="zero strictly inside"):
        render_face_values(mesh, values, html=html, **{**keywords, "limits": (0.0, 1.0)})
    sequential = FACE_METRICS["elevation"].keywords()
    with pytest.raises(ValueError, match="LO < HI"):
        render_face_values(mesh, values, html=html, **{**sequential, "limits": (1.0, 1.0)})
    with pytest.raises(ValueError, match="nothing to draw"):
        render_face_values(mesh, values, **keywords)
    assert not html.exists()


def test_caller_mesh_and_values_are_unchanged(tmp_path, results):
    mesh, values = values_of(results, "arc")
    before = [mesh.vertices.copy(), mesh.faces.copy(), values.copy()]
    screenshot = {"screenshot": tmp_path / "x.png"} if HAVE_PYVISTA else {}
    render_face_values(
        mesh, values, html=tmp_path / "a.html", **screenshot, **FACE_METRICS["arc"].keywords()
    )
    for old, new in zip(before, [mesh.vertices, mesh.faces, values], strict=True):
        np.testing.assert_array_equal(old, new)


# ---------------------------------------------------------------------------
# the command


@pytest.fixture
def tooth_ply():
    return str(sample_paths()["tooth"])


def one_line(capsys) -> str:
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1, err
    return err


@pytest.mark.parametrize("name", ["arc", "angularity", "inclination"])
def test_command_refuses_a_batch_metric_not_computed(tmp_path, capsys, tooth_ply, name):
    png = tmp_path / "x.png"
    argv = [tooth_ply, "--metrics", "slope", "--color-by", name, "--screenshot", str(png)]
    assert main(argv) == 2
    assert f"add --metrics {name}" in one_line(capsys)
    assert not png.exists()


def test_command_refuses_what_it_cannot_draw(tmp_path, capsys, tooth_ply):
    png = tmp_path / "x.png"
    argv = [tooth_ply, "--color-by", "elevation", "--screenshot", str(png), "--limits", "0", "1"]
    assert main(argv) == 2
    assert "sequential scale" in one_line(capsys)
    argv = [tooth_ply, "--metrics", "arc", "--color-by", "arc", "--panel", str(png)]
    assert main(argv) == 2
    assert "draws one mesh" in one_line(capsys)
    assert not png.exists()


def test_command_draws_arc_with_its_parameters(tmp_path, tooth_ply):
    page, table = tmp_path / "arc.html", tmp_path / "t.csv"
    argv = [tooth_ply, "--metrics", "arc", "--color-by", "arc", "--html", str(page)]
    argv += ["--arc-boundary", "leg", "--arc-range", "0.02", "0.98", "-o", str(table), "-q"]
    assert main([*argv, "--limits", "-3", "3"]) == 0
    record = read_provenance(page)
    assert record["metric"] == "arc" and record["camera"]["view"] == "occlusal"
    parameters = record["parameters"]
    assert parameters["arc_boundary"] == "leg" and parameters["arc_range"] == [0.02, 0.98]
    assert parameters["scale"] == [-3.0, 3.0] and parameters["map"] == "diverging"
    assert "border faces (leg rule)" in page.read_text()


def test_command_draws_elevation_without_a_batch_metric(tmp_path, capsys, tooth_ply):
    page, table = tmp_path / "e.html", tmp_path / "t.csv"
    argv = [tooth_ply, "--metrics", "slope", "--color-by", "elevation", "--html", str(page)]
    assert main([*argv, "--orient", "auto", "-o", str(table), "-q"]) == 0
    record = read_provenance(page)
    assert record["metric"] == "elevation" and record["parameters"]["orient"] == "auto"
    assert record["parameters"]["scale"][0] == 0.0
    expected = elevation(tooth_ply, orient="auto").face_elevation.max()
    assert record["parameters"]["scale"][1] == pytest.approx(expected)


@needs_pyvista
def test_command_draws_angularity_png(tmp_path, tooth_ply):
    png, table = tmp_path / "a.png", tmp_path / "t.csv"
    argv = [tooth_ply, "--metrics", "angularity", "--color-by", "angularity"]
    assert main([*argv, "--screenshot", str(png), "--size", "400", "400", "-o", str(table)]) == 0
    record = read_provenance(png)
    assert record["metric"] == "angularity" and record["parameters"]["scale"] == [0.0, 90.0]


def test_command_draws_inclination(tmp_path, tooth_ply):
    from dentopo.batch import _measure

    if "inclination" not in _measure._TOPOGRAPHY:
        pytest.skip("the batch does not compute inclination yet (--metrics inclination)")
    page, table = tmp_path / "i.html", tmp_path / "t.csv"
    argv = [tooth_ply, "--metrics", "inclination", "--color-by", "inclination"]
    assert main([*argv, "--html", str(page), "-o", str(table), "-q"]) == 0
    record = read_provenance(page)
    assert record["metric"] == "inclination" and record["parameters"]["scale"] == [0.0, 180.0]
