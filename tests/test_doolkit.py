"""doolkit 1.42.2's slope, inclination, OPC/OPCR, elevation, relief indices, relief rate,
shape index and hypsodonty.

doolkit's own numbers on the robustness set (read from the reference table at
test time, the crowns measured as they lie: pointing to -z), the cross-check
of its OPC/OPCR against molaR's on every shared mesh, analytic cases (planes,
a cone, a hemisphere), invariances, and the quirks (R's round, the pairing
of face-edges on a non-manifold edge).
"""

from __future__ import annotations

import csv
import math

import numpy as np
import pytest
import trimesh

from conftest import MESHES, REFERENCE, ROBUSTNESS_SET, hemisphere, plane_patch, shared_mesh
from dentopo.topography import (
    DoolkitOPCResult,
    DoolkitOPCRResult,
    doolkit_opc,
    doolkit_opcr,
    doolkit_slope,
    elevation,
    face_bearing,
    footprint_area,
    hypsodonty,
    inclination,
    opc,
    opcr,
    prepare_surface,
    r_round,
    relief_index,
    relief_rate,
    relief_rate_below_median,
    shape_index,
)
from dentopo.topography.opc._doolkit import doolkit_pairs

#: The reference crowns point to -z, as doolkit measured them: that warning is expected here.
pytestmark = [
    pytest.mark.filterwarnings("ignore:the crown points to -z:UserWarning"),
    # planes are flat: no up or down (tests/test_orientation.py)
    pytest.mark.filterwarnings("ignore:the surface is flat:UserWarning"),
    # doolkit's rounding on the small crowns (noise1, noise2: under a millimetre high) is said
    pytest.mark.filterwarnings("ignore::dentopo.topography.UnitWarning"),
]

#: Every shared mesh: the robustness set, its holed variant and six closed museum specimens.
SHARED = (
    *ROBUSTNESS_SET,
    "low_hole",
    "000119433",
    "000120565",
    "000121104",
    "000122274",
    "000458120",
    "000576115",
)

#: Columns compared to 1e-9 relative, and to 1e-6 relative.
TIGHT = (
    "slope_mean",
    "inclin_mean",
    "area3d",
    "area2d_convex",
    *(f"hypso_{k}" for k in ("hypsodonty", "height", "length", "width")),
)
LOOSE = ("rfi_guy", "rrate_below_median", "shape_formfactor", "shape_elongation", "shape_k")

TURN = np.diag([1.0, -1.0, -1.0])


@pytest.fixture(scope="session")
def doolkit_reference():
    path = REFERENCE / "doolkit_1.42.2_topography.csv"
    if not path.exists():
        pytest.skip(f"doolkit 1.42.2 reference values not found at {path}")
    with path.open(newline="") as handle:
        return {row["file"].removesuffix(".ply"): row for row in csv.DictReader(handle)}


def measured(mesh, orient: str = "as-is") -> dict:
    """Every value of the reference table this module computes, by column.

    ``orient="as-is"``: doolkit's numbers (it measures the crown as it lies).
    """
    slope = doolkit_slope(mesh)
    row = {"n_vertices": slope.vertices, "n_faces": slope.faces, **slope.to_dict()}
    row.update(inclination(mesh, orient=orient).to_dict())
    row.update(doolkit_opc(mesh, orient=orient).to_dict())
    row.update(doolkit_opcr(mesh, orient=orient).to_dict())
    convex = relief_index(mesh, hull="convex", orient=orient)
    row.update(area3d=convex.area3d, rfi_guy=convex.rfi_guy, area2d_convex=convex.area2d)
    row.update(relief_rate_below_median(mesh, orient=orient).to_dict())
    row.update(shape_index(mesh).to_dict())
    row.update(hypsodonty(mesh).to_dict())
    return row


def relative(value: float, expected: float) -> float:
    return abs(value - expected) / abs(expected)


def jittered(mesh: trimesh.Trimesh, scale: float = 1e-3) -> trimesh.Trimesh:
    """`mesh` with its vertices jittered (seeded) and rounded to single precision."""
    vertices = mesh.vertices + np.random.default_rng(0).normal(
        scale=scale, size=mesh.vertices.shape
    )
    return trimesh.Trimesh(vertices.astype(np.float32).astype(float), mesh.faces, process=False)


