"""dentopo.prepare: the protocol (checks, TOML, digest), the clean step, the pipeline's record."""

from __future__ import annotations

import json
import pickle

import numpy as np
import pytest
import trimesh

import dentopo
from dentopo.prepare import (
    PreparedCrown,
    Protocol,
    ProtocolError,
    load_protocol,
    named_protocols,
    prepare,
    read_protocol,
)
from dentopo.prepare._clean import face_pieces, largest_piece


def _with_specks(mesh: trimesh.Trimesh, count: int = 3, seed: int = 0) -> trimesh.Trimesh:
    """`mesh` plus `count` small loose spheres beside it (a scan's specks)."""
    rng = np.random.default_rng(seed)
    parts = [mesh]
    size = float(np.ptp(mesh.vertices, axis=0).max())
    for _ in range(count):
        speck = trimesh.creation.icosphere(subdivisions=1, radius=0.02 * size)
        speck.apply_translation(mesh.vertices.mean(axis=0) + rng.normal(size=3) * size)
        parts.append(speck)
    return trimesh.util.concatenate(parts)


# -- the protocol ---------------------------------------------------------------------------------


def test_defaults_clean_and_orient_only():
    steps = Protocol().steps()
    assert list(steps) == ["clean", "orient"]
    assert steps["clean"] == {"keep": "largest"}


@pytest.mark.parametrize(
    "changes, named",
    [
        ({"keep": "most"}, "keep"),
        ({"orient": "up"}, "orient"),
        ({"spin": "yes"}, "spin"),
        ({"faces": 3}, "faces"),
        ({"faces": 10.5}, "faces"),
        ({"faces": True}, "faces"),
        ({"crop_fraction": 0.0}, "crop_fraction"),
        ({"crop_fraction": 1.5}, "crop_fraction"),
        ({"crop_below": float("nan")}, "crop_below"),
        ({"crop_below": -1.0}, "crop_below"),
        ({"crop_plane": (0, 0, 0, 0, 0, 0)}, "crop_plane"),
        ({"crop_plane": (0, 0, 1)}, "crop_plane"),
        ({"crop_below": 1.0, "crop_fraction": 0.5}, "crop_below and crop_fraction"),
        ({"up": (0, 0, 0)}, "up"),
        ({"up": (0, 0, 1), "orient": "none"}, "orient='occlusal'"),
        ({"smooth": "gaussian"}, "smooth"),
        ({"smooth_iterations": 3}, "smooth method"),
        ({"smooth": "implicit", "smooth_iterations": -1}, "smooth_iterations"),
        ({"smooth": "implicit", "smooth_step": 0.0}, "smooth_step"),
        ({"smooth": "laplacian", "smooth_mu": 0.5}, "smooth_mu"),
        ({"decimate": "vtk"}, "decimate"),
    ],
)
def test_wrong_parameters_are_named(changes, named):
    with pytest.raises(ProtocolError, match=named.replace("(", r"\(").replace(")", r"\)")):
        Protocol(**changes)


def test_protocol_error_is_a_value_error():
    assert issubclass(ProtocolError, ValueError)


def test_vectors_from_text_and_sequences_agree():
    assert Protocol(up="0, 1, 0").up == Protocol(up=[0, 1, 0]).up == (0.0, 1.0, 0.0)
    with pytest.raises(ProtocolError, match="3 numbers"):
        Protocol(up="0, one, 0")


def test_digest_ignores_names_and_defaults_filled():
    a = Protocol(name="a", description="one", smooth="implicit")
    b = Protocol(name="b", smooth="implicit", smooth_iterations=3, smooth_step=0.1)
    assert a.digest == b.digest
    assert a.label.startswith("a ") and a.label.split()[1] == a.digest[:12]
    assert Protocol(faces=10000).digest != Protocol(faces=10001).digest
    assert Protocol(orient="none").digest != Protocol().digest


