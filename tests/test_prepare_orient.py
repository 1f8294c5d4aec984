"""The orient step of ``prepare``: analytic poses, real crowns turned at random, the warnings."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh
from scipy.spatial.transform import Rotation

from conftest import ROBUSTNESS_SET, plane_patch, shared_mesh
from dentopo.mesh import boundary_edges
from dentopo.prepare import _crop, _orient

Z = np.array([0.0, 0.0, 1.0])


def _arrays(mesh):
    return np.asarray(mesh.vertices, dtype=np.float64), np.asarray(mesh.faces, dtype=np.int64)


def _frozen(*arrays):
    out = []
    for array in arrays:
        array = np.array(array)
        array.setflags(write=False)  # any write into the caller's arrays raises
        out.append(array)
    return out


def _hemisphere(radius=1.0, subdivisions=4):
    """An icosphere cut at the equator: open, its base loop exactly in z = 0, its axis +z."""
    sphere = trimesh.creation.icosphere(subdivisions=subdivisions, radius=radius)
    cut = _crop.run(*_arrays(sphere), plane=(0, 0, 0, 0, 0, 1))
    return cut.vertices, cut.faces


def _pose(seed):
    """A random rigid motion (rotation, translation)."""
    rotation = Rotation.random(random_state=seed).as_matrix()
    shift = np.random.default_rng(seed).normal(scale=5.0, size=3)
    return rotation, shift


def _angle(a, b):
    cosine = np.dot(a, b) / np.linalg.norm(a) / np.linalg.norm(b)
    return np.degrees(np.arccos(np.clip(cosine, -1.0, 1.0)))


def _assert_rigid(transform):
    rotation = transform[:3, :3]
    np.testing.assert_allclose(rotation.T @ rotation, np.eye(3), atol=1e-12)
    assert np.linalg.det(rotation) == pytest.approx(1.0, abs=1e-12)
    np.testing.assert_array_equal(transform[3], [0.0, 0.0, 0.0, 1.0])


def _apply(transform, vertices):
    return vertices @ transform[:3, :3].T + transform[:3, 3]


def _level(vertices, faces, **options):
    options = {"mode": "occlusal", "up": None, "spin": "none", **options}
    return _orient.run(vertices, faces, **options)


# ---------------------------------------------------------------------------
# the rotation


@pytest.mark.parametrize("seed", range(5))
def test_rotation_to_z_is_the_smallest_rotation(seed):
    direction = np.random.default_rng(seed).normal(size=3)
    rotation = _orient.rotation_to_z(direction)
    np.testing.assert_allclose(rotation @ direction / np.linalg.norm(direction), Z, atol=1e-12)
    np.testing.assert_allclose(rotation.T @ rotation, np.eye(3), atol=1e-12)
    assert np.linalg.det(rotation) == pytest.approx(1.0)
    # the smallest: turned by the angle between them, about an axis perpendicular to both
    assert _orient.rotation_angle(rotation) == pytest.approx(_angle(direction, Z), abs=1e-6)
    axis = Rotation.from_matrix(rotation).as_rotvec()
    assert abs(axis @ direction) < 1e-9 and abs(axis[2]) < 1e-9


@pytest.mark.parametrize("tiny", [0.0, 1e-13, 1e-9])
def test_rotation_to_z_from_minus_z(tiny):
    direction = np.array([tiny, 0.0, -1.0])
    rotation = _orient.rotation_to_z(direction)
    np.testing.assert_allclose(rotation @ direction / np.linalg.norm(direction), Z, atol=1e-12)
    np.testing.assert_allclose(rotation.T @ rotation, np.eye(3), atol=1e-12)
    assert np.linalg.det(rotation) == pytest.approx(1.0)
    assert _orient.rotation_angle(rotation) == pytest.approx(180.0, abs=1e-6)
    if tiny == 0.0:  # the half-turn about x, as the metrics' turn
        np.testing.assert_array_equal(rotation, np.diag([1.0, -1.0, -1.0]))


# ---------------------------------------------------------------------------
# an open hemisphere in random poses


@pytest.mark.parametrize("noise", [0.0, 0.005])
def test_hemisphere_in_random_poses_comes_back_up(noise):
    vertices, faces = _hemisphere()
    rng = np.random.default_rng(7)
    for seed in range(20):
        rotation, shift = _pose(seed)
        noisy = vertices + rng.normal(scale=noise, size=vertices.shape)
        posed = noisy @ rotation.T + shift
        out = _level(posed, faces)
        _assert_rigid(out.transform)
        # the hemisphere's axis (+z before posing) comes back to +z within a degree
        axis = out.transform[:3, :3] @ rotation @ Z
        assert _angle(axis, Z) < 1.0, (seed, _angle(axis, Z))
        assert out.details["rule"] == "open base" and out.details["turned"]
        assert out.warnings == ()
        # above its base: the base plane is z = 0 (its centroid at the origin), the dome above
        new = out.vertices
        np.testing.assert_allclose(new, _apply(out.transform, posed), atol=1e-12)
        base = np.unique(boundary_edges(faces, len(new)))
        assert np.abs(new[base, 2]).max() < 0.02 + 5 * noise
        assert np.abs(new[base].mean(axis=0)).max() < 0.02 + 5 * noise
        assert new[:, 2].max() == pytest.approx(1.0, abs=0.02 + 5 * noise)
        assert new[:, 2].mean() > 0.3
        # the plane found, in the posed coordinates: its normal is the posed axis
        point, normal = out.plane
        assert _angle(normal, rotation @ Z) < 1.0
        assert abs((point - shift) @ (rotation @ Z)) < 0.02 + 5 * noise


def test_hemisphere_upside_down_is_turned_by_half_a_turn():
    vertices, faces = _hemisphere()
    flipped = vertices * [1.0, -1.0, -1.0]
    out = _level(flipped, faces)
    assert out.details["tilt_degrees"] == pytest.approx(180.0, abs=1e-6)
    assert out.vertices[:, 2].max() == pytest.approx(1.0, abs=1e-9)


def test_the_longest_loop_is_the_base():
    """A hole in the dome (a second, shorter loop) does not tilt the base."""
    vertices, faces = _hemisphere()
    centre = _arrays(trimesh.Trimesh(vertices, faces, process=False))[0]
    direction = np.array([0.6, 0.0, 0.8])
    near = (centre[faces].mean(axis=1) @ direction) > 0.97
    holed = faces[~near]
    rotation, shift = _pose(3)
    out = _level(vertices @ rotation.T + shift, holed)
    assert out.details["boundary_loops"] == 2 and out.details["holes"] == 1
    assert _angle(out.transform[:3, :3] @ rotation @ Z, Z) < 0.5


def test_a_closed_surface_with_a_small_hole_warns():
    """The hole is the only loop, so its plane is levelled: said, since it may be wrong."""
    vertices, faces = _arrays(trimesh.creation.icosphere(subdivisions=3))
    direction = np.array([0.0, 0.6, 0.8])
    holed = faces[(vertices[faces].mean(axis=1) @ direction) < 0.97]
    out = _level(vertices, holed)
    assert out.details["rule"] == "open base" and out.details["boundary_loops"] == 1
    assert len(out.warnings) == 1 and "open base is small" in out.warnings[0]
    assert _level(*_hemisphere(subdivisions=3)).warnings == ()


# ---------------------------------------------------------------------------
# real crowns


def _crown(name):
    mesh = trimesh.load(shared_mesh(name), process=False)
    return _arrays(mesh)


def _composed(out, rotation, shift):
    pose = np.eye(4)
    pose[:3, :3], pose[:3, 3] = rotation, shift
    return out.transform @ pose


@pytest.mark.parametrize("name", ROBUSTNESS_SET)
def test_crown_turned_at_random_comes_back_to_the_same_pose(name):
    vertices, faces = _crown(name)
    plain = _level(vertices, faces)
    spun = _level(vertices, faces, spin="footprint")
    size = np.linalg.norm(np.ptp(vertices, axis=0))
    assert plain.details["rule"] == "open base"
    for seed in range(4):
        rotation, shift = _pose(seed)
        posed = vertices @ rotation.T + shift
        # levelled: the same direction of the crown becomes +z
        again = _composed(_level(posed, faces), rotation, shift)
        up_back = again[:3, :3].T @ Z
        assert _angle(up_back, plain.transform[:3, :3].T @ Z) < 1.0
        # spun too: the whole pose is the same (rotation and translation)
        again = _composed(_level(posed, faces, spin="footprint"), rotation, shift)
        turn = again[:3, :3] @ spun.transform[:3, :3].T
        assert _orient.rotation_angle(turn) < 1.0
        assert np.abs(again[:3, 3] - spun.transform[:3, 3]).max() < 1e-3 * size


@pytest.mark.parametrize("name", ROBUSTNESS_SET[:2])
def test_crown_vertex_order_does_not_change_the_transform(name):
    vertices, faces = _crown(name)
    rng = np.random.default_rng(11)
    order = rng.permutation(len(vertices))
    inverse = np.argsort(order)
    shuffled_vertices = vertices[order]
    shuffled_faces = inverse[faces][rng.permutation(len(faces))]
    shuffled_faces = np.roll(shuffled_faces, 1, axis=1)  # the same winding, another first corner
    for spin in ("none", "footprint"):
        a = _level(vertices, faces, spin=spin)
        b = _level(shuffled_vertices, shuffled_faces, spin=spin)
        np.testing.assert_allclose(b.transform, a.transform, atol=1e-9)


def test_crown_is_left_above_its_base():
    vertices, faces = _crown("normal")
    out = _level(vertices, faces)
    heights = out.vertices[:, 2]
    assert np.median(heights) > 0
    edges = boundary_edges(faces, len(vertices))
    base = np.unique(edges)
    # the cervical cut of a scan is not planar: its loop (by length) is centred on the origin
    ends = out.vertices[edges]
    length = np.linalg.norm(ends[:, 1] - ends[:, 0], axis=1)
    centre = (length[:, None] * ends.mean(axis=1)).sum(axis=0) / length.sum()
    np.testing.assert_allclose(centre, 0.0, atol=1e-9)
    assert heights.max() > 5 * np.abs(heights[base]).max()
    assert out.details["base_rms"] > 0


# ---------------------------------------------------------------------------
# up= by hand; spin


def test_up_by_hand():
    vertices, faces = _hemisphere()
    direction = np.array([1.0, -2.0, 0.5])
    out = _level(vertices, faces, up=tuple(direction))
    _assert_rigid(out.transform)
    unit = direction / np.linalg.norm(direction)
    np.testing.assert_allclose(out.transform[:3, :3] @ unit, Z, atol=1e-12)
    assert out.details["rule"] == "up" and out.plane is None
    assert out.details["tilt_degrees"] == pytest.approx(_angle(direction, Z), abs=1e-6)
    # no base finding: the hemisphere is turned as told, not levelled on its base
    assert _angle(out.transform[:3, :3] @ Z, Z) > 30


def test_up_zero_is_an_error():
    vertices, faces = _hemisphere(subdivisions=2)
    with pytest.raises(ValueError, match="up"):
        _level(vertices, faces, up=(0.0, 0.0, 0.0))


def _ellipsoidal_cap(egg=0.0):
    """A dome of semi-axes 3 (x), 1.5 (y), 1 (z) over z = 0; `egg` fattens its +x end."""
    vertices, faces = _hemisphere(subdivisions=4)
    x = vertices[:, 0]
    scale = np.where(x > 0, 1.0 + egg, 1.0)
    shaped = vertices * [3.0, 1.5, 1.0]
    shaped[:, 1] *= np.where(x > 0, scale, 1.0) ** 0.5
    shaped[:, 0] *= scale
    return shaped, faces


@pytest.mark.parametrize("egg", [0.0, 0.3])
def test_spin_puts_the_footprint_long_axis_on_y(egg):
    vertices, faces = _ellipsoidal_cap(egg)
    for seed in range(6):
        rotation, shift = _pose(seed)
        out = _level(vertices @ rotation.T + shift, faces, spin="footprint")
        _assert_rigid(out.transform)
        long_axis = out.transform[:3, :3] @ rotation @ np.array([1.0, 0.0, 0.0])
        assert _angle(long_axis, [0.0, 1.0, 0.0]) < 1.0 or _angle(long_axis, [0, -1, 0]) < 1.0
        assert _angle(out.transform[:3, :3] @ rotation @ Z, Z) < 1.0
        xy = out.vertices[:, :2] - out.vertices[:, :2].mean(axis=0)
        assert np.ptp(xy[:, 1]) > 1.8 * np.ptp(xy[:, 0])
        if egg:  # the fat end's long tail is the skew's side: the sign is the same in every pose
            assert out.details["spin"].endswith("(sign by skew)")
            assert _angle(long_axis, [0.0, -1.0, 0.0]) < 1.0, seed


def test_round_footprint_is_not_spun():
    vertices, faces = _hemisphere()
    out = _level(vertices, faces, spin="footprint")
    assert out.details["spin_degrees"] == 0.0
    assert any("round" in text for text in out.warnings)
    assert out.details["tilt_degrees"] == pytest.approx(0.0, abs=1e-9)


# ---------------------------------------------------------------------------
# flat and closed surfaces; mode none; the inputs


def test_flat_surface_warns_and_is_left_as_is():
    vertices, faces = _arrays(plane_patch())
    rotation, _ = _pose(2)
    posed = vertices @ rotation.T
    out = _level(posed, faces, spin="footprint")
    np.testing.assert_array_equal(out.transform, np.eye(4))
    np.testing.assert_array_equal(out.vertices, posed)
    assert out.details["rule"] == "flat" and not out.details["turned"]
    assert len(out.warnings) == 1
    assert "flat" in out.warnings[0] and "up=(x, y, z)" in out.warnings[0]


def test_closed_undetermined_surface_warns_and_is_left_as_is():
    vertices, faces = _arrays(trimesh.creation.icosphere(subdivisions=3))
    rotation, shift = _pose(4)
    posed = vertices @ rotation.T + shift
    out = _level(posed, faces)
    np.testing.assert_array_equal(out.transform, np.eye(4))
    np.testing.assert_array_equal(out.vertices, posed)
    assert out.details["rule"] == "area" and not out.details["turned"]
    assert "closed" in out.warnings[0] and "up=" in out.warnings[0]


def test_closed_box_with_equal_sides_is_undetermined():
    """A flat box: its shortest axis is clear, but its two faces along it are equal."""
    vertices, faces = _arrays(trimesh.creation.box(extents=(4.0, 3.0, 1.0)))
    out = _level(vertices, faces)
    np.testing.assert_array_equal(out.transform, np.eye(4))
    assert "neither side" in out.warnings[0]


def test_closed_dome_is_turned_up_with_a_warning():
    """A dome closed by a nearly flat floor: its shortest axis, the side its area faces."""
    vertices, faces = _arrays(trimesh.creation.icosphere(subdivisions=3))
    vertices = vertices.copy()
    vertices[:, 2] = np.where(vertices[:, 2] < 0, 0.02 * vertices[:, 2], vertices[:, 2])
    vertices *= [1.5, 1.5, 1.0]
    for seed in range(5):
        rotation, shift = _pose(seed)
        out = _level(vertices @ rotation.T + shift, faces)
        _assert_rigid(out.transform)
        assert out.details["rule"] == "area" and out.details["turned"]
        assert _angle(out.transform[:3, :3] @ rotation @ Z, Z) < 1.0
        assert "closed" in out.warnings[0] and "check it" in out.warnings[0]


def test_mode_none_keeps_the_pose():
    vertices, faces = _hemisphere(subdivisions=2)
    out = _orient.run(vertices, faces, mode="none", up=None, spin="none")
    np.testing.assert_array_equal(out.transform, np.eye(4))
    np.testing.assert_array_equal(out.vertices, vertices)


@pytest.mark.parametrize("options", [{}, {"spin": "footprint"}, {"up": (0.0, 1.0, 1.0)}])
def test_inputs_are_never_modified(options):
    vertices, faces = _crown_or_cap()
    rotation, shift = _pose(1)
    posed = vertices @ rotation.T + shift
    frozen_vertices, frozen_faces = _frozen(posed, faces)
    out = _level(frozen_vertices, frozen_faces, **options)
    np.testing.assert_array_equal(frozen_vertices, posed)
    np.testing.assert_array_equal(frozen_faces, faces)
    assert not np.shares_memory(out.vertices, frozen_vertices)
    assert not np.shares_memory(out.faces, frozen_faces)


def _crown_or_cap():
    return _ellipsoidal_cap(0.3)


def test_prepare_records_the_orient_step():
    import dentopo

    vertices, faces = _ellipsoidal_cap(0.3)
    rotation, shift = _pose(5)
    prepared = dentopo.prepare((vertices @ rotation.T + shift, faces), spin="footprint")
    step = prepared.step("orient")
    _assert_rigid(prepared.transform)
    np.testing.assert_allclose(prepared.transform, step.transform, atol=1e-12)
    assert step.plane is not None and step.details["rule"] == "open base"
    assert _angle(np.asarray(step.plane["normal"]), rotation @ Z) < 1.0
    assert _angle(prepared.transform[:3, :3] @ rotation @ Z, Z) < 1.0
