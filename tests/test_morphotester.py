"""MorphoTester 1.1.1's DNE, RFI and OPCR: its printed digits, its unit-test values, analytic cases.

The reference is MorphoTester's own output for two of its sample crowns
(``../shared/data/morphotester``) and the values its unit tests check, as the shared
description (``../shared/docs/MORPHOTESTER.md``, section 6) quotes them.  Where the shared
data is absent those tests skip, saying so.  The analytic cases and the checks of inputs need
no data.
"""

from __future__ import annotations

import contextlib
import math

import matplotlib as mpl
import matplotlib.style
import numpy as np
import pytest
import trimesh

from conftest import SHARED, plane_patch
from dentopo.formats._layouts import python2_str
from dentopo.mesh import load_mesh, read_ply
from dentopo.prepare import _smooth
from dentopo.topography import (
    MORPHOTESTER_DNE_FIELDS,
    morphotester_dne,
    morphotester_opcr,
    morphotester_rfi,
)
from dentopo.topography.dne._morphotester import dne_quantities, percentile_linear
from dentopo.topography.footprint import _morphotester as footprint
from dentopo.topography.opc._morphotester import aspect, aspect_bin
from dentopo.topography.surface import _morphotester as mt

DATA = SHARED / "data" / "morphotester"
THERO = "Theropithecus_gelada_1963-58"
CERCO = "Cercocebus_atys_89373"


def _expected() -> list[dict]:
    path = DATA / "expected_morphoresults.txt"
    if not path.exists():
        return []
    lines = path.read_text().splitlines()
    header = lines[0].split("\t")
    return [dict(zip(header, line.split("\t"), strict=True)) for line in lines[1:] if line]


def sample(name: str, *, exact_text: bool = True):
    path = DATA / f"{name}.ply"
    if not path.exists():
        pytest.skip(
            f"MorphoTester's sample crowns not found at {DATA} (expected beside the checkout)"
        )
    return read_ply(path, exact_text=exact_text)


@pytest.fixture(scope="module")
def thero():
    return sample(THERO)


@pytest.fixture(scope="module")
def cerco():
    return sample(CERCO)


def dome(rings: int = 48, segments: int = 96) -> tuple[np.ndarray, np.ndarray]:
    """The upper unit hemisphere, open at the equator, one vertex at the pole, faces outward."""
    theta = np.linspace(0.0, np.pi / 2, rings + 1)[1:]
    phi = np.linspace(0.0, 2 * np.pi, segments + 1)[:-1]
    t, p = np.meshgrid(theta, phi, indexing="ij")
    ring = np.column_stack(
        [(np.sin(t) * np.cos(p)).ravel(), (np.sin(t) * np.sin(p)).ravel(), np.cos(t).ravel()]
    )
    vertices = np.vstack([[0.0, 0.0, 1.0], ring])
    idx = 1 + np.arange(rings * segments).reshape(rings, segments)
    nxt = np.roll(idx, -1, axis=1)
    cap = np.column_stack([np.zeros(segments, dtype=np.int64), idx[0], nxt[0]])
    a, b, c, d = idx[:-1], nxt[:-1], idx[1:], nxt[1:]
    faces = np.concatenate(
        [
            cap,
            np.column_stack([a.ravel(), c.ravel(), d.ravel()]),
            np.column_stack([a.ravel(), d.ravel(), b.ravel()]),
        ]
    )
    return vertices, faces


def pyramid() -> tuple[np.ndarray, np.ndarray]:
    """Four faces of a pyramid of height 2 over the square [-1, 1]^2 (open base)."""
    vertices = np.array([[-1.0, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0], [0, 0, 2]])
    faces = np.array([[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]])
    return vertices, faces


# --- MorphoTester's printed results ----------------------------------------------------------


@pytest.mark.parametrize("row", _expected() or [None], ids=lambda r: r and r["Filename"])
def test_the_sample_crowns_give_every_digit_morphotester_printed(row):
    if row is None:
        pytest.skip(f"MorphoTester's expected results not found at {DATA}")
    mesh = sample(row["Filename"].removesuffix(".ply"))
    dne, rfi, opcr = morphotester_dne(mesh), morphotester_rfi(mesh), morphotester_opcr(mesh)
    printed = {
        "Mesh Face Number": str(dne.n_faces),
        "DNE": python2_str(dne.dne),
        "RFI": python2_str(rfi.rfi),
        "Surface Area": python2_str(rfi.surface_area),
        "Outline Area": python2_str(rfi.outline_area),
        "OPCR": python2_str(opcr.opcr),
    }
    assert printed == {key: row[key] for key in printed}


