"""Unusable meshes and parameters raise errors that name the problem."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import trimesh

from dentopo import ariaDNE

TETRA_V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
TETRA_F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])


@pytest.mark.parametrize(
    ("mesh", "error", "words"),
    [
        ((np.empty((0, 3)), np.empty((0, 3), int)), ValueError, "empty"),
        ((TETRA_V[:3], TETRA_F[:1]), ValueError, "at least 4"),
        ((TETRA_V, np.empty((0, 3), int)), ValueError, "no faces"),
        ((np.where(np.eye(4, 3) > 0, np.nan, TETRA_V), TETRA_F), ValueError, "non-finite"),
        ((TETRA_V, np.array([[0, 1, 2, 3]])), ValueError, "triangles"),
        ((TETRA_V, np.array([[0, 1, 9]])), ValueError, "vertex indices outside"),
        ((TETRA_V, np.array([[0, -1, 2]])), ValueError, "vertex indices outside"),
        ((TETRA_V[:, :2], TETRA_F), ValueError, "shape (n, 3)"),
        ((TETRA_V, TETRA_F + 0.5), TypeError, "integer"),
        ("not a mesh at all", FileNotFoundError, "not found"),
        (42, TypeError, "trimesh.Trimesh"),
        (trimesh.PointCloud(TETRA_V), ValueError, "point cloud"),
    ],
)
def test_bad_mesh(mesh, error, words):
    with pytest.raises(error, match=None) as info:
        ariaDNE(mesh)
    assert words in str(info.value)


def test_mesh_that_cleaning_leaves_empty():
    vertices = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0], [4, 0, 0]], dtype=float)
    faces = np.array([[0, 1, 2], [1, 2, 3], [2, 3, 4]])  # all collinear: zero height
    with pytest.raises(ValueError, match="cleaning left the mesh empty"):
        ariaDNE((vertices, faces))


@pytest.mark.parametrize("bandwidth", [0, -0.1, np.nan, np.inf])
def test_bad_bandwidth(bandwidth):
    with pytest.raises(ValueError, match="bandwidth"):
        ariaDNE((TETRA_V, TETRA_F), bandwidth=bandwidth)


@pytest.mark.parametrize("bandwidth", ["0.08", None, True])
def test_bandwidth_of_wrong_type(bandwidth):
    with pytest.raises(TypeError, match="bandwidth"):
        ariaDNE((TETRA_V, TETRA_F), bandwidth=bandwidth)


@pytest.mark.parametrize("cutoff", [-0.1, 1.0, 2.0, np.nan])
def test_bad_cutoff(cutoff):
    with pytest.raises(ValueError, match="cutoff"):
        ariaDNE((TETRA_V, TETRA_F), cutoff=cutoff)


def test_unknown_distance_type():
    with pytest.raises(ValueError, match="distance_type"):
        ariaDNE((TETRA_V, TETRA_F), distance_type="manhattan")


def test_options_are_keyword_only():
    with pytest.raises(TypeError):
        ariaDNE((TETRA_V, TETRA_F), 0.08)


def test_precomputed_of_wrong_shape(sphere):
    with pytest.raises(ValueError, match=r"precomputed_dist must be an \(642, 642\)"):
        ariaDNE(sphere, precomputed_dist=np.zeros((10, 10)))


def test_precomputed_not_symmetric(sphere):
    rng = np.random.default_rng(0)
    distances = rng.random((642, 642))
    with pytest.raises(ValueError, match="symmetric"):
        ariaDNE(sphere, precomputed_dist=distances)


def test_few_neighbours_warn_once_with_a_count():
    with pytest.warns(
        UserWarning, match=r"\d+ of \d+ vertices have 3 or fewer neighbours"
    ) as record:
        ariaDNE(trimesh.creation.icosphere(subdivisions=2), bandwidth=0.01)
    assert len(record) == 1


def test_no_warning_on_ordinary_mesh(sphere):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ariaDNE(sphere)


@pytest.mark.parametrize(
    "content", [b"", b"ply\nformat ascii 1.0\nelement vertex 3\n", b"hello world\n"]
)
def test_corrupt_files(tmp_path, content):
    path = tmp_path / "broken.ply"
    path.write_bytes(content)
    with pytest.raises(ValueError, match=r"broken\.ply"):
        ariaDNE(path)
