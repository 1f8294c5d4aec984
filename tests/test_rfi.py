"""Relief index as molaR computes it: molaR's own numbers, analytic shapes, the hull, the walk."""

from __future__ import annotations

import csv

import numpy as np
import pytest
import trimesh
from scipy.spatial import ConvexHull, Delaunay

from conftest import REFERENCE, ROBUSTNESS_SET, shared_mesh
from dentopo.topography import (
    RFI_FIELDS,
    AlphaAdjustmentError,
    FootprintError,
    FootprintWarning,
    RFIResult,
    molar_scale,
    prepare_surface,
    rfi,
)
from dentopo.topography.footprint._alphahull import (
    FAN_CLEAR,
    FAN_INSIDE,
    FAN_UNDEFINED,
    AlphaHull,
    fan_test,
)
from dentopo.topography.relief import _molar as _rfi
from dentopo.topography.relief._molar import MAX_EVALUATIONS, first_occurrence, walk

#: The reference crowns point to -z, as molaR measured them: that warning is expected here.
pytestmark = [
    pytest.mark.filterwarnings("ignore:the crown points to -z:UserWarning"),
    # planes and single faces are flat: no up or down (tests/test_orientation.py)
    pytest.mark.filterwarnings("ignore:the surface is flat:UserWarning"),
]

PARITY = 1e-12


@pytest.fixture(scope="module")
def molar_rows():
    path = REFERENCE / "molaR_6.0_topography.csv"
    if not path.exists():
        pytest.skip(f"molaR reference values not found at {path} (expected beside the checkout)")
    with path.open(newline="") as handle:
        return {row["file"].removesuffix(".ply"): row for row in csv.DictReader(handle)}


def number(text: str) -> float | None:
    return None if text == "NA" else float(text)


def polar_mesh(radius_at, height_at, rings: int = 40, sectors: int = 160) -> trimesh.Trimesh:
    """A surface of revolution over the unit disc, from its apex (ring 0) to its rim.

    The sectors are turned by an irrational angle so that no two vertices share
    an x or a y value (molaR's duplicate check would drop them).
    """
    t = np.linspace(0, 1, rings + 1)[1:]
    phi = np.linspace(0, 2 * np.pi, sectors, endpoint=False) + 0.1234567
    r, p = np.meshgrid(radius_at(t), phi, indexing="ij")
    z = np.repeat(height_at(t)[:, None], sectors, axis=1)
    ring = np.column_stack(
        [r.ravel() * np.cos(p.ravel()), r.ravel() * np.sin(p.ravel()), z.ravel()]
    )
    vertices = np.vstack([[0.0, 0.0, height_at(np.zeros(1))[0]], ring])
    idx = 1 + np.arange(rings * sectors).reshape(rings, sectors)
    nxt = np.roll(idx, -1, axis=1)
    cap = np.column_stack([np.zeros(sectors, dtype=int), idx[0], nxt[0]])
    a, b, c, d = idx[:-1].ravel(), nxt[:-1].ravel(), idx[1:].ravel(), nxt[1:].ravel()
    faces = np.vstack([cap, np.column_stack([a, c, d]), np.column_stack([a, d, b])])
    return trimesh.Trimesh(vertices, faces, process=False)


def hemisphere() -> trimesh.Trimesh:
    return polar_mesh(lambda t: np.sin(t * np.pi / 2), lambda t: np.cos(t * np.pi / 2))


def cone(height: float) -> trimesh.Trimesh:
    return polar_mesh(lambda t: t, lambda t: height * (1 - t))


def flat_disc() -> trimesh.Trimesh:
    rng = np.random.default_rng(0)
    points = rng.uniform(-1, 1, (4000, 2))
    points = points[np.hypot(*points.T) < 1]
    faces = Delaunay(points).simplices
    return trimesh.Trimesh(np.column_stack([points, np.zeros(len(points))]), faces, process=False)


