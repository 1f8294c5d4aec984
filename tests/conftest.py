"""Shared fixtures: generated meshes and the optional shared reference data."""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np
import pytest
import trimesh

#: The environment variable that says where the shared data is, if not beside the checkout.
SHARED_ENV = "DENTOPO_SHARED"

#: The project's shared data lives beside the checkout (../shared), never inside it, or
#: where DENTOPO_SHARED says.
SHARED = Path(os.environ.get(SHARED_ENV) or Path(__file__).resolve().parents[2] / "shared")
MESHES = SHARED / "data" / "meshes"
REFERENCE = SHARED / "data" / "reference"
ROBUSTNESS_SET = ("normal", "low", "high", "noise1", "noise2", "smooth")


def shared_mesh(name: str) -> Path:
    """Path of a shared mesh; skips the test with the reason when it is absent."""
    path = MESHES / f"{name}.ply"
    if not path.exists():
        pytest.skip(
            f"shared data not found at {path} (expected beside the checkout, or where "
            f"{SHARED_ENV} says)"
        )
    return path


@pytest.fixture(scope="session")
def reference():
    path = REFERENCE / "signdne_0.1.4.json"
    if not path.exists():
        pytest.skip(f"published reference values not found at {path}")
    return json.loads(path.read_text())["meshes"]


@pytest.fixture(scope="session")
def reference_curvature():
    path = REFERENCE / "signdne_0.1.4_local_curvature.npz"
    if not path.exists():
        pytest.skip(f"published per-vertex curvature not found at {path}")
    with np.load(path) as data:
        return {name: data[name] for name in data.files}


@pytest.fixture
def sphere():
    return trimesh.creation.icosphere(subdivisions=3)


@pytest.fixture
def tooth():
    from dentopo.samples import tooth

    return tooth(rings=16)


def plane_patch(n: int = 21) -> trimesh.Trimesh:
    """A flat, regularly triangulated square in the z = 0 plane."""
    x, y = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n))
    vertices = np.column_stack([x.ravel(), y.ravel(), np.zeros(n * n)])
    idx = np.arange(n * n).reshape(n, n)
    a, b, c, d = (
        idx[:-1, :-1].ravel(),
        idx[:-1, 1:].ravel(),
        idx[1:, :-1].ravel(),
        idx[1:, 1:].ravel(),
    )
    faces = np.concatenate([np.column_stack([a, b, d]), np.column_stack([a, d, c])])
    return trimesh.Trimesh(vertices, faces, process=False)


@pytest.fixture
def plane():
    return plane_patch()


@pytest.fixture(scope="session")
def molar_topography():
    """molaR 6.0's slope, OPC, OPCR, RFI ... on the robustness set, one row per mesh file."""
    path = REFERENCE / "molaR_6.0_topography.csv"
    if not path.exists():
        pytest.skip(f"molaR 6.0 reference values not found at {path}")
    import csv

    with path.open(newline="") as handle:
        return {row["file"].removesuffix(".ply"): row for row in csv.DictReader(handle)}


def hemisphere(rings: int = 128, segments: int = 256) -> trimesh.Trimesh:
    """The upper unit hemisphere (z >= 0), open at the equator, normals outward.

    A latitude-longitude grid: the pole is a ring of coincident vertices, so the
    faces touching it have zero area (molaR's cleaning drops them).
    """
    theta = np.linspace(0.0, np.pi / 2, rings + 1)  # from +z
    phi = np.linspace(0.0, 2 * np.pi, segments + 1)[:-1]
    t, p = np.meshgrid(theta, phi, indexing="ij")
    vertices = np.column_stack(
        [(np.sin(t) * np.cos(p)).ravel(), (np.sin(t) * np.sin(p)).ravel(), np.cos(t).ravel()]
    )
    idx = np.arange(len(vertices)).reshape(rings + 1, segments)
    nxt = np.roll(idx, -1, axis=1)
    a, b, c, d = idx[:-1], nxt[:-1], idx[1:], nxt[1:]
    faces = np.concatenate(
        [
            np.column_stack([a.ravel(), c.ravel(), d.ravel()]),
            np.column_stack([a.ravel(), d.ravel(), b.ravel()]),
        ]
    )
    return trimesh.Trimesh(vertices, faces, process=False)


# ---------------------------------------------------------------------------
# pictures: what a composed picture's layout must satisfy


