"""``dentopo prepare``: a batch of raw scans to prepared crowns, called as ``main([...])``.

Most tests keep the pose (``--orient none``) and decimate, so that they test the
command and its files whatever the orient and crop steps do; the tests of the
default protocol, the named protocols and the crop options run those steps.
"""

from __future__ import annotations

import hashlib
import os
import shutil

import numpy as np
import pytest
import trimesh

from dentopo.cli import _prepare as cli
from dentopo.cli import main
from dentopo.formats import read_record
from dentopo.mesh import read_ply
from dentopo.prepare import named_protocols, read_protocol
from dentopo.samples import tooth

KEEP = ["--orient", "none"]


def small_tooth(path, rings=10):
    path.parent.mkdir(parents=True, exist_ok=True)
    tooth(rings=rings).export(path)
    return path


def small_sphere(path):
    path.parent.mkdir(parents=True, exist_ok=True)
    trimesh.creation.icosphere(subdivisions=2).export(path)
    return path


@pytest.fixture
def raw(tmp_path):
    """raw/tooth.ply, raw/sub/sphere.ply and raw/sub/deep/tooth2.ply."""
    small_tooth(tmp_path / "raw" / "tooth.ply")
    small_sphere(tmp_path / "raw" / "sub" / "sphere.ply")
    small_tooth(tmp_path / "raw" / "sub" / "deep" / "tooth2.ply", rings=8)
    return tmp_path / "raw"


def faces_of(path) -> int:
    return len(read_ply(path)[1])


def tree(folder) -> dict[str, bytes]:
    """Every file below `folder`: relative path -> bytes."""
    found = {}
    for root, _, names in os.walk(folder):
        for name in names:
            path = os.path.join(root, name)
            with open(path, "rb") as handle:
                found[os.path.relpath(path, folder)] = handle.read()
    return found


def run(capsys, *argv) -> tuple[int, str]:
    code = main(
        ["prepare", *(os.fspath(a) if isinstance(a, os.PathLike) else str(a) for a in argv)]
    )
    return code, capsys.readouterr().err


def test_registered_as_a_subcommand():
    from dentopo.cli import SUBCOMMANDS

    assert SUBCOMMANDS["prepare"] == "dentopo.cli._prepare:prepare_main"


def test_mirrors_the_tree_and_records_the_input(raw, tmp_path, capsys):
    out = tmp_path / "out"
    code, err = run(capsys, raw, "-o", out, *KEEP, "--faces", "300")
    assert code == 0, err
    assert sorted(tree(out)) == sorted(
        [
            "tooth.ply",
            "tooth.prepare.json",
            os.path.join("sub", "sphere.ply"),
            os.path.join("sub", "sphere.prepare.json"),
            os.path.join("sub", "deep", "tooth2.ply"),
            os.path.join("sub", "deep", "tooth2.prepare.json"),
        ]
    )
    record = read_record(out / "sub" / "sphere.prepare.json")
    given = os.path.join(os.fspath(raw), "sub", "sphere.ply")
    assert record["input"]["path"] == given
    expected = hashlib.sha256((raw / "sub" / "sphere.ply").read_bytes()).hexdigest()
    assert record["input"]["sha256"] == expected
    assert record["protocol"]["faces"] == 300 and record["protocol"]["orient"] == "none"
    assert record["steps"][-1]["step"] == "decimate"
    assert faces_of(out / "tooth.ply") == record_faces(out / "tooth.prepare.json")
    assert abs(faces_of(out / "tooth.ply") - 300) <= 3


def record_faces(path) -> int:
    return read_record(path)["result"]["faces"]