def cone(segments: int = 64, rings: int = 8, radius: float = 2.0, height: float = 1.5):
    """An open cone, apex up at (0, 0, height), base circle of `radius` at z = 0, normals out.

    Every face lies in the plane of two neighbouring generators, whose slope
    is ``atan(height / (radius cos(pi / segments)))``.
    """
    phi = 2 * np.pi * np.arange(segments) / segments
    t = np.arange(1, rings + 1) / rings  # 0 at the apex, 1 at the base
    r, p = np.meshgrid(t * radius, phi, indexing="ij")
    z = np.repeat(height * (1 - t), segments)
    vertices = np.vstack(
        [[0, 0, height], np.column_stack([(r * np.cos(p)).ravel(), (r * np.sin(p)).ravel(), z])]
    )
    ring = 1 + np.arange(rings * segments).reshape(rings, segments)
    nxt = np.roll(ring, -1, axis=1)
    apex = np.column_stack([np.zeros(segments, dtype=int), ring[0], nxt[0]])
    a, b, c, d = ring[:-1], nxt[:-1], ring[1:], nxt[1:]
    quads = np.concatenate(
        [
            np.column_stack([a.ravel(), c.ravel(), d.ravel()]),
            np.column_stack([a.ravel(), d.ravel(), b.ravel()]),
        ]
    )
    return trimesh.Trimesh(vertices, np.vstack([apex, quads]), process=False)


# --- doolkit's numbers --------------------------------------------------------------------


@pytest.mark.parametrize("name", ROBUSTNESS_SET)
def test_matches_doolkit(name, doolkit_reference):
    row = doolkit_reference[name]
    values = measured(shared_mesh(name))
    for key in (
        "n_vertices",
        "n_faces",
        "opc",
        *(f"opc_bin{k}" for k in range(1, 9)),
        *(f"opcr_rot{j}" for j in range(8)),
    ):
        assert values[key] == int(row[key]), key
    assert values["opcr"] == float(row["opcr"])  # a plain mean: 57.125 stays 57.125
    for key in TIGHT:
        assert relative(values[key], float(row[key])) <= 1e-9, key
    for key in LOOSE:
        assert relative(values[key], float(row[key])) <= 1e-6, key


@pytest.mark.parametrize("name", ROBUSTNESS_SET)
def test_ungar_and_boyer_are_their_ratios(name, doolkit_reference):
    """With the convex footprint (the concave one is another module's): A3 / A2 and its log."""
    row = doolkit_reference[name]
    result = relief_index(shared_mesh(name), hull="convex")
    ratio = float(row["area3d"]) / float(row["area2d_convex"])
    assert relative(result.rfi_ungar, ratio) <= 1e-9
    assert relative(result.rfi_boyer, 0.5 * math.log(ratio)) <= 1e-9


@pytest.mark.parametrize("name", SHARED)
def test_opc_and_opcr_totals_equal_molar(name):
    """doolkit's OPC and its 8 rotation totals equal molaR's (bins are numbered differently)."""
    path = shared_mesh(name)
    surface = prepare_surface(path)
    assert doolkit_opc(path, orient="as-is").opc == opc(surface, orient="as-is").opc
    as_is = opcr(surface, orient="as-is").opc_values
    assert doolkit_opcr(path, orient="as-is").opc_values == as_is


@pytest.mark.parametrize("name", SHARED)
def test_runs_on_every_shared_mesh_and_upside_down(name):
    path = shared_mesh(name)
    mesh = trimesh.load(path, process=False)
    turned = trimesh.Trimesh(mesh.vertices @ TURN.T, mesh.faces, process=False)
    values, upside = measured(path), measured(turned)
    for row in (values, upside):
        assert all(np.isfinite(v) for v in row.values())
    # orientation-free quantities are unchanged, inclination becomes 180 minus itself
    assert upside["slope_mean"] == pytest.approx(values["slope_mean"], rel=1e-12)
    assert upside["inclin_mean"] == pytest.approx(180 - values["inclin_mean"], rel=1e-12)
    for key in ("area3d", "area2d_convex", "hypso_height", "hypso_length", "hypso_width"):
        assert upside[key] == pytest.approx(values[key], rel=1e-9), key
    # orient="auto" measures a crown pointing to -z turned: as its upside-down copy as-is
    found = prepare_surface(path, orient="as-is").orientation
    if found.points == "-z":
        assert inclination(path, orient="auto").inclination_mean == pytest.approx(
            inclination(turned, orient="as-is").inclination_mean, rel=1e-12
        )
        assert relief_rate_below_median(path, orient="auto").rrate == pytest.approx(
            relief_rate_below_median(turned, orient="as-is").rrate, rel=1e-6
        )


