"""PCV's exact method (one ray per vertex and direction, Embree): analytic cases and invariances.

The directions here are a Fibonacci lattice of the hemisphere (equal-area: uniform
in z), made independently of :mod:`dentopo.topography.occlusion._directions`,
except where Leopardi's partition itself is checked to converge.
"""

from __future__ import annotations

import sys
import tracemalloc

import numpy as np
import pytest
import trimesh

pytest.importorskip("embreex")

from dentopo._optional import MissingExtraError
from dentopo.topography.occlusion import _rays
from dentopo.topography.occlusion._rays import lit_counts_rays

GOLDEN = np.pi * (3.0 - np.sqrt(5.0))


def fibonacci(k: int, sphere: bool = False) -> np.ndarray:
    """k near-equal-area unit vectors over the upper hemisphere (or the whole sphere)."""
    i = np.arange(k)
    z = 1.0 - (i + 0.5) / k
    if sphere:
        z = 2.0 * z - 1.0
    r = np.sqrt(1.0 - z * z)
    return np.c_[r * np.cos(i * GOLDEN), r * np.sin(i * GOLDEN), z]


def rotation_z(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def grid(xs: np.ndarray, ys: np.ndarray, height) -> tuple[np.ndarray, np.ndarray]:
    """A height field z = height(x, y) over the grid, wound so that its normals point up."""
    x, y = np.meshgrid(xs, ys, indexing="ij")
    vertices = np.c_[x.ravel(), y.ravel(), height(x, y).ravel()]
    idx = np.arange(x.size).reshape(x.shape)
    a, b = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel()
    c, d = idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    return vertices, np.r_[np.c_[a, b, c], np.c_[a, c, d]]


def v_groove(half_angle: float, left: int = 9, right: int = 23):
    """A V-groove along y: walls z = |x| / tan(half_angle), cut into unequal triangles
    (`left` and `right` columns), and the indices of its floor vertices away from the ends."""
    reach = np.tan(half_angle)  # wall height 1
    xs = np.r_[np.linspace(-reach, 0.0, left + 1)[:-1], np.linspace(0.0, reach, right + 1)]
    ys = np.linspace(0.0, 4.0, 81)
    vertices, faces = grid(xs, ys, lambda x, y: np.abs(x) / np.tan(half_angle))
    floor = np.flatnonzero((vertices[:, 0] == 0.0) & (vertices[:, 1] > 1) & (vertices[:, 1] < 3))
    return vertices, faces, floor


def bowl(rim_colatitude: float, rings: int = 24, segments: int = 128):
    """The inside of a unit sphere from its south pole up to `rim_colatitude` (from the
    north pole), wound so its normals point to the centre; vertex 0 is the bottom."""
    theta = np.linspace(np.pi, rim_colatitude, rings + 1)[1:]
    phi = np.linspace(0.0, 2 * np.pi, segments, endpoint=False)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    ring_vertices = np.c_[
        (np.sin(t) * np.cos(p)).ravel(), (np.sin(t) * np.sin(p)).ravel(), np.cos(t).ravel()
    ]
    vertices = np.r_[[[0.0, 0.0, -1.0]], ring_vertices]
    idx = 1 + np.arange(rings * segments).reshape(rings, segments)
    nxt = np.roll(idx, -1, axis=1)
    fan = np.c_[np.zeros(segments, int), idx[0], nxt[0]]
    a, b, c, d = idx[:-1].ravel(), nxt[:-1].ravel(), nxt[1:].ravel(), idx[1:].ravel()
    faces = np.r_[fan, np.c_[a, b, c], np.c_[a, c, d]]
    # wind inward: the material is outside the sphere
    centre_side = np.einsum(
        "ij,ij->i",
        np.cross(
            vertices[faces[:, 1]] - vertices[faces[:, 0]],
            vertices[faces[:, 2]] - vertices[faces[:, 0]],
        ),
        -vertices[faces].mean(axis=1),
    )
    faces[centre_side < 0] = faces[centre_side < 0][:, ::-1]
    return vertices, faces


def bowl_bottom_fraction(rim_colatitude: float) -> float:
    """The share of the hemisphere the bowl's bottom sees: the cone over the rim, a circle
    of the sphere seen from its south pole at half the rim's colatitude (the inscribed
    angle over the arc from the north pole to the rim).  The mesh's rim is a 128-gon
    inscribed in that circle: a relative difference of (2 pi / 128)**2 / 6 = 4e-4, below
    the tests' tolerances; the walls, chords inside the sphere, block nothing inside that
    cone (convexity) and everything outside it."""
    return 1.0 - np.cos(rim_colatitude / 2)


def bumpy(n: int = 41, seed: int = 0):
    """A height field with bumps and pits: most vertices see only part of the sky."""
    rng = np.random.default_rng(seed)
    centres, heights = rng.uniform(0, 1, (12, 2)), rng.normal(0, 0.25, 12)

    def height(x, y):
        z = np.zeros_like(x)
        for (cx, cy), h in zip(centres, heights, strict=True):
            z += h * np.exp(-((x - cx) ** 2 + (y - cy) ** 2) / 0.01)
        return z

    xs = np.linspace(0, 1, n)
    return grid(xs, xs, height)


# --- analytic cases -----------------------------------------------------------------------


def test_a_plane_facing_up_is_lit_from_every_direction_above_it_and_from_none_below():
    vertices, faces = grid(np.linspace(0, 1, 21), np.linspace(0, 2, 31), lambda x, y: 0 * x)
    directions = fibonacci(500, sphere=True)
    x, y = vertices[:, 0], vertices[:, 1]
    inner = (x > 0.1) & (x < 0.9) & (y > 0.1) & (y < 1.9)
    for angle in (0.0, 0.7):  # turned about a horizontal axis, directions with it
        c, s = np.cos(angle), np.sin(angle)
        turn = np.array([[1.0, 0, 0], [0, c, -s], [0, s, c]])
        lit = lit_counts_rays(vertices @ turn.T, faces, directions @ turn.T)
        assert (lit[inner] == np.sum(directions[:, 2] > 0)).all()
    # and each direction: lit exactly when it is above the plane
    for d in directions[::50]:
        lit = lit_counts_rays(vertices, faces, d[None])
        assert (lit[inner] == int(d[2] > 0)).all()


@pytest.mark.parametrize("degrees", [20.0, 45.0, 70.0])
def test_a_v_groove_floor_sees_the_wedge_two_half_angles_over_pi(degrees):
    # a direction at angle psi from the vertical in the x-z plane (any tilt along y) lights
    # the floor iff |psi| <= half-angle a; over the hemisphere that is 4a / (2 pi) = 2a / pi
    a = np.deg2rad(degrees)
    vertices, faces, floor = v_groove(a)
    directions = fibonacci(8192)
    share = lit_counts_rays(vertices, faces, directions)[floor] / len(directions)
    assert np.abs(share - 2 * a / np.pi).max() < 2e-3


@pytest.mark.parametrize("rim_degrees", [90.0, 60.0, 120.0])
def test_a_spherical_bowl_bottom_sees_the_cone_over_its_rim(rim_degrees):
    rim = np.deg2rad(rim_degrees)
    vertices, faces = bowl(rim)
    directions = fibonacci(8192)
    share = lit_counts_rays(vertices, faces, directions)[0] / len(directions)
    assert share == pytest.approx(bowl_bottom_fraction(rim), abs=2e-3)


def test_the_share_converges_to_the_closed_form_as_the_rays_grow():
    rim = np.deg2rad(90.0)
    vertices, faces = bowl(rim)
    expected = bowl_bottom_fraction(rim)
    errors = {}
    for k in (64, 256, 1024, 4096):
        errors[k] = abs(lit_counts_rays(vertices, faces, fibonacci(k))[0] / k - expected)
        assert errors[k] <= 2.0 / k**0.75  # the lattice's discrepancy for a cap
    assert errors[4096] < 1e-3


def test_the_share_converges_with_leopardis_directions_too():
    from dentopo.topography.occlusion._directions import light_directions

    a = np.deg2rad(45.0)
    vertices, faces, floor = v_groove(a)
    for rays in (256, 1024, 4096):
        directions = light_directions(rays, True)
        share = lit_counts_rays(vertices, faces, directions)[floor] / len(directions)
        assert np.abs(share - 2 * a / np.pi).max() <= 2.0 / np.sqrt(rays)


def test_a_direction_into_the_surface_is_not_lit_even_where_the_ray_would_leave_the_mesh():
    # a single tilted plane: from below, a ray into it would escape (nothing else there)
    vertices, faces = grid(np.linspace(0, 1, 11), np.linspace(0, 1, 11), lambda x, y: 0.3 * x)
    inner = np.flatnonzero((np.abs(vertices[:, :2] - 0.5) < 0.3).all(axis=1))
    lit = lit_counts_rays(
        vertices, faces, np.array([[0.0, 0.0, -1.0], [0.9, 0.0, 0.1]]) / [[1], [np.hypot(0.9, 0.1)]]
    )
    assert (lit[inner] == 0).all()
    # the same faces wound the other way: the light now comes from below
    assert (
        lit_counts_rays(vertices, faces[:, ::-1], np.array([[0.0, 0.0, -1.0]]))[inner] == 1
    ).all()


def test_the_counts_agree_with_a_brute_force_double_precision_ray_cast():
    vertices, faces = bumpy(17, seed=3)
    directions = fibonacci(48)
    lit = lit_counts_rays(vertices, faces, directions)
    expected = brute_force(vertices, faces, directions)
    # the same but for a ray or two grazing an edge (1 of 13872 pairs when measured)
    assert np.abs(lit - expected).sum() <= 3


def brute_force(vertices, faces, directions):
    """Each vertex lit from d: d above the height field at v (the surface's outer side) and
    the ray from v itself meeting no face without v (Moller-Trumbore, float64)."""
    a, b, c = vertices[faces[:, 0]], vertices[faces[:, 1]], vertices[faces[:, 2]]
    e1, e2 = b - a, c - a
    normal = np.cross(e1, e2)
    counts = np.zeros(len(vertices), int)
    for i, v in enumerate(vertices):
        own = (faces == i).any(axis=1)
        for d in directions:
            # outer side: just along d, above the plane of the own face under that point
            q = v + 1e-9 * d
            under = [f for f in np.flatnonzero(own) if _inside_xy(q, a[f], b[f], c[f])]
            if under and np.dot(d, normal[under[0]]) < 0:  # v on that plane: q below it
                continue
            p = np.cross(d, e2)
            det = np.einsum("ij,ij->i", e1, p)
            with np.errstate(divide="ignore", invalid="ignore"):
                s = v - a
                u = np.einsum("ij,ij->i", s, p) / det
                qv = np.cross(s, e1)
                w = (qv @ d) / det
                t = np.einsum("ij,ij->i", qv, e2) / det
            hit = (~own) & (det != 0) & (u >= 0) & (w >= 0) & (u + w <= 1) & (t > 0)
            counts[i] += not hit.any()
    return counts


def _inside_xy(q, a, b, c) -> bool:
    def side(p, r, s):
        return (r[0] - p[0]) * (s[1] - p[1]) - (r[1] - p[1]) * (s[0] - p[0])

    d1, d2, d3 = side(q, a, b), side(q, b, c), side(q, c, a)
    return not ((min(d1, d2, d3) < 0) and (max(d1, d2, d3) > 0))


# --- invariances ---------------------------------------------------------------------------


@pytest.fixture(scope="module")
def field():
    vertices, faces = bumpy()
    directions = fibonacci(128)
    return vertices, faces, directions, lit_counts_rays(vertices, faces, directions)


def _agree(a, b, k):
    # the same counts but for a rare ray grazing an edge within rounding
    assert np.abs(a - b).sum() <= 1e-4 * a.size * k


@pytest.mark.parametrize("shift", [[1e3, -2e3, 5e2], [0.1, 0.2, 0.3], [-7e5, 0, 3e5]])
def test_the_counts_do_not_change_with_translation(field, shift):
    vertices, faces, directions, lit = field
    _agree(lit_counts_rays(vertices + shift, faces, directions), lit, len(directions))


@pytest.mark.parametrize("scale", [2.0**-20, 1e-3, 1e4, 2.0**30])
def test_the_counts_do_not_change_with_scale(field, scale):
    vertices, faces, directions, lit = field
    _agree(lit_counts_rays(vertices * scale, faces, directions), lit, len(directions))


def test_the_counts_do_not_change_with_vertex_and_face_order(field):
    vertices, faces, directions, lit = field
    rng = np.random.default_rng(5)
    order = rng.permutation(len(vertices))
    new_index = np.empty_like(order)
    new_index[order] = np.arange(len(order))
    new_faces = new_index[faces][rng.permutation(len(faces))]
    new_faces = np.roll(new_faces, 1, axis=1)  # each face from another corner, same winding
    _agree(lit_counts_rays(vertices[order], new_faces, directions), lit[order], len(directions))


def test_the_counts_turn_with_the_mesh_about_z(field):
    vertices, faces, directions, lit = field
    for angle in (0.3, np.pi / 2, 2.0):
        turn = rotation_z(angle)
        _agree(lit_counts_rays(vertices @ turn.T, faces, directions @ turn.T), lit, len(directions))
        # the directions left as they were: the same shares within the sampling
        turned = lit_counts_rays(vertices @ turn.T, faces, directions)
        assert abs(turned.mean() - lit.mean()) / len(directions) < 0.005


def test_the_inputs_are_not_modified_and_other_dtypes_are_taken(field):
    vertices, faces, directions, lit = field
    v32, f32, d = vertices.astype(np.float32), faces.astype(np.int32), directions.copy()
    copies = v32.copy(), f32.copy(), d.copy()
    for array in (v32, f32, d):
        array.flags.writeable = False
    result = lit_counts_rays(v32, f32, d)
    assert result.dtype == np.int64 and result.shape == (len(vertices),)
    for array, copy in zip((v32, f32, d), copies, strict=True):
        np.testing.assert_array_equal(array, copy)
    _agree(result, lit, len(directions))


# --- edges, errors, memory ------------------------------------------------------------------


def test_no_directions_count_zero_and_a_vertex_in_no_face_sees_what_no_face_blocks():
    vertices, faces = grid(np.linspace(0, 1, 5), np.linspace(0, 1, 5), lambda x, y: 0 * x)
    assert (lit_counts_rays(vertices, faces, np.zeros((0, 3))) == 0).all()
    loose = np.r_[vertices, [[0.5, 0.5, -1.0], [0.5, 0.5, 1.0]]]
    lit = lit_counts_rays(loose, faces, np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0]]))
    assert lit[-2:].tolist() == [1, 2]  # under the plane: blocked upwards; above: free