def test_files_given_go_to_the_top_and_clashes_get_a_hash(tmp_path, capsys):
    a = small_tooth(tmp_path / "a" / "tooth.ply")
    b = small_tooth(tmp_path / "b" / "tooth.ply", rings=8)
    out = tmp_path / "out"
    code, err = run(capsys, a, b, "-o", out, *KEEP)
    assert code == 0, err
    meshes = sorted(name for name in os.listdir(out) if name.endswith(".ply"))
    assert len(meshes) == 2 and all(name.startswith("tooth-") for name in meshes)
    sources = {read_record(out / (m[:-4] + ".prepare.json"))["input"]["path"] for m in meshes}
    assert sources == {os.fspath(a), os.fspath(b)}


def test_a_bad_file_among_good_ones(raw, tmp_path, capsys):
    (raw / "sub" / "bad.ply").write_text("not a mesh\n")
    out = tmp_path / "out"
    code, err = run(capsys, raw, "-o", out, *KEEP, "--faces", "300")
    assert code == 1
    lines = [line for line in err.splitlines() if "bad.ply" in line]
    assert len(lines) == 1 and "error" in lines[0] and "not a PLY file" in lines[0]
    assert (out / "tooth.ply").is_file() and (out / "sub" / "sphere.prepare.json").is_file()
    assert not (out / "sub" / "bad.ply").exists()
    assert not (out / "sub" / "bad.prepare.json").exists()


def test_same_bytes_at_any_jobs_and_twice(raw, tmp_path, capsys):
    outputs = []
    for jobs, name in ((1, "a"), (1, "b"), (2, "c")):
        code, err = run(capsys, raw, "-o", tmp_path / name, *KEEP, "--faces", "300", "-j", jobs)
        assert code == 0, err
        outputs.append(tree(tmp_path / name))
    assert outputs[0] == outputs[1] == outputs[2]
    assert len(outputs[0]) == 6


def test_the_input_is_never_modified(raw, tmp_path, capsys):
    before = {p: (p.read_bytes(), p.stat().st_mtime_ns) for p in raw.rglob("*.ply")}
    code, err = run(capsys, raw, "-o", tmp_path / "out", *KEEP, "--faces", "300")
    assert code == 0, err
    assert {p: (p.read_bytes(), p.stat().st_mtime_ns) for p in raw.rglob("*.ply")} == before


def test_resume_skips_done_files_and_redoes_changed_ones(raw, tmp_path, capsys):
    out = tmp_path / "out"
    options = [raw, "-o", out, *KEEP, "--faces", "300"]
    assert run(capsys, *options)[0] == 0
    stamps = {p: p.stat().st_mtime_ns for p in out.rglob("*") if p.is_file()}
    code, err = run(capsys, *options, "--resume")
    assert code == 0 and "3 of 3 files already done" in err
    assert {p: p.stat().st_mtime_ns for p in out.rglob("*") if p.is_file()} == stamps
    small_tooth(raw / "tooth.ply", rings=9)  # changed input
    (out / "sub" / "sphere.ply").unlink()  # a mesh lost
    code, err = run(capsys, *options, "--resume")
    assert code == 0 and "1 of 3 files already done" in err
    record = read_record(out / "tooth.prepare.json")
    expected = hashlib.sha256((raw / "tooth.ply").read_bytes()).hexdigest()
    assert record["input"]["sha256"] == expected
    assert (out / "sub" / "sphere.ply").is_file()
    deep = out / "sub" / "deep" / "tooth2.prepare.json"
    assert deep.stat().st_mtime_ns == stamps[deep]
    code, err = run(capsys, raw, "-o", out, *KEEP, "--faces", "250", "--resume")  # other protocol
    assert code == 0 and "0 of 3 files already done" in err


def test_save_protocol_then_protocol_gives_the_same_outputs(raw, tmp_path, capsys):
    saved = tmp_path / "study.toml"
    options = [*KEEP, "--faces", "300", "--smooth", "taubin:4", "--smooth-step", "0.4"]
    code, err = run(capsys, raw, "-o", tmp_path / "a", *options, "--save-protocol", saved)
    assert code == 0, err
    protocol = read_protocol(saved)
    assert (protocol.faces, protocol.smooth, protocol.smooth_iterations) == (300, "taubin", 4)
    assert protocol.smooth_step == 0.4 and protocol.orient == "none"
    code, err = run(capsys, raw, "-o", tmp_path / "b", "--protocol", saved)
    assert code == 0, err
    assert tree(tmp_path / "a") == tree(tmp_path / "b")