def test_morphotester_prints_as_python_2_str_does():
    assert [python2_str(x) for x in (68.0, 228.18, 67.125, 1.0 / 3, 1e16)] == [
        "68.0",
        "228.18",
        "67.125",
        "0.333333333333",
        "1e+16",
    ]
    # Python 2 rounds exact binary ties away from zero, Python 3 to even
    assert mt.py2_round(0.0625, 3) == 0.063 and round(0.0625, 3) == 0.062
    assert mt.py2_round(-0.0625, 3) == -0.063
    assert mt.py2_round(2.675, 2) == 2.67  # 2.67499999... in binary: no tie


def test_theropithecus_read_as_float32_misses_the_third_decimal_of_dne():
    # MorphoTester parses the ASCII text as float64; the header's float32 costs the digit
    exact = morphotester_dne(sample(THERO))
    rounded = morphotester_dne(sample(THERO, exact_text=False))
    assert (exact.dne, rounded.dne) == (249.806, 249.804)
    area = morphotester_dne(sample(THERO, exact_text=False), outliers="energy_area")
    assert area.dne == 247.935  # the description's value for the float32 copy (Thege58bin)


def test_read_ply_keeps_ascii_coordinates_as_their_text_only_when_asked(tmp_path):
    header = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
    header += "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
    path = tmp_path / "one.ply"
    path.write_text(header + "end_header\n40.711 0.1 3\n1 2 3\n4 5 6.6152\n3 0 1 2\n")
    exact, faces = read_ply(path, exact_text=True)
    assert exact[0, 0] == 40.711 and exact[2, 2] == 6.6152 and exact.dtype == np.float64
    rounded, _ = read_ply(path)
    assert rounded[0, 0] == float(np.float32(40.711)) != 40.711
    # binary files are unaffected: their float32 values are widened exactly
    binary = tmp_path / "one_binary.ply"
    trimesh.Trimesh(exact.astype(np.float32), faces, process=False).export(binary)
    a, _ = read_ply(binary, exact_text=True)
    b, _ = read_ply(binary)
    assert np.array_equal(a, b) and np.array_equal(a, exact.astype(np.float32))


# --- MorphoTester's unit tests (section 6) -----------------------------------------------------


def test_theropithecus_energy_x_area_dne_is_247_938_with_its_11_outlier_faces(thero):
    result = morphotester_dne(thero, outliers="energy_area")
    assert result.dne == 247.938
    assert list(np.flatnonzero(result.outlier)) == [
        2475, 2519, 2549, 2606, 2645, 2785, 5126, 5127, 5146, 8146, 8207
    ]  # fmt: skip
    q = result.face_energy * result.face_area
    assert q[2606] == pytest.approx(0.70339, abs=5e-6)
    assert result.face_area[2606] == pytest.approx(0.014266, abs=5e-7)
    assert morphotester_dne(thero).dne == 249.806


def test_theropithecus_condition_check_zeroes_faces_0_4_73_5930_and_8778(thero):
    result = morphotester_dne(thero)
    assert list(np.flatnonzero(result.ill_conditioned)) == [0, 4, 73, 5930, 8778]
    assert not result.duplicate.any()
    assert (result.face_density[result.ill_conditioned] == 0).all()
    assert (result.face_area[result.ill_conditioned] == 1).all()


def test_theropithecus_face_1_energy_and_area_and_triangle_0_area(thero):
    result = morphotester_dne(thero)
    assert result.face_density[1] == pytest.approx(6.276453180651151, rel=1e-15)
    assert result.face_area[1] == pytest.approx(0.024020901165739069, rel=1e-15)
    assert mt.face_areas(*thero)[0] == pytest.approx(6.5565e-06, rel=1e-4)


def test_the_small_mesh_has_boundary_faces_0_2_and_3_by_the_leg_rule():
    faces = np.array([[0, 1, 3], [1, 3, 4], [1, 2, 4], [3, 4, 5]])
    assert list(np.flatnonzero(mt.boundary_faces(faces))) == [0, 2, 3]


def test_boundary_faces_are_zeroed_before_the_sum_without_outliers():
    density, area = np.arange(1.0, 8.0), np.arange(2.0, 9.0)
    boundary = np.isin(np.arange(7), [1, 3, 4])
    _, q, outlier, threshold = dne_quantities(density, area, boundary, None, 99.9)
    assert list(q) == [2, 0, 12, 0, 0, 42, 56] and q.sum() == 112.0
    assert not outlier.any() and math.isnan(threshold)


