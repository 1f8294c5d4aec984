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

from conftest import plane_patch
from dentopo import DisplayUnavailableError, ariaDNE, render_curvature, render_panel

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
