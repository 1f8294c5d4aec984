"""The decimate step of ``prepare``: face targets within 1 %, the open base kept, same bytes."""

from __future__ import annotations

import sys

import numpy as np
import pytest
import trimesh

import dentopo
from conftest import shared_mesh
from dentopo._optional import MissingExtraError
from dentopo.prepare import _decimate
from dentopo.prepare._decimate import MESHLAB_PARAMETERS, boundary_loops
from dentopo.prepare._protocol import Protocol, ProtocolError


def _has_pymeshlab() -> bool:
    import importlib.util

    return importlib.util.find_spec("pymeshlab") is not None


def _arrays(mesh):
    return np.asarray(mesh.vertices, dtype=np.float64), np.asarray(mesh.faces, dtype=np.int64)


def _read_only(*arrays):
    copies = [np.array(a) for a in arrays]
    for a in copies:
        a.setflags(write=False)
    return copies


@pytest.fixture(scope="module")
def sphere():
    return _arrays(trimesh.creation.icosphere(subdivisions=5))  # 20,480 faces


@pytest.fixture(scope="module")
def hemisphere():
    """The upper half of a unit icosphere: an open crown-like cap with one boundary loop."""
    s = trimesh.creation.icosphere(subdivisions=5)
    keep = s.vertices[s.faces].mean(axis=1)[:, 2] > 0
    half = trimesh.Trimesh(s.vertices, s.faces[keep], process=False)
    half.remove_unreferenced_vertices()
    return _arrays(half)


def _distance_to_segments(points, starts, ends):
    """Each point's distance to the nearest of the segments starts[i]-ends[i]."""
    d = ends - starts
    length2 = np.maximum((d * d).sum(axis=1), 1e-300)
    out = np.empty(len(points))
    for i, p in enumerate(points):
        t = np.clip(((p - starts) * d).sum(axis=1) / length2, 0.0, 1.0)
        out[i] = np.sqrt(((starts + t[:, None] * d - p) ** 2).sum(axis=1).min())
    return out


def _boundary_off_curve(v0, f0, v1, f1):
    """Hausdorff-style: the largest distance of a boundary vertex after from the boundary before."""
    edges = dentopo.mesh.boundary_edges(f0, len(v0))
    _, on = boundary_loops(f1, len(v1))
    return _distance_to_segments(v1[on], v0[edges[:, 0]], v0[edges[:, 1]]).max()


# --- targets


@pytest.mark.parametrize("target", [10000, 2000, 500])
def test_sphere_reaches_the_target_within_one_percent(sphere, target):
    v, f = sphere
    out = _decimate.run(v, f, faces_target=target, method="quadric")
    assert abs(len(out.faces) - target) <= 0.01 * target
    assert out.details["faces_reached"] == len(out.faces)
    assert not out.warnings
    assert out.faces.max() < len(out.vertices) and out.faces.min() >= 0


@pytest.mark.parametrize("target", [5000, 1000])
def test_hemisphere_reaches_the_target_within_one_percent(hemisphere, target):
    v, f = hemisphere
    out = _decimate.run(v, f, faces_target=target, method="quadric")
    assert abs(len(out.faces) - target) <= 0.01 * target


@pytest.mark.parametrize(("name", "targets"), [("high", (10000, 2000)), ("normal", (4000, 1000))])
def test_real_crown_reaches_the_target_within_one_percent(name, targets):
    v, f = _arrays(trimesh.load(shared_mesh(name), process=False))
    for target in targets:
        out = _decimate.run(v, f, faces_target=target, method="quadric")
        assert abs(out.details["faces_reached"] - target) <= 0.01 * target, (name, target)
        assert len(out.faces) == out.details["faces_reached"]


def test_a_target_that_cannot_be_met_is_reported_not_hidden(hemisphere):
    # 192 boundary vertices are kept, so 100 faces cannot be reached: a warning says so
    v, f = hemisphere
    out = _decimate.run(v, f, faces_target=100, method="quadric")
    assert len(out.faces) > 101
    assert out.details["faces_reached"] == len(out.faces)
    assert any("more than 1 % off" in w for w in out.warnings)


# --- the open base


def test_the_boundary_is_kept_exactly_on_a_hemisphere(hemisphere):
    v, f = hemisphere
    out = _decimate.run(v, f, faces_target=1000, method="quadric")
    loops_before, on_before = boundary_loops(f, len(v))
    loops_after, on_after = boundary_loops(out.faces, len(out.vertices))
    assert loops_before == loops_after == 1
    assert out.details["boundary_loops"] == [1, 1]
    # every base vertex is still there, bit for bit, and no other vertex joined the base
    before = {tuple(p) for p in v[on_before]}
    after = {tuple(p) for p in out.vertices[on_after]}
    assert after == before
    assert _boundary_off_curve(v, f, out.vertices, out.faces) == 0.0


