"""ARC (molaR's and doolkit's) and the VCG float32 curvature: parity, analytic cases."""

from __future__ import annotations

import csv

import numpy as np
import pytest
import trimesh

from conftest import MESHES, REFERENCE, ROBUSTNESS_SET, hemisphere, plane_patch, shared_mesh
from dentopo.topography import (
    ARC_FIELDS,
    DOOLKIT_ARC_FIELDS,
    ARCResult,
    DoolkitARCResult,
    arc,
    doolkit_arc,
    prepare_surface,
)
from dentopo.topography.surface import _vcg

TOLERANCE = 1e-6


def _rows(name: str) -> dict:
    path = REFERENCE / name
    if not path.exists():
        pytest.skip(f"reference values not found at {path}")
    with path.open(newline="") as handle:
        return {row["file"].removesuffix(".ply"): row for row in csv.DictReader(handle)}


@pytest.fixture(scope="module")
def molar_rows():
    return _rows("molaR_6.0_topography.csv")


@pytest.fixture(scope="module")
def doolkit_rows():
    return _rows("doolkit_1.42.2_topography.csv")


def _relative(value: float, expected: float) -> float:
    return abs(value - expected) / abs(expected)


# ---------------------------------------------------------------------------
# parity with the tools


@pytest.mark.parametrize("name", ROBUSTNESS_SET)
def test_matches_molar(name, molar_rows):
    result = arc(shared_mesh(name))
    row = molar_rows[name]
    for field, column in zip(ARC_FIELDS, ("ARC", "ARC_positive", "ARC_negative"), strict=True):
        assert _relative(getattr(result, field), float(row[column])) <= TOLERANCE, column


@pytest.mark.parametrize("name", ROBUSTNESS_SET)
def test_matches_doolkit(name, doolkit_rows):
    result = doolkit_arc(shared_mesh(name))
    row = doolkit_rows[name]
    for field in DOOLKIT_ARC_FIELDS:
        assert _relative(getattr(result, field), float(row[field])) <= TOLERANCE, field


@pytest.mark.parametrize(
    "name", sorted(p.stem for p in MESHES.glob("*.ply")) if MESHES.exists() else ["normal"]
)
def test_every_shared_mesh_runs(name):
    surface = prepare_surface(shared_mesh(name))
    for result in (arc(surface), arc(surface, boundary="leg"), doolkit_arc(surface)):
        values = result.face_arc
        assert values.shape == (len(surface.faces),) and np.isfinite(values).all()
    closed = len(surface.boundary_edges()) == 0
    if closed:
        assert arc(surface).boundary_faces == 0 and doolkit_arc(surface).border_faces == 0


# ---------------------------------------------------------------------------
# the estimator on shapes with known curvature


def _vertex_curvature(mesh):
    surface = prepare_surface(mesh)
    v32 = _vcg.to_float32(surface.vertices)
    normals = _vcg.vertex_normals(v32, surface.faces)
    return surface, _vcg.mean_curvature(v32, surface.faces, normals)


@pytest.mark.parametrize("radius", [1.0, 7.5])
def test_sphere_mean_curvature_is_one_over_r(radius):
    surface, h = _vertex_curvature(trimesh.creation.icosphere(subdivisions=5, radius=radius))
    assert h.dtype == np.float32
    np.testing.assert_allclose(h * radius, 1.0, atol=0.01)  # outward normals: convex is +
    # reversed winding: the normals point inwards, the sign flips (the corner whose angle
    # is derived from pi changes, hence float32 rounding differences)
    inverted = trimesh.Trimesh(surface.vertices, surface.faces[:, ::-1], process=False)
    _, flipped = _vertex_curvature(inverted)
    np.testing.assert_allclose(flipped, -h, rtol=1e-5)


def test_hemisphere_interior_is_one_over_r():
    mesh = hemisphere(rings=64, segments=128)
    surface, h = _vertex_curvature(mesh)
    interior = ~_vcg.border_vertices(surface)
    z = surface.vertices[:, 2]
    # away from the border and the pole (where the latitude grid's faces are slivers)
    inner = interior & (z > 0.1) & (z < 0.95)
    assert inner.sum() > 1000
    np.testing.assert_allclose(h[inner], 1.0, atol=0.01)


def test_plane_has_zero_curvature():
    surface, h = _vertex_curvature(plane_patch(15))
    # Meyer's operator is applied as it is at the border (the border faces are zeroed later)
    interior = ~_vcg.border_vertices(surface)
    assert np.abs(h[interior]).max() < 1e-5 and np.abs(h[~interior]).max() > 1
    assert doolkit_arc(plane_patch(15)).arc_mean == pytest.approx(0.0, abs=1e-4)
    assert arc(plane_patch(15)).arc == pytest.approx(0.0, abs=1e-4)


def test_face_max_takes_the_largest_magnitude_first_wins():
    values = np.array([1.0, -3.0, 3.0, 2.0], dtype=np.float32)
    faces = np.array([[0, 1, 2], [0, 2, 1], [3, 0, 0]])
    assert _vcg.face_max(values, faces).tolist() == [-3.0, 3.0, 2.0]