def test_toml_round_trip(tmp_path):
    protocol = Protocol(
        name='odd "name" é',
        description="line one",
        keep="all",
        up=(0.1, 0.2, 0.97),
        spin="footprint",
        crop_plane=(0, 0, 1.5, 0, 0.1, 1),
        faces=12000,
        smooth="taubin",
        smooth_iterations=7,
        smooth_mu=0.53,
    )
    path = tmp_path / "p.toml"
    path.write_text(protocol.to_toml(), encoding="utf-8")
    back = read_protocol(path)
    assert back.digest == protocol.digest
    assert back.name == protocol.name and back.keep == "all" and back.up == protocol.up


def test_every_field_survives_the_file(tmp_path):
    for protocol in [
        Protocol(),
        Protocol(clean=False, orient="none"),
        Protocol(crop_below=2.5),
        Protocol(decimate="meshlab"),
        Protocol(smooth="implicit", smooth_pin_boundary=False),
    ]:
        path = tmp_path / "p.toml"
        path.write_text(protocol.to_toml(), encoding="utf-8")
        back = read_protocol(path)
        assert back.to_toml() == protocol.to_toml() and back.digest == protocol.digest
        if protocol.smooth is None:  # smoothing's defaults are written out, filled in
            assert back == protocol


@pytest.mark.parametrize(
    "text, named",
    [
        ("[decimate]\nface = 10\n", "no key 'face'"),
        ("[smoothing]\nmethod = 'hc'\n", "unknown key 'smoothing'"),
        ("decimate = 3\n", r"\[decimate\] must be a table"),
        ("[decimate]\nfaces = 'many'\n", "faces"),
        ("[crop\n", "not valid TOML"),
    ],
)
def test_bad_protocol_files_name_the_problem(tmp_path, text, named):
    path = tmp_path / "bad.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(ProtocolError, match=named):
        read_protocol(path)
    with pytest.raises(ProtocolError, match=r"bad\.toml"):
        read_protocol(path)


def test_binary_protocol_file_is_refused(tmp_path):
    path = tmp_path / "bin.toml"
    path.write_bytes(b"\xff\xfe\x00name")
    with pytest.raises(ProtocolError, match="UTF-8"):
        read_protocol(path)


def test_a_hand_written_file_says_what_differs_from_the_defaults(tmp_path):
    path = tmp_path / "p.toml"
    path.write_text("[decimate]\nfaces = 5000\n", encoding="utf-8")
    protocol = read_protocol(path)
    assert list(protocol.steps()) == ["clean", "orient", "decimate"]


def test_shipped_protocols_load_by_name_and_state_a_source():
    named = named_protocols()
    assert {"crown-10k", "morphotester-smooth"} <= set(named)
    for name, protocol in named.items():
        assert protocol.name == name
        assert protocol.description and protocol.source
        assert load_protocol(name) is not None
    assert named["crown-10k"].faces == 10000
    assert named["morphotester-smooth"].smoothing() == {
        "method": "implicit",
        "iterations": 3,
        "step": 0.1,
        "pin_boundary": False,
    }


def test_unknown_protocol_name_lists_the_shipped_ones():
    with pytest.raises(ProtocolError, match="crown-10k"):
        load_protocol("no-such-protocol")


def test_replace_marks_a_named_protocol_changed():
    changed = load_protocol("crown-10k").replace(faces=5000)
    assert changed.name == "crown-10k+" and changed.faces == 5000
    with pytest.raises(ProtocolError, match="unknown protocol parameter 'facets'"):
        Protocol().replace(facets=3)


def test_protocol_pickles():
    protocol = Protocol(faces=2000, smooth="hc")
    assert pickle.loads(pickle.dumps(protocol)) == protocol


# -- the clean step -------------------------------------------------------------------------------


def test_pieces_and_the_largest_by_area():
    big = trimesh.creation.icosphere(subdivisions=2)
    small = trimesh.creation.icosphere(subdivisions=3, radius=0.1)  # more faces, less area
    small.apply_translation([5, 0, 0])
    both = trimesh.util.concatenate([small, big])
    count, piece = face_pieces(both.faces, len(both.vertices))
    assert count == 2 and len(np.unique(piece)) == 2
    v, f, dropped = largest_piece(np.asarray(both.vertices), np.asarray(both.faces))
    assert dropped == 1
    assert len(f) == len(big.faces) and np.allclose(
        np.sort(v, axis=0), np.sort(big.vertices, axis=0)
    )


