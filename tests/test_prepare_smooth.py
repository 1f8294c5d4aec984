"""The smooth step of ``prepare``: trimesh's filters exactly, implicit fairing, the base pinned."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh
from scipy.spatial.transform import Rotation

import dentopo
from conftest import plane_patch, shared_mesh
from dentopo.prepare import _smooth
from dentopo.prepare._protocol import SMOOTHERS, Protocol, ProtocolError, named_protocols

METHODS = ("laplacian", "taubin", "hc", "implicit")


def _arrays(mesh):
    return np.asarray(mesh.vertices, dtype=np.float64), np.asarray(mesh.faces, dtype=np.int64)


def _defaults(method):
    d = SMOOTHERS[method]
    return {"iterations": d["iterations"], "step": d["step"], "mu": d["mu"]}


@pytest.fixture(scope="module")
def noisy_sphere():
    s = trimesh.creation.icosphere(subdivisions=4)
    rng = np.random.default_rng(20)
    radial = 1.0 + 0.02 * rng.standard_normal(len(s.vertices))
    return np.asarray(s.vertices * radial[:, None]), np.asarray(s.faces, dtype=np.int64)


@pytest.fixture(scope="module")
def crown():
    """A shared crown (open at its base)."""
    return _arrays(trimesh.load(shared_mesh("normal"), process=False))


def _trimesh_filter(method, vertices, faces, params, pinned=None):
    """trimesh's filter called directly, as a user would, on a fresh mesh."""
    mesh = trimesh.Trimesh(vertices=vertices.copy(), faces=faces.copy(), process=False)
    operator = None
    if pinned is not None:
        operator = trimesh.smoothing.laplacian_calculation(mesh, pinned_vertices=pinned)
    it, step, mu = params["iterations"], params["step"], params["mu"]
    if method == "laplacian":
        trimesh.smoothing.filter_laplacian(
            mesh, lamb=step, iterations=it, volume_constraint=False, laplacian_operator=operator
        )
    elif method == "taubin":
        trimesh.smoothing.filter_taubin(
            mesh, lamb=step, nu=mu, iterations=it, laplacian_operator=operator
        )
    else:
        trimesh.smoothing.filter_humphrey(
            mesh, alpha=step, beta=mu, iterations=it, laplacian_operator=operator
        )
    return np.asarray(mesh.vertices)


# --- trimesh's filters, exactly


def test_the_defaults_are_trimeshs():
    import inspect

    sm = trimesh.smoothing
    lap = inspect.signature(sm.filter_laplacian).parameters
    taubin = inspect.signature(sm.filter_taubin).parameters
    hc = inspect.signature(sm.filter_humphrey).parameters
    assert SMOOTHERS["laplacian"]["step"] == lap["lamb"].default
    assert SMOOTHERS["laplacian"]["iterations"] == lap["iterations"].default
    assert SMOOTHERS["taubin"]["step"] == taubin["lamb"].default
    assert SMOOTHERS["taubin"]["mu"] == taubin["nu"].default
    assert SMOOTHERS["taubin"]["iterations"] == taubin["iterations"].default
    assert SMOOTHERS["hc"]["step"] == hc["alpha"].default
    assert SMOOTHERS["hc"]["mu"] == hc["beta"].default
    assert SMOOTHERS["hc"]["iterations"] == hc["iterations"].default
    assert SMOOTHERS["implicit"] == {"iterations": 3, "step": 0.1, "mu": None}  # MorphoTester's


@pytest.mark.parametrize("method", ["laplacian", "taubin", "hc"])
def test_a_closed_mesh_is_smoothed_exactly_as_trimesh_does(noisy_sphere, method):
    v, f = noisy_sphere  # no boundary: nothing pinned
    params = _defaults(method)
    out = _smooth.run(v, f, method=method, **params)
    assert out.details["pinned_vertices"] == 0
    assert np.array_equal(out.vertices, _trimesh_filter(method, v, f, params))


@pytest.mark.parametrize("method", ["laplacian", "taubin", "hc"])
def test_unpinned_the_crown_is_smoothed_exactly_as_trimesh_does(crown, method):
    v, f = crown
    params = {**_defaults(method), "iterations": 4}
    out = _smooth.run(v, f, method=method, pin_boundary=False, **params)
    assert np.array_equal(out.vertices, _trimesh_filter(method, v, f, params))
    assert np.array_equal(out.faces, f)


