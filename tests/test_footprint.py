"""doolkit's footprint area (area2d): doolkit's numbers, hand-made hulls, the JavaScript ring."""

from __future__ import annotations

import csv
import json
import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
import trimesh

from conftest import MESHES, REFERENCE, ROBUSTNESS_SET, shared_mesh
from dentopo.topography import (
    HULLS,
    FootprintResult,
    UnitWarning,
    concave_hull,
    convex_hull,
    footprint_area,
    prepare_surface,
)
from dentopo.topography.footprint import _concaveman
from dentopo.topography.footprint._doolkit import json_digits, shoelace, unique_xy
from dentopo.topography.footprint._jsmath import js_exp, js_log


def concaveman_ring(points, concavity, length_threshold):
    """The compiled concaveman's closed ring (its first index repeated at the end)."""
    points = np.ascontiguousarray(points, dtype=np.float64)
    out = np.empty(2 * len(points) + 3, dtype=np.int64)
    return out[: _concaveman.concaveman_ring(points, concavity, length_threshold, out)]


PARITY = 1e-9


@pytest.fixture(scope="module")
def doolkit_rows():
    path = REFERENCE / "doolkit_1.42.2_topography.csv"
    if not path.exists():
        pytest.skip(f"doolkit reference values not found at {path} (expected beside the checkout)")
    with path.open(newline="") as handle:
        return {row["file"].removesuffix(".ply"): row for row in csv.DictReader(handle)}


def l_grid(h: float) -> np.ndarray:
    """Grid points of spacing h filling the L = [0,2]x[0,1] union [0,1]x[0,2] (area 3)."""
    k = round(2 / h)
    return np.array(
        [[i * h, j * h] for i in range(k + 1) for j in range(k + 1) if min(i, j) * h <= 1 + 1e-9]
    )


# doolkit's own numbers ----------------------------------------------------------------


@pytest.mark.parametrize("name", ROBUSTNESS_SET)
def test_matches_doolkit(name, doolkit_rows):
    row = doolkit_rows[name]
    surface = prepare_surface(shared_mesh(name))
    concave = footprint_area(surface, orient="as-is")  # doolkit's: as the crown lies
    convex = footprint_area(surface, hull="convex", orient="as-is")
    assert concave.area == pytest.approx(float(row["area2d"]), rel=PARITY)
    assert convex.area == pytest.approx(float(row["area2d_convex"]), rel=PARITY)
    assert concave.to_dict() == {"area2d": concave.area}
    assert convex.to_dict() == {"area2d_convex": convex.area}
    assert concave.vertices == int(row["n_vertices"]) and concave.faces == int(row["n_faces"])


# hulls that can be drawn by hand ------------------------------------------------------


def test_square_with_an_interior_point_is_the_square():
    square = [(0, 0), (1, 0), (1, 1), (0, 1), (0.5, 0.5)]
    ring = concave_hull(square)
    assert sorted(ring.tolist()) == [0, 1, 2, 3]
    assert shoelace(np.array(square, float)[ring]) == 1.0
    assert sorted(convex_hull(square).tolist()) == [0, 1, 2, 3]


@pytest.mark.parametrize("h", [0.1, 0.05])
def test_l_shape_is_its_outline(h):
    points = l_grid(h)
    ring = points[concave_hull(points)]
    assert shoelace(ring) == pytest.approx(3.0, rel=1e-12)
    # every ring point lies on the L's boundary
    x, y = ring.T
    on_edge = np.isclose(x, 0) | np.isclose(y, 0) | np.isclose(x, 2) | np.isclose(y, 2)
    on_edge |= (np.isclose(x, 1) & (y >= 1 - 1e-9)) | (np.isclose(y, 1) & (x >= 1 - 1e-9))
    assert on_edge.all()
    # the convex hull bridges the notch: area 3.5
    assert shoelace(points[convex_hull(points)]) == pytest.approx(3.5, rel=1e-12)