def test_the_pyramid_has_morphotester_normals():
    faces_n, vertex_n, negated = mt.normals(*pyramid())
    assert not negated
    np.testing.assert_allclose(faces_n[0], [0, -2 / 5**0.5, 1 / 5**0.5], atol=1e-15)
    np.testing.assert_allclose(vertex_n[4], [0, 0, 1], atol=1e-15)


def test_theropithecus_rfi_pixel_counts(thero):
    result = morphotester_rfi(thero)
    assert (result.rfi, result.surface_area, result.outline_area) == (2.178, 213.537, 98.056)
    assert (result.red, result.blue, 480_000 - result.blue) == (480, 101_564, 378_436)
    assert result.length == pytest.approx(14.9145, abs=1e-12)
    assert result.scale == pytest.approx(32.183445640148854, rel=1e-15)
    colours, counts = np.unique(result.image().reshape(-1, 4), axis=0, return_counts=True)
    found = {
        tuple(int(c) for c in colour): int(n) for colour, n in zip(colours, counts, strict=True)
    }
    assert found[(255, 255, 255, 255)] == 377_477 and found[(0, 0, 255, 255)] == 100_493
    assert found[(255, 0, 0, 255)] == 479 and found[(255, 127, 127, 255)] == 1
    assert found[(255, 205, 205, 255)] == 479 and found[(255, 230, 230, 255)] == 1


def test_cercocebus_rfi_pixel_counts(cerco):
    result = morphotester_rfi(cerco)
    assert (result.red, result.blue) == (480, 112_707)
    assert result.length == pytest.approx(9.37861, abs=1e-12)


def test_the_samples_opc_lists_and_their_gui_default_opcr(thero, cerco):
    assert morphotester_opcr(thero).opc == (79, 80, 77, 72, 75, 75, 79, 75)
    assert morphotester_opcr(cerco).opc == (70, 68, 68, 63, 67, 70, 68, 70)
    assert morphotester_opcr(thero, min_patch=3).opcr == 92.625
    assert morphotester_opcr(cerco, min_patch=3).opcr == 79.5
    assert morphotester_dne(cerco, outliers="energy_area").dne == 208.763


def test_aspects_and_bin_edges():
    normals = np.array([[0.0, 0, 1], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, -1, 0]])
    assert list(aspect(normals)) == [0, 0, 45, 90, 270]
    assert list(aspect_bin([337.5, 22.5, 360.0, 0.0, 22.4999, 67.5])) == [0, 1, 0, 0, 0, 2]


def test_the_outlier_percentile_is_numpys_linear_rule():
    values = np.random.default_rng(3).exponential(size=10_040)
    for p in (99.9, 50.0, 100.0, 0.01):
        assert percentile_linear(values, p) == pytest.approx(np.percentile(values, p), rel=1e-15)


# --- smoothing and its Cholesky rule ---------------------------------------------------------


def test_smoothed_cercocebus_energy_x_area_dne_is_the_described_175_06(cerco):
    assert morphotester_dne(cerco, smooth=True, outliers="energy_area").dne == 175.06


def test_smoothing_theropithecus_is_morphotester_cholesky_error(thero):
    with pytest.raises(ValueError, match=r"not positive definite.*face 5930.*Cholesky error"):
        morphotester_dne(thero, smooth=True)


def test_a_collinear_face_stops_morphotester_smoothing_but_not_dentopo_prepare():
    # its angles are 0, 0 and 180 degrees: MorphoTester's cot(180) is -8e15 (from the arccos),
    # the stable cotangent of a face without area is 0 (it adds nothing to L)
    vertices = np.array([[0.0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 1, 0]])
    faces = np.array([[0, 1, 2], [0, 2, 3], [3, 2, 4]])
    with pytest.raises(mt.NotPositiveDefiniteError, match="Cholesky"):
        mt.implicit_fairing(vertices, faces, iterations=3, step=0.1, cotangents="arccos")
    out = _smooth.run(vertices, faces, method="implicit", iterations=3, step=0.1)
    assert np.isfinite(out.vertices).all()


def test_prepare_smooths_with_the_checked_solve():
    assert _smooth.implicit_fairing is mt.implicit_fairing
    assert _smooth.cotangent_operator is mt.cotangent_operator