@pytest.mark.parametrize("method", ["laplacian", "taubin", "hc"])
def test_pinned_the_interior_is_trimeshs_with_its_pinned_operator(crown, method):
    v, f = crown
    params = _defaults(method)
    pinned = _smooth.boundary_vertices(f, len(v))
    assert len(pinned) > 50
    out = _smooth.run(v, f, method=method, **params)
    direct = _trimesh_filter(method, v, f, params, pinned=pinned)
    free = np.setdiff1d(np.arange(len(v)), pinned)
    assert np.array_equal(out.vertices[free], direct[free])
    assert np.array_equal(out.vertices[pinned], v[pinned])  # the base outline, bit for bit
    np.testing.assert_allclose(direct[pinned], v[pinned], rtol=0, atol=1e-12)  # trimesh's too
    assert out.details["pinned_vertices"] == len(pinned)


@pytest.mark.parametrize("method", METHODS)
def test_unpinned_every_filter_moves_the_base(crown, method):
    """Why pin: each filter, as published, pulls the open boundary inwards."""
    v, f = crown
    pinned = _smooth.boundary_vertices(f, len(v))
    out = _smooth.run(v, f, method=method, pin_boundary=False, **_defaults(method))
    edge = np.linalg.norm(v[f[:, 0]] - v[f[:, 1]], axis=1).mean()
    assert np.linalg.norm(out.vertices[pinned] - v[pinned], axis=1).mean() > 0.2 * edge


# --- implicit fairing


def test_implicit_fairing_smooths_a_noisy_sphere_and_keeps_its_volume(noisy_sphere):
    v, f = noisy_sphere
    before = trimesh.Trimesh(v, f, process=False)
    out = _smooth.run(v, f, method="implicit", iterations=3, step=0.1)
    after = trimesh.Trimesh(out.vertices, f, process=False)
    defects = trimesh.curvature.vertex_defects
    assert defects(after).var() < 0.05 * defects(before).var()  # Gaussian curvature evens out
    radius = np.linalg.norm(out.vertices, axis=1)
    assert radius.std() < 0.5 * np.linalg.norm(v, axis=1).std()
    assert abs(after.volume / before.volume - 1) < 0.03


def test_more_iterations_smooth_more(noisy_sphere):
    v, f = noisy_sphere
    spread = [
        np.linalg.norm(
            _smooth.run(v, f, method="implicit", iterations=n, step=0.1).vertices, axis=1
        ).std()
        for n in (1, 3, 10)
    ]
    assert spread[0] > spread[1] > spread[2]


def test_implicit_fairing_solves_its_system(noisy_sphere):
    # one iteration: (I - step L) X_new = X, L the cotangent operator of the input
    v, f = noisy_sphere
    out = _smooth.implicit_fairing(v, f, iterations=1, step=0.1)
    lap = _smooth.cotangent_operator(v, f)
    np.testing.assert_allclose(out - 0.1 * (lap @ out), v, rtol=0, atol=1e-12)


def test_the_cotangent_operator_on_one_triangle():
    # equilateral: every angle is 60 degrees, each edge's weight cot(60) = 1/sqrt(3)
    v = np.array([[0.0, 0, 0], [1, 0, 0], [0.5, np.sqrt(3) / 2, 0]])
    lap = _smooth.cotangent_operator(v, np.array([[0, 1, 2]])).toarray()
    w = 1 / np.sqrt(3)
    expected = np.full((3, 3), w) - np.eye(3) * 3 * w
    np.testing.assert_allclose(lap, expected, rtol=1e-14, atol=1e-15)
    # a right angle faces the hypotenuse with weight 0
    v = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]])
    lap = _smooth.cotangent_operator(v, np.array([[0, 1, 2]])).toarray()
    assert abs(lap[1, 2]) < 1e-15 and abs(lap[0, 1] - 1) < 1e-15


def test_the_implicit_step_means_the_same_at_any_unit(crown):
    v, f = crown
    base = _smooth.run(v, f, method="implicit", iterations=3, step=0.1, pin_boundary=False)
    scaled = _smooth.run(v * 1000, f, method="implicit", iterations=3, step=0.1, pin_boundary=False)
    np.testing.assert_allclose(scaled.vertices, base.vertices * 1000, rtol=1e-9, atol=1e-9)


# --- every method


@pytest.mark.parametrize("method", METHODS)
def test_a_plane_stays_a_plane(method):
    v, f = _arrays(plane_patch(15))
    for pin in (True, False):
        out = _smooth.run(v, f, method=method, pin_boundary=pin, **_defaults(method))
        assert np.abs(out.vertices[:, 2]).max() < 1e-12
        assert not np.array_equal(out.vertices, v) or pin  # unpinned, the sheet does move


