"""The crop step of ``prepare``: a sphere cut by a plane has a planar base of the right radius."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from conftest import shared_mesh
from dentopo.mesh import boundary_edges
from dentopo.prepare import _crop

R = 2.0


def _sphere(subdivisions=4, radius=R):
    sphere = trimesh.creation.icosphere(subdivisions=subdivisions, radius=radius)
    return np.asarray(sphere.vertices, dtype=np.float64), np.asarray(sphere.faces, dtype=np.int64)


def _frozen(*arrays):
    out = []
    for array in arrays:
        array = np.array(array)
        array.setflags(write=False)
        out.append(array)
    return out


def _area(vertices, faces):
    return trimesh.Trimesh(vertices, faces, process=False).area


def _loops(vertices, faces):
    """The boundary's loops: (count, each vertex's number of boundary edges)."""
    edges = boundary_edges(faces, len(vertices))
    mesh = trimesh.Trimesh(vertices, faces, process=False)
    count = len(trimesh.graph.connected_components(edges, nodes=np.unique(edges)))
    degree = np.bincount(edges.ravel(), minlength=len(vertices))
    return count, degree, edges, mesh


def _chord_deficit(vertices, faces, radius, distance):
    """How far inside the circle of the cut a loop vertex can lie, honestly bounded.

    The icosphere's vertices are on the sphere, its edges are chords: a point
    of a chord of length at most L is at least ``sqrt(R^2 - L^2 / 4)`` from
    the centre.  Cut by a plane at `distance` from the centre, such a point
    lies at least ``sqrt(R^2 - L^2 / 4 - d^2)`` from the plane's centre; the
    circle's radius is ``sqrt(R^2 - d^2)``.
    """
    ends = vertices[faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)]
    longest = np.linalg.norm(ends[:, 1] - ends[:, 0], axis=1).max()
    circle = np.sqrt(radius**2 - distance**2)
    return circle, circle - np.sqrt(radius**2 - longest**2 / 4 - distance**2)


@pytest.mark.parametrize("height", [0.0, 0.3, -1.1, 1.2])
def test_sphere_cut_by_a_plane_has_a_planar_circular_base(height):
    vertices, faces = _sphere()
    out = _crop.run(vertices, faces, plane=(0.0, 0.0, height, 0.0, 0.0, 1.0))
    v, f = out.vertices, out.faces
    count, degree, edges, mesh = _loops(v, f)
    # one loop, not a crack: every boundary vertex has exactly two boundary edges
    assert count == 1
    assert set(np.unique(degree[degree > 0])) == {2}
    assert out.details["boundary_loops"] == 1 and out.details["pieces"] == 1
    assert out.details["faces_cut"] > 0
    assert mesh.is_winding_consistent
    base = np.unique(edges)
    np.testing.assert_allclose(v[base, 2], height, rtol=0, atol=1e-12 * R)
    assert v[:, 2].min() >= height  # nothing on the removed side
    # the base's radius: on or inside the circle, by at most the chord's sagitta
    circle, deficit = _chord_deficit(vertices, faces, R, height)
    radius = np.hypot(v[base, 0], v[base, 1])
    assert radius.max() <= circle + 1e-12
    assert radius.min() >= circle - deficit * (1 + 1e-9)
    assert deficit < 1e-3 * R * 2.5  # subdivision 4: the loop is within ~1e-3 R of the circle
    # the area: the spherical cap's, within the mesh's own discretisation error
    cap = 2 * np.pi * R * (R - height)
    sphere_area = _area(vertices, faces)
    effective = np.sqrt(sphere_area / (4 * np.pi))  # the sphere of the mesh's area
    shrink = (R - effective) / R
    first_order = (2 * R - height) / (R - height) * shrink
    assert abs(mesh.area / cap - 1) < 1.5 * first_order
    assert mesh.area == pytest.approx(2 * np.pi * effective * (effective - height), rel=1e-3)
    point, normal = out.plane
    np.testing.assert_allclose(point, [0, 0, height])
    np.testing.assert_allclose(normal, [0, 0, 1])


def test_trimesh_alone_leaves_a_crack():
    """Why the cut points are merged: trimesh gives each cut face its own copies."""
    vertices, faces = _sphere()
    v, f, _ = trimesh.intersections.slice_faces_plane(
        vertices, faces, np.array([0.0, 0.0, 1.0]), np.array([0.0, 0.0, 0.3])
    )
    mine = _crop.run(vertices, faces, plane=(0.0, 0.0, 0.3, 0.0, 0.0, 1.0))
    assert len(boundary_edges(f, len(v))) > 2 * len(boundary_edges(mine.faces, len(mine.vertices)))
    assert mine.details["merged_vertices"] > 0


@pytest.mark.parametrize("seed", range(3))
def test_tilted_plane(seed):
    vertices, faces = _sphere()
    rng = np.random.default_rng(seed)
    normal = rng.normal(size=3)
    normal /= np.linalg.norm(normal)
    distance = rng.uniform(-1.2, 1.2)
    point = distance * normal + np.cross(normal, rng.normal(size=3))  # any point of the plane
    out = _crop.run(vertices, faces, plane=(*point, *(3.0 * normal)))
    count, _, edges, _ = _loops(out.vertices, out.faces)
    assert count == 1
    base = np.unique(edges)
    offset = (out.vertices - point) @ normal
    np.testing.assert_allclose(offset[base], 0.0, atol=1e-12 * R)
    assert offset.min() >= -1e-12 * R
    centre = distance * normal
    flat = out.vertices[base] - centre
    radius = np.linalg.norm(flat - np.outer(flat @ normal, normal), axis=1)
    circle, deficit = _chord_deficit(vertices, faces, R, distance)
    assert radius.max() <= circle + 1e-9
    assert radius.min() >= circle - deficit * (1 + 1e-6)
    np.testing.assert_allclose(out.plane[1], normal)  # the unit normal, reported


def test_fraction_and_below_are_their_planes():
    vertices, faces = _sphere(subdivisions=3)
    height = 0.7
    by_plane = _crop.run(vertices, faces, plane=(0.0, 0.0, -R + height, 0.0, 0.0, 1.0))
    below = _crop.run(vertices, faces, below=height)
    fraction = _crop.run(vertices, faces, fraction=(2 * R - height) / (2 * R))
    for other in (below, fraction):
        np.testing.assert_allclose(other.vertices, by_plane.vertices, atol=1e-12)
        np.testing.assert_array_equal(other.faces, by_plane.faces)
        np.testing.assert_allclose(other.plane[0], by_plane.plane[0], atol=1e-12)
    assert below.details["height"] == pytest.approx(height)
    assert fraction.details["kept_height"] == pytest.approx(2 * R - height)


def test_removing_everything_is_an_error_naming_the_plane():
    vertices, faces = _sphere(subdivisions=2)
    named = r"crop plane through \(0, 0, 2\.5\) with normal \(0, 0, 1\) \(mesh units\)"
    with pytest.raises(ValueError, match=named):
        _crop.run(vertices, faces, plane=(0.0, 0.0, 2.5, 0.0, 0.0, 1.0))
    with pytest.raises(ValueError, match="removes the whole mesh"):
        _crop.run(vertices, faces, below=2 * R)


def test_removing_nothing_is_fine():
    vertices, faces = _sphere(subdivisions=2)
    out = _crop.run(vertices, faces, plane=(0.0, 0.0, -3.0, 0.0, 0.0, 1.0))
    np.testing.assert_array_equal(out.vertices, vertices)
    np.testing.assert_array_equal(out.faces, faces)
    assert out.details["faces_cut"] == 0 and out.details["faces_removed"] == 0
    full = _crop.run(vertices, faces, fraction=1.0)
    np.testing.assert_array_equal(full.faces, faces)


def test_pieces_are_kept_and_counted():
    """Two spheres side by side: both caps are kept, reported as two pieces."""
    a, fa = _sphere(subdivisions=2, radius=1.0)
    vertices = np.concatenate([a, a + np.array([3.0, 0.0, 0.0])])
    faces = np.concatenate([fa, fa + len(a)])
    out = _crop.run(vertices, faces, plane=(0.0, 0.0, 0.2, 0.0, 0.0, 1.0))
    assert out.details["pieces"] == 2 and out.details["boundary_loops"] == 2
    assert out.pieces_removed == 0


@pytest.mark.parametrize("options", [{"fraction": 0.5}, {"plane": (0.1, 0, 0, 1, 1, 1)}])
def test_input_never_modified(options):
    vertices, faces = _sphere(subdivisions=3)
    frozen_vertices, frozen_faces = _frozen(vertices, faces)
    out = _crop.run(frozen_vertices, frozen_faces, **options)
    np.testing.assert_array_equal(frozen_vertices, vertices)
    np.testing.assert_array_equal(frozen_faces, faces)
    assert not np.shares_memory(out.vertices, frozen_vertices)


def test_snapping_leaves_no_sliver():
    """A vertex a hair's breadth above the plane lies on it: no face thinner than that."""
    vertices, faces = _sphere(subdivisions=3)
    height = float(np.sort(np.unique(vertices[:, 2]))[40])
    out = _crop.run(vertices, faces, plane=(0.0, 0.0, height - 1e-13, 0.0, 0.0, 1.0))
    tri = out.vertices[out.faces]
    area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
    assert area.min() > 1e-8
    assert _loops(out.vertices, out.faces)[0] == 1
    assert out.vertices[:, 2].min() >= height - 1e-13


def test_crown_cropped_in_the_pipeline():
    """Oriented, then the top 60 % kept: a crown with one planar base loop at the plane's height."""
    import dentopo

    path = shared_mesh("normal")
    mesh = trimesh.load(path, process=False)
    prepared = dentopo.prepare(mesh, crop_fraction=0.6)
    crop = prepared.step("crop")
    v, f = np.asarray(prepared.vertices), np.asarray(prepared.faces)
    count, _, edges, _ = _loops(v, f)
    height = crop.plane["point"][2]
    np.testing.assert_allclose(v[np.unique(edges), 2], height, atol=1e-12 * np.ptp(v))
    assert v[:, 2].min() >= height
    assert count == crop.details["boundary_loops"] >= 1
    assert crop.details["faces_cut"] > 0 and crop.faces_after < crop.faces_before
    oriented = dentopo.prepare(mesh).vertices[:, 2]
    assert v[:, 2].max() == pytest.approx(oriented.max())
    assert crop.details["kept_height"] == pytest.approx(oriented.max() - height)
    assert oriented.max() - height == pytest.approx(0.6 * np.ptp(oriented))
