"""The faster paths of the topography metrics give what the paths they replace gave.

A result's mesh built on first read, the border vertices found without grouping
the edges, both tails' quantiles from one partition, molaR's size measure without
numpy's mean, the scale check without the median: each is compared here with the
computation it replaces, bit for bit where the numbers are concerned.
"""

from __future__ import annotations

import math
import pickle
import warnings

import numpy as np
import pytest
import trimesh

import dentopo
from conftest import plane_patch, shared_mesh
from dentopo.topography import arc, doolkit_opcr, doolkit_slope, prepare_surface, slope
from dentopo.topography._lazy import MeshLater
from dentopo.topography.surface import _kernels, _vcg
from dentopo.topography.surface._molar import check_scale, molar_scale


@pytest.fixture(scope="module")
def normal():
    path = shared_mesh("normal")
    if not path.exists():
        pytest.skip("shared meshes not found")
    return dentopo.load_mesh(path)


def test_the_result_mesh_is_built_on_first_read_and_kept(tooth):
    result = doolkit_slope(tooth)
    assert isinstance(vars(result)["mesh"], MeshLater)  # not built by the call
    mesh = result.mesh
    assert isinstance(mesh, trimesh.Trimesh) and result.mesh is mesh
    surface = prepare_surface(tooth)
    assert np.array_equal(mesh.faces, surface.faces)
    np.testing.assert_array_equal(mesh.vertices, surface.vertices.astype(np.float32))
    mesh.vertices[0] += 1.0  # a private copy: the surface's arrays are untouched
    assert not np.array_equal(mesh.vertices, surface.vertices.astype(np.float32))
    with pytest.raises(AttributeError):
        result.mesh = mesh  # still frozen


def test_a_result_pickles_before_and_after_its_mesh_is_built(tooth):
    for read in (False, True):
        result = slope(tooth)
        if read:
            result.mesh  # noqa: B018
        back = pickle.loads(pickle.dumps(result))
        assert back.slope == result.slope
        assert np.array_equal(back.mesh.faces, result.mesh.faces)


def test_opcr_rotations_share_one_mesh(tooth):
    result = doolkit_opcr(tooth)
    assert result.first.mesh is result.first.mesh
    assert len(result.first.mesh.faces) == result.faces


def test_a_mesh_must_be_given(tooth):
    result = slope(tooth)
    with pytest.raises(TypeError, match="mesh"):
        type(result)(**{**vars(result), "mesh": type(result).mesh})


def _border_by_groups(surface) -> np.ndarray:
    flags = np.zeros(len(surface.vertices), dtype=bool)
    flags[surface.boundary_edges().ravel()] = True
    return flags


@pytest.mark.parametrize("case", ["plane", "tooth", "sphere", "nonmanifold", "repeated"])
def test_border_vertices_without_edge_groups(case, tooth, sphere):
    if case == "plane":
        mesh = plane_patch(9)
    elif case == "tooth":
        mesh = tooth
    elif case == "sphere":
        mesh = sphere  # closed: no border
    else:
        patch = plane_patch(6)
        faces = np.asarray(patch.faces)
        if case == "nonmanifold":  # a third face on an interior edge, out of the plane
            a, b = faces[7, 0], faces[7, 1]
            apex = len(patch.vertices)
            vertices = np.vstack([patch.vertices, [[0.3, 0.3, 1.0]]])
            faces = np.vstack([faces, [[a, b, apex]]])
        else:  # a face listed twice, kept as listed
            vertices = np.asarray(patch.vertices)
            faces = np.vstack([faces, faces[3:4]])
        mesh = (vertices, faces)
    duplicates = "keep" if case == "repeated" else "drop"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # the repeated face, said
        surface = prepare_surface(mesh, duplicates=duplicates)
        fresh = prepare_surface(mesh, duplicates=duplicates)  # nothing grouped yet
    expected = _border_by_groups(surface)
    flags = np.zeros(len(surface.vertices), dtype=bool)
    _kernels.border_vertex_flags(_kernels.readonly(surface.faces), flags)
    assert np.array_equal(flags, expected)
    assert np.array_equal(_vcg.border_vertices(fresh), expected)
    if case == "sphere":
        assert not expected.any()


