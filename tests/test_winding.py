"""The inside test: exact where it matters, independent of luck and orientation."""

from __future__ import annotations

import numpy as np
import trimesh

from dentopo.mesh import boundary_edges, close_holes, orient_consistently
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
    from dentopo.sign._winding import _split_long

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
    from dentopo.sign._winding import STRIP_BUDGET, _split_long

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
    from dentopo.sign._winding import _capped

    wanted = np.array([3, 1, 500, 2, 40, 0])
    np.testing.assert_array_equal(_capped(wanted, 1000), wanted)  # within the budget
    capped = _capped(wanted, 30)
    np.testing.assert_array_equal(capped, [3, 1, 12, 2, 12, 0])  # 6 + 2 x 12 = 30
    assert _capped(wanted, 3).sum() <= 3