def test_positive_definiteness_is_decided_as_a_dense_cholesky_decides_it():
    rng = np.random.default_rng(7)
    decided = []
    for trial in range(200):
        n = int(rng.integers(1, 12))
        a = rng.normal(size=(n, n))
        a = a @ a.T if trial % 2 else (a + a.T) / 2
        a += np.eye(n) * rng.choice([-1.0, 0.0, 0.5, 3.0])
        if trial % 7 == 0:
            a[0, :] = a[:, 0] = 0.0  # singular, with a zero pivot
        try:
            np.linalg.cholesky(a)
            dense = True
        except np.linalg.LinAlgError:
            dense = False
        sparse = mt.positive_definite_solver(a) is not None
        decided.append((dense, sparse))
    assert all(dense == sparse for dense, sparse in decided)
    assert {d for d, _ in decided} == {True, False}


def test_pinned_implicit_fairing_solves_the_free_vertices_system(thero):
    vertices, faces = thero
    pinned = np.unique(faces[mt.boundary_faces(faces)])
    out = mt.implicit_fairing(vertices, faces, iterations=1, step=0.1, pinned=pinned)
    assert np.array_equal(out[pinned], vertices[pinned])
    free = np.setdiff1d(np.arange(len(vertices)), pinned)
    lap = mt.cotangent_operator(vertices, faces)
    residual = out - 0.1 * (lap @ out) - vertices
    assert np.abs(residual[free]).max() < 1e-12


# --- analytic cases and invariances ------------------------------------------------------------


def test_a_flat_plane_has_no_dne_no_patch_and_an_outline_just_above_its_area():
    plane = plane_patch(21)
    dne = morphotester_dne(plane)
    assert dne.dne == 0.0 and dne.n_boundary > 0
    opcr = morphotester_opcr(plane, min_patch=0)
    assert opcr.opcr == 0.0 and (opcr.face_bins == -1).all()  # horizontal: x component 0
    rfi = morphotester_rfi(plane)
    assert rfi.surface_area == 1.0
    assert 1.0 < rfi.outline_area < 1.03  # the 1 pt stroke and antialiasing: a little more


def test_a_hemisphere_has_dne_near_4_pi_and_a_dome_opcr_of_8():
    vertices, faces = dome()
    result = morphotester_dne((vertices, faces))
    assert result.dne == pytest.approx(4 * np.pi, rel=0.04)  # less its boundary ring
    assert result.n_boundary == 96 and result.n_outliers > 0
    opcr = morphotester_opcr((vertices, faces))
    assert opcr.opc == (8,) * 8 and opcr.opcr == 8.0


def test_vertex_order_and_face_order_change_no_morphotester_value(thero):
    vertices, faces = thero
    rng = np.random.default_rng(11)
    face_order, vertex_order = rng.permutation(len(faces)), rng.permutation(len(vertices))
    relabel = np.argsort(vertex_order)
    other = (vertices[vertex_order], relabel[faces[face_order]])
    for metric, key in (
        (morphotester_dne, "dne"),
        (morphotester_rfi, "blue"),
        (morphotester_opcr, "opc"),
    ):
        assert getattr(metric(other), key) == getattr(metric(thero), key)
    a, b = morphotester_dne(thero), morphotester_dne(other)
    np.testing.assert_allclose(b.face_quantity, a.face_quantity[face_order], rtol=1e-12, atol=0)


def test_a_translation_changes_nothing_on_a_well_shaped_dome_without_outlier_ties():
    vertices, faces = dome()
    moved = vertices + np.array([3.25, -7.5, 2.0])
    a = morphotester_dne((vertices, faces), outliers=None)
    b = morphotester_dne((moved, faces), outliers=None)
    assert b.dne == a.dne and b.dne_unrounded == pytest.approx(a.dne_unrounded, rel=1e-12)
    assert morphotester_opcr((moved, faces)).opc == morphotester_opcr((vertices, faces)).opc
    ra, rb = morphotester_rfi((vertices, faces)), morphotester_rfi((moved, faces))
    assert (rb.blue, rb.red, rb.rfi) == (ra.blue, ra.red, ra.rfi)


def test_ties_at_the_outlier_percentile_are_broken_by_rounding_so_a_translation_moves_them():
    # the faces of one ring of the dome have one energy, up to rounding: the 99.9th
    # percentile falls among them, and which of them lie above it is decided by rounding
    vertices, faces = dome()
    a = morphotester_dne((vertices, faces))
    b = morphotester_dne((vertices + np.array([3.25, -7.5, 2.0]), faces))
    top = a.face_density[a.outlier]
    assert np.ptp(top) < 1e-9 * top.max()  # every outlier is one of the tied faces
    assert not np.array_equal(a.outlier, b.outlier)
    assert a.dne_unrounded != pytest.approx(b.dne_unrounded, rel=1e-9)


