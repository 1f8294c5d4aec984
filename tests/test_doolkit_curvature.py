"""doolkit's DNE and angularity (float32 VCG normals): parity, analytic cases, invariances."""

from __future__ import annotations

import csv

import numpy as np
import pytest
import trimesh

from conftest import MESHES, REFERENCE, ROBUSTNESS_SET, plane_patch, shared_mesh
from dentopo.topography import (
    ANGULARITY_FIELDS,
    DOOLKIT_DNE_FIELDS,
    AngularityResult,
    DoolkitDNEResult,
    angularity,
    doolkit_dne,
    prepare_surface,
)
from dentopo.topography.surface import _vcg

TOLERANCE = 1e-6


@pytest.fixture(scope="module")
def doolkit_rows():
    path = REFERENCE / "doolkit_1.42.2_topography.csv"
    if not path.exists():
        pytest.skip(f"doolkit reference values not found at {path}")
    with path.open(newline="") as handle:
        return {row["file"].removesuffix(".ply"): row for row in csv.DictReader(handle)}


@pytest.mark.parametrize("name", ROBUSTNESS_SET)
def test_dne_matches_doolkit(name, doolkit_rows):
    result = doolkit_dne(shared_mesh(name))
    row = doolkit_rows[name]
    expected = float(row["dne_total_unrounded"])
    assert abs(result.dne_total_unrounded - expected) <= TOLERANCE * abs(expected)
    assert round(result.dne_total, 3) == round(float(row["dne_total"]), 3)


@pytest.mark.parametrize("name", ROBUSTNESS_SET)
def test_angularity_matches_doolkit(name, doolkit_rows):
    result = angularity(shared_mesh(name))
    expected = float(doolkit_rows[name]["angularity_mean"])
    assert abs(result.angularity_mean - expected) <= TOLERANCE * abs(expected)


@pytest.mark.parametrize(
    "name", sorted(p.stem for p in MESHES.glob("*.ply")) if MESHES.exists() else ["normal"]
)
def test_every_shared_mesh_runs(name):
    surface = prepare_surface(shared_mesh(name))
    dne = doolkit_dne(surface)
    ang = angularity(surface)
    assert np.isfinite(dne.dne_total) and dne.dne_total > 0
    assert np.isfinite(ang.angularity_mean) and 0 <= ang.angularity_mean <= 90


def test_vertex_normals_are_float32_area_weighted():
    mesh = trimesh.creation.icosphere(subdivisions=3)
    v32 = _vcg.to_float32(mesh.vertices)
    normals = _vcg.vertex_normals(v32, mesh.faces)
    assert normals.dtype == np.float32
    unit = v32 / np.linalg.norm(v32, axis=1)[:, None]
    np.testing.assert_allclose(normals, unit, atol=0.02)
    # the area-weighted sum of face normals, normalised, as a double computation gives it
    weighted = np.zeros_like(mesh.vertices)
    for k in range(3):
        np.add.at(
            weighted,
            mesh.faces[:, k],
            np.cross(*(v32[mesh.faces[:, i]] - v32[mesh.faces[:, 0]] for i in (1, 2))),
        )
    weighted /= np.linalg.norm(weighted, axis=1)[:, None]
    np.testing.assert_allclose(normals, weighted, atol=1e-6)
    np.testing.assert_allclose(np.linalg.norm(normals, axis=1), 1.0, atol=1e-6)


def test_sphere_dne_is_eight_pi():
    # a unit sphere's normal map is the identity: energy density 2/r^2 over area 4 pi r^2
    for radius in (1.0, 3.0):
        result = doolkit_dne(trimesh.creation.icosphere(subdivisions=5, radius=radius))
        assert result.border_faces == 0
        assert result.dne_total_unrounded == pytest.approx(8 * np.pi, rel=0.01)
        area = result.face_area
        assert area.sum() == pytest.approx(4 * np.pi * radius**2, rel=0.01)


def test_plane_dne_and_angularity_are_zero():
    plane = plane_patch(9)
    assert doolkit_dne(plane).dne_total == 0.0
    assert angularity(plane).angularity_mean == 0.0