def test_quantile7_is_r_type_7():
    x = np.array([3.0, 1.0, 4.0, 1.0, 5.0, 9.0, 2.0, 6.0])
    for p in (0.0, 0.01, 0.25, 0.5, 0.99, 1.0):
        assert _vcg.quantile7(x, p) == pytest.approx(np.quantile(x, p), rel=1e-15)


def test_border_rules_on_a_plane():
    surface = prepare_surface(plane_patch(5))  # a 4 x 4 grid of squares, 2 triangles each
    vertex = _vcg.border_faces(surface, "vertex")
    leg = _vcg.border_faces(surface, "leg")
    assert (leg <= vertex).all() and leg.sum() < vertex.sum() < len(surface.faces)
    assert not _vcg.border_faces(surface, "none").any()
    with pytest.raises(ValueError, match="border rule"):
        _vcg.border_faces(surface, "edge")


# ---------------------------------------------------------------------------
# invariances


def _crown():
    return trimesh.load(shared_mesh("low"), process=False)


def test_invariant_to_translation_and_scale():
    mesh = _crown()
    base_m, base_d = arc(mesh), doolkit_arc(mesh)
    moved = (mesh.vertices + np.array([3.0, -2.0, 5.0]), mesh.faces)
    assert arc(moved).arc == pytest.approx(base_m.arc, rel=1e-4)
    assert doolkit_arc(moved).arc_mean == pytest.approx(base_d.arc_mean, rel=1e-4)
    scaled = (mesh.vertices * 4.0, mesh.faces)  # exact in float32: a power of two
    assert arc(scaled).arc == pytest.approx(base_m.arc, rel=1e-12)
    assert doolkit_arc(scaled).arc_mean == pytest.approx(base_d.arc_mean, rel=1e-12)
    # molaR's rescaling makes any uniform scale irrelevant, up to float32 rounding
    assert arc((mesh.vertices * 3.7, mesh.faces)).arc == pytest.approx(base_m.arc, rel=1e-4)


def test_vertex_order_and_face_order():
    mesh = _crown()
    rng = np.random.default_rng(3)
    perm = rng.permutation(len(mesh.vertices))
    inverse = np.argsort(perm)
    permuted = (mesh.vertices[perm], inverse[mesh.faces])
    order = rng.permutation(len(mesh.faces))
    shuffled = (mesh.vertices, mesh.faces[order])
    for metric in (arc, doolkit_arc):
        base = metric(mesh)
        # vertex order does not change the float32 sums' order: the same per-face values
        np.testing.assert_array_equal(metric(permuted).face_arc, base.face_arc)
        # face order changes the order of the float32 sums: per-face values permuted, to rounding
        np.testing.assert_allclose(
            metric(shuffled).face_arc, base.face_arc[order], rtol=1e-4, atol=1e-5
        )


def test_input_not_modified():
    mesh = _crown()
    vertices, faces = mesh.vertices.copy(), mesh.faces.copy()
    arc(mesh)
    doolkit_arc(mesh)
    np.testing.assert_array_equal(mesh.vertices, vertices)
    np.testing.assert_array_equal(mesh.faces, faces)


def test_results_and_settings():
    mesh = _crown()
    result = arc(mesh, boundary="Leg", range=[0.05, 0.95])
    assert isinstance(result, ARCResult) and result.boundary == "leg"
    assert result.range == (0.05, 0.95)
    assert list(result.to_dict()) == list(ARC_FIELDS)
    assert arc(mesh, boundary="none").boundary_faces == 0
    values = result.face_arc
    assert result.arc == pytest.approx(values.mean())
    assert result.arc_positive == pytest.approx(values[values >= 0].mean())
    dk = doolkit_arc(mesh)
    assert isinstance(dk, DoolkitARCResult) and list(dk.to_dict()) == list(DOOLKIT_ARC_FIELDS)
    # doolkit clamps the tails where molaR zeroes them
    low, high = dk.face_arc.min(), dk.face_arc.max()
    assert (dk.face_arc == low).sum() > 1 and (dk.face_arc == high).sum() > 1
    # absolute limits (outside [0, 1]) clamp after the scaling
    limited = doolkit_arc(mesh, range=(-2.0, 2.0))
    assert limited.face_arc.min() >= -2.0 and limited.face_arc.max() <= 2.0


@pytest.mark.parametrize(
    ("kwargs", "error"),
    [
        ({"boundary": "edge"}, ValueError),
        ({"boundary": 1}, TypeError),
        ({"range": (0.9, 0.1)}, ValueError),
        ({"range": (0.1,)}, ValueError),
        ({"range": 0.5}, TypeError),
        ({"range": "ab"}, TypeError),
        ({"range": (0.1, np.nan)}, ValueError),
        ({"range": (0.1, True)}, TypeError),
        ({"range": (-0.1, 0.9)}, ValueError),
    ],
)
def test_bad_parameters_raise(kwargs, error):
    with pytest.raises(error):
        arc(plane_patch(5), **kwargs)


@pytest.mark.parametrize(
    "bad", [(0.9, 0.1), (0.1, np.inf), (0.1,), "ab", 3, (0.1, None), (1.0, 1.0)]
)
def test_doolkit_bad_range_raises(bad):
    with pytest.raises((TypeError, ValueError)):
        doolkit_arc(plane_patch(5), range=bad)
