"""molaR's orientation patch count (OPC) and its rotated mean (OPCR).

Analytic cases (a square pyramid, hand-made faces for molaR's quirks),
invariances, and molaR's own numbers on the robustness set.
"""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from conftest import ROBUSTNESS_SET, plane_patch, shared_mesh
from dentopo.topography import OPC_FIELDS, OPCResult, OPCRResult, opc, opcr

#: The reference crowns point to -z, as molaR measured them: that warning is expected here.
pytestmark = [
    pytest.mark.filterwarnings("ignore:the crown points to -z:UserWarning"),
    # planes and single faces are flat: no up or down (tests/test_orientation.py)
    pytest.mark.filterwarnings("ignore:the surface is flat:UserWarning"),
]

ROTATIONS = (0, 5.625, 11.25, 16.875, 22.5, 28.125, 33.75, 39.375)


def pyramid(turn: float = 22.5, subdivisions: int = 3) -> trimesh.Trimesh:
    """An open square pyramid (no base), sides facing +-x and +-y, turned `turn` degrees about z.

    Turned by 22.5 degrees, the sides' aspects are 22.5, 112.5, -157.5 and -67.5
    degrees: the middles of bins 5, 7, 1 and 3.  Each side has 4**subdivisions faces.
    """
    corners = [[1, 1, 0], [-1, 1, 0], [-1, -1, 0], [1, -1, 0], [0, 0, 1]]
    faces = [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]
    vertices, faces = np.array(corners, dtype=float), np.array(faces)
    for _ in range(subdivisions):
        vertices, faces = trimesh.remesh.subdivide(vertices, faces)
    mesh = trimesh.Trimesh(vertices, faces, process=False)
    mesh.apply_transform(trimesh.transformations.rotation_matrix(np.radians(turn), [0, 0, 1]))
    return mesh


def jittered_tooth(tooth) -> trimesh.Trimesh:
    """The sample tooth with its heights jittered (seeded): no aspect on a bin break."""
    vertices = tooth.vertices.copy()
    vertices[:, 2] += np.random.default_rng(0).normal(scale=1e-3, size=len(vertices))
    return trimesh.Trimesh(vertices, tooth.faces, process=False)


# --- molaR's numbers ----------------------------------------------------------------------


@pytest.mark.parametrize("name", ROBUSTNESS_SET)
def test_matches_molar(name, molar_topography):
    row = molar_topography[name]
    path = shared_mesh(name)
    result = opc(path, orient="as-is")  # molaR's numbers: the crown as it lies
    assert result.opc == int(row["OPC"])
    assert result.bin_counts == tuple(int(row[f"OPC_bin{k}"]) for k in range(1, 9))
    rotated = opcr(path, orient="as-is")
    assert rotated.opc_values == tuple(int(row[f"OPCR_rot{k}"]) for k in range(8))
    assert rotated.opcr == pytest.approx(float(row["OPCR"]), rel=1e-12, abs=0)
    assert rotated.first.bin_counts == result.bin_counts


def test_opcr_rounds_half_to_even(molar_topography):
    # low.ply's eight counts have the mean 57.125 (exact in binary); molaR reports 57.12
    row = molar_topography["low"]
    values = [int(row[f"OPCR_rot{k}"]) for k in range(8)]
    assert sum(values) / 8 == 57.125 and float(row["OPCR"]) == 57.12
    assert opcr(shared_mesh("low")).opcr == 57.12


# --- analytic cases -----------------------------------------------------------------------


def test_pyramid_has_one_patch_per_side():
    mesh = pyramid()
    result = opc(mesh)
    assert result.opc == 4
    assert result.bin_counts == (1, 0, 1, 0, 1, 0, 1, 0)
    assert len(result.patch_faces) == 4 and (result.patch_faces == 64).all()
    assert result.patch_counted.all()
    assert sorted(result.patch_bin.tolist()) == [1, 3, 5, 7]
    assert result.patch_area == pytest.approx(np.full(4, mesh.area / 4), rel=1e-12)
    # every face of a patch is in the patch's bin
    assert np.array_equal(result.patch_bin[result.face_patch], result.face_bin)


