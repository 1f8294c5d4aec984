"""Comparison signs from trimesh's discrete curvature measures."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from dentopo import ariaDNE, curvature_measure, curvature_measure_sign, measure_radius
from dentopo.mesh import outward_faces


def test_radius_rule_is_bandwidth_times_sqrt_area():
    assert measure_radius(9.0, 0.08) == pytest.approx(0.24)
    assert measure_radius(9.0, 0.08, factor=2.0) == pytest.approx(0.48)
    with pytest.raises(ValueError, match="bandwidth"):
        measure_radius(1.0, 0.0)


@pytest.mark.parametrize("kind", ["mean", "gaussian"])
def test_same_numbers_as_trimesh(tooth, kind):
    ours = curvature_measure(tooth, kind, 0.08)
    mesh = trimesh.Trimesh(
        tooth.vertices, outward_faces(tooth.vertices, tooth.faces), process=False
    )
    radius = 0.08 * np.sqrt(mesh.area)
    reference = getattr(trimesh.curvature, f"discrete_{kind}_curvature_measure")
    np.testing.assert_allclose(ours, reference(mesh, mesh.vertices, radius), atol=1e-12)


def test_signs_on_the_tooth_cusps_basin_and_flanks(tooth):
    vertices = np.asarray(tooth.vertices)
    centre = int(np.argmin(np.linalg.norm(vertices[:, :2], axis=1)))
    cusp = int(np.argmin(np.linalg.norm(vertices[:, :2] - [0.45, 0.45], axis=1)))
    mean = curvature_measure_sign(tooth, "mean_curvature", 0.08)
    gauss = curvature_measure_sign(tooth, "gaussian", 0.08)
    assert mean[cusp] == 1.0 and mean[centre] == -1.0  # convex cusp, concave basin
    assert gauss[cusp] == 1.0 and gauss[centre] == 1.0  # both elliptic


def test_invariant_to_units_and_winding(tooth):
    flipped = trimesh.Trimesh(tooth.vertices * 25.0, tooth.faces[:, ::-1], process=False)
    np.testing.assert_array_equal(
        curvature_measure_sign(flipped, "mean", 0.08), curvature_measure_sign(tooth, "mean", 0.08)
    )


def test_agrees_with_ariadne_mean_curvature_sign_method(tooth):
    result = ariaDNE(tooth, sign_method="mean_curvature")
    sign = curvature_measure_sign(result.mesh, "mean", result.bandwidth)
    bent = np.abs(result.local_curvature) > 0
    np.testing.assert_array_equal(np.sign(result.local_curvature[bent]), sign[bent])


def test_caller_mesh_is_not_modified(tooth):
    inward = trimesh.Trimesh(tooth.vertices, tooth.faces[:, ::-1], process=False)
    faces, vertices = inward.faces.copy(), inward.vertices.copy()
    curvature_measure_sign(inward, "mean", 0.1)  # flips a copy of the faces outward
    np.testing.assert_array_equal(inward.faces, faces)
    np.testing.assert_array_equal(inward.vertices, vertices)


def test_unknown_kind_is_refused(tooth):
    with pytest.raises(ValueError, match="kind"):
        curvature_measure(tooth, "principal", 0.08)


@pytest.mark.parametrize("kind", ["mean", "gaussian"])
def test_the_chunks_do_not_change_a_bit(tooth, kind, monkeypatch):
    # each vertex's neighbours come in the k-d tree's order whatever the chunk, so that
    # a budget of pairs per chunk (small here: chunks of a few vertices) changes no sum
    from dentopo.sign import _measures

    whole = curvature_measure(tooth, kind, 0.3)
    monkeypatch.setattr(_measures, "PAIRS_PER_CHUNK", 5000)
    assert len(_measures._chunks(np.asarray(tooth.vertices), tooth.vertices, 0.5)) > 10
    assert curvature_measure(tooth, kind, 0.3).tobytes() == whole.tobytes()


def test_the_pair_bound_is_an_upper_bound(tooth):
    from scipy.spatial import cKDTree

    from dentopo.sign._measures import _ball_count_bound

    rng = np.random.default_rng(1)
    points = np.vstack([tooth.vertices, [[1e6, 0, 0]]])  # and one far away
    items = rng.normal(size=(3000, 3))
    for radius in (0.05, 0.3, 5.0):
        exact = cKDTree(items).query_ball_point(points, radius, return_length=True)
        bound = _ball_count_bound(points, items, radius)
        assert (bound >= exact).all() and (bound <= len(items)).all()
        assert bound.sum() > 0


def test_long_edges_add_the_same_as_trimesh():
    # a vertex far out: its edges are searched for on their own, among the vertices
    # within reach of each, instead of widening every vertex's search
    from dentopo.samples import tooth as make_tooth

    crown = make_tooth(rings=12)
    vertices = np.array(crown.vertices)
    vertices[len(vertices) // 2] += 10.0 * np.ptp(vertices, axis=0).max()
    mesh = trimesh.Trimesh(vertices, outward_faces(vertices, crown.faces), process=False)
    radius = 0.02 * np.sqrt(mesh.area)
    lengths = mesh.edges_unique_length
    assert (lengths > max(8 * np.median(lengths), 2 * radius)).any()  # the case tested
    ours = curvature_measure(mesh, "mean", 0.02)
    reference = trimesh.curvature.discrete_mean_curvature_measure(mesh, mesh.vertices, radius)
    np.testing.assert_allclose(ours, reference, atol=1e-12)
