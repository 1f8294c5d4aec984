"""Classic DNE as molaR computes it: analytic checks and molaR's own numbers."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from conftest import plane_patch, shared_mesh
from dentopo import classic_dne

#: molaR 6.0's output on normal.ply (CLASSIC_DNE.md).
MOLAR_NORMAL = {
    "dne": 290.094956260407,
    "convex_dne": 208.881100454037,
    "concave_dne": 81.2138558063703,
    "convex_area": 48.3409421246734,
    "concave_area": 19.5215786676238,
}


def test_matches_molar_on_normal():
    result = classic_dne(shared_mesh("normal"))
    assert result.dne == pytest.approx(MOLAR_NORMAL["dne"], rel=1e-6)
    for key in ("convex_dne", "concave_dne", "convex_area", "concave_area"):
        assert getattr(result, key) == pytest.approx(MOLAR_NORMAL[key], rel=1e-4), key


def test_plane_has_zero_energy_and_is_concave(plane):
    result = classic_dne(plane)
    assert result.dne == 0.0
    # molaR gives a vertex used by one face a zero normal: the two corner faces
    # of this triangulation have energy, but they are boundary faces
    uses = np.bincount(plane.faces.ravel())
    lonely = (uses[plane.faces] == 1).any(axis=1)
    assert lonely.sum() == 2 and result.excluded[lonely].all()
    assert np.abs(result.face_energy[~lonely]).max() < 1e-12
    # kappa is 0 on a plane, and ties count as concave
    assert result.convex_area == 0.0
    assert result.concave_area == pytest.approx(1.0)


def test_sphere_approaches_eight_pi():
    # the Dirichlet energy of the normal of any sphere is 8 pi
    coarse = classic_dne(trimesh.creation.icosphere(subdivisions=3), outliers=0.0).dne
    fine = classic_dne(trimesh.creation.icosphere(subdivisions=4), outliers=0.0).dne
    assert abs(fine - 8 * np.pi) < abs(coarse - 8 * np.pi) < 0.01 * 8 * np.pi


def test_closed_mesh_has_no_boundary_faces(sphere):
    result = classic_dne(sphere)
    assert result.boundary_faces == 0
    assert result.convex.all()
    assert result.convex_dne == result.dne > 0


def test_scale_and_rigid_motion_invariance(tooth):
    base = classic_dne(tooth)
    moved = tooth.copy()
    rotation = trimesh.transformations.random_rotation_matrix(np.random.default_rng(0).random(3))
    moved.apply_transform(rotation)
    moved.apply_scale(37.5)
    other = classic_dne(moved)
    for key in ("dne", "convex_dne", "concave_dne"):
        assert getattr(other, key) == pytest.approx(getattr(base, key), rel=1e-9), key
    assert other.convex_area == pytest.approx(37.5**2 * base.convex_area, rel=1e-9)
    assert np.array_equal(other.convex, base.convex)


def test_boundary_modes_on_a_plane_patch():
    patch = plane_patch(5)  # 16 boundary vertices, 16 boundary edges, 32 faces
    assert classic_dne(patch, boundary="vertex").boundary_faces == 32 - 8
    assert classic_dne(patch, boundary="leg").boundary_faces == 16 - 2
    assert classic_dne(patch, boundary="None").boundary_faces == 0


def test_split_and_per_face_arrays_are_consistent(tooth):
    result = classic_dne(tooth, outliers=1.0)
    assert result.convex_dne + result.concave_dne == pytest.approx(result.dne, rel=1e-12)
    assert result.face_dne.sum() == pytest.approx(result.dne, rel=1e-12)
    assert np.all(result.face_dne[result.excluded] == 0.0)
    assert result.convex_area + result.concave_area == pytest.approx(tooth.area, rel=1e-12)
    assert np.allclose(result.face_area, tooth.area_faces)
    assert result.boundary_faces > 0 and result.outlier_faces > 0
    assert result.excluded.sum() == result.boundary_faces + result.outlier_faces
    assert result.to_dict()["dne"] == result.dne


def test_outlier_quantile_is_r_type_7(tooth):
    # with 1 % outliers, the faces dropped are exactly those above numpy's linear quantile
    result = classic_dne(tooth, outliers=1.0, boundary="none")
    q = np.quantile(result.face_energy, 0.99)
    assert np.array_equal(result.excluded, result.face_energy > q)
    assert classic_dne(tooth, outliers=0.0, boundary="none").outlier_faces == 0


def test_separate_outlier_mode_changes_the_split(tooth):
    combined = classic_dne(tooth, outliers=5.0)
    separate = classic_dne(tooth, outliers=5.0, outlier_mode="separate")
    assert separate.convex_area == combined.convex_area
    assert (separate.convex_dne, separate.concave_dne) != (
        combined.convex_dne,
        combined.concave_dne,
    )


def test_caller_mesh_unchanged(tooth):
    vertices, faces = tooth.vertices.copy(), tooth.faces.copy()
    classic_dne(tooth)
    assert np.array_equal(tooth.vertices, vertices)
    assert np.array_equal(tooth.faces, faces)


@pytest.mark.parametrize(
    ("options", "error", "words"),
    [
        ({"outliers": -1}, ValueError, "outliers"),
        ({"outliers": 101}, ValueError, "outliers"),
        ({"outliers": "0.1"}, TypeError, "outliers"),
        ({"kappa": float("nan")}, ValueError, "kappa"),
        ({"boundary": "edge"}, ValueError, "boundary"),
        ({"outlier_mode": "s"}, ValueError, "outlier_mode"),
    ],
)
def test_bad_options(sphere, options, error, words):
    with pytest.raises(error, match=words):
        classic_dne(sphere, **options)