def _quantile7_before(values, p):
    """quantile7 as it was, one partition per probability."""
    n = len(values)
    index = 1.0 + (n - 1) * p
    lo, hi = math.floor(index), math.ceil(index)
    part = np.partition(values, (lo - 1, hi - 1)) if hi != lo else np.partition(values, lo - 1)
    q, upper = float(part[lo - 1]), float(part[hi - 1])
    if index > lo and upper != q:
        g = index - lo
        q = (1.0 - g) * q + g * upper
    return q


def test_quantiles_from_one_partition_are_each_quantile():
    rng = np.random.default_rng(3)
    for n in (1, 2, 3, 10, 101, 8000):
        x = rng.normal(size=n)
        x[: n // 3] = 0.0  # ties, as the zeroed border faces make
        for ps in ((0.01, 0.99), (0.0, 1.0), (0.5, 0.5), (0.001, 0.999)):
            got = _vcg.quantiles7(x, ps)
            assert got == tuple(_quantile7_before(x, p) for p in ps)
            assert _vcg.quantile7(x, ps[0]) == got[0]
            for value, p in zip(got, ps, strict=True):
                assert value == pytest.approx(np.quantile(x, p), rel=1e-12, abs=1e-300)


def test_molar_scale_is_numpys_formula_bit_for_bit(normal):
    rng = np.random.default_rng(5)
    arrays = [np.asarray(normal.vertices, dtype=np.float64)]
    arrays += [rng.normal(size=(rng.integers(1, 3000), 3)) * 10.0 ** rng.uniform(-4, 4)
               for _ in range(50)]  # fmt: skip
    for vertices in arrays:
        centred = vertices - vertices.mean(axis=1, keepdims=True)
        expected = 100.0 / float(np.sqrt(np.sum(centred**2)))
        assert molar_scale(vertices) == expected


def test_the_scale_check_without_the_median():
    check_scale(np.array([1.0, 2.0, 3.0]))
    check_scale(np.array([0.0, 1.0, 2.0]))  # one tiny face, the median fine
    with pytest.raises(ValueError, match="too small"):
        check_scale(np.array([0.0, 0.0, 2.0]))
    with pytest.raises(ValueError, match="too large"):
        check_scale(np.array([1.0, 1e19]))
    with pytest.raises(ValueError, match="too large"):
        check_scale(np.array([1.0, np.nan]))


def test_arc_on_a_plane_still_zeroes_its_border():
    result = arc(plane_patch(15))
    assert result.boundary_faces > 0 and result.arc == pytest.approx(0.0, abs=1e-4)


def test_doolkit_normals_and_slopes_are_numpys_bit_for_bit(normal):
    from dentopo.topography.slope._doolkit import doolkit_mesh, face_slope

    dm = doolkit_mesh(normal)
    cross = np.empty((len(dm.faces), 3))
    norm = np.empty(len(dm.faces))
    _kernels.face_cross_norm(
        _kernels.readonly(dm.vertices), _kernels.readonly(dm.faces), cross, norm
    )
    expected = cross / np.where(norm > 0, norm, 1.0)[:, None]
    assert np.array_equal(dm.normals, expected)
    normals = np.vstack([expected, np.zeros((1, 3)), [[0.0, 0.0, -1.0]], [[1.0, 0.0, 0.0]]])
    horizontal = normals[:, 0] ** 2 + normals[:, 1] ** 2
    with np.errstate(invalid="ignore"):
        ratio = np.sqrt(horizontal) / np.sqrt(horizontal + normals[:, 2] ** 2)
    got = face_slope(normals)
    assert np.array_equal(got, 90.0 - np.arccos(ratio) * (180.0 / np.pi), equal_nan=True)
    assert np.isnan(got[-3]) and got[-2] == 0.0 and got[-1] == 90.0
