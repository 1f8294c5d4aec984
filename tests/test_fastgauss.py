"""The fast Gauss transform path (method="fast") against the exact kernel sums."""

from __future__ import annotations

import sys

import numpy as np
import pytest
import trimesh

from dentopo import ariaDNE
from dentopo.ariadne import _fastgauss, _kernel
from dentopo.mesh import prepare
from dentopo.samples import tooth as make_tooth

pytest.importorskip("finufft")


@pytest.fixture(scope="module")
def noisy_tooth():
    """A crown of about 11k vertices with seeded sub-edge-length noise."""
    mesh = make_tooth(rings=60)
    rng = np.random.default_rng(0)
    vertices = mesh.vertices + rng.normal(scale=2e-3, size=mesh.vertices.shape)
    return trimesh.Trimesh(vertices, mesh.faces, process=False)


def test_moments_match_exact_sums(noisy_tooth):
    points = prepare(noisy_tooth).points
    h = 0.08
    exact = _kernel.euclidean_moments(points, h, 0.0)
    fast = _fastgauss.fast_euclidean_moments(points, h)
    assert np.max(np.abs(fast.weight - exact.weight) / exact.weight) < 1e-8
    trace = np.trace(exact.covariance, axis1=1, axis2=2)
    cov_error = np.abs(fast.covariance - exact.covariance).reshape(-1, 9).max(axis=1)
    assert np.max(cov_error / trace) < 1e-8
    centroid_error = np.abs(fast.centroid(points) - exact.centroid(points)).max()
    assert centroid_error < 1e-8 * h
    # counts: exact below 4, "4 or more" above (they only feed the warning)
    assert np.all(fast.count == np.minimum(exact.count, 4))


@pytest.mark.parametrize("bandwidth", [0.05, 0.08, 0.15])
def test_totals_and_signs_match_exact(noisy_tooth, bandwidth):
    exact = ariaDNE(noisy_tooth, bandwidth=bandwidth, method="exact")
    fast = ariaDNE(noisy_tooth, bandwidth=bandwidth, method="fast")
    assert (exact.method, fast.method) == ("exact", "fast")
    for name in ("dne", "positive_dne", "negative_dne"):
        assert getattr(fast, name) == pytest.approx(getattr(exact, name), rel=1e-8, abs=1e-12)
    same_sign = np.sign(fast.local_curvature) == np.sign(exact.local_curvature)
    assert same_sign.mean() >= 0.9999
    np.testing.assert_allclose(
        np.abs(fast.local_curvature), np.abs(exact.local_curvature), rtol=0, atol=1e-8
    )


def test_fast_on_a_closed_surface():
    sphere = trimesh.creation.icosphere(subdivisions=4)
    exact = ariaDNE(sphere, method="exact")
    fast = ariaDNE(sphere, method="fast")
    assert fast.dne == pytest.approx(exact.dne, rel=1e-8)
    assert fast.negative_dne == 0.0


def test_auto_picks_by_size(sphere, monkeypatch):
    assert ariaDNE(sphere).method == "exact"  # small: exact
    assert ariaDNE(sphere).to_dict()["method"] == "exact"
    monkeypatch.setattr(_fastgauss, "AUTO_FAST_VERTICES", 100)
    assert ariaDNE(sphere).method == "fast"
    # auto never picks fast where it cannot apply
    assert ariaDNE(sphere, cutoff=0.1).method == "exact"
    assert ariaDNE(sphere, distance_type="geodesic").method == "exact"


def test_method_is_case_insensitive(sphere):
    assert ariaDNE(sphere, method="EXACT").method == "exact"


@pytest.mark.parametrize("bad", ["quick", "", None, 1])
def test_bad_method_raises(sphere, bad):
    with pytest.raises(ValueError, match="method must be one of"):
        ariaDNE(sphere, method=bad)


def test_fast_refuses_a_cutoff(sphere):
    with pytest.raises(ValueError, match="cutoff"):
        ariaDNE(sphere, cutoff=0.01, method="fast")