def test_collinear_points_have_no_area():
    points = np.column_stack([np.arange(20.0), 2 * np.arange(20.0)])[::-1]
    for ring in (concave_hull(points), convex_hull(points)):
        assert shoelace(points[ring]) == 0.0
    assert sorted(convex_hull(points).tolist()) == [0, 19]  # only the two ends


def test_few_points():
    assert sorted(concave_hull([(0, 0), (1, 0), (0, 1)]).tolist()) == [0, 1, 2]
    assert len(concave_hull([(2.0, 3.0)])) == 2  # concaveman's degenerate ring: the point twice
    assert convex_hull([(2.0, 3.0)]).tolist() == [0]


def test_ring_is_clockwise_and_closed_by_concaveman():
    rng = np.random.default_rng(1)
    points = rng.random((500, 2))
    closed = concaveman_ring(points, 2.0, 0.0)
    assert closed[0] == closed[-1]
    ring = points[concave_hull(points)]
    signed = np.sum(ring[:, 0] * np.roll(ring[:, 1], -1) - np.roll(ring[:, 0], -1) * ring[:, 1])
    assert signed < 0
    assert shoelace(ring) <= shoelace(points[convex_hull(points)])


def test_box_mesh():
    box = trimesh.creation.box(extents=(2.0, 3.0, 1.0))
    for hull in ("concave", "convex"):
        result = footprint_area(box, hull=hull)
        assert isinstance(result, FootprintResult)
        assert result.area == 6.0
        assert result.points == 4 and result.hull == hull


def test_concavity_and_threshold():
    points = l_grid(0.1)
    convex = shoelace(points[convex_hull(points)])
    assert shoelace(points[concave_hull(points, concavity=np.inf)]) == pytest.approx(convex)
    # edges shorter than the threshold are not bent: a long threshold keeps the convex hull
    assert shoelace(points[concave_hull(points, length_threshold=10.0)]) == pytest.approx(convex)


# jsonlite's 4 decimals ----------------------------------------------------------------


def test_json_digits_is_sprintf_on_ordinary_values():
    rng = np.random.default_rng(2)
    values = rng.random(5000) * 30
    expected = np.array([float(f"{v:.4f}") for v in values])
    assert np.array_equal(json_digits(values), expected)


def test_json_digits_edge_cases():
    cases = {
        0.0: 0.0,
        1e-5: 1e-5,  # at or below 1e-5: sprintf("%.5g"), five significant digits
        2.5e-6: 2.5e-6,
        3e-5: 0.0,  # above 1e-5: four decimals
        6e-5: 1e-4,
        0.99995: 0.1,  # jsonlite's half-way 9999 + 1 without the carry: written "0.1"
    }
    for value, expected in cases.items():
        assert json_digits(np.array([value]))[0] == expected, value


def test_fdlibm_log_exp_on_known_values():
    assert js_log(16.0) == np.log(16.0)
    assert js_exp(0.0) == 1.0
    for n in (601.0, 4050.0, 10080.0, 65536.0, 1e6):
        assert js_log(n) == pytest.approx(np.log(n), rel=1e-15)
        assert js_exp(2 * js_log(n) / 3) == pytest.approx(n ** (2 / 3), rel=1e-14)


# invariances, inputs, parameters ------------------------------------------------------


def crown():
    from dentopo.samples import tooth

    mesh = tooth(rings=24)
    rng = np.random.default_rng(3)
    # an irregular outline, coordinates on a 2**-20 grid so translations stay exact
    vertices = np.round((mesh.vertices + rng.normal(0, 0.01, mesh.vertices.shape)) * 2**20) / 2**20
    return vertices, mesh.faces


def test_translation_and_vertex_order():
    vertices, faces = crown()
    base = {hull: footprint_area((vertices, faces), hull=hull).area for hull in HULLS}
    moved = (vertices + np.array([3.0, -5.0, 7.0]), faces)  # exact: the shift removes it
    assert footprint_area(moved).area == base["concave"]
    assert footprint_area(moved, hull="convex").area == pytest.approx(base["convex"], rel=1e-13)
    perm = np.random.default_rng(4).permutation(len(vertices))
    inverse = np.empty_like(perm)
    inverse[perm] = np.arange(len(perm))
    shuffled = (vertices[perm], inverse[faces])
    assert footprint_area(shuffled, hull="convex").area == pytest.approx(base["convex"], rel=1e-13)