def test_the_frozen_base_has_no_chord(hemisphere):
    v, f = hemisphere
    assert _decimate.run(v, f, faces_target=1000).details["boundary_chord"] == 0.0


def test_sliding_keeps_the_base_on_its_curve_with_fewer_vertices(hemisphere, monkeypatch):
    # the alternative: boundary edges collapse, moved vertices are put back on the outline
    monkeypatch.setattr(_decimate, "BOUNDARY", "slide")
    v, f = hemisphere
    out = _decimate.run(v, f, faces_target=1000)
    assert abs(len(out.faces) - 1000) <= 10
    assert out.details["boundary_loops"] == [1, 1]
    before, after = out.details["boundary_vertices"]
    assert after < before / 2
    assert _boundary_off_curve(v, f, out.vertices, out.faces) < 1e-12
    assert 1e-3 < out.details["boundary_chord"] < 0.05  # the outline becomes chords


def test_without_preserve_border_the_library_moves_the_base(hemisphere):
    """Why preserve_border: fast-simplification's default pulls the outline off its curve."""
    import fast_simplification

    v, f = hemisphere
    v1, f1 = fast_simplification.simplify(v, f, target_count=1000)
    assert _boundary_off_curve(v, f, np.asarray(v1), np.asarray(f1, np.int64)) > 1e-3


def test_the_boundary_is_kept_on_a_crown_with_a_hole():
    v, f = _arrays(trimesh.load(shared_mesh("low_hole"), process=False))
    out = _decimate.run(v, f, faces_target=400, method="quadric")
    assert out.details["boundary_loops"] == [2, 2]
    assert _boundary_off_curve(v, f, out.vertices, out.faces) == 0.0


# --- determinism, the input, units


def test_the_same_input_gives_the_same_bytes_twice(hemisphere):
    v, f = hemisphere
    one = _decimate.run(v.copy(), f.copy(), faces_target=1200, method="quadric")
    two = _decimate.run(v.copy(), f.copy(), faces_target=1200, method="quadric")
    assert one.vertices.tobytes() == two.vertices.tobytes()
    assert one.faces.tobytes() == two.faces.tobytes()


def test_prepare_gives_the_same_bytes_twice():
    path = shared_mesh("normal")
    one = dentopo.prepare(path, orient="none", faces=3000)
    two = dentopo.prepare(path, orient="none", faces=3000)
    assert one.vertices.tobytes() == two.vertices.tobytes()
    assert one.faces.tobytes() == two.faces.tobytes()
    assert one.step("decimate").details == two.step("decimate").details


def test_the_input_is_never_modified(hemisphere):
    v, f = _read_only(*hemisphere)  # an in-place write would raise
    _decimate.run(v, f, faces_target=1000, method="quadric")
    _decimate.run(v, f, faces_target=len(f) + 10, method="quadric")
    if _has_pymeshlab():
        _decimate.run(v, f, faces_target=1000, method="meshlab")
    np.testing.assert_array_equal(v, hemisphere[0])
    np.testing.assert_array_equal(f, hemisphere[1])


def test_the_result_does_not_depend_on_the_unit(hemisphere):
    # scaled by a power of two, the result is the same mesh scaled, bit for bit
    v, f = hemisphere
    base = _decimate.run(v, f, faces_target=1000, method="quadric")
    for scale in (1024.0, 2.0**-10):
        scaled = _decimate.run(v * scale, f, faces_target=1000, method="quadric")
        np.testing.assert_array_equal(scaled.faces, base.faces)
        np.testing.assert_array_equal(scaled.vertices, base.vertices * scale)


def test_a_mesh_in_micrometres_reaches_the_target(hemisphere):
    v, f = hemisphere
    out = _decimate.run(v * 5000.0, f, faces_target=1000, method="quadric")  # a 10 mm crown in um
    assert abs(len(out.faces) - 1000) <= 10


# --- bad and odd targets