@pytest.mark.parametrize("method", METHODS)
def test_a_rigid_motion_commutes_with_smoothing(crown, method):
    v, f = crown
    rotation = Rotation.from_euler("xyz", [33, -71, 12], degrees=True).as_matrix()
    shift = np.array([12.5, -3.0, 40.0])
    params = _defaults(method)
    moved_then_smoothed = _smooth.run(v @ rotation.T + shift, f, method=method, **params).vertices
    smoothed_then_moved = _smooth.run(v, f, method=method, **params).vertices @ rotation.T + shift
    np.testing.assert_allclose(moved_then_smoothed, smoothed_then_moved, rtol=0, atol=1e-9)


@pytest.mark.parametrize("method", METHODS)
def test_scaling_commutes_with_smoothing(crown, method):
    v, f = crown
    params = _defaults(method)
    big = _smooth.run(v * 1000, f, method=method, **params).vertices
    np.testing.assert_allclose(
        big, _smooth.run(v, f, method=method, **params).vertices * 1000, rtol=1e-9, atol=1e-9
    )


@pytest.mark.parametrize("method", METHODS)
def test_zero_iterations_is_the_identity(crown, method):
    v, f = crown
    params = {**_defaults(method), "iterations": 0}
    for pin in (True, False):
        out = _smooth.run(v, f, method=method, pin_boundary=pin, **params)
        assert np.array_equal(out.vertices, v) and np.array_equal(out.faces, f)
        assert out.vertices is not v


@pytest.mark.parametrize("method", METHODS)
def test_the_input_is_never_modified(crown, method):
    v, f = (np.array(a) for a in crown)
    v.setflags(write=False)
    f.setflags(write=False)
    for pin in (True, False):
        _smooth.run(v, f, method=method, pin_boundary=pin, **_defaults(method))
    assert np.array_equal(v, crown[0]) and np.array_equal(f, crown[1])


@pytest.mark.parametrize("method", METHODS)
def test_pinned_the_base_does_not_move(crown, method):
    v, f = crown
    pinned = _smooth.boundary_vertices(f, len(v))
    out = _smooth.run(v, f, method=method, **_defaults(method))
    assert np.array_equal(out.vertices[pinned], v[pinned])
    assert not np.allclose(out.vertices, v)  # the rest is smoothed


@pytest.mark.parametrize(
    ("options", "words"),
    [
        ({"method": "bilateral", "iterations": 3, "step": 0.1}, "method must be one of"),
        ({"method": "implicit", "iterations": -1, "step": 0.1}, "iterations must be at least 0"),
        ({"method": "implicit", "iterations": 2.5, "step": 0.1}, "whole number"),
        ({"method": "implicit", "iterations": 3, "step": 0.0}, "step must be above 0"),
        ({"method": "taubin", "iterations": 3, "step": float("nan")}, "finite"),
        ({"method": "laplacian", "iterations": 3, "step": 0.5, "mu": 0.5}, "mu is a parameter"),
    ],
)
def test_bad_parameters_are_named(crown, options, words):
    v, f = crown
    with pytest.raises(ValueError, match=words):
        _smooth.run(v, f, **options)


# --- through the protocol


def test_the_protocol_carries_pin_boundary():
    assert Protocol(smooth="implicit").smoothing()["pin_boundary"] is True
    unpinned = Protocol.from_mapping({"smooth": {"method": "hc", "pin_boundary": False}})
    assert unpinned.steps()["smooth"]["pin_boundary"] is False
    assert "pin_boundary = false" in unpinned.to_toml()
    assert unpinned.digest != Protocol(smooth="hc").digest
    with pytest.raises(ProtocolError, match="pin_boundary must be true or false"):
        Protocol(smooth="hc", smooth_pin_boundary="no")
    with pytest.raises(ProtocolError, match="need a smooth method"):
        Protocol(smooth_pin_boundary=False)
    assert named_protocols()["morphotester-smooth"].smooth_pin_boundary is False


def test_prepare_smooths_and_records_it():
    path = shared_mesh("normal")
    crown = dentopo.prepare(path, orient="none", smooth="implicit")
    step = crown.step("smooth")
    assert step.parameters == {
        "method": "implicit",
        "iterations": 3,
        "step": 0.1,
        "pin_boundary": True,
    }
    v, f = _arrays(trimesh.load(path, process=False))
    direct = _smooth.run(v, f, method="implicit", iterations=3, step=0.1)
    np.testing.assert_array_equal(crown.vertices, direct.vertices)  # clean changes nothing here
    again = dentopo.prepare(path, orient="none", smooth="implicit")
    assert again.vertices.tobytes() == crown.vertices.tobytes()