def test_outliers_at_or_above_the_quantile_are_zeroed():
    result = doolkit_dne(shared_mesh("normal"))
    kept = result.face_energy
    assert result.border_faces > 0 and result.outlier_faces > 0
    assert result.dne_total_unrounded == pytest.approx(float(np.sum(kept * result.face_area)))
    assert result.face_area.dtype == np.float64
    assert list(result.to_dict()) == list(DOOLKIT_DNE_FIELDS)
    everything = doolkit_dne(shared_mesh("normal"), range=1.0)
    assert everything.outlier_faces <= 1  # only faces equal to the maximum


def test_degenerate_gram_falls_back_to_rank_one():
    from dentopo.topography.dne._doolkit import face_energy

    # a needle: the third vertex (almost) on the first edge
    vertices = np.array([[0.0, 0, 0], [1.0, 0, 0], [2.0, 1e-12, 0]])
    normals = np.array([[0.0, 0, 1], [0.0, 0.1, 1], [0.0, 0.2, 1]])
    energy = face_energy(vertices, np.array([[0, 1, 2]]), normals)
    assert np.isfinite(energy).all()


def test_angularity_is_scale_dependent_and_orientation_free():
    mesh = trimesh.load(shared_mesh("low"), process=False)
    base = angularity(mesh)
    assert isinstance(base, AngularityResult) and list(base.to_dict()) == list(ANGULARITY_FIELDS)
    assert np.isfinite(base.face_angularity).all()
    assert base.face_angularity.min() >= 0 and base.face_angularity.max() <= 90
    small = angularity((mesh.vertices / 8.0, mesh.faces))
    assert small.angularity_mean > base.angularity_mean  # by design: x, y in mm, z in degrees
    upside_down = angularity((mesh.vertices * [1.0, -1.0, -1.0], mesh.faces))
    assert upside_down.angularity_mean == pytest.approx(base.angularity_mean, rel=1e-12)


def test_invariances_and_input_not_modified():
    mesh = trimesh.load(shared_mesh("low"), process=False)
    vertices, faces = mesh.vertices.copy(), mesh.faces.copy()
    dne, ang = doolkit_dne(mesh), angularity(mesh)
    np.testing.assert_array_equal(mesh.vertices, vertices)
    np.testing.assert_array_equal(mesh.faces, faces)
    moved = (mesh.vertices + np.array([1.0, 2.0, -3.0]), mesh.faces)
    assert doolkit_dne(moved).dne_total_unrounded == pytest.approx(dne.dne_total_unrounded, 1e-4)
    assert angularity(moved).angularity_mean == pytest.approx(ang.angularity_mean, rel=1e-6)
    # DNE is scale free: a power of two is exact in float32
    scaled = doolkit_dne((mesh.vertices * 4.0, mesh.faces))
    assert scaled.dne_total_unrounded == pytest.approx(dne.dne_total_unrounded, rel=1e-12)
    rng = np.random.default_rng(5)
    perm = rng.permutation(len(vertices))
    permuted = (vertices[perm], np.argsort(perm)[faces])
    np.testing.assert_array_equal(doolkit_dne(permuted).face_energy, dne.face_energy)
    np.testing.assert_array_equal(angularity(permuted).face_angularity, ang.face_angularity)
    order = rng.permutation(len(faces))
    shuffled = (vertices, faces[order])
    np.testing.assert_allclose(
        angularity(shuffled).face_angularity, ang.face_angularity[order], rtol=1e-5, atol=1e-4
    )
    assert doolkit_dne(shuffled).dne_total_unrounded == pytest.approx(
        dne.dne_total_unrounded, rel=1e-4
    )
    assert isinstance(dne, DoolkitDNEResult)


@pytest.mark.parametrize("bad", [1.5, -0.1, np.nan, "0.9", True, None])
def test_dne_bad_range_raises(bad):
    with pytest.raises((TypeError, ValueError)):
        doolkit_dne(plane_patch(5), range=bad)