# --- analytic cases -----------------------------------------------------------------------


def test_plane_facing_up(plane):
    assert np.all(doolkit_slope(plane).face_slope == 0)
    assert np.all(inclination(plane).face_inclination == 180)
    result = doolkit_opc(plane)
    assert np.all(result.face_bearing == 0)  # exactly: doolkit's expression gives 0 at atan2 0
    assert result.bins == (1, 0, 0, 0, 0, 0, 0, 0)
    assert doolkit_opc(plane, rotation=5.625).bins == (0, 0, 0, 0, 0, 0, 0, 1)  # the wrap-around
    rotated = doolkit_opcr(plane)
    assert rotated.opc_values == (1,) * 8 and rotated.opcr == 1.0
    assert np.all(elevation(plane).face_elevation == 0)
    assert math.isnan(relief_index(plane, hull="convex").rfi_guy)  # no face steeper than 45
    assert relief_index(plane, hull="convex").area2d == pytest.approx(1.0, rel=1e-12)
    with pytest.raises(ValueError, match="median"):
        relief_rate_below_median(plane)


@pytest.mark.parametrize("degrees", [10.0, 30.0, 60.0])
def test_tilted_plane(plane, degrees):
    """Rising towards azimuth 67.5 (from +x): slope a, inclination 180 - a, bearing 202.5."""
    vertices = plane.vertices.copy()
    beta = math.radians(67.5)
    rise = vertices[:, 0] * math.cos(beta) + vertices[:, 1] * math.sin(beta)
    vertices[:, 2] = rise * math.tan(math.radians(degrees))
    tilted = trimesh.Trimesh(vertices, plane.faces, process=False)
    # the coordinates are read in single precision: angles to about 1e-5 degrees
    assert doolkit_slope(tilted).face_slope == pytest.approx(degrees, abs=1e-4)
    assert inclination(tilted).face_inclination == pytest.approx(180 - degrees, abs=1e-4)
    result = doolkit_opc(tilted)
    assert result.face_bearing == pytest.approx(202.5, abs=1e-3)
    assert result.bins == (0, 0, 0, 0, 1, 0, 0, 0)  # bin 5: [180, 225)
    gamma = relief_index(tilted, hull="convex").rfi_guy
    if degrees < 45:
        assert math.isnan(gamma)  # no face steeper than 45
    else:
        assert gamma == 0.0  # no face gentler than 45


