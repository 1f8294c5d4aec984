"""The camera rule: the occlusal view of open crowns and closed surfaces, named views, turns.

The paper's crowns point to -z (their cut rim faces +z): the occlusal camera
must stand on the -z side of ``normal.ply``, and on the +z side of a copy
turned upside down.
"""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from conftest import shared_mesh
from dentopo.figures import Camera, camera_for

#: Turned upside down: 180 degrees about x, a proper rotation.
UPSIDE_DOWN = np.diag([1.0, -1.0, -1.0])


def towards(camera: Camera) -> np.ndarray:
    return camera.rotation()[2]


@pytest.fixture(scope="module")
def normal():
    mesh = trimesh.load(shared_mesh("normal"), process=False)
    return np.asarray(mesh.vertices), np.asarray(mesh.faces)


def test_normal_ply_is_seen_from_minus_z(normal):
    vertices, faces = normal
    camera = camera_for(vertices, faces)
    assert camera.view == "occlusal"
    assert towards(camera)[2] < -0.9
    assert camera.position[2] < vertices[:, 2].min()  # the camera stands below the crown


def test_normal_ply_upside_down_is_seen_from_plus_z(normal):
    vertices, faces = normal
    camera = camera_for(vertices @ UPSIDE_DOWN.T, faces)
    assert towards(camera)[2] > 0.9
    assert camera.position[2] > (vertices @ UPSIDE_DOWN.T)[:, 2].max()


def test_sample_crown_points_up_and_turned_down(tooth):
    vertices, faces = np.asarray(tooth.vertices), np.asarray(tooth.faces)
    assert towards(camera_for(vertices, faces))[2] > 0.9
    assert towards(camera_for(vertices @ UPSIDE_DOWN.T, faces))[2] < -0.9


def test_the_rule_follows_the_mesh_not_the_axes(tooth):
    # a crown lying on its side, pointing to +x: seen from +x
    turn = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]])  # +z to +x
    vertices = np.asarray(tooth.vertices) @ turn.T
    assert towards(camera_for(vertices, tooth.faces))[0] > 0.9


def closed_dome() -> trimesh.Trimesh:
    """A closed half ball, flat base at z = 0: two thirds of its area face +z."""
    sphere = trimesh.creation.icosphere(subdivisions=3)
    points = np.asarray(sphere.vertices)
    points = points[points[:, 2] >= 0]
    angle = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    rim = np.column_stack([np.cos(angle), np.sin(angle), np.zeros_like(angle)])
    hull = trimesh.convex.convex_hull(np.vstack([points, rim]))
    assert hull.is_watertight
    return hull


def test_closed_mesh_is_seen_along_its_thinnest_axis_from_its_area_side():
    dome = closed_dome()
    vertices, faces = np.asarray(dome.vertices), np.asarray(dome.faces)
    assert towards(camera_for(vertices, faces))[2] > 0.9
    assert towards(camera_for(vertices @ UPSIDE_DOWN.T, faces))[2] < -0.9


def test_closed_mesh_without_a_side_is_seen_from_plus_z():
    ellipsoid = trimesh.creation.icosphere(subdivisions=3)
    vertices = np.asarray(ellipsoid.vertices) * [2.0, 1.5, 0.5]
    faces = np.asarray(ellipsoid.faces)
    assert towards(camera_for(vertices, faces))[2] > 0.99
    assert towards(camera_for(vertices @ UPSIDE_DOWN.T, faces))[2] > 0.99


def test_the_longer_axis_runs_across_the_picture():
    ellipsoid = trimesh.creation.icosphere(subdivisions=3)
    vertices = np.asarray(ellipsoid.vertices) * [0.5, 3.0, 1.0]  # longest along y
    rotation = camera_for(vertices, ellipsoid.faces).rotation()
    assert abs(rotation[0][1]) > 0.99  # right is along y
    assert abs(rotation[2][0]) > 0.99  # seen along x, the thinnest


