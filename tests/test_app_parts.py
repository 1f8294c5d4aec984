"""The app's parts without a server: options, protocols, pictures of large meshes, jobs."""

from __future__ import annotations

import os

import numpy as np
import pytest

pytest.importorskip("starlette")

from dentopo.app import AppError, RunOptions
from dentopo.app._folder import draw_thumbnail, group_of, simplified
from dentopo.app._jobs import Job, shown
from dentopo.app._workspace import protocol_from_json
from dentopo.topography import GROUPS, METRICS


def test_run_options_expand_sets_and_keep_the_table_order():
    options = RunOptions.from_json({"metrics": ["slope", "molar", "ariadne"], "jobs": 2})
    assert options.metrics == tuple(m for m in METRICS if m in {"ariadne", *GROUPS["molar"]})
    arguments = options.arguments()
    assert arguments[arguments.index("--metrics") + 1] == ",".join(options.metrics)
    assert RunOptions.from_json({}) == RunOptions()


@pytest.mark.parametrize(
    "data",
    [
        {"bandwidth": float("nan")},
        {"bandwidth": True},
        {"cutoff": -0.1},
        {"jobs": 1.5},
        {"prepare": "yes"},
        {"sign_method": "vote"},
        [],
    ],
)
def test_run_options_refuse_what_the_command_would(data):
    with pytest.raises(AppError):
        RunOptions.from_json(data)


def test_protocols_from_the_page_are_checked_and_lists_become_tuples():
    protocol = protocol_from_json({"up": [0, 0, 1], "faces": 500})
    assert protocol.up == (0.0, 0.0, 1.0) and protocol.faces == 500 and protocol.name == "app"
    with pytest.raises(AppError, match="faces"):
        protocol_from_json({"faces": -3})
    with pytest.raises(AppError, match="colour"):
        protocol_from_json({"colour": "red"})


def test_a_large_read_only_mesh_is_simplified_for_pictures_only(tooth):
    from dentopo.samples import tooth as make_tooth

    mesh = make_tooth(rings=120)
    vertices = np.asarray(mesh.vertices).copy()
    faces = np.asarray(mesh.faces).copy()
    vertices.flags.writeable = False  # as a prepared crown's arrays are
    faces.flags.writeable = False
    before = vertices.copy()
    small_v, small_f = simplified(vertices, faces, 5_000)
    assert len(small_f) <= 5_100 and small_f.max() < len(small_v)
    assert np.array_equal(vertices, before)  # never modified
    png = draw_thumbnail(vertices, faces)
    assert png.startswith(b"\x89PNG")


def test_groups_are_the_first_folder():
    assert group_of("a.ply") == "" and group_of("g/a.ply") == "g" and group_of("g/h/a.ply") == "g"


def test_the_command_shown_is_quoted_for_a_shell():
    text = shown(["--", "<img src=x>.ply", "a b.ply"], "/data/my scans")
    assert text == "cd '/data/my scans' && dentopo -- '<img src=x>.ply' 'a b.ply'"


def test_a_job_runs_its_commands_and_stops_at_a_usage_error(tmp_path):
    job = Job([["--version"], ["--no-such-option"], ["--version"]], str(tmp_path)).start()
    job.wait(120)
    assert job.codes == [0, 2] and job.state == "failed"
    assert any("no-such-option" in line for line in job.log)


@pytest.mark.skipif(not os.path.isdir("/proc/self"), reason="needs /proc, where nothing is created")
def test_an_output_folder_that_cannot_be_made_is_named(tmp_path):
    from dentopo.app import Workspace

    with pytest.raises(AppError, match="cannot write into the output folder /proc/"):
        Workspace(str(tmp_path), "/proc/dentopo-app-output")


@pytest.mark.parametrize(
    "changes",
    [
        {"faces": 3000, "crop_below": 0.5, "smooth": "taubin"},
        {"spin": "footprint", "up": (0.0, 1.0, 0.0), "crop_fraction": 0.5, "smooth": "implicit"},
        {"keep": "all", "faces": 900, "clean": False},
        {"orient": "none", "crop_fraction": 0.7},
    ],
)
def test_the_preview_in_two_is_the_preparation_to_the_bit(changes):
    from conftest import shared_mesh
    from dentopo.app._preview import prepared_in_two
    from dentopo.mesh import load_mesh
    from dentopo.prepare import Protocol, prepare

    mesh = load_mesh(shared_mesh("low_hole" if changes.get("keep") else "normal"))
    protocol = Protocol(**changes)
    whole = prepare(mesh, protocol)
    oriented, rest = prepared_in_two(mesh, protocol)
    assert np.array_equal(rest.vertices, whole.vertices)
    assert np.array_equal(rest.faces, whole.faces)
    names = [s.name for s in (*oriented.steps, *rest.steps)]
    assert names == [s.name for s in whole.steps]


def test_a_rescan_of_an_unchanged_folder_only_walks_it_and_a_change_is_seen(tmp_path, monkeypatch):
    import shutil

    from dentopo.app import _folder
    from dentopo.samples import sample_paths

    sample = str(sample_paths()["tooth"])
    shutil.copy(sample, tmp_path / "a.ply")
    (tmp_path / "sub").mkdir()
    shutil.copy(sample, tmp_path / "sub" / "b.ply")
    output = tmp_path / "dentopo-app"
    output.mkdir()
    folder = _folder.Folder(str(tmp_path), str(output))
    folder.close()  # no reading in the background: only the listing is tested
    scans = []
    finding = _folder.find_mesh_files
    monkeypatch.setattr(_folder, "find_mesh_files", lambda p: scans.append(p) or finding(p))
    (output / "written.png").write_bytes(b"the app's own files change all the time")
    folder.refresh(0.0)
    assert scans == []  # nothing changed: no scan
    shutil.copy(sample, tmp_path / "sub" / "c.ply")
    folder.refresh(0.0)
    assert len(scans) == 1 and [e.path for e in folder.entries()] == [
        "a.ply",
        "sub/b.ply",
        "sub/c.ply",
    ]
    with open(tmp_path / "a.ply", "ab") as stream:  # rewritten in place: same name, same folder
        stream.write(b"\n")
    folder.refresh(0.0)
    assert len(scans) == 2 and folder.entries()[0].bytes == os.path.getsize(tmp_path / "a.ply")
    folder.refresh(60.0)
    assert len(scans) == 2