def test_fast_refuses_geodesic_and_precomputed(sphere):
    with pytest.raises(ValueError, match="Euclidean"):
        ariaDNE(sphere, distance_type="geodesic", method="fast")
    n = len(sphere.vertices)
    distances = np.linalg.norm(sphere.vertices[:, None] - sphere.vertices[None], axis=2)
    assert distances.shape == (n, n)
    with pytest.raises(ValueError, match="Euclidean"):
        ariaDNE(sphere, precomputed_dist=distances, method="fast")


def test_too_small_bandwidth_is_refused(sphere, monkeypatch):
    monkeypatch.setattr(_fastgauss, "MAX_MODES", 1000)
    with pytest.raises(ValueError, match="too small for the fast transform"):
        ariaDNE(sphere, method="fast")
    monkeypatch.setattr(_fastgauss, "AUTO_FAST_VERTICES", 10)
    assert ariaDNE(sphere).method == "exact"


def test_without_finufft(sphere, monkeypatch):
    monkeypatch.setitem(sys.modules, "finufft", None)  # import finufft now fails
    with pytest.raises(ImportError, match=r"dentopo\[fast\]"):
        ariaDNE(sphere, method="fast")
    monkeypatch.setattr(_fastgauss, "AUTO_FAST_VERTICES", 10)
    assert ariaDNE(sphere).method == "exact"


def test_progress_reports_phases(sphere):
    seen = []
    ariaDNE(sphere, progress=seen.append)
    assert seen == ["prepare", "kernel", "bending", "sign", "totals"]


def test_few_neighbours_warning_on_fast_path():
    # a dense sphere and a far-away lone triangle: its 3 vertices have 3 neighbours
    sphere = trimesh.creation.icosphere(subdivisions=3)
    lone = trimesh.Trimesh([[4.0, 0, 0], [4.1, 0, 0], [4.0, 0.1, 0]], [[0, 1, 2]])
    mesh = trimesh.util.concatenate([sphere, lone])
    with pytest.warns(UserWarning, match="3 of"):
        ariaDNE(mesh, method="fast")


@pytest.mark.parametrize("split", [False, True], ids=["one spectrum", "spectrum in parts"])
def test_same_bits_at_any_thread_count(noisy_tooth, monkeypatch, split):
    points = prepare(noisy_tooth).points
    whole = _fastgauss.fast_euclidean_moments(points, 0.08)
    if split:  # as on large meshes: the type-1 transform in parts, shared by the threads
        monkeypatch.setattr(_fastgauss, "SPLIT_SPECTRUM_FROM", 100)
    runs = [_fastgauss.fast_euclidean_moments(points, 0.08, nthreads=t) for t in (1, 2, 3, 1)]
    for run in runs[1:]:
        for name in ("weight", "first", "second", "count"):
            assert getattr(run, name).tobytes() == getattr(runs[0], name).tobytes(), name
    # cut in parts, the spectrum is summed in another order: equal to rounding
    scale = np.abs(whole.second).max()
    assert np.abs(runs[0].second - whole.second).max() < 1e-12 * scale
    assert np.abs(runs[0].weight - whole.weight).max() < 1e-12 * whole.weight.max()


def test_interpolation_in_parts_gives_the_same_bits(noisy_tooth, monkeypatch):
    # each thread interpolates its part of the points: every value is the same,
    # bit for bit, as when one transform interpolates them all
    points = prepare(noisy_tooth).points
    whole = _fastgauss.fast_euclidean_moments(points, 0.08, nthreads=1)
    monkeypatch.setattr(_fastgauss, "MIN_INTERPOLATED", 100)
    for threads in (2, 3):
        parts = _fastgauss.fast_euclidean_moments(points, 0.08, nthreads=threads)
        for name in ("weight", "first", "second", "count"):
            assert getattr(parts, name).tobytes() == getattr(whole, name).tobytes(), name


def _with_far_triangle(mesh, distance):
    far = trimesh.Trimesh(
        np.array([[0.0, 0, 0], [0.02, 0, 0], [0, 0.02, 0]]) + distance, [[0, 1, 2]]
    )
    return trimesh.util.concatenate([mesh, far])