@pytest.mark.parametrize(
    "change, words",
    [
        (lambda v, f, d: (np.r_[v, [[np.nan, 0, 0]]], f, d), "NaN"),
        (lambda v, f, d: (v, np.r_[f, [[0, 1, len(v)]]], d), "indices"),
        (lambda v, f, d: (v, f, d * 1.01), "unit"),
        (lambda v, f, d: (v, f, np.r_[d, [[np.inf, 0, 0]]]), "direction"),
        (lambda v, f, d: (v[:, :2], f, d), "(n, 3)"),
        (lambda v, f, d: (v, f.astype(float), d), "integer"),
        (lambda v, f, d: (v, f, d[:, :2]), "(k, 3)"),
    ],
)
def test_bad_input_is_a_value_error_naming_the_problem(change, words):
    vertices, faces = grid(np.linspace(0, 1, 3), np.linspace(0, 1, 3), lambda x, y: 0 * x)
    with pytest.raises(ValueError, match=words.replace("(", r"\(").replace(")", r"\)")):
        lit_counts_rays(*change(vertices, faces, fibonacci(4)))


def test_without_embreex_the_exact_method_is_a_named_missing_extra(monkeypatch):
    for name in [m for m in sys.modules if m == "embreex" or m.startswith("embreex.")]:
        monkeypatch.delitem(sys.modules, name)
    monkeypatch.setitem(sys.modules, "embreex", None)
    vertices, faces = grid(np.linspace(0, 1, 3), np.linspace(0, 1, 3), lambda x, y: 0 * x)
    with pytest.raises(MissingExtraError, match="rays"):
        lit_counts_rays(vertices, faces, fibonacci(4))


