"""Analytic and structural truths of ariaDNE on generated meshes."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh
from scipy.spatial.transform import Rotation

from conftest import plane_patch
from dentopo import AriaDNEResult, ariaDNE

SCALARS = ("dne", "positive_dne", "negative_dne")


def test_sphere_is_convex_everywhere(sphere):
    result = ariaDNE(sphere)
    assert np.all(result.local_curvature > 0)
    assert result.negative_dne == 0.0
    assert result.negative_surface_area == 0.0
    assert result.positive_dne == result.dne > 0


@pytest.mark.parametrize("radius", [0.01, 1.0, 250.0])
def test_sphere_bending_does_not_depend_on_radius(radius):
    unit = ariaDNE(trimesh.creation.icosphere(subdivisions=3))
    scaled = ariaDNE(trimesh.creation.icosphere(subdivisions=3, radius=radius))
    assert scaled.dne == pytest.approx(unit.dne, rel=1e-9)
    assert scaled.surface_area == pytest.approx(4 * np.pi * radius**2, rel=0.01)


def test_plane_has_zero_bending(plane):
    result = ariaDNE(plane)
    assert np.max(np.abs(result.local_curvature)) < 1e-12
    assert result.dne < 1e-12


def test_tooth_has_convex_cusps_and_concave_basin(tooth):
    result = ariaDNE(tooth)
    vertices = np.asarray(result.mesh.vertices)
    centre = np.argmin(np.linalg.norm(vertices[:, :2], axis=1))
    cusp = np.argmin(np.linalg.norm(vertices[:, :2] - [0.45, 0.45], axis=1))
    assert result.local_curvature[centre] < 0, "the central basin is concave"
    assert result.local_curvature[cusp] > 0, "a cusp tip is convex"
    assert 0 < result.negative_dne < result.positive_dne


def test_positive_plus_negative_is_total(tooth):
    result = ariaDNE(tooth)
    assert result.positive_dne + result.negative_dne == pytest.approx(result.dne, rel=1e-14)
    assert result.positive_surface_area + result.negative_surface_area == pytest.approx(
        result.surface_area, rel=1e-14
    )
    assert np.allclose(result.local_dne.sum(), result.positive_dne - result.negative_dne)


def _assert_same(a: AriaDNEResult, b: AriaDNEResult, permutation=None):
    for key in SCALARS:
        assert getattr(b, key) == pytest.approx(getattr(a, key), rel=1e-9, abs=1e-15), key
    expected = a.local_curvature if permutation is None else a.local_curvature[permutation]
    np.testing.assert_allclose(b.local_curvature, expected, rtol=0, atol=1e-9)
    np.testing.assert_array_equal(np.sign(b.local_curvature), np.sign(expected))


def test_invariant_under_rotation_translation_and_scaling(tooth):
    base = ariaDNE(tooth)
    rotation = Rotation.from_euler("xyz", [0.3, -1.1, 2.0]).as_matrix()
    moved = np.asarray(tooth.vertices) @ rotation.T * 37.5 + [100.0, -20.0, 3.0]
    _assert_same(base, ariaDNE((moved, tooth.faces)))


@pytest.mark.parametrize("seed", [0, 1])
def test_invariant_under_vertex_and_face_order(tooth, seed):
    rng = np.random.default_rng(seed)
    base = ariaDNE(tooth)
    n = len(tooth.vertices)
    new_of_old = rng.permutation(n)
    vertices = np.empty_like(tooth.vertices)
    vertices[new_of_old] = tooth.vertices
    faces = new_of_old[tooth.faces][rng.permutation(len(tooth.faces))]
    shuffled = ariaDNE((vertices, faces))
    old_of_new = np.argsort(new_of_old)
    _assert_same(base, shuffled, permutation=old_of_new)


def test_rotated_sphere_gives_identical_signs(sphere):
    base = np.sign(ariaDNE(sphere).local_curvature)
    for angles in ([0.1, 0.2, 0.3], [1.0, -2.0, 0.5]):
        rotation = Rotation.from_euler("xyz", angles).as_matrix()
        turned = ariaDNE((sphere.vertices @ rotation.T, sphere.faces))
        np.testing.assert_array_equal(np.sign(turned.local_curvature), base)


def test_geodesic_equals_euclidean_on_a_plane(plane):
    euclidean = ariaDNE(plane)
    geodesic = ariaDNE(plane, distance_type="geodesic")
    assert geodesic.distance_type == "geodesic"
    np.testing.assert_allclose(geodesic.local_curvature, euclidean.local_curvature, atol=1e-12)
    assert geodesic.dne == pytest.approx(euclidean.dne, abs=1e-12)


def test_geodesic_on_sphere_is_convex_and_below_euclidean(sphere):
    """Edge paths are longer than chords, so the kernel is effectively narrower."""
    euclidean = ariaDNE(sphere)
    geodesic = ariaDNE(sphere, distance_type="Geodesic")
    assert np.all(geodesic.local_curvature > 0)
    assert 0.6 * euclidean.dne < geodesic.dne < euclidean.dne


def test_geodesic_matches_dense_dijkstra_reference(tooth):
    """The bounded, blocked Dijkstra equals a precomputed all-pairs matrix."""
    from scipy.sparse.csgraph import dijkstra

    from dentopo.ariadne._kernel import edge_graph

    geodesic = ariaDNE(tooth, distance_type="geodesic")
    points = np.asarray(geodesic.mesh.vertices) / np.sqrt(geodesic.surface_area)
    distances = dijkstra(edge_graph(points, np.asarray(geodesic.mesh.faces)), directed=False)
    dense = ariaDNE(tooth, precomputed_dist=distances)
    np.testing.assert_allclose(geodesic.local_curvature, dense.local_curvature, atol=1e-12)


def test_cutoff_drops_far_neighbours(tooth):
    full = ariaDNE(tooth)
    cut = ariaDNE(tooth, cutoff=0.5)
    assert cut.cutoff == 0.5
    assert cut.dne != pytest.approx(full.dne, rel=1e-3)
    tiny = ariaDNE(tooth, cutoff=1e-300)
    assert tiny.dne == pytest.approx(full.dne, rel=1e-12)


def test_larger_bandwidth_changes_the_scale(tooth):
    assert ariaDNE(tooth, bandwidth=0.04).dne != pytest.approx(ariaDNE(tooth, bandwidth=0.12).dne)


def test_callers_mesh_is_not_modified(tooth):
    vertices = tooth.vertices.copy()
    faces = tooth.faces.copy()
    ariaDNE(tooth)
    np.testing.assert_array_equal(tooth.vertices, vertices)
    np.testing.assert_array_equal(tooth.faces, faces)
    arrays = (vertices.copy(), faces.copy())
    ariaDNE(arrays)
    np.testing.assert_array_equal(arrays[0], vertices)
    np.testing.assert_array_equal(arrays[1], faces)


def test_open_mesh_with_holes_is_capped_without_touching_input():
    mesh = trimesh.creation.icosphere(subdivisions=3)
    mesh = trimesh.Trimesh(mesh.vertices, mesh.faces[20:], process=False)  # a big hole
    before = mesh.faces.copy()
    result = ariaDNE(mesh)
    np.testing.assert_array_equal(mesh.faces, before)
    assert np.mean(result.local_curvature > 0) > 0.95


def test_inconsistently_oriented_faces_give_same_result(sphere):
    faces = sphere.faces.copy()
    faces[::3] = faces[::3, ::-1]
    flipped = ariaDNE((sphere.vertices, faces))
    base = ariaDNE(sphere)
    np.testing.assert_allclose(flipped.local_curvature, base.local_curvature, atol=1e-12)


def test_result_record(tooth):
    result = ariaDNE(tooth, bandwidth=0.1)
    row = result.to_dict()
    assert list(row) == [
        "dne",
        "positive_dne",
        "negative_dne",
        "surface_area",
        "positive_surface_area",
        "negative_surface_area",
        "vertices",
        "faces",
        "bandwidth",
        "cutoff",
        "distance_type",
        "sign_method",
        "method",
    ]
    assert row["bandwidth"] == 0.1 and row["distance_type"] == "euclidean"
    assert row["sign_method"] == "centroid"
    assert row["vertices"] == len(tooth.vertices) and row["faces"] == len(tooth.faces)
    assert result.local_dne.shape == result.local_curvature.shape == (len(tooth.vertices),)


def test_path_and_arrays_agree(tmp_path, tooth):
    path = tmp_path / "crown with space é.ply"
    tooth.export(path)
    from_path = ariaDNE(path)
    from_str = ariaDNE(str(path))
    loaded = trimesh.load(path)  # PLY stores float32 coordinates
    from_arrays = ariaDNE((loaded.vertices, loaded.faces))
    assert from_path.dne == pytest.approx(from_arrays.dne, rel=1e-12)
    assert from_str.dne == from_path.dne


def test_plane_patch_helper_is_flat():
    assert np.ptp(plane_patch().vertices[:, 2]) == 0