def test_cone():
    segments, radius, height = 64, 2.0, 1.5
    mesh = cone(segments=segments, radius=radius, height=height)
    angle = math.degrees(math.atan(height / (radius * math.cos(math.pi / segments))))
    # coordinates read in single precision: angles to about 1e-5 degrees
    assert doolkit_slope(mesh).face_slope == pytest.approx(angle, abs=1e-4)
    assert inclination(mesh).inclination_mean == pytest.approx(180 - angle, abs=1e-4)
    # each facet faces its middle direction phi: bearing 90 - phi
    result = doolkit_opc(mesh)
    phi = 360.0 * (np.arange(segments) + 0.5) / segments
    expected = np.tile((90.0 - phi) % 360.0, len(mesh.faces) // segments)  # 15 faces a facet
    assert np.sort(result.face_bearing) == pytest.approx(np.sort(expected), abs=1e-3)
    # 8 facets per 45-degree sector, none on a bin edge at any OPCR rotation: one patch a bin
    assert result.bins == (1,) * 8
    assert doolkit_opcr(mesh).opc_values == (8,) * 8
    hyp = hypsodonty(mesh)
    assert (hyp.height, hyp.width) == (r_round(height), r_round(2 * radius))


def test_hemisphere():
    mesh = hemisphere(rings=128, segments=256)
    hyp = hypsodonty(mesh)
    assert (hyp.hypsodonty, hyp.height, hyp.length, hyp.width) == (0.5, 1.0, 2.0, 2.0)
    # faces are evenly spread in polar angle t, elevation ~ cos t, slope ~ t:
    # gamma ~ (integral of cos over [0, 45]) / (integral over [45, 90]) = s / (1 - s)
    s = math.sin(math.pi / 4)
    assert relief_index(mesh, hull="convex").rfi_guy == pytest.approx(s / (1 - s), rel=1e-2)
    assert relief_index(mesh, hull="convex").area2d == pytest.approx(math.pi, rel=1e-3)
    shape = shape_index(mesh)
    assert shape.length == 2.0
    assert shape.formfactor == pytest.approx(2 * math.pi / 4, rel=1e-3)
    assert shape.k == pytest.approx(math.pi * 4 / (4 * 2 * math.pi), rel=1e-3)


def test_box_examples():
    box = trimesh.creation.box()
    assert doolkit_slope(box).slope_mean == 60.0
    assert inclination(box, orient="as-is").inclination_mean == 90.0
    with pytest.warns(UserWarning, match="the surface is closed"):  # by default: as it lies
        assert inclination(box).inclination_mean == 90.0
    ungar = relief_index(box, hull="convex", orient="as-is").rfi_ungar
    assert ungar == pytest.approx(6.0, rel=1e-12)


# --- invariances and inputs ---------------------------------------------------------------


def test_translation_and_vertex_order(tooth):
    mesh = jittered(tooth)
    offset = np.array([0.5, -0.25, 2.0])
    shifted = trimesh.Trimesh(mesh.vertices + offset, mesh.faces, process=False)
    perm = np.random.default_rng(1).permutation(len(mesh.vertices))
    inverse = np.argsort(perm)
    renumbered = trimesh.Trimesh(mesh.vertices[perm], inverse[mesh.faces], process=False)
    base = measured(mesh)
    for other, rel in ((shifted, 1e-6), (renumbered, 1e-12)):
        row = measured(other)
        for key, value in base.items():
            assert row[key] == pytest.approx(value, rel=rel, abs=1e-12), key


def test_face_order(tooth):
    mesh = jittered(tooth)
    order = np.random.default_rng(2).permutation(len(mesh.faces))
    shuffled = trimesh.Trimesh(mesh.vertices, mesh.faces[order], process=False)
    a, b = doolkit_slope(mesh), doolkit_slope(shuffled)
    assert b.face_slope == pytest.approx(a.face_slope[order], rel=1e-15)
    assert doolkit_opcr(shuffled).opc_values == doolkit_opcr(mesh).opc_values
    assert elevation(shuffled).face_elevation == pytest.approx(
        elevation(mesh).face_elevation[order], rel=0, abs=0
    )


def test_input_not_modified(tooth):
    vertices, faces = tooth.vertices.copy(), tooth.faces.copy()
    measured(tooth)
    relief_rate(tooth, tooth)
    elevation(tooth, orient="auto")
    assert np.array_equal(tooth.vertices, vertices) and np.array_equal(tooth.faces, faces)
    surface = prepare_surface(tooth)
    before = surface.vertices.copy()
    measured(surface)
    assert np.array_equal(surface.vertices, before)


def test_surface_and_mesh_agree():
    path = shared_mesh("normal")
    assert measured(prepare_surface(path)) == measured(path)


def test_relief_rate_of_the_whole_is_one(tooth):
    assert relief_rate(tooth, tooth).rrate == pytest.approx(1.0, rel=1e-15)
    result = relief_rate_below_median(tooth)
    assert 0 < result.rrate < 1 and result.below_median
    assert result.to_dict() == {"rrate_below_median": result.rrate}
    assert relief_rate(tooth, tooth).to_dict() == {"rrate": 1.0}


def test_results_and_dicts(tooth):
    result = doolkit_opcr(tooth)
    assert isinstance(result, DoolkitOPCRResult) and isinstance(result.first, DoolkitOPCResult)
    assert list(result.to_dict()) == ["opcr", *(f"opcr_rot{j}" for j in range(8))]
    assert result.opcr == sum(result.opc_values) / 8
    assert result.first.opc == doolkit_opc(tooth).opc
    assert list(doolkit_opc(tooth).to_dict()) == ["opc", *(f"opc_bin{k}" for k in range(1, 9))]


def test_duplicate_vertices_and_faces_are_cleaned(plane):
    """vcgImport(clean = TRUE): equal vertices merged, repeated faces dropped."""
    n = len(plane.vertices)
    vertices = np.vstack([plane.vertices, plane.vertices[:1]])
    faces = np.vstack([plane.faces, plane.faces[:3]])
    faces[0, 0] = n  # uses the copy of vertex 0
    result = doolkit_slope((vertices, faces))
    assert (result.vertices, result.faces) == (n, len(plane.faces))


def test_degenerate_face_gives_nan_slope(plane):
    """doolkit keeps a face of no area: its slope is NaN, and so is the mean."""
    vertices = np.vstack([plane.vertices, [[2.0, 0.0, 0.0], [3.0, 0.0, 0.0], [4.0, 0.0, 0.0]]])
    n = len(plane.vertices)
    faces = np.vstack([plane.faces, [[n, n + 1, n + 2]]])
    result = doolkit_slope((vertices, faces))
    assert np.isnan(result.face_slope[-1]) and np.isnan(result.slope_mean)
    assert not np.isnan(doolkit_slope(prepare_surface((vertices, faces))).slope_mean)


# --- quirks -------------------------------------------------------------------------------


def test_non_manifold_pairing():
    """Face-edges sorted and paired two by two: three faces on one edge shift every pair after."""
    faces = np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4], [2, 1, 5]])
    pairs = np.empty((8, 2), dtype=np.int64)
    count = doolkit_pairs(faces, 6, pairs)
    # rows of edge (0, 1): faces 0, 1, 2; of edge (1, 2): faces 0, 3; the rest are border
    assert pairs[:count].tolist() == [[0, 1], [2, 0]]  # faces 0 and 3 are not joined
    manifold = plane_patch(5).faces
    pairs = np.empty((len(manifold) * 3 // 2 + 1, 2), dtype=np.int64)
    count = doolkit_pairs(manifold, 25, pairs)
    shared = {tuple(sorted(set(manifold[a]) & set(manifold[b]))) for a, b in pairs[:count]}
    assert count == len(shared) == 40  # the interior edges of a 4 x 4 grid of split squares
    assert all(len(edge) == 2 for edge in shared)


def test_bearing_expression():
    """Bearing 0 towards +y, 90 towards +x; a tiny negative angle can land on exactly 360."""
    normals = np.array(
        [
            [0.0, 1.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, -1.0, 0.0],
            [-1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0],
            [-1e-300, 1.0, 0.0],
        ]
    )
    bearing = face_bearing(normals)
    assert bearing[:5] == pytest.approx([0.0, 90.0, 180.0, 270.0, 0.0], abs=1e-12)
    assert bearing[4] == 0.0
    assert bearing[5] == 360.0
    from dentopo.topography.opc._doolkit import face_bins

    assert face_bins(bearing, 8, 0.0)[5] == 0  # in no bin at rotation 0


def test_r_round():
    # exact halves: ties to even, as Python
    assert (r_round(0.125), r_round(0.375)) == (0.12, 0.38)
    assert r_round(0.15, 1) == 0.1  # R 4's documented example (0.15 is stored below 0.15)
    assert r_round(2.675) == 2.67
    # R compares the two candidates in double arithmetic: not always Python's choice
    assert (r_round(0.155), round(0.155, 2)) == (0.16, 0.15)
    assert (r_round(0.065), round(0.065, 2)) == (0.06, 0.07)
    assert r_round(-0.155) == -0.16
    assert r_round(4.986303508281708) == 4.99
    assert math.isnan(r_round(math.nan))


# --- parameters ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("call", "error"),
    [
        (lambda m: doolkit_opc(m, bins=0), ValueError),
        (lambda m: doolkit_opc(m, bins=2.5), TypeError),
        (lambda m: doolkit_opc(m, min_size=0), ValueError),
        (lambda m: doolkit_opc(m, min_size=True), TypeError),
        (lambda m: doolkit_opc(m, rotation=math.nan), ValueError),
        (lambda m: doolkit_opc(m, rotation="5"), TypeError),
        (lambda m: doolkit_opc(m, rotation=50.0), ValueError),
        (lambda m: doolkit_opcr(m, bins=0), ValueError),
        (lambda m: doolkit_opc(m, orient="up"), ValueError),
        (lambda m: inclination(m, orient=None), ValueError),
        (lambda m: elevation(m, orient="down"), ValueError),
        (lambda m: relief_index(m, hull="alpha"), ValueError),
        (lambda m: relief_index(m, hull=3), TypeError),
        (lambda m: footprint_area(m, hull="round"), ValueError),
        (lambda m: relief_rate_below_median(m, orient=1), ValueError),
        (lambda m: doolkit_slope("no/such/file.ply"), (FileNotFoundError, ValueError)),
        (lambda m: doolkit_slope(42), TypeError),
    ],
)
def test_bad_parameters_raise(tooth, call, error):
    with pytest.raises(error):
        call(tooth)


def test_shared_meshes_present():
    if not MESHES.exists():
        pytest.skip("shared meshes absent")
    assert {p.stem for p in MESHES.glob("*.ply")} >= set(SHARED)