def test_pyramid_opcr():
    # turned 2.8125 degrees, the aspects stay mid-bin (2.8125 .. 42.1875 from the axes)
    result = opcr(pyramid(turn=2.8125))
    assert result.rotations == ROTATIONS
    assert result.opc_values == (4,) * 8 and result.opcr == 4.0


def test_rotation_is_counter_clockwise():
    # unturned, the sides face 0, 90, 180 and -90 degrees (on the breaks); rotating the
    # aspects by +22.5 degrees puts them mid-bin in bins 5, 7, 1, 3, and -22.5 in 4, 6, 8, 2
    mesh = pyramid(turn=0.0)
    assert opc(mesh, rotation=22.5).bin_counts == (1, 0, 1, 0, 1, 0, 1, 0)
    assert opc(mesh, rotation=-22.5).bin_counts == (0, 1, 0, 1, 0, 1, 0, 1)
    turned = opc(pyramid(turn=22.5))
    assert np.array_equal(opc(mesh, rotation=22.5).face_bin, turned.face_bin)


def test_min_faces_and_min_area():
    mesh = pyramid()  # four patches of 64 faces, each a quarter of the area
    assert opc(mesh, min_faces=64).opc == 4
    assert opc(mesh, min_faces=65).opc == 0
    assert opc(mesh, min_faces=0).opc == opc(mesh, min_faces=1).opc == 4
    assert opc(mesh, min_area=0.2).opc == 4
    assert opc(mesh, min_area=0.3).opc == 0
    # a positive min_area replaces min_faces
    assert opc(mesh, min_faces=1000, min_area=0.2).opc == 4


def test_plane_faces_are_binned_by_their_tiny_tilt():
    # there is no slope threshold: the plane's normals are exactly (+0, +0, 1), whose
    # aspect atan2(+0, +0) = 0 is in bin 4, so the whole plane is one patch
    result = opc(plane_patch(5))
    assert (result.face_bin == 4).all()
    assert result.bin_counts == (0, 0, 0, 1, 0, 0, 0, 0)


def fin(third_points) -> tuple[np.ndarray, np.ndarray]:
    """Faces (A, B, C_i) sharing the edge A-B along +y.

    Face i's normal is (c_z, 0, -c_x): aspect 0 when c_z > 0, pi when c_z < 0.
    """
    vertices = np.array([[0, 0, 0], [0, 1, 0], *third_points], dtype=float)
    faces = np.array([[0, 1, 2 + i] for i in range(len(third_points))])
    return vertices, faces


def test_edge_joins_only_when_exactly_two_faces_of_the_bin_use_it():
    # three faces of one bin on one edge: none joined (rotated off the breaks, +x -> bin 5)
    three = opc(fin([[-1, 0.5, 1], [-2, 0.5, 1], [-3, 0.5, 1]]), rotation=22.5, min_faces=1)
    assert three.face_bin.tolist() == [5, 5, 5]
    assert three.opc == 3 and three.face_patch.tolist() == [0, 1, 2]
    # two of the three in bin 5, one facing -x (bin 1): the two are joined
    two = opc(fin([[-1, 0.5, 1], [-2, 0.5, -1], [-3, 0.5, 1]]), rotation=22.5, min_faces=1)
    assert two.face_bin.tolist() == [5, 1, 5]
    assert two.face_patch.tolist() == [0, 1, 0]
    assert two.patch_faces.tolist() == [2, 1]
    assert opc(fin([[-1, 0.5, 1], [-2, 0.5, -1], [-3, 0.5, 1]]), rotation=22.5).opc == 0


