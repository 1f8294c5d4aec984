"""The compiled geodesic searches: scipy's Dijkstra distances bit for bit, and the sums."""

from __future__ import annotations

import numba
import numpy as np
import pytest
import trimesh
from scipy.sparse.csgraph import dijkstra

from dentopo.ariadne import _geodesic
from dentopo.ariadne._kernel import edge_graph, geodesic_moments, kernel_radius


def noisy_sphere(seed: int = 3) -> tuple[np.ndarray, np.ndarray]:
    mesh = trimesh.creation.icosphere(subdivisions=3)
    rng = np.random.default_rng(seed)
    points = mesh.vertices * (1 + 0.05 * rng.standard_normal((len(mesh.vertices), 1)))
    return points * 0.3, np.asarray(mesh.faces)


def grid(n: int = 15, step: float = 0.05) -> tuple[np.ndarray, np.ndarray]:
    """A flat grid, each square cut along its (+x, +y) diagonal."""
    x, y = np.meshgrid(np.arange(n) * step, np.arange(n) * step, indexing="ij")
    points = np.column_stack([x.ravel(), y.ravel(), np.zeros(n * n)])
    idx = np.arange(n * n).reshape(n, n)
    a, b, c, d = idx[:-1, :-1], idx[1:, :-1], idx[1:, 1:], idx[:-1, 1:]
    faces = np.concatenate([np.stack([a, b, c], -1), np.stack([a, c, d], -1)]).reshape(-1, 3)
    return points, faces


def searched(points, faces, radius, first, lanes):
    """``dist`` of one group's ``_search`` (the compiled search, called directly)."""
    graph = edge_graph(points, faces)
    graph.sort_indices()
    n = len(points)
    inv_step, ring = _geodesic.buckets(graph.data, radius)
    dist = np.full((n, _geodesic.LANES), np.inf)
    bucket = np.full(n, -1, np.int64)
    head = np.full(ring, -1, np.int64)
    scratch = [np.empty(n, np.int64) for _ in range(2)]
    visited = np.zeros(n, np.uint8)
    seen = np.empty(n, np.int64)
    indptr, indices = graph.indptr.astype(np.int64), graph.indices.astype(np.int64)
    reached = _geodesic._search(
        first, lanes, indptr, indices, graph.data, radius, inv_step, dist, bucket, head,
        *scratch, visited, seen,
    )  # fmt: skip
    assert np.all(head == -1) and np.all(bucket == -1)
    assert sorted(seen[:reached]) == sorted(np.flatnonzero(visited))
    return dist[:, :lanes].T, graph


@pytest.mark.parametrize("radius", [1e-50, 0.05, 0.2, 0.6, 10.0, 1e50])
def test_search_distances_equal_scipy_dijkstra_bit_for_bit(radius):
    points, faces = noisy_sphere()
    n = len(points)
    for first in (0, 40, n - 5):
        lanes = min(_geodesic.LANES, n - first)
        dist, graph = searched(points, faces, radius, first, lanes)
        sources = np.arange(first, first + lanes)
        expected = dijkstra(graph, directed=False, indices=sources, limit=radius)
        np.testing.assert_array_equal(dist, expected)


def test_search_on_a_flat_grid_is_the_lattice_distance():
    step = 0.05
    points, faces = grid(15, step)
    dist, _ = searched(points, faces, 10.0, 7 * 15 + 7, 1)
    offset = np.rint((points[:, :2] - points[7 * 15 + 7, :2]) / step)
    a, b = offset[:, 0], offset[:, 1]
    same = np.sign(a) * np.sign(b) >= 0  # the diagonals go (+x, +y): a shortcut here only
    steps = np.where(
        same,
        np.minimum(abs(a), abs(b)) * np.sqrt(2) + abs(abs(a) - abs(b)),
        abs(a) + abs(b),
    )
    np.testing.assert_allclose(dist[0], steps * step, rtol=1e-13)


def dense_reference(points, faces, bandwidth, cutoff):
    """The kernel sums from scipy's full distance matrix, relative to each vertex."""
    distances = dijkstra(edge_graph(points, faces), directed=False)
    radius = kernel_radius(bandwidth, cutoff)
    weight = np.exp(-(distances**2) / bandwidth**2)
    keep = (distances <= radius) & (weight > cutoff)
    weight = np.where(keep, weight, 0.0)
    diff = points[None, :, :] - points[:, None, :]
    return (
        weight.sum(1),
        np.einsum("ij,ijk->ik", weight, diff),
        np.einsum("ij,ijk,ijl->ikl", weight, diff, diff),
        keep.sum(1),
    )


@pytest.mark.parametrize(("bandwidth", "cutoff"), [(0.08, 0.0), (0.2, 0.0), (0.1, 0.3)])
def test_geodesic_moments_equal_dense_dijkstra_sums(bandwidth, cutoff):
    points, faces = noisy_sphere()
    moments = geodesic_moments(points, faces, bandwidth, cutoff)
    weight, first, second, count = dense_reference(points, faces, bandwidth, cutoff)
    np.testing.assert_array_equal(moments.count, count)
    np.testing.assert_allclose(moments.weight, weight, rtol=1e-13)
    np.testing.assert_allclose(moments.first, first, rtol=1e-12, atol=1e-14 * np.abs(first).max())
    np.testing.assert_allclose(
        moments.second, second, rtol=1e-12, atol=1e-14 * np.abs(second).max()
    )


def test_geodesic_moments_do_not_depend_on_threads_or_slices(monkeypatch):
    points, faces = noisy_sphere(5)
    before = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        one = geodesic_moments(points, faces, 0.3, 0.0)
    finally:
        numba.set_num_threads(before)
    monkeypatch.setattr(_geodesic, "SECONDS_PER_CALL", 1e-9)  # a slice of one group per thread
    sliced = geodesic_moments(points, faces, 0.3, 0.0)
    for name in ("weight", "first", "second", "count"):
        np.testing.assert_array_equal(getattr(one, name), getattr(sliced, name))


def test_vertices_without_edges_see_themselves_only():
    points = np.random.default_rng(1).normal(size=(20, 3))
    moments = geodesic_moments(points, np.zeros((0, 3), int), 0.5, 0.0)
    np.testing.assert_array_equal(moments.weight, np.ones(20))
    np.testing.assert_array_equal(moments.count, np.ones(20, int))
    assert not moments.first.any() and not moments.second.any()
    empty = geodesic_moments(np.zeros((0, 3)), np.zeros((0, 3), int), 0.5, 0.0)
    assert empty.weight.shape == (0,) and empty.second.shape == (0, 3, 3)
