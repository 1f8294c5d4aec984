"""The batch API: finding files, computing many meshes, tables read back exactly."""

from __future__ import annotations

import os
import signal

import numpy as np
import pytest
import trimesh

from dentopo import COLUMNS, ariaDNE, compute_batch, find_mesh_files, to_dataframe
from dentopo.batch import Interrupted, guard_interrupts
from dentopo.batch._pool import death_reason
from dentopo.formats import atomic_write, read_table, write_table
from dentopo.samples import tooth


@pytest.fixture
def folder(tmp_path):
    tooth(rings=10).export(tmp_path / "b_tooth.ply")
    trimesh.creation.icosphere(subdivisions=2).export(tmp_path / "a_sphere.obj")
    (tmp_path / "sub").mkdir()
    tooth(rings=12).export(tmp_path / "sub" / "c_tooth.stl")
    (tmp_path / "sub" / "d_bad.ply").write_text("not a mesh")
    return tmp_path


def without_seconds(records):
    return [{k: v for k, v in r.items() if k != "seconds"} for r in records]


def test_records_are_sorted_rows_with_the_librarys_numbers(folder):
    records = compute_batch(folder)
    assert [os.path.relpath(r["file"], folder) for r in records] == [
        "a_sphere.obj",
        "b_tooth.ply",
        os.path.join("sub", "c_tooth.stl"),
        os.path.join("sub", "d_bad.ply"),
    ]
    for record in records[:3]:
        assert list(record) == list(COLUMNS)
        assert record["status"] == "ok" and record["error"] is None
        expected = ariaDNE(record["file"]).to_dict()
        assert {k: record[k] for k in expected} == expected
    bad = records[3]
    assert bad["status"] == "error" and bad["error"]
    assert all(bad[name] is None for name in COLUMNS[1:13])


def test_jobs_2_is_identical_to_jobs_1(folder):
    one = compute_batch(folder, jobs=1)
    two = compute_batch(folder, jobs=2)
    assert without_seconds(one) == without_seconds(two)


def test_progress_is_called_once_per_file(folder):
    seen = []
    compute_batch(folder, progress=lambda done, total, record: seen.append((done, total)))
    assert seen == [(1, 4), (2, 4), (3, 4), (4, 4)]


def test_resume_from_records_skips_matching_ok_rows(folder):
    first = compute_batch(folder)
    marked = [dict(r, dne=-1.0) if r["status"] == "ok" else r for r in first]
    again = compute_batch(folder, resume_from=marked)
    assert [r["dne"] for r in again[:3]] == [-1.0, -1.0, -1.0]  # reused, not recomputed
    assert again[3]["status"] == "error"  # retried (and still bad)
    other = compute_batch(folder, resume_from=marked, cutoff=0.01)
    assert all(r["dne"] != -1.0 for r in other[:3])  # other settings: recomputed


def test_warnings_name_the_file(tmp_path):
    trimesh.creation.icosphere(subdivisions=2).export(tmp_path / "tiny_kernel.ply")
    with pytest.warns(UserWarning, match="tiny_kernel.ply: .* neighbours"):
        compute_batch(tmp_path, bandwidth=0.01)


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"bandwidth": -1.0}, "bandwidth"),
        ({"cutoff": 1.0}, "cutoff"),
        ({"distance_type": "taxicab"}, "distance_type"),
        ({"jobs": -2}, "jobs"),
        ({"threads": 0}, "threads"),
    ],
)
def test_bad_options_raise_before_any_work(folder, options, message):
    with pytest.raises(ValueError, match=message):
        compute_batch(folder, **options)


def test_no_mesh_files_raises(tmp_path):
    with pytest.raises(ValueError, match="no mesh files found"):
        compute_batch(tmp_path)


def test_to_dataframe_keeps_the_column_order(folder):
    frame = to_dataframe(compute_batch(folder))
    assert tuple(frame.columns) == COLUMNS
    assert frame["status"].tolist() == ["ok", "ok", "ok", "error"]


