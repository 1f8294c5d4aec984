"""A run's progress on the page: a count that never goes back, the compile wait shown in it, and
the output folder chosen on the page (inside the folder only)."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import time

import pytest

pytest.importorskip("starlette")

from dentopo.app import AppError, Workspace, _jobs
from dentopo.app._progress import RunProgress
from dentopo.cli._compiling import notice_text
from dentopo.formats import Journal, journal_path, read_table
from dentopo.samples import sample_paths

pytestmark = pytest.mark.slow


@pytest.fixture()
def folder(tmp_path):
    folder = tmp_path / "study"
    (folder / "sub").mkdir(parents=True)
    paths = sample_paths()
    for name in ("tooth", "saddle", "sphere"):
        shutil.copy(paths[name], folder / f"{name}.ply")
    shutil.copy(paths["tooth"], folder / "sub" / "tooth2.ply")
    return folder


def follow(workspace: Workspace, seconds: float = 300) -> list[dict]:
    """Every state of the run, asked for as often as the machine allows, until it ends."""
    states = []
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        state = workspace.run_state()
        states.append(state)
        if state["state"] not in ("running", "cancelling"):
            return states
        time.sleep(0.005)
    raise AssertionError("the run did not end")


def test_the_count_never_goes_back_over_an_old_journal_resumed_rows_and_two_commands(folder):
    workspace = Workspace(str(folder))
    try:
        # a killed run's rows, as it leaves them: its journal beside a table not yet written
        subprocess.run(
            [
                sys.executable,
                "-m",
                "dentopo",
                "-o",
                workspace.table,
                "--",
                "saddle.ply",
                "tooth.ply",
            ],
            cwd=folder,
            check=True,
            capture_output=True,
            env={**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)},
        )
        rows = read_table(workspace.table)
        os.unlink(workspace.table)
        with Journal(journal_path(workspace.table)) as journal:
            for row in rows:
                journal.append(row)
        # a mesh with a protocol of its own: two commands into one table
        workspace.save_protocol("mesh", "sphere.ply", {"faces": 500})
        run = workspace.start_run({"metrics": ["ariadne"], "jobs": 1, "prepare": True})
        assert len(workspace.run.commands) == 2
        states = [run, *follow(workspace)]
        counts = [s["done"] for s in states]
        assert counts == sorted(counts), counts  # never backwards
        assert counts[0] == 2  # the killed run's rows are reused: counted from the start
        assert counts[-1] == 4 and states[-1]["state"] == "done", states[-1]
        assert {f["status"] for f in states[-1]["files"].values()} == {"ok"}
        serials = [s["serial"] for s in states]
        assert serials == sorted(serials) and len(set(serials)) == len(serials)
        assert len({s["run"] for s in states}) == 1
        # a second run: its own number, and every row reused at once
        states = [workspace.start_run({"metrics": ["ariadne"], "jobs": 1, "prepare": True})]
        states += follow(workspace)
        assert {s["run"] for s in states} == {states[0]["run"]} != {run["run"]}
        assert [s["done"] for s in states] == [4] * len(states)
    finally:
        workspace.close()


def test_rows_once_seen_stay_and_an_earlier_run_s_journal_is_not_this_run_s():
    class Running:
        state, log, exit_code, command, compiling = "running", [], None, "", None

        def running(self):
            return True

    old = {"file": "b.ply", "status": "ok", "seconds": 1.0}
    progress = RunProgress(["a.ply", "b.ply", "c.ply"], {"c.ply": {"file": "c.ply"}}, [old])
    job = Running()
    assert progress.state(job)["done"] == 1  # c.ply: reused
    progress.see([old])  # the old journal, not yet folded into the table
    assert progress.state(job)["done"] == 1
    progress.see([{"file": "a.ply", "status": "ok"}, {"file": "elsewhere.ply"}])
    assert progress.state(job)["done"] == 2
    progress.see([])  # the journal gone (the table written, not yet read)
    state = progress.state(job)
    assert state["done"] == 2 and state["files"]["a.ply"]["status"] == "ok"
    progress.see([{**old, "seconds": 2.0}], final=True)  # b.ply computed by this run
    assert progress.state(job)["done"] == 3


def fake_command(monkeypatch, tmp_path, lines_before, lines_after):
    """The command replaced by a script: `lines_before` on stderr, a wait for a flag file, then
    `lines_after` and a short wait (so that the run is still going when they are read)."""
    flag = tmp_path / "go"
    script = (
        "import os, sys, time\n"
        f"for line in {lines_before!r}: print(line, file=sys.stderr, flush=True)\n"
        f"while not os.path.exists({str(flag)!r}): time.sleep(0.02)\n"
        f"for line in {lines_after!r}: print(line, file=sys.stderr, flush=True)\n"
        "time.sleep(1.5)\n"
    )
    monkeypatch.setattr(_jobs, "dentopo_command", lambda arguments: [sys.executable, "-c", script])
    return flag


def wait_for(check, seconds=30):
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        value = check()
        if value:
            return value
        time.sleep(0.02)
    raise AssertionError("timed out")


@pytest.mark.parametrize(
    "after",
    [
        "dentopo: [1/4] saddle.ply: ok (0.12 s)",  # a file done: the kernels are compiled
        "dentopo: compiled dentopo's kernels in 31 s",  # said to be over, in whatever words
    ],
)
def test_the_compile_wait_shows_in_the_progress_until_it_is_over(
    folder, tmp_path, monkeypatch, after
):
    notice = "dentopo: " + notice_text(["ariadne"])  # the command's own line
    flag = fake_command(
        monkeypatch, tmp_path, [notice, "dentopo: saddle.ply: sign (3.1 s)"], [after]
    )
    workspace = Workspace(str(folder))
    try:
        workspace.start_run({"metrics": ["ariadne"], "jobs": 1})
        state = wait_for(lambda: (s := workspace.run_state())["compiling"] and s)
        assert state["compiling"]["message"] == notice.removeprefix("dentopo: ")
        assert state["compiling"]["seconds"] >= 0 and state["done"] == 0
        time.sleep(1.1)
        assert workspace.run_state()["compiling"]["seconds"] >= 1  # the phase line kept it
        flag.write_text("go")
        wait_for(lambda: "compiled" in after or after in workspace.run.log)
        wait_for(lambda: workspace.run_state()["compiling"] is None)
        assert workspace.run.running()  # over while the command still runs
    finally:
        workspace.close()


def test_the_output_folder_is_chosen_inside_the_folder_only(folder, tmp_path):
    outside = tmp_path / "outside"
    outside.mkdir()
    os.symlink(outside, folder / "link-out")
    workspace = Workspace(str(folder))
    try:
        first = workspace.output
        state = workspace.choose_output("results/first try")
        chosen = os.path.realpath(folder / "results" / "first try")
        assert state["output"] == chosen and state["output_relative"] == "results/first try"
        assert state["table"] == os.path.join(chosen, "results.csv")
        assert os.path.exists(os.path.join(chosen, ".dentopo-output"))  # skipped as scans
        assert sorted(m["path"] for m in state["meshes"]) == sorted(
            ["saddle.ply", "sphere.ply", "tooth.ply", "sub/tooth2.ply"]
        )
        refused = {
            "../elsewhere": 403,
            "/tmp/elsewhere": 403,
            "results/../../elsewhere": 403,
            "link-out": 403,  # a symlink out of the folder
            "link-out/deeper": 403,
            "": 403,
            ".": 403,
            "a\x00b": 403,
            "a\\..\\b": 403,
            "sub": 400,  # holds meshes of the folder
            "tooth.ply": 400,  # a file
        }
        for path, status in refused.items():
            with pytest.raises(AppError) as caught:
                workspace.choose_output(path)
            assert caught.value.status == status, (path, str(caught.value))
            assert workspace.output == chosen
        assert not os.listdir(outside)
        with pytest.raises(AppError, match="must be a text"):
            workspace.choose_output(["results"])
        back = workspace.choose_output("dentopo-app")
        assert back["output"] == first
    finally:
        workspace.close()


def test_the_output_folder_cannot_change_while_a_run_goes(folder, tmp_path, monkeypatch):
    flag = fake_command(monkeypatch, tmp_path, ["dentopo: working"], [])
    workspace = Workspace(str(folder))
    try:
        workspace.start_run({"metrics": ["ariadne"], "jobs": 1})
        with pytest.raises(AppError) as caught:
            workspace.choose_output("elsewhere")
        assert caught.value.status == 409
        flag.write_text("go")
        workspace.run.wait(30)
        assert workspace.choose_output("elsewhere")["output_relative"] == "elsewhere"
        assert workspace.run_state()["state"] == "idle"  # the run was the other folder's
    finally:
        workspace.close()