def test_a_translation_moves_morphotester_dne_where_a_degenerate_face_normal_is_noise(thero):
    # face 5930's corners are collinear to 1e-13 degrees: its unit normal is rounding noise,
    # summed unweighted into its corners' normals; moving the crown changes that noise
    vertices, faces = thero
    moved = morphotester_dne((vertices + np.array([100.0, -50.0, 30.0]), faces))
    here = morphotester_dne(thero)
    assert moved.dne != here.dne
    changed = np.flatnonzero(~np.isclose(moved.face_quantity, here.face_quantity, rtol=1e-6))
    near = np.flatnonzero(np.isin(faces, faces[5930]).any(axis=1))
    assert set(changed) <= set(near) and len(changed) > 0


def test_a_translation_can_turn_every_bin_label_by_four_through_the_vote_but_no_count():
    plane = plane_patch(11)
    vertices = plane.vertices.copy()
    vertices[:, 2] = 0.3 * vertices[:, 0] + 0.2 * vertices[:, 1]  # normal (-0.3, -0.2, 1)
    moved = vertices + np.array(
        [-5.0, -5.0, 0.0]
    )  # every one of the vote's three sums changes sign
    assert mt.normals(vertices, plane.faces)[2] != mt.normals(moved, plane.faces)[2]
    a, b = morphotester_opcr((vertices, plane.faces)), morphotester_opcr((moved, plane.faces))
    assert ((b.face_bins - a.face_bins) % 8 == 4).all()
    assert a.opc == b.opc == (1,) * 8


def test_reversing_every_face_changes_no_bin_label_as_the_vote_undoes_it(cerco):
    vertices, faces = cerco
    flipped = (vertices, faces[:, ::-1].copy())
    assert np.array_equal(morphotester_opcr(flipped).face_bins, morphotester_opcr(cerco).face_bins)
    assert morphotester_dne(flipped).dne == morphotester_dne(cerco).dne


def test_turning_the_crown_about_z_changes_morphotester_outline_area(thero):
    vertices, faces = thero
    t = np.radians(30.0)
    turn = np.array([[np.cos(t), -np.sin(t), 0], [np.sin(t), np.cos(t), 0], [0, 0, 1]])
    turned = morphotester_rfi((vertices @ turn.T, faces))
    here = morphotester_rfi(thero)
    assert turned.surface_area == here.surface_area
    assert turned.outline_area != here.outline_area  # 98.009 against 98.056


def test_morphotester_rfi_depends_on_the_mesh_unit(thero):
    # the axis margins are 0.5 units and the strokes 1 pt, whatever the unit
    vertices, faces = thero
    assert morphotester_rfi((vertices * 1000, faces)).rfi != morphotester_rfi(thero).rfi
    with pytest.raises(ValueError, match="too small in its own units"):
        morphotester_rfi((vertices / 1000, faces))


def test_a_users_matplotlib_style_does_not_change_the_pixel_count():
    vertices, faces = dome(16, 32)
    vertices = vertices * [3.0, 2.0, 1.0]
    plain = morphotester_rfi((vertices, faces))
    style = {
        "path.snap": False,
        "patch.antialiased": False,
        "patch.linewidth": 4.0,
        "lines.antialiased": False,
        "figure.dpi": 37,
        "figure.figsize": (3.0, 2.0),
        "figure.subplot.left": 0.3,
        "savefig.dpi": 300,
        "axes.xmargin": 0.4,
        "agg.path.chunksize": 10,
    }
    with contextlib.ExitStack() as stack:
        stack.enter_context(mpl.style.context("dark_background"))
        stack.enter_context(mpl.rc_context(style))
        styled = morphotester_rfi((vertices, faces))
        assert mpl.rcParams["path.snap"] is False  # the user's style is left as it was
    assert (styled.blue, styled.red) == (plain.blue, plain.red)
    assert np.array_equal(styled.image(), plain.image())


# --- inputs --------------------------------------------------------------------------------------


def test_inputs_are_never_modified():
    vertices, faces = dome(8, 16)
    mesh = trimesh.Trimesh(vertices.copy(), faces.copy(), process=False)
    keep = (vertices.copy(), faces.copy())
    for metric in (morphotester_dne, morphotester_rfi, morphotester_opcr):
        metric((vertices, faces))
        metric(mesh)
    morphotester_dne((vertices, faces), smooth=True)
    assert np.array_equal(vertices, keep[0]) and np.array_equal(faces, keep[1])
    assert np.array_equal(mesh.vertices, keep[0]) and np.array_equal(mesh.faces, keep[1])