def test_find_mesh_files_dedupes_links_and_skips_hidden_and_own_outputs(tmp_path):
    tooth(rings=6).export(tmp_path / "a.ply")
    os.symlink(tmp_path / "a.ply", tmp_path / "link_to_a.ply")
    (tmp_path / ".hidden.ply").write_bytes(b"")
    (tmp_path / "a.dentopo.ply").write_bytes(b"")
    (tmp_path / "a.dentopo.csv").write_text("")
    (tmp_path / "readme.txt").write_text("")
    found = find_mesh_files([tmp_path, tmp_path / "a.ply", str(tmp_path / "*.ply")])
    assert found.files == [str(tmp_path / "a.ply")]
    assert found.unmatched == []
    assert find_mesh_files([str(tmp_path / "*.obj")]).unmatched == [str(tmp_path / "*.obj")]
    # a file named explicitly is kept whatever its extension
    assert find_mesh_files([tmp_path / "readme.txt"]).files == [str(tmp_path / "readme.txt")]


def test_find_mesh_files_skips_the_apps_output_folder_unless_named(tmp_path):
    from dentopo.batch import OUTPUT_FOLDER_MARK

    tooth(rings=6).export(tmp_path / "a.ply")
    prepared = tmp_path / "dentopo-app" / "prepared"
    prepared.mkdir(parents=True)
    tooth(rings=6).export(prepared / "a.ply")
    assert len(find_mesh_files([tmp_path]).files) == 2  # no mark: an ordinary folder
    (tmp_path / "dentopo-app" / OUTPUT_FOLDER_MARK).write_text("")
    assert find_mesh_files([tmp_path]).files == [str(tmp_path / "a.ply")]
    # the folder itself, named, is searched: the mark only hides it below another
    assert find_mesh_files([prepared]).files == [str(prepared / "a.ply")]


@pytest.mark.parametrize("ext", ["csv", "json"])
def test_tables_read_back_exactly(tmp_path, folder, ext):
    records = compute_batch(folder)
    path = tmp_path / f"table.{ext}"
    write_table(path, records)
    assert read_table(path) == records


def test_read_table_rejects_other_files(tmp_path):
    path = tmp_path / "other.csv"
    path.write_text("a,b\n1,2\n")
    with pytest.raises(ValueError, match="not a dentopo results table"):
        read_table(path)


def test_atomic_write_leaves_the_old_file_when_writing_fails(tmp_path):
    path = tmp_path / "out.csv"
    path.write_text("old\n")

    def fail_halfway(stream):
        stream.write("new, partial")
        raise RuntimeError("boom")

    with pytest.raises(RuntimeError):
        atomic_write(path, fail_halfway)
    assert path.read_text() == "old\n"
    assert os.listdir(tmp_path) == ["out.csv"]
    atomic_write(path, lambda stream: stream.write("new\n"))
    assert path.read_text() == "new\n"


def test_per_vertex_dir_must_exist(folder, tmp_path):
    with pytest.raises(ValueError, match="per_vertex_dir"):
        compute_batch(folder, per_vertex_dir=tmp_path / "missing")


def test_caller_list_is_not_modified(folder):
    paths = [folder / "b_tooth.ply", folder / "a_sphere.obj"]
    copy = list(paths)
    records = compute_batch(paths)
    assert paths == copy
    assert np.isfinite([r["dne"] for r in records]).all()


# --- interrupts and dead workers (the subprocess cases are in tests/faults) -------------------


def test_the_guard_raises_a_signal_at_once():
    before = signal.getsignal(signal.SIGINT)
    with guard_interrupts():
        with pytest.raises(Interrupted) as caught:
            signal.raise_signal(signal.SIGINT)
    assert isinstance(caught.value, KeyboardInterrupt) and caught.value.name == "SIGINT"
    assert signal.getsignal(signal.SIGINT) is before  # restored


def test_the_guard_raises_a_held_signal_as_the_block_ends():
    with pytest.raises(Interrupted):
        with guard_interrupts() as guard:
            with guard.held():
                signal.raise_signal(signal.SIGINT)  # kept: not raised in the block


def test_a_held_guard_keeps_the_signal_for_later():
    with guard_interrupts() as guard:
        with guard.held():
            signal.raise_signal(signal.SIGINT)  # in a critical section: kept
        with pytest.raises(Interrupted):
            guard.check()


