"""The sign methods of ariaDNE: centroid (default), winding, mean and Gaussian curvature."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from dentopo import ariaDNE
from dentopo.mesh import outward_faces
from dentopo.sign import SIGN_METHODS

CURVATURE_SIGNS = ("centroid", "winding", "mean_curvature")


def _landmarks(mesh):
    xy = np.asarray(mesh.vertices)[:, :2]
    cusp = int(np.argmin(np.linalg.norm(xy - [0.45, 0.45], axis=1)))
    basin = int(np.argmin(np.linalg.norm(xy, axis=1)))
    return cusp, basin


@pytest.mark.parametrize("method", SIGN_METHODS)
def test_sphere_is_convex_for_every_method(sphere, method):
    result = ariaDNE(sphere, sign_method=method)
    assert result.sign_method == method
    assert result.negative_dne == 0.0
    assert np.all(result.local_curvature > 0)


@pytest.mark.parametrize("method", CURVATURE_SIGNS)
def test_tooth_cusp_positive_basin_negative(tooth, method):
    result = ariaDNE(tooth, sign_method=method)
    cusp, basin = _landmarks(tooth)
    assert result.local_curvature[cusp] > 0
    assert result.local_curvature[basin] < 0
    assert result.positive_dne > result.negative_dne > 0


def test_gaussian_sign_sees_a_bowl_as_positive_and_a_saddle_as_negative(tooth):
    from dentopo.samples import saddle

    result = ariaDNE(tooth, sign_method="gaussian_curvature")
    cusp, basin = _landmarks(tooth)
    assert result.local_curvature[cusp] > 0 and result.local_curvature[basin] > 0
    patch = saddle()
    centre = int(np.argmin(np.linalg.norm(patch.vertices[:, :2], axis=1)))
    assert ariaDNE(patch, sign_method="gaussian_curvature").local_curvature[centre] < 0


@pytest.mark.parametrize("method", SIGN_METHODS[1:])
def test_methods_change_only_the_sign(tooth, method):
    default = ariaDNE(tooth)
    other = ariaDNE(tooth, sign_method=method)
    assert np.array_equal(np.abs(other.local_curvature), np.abs(default.local_curvature))
    assert other.dne == default.dne


def test_default_is_centroid(tooth):
    default = ariaDNE(tooth)
    assert default.sign_method == "centroid"
    assert np.array_equal(
        default.local_curvature, ariaDNE(tooth, sign_method="Centroid").local_curvature
    )


def test_winding_equals_centroid_on_a_closed_mesh():
    # a sphere with a deep dent: closed, with a concave region
    dented = trimesh.creation.icosphere(subdivisions=4)
    v = np.asarray(dented.vertices)
    v = v * (1.0 - 0.5 * np.exp(-np.sum((v - [0, 0, 1]) ** 2, axis=1) / 0.2))[:, None]
    dented = trimesh.Trimesh(v, dented.faces, process=False)
    centroid = ariaDNE(dented)
    winding = ariaDNE(dented, sign_method="winding")
    assert centroid.negative_dne > 0
    assert np.array_equal(centroid.local_curvature, winding.local_curvature)


@pytest.mark.parametrize("method", ["winding", "mean_curvature", "gaussian_curvature"])
def test_sign_does_not_depend_on_face_orientation(tooth, method):
    flipped = trimesh.Trimesh(tooth.vertices, tooth.faces[:, ::-1], process=False)
    assert np.array_equal(
        ariaDNE(tooth, sign_method=method).local_curvature,
        ariaDNE(flipped, sign_method=method).local_curvature,
    )


def test_outward_faces_gives_positive_volume(sphere):
    inward = np.asarray(sphere.faces)[:, ::-1]
    fixed = outward_faces(np.asarray(sphere.vertices), inward)
    assert trimesh.Trimesh(sphere.vertices, fixed, process=False).volume > 0


@pytest.mark.parametrize("bad", ["ray", "", None, 3])
def test_unknown_sign_method(sphere, bad):
    with pytest.raises(ValueError, match="sign_method"):
        ariaDNE(sphere, sign_method=bad)


def test_command_sign_method(tmp_path):
    import csv

    from dentopo.cli import main
    from dentopo.samples import sample_paths

    out = tmp_path / "out.csv"
    assert main([str(sample_paths()["sphere"]), "--sign-method", "Winding", "-o", str(out)]) == 0
    with open(out, newline="") as handle:
        (row,) = list(csv.DictReader(handle))
    assert row["sign_method"] == "winding"
    assert float(row["negative_dne"]) == 0.0
