"""molaR's mean surface slope: analytic checks, invariances and molaR's own numbers."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from conftest import ROBUSTNESS_SET, hemisphere, shared_mesh
from dentopo.topography import SLOPE_FIELDS, SlopeResult, slope

#: The reference crowns point to -z, as molaR measured them: that warning is expected here.
pytestmark = [
    pytest.mark.filterwarnings("ignore:the crown points to -z:UserWarning"),
    # planes and single faces are flat: no up or down (tests/test_orientation.py)
    pytest.mark.filterwarnings("ignore:the surface is flat:UserWarning"),
]


@pytest.mark.parametrize("name", ROBUSTNESS_SET)
def test_matches_molar(name, molar_topography):
    # molaR measures the crown as it lies (the paper's crowns point to -z): --orient as-is
    result = slope(shared_mesh(name), orient="as-is")
    assert result.slope == pytest.approx(float(molar_topography[name]["slope"]), rel=1e-9)


def test_plane_facing_up_and_down(plane):
    up = slope(plane)
    assert up.slope == 0.0 and (up.face_slope == 0).all()
    down = slope(trimesh.Trimesh(plane.vertices, plane.faces[:, ::-1], process=False))
    assert down.slope == 180.0


def test_hemisphere_mean_slope_is_one_radian():
    # on a unit hemisphere the normal's angle from +z is the polar angle t, and the
    # area-weighted mean of t over 0 <= t <= pi/2 is int(t sin t) / int(sin t) = 1 radian
    mesh = hemisphere()
    result = slope(mesh)
    assert result.slope == pytest.approx(np.degrees(1.0), abs=0.05)
    # the faces at the pole have zero area: molaR's cleaning drops them
    assert result.faces == len(mesh.faces) - 256
    assert result.face_slope.min() == 0 and result.face_slope.max() == 90


def test_whole_degrees_round_half_to_even():
    # a face tilted by exactly atan(1) = 45 degrees about the x axis (n_z = cos 45)
    def tilted(degrees):
        t = np.radians(degrees)
        # the fourth vertex is unused (a mesh needs 4): molaR's cleaning drops it
        vertices = np.array([[0, 0, 0], [1, 0, 0], [0, np.cos(t), np.sin(t)], [9, 9, 9]])
        return vertices, np.array([[0, 1, 2]])

    assert slope(tilted(45.0)).face_slope.tolist() == [45]
    assert slope(tilted(30.2)).face_slope.tolist() == [30]
    assert slope(tilted(30.8)).face_slope.tolist() == [31]
    assert slope(tilted(100.0)).face_slope.tolist() == [100]
    # numpy's rint, like R's round, rounds exact halves to even
    assert np.rint([0.5, 1.5, 2.5, 44.5, 45.5]).tolist() == [0, 2, 2, 44, 46]


def test_area_weighted_mean_of_whole_degrees():
    # a unit box: 4 vertical sides (90), a top (0) and a bottom (180), all of equal area
    box = trimesh.creation.box()
    with pytest.warns(UserWarning, match="the surface is closed"):  # no base: as it lies
        assert slope(box).slope == 90.0
    # stretch the box in z: the sides weigh more, the mean stays 90 by symmetry
    with pytest.warns(UserWarning, match="the surface is closed"):
        assert slope(trimesh.creation.box(extents=(1, 1, 5))).slope == 90.0
    # a flat face of area 2 and a vertical face of area 0.5: (0 * 2 + 90 * 0.5) / 2.5
    vertices = [[0, 0, 0], [2, 0, 0], [0, 2, 0], [5, 0, 0], [6, 0, 0], [5, 0, 1]]
    result = slope((vertices, [[0, 1, 2], [3, 4, 5]]), orient="as-is")
    assert result.face_slope.tolist() == [0, 90]
    assert result.face_area.tolist() == [2.0, 0.5]
    assert result.slope == 18.0


def test_invariances(tooth):
    base = slope(tooth)
    rng = np.random.default_rng(0)
    # translation and uniform scale
    moved = trimesh.Trimesh(tooth.vertices * 37.5 + [3.0, -2.0, 11.0], tooth.faces, process=False)
    # the per-face slopes do not change; the mean's weights are molaR's single-precision areas
    assert np.array_equal(slope(moved).face_slope, base.face_slope)
    assert slope(moved).slope == pytest.approx(base.slope, rel=1e-7)
    # vertex order (faces remapped) leaves every face's normal bit for bit
    perm = rng.permutation(len(tooth.vertices))
    inverse = np.argsort(perm)
    shuffled = trimesh.Trimesh(tooth.vertices[perm], inverse[tooth.faces], process=False)
    other = slope(shuffled)
    assert np.array_equal(other.face_slope, base.face_slope)
    assert other.slope == pytest.approx(base.slope, rel=1e-12)
    # face order
    order = rng.permutation(len(tooth.faces))
    reordered = slope(trimesh.Trimesh(tooth.vertices, tooth.faces[order], process=False))
    assert np.array_equal(reordered.face_slope, base.face_slope[order])
    assert reordered.slope == pytest.approx(base.slope, rel=1e-12)


def test_orientation_matters(tooth):
    upside_down = tooth.copy()
    upside_down.apply_transform(trimesh.transformations.rotation_matrix(np.pi, [1, 0, 0]))
    as_is = slope(upside_down, orient="as-is").slope
    assert as_is == pytest.approx(180.0 - slope(tooth, orient="as-is").slope, abs=0.01)
    # by default the crown is turned back up (away from its open base)
    assert slope(upside_down).slope == pytest.approx(slope(tooth).slope, abs=1e-9)


def test_result_shape(tooth):
    result = slope(tooth)
    assert isinstance(result, SlopeResult)
    assert list(result.to_dict()) == list(SLOPE_FIELDS) == ["slope"]
    assert result.face_slope.dtype == np.int64
    assert result.face_slope.shape == result.face_area.shape == (result.faces,)
    assert len(result.mesh.faces) == result.faces and len(result.mesh.vertices) == result.vertices
    assert "face_slope" not in repr(result)


def test_caller_mesh_unchanged(tooth):
    vertices, faces = tooth.vertices.copy(), tooth.faces.copy()
    slope(tooth)
    array_vertices, array_faces = vertices.copy(), faces.copy()
    slope((array_vertices, array_faces))
    for a, b in [(tooth.vertices, vertices), (tooth.faces, faces)]:
        assert np.array_equal(a, b)
    assert np.array_equal(array_vertices, vertices) and np.array_equal(array_faces, faces)


def test_bad_mesh_raises():
    with pytest.raises(ValueError, match="non-zero area"):
        slope((np.zeros((4, 3)), np.array([[0, 1, 2], [1, 2, 3]])))
    with pytest.raises(TypeError, match="mesh must be"):
        slope(42)