def test_an_interrupt_swallowed_by_library_code_stops_the_batch_without_a_row(
    tmp_path, monkeypatch
):
    from dentopo.batch import _measure, make_settings, plan_batch, run_tasks

    def swallowing_reader(mesh, **options):  # as trimesh's loader does with a Ctrl-C
        try:
            signal.raise_signal(signal.SIGINT)
        except BaseException:
            raise ValueError("string is not a file") from None

    monkeypatch.setattr(_measure, "ariaDNE", swallowing_reader)
    tasks = plan_batch([str(tmp_path / "a.ply"), str(tmp_path / "b.ply")], make_settings())
    got = []
    with pytest.raises(KeyboardInterrupt):
        for outcome in run_tasks(tasks, make_settings()):
            got.append(outcome)
    assert got == []  # no wrong error row for a file that was only interrupted


def test_a_dead_workers_reason_names_the_signal():
    assert death_reason(-signal.SIGKILL) == "worker process killed by SIGKILL (out of memory?)"
    assert death_reason(-signal.SIGSEGV) == "worker process killed by SIGSEGV"
    assert death_reason(3) == "worker process exited unexpectedly (exit code 3)"


def test_dae_files_skipped_without_pycollada_are_warned_about_once(tmp_path, monkeypatch):
    import dentopo.batch._inputs as inputs

    tooth(rings=3).export(tmp_path / "a.ply")
    for name in ("b.dae", "sub/c.dae"):
        (tmp_path / name).parent.mkdir(exist_ok=True)
        (tmp_path / name).write_text("<COLLADA/>")
    monkeypatch.setattr(inputs, "mesh_extensions", lambda: ("ply",))  # as without pycollada
    with pytest.warns(UserWarning, match=r"2 \.dae files skipped .* needs pycollada") as caught:
        found = find_mesh_files([tmp_path, str(tmp_path / "sub")])
    assert len(caught) == 1  # once, not per file or folder
    assert [os.path.basename(f) for f in found.files] == ["a.ply"]
    monkeypatch.setattr(inputs, "mesh_extensions", lambda: ("ply", "dae"))  # with pycollada
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        found = find_mesh_files([tmp_path])
    assert sorted(os.path.basename(f) for f in found.files) == ["a.ply", "b.dae", "c.dae"]


def test_the_command_says_a_dae_file_was_skipped(tmp_path, monkeypatch, capsys):
    import dentopo.batch._inputs as inputs
    from dentopo.cli import main

    tooth(rings=3).export(tmp_path / "a.ply")
    (tmp_path / "b.dae").write_text("<COLLADA/>")
    monkeypatch.setattr(inputs, "mesh_extensions", lambda: ("ply",))
    assert main([str(tmp_path), "-q"]) == 0
    err = capsys.readouterr().err
    assert err.splitlines() == [
        "dentopo: warning: a .dae file skipped in the folders searched: reading .dae needs "
        "pycollada (pip install pycollada)"
    ]


def test_a_protocol_renamed_since_keeps_its_rows_under_its_new_name(tmp_path, capsys):
    from dentopo import Protocol
    from dentopo.cli import main
    from dentopo.formats import PROTOCOL_KEY

    for name in ("a.ply", "b.ply"):
        tooth(rings=10).export(tmp_path / name)
    old = Protocol(name="lab-old", orient="none", faces=500)  # below its 600 faces
    new = old.replace(name="lab-new")
    assert new.digest == old.digest and new.label != old.label
    first = compute_batch(tmp_path, prepare=old)
    marked = [dict(r, dne=-1.0) for r in first]
    copy = [dict(r) for r in marked]
    again = compute_batch(tmp_path, prepare=new, resume_from=marked)
    assert [r["dne"] for r in again] == [-1.0, -1.0]  # reused: the same steps, same digest
    assert [r[PROTOCOL_KEY] for r in again] == [new.label] * 2  # named as this run names it
    assert marked == copy  # the rows passed in are untouched
    # the command: a table measured under the old name, resumed under the new one
    toml = tmp_path / "new.toml"
    toml.write_text(new.to_toml(), encoding="utf-8")
    out = tmp_path / "out.csv"
    write_table(out, first)
    capsys.readouterr()
    assert (
        main(
            [
                str(tmp_path / "a.ply"),
                str(tmp_path / "b.ply"),
                "--prepare",
                str(toml),
                "-o",
                str(out),
                "--resume",
            ]
        )
        == 0
    )
    assert "2 of 2 files already done" in capsys.readouterr().err
    assert [r[PROTOCOL_KEY] for r in read_table(out)] == [new.label] * 2