def test_clean_keeps_the_largest_piece_and_records_it():
    from dentopo.samples import tooth

    crown = tooth()
    raw = _with_specks(crown)
    result = prepare(raw, orient="none")
    step = result.step("clean")
    assert step.pieces_removed == 3
    assert step.details["pieces"] == 4
    assert result.faces.shape == crown.faces.shape
    assert step.area_after < step.area_before
    assert step.details["removed_area"] == pytest.approx(step.area_before - step.area_after)
    everything = prepare(raw, orient="none", keep="all")
    assert everything.step("clean").pieces_removed == 0
    assert len(everything.faces) == len(raw.faces)


def test_no_clean_keeps_the_mesh_as_given():
    from dentopo.samples import tooth

    raw = _with_specks(tooth())
    result = prepare(raw, clean=False, orient="none")
    assert result.steps == ()
    assert np.array_equal(result.vertices, raw.vertices) and np.array_equal(result.faces, raw.faces)


# -- the pipeline's record ------------------------------------------------------------------------


def test_result_is_frozen_and_read_only(tooth):
    result = prepare(tooth, orient="none")
    with pytest.raises(ValueError):
        result.vertices[0, 0] = 1.0
    with pytest.raises(AttributeError):
        result.protocol = Protocol()
    mesh = result.mesh
    mesh.vertices[0] = [9, 9, 9]  # a copy: the result does not change
    assert not np.allclose(result.vertices[0], [9, 9, 9])


def test_the_callers_mesh_is_never_modified(tooth):
    raw = _with_specks(tooth)
    vertices, faces = raw.vertices.copy(), raw.faces.copy()
    prepare(raw, orient="none", faces=500, smooth="taubin")
    prepare((raw.vertices, raw.faces), orient="none", keep="all")
    assert np.array_equal(raw.vertices, vertices) and np.array_equal(raw.faces, faces)


def test_record_from_a_file_has_its_sha256(tmp_path, tooth):
    import hashlib

    path = tmp_path / "crown.ply"
    tooth.export(path)
    result = prepare(path, orient="none")
    assert result.source == str(path)
    assert result.source_sha256 == hashlib.sha256(path.read_bytes()).hexdigest()
    record = json.loads(json.dumps(result.to_dict(), allow_nan=False))
    assert record["input"]["sha256"] == result.source_sha256
    assert record["protocol"]["digest"] == result.protocol.digest
    assert [s["step"] for s in record["steps"]] == ["clean"]
    assert record["result"] == {"vertices": len(result.vertices), "faces": len(result.faces)}


def test_no_path_no_sha(tooth):
    result = prepare(tooth, orient="none")
    assert result.source is None and result.source_sha256 is None


def test_protocol_and_changes_combine(tooth):
    result = prepare(tooth, "crown-10k", orient="none", faces=800)
    assert result.protocol.name == "crown-10k+"
    assert result.step_names == ("clean", "decimate")
    assert result.step("decimate").faces_after == pytest.approx(800, rel=0.01)
    with pytest.raises(KeyError, match="no 'smooth' step ran"):
        result.step("smooth")


def test_a_wrong_change_is_named_before_reading(tmp_path):
    with pytest.raises(ProtocolError, match="faces"):
        prepare(tmp_path / "missing.ply", faces=2)


def test_identity_transform_when_nothing_moves(tooth):
    result = prepare(tooth, orient="none")
    assert np.array_equal(result.transform, np.eye(4))


def test_public_names():
    assert dentopo.prepare is prepare
    assert dentopo.Protocol is Protocol
    assert dentopo.PreparedCrown is PreparedCrown


def test_notebook_view_escapes(tooth):
    result = prepare(tooth, Protocol(name="<b>x</b>", orient="none"))
    page = result._repr_html_()
    assert "<b>x</b>" not in page and "&lt;b&gt;x&lt;/b&gt;" in page
