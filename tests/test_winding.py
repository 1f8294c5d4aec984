"""The inside test: exact where it matters, independent of luck and orientation."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from dentopo.mesh import boundary_edges, close_holes, orient_consistently
from dentopo.sign import _strips
from dentopo.sign._winding import exact_winding_number, inside, winding_number


def test_fast_winding_number_agrees_with_exact_sum(sphere):
    rng = np.random.default_rng(0)
    points = rng.uniform(-1.5, 1.5, size=(2000, 3))
    fast = winding_number(sphere.vertices, sphere.faces, points)
    exact = exact_winding_number(sphere.vertices, sphere.faces, points)
    assert np.max(np.abs(fast - exact)) < 0.05
    np.testing.assert_array_equal(np.abs(fast) > 0.5, np.abs(exact) > 0.5)
    np.testing.assert_array_equal(np.abs(fast) > 0.5, sphere.contains(points))


def test_points_a_hairs_breadth_from_the_surface(sphere):
    """Points 1e-9 inside and outside every face centre are classified exactly."""
    centres = sphere.triangles_center
    normals = sphere.face_normals
    for offset, expected in ((-1e-9, True), (1e-9, False)):
        points = centres + offset * normals
        np.testing.assert_array_equal(inside(sphere.vertices, sphere.faces, points), expected)


def test_points_near_vertices_and_edges(sphere):
    vertices = sphere.vertices
    edges = sphere.edges_unique
    mid = vertices[edges].mean(axis=1)
    radial = mid / np.linalg.norm(mid, axis=1, keepdims=True)
    for points, expected in (
        (vertices * (1 - 1e-10), True),
        (vertices * (1 + 1e-10), False),
        (mid - 1e-10 * radial, True),
        (mid + 1e-10 * radial, False),
    ):
        np.testing.assert_array_equal(inside(vertices, sphere.faces, points), expected)


def test_inward_orientation_is_handled(sphere):
    flipped = sphere.faces[:, ::-1]
    points = np.array([[0, 0, 0], [0.5, 0.1, 0.2], [2, 0, 0]])
    np.testing.assert_array_equal(inside(sphere.vertices, flipped, points), [True, True, False])


def test_orient_consistently_repairs_flipped_faces(sphere):
    faces = sphere.faces.copy()
    faces[::2] = faces[::2, ::-1]
    fixed = orient_consistently(faces, len(sphere.vertices))
    mesh = trimesh.Trimesh(sphere.vertices, fixed, process=False)
    assert mesh.is_winding_consistent


def test_close_holes_makes_a_watertight_surface():
    sphere = trimesh.creation.icosphere(subdivisions=3)
    opened = sphere.faces[sphere.triangles_center[:, 2] < 0.6]  # a cap removed
    assert len(boundary_edges(opened, len(sphere.vertices))) > 0
    vertices, faces = close_holes(sphere.vertices, opened)
    closed = trimesh.Trimesh(vertices, faces, process=False)
    assert closed.is_watertight and closed.is_winding_consistent
    assert len(vertices) == len(sphere.vertices) + 1


def test_two_holes_get_two_caps():
    sphere = trimesh.creation.icosphere(subdivisions=3)
    z = sphere.triangles_center[:, 2]
    vertices, faces = close_holes(sphere.vertices, sphere.faces[np.abs(z) < 0.7])
    assert len(vertices) == len(sphere.vertices) + 2
    assert trimesh.Trimesh(vertices, faces, process=False).is_watertight


def test_long_cap_triangles_are_cut_without_changing_the_surface(tooth):
    from dentopo.sign._strips import _split_long

    vertices, faces = close_holes(np.asarray(tooth.vertices), np.asarray(tooth.faces))
    tri = vertices[faces]
    cut = _split_long(tri)
    assert len(cut) > len(tri)  # the cap's fan triangles were cut into strips

    def area_vectors(t):
        return 0.5 * np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])

    np.testing.assert_allclose(area_vectors(cut).sum(0), area_vectors(tri).sum(0), atol=1e-12)
    np.testing.assert_allclose(
        np.linalg.norm(area_vectors(cut), axis=1).sum(),
        np.linalg.norm(area_vectors(tri), axis=1).sum(),
        rtol=1e-12,
    )
    rng = np.random.default_rng(1)
    lo, hi = vertices.min(0), vertices.max(0)
    points = rng.uniform(lo - 0.1, hi + 0.1, size=(3000, 3))
    fast = winding_number(vertices, faces, points)
    exact = exact_winding_number(vertices, faces, points)
    assert np.max(np.abs(fast - exact)) < 0.05
    np.testing.assert_array_equal(np.abs(fast) > 0.5, np.abs(exact) > 0.5)


def test_fractional_winding_numbers_of_an_open_surface(sphere):
    """Points near an open hemisphere's rim have fractional winding numbers: refined, not
    summed exactly one by one, yet within 1e-3 of the exact sum, and decided alike."""
    keep = sphere.triangles_center[:, 2] > 0
    faces = sphere.faces[keep]
    rng = np.random.default_rng(2)
    points = np.column_stack([rng.uniform(-1.2, 1.2, (2000, 2)), rng.uniform(-0.2, 0.3, 2000)])
    fast = winding_number(sphere.vertices, faces, points)
    exact = exact_winding_number(sphere.vertices, faces, points)
    fractional = np.abs(exact - np.round(exact)) > 0.25
    assert fractional.mean() > 0.1  # many points were refined
    assert np.max(np.abs(fast - exact)[fractional]) < 1e-3
    assert np.max(np.abs(fast - exact)) < 0.05  # the first pass's accuracy elsewhere
    np.testing.assert_array_equal(np.abs(fast) > 0.5, np.abs(exact) > 0.5)


def test_a_far_vertex_adds_few_strips_and_keeps_the_winding_number(sphere):
    from dentopo.sign._strips import STRIP_BUDGET, _split_long

    vertices = np.vstack([sphere.vertices, [[3e6, 1e6, 2e6]]])
    far = len(vertices) - 1
    # a thin fin from the sphere to a point 3 million radii away, both sides
    a, b = sphere.faces[0, :2]
    faces = np.vstack([sphere.faces, [[a, b, far], [b, a, far]]])
    tri = vertices[faces]
    split = _split_long(tri.copy())
    assert len(tri) < len(split) <= (1 + STRIP_BUDGET) * len(tri)
    # strips growing geometrically away from the sphere: about 40 per fin triangle
    assert len(split) - len(tri) < 4 * 50
    queries = np.array([[0.0, 0.0, 0.0], [0.3, -0.2, 0.1], [2.0, 0.0, 0.0], [0.0, 5.0, 0.0]])
    exact = exact_winding_number(vertices, faces, queries)
    np.testing.assert_allclose(exact, [1, 1, 0, 0], atol=1e-9)
    np.testing.assert_allclose(winding_number(vertices, faces, queries), exact, atol=0.05)
    assert inside(vertices, faces, queries).tolist() == [True, True, False, False]


def test_points_on_the_surface_cost_a_bounded_amount_of_work(monkeypatch):
    # every query on the surface (a tiny bandwidth makes each centroid its own
    # vertex): the exact sums stay within 64 solid angles per point and triangle
    from dentopo.mesh import prepare
    from dentopo.samples import tooth
    from dentopo.sign import _winding

    prepared = prepare(tooth(rings=50))
    vertices, faces = close_holes(prepared.points, np.asarray(prepared.mesh.faces))
    calls = []
    exact = _winding._exact

    def counting_exact(tri, queries):
        calls.append(len(tri) * len(queries))
        return exact(tri, queries)

    monkeypatch.setattr(_winding, "_exact", counting_exact)
    inside(vertices, faces, prepared.points)
    triangles = 2 * len(faces)  # at most, with the strips
    assert sum(calls) <= max(4_000_000, 64 * (len(prepared.points) + triangles))


def test_strip_budget_caps_only_the_largest_requests():
    from dentopo.sign._strips import _capped

    wanted = np.array([3, 1, 500, 2, 40, 0])
    np.testing.assert_array_equal(_capped(wanted, 1000), wanted)  # within the budget
    capped = _capped(wanted, 30)
    np.testing.assert_array_equal(capped, [3, 1, 12, 2, 12, 0])  # 6 + 2 x 12 = 30
    assert _capped(wanted, 3).sum() <= 3


# --- the hierarchy, the near field's product and the thread count ---------------------------


def _thin_slab(thickness: float) -> trimesh.Trimesh:
    """A closed box 1 x 1 x `thickness`, finely triangulated (both faces close together)."""
    slab = trimesh.creation.box(extents=(1.0, 1.0, thickness))
    for _ in range(4):
        slab = slab.subdivide()
    return slab


def test_thin_slab_and_points_near_both_faces_agree_with_the_exact_test():
    slab = _thin_slab(1e-3)
    rng = np.random.default_rng(3)
    xy = rng.uniform(-0.49, 0.49, size=(3000, 2))
    # anywhere across the slab and just outside, and a hair's breadth from either face
    z = rng.uniform(0, 1e-3, 3000)
    z[::3] = 5e-4 + rng.choice([-1e-9, 1e-9], 1000)
    points = np.column_stack([xy, rng.choice([-1.0, 1.0], 3000) * z])
    exact = exact_winding_number(slab.vertices, slab.faces, points)
    assert 0.2 < np.mean(np.abs(exact) > 0.5) < 0.8  # both sides are represented
    expected = np.abs(exact) > 0.5
    np.testing.assert_array_equal(inside(slab.vertices, slab.faces, points), expected)
    np.testing.assert_array_equal(expected, np.abs(points[:, 2]) < 5e-4)


def test_points_near_an_open_crown_capped_agree_with_the_exact_test(tooth):
    vertices, faces = close_holes(np.asarray(tooth.vertices), np.asarray(tooth.faces))
    rng = np.random.default_rng(4)
    mesh = trimesh.Trimesh(vertices, faces, process=False)
    edge = float(np.median(mesh.edges_unique_length))
    base = np.asarray(tooth.vertices)[rng.integers(0, len(tooth.vertices), 4000)]
    scale = np.array([edge, 1e-3 * edge, 1e-9])[rng.integers(0, 3, len(base))]
    points = base + scale[:, None] * rng.normal(size=base.shape)  # near, very near, on it
    exact = exact_winding_number(vertices, faces, points)
    np.testing.assert_array_equal(inside(vertices, faces, points), np.abs(exact) > 0.5)


def test_the_near_field_product_equals_the_sum_of_arctangents(sphere):
    # with an infinite far-field ratio every triangle is near: the product of ``_near_product``
    # against the sum of arctangents of ``_exact``, also for points on the surface
    from dentopo.sign._hierarchy import _ordered_triangles, _tree
    from dentopo.sign._winding import _approximate, _exact

    rng = np.random.default_rng(5)
    points = np.vstack(
        [
            rng.uniform(-1.5, 1.5, size=(500, 3)),
            sphere.triangles_center,  # on the surface
            sphere.vertices,  # on a vertex: atan2(0, 0) terms
            sphere.triangles_center + 1e-12 * sphere.face_normals,
        ]
    )
    tri = _ordered_triangles(sphere.vertices, sphere.faces)
    near, _ = _approximate(tri, _tree(tri), points, np.inf, True)
    np.testing.assert_allclose(near, _exact(tri, points), rtol=0, atol=1e-12)


def test_the_hierarchy_holds_its_triangles():
    # every triangle once, each node's sphere holds its vertices, its area vector is the sum
    from dentopo.sign._hierarchy import _DIPOLE, _RADIUS, _ordered_triangles, _shape, _tree

    slab = _thin_slab(0.2)
    tri = _ordered_triangles(slab.vertices, slab.faces)
    expected = np.sort(np.asarray(slab.triangles).reshape(len(slab.faces), 9), axis=0)
    np.testing.assert_array_equal(np.sort(tri.reshape(len(tri), 9), axis=0), expected)
    link, nodes, packed = _tree(tri)
    lo, hi, _, _ = _shape(len(tri), 4)
    area = 0.5 * np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    for node in range(len(link)):
        vertices = tri[lo[node] : hi[node]].reshape(-1, 3)
        reach = np.linalg.norm(vertices - nodes[node, :3], axis=1).max()
        assert reach <= packed[node, _RADIUS]
        np.testing.assert_allclose(
            packed[node, _DIPOLE : _DIPOLE + 3], area[lo[node] : hi[node]].sum(0), atol=1e-6
        )
        if link[node, 1] >= 0:
            assert (lo[node], hi[node]) == tuple(link[node])


def test_node_count_is_that_of_the_layout():
    from dentopo.sign._hierarchy import _node_count

    def halving(n, leaf):  # the ranges of ``_layout``, one by one
        ranges, count = [n], 0
        while ranges:
            k = ranges.pop()
            count += 1
            if k > leaf:
                ranges += [k // 2, k - k // 2]
        return count

    for leaf in (1, 2, 4, 5):
        for n in [*range(0, 70), 1000, 4097, 12345]:
            assert _node_count(n, leaf) == halving(n, leaf), (n, leaf)


def test_winding_numbers_do_not_depend_on_the_thread_count(tmp_path):
    # each query is computed alone and the hierarchy's levels own their ranges: the same
    # bits with 1 and 2 threads, on a mesh large enough for the parallel build
    import subprocess
    import sys

    script = tmp_path / "run.py"
    script.write_text(
        "import sys, numpy as np\n"
        "from dentopo.samples import tooth\n"
        "from dentopo.mesh import close_holes\n"
        "from dentopo.sign import winding_number\n"
        "crown = tooth(rings=190)\n"  # 108k vertices, 216k faces
        "v, f = close_holes(np.asarray(crown.vertices), np.asarray(crown.faces))\n"
        "rng = np.random.default_rng(6)\n"
        "p = v[rng.integers(0, len(v), 20000)] + rng.normal(scale=1e-3, size=(20000, 3))\n"
        "np.save(sys.argv[1], winding_number(v, f, p, far_field_ratio=1.5, second_order=True))\n"
    )
    import os

    results = []
    for threads in ("1", "2"):
        out = tmp_path / f"w{threads}.npy"
        env = dict(os.environ, NUMBA_NUM_THREADS=threads)
        subprocess.run([sys.executable, str(script), str(out)], check=True, env=env)
        results.append(np.load(out))
    assert results[0].tobytes() == results[1].tobytes()


def test_close_holes_finds_the_boundary_of_consistent_faces_like_boundary_edges():
    from dentopo.mesh._topology import _consistent_boundary

    sphere = trimesh.creation.icosphere(subdivisions=3)
    opened = sphere.faces[sphere.triangles_center[:, 2] < 0.6]
    degenerate = np.vstack([opened, [[0, 0, 5]]])  # an edge from a vertex to itself
    for faces in (opened, degenerate, sphere.faces, opened[:, ::-1]):
        found = _consistent_boundary(faces, len(sphere.vertices))
        np.testing.assert_array_equal(found, boundary_edges(faces, len(sphere.vertices)))
    flipped = opened.copy()
    flipped[::3] = flipped[::3, ::-1]
    assert _consistent_boundary(flipped, len(sphere.vertices)) is None  # the general path
    vertices, faces = close_holes(sphere.vertices, flipped)
    closed = trimesh.Trimesh(vertices, faces, process=False)
    assert closed.is_watertight and closed.is_winding_consistent


def test_the_exact_sums_in_blocks_of_queries_are_those_of_one_call(tooth, monkeypatch):
    # the exact sums run in blocks of queries (so that Ctrl-C and SIGTERM are raised
    # between blocks): every block size gives the same values, bit for bit
    from dentopo.sign import _winding

    vertices, faces = np.asarray(tooth.vertices), np.asarray(tooth.faces)
    tri = np.ascontiguousarray(vertices[faces], dtype=np.float64)
    rng = np.random.default_rng(7)
    queries = vertices[rng.choice(len(vertices), 300)] + rng.normal(scale=1e-3, size=(300, 3))
    queries = np.ascontiguousarray(queries)
    whole = np.empty(len(queries))
    _winding._exact_sums(tri, queries, whole)
    for per_call in (None, 1, 7, 299, 300, 10_000):
        assert np.array_equal(_winding._exact(tri, queries, per_call), whole), per_call
    monkeypatch.setattr(_winding, "EXACT_PAIRS_PER_CALL", 1)  # one query a thread per call
    expected = exact_winding_number(vertices, faces, queries)
    assert np.array_equal(expected, whole / (4.0 * np.pi))


@pytest.mark.parametrize("cell", [1e-3, 0.05, 0.3, 10.0])
def test_grid_cells_are_numpys_unique_rows(cell):
    rng = np.random.default_rng(7)
    points = np.vstack([rng.normal(size=(2000, 3)), np.zeros((5, 3)), -np.zeros((5, 3))])
    points[1000:1100] = points[:100]  # exact repeats
    expected = np.unique(np.floor(points / cell), axis=0)
    got = _strips._grid_cells(points, cell)
    np.testing.assert_array_equal((got + 0.5) * cell, (expected + 0.5) * cell)