def test_a_target_at_or_above_the_count_leaves_the_mesh_as_it_is(hemisphere):
    v, f = hemisphere
    for target in (len(f), len(f) + 1000):
        out = _decimate.run(v, f, faces_target=target, method="quadric")
        np.testing.assert_array_equal(out.vertices, v)
        np.testing.assert_array_equal(out.faces, f)
        assert out.details["faces_reached"] == len(f)
        assert (
            out.details["note"] == f"{len(f)} faces, no more than the {target} asked: not decimated"
        )
        assert out.warnings == (out.details["note"],)  # said, not only recorded
        assert out.vertices is not v and out.faces is not f


@pytest.mark.parametrize(
    ("target", "method", "words"),
    [
        (3, "quadric", "at least 4"),
        (0, "quadric", "at least 4"),
        (2.5, "quadric", "whole number"),
        (True, "quadric", "whole number"),
        (100, "vcg", "method must be one of"),
    ],
)
def test_bad_parameters_are_named(hemisphere, target, method, words):
    v, f = hemisphere
    with pytest.raises(ValueError, match=words):
        _decimate.run(v, f, faces_target=target, method=method)


def test_the_protocol_refuses_fewer_than_four_faces():
    with pytest.raises(ProtocolError, match="faces must be at least 4"):
        Protocol(faces=3)
    with pytest.raises(ProtocolError, match="decimate must be one of"):
        Protocol(faces=1000, decimate="vcg")


def test_prepare_records_the_count_reached():
    crown = dentopo.prepare(shared_mesh("normal"), orient="none", faces=2500)
    step = crown.step("decimate")
    assert step.parameters == {"faces": 2500, "method": "quadric"}
    assert step.faces_after == step.details["faces_reached"] == len(crown.faces)
    assert abs(len(crown.faces) - 2500) <= 25
    assert step.details["boundary_loops"] == [1, 1]


# --- MeshLab's quadric edge collapse (the meshlab extra)


def test_meshlab_equals_pymeshlab_called_directly(hemisphere):
    pymeshlab = pytest.importorskip(
        "pymeshlab", reason="pymeshlab (the meshlab extra, GPL) is not installed"
    )
    v, f = hemisphere
    out = _decimate.run(v, f, faces_target=1000, method="meshlab")
    meshes = pymeshlab.MeshSet()
    meshes.add_mesh(pymeshlab.Mesh(vertex_matrix=v, face_matrix=f.astype(np.int32)))
    meshes.meshing_decimation_quadric_edge_collapse(targetfacenum=1000, **MESHLAB_PARAMETERS)
    direct = meshes.current_mesh()
    np.testing.assert_array_equal(out.vertices, direct.vertex_matrix())
    np.testing.assert_array_equal(out.faces, direct.face_matrix())
    assert abs(len(out.faces) - 1000) <= 10
    assert out.details["boundary_loops"] == [1, 1]
    assert _boundary_off_curve(v, f, out.vertices, out.faces) < 1e-12
    assert out.details["meshlab"]["targetfacenum"] == 1000


def test_meshlab_gives_the_same_bytes_twice(hemisphere):
    pytest.importorskip("pymeshlab", reason="pymeshlab (the meshlab extra, GPL) is not installed")
    v, f = hemisphere
    one = _decimate.run(v, f, faces_target=800, method="meshlab")
    two = _decimate.run(v, f, faces_target=800, method="meshlab")
    assert one.vertices.tobytes() == two.vertices.tobytes()
    assert one.faces.tobytes() == two.faces.tobytes()


def test_meshlab_without_pymeshlab_names_the_extra(hemisphere, monkeypatch):
    monkeypatch.setitem(sys.modules, "pymeshlab", None)  # as if not installed
    v, f = hemisphere
    with pytest.raises(MissingExtraError, match=r"the meshlab extra: pip install '\.\[meshlab\]'"):
        _decimate.run(v, f, faces_target=1000, method="meshlab")


@pytest.mark.parametrize("name, target", [("high", 2000), ("000576115", 2000)])
def test_faces_left_twice_by_the_edge_collapse_are_dropped(name, target):
    """fast-simplification leaves a face listed twice now and then (on these: 1 and 11)."""
    v, f = _arrays(trimesh.load(shared_mesh(name), process=False))
    out = _decimate.run(v, f, faces_target=target)
    corners = np.sort(out.faces, axis=1)
    assert len(np.unique(corners, axis=0)) == len(corners)
    assert out.details["dropped_faces"] > 0  # there were some, on these meshes
    assert out.details["faces_reached"] == len(out.faces)
    assert len(out.faces) == pytest.approx(target, rel=0.01)
    assert np.all(np.bincount(out.faces.ravel(), minlength=len(out.vertices)) > 0)