def signed_zero_face(offset: float, sign: float) -> list[np.ndarray]:
    """A face with unit normal (-1, sign * 0.0, +-1) / sqrt(2): aspect exactly -pi or pi.

    ``sign = -1``: v2 - v1 = (0, -1, 0), v3 - v1 = (-1, 0, 1), cross product
    (-1, 0 * -1 - 0 * 1, -1) = (-1, -0.0, -1); at rotation 0, ``y' = x * 0 + y``
    stays -0.0 and ``atan2(-0.0, x' < 0) = -pi``.  ``sign = +1``: v3 - v1 =
    (1, 0, 1) gives (-1, +0.0, 1) and ``atan2(+0.0, x' < 0) = pi``.
    """
    v1 = np.array([offset, 0.0, 0.0])
    return [v1, v1 + np.array([0, -1, 0]), v1 + np.array([sign, 0, 1])]


#: A face whose normal is (-1, 2, 0): aspect 116.6 degrees, bin 7.
BIN7_FACE = [[0.0, 0, 0], [0, 0, 1], [2, 1, 0]]


def test_minus_pi_takes_the_bin_of_the_next_binned_face():
    minus, plus = (lambda x: signed_zero_face(x, -1.0)), (lambda x: signed_zero_face(x, 1.0))
    vertices = np.array([*minus(10), *BIN7_FACE, *minus(20), *plus(30)])
    faces = np.arange(12).reshape(4, 3)
    tri = vertices[faces]
    normals = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    aspects = np.arctan2(normals[:, 1], normals[:, 0])
    assert aspects[0] == aspects[2] == -np.pi and aspects[3] == np.pi  # the premise
    # faces 0 and 2 take the bins of faces 1 and 3; pi itself is in bin 8
    assert opc((vertices, faces), min_faces=1).face_bin.tolist() == [7, 7, 8, 8]
    # the last face wraps round to the first face that has a bin
    vertices = np.array([*BIN7_FACE, *minus(10), *plus(20), *minus(30)])
    assert opc((vertices, faces), min_faces=1).face_bin.tolist() == [7, 8, 8, 7]
    # no face with a bin at all (our choice): bin 8, the bin of pi, the same direction
    vertices = np.array([*minus(10), *minus(20), *minus(30), *minus(40)])
    assert opc((vertices, faces), min_faces=1).face_bin.tolist() == [8, 8, 8, 8]
    # with a rotation the aspects move off -pi and the faces get their own bins
    assert opc((vertices, faces), rotation=10.0, min_faces=1).face_bin.tolist() == [1] * 4


def test_patches_are_numbered_by_their_first_face(tooth):
    result = opc(jittered_tooth(tooth))
    first = [np.flatnonzero(result.face_patch == p)[0] for p in range(len(result.patch_bin))]
    assert first == sorted(first) and first[0] == 0
    assert result.patch_faces.sum() == result.faces
    assert result.patch_area.sum() == pytest.approx(result.mesh.area, rel=1e-12)
    counted = result.patch_faces >= 3
    assert np.array_equal(result.patch_counted, counted)
    assert result.bin_counts == tuple(
        np.bincount(result.patch_bin[counted], minlength=9)[1:].tolist()
    )


# --- invariances --------------------------------------------------------------------------


def _counts(mesh):
    one = opc(mesh)
    return one.bin_counts, opcr(mesh).opc_values


def test_translation_scale_and_order_change_nothing(tooth):
    mesh = jittered_tooth(tooth)
    base = _counts(mesh)
    assert base[0] != (0,) * 8
    moved = trimesh.Trimesh(mesh.vertices * 37.5 + [3.0, -2.0, 11.0], mesh.faces, process=False)
    assert _counts(moved) == base
    rng = np.random.default_rng(1)
    perm = rng.permutation(len(mesh.vertices))
    shuffled = trimesh.Trimesh(mesh.vertices[perm], np.argsort(perm)[mesh.faces], process=False)
    assert _counts(shuffled) == base
    order = rng.permutation(len(mesh.faces))
    reordered = trimesh.Trimesh(mesh.vertices, mesh.faces[order], process=False)
    assert _counts(reordered) == base
    assert np.array_equal(opc(reordered).face_bin, opc(mesh).face_bin[order])