def test_smooth_base_free_runs_the_filter_as_published(tmp_path, capsys):
    saved = tmp_path / "p.toml"
    code, err = run(capsys, "--smooth", "hc", "--smooth-base", "free", "--save-protocol", saved)
    assert code == 0, err
    assert read_protocol(saved).smooth_pin_boundary is False
    code, err = run(capsys, "--smooth", "hc", "--save-protocol", saved)
    assert code == 0, err
    assert read_protocol(saved).smooth_pin_boundary is True
    code, err = run(capsys, "--smooth-base", "free", "--save-protocol", saved)
    assert code == 2 and "--smooth" in err


def test_save_protocol_alone_writes_only_the_protocol(tmp_path, capsys):
    saved = tmp_path / "p.toml"
    code, err = run(capsys, "--faces", "5000", "--orient", "none", "--save-protocol", saved)
    assert code == 0, err
    assert read_protocol(saved).faces == 5000
    assert sorted(os.listdir(tmp_path)) == ["p.toml"]


def test_options_override_the_protocol_file(raw, tmp_path, capsys):
    saved = tmp_path / "p.toml"
    saved.write_text('name = "mine"\n[orient]\nmode = "none"\n[decimate]\nfaces = 400\n')
    code, err = run(
        capsys, raw / "tooth.ply", "-o", tmp_path / "out", "--protocol", saved, "--faces", "300"
    )
    assert code == 0, err
    record = read_record(tmp_path / "out" / "tooth.prepare.json")
    assert record["protocol"]["faces"] == 300 and record["protocol"]["name"] == "mine+"


@pytest.mark.parametrize(
    ("options", "named"),
    [
        (["--faces", "2"], "--faces"),
        (["--faces", "many"], "--faces"),
        (["--smooth", "blur"], "--smooth"),
        (["--smooth", "taubin:x"], "--smooth"),
        (["--smooth", "taubin:-1"], "--smooth"),
        (["--smooth-mu", "0.5"], "--smooth-mu"),
        (["--smooth", "laplacian", "--smooth-mu", "0.5"], "--smooth-mu"),
        (["--smooth", "taubin", "--smooth-step", "0"], "--smooth-step"),
        (["--up", "1,2"], "--up"),
        (["--up", "0,0,0"], "--up"),
        (["--orient", "none", "--up", "0,0,1"], "--up"),
        (["--orient", "sideways"], "--orient"),
        (["--crop-fraction", "1.5"], "--crop-fraction"),
        (["--crop-below", "-1"], "--crop-below"),
        (["--crop-plane", "0,0,0,0,0,0"], "--crop-plane"),
        (["--crop-below", "1", "--crop-fraction", "0.5"], "--crop-below"),
        (["--keep", "some"], "--keep"),
        (["--decimate", "magic"], "--decimate"),
        (["--protocol", "no-such-protocol"], "--protocol"),
        (["-j", "-1"], "--jobs"),
    ],
)
def test_wrong_values_exit_2_naming_the_option(raw, tmp_path, capsys, options, named):
    code, err = run(capsys, raw, "-o", tmp_path / "out", *options)
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and named in lines[0], err
    assert not (tmp_path / "out").exists()  # nothing computed or written