def capture_layouts(monkeypatch, module) -> list:
    """Record every layout `module` (a figures module) saves, saving it as usual."""
    layouts = []
    original = module.save

    def spy(layout, path, **options):
        layouts.append(layout)
        original(layout, path, **options)

    monkeypatch.setattr(module, "save", spy)
    return layouts


def _overlap(a, b) -> bool:
    return a.x0 < b.x1 and b.x0 < a.x1 and a.y0 < b.y1 and b.y0 < a.y1


def layout_problems(layout) -> list[str]:
    """Texts that touch another text, a 3D view, a legend's drawing or the picture's edge."""
    figure = layout.figure
    renderer = figure.canvas.get_renderer()
    width, height = figure.bbox.width, figure.bbox.height
    texts = [(t.get_text(), t.get_window_extent(renderer)) for t in layout.texts if t.get_text()]
    drawings = [("axes", a.get_window_extent(renderer)) for a in figure.axes]
    drawings += [("patch", p.get_window_extent(renderer)) for p in figure.artists]
    problems = []
    for i, (text, box) in enumerate(texts):
        if box.x0 < 0 or box.y0 < 0 or box.x1 > width or box.y1 > height:
            problems.append(f"{text!r} leaves the picture: {box}")
        for other, other_box in texts[i + 1 :]:
            if _overlap(box, other_box):
                problems.append(f"{text!r} overlaps {other!r}")
        for kind, other_box in drawings:
            if _overlap(box, other_box):
                problems.append(f"{text!r} overlaps a {kind} at {other_box}")
    return problems


def view_region(layout, image: np.ndarray, index: int = 0) -> np.ndarray:
    """The pixels of the saved picture `image` inside the layout's 3D view `index`."""
    box = layout.views[index].get_window_extent(layout.figure.canvas.get_renderer())
    height = image.shape[0]
    rows = slice(round(height - box.y1), round(height - box.y0))
    return image[rows, round(box.x0) : round(box.x1)]


def meshes_outside_their_frames(layout, image: np.ndarray, margin: float = 0.02) -> list[str]:
    """Views whose mesh pixels (not white, or not transparent) come within `margin` of the edge.

    `image` is the saved PNG as an (h, w, 3 or 4) array.
    """
    renderer = layout.figure.canvas.get_renderer()
    height = image.shape[0]
    problems = []
    for index, axes in enumerate(layout.views):
        box = axes.get_window_extent(renderer)
        rows = slice(round(height - box.y1), round(height - box.y0))
        cols = slice(round(box.x0), round(box.x1))
        region = image[rows, cols]
        if image.shape[2] == 4 and (image[..., 3] < 255).any():  # a transparent background
            mesh = region[..., 3] > 0
        else:
            mesh = (region[..., :3] < 250).any(axis=2)
        if mesh.sum() < 100:
            problems.append(f"view {index}: no mesh drawn")
            continue
        r, c = np.nonzero(mesh)
        h, w = mesh.shape
        inside = (
            r.min() >= margin * h
            and c.min() >= margin * w
            and r.max() < (1 - margin) * h
            and c.max() < (1 - margin) * w
        )
        if not inside:
            problems.append(
                f"view {index}: mesh rows {r.min()}-{r.max()} of {h}, "
                f"cols {c.min()}-{c.max()} of {w}"
            )
    return problems


#: Appended to a copy of a page: marks in the DOM every text box whose content is wider
#: than the box, or that reaches outside its panel or the window.
OVERFLOW_CHECK = """
<script>
(function () {
  const bad = [];
  const inside = function (a, b) {
    return a.left >= b.left - 1 && a.right <= b.right + 1 && a.top >= b.top - 1 &&
      a.bottom <= b.bottom + 1;
  };
  const page = { left: 0, top: 0, right: window.innerWidth, bottom: window.innerHeight };
  document.querySelectorAll(".text, #rule, #note, #ticks span, .entry").forEach(function (el) {
    const box = el.getBoundingClientRect();
    const cell = el.closest(".cell");
    const wide = el.scrollWidth > el.clientWidth + 1 && el.clientWidth > 0;
    if (wide) bad.push("wide:" + el.textContent);
    if (cell && !inside(box, cell.getBoundingClientRect())) bad.push("cell:" + el.textContent);
    if (!inside(box, page)) bad.push("page:" + el.textContent);
  });
  document.body.setAttribute("data-checked", String(document.querySelectorAll(".text").length));
  document.body.setAttribute("data-overflow", JSON.stringify(bad));
})();
</script>
"""
