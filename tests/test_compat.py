"""dentopo.compat.signDNE: the published signDNE 0.1.4's call and 8-tuple, computed by ariaDNE."""

from __future__ import annotations

import inspect

import numpy as np
import pytest
import trimesh

from conftest import shared_mesh
from dentopo import ariaDNE
from dentopo.compat import PUBLISHED_RETURNS, signDNE

#: The published signature, read from signDNE 0.1.4's source (signDNE/signDNE.py of the PyPI
#: wheel): ``def signDNE(mesh, bandwidth=0.08, cutoff=0, distance_type='Euclidean',
#: precomputed_dist=None)``, every parameter positional-or-keyword.
PUBLISHED_SIGNATURE = [
    ("mesh", inspect.Parameter.empty),
    ("bandwidth", 0.08),
    ("cutoff", 0),
    ("distance_type", "Euclidean"),
    ("precomputed_dist", None),
]

#: Its return statement, in order.
PUBLISHED_ORDER = (
    "local_dne",
    "local_curvature",
    "dne",
    "positive_dne",
    "negative_dne",
    "surface_area",
    "positive_surface_area",
    "negative_surface_area",
)


def test_the_signature_is_the_published_one():
    parameters = inspect.signature(signDNE).parameters.values()
    assert [(p.name, p.default) for p in parameters] == PUBLISHED_SIGNATURE
    assert all(p.kind is inspect.Parameter.POSITIONAL_OR_KEYWORD for p in parameters)
    assert type(inspect.signature(signDNE).parameters["cutoff"].default) is int  # 0, not 0.0
    assert PUBLISHED_RETURNS == PUBLISHED_ORDER


def test_the_tuple_holds_ariaDNE_in_the_published_order(tooth):
    out = signDNE(tooth)
    result = ariaDNE(tooth)
    assert isinstance(out, tuple) and len(out) == 8
    for name, value in zip(PUBLISHED_ORDER, out, strict=True):
        if name.startswith("local_"):
            assert isinstance(value, np.ndarray) and value.dtype == np.float64
            assert value.shape == (len(tooth.vertices),)
            assert np.array_equal(value, getattr(result, name)), name
        else:
            assert type(value) is np.float64, name
            assert value == getattr(result, name), name
    local_dne, local_curvature, dne, positive, negative = out[:5]
    assert negative >= 0 and positive + negative == pytest.approx(dne, rel=1e-12)
    assert np.sum(np.abs(local_dne)) == pytest.approx(dne, rel=1e-12)
    assert np.any(local_curvature < 0) and np.any(local_curvature > 0)  # both signs present


def test_options_are_passed_on_positionally_and_by_name(tooth):
    wide = ariaDNE(tooth, bandwidth=0.12, cutoff=0.01, distance_type="geodesic")
    for out in (
        signDNE(tooth, 0.12, 0.01, "Geodesic"),
        signDNE(tooth, bandwidth=0.12, cutoff=0.01, distance_type="Geodesic"),
    ):
        assert out[2] == wide.dne and out[3] == wide.positive_dne
        assert np.array_equal(out[1], wide.local_curvature)


def test_precomputed_distances_are_passed_on(tooth):
    result = ariaDNE(tooth)
    points = result.mesh.vertices - result.mesh.vertices.mean(axis=0)
    points = points / np.sqrt(result.surface_area)  # the unit-area scale
    distances = np.linalg.norm(points[:, None] - points[None], axis=-1)
    out = signDNE(tooth, precomputed_dist=distances, distance_type="ignored when given")
    expected = ariaDNE(tooth, precomputed_dist=distances)
    assert out[2] == expected.dne and np.array_equal(out[1], expected.local_curvature)
    assert out[2] == pytest.approx(result.dne, rel=1e-9)


def test_the_callers_mesh_is_not_modified(tooth):
    before = tooth.vertices.copy(), tooth.faces.copy()
    signDNE(tooth)
    assert np.array_equal(tooth.vertices, before[0]) and np.array_equal(tooth.faces, before[1])


def test_a_warning_when_cleaning_removes_vertices(tooth):
    stray = np.vstack([tooth.vertices, [[9.0, 9.0, 9.0]]])  # a vertex no face uses
    mesh = trimesh.Trimesh(stray, tooth.faces, process=False)
    with pytest.warns(UserWarning, match=f"left {len(tooth.vertices)} of its {len(stray)}"):
        out = signDNE(mesh)
    assert out[1].shape == (len(tooth.vertices),)
    assert np.array_equal(out[1], ariaDNE(tooth).local_curvature)


def test_bad_options_raise_clear_errors(tooth):
    with pytest.raises(ValueError, match="distance_type"):
        signDNE(tooth, distance_type="Manhattan")
    with pytest.raises(ValueError, match="cutoff"):
        signDNE(tooth, cutoff=1)
    with pytest.raises(ValueError, match="precomputed_dist"):
        signDNE(tooth, precomputed_dist=np.zeros((3, 3)))


def test_the_published_values_on_a_shared_mesh(reference, reference_curvature):
    """The order checked against the published package's own output (stored reference)."""
    out = signDNE(trimesh.load(shared_mesh("normal")))
    published = reference["normal"]["published"]
    for position, name in enumerate(PUBLISHED_ORDER[2:], start=2):
        assert out[position] == pytest.approx(published[name], rel=1e-9), name
    assert np.allclose(out[1], reference_curvature["normal"], rtol=0, atol=1e-9)
