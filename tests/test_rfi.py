"""Relief index as molaR computes it: molaR's own numbers, analytic shapes, the alpha shape."""

from __future__ import annotations

import csv

import numpy as np
import pytest
import trimesh
from scipy.spatial import Delaunay

from conftest import REFERENCE, ROBUSTNESS_SET, shared_mesh
from dentopo.topography import RFI_FIELDS, AlphaAdjustmentError, RFIResult, rfi
from dentopo.topography._rfi import DOWN_STEP, FINE_STEP, UP_STEP, AlphaShape, first_occurrence

#: The reference crowns point to -z, as molaR measured them: that warning is expected here.
pytestmark = [
    pytest.mark.filterwarnings("ignore:the crown points to -z:UserWarning"),
    # planes and single faces are flat: no up or down (tests/test_orientation.py)
    pytest.mark.filterwarnings("ignore:the surface is flat:UserWarning"),
]

PARITY = 1e-9


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


# molaR's own numbers ------------------------------------------------------------------


@pytest.mark.parametrize("name", ROBUSTNESS_SET)
def test_matches_molar_at_default_alpha(name, molar_rows):
    row = molar_rows[name]
    mesh = shared_mesh(name)
    if row["RFI"] == "NA":
        # molaR stopped with "alpha adjustment required"
        with pytest.raises(AlphaAdjustmentError, match=r"find_alpha=True.*") as caught:
            rfi(mesh)
        assert "alpha = 0.075" in str(caught.value)
        assert "pinches" in str(caught.value)
        return
    result = rfi(mesh)
    for key, column in (("rfi", "RFI"), ("area_3d", "area_3d"), ("area_2d", "area_2d")):
        assert getattr(result, key) == pytest.approx(number(row[column]), rel=PARITY), key
    assert result.alpha == number(row["alpha"])


@pytest.mark.parametrize("name", ROBUSTNESS_SET)
def test_matches_molar_find_alpha(name, molar_rows):
    row = molar_rows[name]
    result = rfi(shared_mesh(name), find_alpha=True)
    # the same floating-point number as molaR's search, artefacts included
    assert result.alpha == float(row["alpha_found"])
    assert result.rfi == pytest.approx(float(row["RFI_findalpha"]), rel=PARITY)
    assert result.find_alpha is True


def test_search_replay_matches_a_plain_loop():
    """The run-skipping search equals molaR's procedure written as plain loops."""
    mesh = trimesh.load(shared_mesh("low"), process=False)
    points = mesh.vertices - mesh.vertices.mean(axis=0)
    from dentopo.topography._surface import molar_scale

    shape = AlphaShape(np.vstack([points, [[0, 0, 0]]])[:, :2] * molar_scale(mesh.vertices))

    def plain(alpha):
        def ok(a):
            return shape.problem(a) is None

        if ok(alpha):
            while ok(alpha):
                alpha = alpha - DOWN_STEP
        else:
            i = 1
            while not ok(alpha + i * UP_STEP):
                i += 1
            alpha = alpha + i * UP_STEP - UP_STEP
        while not ok(alpha):
            alpha = alpha + FINE_STEP
        return alpha

    for start in (0.01, 0.05, 0.075, 0.2, 0.31):
        assert shape.find_alpha(start) == plain(start), start


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


# the alpha shape ----------------------------------------------------------------------


def test_alpha_shape_edges_are_the_alpha_exposed_pairs():
    """An edge is on the boundary iff an empty disc of radius alpha has both ends on its circle."""
    rng = np.random.default_rng(3)
    points = rng.random((40, 2))
    shape = AlphaShape(points)
    i, j = np.triu_indices(len(points), 1)
    p, q = points[i], points[j]
    mid, half = (p + q) / 2, np.hypot(*(q - p).T) / 2
    normal = np.column_stack([-(q - p)[:, 1], (q - p)[:, 0]]) / (2 * half[:, None])
    for alpha in (0.03, 0.06, 0.1, 0.2, 0.5, 5.0):
        reach = np.sqrt(np.maximum(alpha**2 - half**2, 0))[:, None]
        exposed = np.zeros(len(i), dtype=bool)
        for side in (1, -1):
            centre = mid + side * reach * normal
            inside = np.hypot(*(points[None] - centre[:, None]).transpose(2, 0, 1)) < alpha - 1e-12
            exposed |= ~inside.any(axis=1)
        exposed &= half <= alpha
        expected = {(a, b) for a, b in zip(i[exposed], j[exposed], strict=True)}
        found = {tuple(sorted(e)) for e in shape.boundary(alpha).tolist()}
        assert found == expected, alpha


def test_duplicate_check_is_molars():
    # (0, 1) is a new point, but its x and its y were both seen before
    points = np.array([[0.0, 0.0], [1.0, 1.0], [0.0, 1.0], [2.0, 0.0], [2.0, 3.0]])
    assert first_occurrence(points).tolist() == [True, True, False, True, True]


def test_several_loops_need_adjustment():
    # two separate discs: the boundary is two loops whatever alpha molaR tries
    # below the gap, and one (the hull) above it
    disc = flat_disc()
    other = disc.copy()
    other.apply_translation([5.0, 0.0, 0.0])
    both = trimesh.util.concatenate([disc, other])
    with pytest.raises(AlphaAdjustmentError, match="2 separate loops"):
        rfi(both, alpha=0.075)
    assert rfi(both, find_alpha=True).area_2d > 2 * disc.area


# the result and its invariances -------------------------------------------------------


def test_result_fields_and_footprint():
    mesh = hemisphere()
    result = rfi(mesh, find_alpha=True)
    assert isinstance(result, RFIResult)
    assert tuple(result.to_dict()) == RFI_FIELDS
    assert result.vertices == len(mesh.vertices) and result.faces == len(mesh.faces)
    ends = result.footprint
    assert ends.ndim == 3 and ends.shape[1:] == (2, 2)
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


def test_adjustment_error_is_a_value_error():
    assert issubclass(AlphaAdjustmentError, ValueError)