def test_a_bad_protocol_file_is_named(raw, tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text("[decimate]\nfaces = 'many'\n")
    code, err = run(capsys, raw, "-o", tmp_path / "out", "--protocol", bad)
    assert code == 2 and "bad.toml" in err and "faces" in err


def test_an_output_that_is_an_input_is_refused_before_computing(raw, capsys):
    before = (raw / "tooth.ply").read_bytes()
    code, err = run(capsys, raw / "tooth.ply", "-o", raw, *KEEP)
    assert code == 2 and "would replace it" in err
    assert (raw / "tooth.ply").read_bytes() == before
    assert not (raw / "tooth.prepare.json").exists()


def test_an_unwritable_output_is_refused_before_computing(raw, tmp_path, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("")
    code, err = run(capsys, raw, "-o", blocker / "out", *KEEP)
    assert code == 2 and "not a directory" in err


def test_outputs_go_nowhere_through_a_planted_link(raw, tmp_path, capsys):
    out = tmp_path / "out"
    out.mkdir()
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    os.symlink(elsewhere, out / "sub")
    code, err = run(capsys, raw, "-o", out, *KEEP)
    assert code == 1 and "symbolic link" in err
    assert os.listdir(elsewhere) == []
    assert (out / "tooth.ply").is_file()


def test_a_failed_write_leaves_no_partial_file(raw, tmp_path, capsys, monkeypatch):
    from dentopo.formats import _prepared

    def broken(record):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(_prepared, "record_text", broken)
    out = tmp_path / "out"
    code, err = run(capsys, raw / "tooth.ply", "-o", out, *KEEP)
    assert code == 1 and "No space left on device" in err and "an output failed" in err
    assert sorted(os.listdir(out)) == ["tooth.ply"]  # no record (so not done), no temporary
    monkeypatch.undo()
    code, err = run(capsys, raw / "tooth.ply", "-o", out, *KEEP, "--resume")
    assert code == 0 and "0 of 1 files already done" in err


def test_output_folders_inside_an_input_folder_are_not_inputs(raw, capsys):
    out = raw / "prepared"
    assert run(capsys, raw, "-o", out, *KEEP)[0] == 0
    code, err = run(capsys, raw, "-o", out, *KEEP)
    assert code == 0, err
    assert not (out / "prepared").exists()


def test_hostile_names_are_data(tmp_path, capsys):
    name = "a b\n'\"<x>;$(rm).ply"
    small_tooth(tmp_path / "raw" / name)
    out = tmp_path / "out"
    code, err = run(capsys, tmp_path / "raw", "-o", out, *KEEP)
    assert code == 0, err
    stem = name[:-4]
    assert (out / (stem + ".ply")).is_file()
    assert read_record(out / (stem + ".prepare.json"))["input"]["path"].endswith(name)


def test_list_protocols(capsys):
    assert main(["prepare", "--protocols"]) == 0
    out = capsys.readouterr().out
    for name, protocol in named_protocols().items():
        assert name in out and protocol.source in out


def test_no_inputs_is_a_usage_error(capsys):
    assert main(["prepare"]) == 2
    assert "no mesh files given" in capsys.readouterr().err


def test_preview_without_the_viz_extra_exits_2_before_computing(raw, tmp_path, capsys, monkeypatch):
    from dentopo._optional import MissingExtraError

    def missing():
        raise MissingExtraError("pictures", "viz")

    class Missing:
        check = staticmethod(missing)

    monkeypatch.setattr(cli, "PICTURES", Missing())
    code, err = run(capsys, raw, "-o", tmp_path / "out", *KEEP, "--preview", tmp_path / "p")
    assert code == 2 and "viz extra" in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "out").exists()


def test_preview_pictures_and_sheet(raw, tmp_path, capsys):
    pytest.importorskip("pyvista", reason="pyvista (the viz extra) draws the previews")
    image = pytest.importorskip("PIL.Image", reason="Pillow reads the PNGs")
    previews = tmp_path / "previews"
    argv = [raw, "-o", tmp_path / "out", *KEEP, "--faces", "300", "--preview", previews]
    code, err = run(capsys, *argv)
    assert code == 0, err
    pictures = [
        previews / "tooth.png",
        previews / "sub" / "sphere.png",
        previews / "sub" / "deep" / "tooth2.png",
    ]
    for path in pictures:
        with image.open(path) as picture:
            assert picture.format == "PNG" and picture.size == (880, 440)
            pixels = np.asarray(picture.convert("L"))
            assert pixels.std() > 5  # not blank: a crown is drawn
    with image.open(previews / "sheet.png") as sheet:
        assert sheet.format == "PNG" and sheet.width >= 440 and sheet.height >= 220
    code, err = run(capsys, *argv, "--resume")
    assert code == 0 and "3 of 3 files already done" in err
    os.unlink(pictures[0])  # a preview lost: that file is redone
    code, err = run(capsys, *argv, "--resume")
    assert code == 0 and "2 of 3 files already done" in err and pictures[0].is_file()


# -- the steps that turn and cut the crown (the default protocol, named protocols, crops)


def test_default_protocol_orients_and_records_the_transform(raw, tmp_path, capsys):
    out = tmp_path / "out"
    code, err = run(capsys, raw / "tooth.ply", "-o", out)
    assert code == 0, err
    record = read_record(out / "tooth.prepare.json")
    assert [s["step"] for s in record["steps"]] == ["clean", "orient"]
    transform = np.array(record["transform"])
    assert transform.shape == (4, 4)
    assert np.allclose(transform[:3, :3] @ transform[:3, :3].T, np.eye(3))


def test_a_named_protocol_runs_by_name(tmp_path, capsys):
    raw = small_tooth(tmp_path / "raw" / "tooth.ply", rings=40)
    out = tmp_path / "out"
    code, err = run(capsys, raw, "-o", out, "--protocol", "crown-10k")
    assert code == 0, err
    record = read_record(out / "tooth.prepare.json")
    assert record["protocol"]["name"] == "crown-10k"
    assert record["protocol"]["digest"] == named_protocols()["crown-10k"].digest


def test_crop_fraction_keeps_the_top_and_records_its_plane(raw, tmp_path, capsys):
    out = tmp_path / "out"
    code, err = run(capsys, raw / "tooth.ply", "-o", out, *KEEP, "--crop-fraction", "0.5")
    assert code == 0, err
    record = read_record(out / "tooth.prepare.json")
    crop = next(s for s in record["steps"] if s["step"] == "crop")
    assert crop["plane"] is not None and crop["faces"][1] < crop["faces"][0]
    shutil.rmtree(out)


def test_ctrl_c_stops_without_half_files(raw, tmp_path, capsys, monkeypatch):
    from dentopo.formats import _prepared

    calls = []
    original = _prepared.record_text

    def interrupted_on_the_second(record):
        calls.append(record["input"]["path"])
        if len(calls) == 2:
            raise KeyboardInterrupt
        return original(record)

    monkeypatch.setattr(_prepared, "record_text", interrupted_on_the_second)
    out = tmp_path / "out"
    code, err = run(capsys, raw, "-o", out, *KEEP)
    assert code == 130 and "interrupted" in err and "--resume" in err
    files = [p for p in out.rglob("*") if p.is_file()]
    assert not [p for p in files if p.name.endswith(".tmp")]
    assert len([p for p in files if p.name.endswith(".prepare.json")]) == 1
    monkeypatch.undo()
    code, err = run(capsys, raw, "-o", out, *KEEP, "--resume")
    assert code == 0 and "1 of 3 files already done" in err


def test_render_preparation_draws_the_axis_and_the_crop_plane(tmp_path):
    """A tilted crown whose orientation and crop are known: blue axis, red plane, both drawn."""
    pytest.importorskip("pyvista", reason="pyvista (the viz extra) draws the previews")
    image = pytest.importorskip("PIL.Image", reason="Pillow reads the PNGs")
    import dataclasses

    import dentopo
    from dentopo.figures import render_preparation
    from dentopo.prepare import Step

    mesh = tooth(rings=12)
    angle = np.radians(30.0)
    turn = np.array(
        [[1, 0, 0], [0, np.cos(angle), -np.sin(angle)], [0, np.sin(angle), np.cos(angle)]]
    )
    raw_vertices = mesh.vertices @ turn.T  # the raw scan, tilted by 30 degrees
    transform = np.eye(4)
    transform[:3, :3] = turn.T  # orient: back upright
    upright = mesh.vertices
    height = upright[:, 2].min() + 0.3 * np.ptp(upright[:, 2])
    kept = mesh.faces[(upright[mesh.faces][:, :, 2] >= height).all(axis=1)]
    crown = dentopo.prepare((upright, kept), orient="none")
    sizes = (len(upright), len(upright), len(mesh.faces), len(mesh.faces), 1.0, 1.0)
    orient = Step(
        "orient",
        {"mode": "occlusal"},
        *sizes,
        transform=transform,
        plane={"point": [0.0, 0.0, 0.0], "normal": list(turn @ [0.0, 0.0, 1.0])},
    )
    crop = Step(
        "crop",
        {"fraction": 0.7},
        *sizes,
        plane={"point": [0.0, 0.0, float(height)], "normal": [0.0, 0.0, 1.0]},
    )
    crown = dataclasses.replace(crown, steps=(crown.steps[0], orient, crop), transform=transform)
    before = raw_vertices.copy()
    drawn, plain = tmp_path / "drawn.png", tmp_path / "plain.png"
    render_preparation(raw_vertices, mesh.faces, crown, drawn, title="specimen <1>.ply")
    render_preparation(
        raw_vertices,
        mesh.faces,
        dataclasses.replace(crown, steps=crown.steps[:1], transform=np.eye(4)),
        plain,
    )
    assert np.array_equal(raw_vertices, before)  # never modified

    def coloured(path):
        with image.open(path) as picture:
            pixels = np.asarray(picture.convert("RGB")).astype(int)
        left = pixels[:, : pixels.shape[1] // 2]
        red = (left[..., 0] > 150) & (left[..., 1] < 90) & (left[..., 2] < 90)
        blue = (left[..., 2] > 150) & (left[..., 0] < 90)
        return int(red.sum()), int(blue.sum())

    red, blue = coloured(drawn)
    assert red > 200 and blue > 200  # the crop plane and the axis
    assert coloured(plain)[0] == 0  # no crop: no red


def test_files_named_go_to_the_top_unless_a_folder_given_holds_them(raw, tmp_path, capsys):
    out = tmp_path / "out"
    code, err = run(capsys, raw / "tooth.ply", raw / "sub" / "sphere.ply", "-o", out, *KEEP)
    assert code == 0, err
    assert sorted(p.name for p in out.iterdir()) == [
        "sphere.ply",
        "sphere.prepare.json",
        "tooth.ply",
        "tooth.prepare.json",
    ]
    out2 = tmp_path / "out2"
    code, err = run(capsys, raw / "sub", raw / "sub" / "deep" / "tooth2.ply", "-o", out2, *KEEP)
    assert code == 0, err
    assert (out2 / "deep" / "tooth2.ply").is_file() and (out2 / "sphere.ply").is_file()


def test_a_killed_worker_leaves_no_temporary_file(tmp_path, monkeypatch):
    from dentopo.batch import _prepare as batch

    monkeypatch.chdir(tmp_path)
    small_tooth(tmp_path / "raw" / "a" / "tooth.ply")
    (task,) = batch.plan_preparation(["raw/a/tooth.ply"], ["raw"], tmp_path / "out")
    folder = tmp_path / "out" / "a"
    folder.mkdir(parents=True)
    left = [folder / ".tooth.ply.k2j4.tmp", folder / ".tooth.prepare.json.x9.tmp"]
    kept = [folder / "tooth.ply", folder / ".other.ply.k2j4.tmp"]
    for path in left + kept:
        path.write_bytes(b"x")
    outcome = batch._failed(task, "worker process killed by SIGKILL (out of memory?)")
    assert outcome.status == "error" and "SIGKILL" in outcome.error
    assert not any(path.exists() for path in left)
    assert all(path.exists() for path in kept)
