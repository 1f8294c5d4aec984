"""Killed processes: a dead worker costs only its file; a killed run loses only what was in flight.

Before the fix a worker killed by the out-of-memory killer broke the whole pool
(every unfinished file failed), the workers outlived a killed parent, and a
killed run lost every row it had finished (the table was only written at the
end).
"""

from __future__ import annotations

import csv
import json
import os
import signal
import time

import pytest

from dentopo import ariaDNE
from faults.live import alive, environment, needs_proc, start, write_tooth

EXACT = ("--method", "exact")


def rows(path):
    with open(path, newline="", encoding="utf-8") as stream:
        return {os.path.basename(r["file"]): r for r in csv.DictReader(stream)}


def test_a_killed_worker_costs_only_the_file_it_held(tmp_path):
    names = [f"{letter}.ply" for letter in "abcdef"]
    for name in names:
        write_tooth(tmp_path / name, 12)
    out = tmp_path / "out.csv"
    env = environment(DENTOPO_TEST_KILL_WORKER_ON="c.ply")  # the worker dies of SIGKILL there
    ran = start(str(tmp_path), "-j", "2", "-o", str(out), env=env).finish()
    assert ran.returncode == 1, ran.describe()
    assert "Traceback" not in ran.stderr, ran.describe()
    table = rows(out)
    assert sorted(table) == names
    assert table["c.ply"]["status"] == "error"
    assert table["c.ply"]["error"] == "worker process killed by SIGKILL (out of memory?)"
    for name in names:
        if name != "c.ply":  # the others went on, in the worker that replaced it too
            assert table[name]["status"] == "ok", table[name]
            assert float(table[name]["dne"]) == ariaDNE(str(tmp_path / name)).dne


def test_workers_die_with_their_parent(tmp_path):
    needs_proc()
    for name in ("a.ply", "b.ply"):
        write_tooth(tmp_path / name, 150)  # seconds of kernel each
    run = start(str(tmp_path), *EXACT, "-j", "2", "-o", str(tmp_path / "out.csv"))
    workers = []
    try:
        deadline = time.monotonic() + 20
        while len(run.workers()) < 2 and time.monotonic() < deadline:
            time.sleep(0.1)
        workers = run.workers()
        assert len(workers) == 2, run.describe()
        time.sleep(4.0)  # imported, reading or in the kernel
        run.send(signal.SIGKILL)
        run.finish()
        deadline = time.monotonic() + 5
        while any(alive(pid) for pid in workers) and time.monotonic() < deadline:
            time.sleep(0.1)
        assert not [pid for pid in workers if alive(pid)]
    finally:
        run.kill()
        for pid in workers:  # orphans are no longer the run's children
            if alive(pid):
                os.kill(pid, signal.SIGKILL)


@pytest.mark.parametrize("jobs", ["1", "2"])
def test_a_killed_run_keeps_its_finished_rows_for_resume(tmp_path, jobs):
    for name in ("a.ply", "b.ply", "c.ply"):
        write_tooth(tmp_path / name, 20)
    write_tooth(tmp_path / "d.ply", 100)  # seconds: killed while it runs
    out = tmp_path / "out.csv"
    journal = tmp_path / "out.csv.partial.jsonl"
    run = start(str(tmp_path), *EXACT, "-j", jobs, "-o", str(out))
    try:
        run.wait_for(r"\[3/4\] .*: ok")
        run.send(signal.SIGKILL)
        assert run.finish().returncode == -signal.SIGKILL
    finally:
        run.kill()
    assert not out.exists()  # the table is written at the end...
    header, *lines = journal.read_text().splitlines()
    assert json.loads(header) == {"journal": "dentopo", "version": 1}  # what the file is
    kept = [json.loads(line) for line in lines]
    done = [str(tmp_path / name) for name in ("a.ply", "b.ply", "c.ply")]
    assert sorted(row["file"] for row in kept) == done

    again = start(str(tmp_path), *EXACT, "-o", str(out), "--resume").finish()
    assert again.returncode == 0, again.describe()
    assert "added 3 rows of an earlier run" in again.stderr
    assert "resuming: 3 of 4 files already done" in again.stderr
    assert "waiting" not in again.stderr  # the killed run's lock went with it
    table = rows(out)
    assert sorted(table) == ["a.ply", "b.ply", "c.ply", "d.ply"]
    for row in kept:  # ...from the rows kept as they finished, not computed again
        assert table[os.path.basename(row["file"])]["seconds"] == repr(row["seconds"])
    assert table["d.ply"]["status"] == "ok"
    assert not journal.exists()