def test_concave_ring_does_not_depend_on_point_order_without_ties():
    """concaveman depends on the input order only where distances tie exactly.

    (On 4-decimal coordinates ties do happen, e.g. two points at the same
    height above an axis-parallel edge: doolkit's concave area then depends on
    the vertex order too, and so does this one, in the same way.)
    """
    rng = np.random.default_rng(6)
    points = rng.random((3000, 2))
    ring = set(concave_hull(points).tolist())
    for _ in range(3):
        perm = rng.permutation(len(points))
        assert {int(perm[i]) for i in concave_hull(points[perm])} == ring


def test_shared_crown_vertex_order():
    mesh = trimesh.load(shared_mesh("normal"), process=False)
    perm = np.random.default_rng(7).permutation(len(mesh.vertices))
    inverse = np.empty_like(perm)
    inverse[perm] = np.arange(len(perm))
    shuffled = (mesh.vertices[perm], inverse[mesh.faces])
    assert footprint_area(shuffled).area == footprint_area(mesh).area


def test_ring_in_mesh_units():
    vertices, faces = crown()
    result = footprint_area((vertices, faces))
    assert np.array_equal(result.ring, vertices[result.ring_vertices, :2])
    # the area is drawn on 4-decimal coordinates: the ring's own area is within the rounding
    perimeter = np.sum(np.linalg.norm(np.diff(result.ring, axis=0, append=result.ring[:1]), axis=1))
    assert abs(shoelace(result.ring) - result.area) <= 1e-4 * perimeter
    assert not result.ring.flags.writeable


def test_surface_input_and_unmodified_input():
    vertices, faces = crown()
    keep = vertices.copy(), faces.copy()
    direct = footprint_area((vertices, faces))
    surface = prepare_surface((vertices, faces))
    assert footprint_area(surface).area == direct.area
    assert footprint_area(surface) is footprint_area(surface)  # kept with the surface
    assert np.array_equal(vertices, keep[0]) and np.array_equal(faces, keep[1])


def test_orient_auto_mirrors_the_footprint():
    vertices, faces = crown()
    down = (vertices * np.array([-1.0, 1.0, -1.0]), faces[:, ::-1])  # turned to -z
    turned = footprint_area(down, orient="auto")
    assert turned.orientation is not None and turned.orientation.turned
    assert turned.area == pytest.approx(footprint_area((vertices, faces)).area, rel=1e-3)
    assert footprint_area(down) == turned  # auto is the default
    assert footprint_area(down, orient="as-is").orientation is None


def test_unique_xy_keeps_first_occurrences():
    vertices = np.array([[0, 0, 1], [1, 0, 0], [0, 0, 5], [-0.0, 1, 0], [0.0, 1, 2]], float)
    xy, first = unique_xy(vertices)
    assert first.tolist() == [0, 1, 3]
    assert xy.tolist() == [[0, 0], [1, 0], [0, 1]]


@pytest.mark.parametrize(
    ("kwargs", "error"),
    [
        ({"hull": "alpha"}, ValueError),
        ({"hull": 2}, TypeError),
        ({"orient": "up"}, ValueError),
    ],
)
def test_bad_parameters(kwargs, error):
    with pytest.raises(error):
        footprint_area(trimesh.creation.box(), **kwargs)


@pytest.mark.parametrize(
    ("points", "kwargs", "error"),
    [
        ([], {}, ValueError),
        ([(0, 0, 0)], {}, ValueError),
        ([(0, np.nan)], {}, ValueError),
        ("abc", {}, TypeError),
        ([(0, 0)], {"concavity": -1}, ValueError),
        ([(0, 0)], {"concavity": np.nan}, ValueError),
        ([(0, 0)], {"concavity": "2"}, TypeError),
        ([(0, 0)], {"length_threshold": -0.5}, ValueError),
    ],
)
def test_bad_points(points, kwargs, error):
    with pytest.raises(error):
        concave_hull(points, **kwargs)


