"""Which way a crown points, by the stated rule, and turning it with orient="auto"."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from conftest import hemisphere, shared_mesh
from dentopo.mesh import close_holes, outward_faces
from dentopo.topography import (
    find_orientation,
    opc,
    opcr,
    orient_vertices,
    rfi,
    slope,
)

TURN = np.diag([1.0, -1.0, -1.0])


def dome(rings=10, segments=20):
    mesh = hemisphere(rings=rings, segments=segments)
    mesh.vertices[:, 2] *= 0.6
    return mesh


def capped(mesh):
    """An open mesh closed by a fan over its base, faces outward."""
    vertices, faces = close_holes(mesh.vertices, mesh.faces)
    return trimesh.Trimesh(vertices, outward_faces(vertices, faces), process=False)


def test_an_open_crown_points_away_from_its_open_base():
    up = dome()
    assert find_orientation(up.vertices, up.faces).points == "+z"
    assert find_orientation(up.vertices, up.faces).rule == "open base"
    down = up.vertices @ TURN.T
    assert find_orientation(down, up.faces).points == "-z"
    # the rule does not depend on how the faces are oriented
    assert find_orientation(down, up.faces[:, ::-1]).points == "-z"


def test_a_closed_crown_points_to_the_side_its_area_faces():
    sphere = trimesh.creation.icosphere(subdivisions=3)
    upper = sphere.faces[sphere.vertices[sphere.faces].mean(axis=1)[:, 2] > 0]
    closed = capped(trimesh.Trimesh(sphere.vertices, upper))  # 2 pi r^2 up, pi r^2 down
    assert closed.is_watertight
    found = find_orientation(closed.vertices, closed.faces)
    assert (found.points, found.rule) == ("+z", "area")
    assert find_orientation(closed.vertices @ TURN.T, closed.faces).points == "-z"


def test_a_sphere_is_undetermined_and_never_turned():
    sphere = trimesh.creation.icosphere(subdivisions=3)
    found = find_orientation(sphere.vertices, sphere.faces)
    assert found.points == "undetermined" and found.warning() is None
    vertices, done = orient_vertices(sphere.vertices, sphere.faces, "auto")
    assert not done.turned and np.array_equal(vertices, sphere.vertices)


def test_auto_turns_a_crown_pointing_down_and_equals_turning_it_by_hand():
    up = dome()
    down = trimesh.Trimesh(up.vertices @ TURN.T, up.faces, process=False)
    before = down.vertices.copy()
    with pytest.warns(UserWarning, match="points to -z"):
        as_is = slope(down)
    assert str(as_is.orientation) == "-z"
    turned = slope(down, orient="auto")
    assert str(turned.orientation) == "-z, turned to +z"
    assert np.array_equal(turned.face_slope, slope(up).face_slope)
    assert np.array_equal(as_is.face_slope, 180 - turned.face_slope)
    assert opc(down, orient="auto").opc == opc(up).opc
    assert opcr(down, orient="auto").opc_values == opcr(up).opc_values
    # from alpha 1: on this coarse dome molaR's walk from 0.075 runs out of its 99 hulls
    searched = rfi(down, orient="auto", alpha=1.0, find_alpha=True)
    expected = rfi(up, alpha=1.0, find_alpha=True)
    assert (searched.rfi, searched.alpha) == (expected.rfi, expected.alpha)
    np.testing.assert_array_equal(down.vertices, before)  # the caller's mesh is untouched


def test_a_crown_pointing_up_is_measured_as_it_is_and_not_warned_about(recwarn):
    up = dome()
    assert str(slope(up, orient="auto").orientation) == "+z"
    assert slope(up, orient="auto").slope == slope(up).slope
    assert not [w for w in recwarn if "points to" in str(w.message)]


def test_bad_orient_is_refused():
    with pytest.raises(ValueError, match="orient must be one of"):
        slope(dome(), orient="up")


@pytest.mark.parametrize("name", ["normal", "low_hole"])
def test_the_papers_crowns_point_down(name):
    path = shared_mesh(name)
    result = slope(path, orient="auto")
    assert str(result.orientation) == "-z, turned to +z"
    assert result.slope < 90  # molaR's 106 degrees, measured the right way up
