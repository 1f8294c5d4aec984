"""Which way a crown points, by the stated rule, and turning it with orient="auto"."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from conftest import ROBUSTNESS_SET, hemisphere, shared_mesh
from dentopo.mesh import close_holes, outward_faces
from dentopo.topography import (
    classic_dne,
    find_orientation,
    opc,
    opcr,
    orient_vertices,
    prepare_surface,
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
    assert found.points == "undetermined" and "the surface is closed" in found.warning()
    assert str(found) == "direction undetermined; closed, as it lies"
    vertices, done = orient_vertices(sphere.vertices, sphere.faces, "auto")
    assert not done.turned and np.array_equal(vertices, sphere.vertices)


def test_a_closed_crown_pointing_down_is_warned_about_and_not_turned():
    # issue 21: a closed surface has no open base; the area rule is a hint, never a turn
    sphere = trimesh.creation.icosphere(subdivisions=3)
    upper = sphere.faces[sphere.vertices[sphere.faces].mean(axis=1)[:, 2] > 0]
    closed = capped(trimesh.Trimesh(sphere.vertices, upper))
    down = (closed.vertices @ TURN.T, closed.faces)
    with pytest.warns(UserWarning, match="the surface is closed.*most of its area faces -z"):
        auto = slope(down)
    assert not auto.orientation.turned and str(auto.orientation) == "points -z; closed, as it lies"
    as_is = slope(down, orient="as-is")  # as it lies is what was asked for: nothing to say
    assert np.array_equal(auto.face_slope, as_is.face_slope)  # measured as it lies
    # classic DNE does not assume +z: no word about it there
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        classic_dne(down)


def test_auto_is_the_default_and_as_is_is_molars_way():
    up = dome()
    down = trimesh.Trimesh(up.vertices @ TURN.T, up.faces, process=False)
    assert str(slope(down).orientation) == "points -z, turned to +z"
    assert slope(down).slope == slope(down, orient="auto").slope
    with pytest.warns(UserWarning, match="points to -z"):
        assert slope(down, orient="as-is").slope > 90


def test_auto_turns_a_crown_pointing_down_and_equals_turning_it_by_hand():
    up = dome()
    down = trimesh.Trimesh(up.vertices @ TURN.T, up.faces, process=False)
    before = down.vertices.copy()
    with pytest.warns(UserWarning, match="points to -z"):
        as_is = slope(down, orient="as-is")
    assert str(as_is.orientation) == "points -z"
    turned = slope(down, orient="auto")
    assert str(turned.orientation) == "points -z, turned to +z"
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
    assert str(slope(up, orient="auto").orientation) == "points +z"
    assert slope(up, orient="auto").slope == slope(up).slope
    assert not [w for w in recwarn if "points to" in str(w.message)]


def test_bad_orient_is_refused():
    with pytest.raises(ValueError, match="orient must be one of"):
        slope(dome(), orient="up")


@pytest.mark.parametrize("name", ["normal", "low_hole"])
def test_the_papers_crowns_point_down(name):
    path = shared_mesh(name)
    result = slope(path, orient="auto")
    assert str(result.orientation) == "points -z, turned to +z"
    assert result.slope < 90  # molaR's 106 degrees, measured the right way up


# --- faces wound inward (issue 22, item 2) and flat surfaces (item 3) ---


def _rotation(seed: int) -> np.ndarray:
    """A random proper rotation."""
    q, r = np.linalg.qr(np.random.default_rng(seed).normal(size=(3, 3)))
    q = q * np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


def _caught(function, *args, **kwargs):
    import warnings

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = function(*args, **kwargs)
    return result, [str(w.message) for w in caught if issubclass(w.category, UserWarning)]


def test_faces_wound_inward_are_warned_about_and_rewound_with_auto():
    up = dome()
    inward = trimesh.Trimesh(up.vertices, up.faces[:, ::-1], process=False)
    found = find_orientation(inward.vertices, inward.faces)
    assert (found.points, found.winding) == ("+z", "inward")
    as_is, caught = _caught(slope, inward, orient="as-is")
    assert any("every face is wound inward" in m and "orient='auto'" in m for m in caught)
    assert str(as_is.orientation) == "points +z; wound inward"
    fixed, caught = _caught(slope, inward, orient="auto")
    assert str(fixed.orientation) == "points +z; wound inward, rewound"
    assert any("rewound outward" in m for m in caught)
    assert np.array_equal(fixed.face_slope, slope(up).face_slope)
    assert np.array_equal(as_is.face_slope, 180 - fixed.face_slope)
    assert _caught(opc, inward, orient="auto")[0].bin_counts == opc(up).bin_counts
    # classic DNE: its convex and concave parts swap as wound, and come back when rewound
    right = classic_dne(up)
    swapped, caught = _caught(classic_dne, inward, orient="as-is")
    assert any("wound inward" in m for m in caught)
    # (the energy does not depend on the winding; with no outliers dropped, no face
    # can cross the outlier quantile by a rounding error)
    unsigned = _caught(classic_dne, inward, outliers=0.0, orient="as-is")[0].dne
    assert unsigned == pytest.approx(classic_dne(up, outliers=0.0).dne, rel=1e-9)
    assert swapped.convex_area == pytest.approx(right.concave_area, rel=1e-9)
    rewound = _caught(classic_dne, inward, orient="auto")[0]
    assert (rewound.convex_dne, rewound.concave_dne) == (right.convex_dne, right.concave_dne)
    assert rewound.orientation.rewound and not rewound.orientation.turned
    np.testing.assert_array_equal(inward.faces, up.faces[:, ::-1])  # the caller's mesh untouched


@pytest.mark.parametrize("seed", range(4))
def test_the_winding_does_not_depend_on_the_pose(seed):
    up = dome()
    rotated = (up.vertices @ _rotation(seed).T) * 7.0 + [3.0, -1.0, 20.0]
    assert find_orientation(rotated, up.faces).winding == "outward"
    assert find_orientation(rotated, up.faces[:, ::-1]).winding == "inward"


def test_a_crown_pointing_down_and_wound_inward_is_turned_and_rewound():
    up = dome()
    both = trimesh.Trimesh(up.vertices @ TURN.T, up.faces[:, ::-1], process=False)
    result, _ = _caught(slope, both, orient="auto")
    assert str(result.orientation) == "points -z, turned to +z; wound inward, rewound"
    assert np.array_equal(result.face_slope, slope(up).face_slope)
    assert classic_dne(up).convex_dne == _caught(classic_dne, both, orient="auto")[0].convex_dne


def test_some_faces_wound_inward_are_found_and_rewound():
    up = prepare_surface(dome()).trimesh()  # no face of zero area: each flipped face counts
    faces = up.faces.copy()
    flipped = np.arange(0, len(faces), 10)
    faces[flipped] = faces[flipped][:, ::-1]
    found = find_orientation(up.vertices, faces)
    assert (found.winding, found.inward_faces) == ("mixed", len(flipped))
    result, _ = _caught(slope, (up.vertices, faces), orient="auto")
    assert str(result.orientation) == f"points +z; {len(flipped)} faces wound inward, rewound"
    assert np.array_equal(result.face_slope, slope(up).face_slope)


def test_a_closed_sphere_wound_inward_is_found_and_rewound():
    sphere = trimesh.creation.icosphere(subdivisions=3)
    outward = classic_dne(sphere)
    assert outward.concave_dne == 0.0
    found = find_orientation(sphere.vertices, sphere.faces[:, ::-1])
    assert (found.points, found.winding) == ("undetermined", "inward")
    inward = (sphere.vertices, sphere.faces[:, ::-1])
    swapped, caught = _caught(classic_dne, inward, orient="as-is")
    assert swapped.convex_dne == 0.0 and any("wound inward" in m for m in caught)
    rewound = _caught(classic_dne, inward, orient="auto")[0]
    assert (rewound.convex_dne, rewound.concave_dne) == (outward.convex_dne, 0.0)
    turned = _caught(slope, inward, orient="auto")[0]
    assert not turned.orientation.turned and turned.orientation.rewound
    assert turned.slope == _caught(slope, sphere)[0].slope


@pytest.mark.parametrize("pose", range(6))
def test_a_plane_in_any_pose_is_undetermined_warned_about_and_never_turned(pose):
    from conftest import plane_patch

    plane = plane_patch(15)
    vertices = plane.vertices.copy()
    if pose >= 2:
        vertices = vertices @ _rotation(pose).T
    if pose >= 4:  # scanner noise, a thousandth of its size
        vertices += np.random.default_rng(pose).normal(scale=1e-3, size=vertices.shape)
    vertices = vertices * 10.0**pose + pose
    faces = plane.faces if pose % 2 == 0 else plane.faces[:, ::-1]
    found = find_orientation(vertices, faces)
    assert (found.points, found.rule, found.winding) == ("undetermined", "flat", "undetermined")
    as_is, _ = _caught(slope, (vertices, faces))
    auto, caught = _caught(slope, (vertices, faces), orient="auto")
    assert str(auto.orientation) == "direction undetermined"
    assert any("the surface is flat" in m for m in caught)
    assert not auto.orientation.turned and not auto.orientation.rewound
    assert np.array_equal(auto.face_slope, as_is.face_slope)  # measured as it lies
    if pose == 0:
        assert auto.slope == 0.0  # facing up: not "turned" to 180 degrees


@pytest.mark.parametrize("name", [*ROBUSTNESS_SET, "low_hole"])
def test_the_papers_crowns_point_down_from_their_open_base_and_are_wound_outward(name):
    from dentopo.mesh import load_mesh

    mesh = load_mesh(shared_mesh(name))
    found = find_orientation(mesh.vertices, mesh.faces)
    assert (found.points, found.rule, found.winding) == ("-z", "open base", "outward")
    assert str(found) == "points -z"
    inward = find_orientation(mesh.vertices, mesh.faces[:, ::-1])
    assert (inward.points, inward.winding, str(inward)) == (
        "-z",
        "inward",
        "points -z; wound inward",
    )


def test_the_batch_orientation_column_says_the_faces_were_rewound():
    from dentopo.batch._measure import TopographyOptions, measure_mesh
    from dentopo.mesh import load_mesh

    mesh = load_mesh(shared_mesh("normal"))
    inward = (mesh.vertices, mesh.faces[:, ::-1])
    auto = TopographyOptions(orient="auto")
    right = _caught(measure_mesh, mesh, ("classic", "slope", "opc"), options=auto)[0]
    fixed, caught = _caught(measure_mesh, inward, ("classic", "slope", "opc"), options=auto)
    assert fixed.record["orientation"] == "points -z, turned to +z; wound inward, rewound"
    assert {k: v for k, v in fixed.record.items() if k != "orientation"} == {
        k: v for k, v in right.record.items() if k != "orientation"
    }
    assert sum("wound inward" in m for m in caught) >= 1


def test_auto_measures_a_crown_wound_inward_as_the_same_crown_wound_outward(recwarn):
    # the behaviour alone (issue 22, item 2): before, auto turned the crown but not its normals
    mesh = dome()
    inward = trimesh.Trimesh(mesh.vertices, mesh.faces[:, ::-1], process=False)
    assert slope(inward, orient="auto").slope == slope(mesh).slope
    assert opc(inward, orient="auto").bin_counts == opc(mesh).bin_counts
    assert any("wound inward" in str(w.message) for w in recwarn)


def test_auto_does_not_turn_a_flat_plane(recwarn):
    # the behaviour alone (issue 22, item 3): before, auto "turned" it and reported 180 degrees
    from conftest import plane_patch

    result = slope(plane_patch(), orient="auto")
    assert result.slope == 0.0 and result.orientation.points == "undetermined"
    assert any("the surface is flat" in str(w.message) for w in recwarn)