def test_caller_mesh_unchanged(tooth):
    vertices, faces = tooth.vertices.copy(), tooth.faces.copy()
    opc(tooth)
    opcr(tooth)
    assert np.array_equal(tooth.vertices, vertices) and np.array_equal(tooth.faces, faces)
    array_vertices, array_faces = vertices.copy(), faces.copy()
    opcr((array_vertices, array_faces), steps=2)
    assert np.array_equal(array_vertices, vertices) and np.array_equal(array_faces, faces)


# --- results and parameters ---------------------------------------------------------------


def test_result_fields(tooth):
    result = opc(tooth)
    assert isinstance(result, OPCResult)
    assert list(result.to_dict()) == list(OPC_FIELDS)
    assert OPC_FIELDS == ("opc", *(f"opc_bin{k}" for k in range(1, 9)))
    assert result.to_dict()["opc"] == result.opc == sum(result.bin_counts)
    assert result.face_bin.shape == result.face_patch.shape == (result.faces,)
    assert "face_bin" not in repr(result)

    rotated = opcr(tooth)
    assert isinstance(rotated, OPCRResult)
    assert list(rotated.to_dict()) == ["opcr"] + [f"opc_{r}" for r in ROTATIONS]
    assert rotated.opcr == round(sum(rotated.opc_values) / 8, 2)
    assert rotated.first.rotation == 0.0
    assert rotated.first.bin_counts == result.bin_counts
    assert np.array_equal(rotated.first.face_bin, result.face_bin)


def test_opcr_settings(tooth):
    mesh = jittered_tooth(tooth)
    single = opcr(mesh, steps=1)
    assert single.rotations == (0.0,) and single.opcr == opc(mesh).opc
    three = opcr(mesh, steps=3, step=10, min_faces=5)
    assert three.rotations == (0.0, 10.0, 20.0)
    assert three.opc_values == tuple(opc(mesh, rotation=r, min_faces=5).opc for r in (0, 10, 20))
    assert list(three.to_dict()) == ["opcr", "opc_0", "opc_10", "opc_20"]
    area = opcr(mesh, steps=2, min_area=0.01)
    assert area.opc_values[1] == opc(mesh, rotation=5.625, min_area=0.01).opc


@pytest.mark.parametrize(
    ("kwargs", "error", "name"),
    [
        ({"rotation": float("nan")}, ValueError, "rotation"),
        ({"rotation": "0"}, TypeError, "rotation"),
        ({"min_faces": -1}, ValueError, "min_faces"),
        ({"min_faces": 2.5}, TypeError, "min_faces"),
        ({"min_faces": True}, TypeError, "min_faces"),
        ({"min_area": -0.1}, ValueError, "min_area"),
        ({"min_area": 1.0}, ValueError, "min_area"),
        ({"min_area": float("inf")}, ValueError, "min_area"),
    ],
)
def test_opc_bad_parameters(kwargs, error, name, tooth):
    with pytest.raises(error, match=name):
        opc(tooth, **kwargs)


@pytest.mark.parametrize(
    ("kwargs", "error", "name"),
    [
        ({"steps": 0}, ValueError, "steps"),
        ({"steps": 8.0}, TypeError, "steps"),
        ({"step": float("inf")}, ValueError, "step"),
        ({"step": None}, TypeError, "step"),
        ({"min_faces": -3}, ValueError, "min_faces"),
        ({"min_area": 2}, ValueError, "min_area"),
    ],
)
def test_opcr_bad_parameters(kwargs, error, name, tooth):
    with pytest.raises(error, match=name):
        opcr(tooth, **kwargs)