def inside(polygon: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Even-odd test of points against a closed polygon."""
    x, y = points[:, :1], points[:, 1:2]
    ax, ay = polygon[:, 0], polygon[:, 1]
    bx, by = np.roll(ax, -1), np.roll(ay, -1)
    with np.errstate(divide="ignore", invalid="ignore"):
        crossing = ((ay > y) != (by > y)) & (x < (bx - ax) * (y - ay) / (by - ay) + ax)
    return crossing.sum(axis=1) % 2 == 1


def polygon_mesh(polygon, spacing: float = 0.04, seed: int = 1) -> trimesh.Trimesh:
    """A flat mesh filling a polygon: points along its sides and a jittered grid inside.

    The positions are random enough that no two vertices share an x or a y
    value (molaR's duplicate check would drop them).
    """
    rng = np.random.default_rng(seed)
    polygon = np.asarray(polygon, dtype=float)
    rim = []
    for a, b in zip(polygon, np.roll(polygon, -1, axis=0), strict=True):
        count = max(int(np.ceil(np.hypot(*(b - a)) / spacing)), 1)
        t = (np.arange(count) + rng.uniform(-0.2, 0.2, count)) / count
        t[0] = 0.0
        rim.append(a + t[:, None] * (b - a))
    rim = np.vstack(rim)
    low, high = polygon.min(axis=0), polygon.max(axis=0)
    gx, gy = np.meshgrid(np.arange(low[0], high[0], spacing), np.arange(low[1], high[1], spacing))
    grid = np.column_stack([gx.ravel(), gy.ravel()])
    grid = grid + rng.uniform(-0.3, 0.3, grid.shape) * spacing
    grid = grid[inside(polygon, grid)]
    gap = np.hypot(*(grid[:, None] - rim[None]).transpose(2, 0, 1)).min(axis=1)
    points = np.vstack([rim, grid[gap > 0.5 * spacing]])
    triangles = Delaunay(points).simplices
    triangles = triangles[inside(polygon, points[triangles].mean(axis=1))]
    return trimesh.Trimesh(
        np.column_stack([points, np.zeros(len(points))]), triangles, process=False
    )


def scaled_alpha(mesh, spacings: float, spacing: float = 0.04) -> float:
    """An alpha of so many point spacings, in molaR's rescaled units."""
    return spacings * spacing * molar_scale(np.asarray(mesh.vertices))


#: A five-pointed star (star-shaped from its centre, not convex).
STAR = np.array(
    [
        [r * np.cos(t), r * np.sin(t)]
        for t, r in zip(
            np.linspace(0, 2 * np.pi, 10, endpoint=False) + 0.1, [1, 0.45] * 5, strict=True
        )
    ]
)
#: A square with a slot from its right side, above its centre: from the centre
#: the slot hides part of its upper wall, so the footprint is not star-shaped.
SLOT = np.array(
    [[1, -1], [1, 0.2], [0.1, 0.2], [0.1, 0.5], [1, 0.5], [1, 1], [-1, 1], [-1, -1]], dtype=float
)
#: Two lobes touching at the origin by sharp tips (the larger one holds the mean).
PINCH = np.array(
    [
        [0, 0], [-1.5, 0.4], [-3, 0.6], [-3, -0.6], [-1.5, -0.4],
        [0, 0], [0.8, -0.2], [1.4, -0.4], [1.4, 0.4], [0.8, 0.2],
    ],
    dtype=float,
)  # fmt: skip


# molaR's own numbers ------------------------------------------------------------------


@pytest.mark.parametrize("name", ROBUSTNESS_SET)
def test_matches_molar_at_default_alpha(name, molar_rows):
    row = molar_rows[name]
    mesh = shared_mesh(name)
    if row["RFI"] == "NA":
        # molaR stopped with "alpha adjustment required" (S)
        with pytest.raises(AlphaAdjustmentError, match=r"find_alpha=True.*") as caught:
            rfi(mesh)
        assert "alpha = 0.075" in str(caught.value)
        return
    result = rfi(mesh)
    assert result.warning is None
    for key, column in (("rfi", "RFI"), ("area_3d", "area_3d"), ("area_2d", "area_2d")):
        assert getattr(result, key) == pytest.approx(number(row[column]), rel=PARITY), key
    assert result.alpha == number(row["alpha"])


@pytest.mark.parametrize("name", ROBUSTNESS_SET)
def test_matches_molar_find_alpha(name, molar_rows):
    row = molar_rows[name]
    result = rfi(shared_mesh(name), find_alpha=True, orient="as-is")  # molaR's pose
    # the same floating-point number as molaR's walk, artefacts included
    assert result.alpha == float(row["alpha_found"])
    assert result.rfi == pytest.approx(float(row["RFI_findalpha"]), rel=PARITY)
    assert result.find_alpha is True and result.warning is None


# molaR's walk ---------------------------------------------------------------------------


def test_walk_steps_are_repeated_double_operations():
    # smooth's path: OK down by 0.005 to 0.04, S at 0.035 and 0.036 (each up 0.01
    # past the last success, then back 0.009), F at 0.037 .. 0.039, OK 0.001 above
    # the last failure: 0.040000000000000008, although 0.04 (an OK) is smaller
    def verdict(a):
        if a >= 0.04 - 1e-9:
            return "OK"
        return "S" if a < 0.0365 else "F"

    found, steps = walk(0.075, verdict)
    down = [0.075]
    for _ in range(8):
        down.append(down[-1] - 0.005)
    s1 = down[-1]
    s2 = s1 + 0.01 - 0.009
    f1 = s2 + 0.01 - 0.009
    f2 = f1 + 0.001
    f3 = f2 + 0.001
    accepted = f3 + 0.001
    assert [a for a, _ in steps] == [*down, s2, f1, f2, f3, accepted]
    assert "".join(v[0] for _, v in steps) == "O" * 8 + "SSFFFO"
    assert found == accepted == 0.040000000000000008
    assert found != down[7] and verdict(down[7]) == "OK"


def test_walk_climbs_back_after_an_s_below_a_success():
    # OK at 0.075, S at 0.07: up 0.01 past the last success, back 0.009 to
    # 0.071 (F), 0.072 .. 0.074 (F), then OK 0.001 above the last failure
    def verdict(a):
        return "OK" if a >= 0.075 - 1e-12 else ("S" if a < 0.0705 else "F")

    found, steps = walk(0.075, verdict)
    assert found is not None and abs(found - 0.075) < 1e-12
    assert "".join(v[0] for _, v in steps) == "OSFFFFO"


def test_walk_never_tries_alpha_below_zero():
    # 0.003 - 0.005 is below the last failure (none: 0), so 0 + 0.001 is next
    found, steps = walk(0.003, lambda a: "OK")
    assert steps == [(0.003, "OK"), (0.001, "OK")] and found == 0.001


def test_walk_gives_up_after_99_hulls():
    found, steps = walk(0.075, lambda a: "F")
    assert found is None and len(steps) == MAX_EVALUATIONS == 99
    found, steps = walk(0.075, lambda a: "S")
    assert found is None and len(steps) == 99

    def broken(a):
        raise FootprintError("R stops")

    found, steps = walk(0.075, broken)
    assert found is None and steps == [(0.075, "error")]


def test_failed_walk_falls_back_to_the_start_alpha_with_a_warning():
    # the slot keeps F from 0.12 past the 99th hull: molaR measures at 0.12
    mesh = polygon_mesh(SLOT)
    with pytest.warns(FootprintWarning) as caught:
        result = rfi(mesh, alpha=0.12, find_alpha=True)
    assert result.alpha == 0.12 and result.find_alpha is True
    assert "find_alpha failed" in result.warning and "over-estimated" in result.warning
    assert [str(w.message) for w in caught if w.category is FootprintWarning] == [result.warning]
    with pytest.warns(FootprintWarning):
        fixed = rfi(mesh, alpha=0.12)
    assert (fixed.rfi, fixed.area_2d) == (result.rfi, result.area_2d)


def test_failed_walk_with_s_at_the_start_needs_adjustment(monkeypatch):
    mesh = cone(1.0)
    start = rfi(mesh, find_alpha=True).alpha  # OK there
    monkeypatch.setattr(_rfi._Footprint, "verdict", lambda self, a: "S")
    with pytest.raises(AlphaAdjustmentError, match="search from there failed"):
        rfi(mesh, alpha=1e-4, find_alpha=True)
    # from a start alpha that is OK on its own: the number, with the warning
    with pytest.warns(FootprintWarning, match="find_alpha failed"):
        result = rfi(mesh, alpha=start, find_alpha=True)
    assert result.alpha == start and result.rfi == rfi(mesh, alpha=start).rfi


# analytic shapes ----------------------------------------------------------------------


def test_flat_disc_has_zero_relief():
    result = rfi(flat_disc(), find_alpha=True)
    assert abs(result.rfi) < 0.01
    # with a radius beyond every circumradius the outline is the convex hull,
    # which the triangulation covers exactly: 3D and 2D areas agree
    hull = rfi(flat_disc(), alpha=1e6)
    assert hull.area_2d == pytest.approx(hull.area_3d, rel=1e-6)
    assert abs(hull.rfi) < 1e-6


def test_hemisphere_relief_is_log_root_two():
    # area_3d = 2 pi r^2 and area_2d = pi r^2: RFI = ln(sqrt 2), less the
    # polygon error of the faceted hemisphere and its 160-gon outline
    result = rfi(hemisphere(), find_alpha=True)
    assert result.rfi == pytest.approx(0.5 * np.log(2), abs=2e-3)
    assert result.area_3d == pytest.approx(2 * np.pi, rel=2e-3)
    assert result.area_2d == pytest.approx(np.pi, rel=2e-3)


@pytest.mark.parametrize("height", [0.5, 1.0, 3.0])
def test_cone_relief(height):
    # lateral area pi r sqrt(r^2 + h^2) over the base pi r^2
    result = rfi(cone(height), find_alpha=True)
    expected = 0.5 * np.log(np.hypot(1.0, height))
    assert result.rfi == pytest.approx(expected, abs=2e-3)


# the hull ------------------------------------------------------------------------------


def test_arcs_are_the_edges_with_an_empty_disc_on_one_side_only():
    """An arc's edge has an empty radius-alpha disc through its ends on its left only."""
    rng = np.random.default_rng(3)
    points = rng.random((40, 2))
    hull = AlphaHull(points)
    i, j = np.triu_indices(len(points), 1)
    p, q = points[i], points[j]
    mid, half = (p + q) / 2, np.hypot(*(q - p).T) / 2
    left = np.column_stack([-(q - p)[:, 1], (q - p)[:, 0]]) / (2 * half[:, None])
    for alpha in (0.06, 0.1, 0.2, 0.5, 5.0):
        reach = np.sqrt(np.maximum(alpha**2 - half**2, 0))[:, None]
        empty = []
        for side in (1, -1):
            centre = mid + side * reach * left
            gap = np.hypot(*(points[None] - centre[:, None]).transpose(2, 0, 1))
            empty.append(~(gap < alpha - 1e-12).any(axis=1) & (half <= alpha))
        one, other = empty[0] & ~empty[1], empty[1] & ~empty[0]
        expected = {(a, b) for a, b in zip(i[one], j[one], strict=True)}
        expected |= {(b, a) for a, b in zip(i[other], j[other], strict=True)}
        arcs = hull.arcs(alpha)
        found = set(
            zip(arcs.start[: arcs.arcs].tolist(), arcs.end[: arcs.arcs].tolist(), strict=True)
        )
        n = len(points)
        untrimmed = {(a, b) for a, b in found if a < n and b < n}
        assert untrimmed <= expected, alpha
        assert arcs.arcs == len(expected), alpha
        # each arc's centre is at distance alpha from its untrimmed ends, on the free side
        for arc in range(arcs.arcs):
            for end in (arcs.start[arc], arcs.end[arc]):
                if end < n:
                    assert np.hypot(*(arcs.centre[arc] - points[end])) == pytest.approx(alpha)


def test_below_the_spacing_every_point_is_a_degenerate_arc():
    points = np.random.default_rng(4).random((30, 2))
    arcs = AlphaHull(points).arcs(1e-4)
    assert arcs.arcs == 0 and arcs.structural
    assert arcs.start.tolist() == arcs.end.tolist() == list(range(30))


def test_convex_footprint_is_the_convex_hull_for_every_large_alpha():
    mesh = flat_disc()
    flat = mesh.vertices[:, :2] - mesh.vertices[:, :2].mean(axis=0)
    area = ConvexHull(flat).volume
    hull = AlphaHull(flat * molar_scale(mesh.vertices))
    largest = hull.radius[np.isfinite(hull.radius)].max()
    for alpha in (1.01 * largest, 10 * largest, 1e6):
        result = rfi(mesh, alpha=alpha)
        assert result.warning is None
        assert result.area_2d == pytest.approx(area, rel=1e-12)
        assert len(result.footprint) == len(ConvexHull(flat).vertices)


def test_star_shaped_footprint_passes_the_fan_test():
    mesh = polygon_mesh(STAR)
    for spacings in (1.5, 2, 3):
        result = rfi(mesh, alpha=scaled_alpha(mesh, spacings))  # no warning
        assert result.warning is None
        assert result.area_2d == pytest.approx(mesh.area, rel=0.02)


def test_notched_footprint_fails_the_fan_test_with_a_warning():
    mesh = polygon_mesh(SLOT)
    for spacings in (1.5, 2, 3):
        alpha = scaled_alpha(mesh, spacings)
        with pytest.warns(FootprintWarning, match="over-estimated") as caught:
            result = rfi(mesh, alpha=alpha)
        (message,) = [str(w.message) for w in caught if w.category is FootprintWarning]
        assert "not star-shaped from the vertices' mean" in message
        assert result.warning == message and result.alpha == alpha
        # the number is kept: the fan covers part of the footprint twice
        assert np.isfinite(result.rfi) and result.area_2d > mesh.area
    # wide discs close the slot: the outline is star-shaped again
    assert rfi(mesh, alpha=scaled_alpha(mesh, 5)).warning is None


def test_pinched_footprint_is_trimmed_at_the_pinch():
    mesh = polygon_mesh(PINCH)
    surface = prepare_surface(mesh)
    scale = molar_scale(surface.vertices)
    footprint = _rfi._Footprint(surface.vertices)
    for spacings in (1.0, 1.3, 1.6):
        arcs = footprint.arcs(scaled_alpha(mesh, spacings))
        # both wedges at the pinch are cut off by the two discs over them:
        # two points of the hull's own near it, and the pinch on no arc (S)
        own = arcs.xy[footprint.hull.n :] / scale + footprint.mean[:2]
        assert (np.hypot(*own.T) < 2 * 0.04).sum() == 2
        assert arcs.structural
        pinch = footprint.hull.points[arcs.isolated] / scale + footprint.mean[:2]
        assert np.hypot(*pinch) < 1e-12
        with pytest.raises(AlphaAdjustmentError, match="ends no arc"):
            rfi(mesh, alpha=scaled_alpha(mesh, spacings))


def test_fan_test_is_molars_barycentric_test():
    square = np.array([[1.0, -1.0], [1.0, 1.0], [-1.0, 1.0], [-1.0, -1.0]])
    start, end = np.array([0, 3, 2, 1]), np.array([3, 2, 1, 0])  # clockwise
    assert fan_test(square, start, end, 0.0, 0.0) == FAN_CLEAR
    # a corner pushed in towards O: still star-shaped
    dented = np.vstack([square, [[0.2, 0.1]]])
    start, end = np.array([0, 3, 2, 4]), np.array([3, 2, 4, 0])
    assert fan_test(dented, start, end, 0.0, 0.0) == FAN_CLEAR
    # a turn back: (0.5, 0.45) lies inside the triangle (O, (1, 1), (0.9, 0.1))
    hidden = np.vstack([square, [[0.9, 0.1], [0.5, 0.45]]])
    start, end = np.array([0, 3, 2, 1, 4, 5]), np.array([3, 2, 1, 4, 5, 0])
    assert fan_test(hidden, start, end, 0.0, 0.0) == FAN_INSIDE
    # O on the line through an arc's ends: R's 0 / 0 (a missing value)
    assert fan_test(square, np.array([0, 2]), np.array([2, 0]), 0.0, 0.0) == FAN_UNDEFINED


def test_duplicate_check_is_molars():
    # (0, 1) is a new point, but its x and its y were both seen before
    points = np.array([[0.0, 0.0], [1.0, 1.0], [0.0, 1.0], [2.0, 0.0], [2.0, 3.0]])
    assert first_occurrence(points).tolist() == [True, True, False, True, True]


def test_separate_discs_need_adjustment():
    # the mean lies between two discs: an isolated point of the hull, whatever
    # alpha the walk reaches in its 99 hulls
    disc = flat_disc()
    other = disc.copy()
    other.apply_translation([5.0, 0.0, 0.0])
    both = trimesh.util.concatenate([disc, other])
    with pytest.raises(AlphaAdjustmentError, match="ends no arc"):
        rfi(both, alpha=0.075)
    with pytest.raises(AlphaAdjustmentError, match="search from there failed"):
        rfi(both, find_alpha=True)


# the result and its invariances -------------------------------------------------------


def test_result_fields_and_footprint():
    mesh = hemisphere()
    result = rfi(mesh, find_alpha=True)
    assert isinstance(result, RFIResult)
    assert tuple(result.to_dict()) == RFI_FIELDS
    assert result.vertices == len(mesh.vertices) and result.faces == len(mesh.faces)
    ends = result.footprint
    assert ends.ndim == 3 and ends.shape[1:] == (2, 2)
    assert result.warning is None and "warning" not in result.to_dict()
    # chained head to tail around one loop, at vertex positions of the mesh
    assert np.array_equal(ends[1:, 0], ends[:-1, 1]) and np.array_equal(ends[0, 0], ends[-1, 1])
    on_mesh = {tuple(xy) for xy in mesh.vertices[:, :2].tolist()}
    assert all(tuple(xy) in on_mesh for xy in ends[:, 0].tolist())
    # the outline of a hemisphere is its rim
    assert np.hypot(*ends[:, 0].T) == pytest.approx(1.0)


def test_invariances():
    mesh = cone(1.5)
    base = rfi(mesh, find_alpha=True)

    def same(result, area_factor=1.0):
        assert result.alpha == base.alpha
        assert result.rfi == pytest.approx(base.rfi, rel=1e-6)
        assert result.area_3d == pytest.approx(base.area_3d * area_factor, rel=1e-6)
        assert result.area_2d == pytest.approx(base.area_2d * area_factor, rel=1e-9)

    # molaR's size centres each vertex on the mean of its own x, y and z, so it
    # is invariant to translations along (1, 1, 1) only
    moved = mesh.copy()
    moved.apply_translation([3.0, 3.0, 3.0])
    same(rfi(moved, find_alpha=True))
    scaled = mesh.copy()
    scaled.apply_scale(2.5)
    same(rfi(scaled, find_alpha=True), 2.5**2)
    rng = np.random.default_rng(1)
    order = rng.permutation(len(mesh.vertices))
    inverse = np.argsort(order)
    shuffled = trimesh.Trimesh(
        mesh.vertices[order], inverse[mesh.faces][rng.permutation(len(mesh.faces))], process=False
    )
    same(rfi(shuffled, find_alpha=True))


def test_caller_mesh_unchanged():
    mesh = hemisphere()
    vertices, faces = mesh.vertices.copy(), mesh.faces.copy()
    rfi(mesh, find_alpha=True)
    rfi((mesh.vertices, mesh.faces), alpha=0.5)
    assert np.array_equal(mesh.vertices, vertices) and np.array_equal(mesh.faces, faces)


@pytest.mark.parametrize("alpha", [0, -0.1, float("nan"), float("inf")])
def test_bad_alpha_value(alpha):
    with pytest.raises(ValueError, match="alpha"):
        rfi(hemisphere(), alpha=alpha)


@pytest.mark.parametrize("alpha", [True, "0.075", None, [0.075]])
def test_bad_alpha_type(alpha):
    with pytest.raises(TypeError, match="alpha"):
        rfi(hemisphere(), alpha=alpha)


@pytest.mark.parametrize("find_alpha", [1, "yes", None, 0.0])
def test_bad_find_alpha(find_alpha):
    with pytest.raises(TypeError, match="find_alpha"):
        rfi(hemisphere(), find_alpha=find_alpha)


def test_errors_and_warning_classes():
    assert issubclass(AlphaAdjustmentError, ValueError)
    assert issubclass(FootprintError, ValueError)
    assert issubclass(FootprintWarning, UserWarning)