def test_a_far_away_triangle_keeps_the_fast_path(noisy_tooth):
    # its bounding box would need ~1e18 Fourier modes: the points are cut into
    # groups out of each other's reach, a transform for the crown, exact sums
    # for the triangle
    mesh = _with_far_triangle(noisy_tooth, 1e6)
    points = prepare(mesh).points
    plan = _fastgauss.plan_fast(points, 0.08)
    assert plan.problem is None and len(plan.groups) == 1 and len(plan.exact) == 3
    fast = _fastgauss.fast_euclidean_moments(points, 0.08)
    exact = _kernel.euclidean_moments(points, 0.08, 0.0)
    assert np.max(np.abs(fast.weight - exact.weight) / exact.weight) < 1e-8
    trace = np.trace(exact.covariance, axis1=1, axis2=2)
    crown = trace > 0
    cov_error = np.abs(fast.covariance - exact.covariance).reshape(-1, 9).max(axis=1)
    assert np.max(cov_error[crown] / trace[crown]) < 1e-8
    assert np.array_equal(fast.count[~crown], exact.count[~crown])
    with pytest.warns(UserWarning, match="3 of"):
        result = ariaDNE(mesh, method="fast")
    assert result.method == "fast"


@pytest.mark.parametrize("bandwidth", [1e-30, 1e-12])
def test_a_tiny_bandwidth_never_wraps_the_mode_count(noisy_tooth, bandwidth):
    # the mode counts once went through int64 and wrapped: 1 mode, weights 1e-89
    points = prepare(noisy_tooth).points
    moments = _fastgauss.fast_euclidean_moments(points, bandwidth)
    assert np.array_equal(moments.weight, np.ones(len(points)))


@pytest.mark.parametrize("bandwidth", [0.3, 0.6, 2.0, 20.0, 1e4, 1e50])
def test_moments_match_exact_sums_at_any_bandwidth(noisy_tooth, bandwidth):
    # beyond half the extent the raw sums replace the derivatives, whose
    # (h**4/4) F_nn and (h**2/2) F cancel: a local curvature of 893 at h = 1e4
    points = prepare(noisy_tooth).points
    exact = _kernel.euclidean_moments(points, bandwidth, 0.0)
    fast = _fastgauss.fast_euclidean_moments(points, bandwidth)
    assert np.max(np.abs(fast.weight - exact.weight) / exact.weight) < 1e-8
    trace = np.trace(exact.covariance, axis1=1, axis2=2)
    cov_error = np.abs(fast.covariance - exact.covariance).reshape(-1, 9).max(axis=1)
    assert np.max(cov_error / trace) < 1e-8
    extent = np.ptp(points, axis=0).max()
    assert np.abs(fast.centroid(points) - exact.centroid(points)).max() < 1e-8 * extent


def test_compiled_bending_matches_lapack_eigh(noisy_tooth):
    """The fast path's Jacobi bending equals eigh's to rounding, degenerate matrices included."""
    from dentopo.ariadne._ariadne import unsigned_bending

    rng = np.random.default_rng(3)
    x = rng.normal(size=(3000, 3, 3))
    second = x @ x.transpose(0, 2, 1)
    second[:100] = np.eye(3)  # three equal eigenvalues
    second[100:200, 2, :] = second[100:200, :, 2] = 0.0  # a zero eigenvalue (a plane)
    second[200:300] = 0.0  # an isolated vertex
    second[300:400] *= 1e-30  # tiny scale
    weight = rng.uniform(1, 50, size=len(second))
    normals = rng.normal(size=(len(second), 3))
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    moments = _kernel.KernelMoments(weight, np.zeros((len(weight), 3)), second, weight * 0)
    expected = unsigned_bending(moments.covariance, normals)
    assert np.max(np.abs(_fastgauss.bending(moments, normals) - expected)) < 1e-14
    prepared = prepare(noisy_tooth)
    moments = _fastgauss.fast_euclidean_moments(prepared.points, 0.08)
    expected = unsigned_bending(moments.covariance, prepared.normals)
    assert np.max(np.abs(_fastgauss.bending(moments, prepared.normals) - expected)) < 1e-14