def test_memory_grows_with_the_vertices_not_with_vertices_times_directions():
    vertices, faces = grid(np.linspace(0, 1, 300), np.linspace(0, 1, 300), lambda x, y: 0 * x)
    k = 128
    tracemalloc.start()
    try:
        lit_counts_rays(vertices, faces, fibonacci(k))
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    # n * k rays of float32 origins and directions would be 24 * n * k bytes (276 MB here);
    # the normals' temporaries take some 600 bytes a vertex
    assert peak < 1000 * len(vertices) < 24 * len(vertices) * k / 3


def test_chunks_of_vertices_count_as_one_call(field, monkeypatch):
    vertices, faces, directions, lit = field
    monkeypatch.setattr(_rays, "CHUNK_VERTICES", 100)
    np.testing.assert_array_equal(lit_counts_rays(vertices, faces, directions), lit)


def test_cutting_the_faces_in_four_changes_no_count_of_the_vertices_kept(field):
    # midpoint subdivision leaves the surface where it was: each old vertex sees the same sky
    vertices, faces, directions, lit = field
    finer, finer_faces = trimesh.remesh.subdivide(vertices, faces)
    counts = lit_counts_rays(finer, finer_faces, directions)
    np.testing.assert_array_equal(finer[: len(vertices)], vertices)
    _agree(counts[: len(vertices)], lit, len(directions))