def test_large_crown_is_fast_enough():
    """No quadratic blow-up: 200k points in well under a few seconds."""
    import time

    from dentopo.samples import tooth

    mesh = tooth(rings=256)
    with pytest.warns(UnitWarning):  # a piece 0.01 across: doolkit's rounding matters, said
        footprint_area((mesh.vertices[:100], mesh.faces[:10]))  # compiled already
    start = time.perf_counter()
    result = footprint_area(mesh)
    assert time.perf_counter() - start < 10.0
    assert result.points > 190_000
    assert result.area == pytest.approx(footprint_area(mesh, hull="convex").area, rel=1e-3)


# the JavaScript itself, where node and concaveman 1.1 are installed --------------------

_NODE_SCRIPT = r"""
const dir = process.env.CONCAVEMAN_DIR;
const path = dir ? require('path').join(dir, 'node_modules', 'concaveman') : 'concaveman';
const version = require(path + '/package.json').version;
const concaveman = require(path);
const cases = JSON.parse(require('fs').readFileSync(0, 'utf8'));
const rings = cases.map(pts => {
  const index = new Map(pts.map((p, i) => [p, i]));
  return concaveman(pts).map(p => index.get(p));
});
process.stdout.write(JSON.stringify({version, rings}));
"""


def run_concaveman_js(cases: list[np.ndarray]) -> list[list[int]]:
    """concaveman's rings from node, or skip saying what is missing."""
    node = shutil.which("node")
    if node is None:
        pytest.skip("node is not installed: the JavaScript concaveman cannot be run")
    env = dict(os.environ)
    where = os.environ.get("DENTOPO_CONCAVEMAN_DIR")
    if where:
        env["CONCAVEMAN_DIR"] = where
    payload = "[" + ",".join(json.dumps(np.asarray(c, float).tolist()) for c in cases) + "]"
    out = subprocess.run(
        [node, "-e", _NODE_SCRIPT], input=payload, capture_output=True, text=True, env=env
    )
    if out.returncode != 0:
        lines = out.stderr.strip().splitlines() or ["(no message)"]
        reason = next((line for line in lines if "Error" in line), lines[0])
        pytest.skip(
            "the npm package concaveman is not reachable from node (install it with "
            "`npm install concaveman@1.1.1` in a folder and set DENTOPO_CONCAVEMAN_DIR to it): "
            + reason.strip()
        )
    answer = json.loads(out.stdout)
    if not answer["version"].startswith("1.1."):
        pytest.skip(f"concaveman {answer['version']} found; doolkit's is the 1.1 series")
    return answer["rings"]


def doolkit_points(path: Path, mirror: bool) -> np.ndarray:
    xy, _ = unique_xy(prepare_surface(path).vertices)
    if mirror:  # the crown turned upside down about y
        xy = xy * np.array([-1.0, 1.0])
    return json_digits(xy - xy.min(axis=0))


def test_same_ring_as_the_javascript():
    meshes = sorted(MESHES.glob("*.ply")) if MESHES.exists() else []
    cases = [doolkit_points(path, mirror) for path in meshes for mirror in (False, True)]
    rng = np.random.default_rng(5)
    grid = np.array([[i, j] for i in range(30) for j in range(30)], float) * 0.1
    cases += [
        grid,  # equal distances everywhere
        grid[rng.permutation(len(grid))],
        np.vstack([grid, grid[rng.choice(len(grid), 100)]]),  # repeated points
        l_grid(0.1),
        np.column_stack([np.arange(40.0), 3 * np.arange(40.0)])[rng.permutation(40)],
        np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]),
        np.round(rng.random((3000, 2)), 2),
        rng.random((5000, 2)),
    ]
    expected = run_concaveman_js(cases)
    for points, ring in zip(cases, expected, strict=True):
        assert concaveman_ring(points, 2.0, 0.0).tolist() == ring