def test_named_views_follow_the_mesh_axes(tooth):
    v, f = tooth.vertices, tooth.faces
    np.testing.assert_allclose(towards(camera_for(v, f, "top")), [0, 0, 1], atol=1e-12)
    np.testing.assert_allclose(towards(camera_for(v, f, "bottom")), [0, 0, -1], atol=1e-12)
    np.testing.assert_allclose(towards(camera_for(v, f, "front")), [0, -1, 0], atol=1e-12)
    np.testing.assert_allclose(towards(camera_for(v, f, "LEFT")), [-1, 0, 0], atol=1e-12)
    iso = towards(camera_for(v, f, "iso"))
    np.testing.assert_allclose(iso, np.array([1, -1, 1]) / np.sqrt(3), atol=1e-12)


def test_azimuth_and_elevation_turn_from_the_view(tooth):
    v, f = tooth.vertices, tooth.faces
    base = camera_for(v, f).rotation()
    turned = camera_for(v, f, azimuth=180.0).rotation()
    np.testing.assert_allclose(turned[2], -base[2], atol=1e-12)
    np.testing.assert_allclose(turned[1], base[1], atol=1e-12)
    raised = camera_for(v, f, elevation=90.0).rotation()
    np.testing.assert_allclose(raised[2], base[1], atol=1e-12)  # now looking from above
    side = camera_for(v, f, azimuth=90.0).rotation()
    np.testing.assert_allclose(side[2], base[0], atol=1e-12)  # from the picture's right
    assert camera_for(v, f, azimuth=30.0, elevation=-10.0).azimuth == 30.0


def test_camera_frames_the_mesh(tooth):
    vertices = np.asarray(tooth.vertices)
    camera = camera_for(vertices, tooth.faces, "front")
    rotation = camera.rotation()
    offset = vertices - camera.focal_point
    across, up = offset @ rotation[0], offset @ rotation[1]
    # the focal point is the centre of the mesh's extent across and up the picture
    assert abs(across.min() + across.max()) < 1e-9 and abs(up.min() + up.max()) < 1e-9
    assert np.linalg.norm(np.subtract(camera.position, camera.focal_point)) > np.ptp(vertices)
    half = camera.half_extent(vertices, aspect=2.0, margin=0.1)
    assert np.abs(up).max() <= 0.8 * half + 1e-12 and np.abs(across).max() <= 1.6 * half + 1e-12


def test_a_camera_given_as_points_is_kept(tooth):
    points = ((0.0, 0.0, 10.0), (0.0, 0.0, 0.5), (0.0, 1.0, 0.0))
    camera = camera_for(tooth.vertices, tooth.faces, points)
    assert camera.view == "camera"
    np.testing.assert_allclose(camera.position, points[0])
    np.testing.assert_allclose(camera.focal_point, points[1])
    np.testing.assert_allclose(camera.up, points[2])
    assert camera_for(tooth.vertices, tooth.faces, camera) == camera


def test_bad_views_are_refused(tooth):
    v, f = tooth.vertices, tooth.faces
    with pytest.raises(ValueError, match="view must be one of"):
        camera_for(v, f, "sideways")
    with pytest.raises(ValueError, match=r"shape \(3, 3\)"):
        camera_for(v, f, [[0, 0, 1], [0, 0, 0]])
    with pytest.raises(ValueError, match="view-up"):
        camera_for(v, f, [[0, 0, 1], [0, 0, 0], [0, 0, 1]])
    with pytest.raises(TypeError, match="azimuth"):
        camera_for(v, f, azimuth="left")
    with pytest.raises(TypeError, match="elevation"):
        camera_for(v, f, elevation=float("nan"))


def test_inputs_are_not_modified(normal):
    vertices, faces = normal
    before = vertices.copy(), faces.copy()
    camera_for(vertices, faces, azimuth=20.0)
    np.testing.assert_array_equal(vertices, before[0])
    np.testing.assert_array_equal(faces, before[1])