def test_results_are_read_only_and_their_tables_hold_scalars():
    mesh = dome(8, 16)
    dne = morphotester_dne(mesh)
    assert list(dne.to_dict()) == list(MORPHOTESTER_DNE_FIELDS)
    for value in dne.to_dict().values():
        assert value is None or isinstance(value, (bool, int, float, str))
    with pytest.raises(ValueError):
        dne.face_energy[0] = 1.0
    opcr = morphotester_opcr(mesh)
    assert opcr.face_bins.dtype == np.int8 and not opcr.face_bins.flags.writeable
    assert opcr.to_dict()["opc_39.375"] == opcr.opc[-1]
    assert not morphotester_rfi(mesh).image().flags.writeable
    assert "<table" in dne._repr_html_()


@pytest.mark.parametrize(
    ("options", "named"),
    [
        ({"percentile": 100.5}, "percentile"),
        ({"percentile": float("nan")}, "percentile"),
        ({"percentile": 0}, "percentile"),
        ({"percentile": True}, "percentile"),
        ({"outliers": "area"}, "outliers"),
        ({"condition_check": "yes"}, "condition_check"),
        ({"smooth": 1}, "smooth"),
    ],
)
def test_bad_dne_options_are_named(options, named):
    with pytest.raises(ValueError, match=named):
        morphotester_dne(dome(8, 16), **options)


@pytest.mark.parametrize("min_patch", [-1, True, 2.5, "5"])
def test_a_bad_min_patch_is_named(min_patch):
    with pytest.raises(ValueError, match="min_patch"):
        morphotester_opcr(dome(8, 16), min_patch=min_patch)


@pytest.mark.parametrize("metric", [morphotester_dne, morphotester_rfi, morphotester_opcr])
def test_meshes_without_faces_or_with_non_finite_coordinates_are_named(metric):
    vertices, faces = dome(8, 16)
    with pytest.raises(ValueError, match="no faces"):
        metric((vertices, np.zeros((0, 3), dtype=np.int64)))
    bad = vertices.copy()
    bad[3, 1] = np.nan
    with pytest.raises(ValueError, match=r"finite|NaN"):
        metric((bad, faces))


def test_a_mesh_without_extent_in_y_is_morphotester_l_1_error():
    vertices = np.array([[0.0, 0, 0], [1, 0, 0], [1, 0, 1], [0, 0, 1]])
    faces = np.array([[0, 1, 2], [0, 2, 3]])
    with pytest.raises(ValueError, match=r"no extent in y.*L = 1"):
        morphotester_rfi((vertices, faces))
    with pytest.raises(ValueError, match="no extent in x"):
        morphotester_rfi((vertices[:, [1, 0, 2]], faces))


def test_a_collinear_face_without_the_condition_check_is_morphotester_abort():
    vertices, faces = dome(8, 16)
    vertices = np.vstack([vertices, [[2.0, 0, 0], [3, 0, 0], [4, 0, 0]]])
    faces = np.vstack([faces, [[len(vertices) - 3, len(vertices) - 2, len(vertices) - 1]]])
    with pytest.raises(ValueError, match=f"face {len(faces) - 1}.*singular"):
        morphotester_dne((vertices, faces), condition_check=False)
    assert morphotester_dne((vertices, faces)).ill_conditioned[-1]  # the check zeroes it


def test_a_mesh_of_boundary_faces_only_has_nothing_to_measure():
    vertices = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [5, 5, 5]])
    with pytest.raises(ValueError, match="boundary faces"):
        morphotester_dne((vertices, np.array([[0, 1, 2]])))


def test_loaded_and_cleaned_samples_measure_as_read_float32(thero):
    # dentopo's reader for the other metrics (float32, coincident vertices merged): what
    # the morphotester metrics then measure
    mesh = load_mesh(DATA / f"{THERO}.ply")
    assert len(mesh.vertices) == len(thero[0])  # no coincident vertices to merge here
    assert morphotester_dne(mesh).dne == 249.804
    assert morphotester_rfi(mesh).rfi == 2.178 and morphotester_opcr(mesh).opcr == 76.5


def test_the_raster_is_800_by_600_with_the_box_480_px_high(thero):
    raster = footprint.render_outline(*thero)
    assert raster.image.shape == (600, 800, 4) and raster.red == 480
