"""The output table: found unwritable before any work, one writer at a time, a full disk survived.

Before the fix an output that could not be written was only found after every
mesh had been computed, two runs on one table overwrote each other's rows,
and a full disk lost the rows computed (there was no journal).
"""

from __future__ import annotations

import csv
import json
import os
import resource
import signal
import tempfile
import threading

import pytest

from faults.harness import dentopo
from faults.live import start, write_tooth


def read_journal(path):
    from dentopo.formats import read_journal

    return read_journal(path)


def rows(path):
    with open(path, newline="", encoding="utf-8") as stream:
        return {os.path.basename(r["file"]): r for r in csv.DictReader(stream)}


def assert_nothing_computed(ran):
    assert ran.returncode == 2, ran.describe()
    assert "ok (" not in ran.stderr, ran.describe()  # no mesh was computed first
    assert "Traceback" not in ran.stderr, ran.describe()


def unwritable_system_directory() -> str:
    """A directory nobody can create files in, root included (sysfs), or skip."""
    if not os.path.isdir("/sys"):
        pytest.skip("no /sys here: no directory that even root cannot write to")
    try:
        handle, probe = tempfile.mkstemp(dir="/sys")
    except OSError:
        return "/sys"
    os.close(handle)
    os.unlink(probe)
    pytest.skip("/sys is writable here")


def skip_unless_permissions_bind(folder) -> None:
    """Skip where a read-only file can be written anyway (root, with CAP_DAC_OVERRIDE)."""
    probe = folder / "read-only-probe"
    probe.write_text("")
    probe.chmod(0o444)
    try:
        with open(probe, "a"):
            pass
    except PermissionError:
        return
    finally:
        probe.unlink()
    pytest.skip("file permissions do not stop this user from writing (root)")


@pytest.fixture(scope="module")
def mesh(tmp_path_factory):
    return write_tooth(tmp_path_factory.mktemp("mesh") / "a.ply", 12)


# --- an output that cannot be written is found before the first mesh ------------------------


def test_an_output_in_a_directory_nobody_can_write_is_refused_before_computing(mesh):
    ran = dentopo(str(mesh), "-o", os.path.join(unwritable_system_directory(), "dentopo.csv"))
    assert_nothing_computed(ran)
    assert "cannot write --output" in ran.stderr


def test_an_output_below_a_file_is_refused_before_computing(mesh, tmp_path):
    (tmp_path / "notes.txt").write_text("not a directory\n")
    ran = dentopo(str(mesh), "-o", str(tmp_path / "notes.txt" / "out.csv"))
    assert_nothing_computed(ran)
    assert "notes.txt' is not a directory" in ran.stderr


def test_a_per_vertex_directory_that_cannot_be_written_is_refused_before_computing(mesh):
    folder = os.path.join(unwritable_system_directory(), "dentopo-per-vertex")
    ran = dentopo(str(mesh), "--per-vertex", folder)
    assert_nothing_computed(ran)
    assert "--per-vertex" in ran.stderr


def test_a_read_only_output_is_not_replaced(mesh, tmp_path):
    skip_unless_permissions_bind(tmp_path)
    out = tmp_path / "out.csv"
    out.write_text("precious\n")
    out.chmod(0o444)
    ran = dentopo(str(mesh), "-o", str(out))
    assert_nothing_computed(ran)
    assert "read-only" in ran.stderr
    assert out.read_text() == "precious\n"


def test_an_output_directory_without_write_permission_is_refused_before_computing(mesh, tmp_path):
    skip_unless_permissions_bind(tmp_path)
    folder = tmp_path / "locked"
    folder.mkdir()
    folder.chmod(0o555)
    try:
        ran = dentopo(str(mesh), "-o", str(folder / "out.csv"))
    finally:
        folder.chmod(0o755)
    assert_nothing_computed(ran)
    assert "Permission denied" in ran.stderr


# --- two runs on one table -------------------------------------------------------------------


def test_two_runs_on_one_table_take_turns_and_keep_every_row(tmp_path):
    first_files = [write_tooth(tmp_path / n, 20) for n in ("a1.ply", "a2.ply")]
    # about 5 s of exact ariaDNE: the second run must start and find the lock before it ends
    # (at rings=100, 0.9 s, it once started too late while two suites shared two cores)
    first_files.append(write_tooth(tmp_path / "a3.ply", 150))
    second_files = [write_tooth(tmp_path / n, 20) for n in ("b1.ply", "b2.ply")]
    out = str(tmp_path / "out.csv")
    first = start(*map(str, first_files), "--method", "exact", "-o", out, "--resume")
    try:
        first.wait_for(r"\[1/3\] .*: ok")
        second = start(*map(str, second_files), "-o", out, "--resume")
        try:
            line = second.wait_for("is being written by another dentopo run", timeout=20)
            assert f"(pid {first.pid})" in line
            ran_first, ran_second = first.finish(), second.finish()
        finally:
            second.kill()
    finally:
        first.kill()
    assert ran_first.returncode == 0, ran_first.describe()
    assert ran_second.returncode == 0, ran_second.describe()
    table = rows(out)
    assert sorted(table) == ["a1.ply", "a2.ply", "a3.ply", "b1.ply", "b2.ply"]
    assert {row["status"] for row in table.values()} == {"ok"}
    assert not os.path.exists(os.path.join(tmp_path, ".out.csv.lock"))


def test_the_lock_waits_for_its_holder_and_is_removed_after(tmp_path):
    from dentopo.formats import OutputLock, lock_path

    out = tmp_path / "out.csv"
    waited = []
    with OutputLock(out):
        second = OutputLock(out, on_wait=waited.append)
        taker = threading.Thread(target=second.acquire)
        taker.start()
        taker.join(0.5)
        assert taker.is_alive()  # waits while the first holds it
        assert waited == [os.getpid()]  # and was told by whom
    taker.join(5)
    assert not taker.is_alive()
    assert os.path.exists(lock_path(out))
    second.release()
    assert not os.path.exists(lock_path(out))


# --- a full disk -----------------------------------------------------------------------------


def file_size_limit(size: int):
    """A Popen ``preexec_fn``: writes beyond `size` bytes fail with EFBIG, as on a full disk."""

    def limit():
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (size, size))

    return limit


def test_a_full_disk_leaves_the_old_table_and_keeps_the_rows_for_resume(tmp_path):
    for letter in "abcdef":
        write_tooth(tmp_path / f"{letter}.ply", 12)
    out = tmp_path / "out.csv"
    assert dentopo(str(tmp_path), "-o", str(out), "-q").returncode == 0
    before = out.read_bytes()
    write_tooth(tmp_path / "g.ply", 12)

    # the journal's one row fits, the table with seven rows does not
    full = file_size_limit(len(before))
    ran = start(str(tmp_path), "-o", str(out), "--resume", preexec_fn=full).finish()
    assert ran.returncode == 1, ran.describe()
    assert "File too large" in ran.stderr and "left as it was" in ran.stderr, ran.describe()
    assert "Traceback" not in ran.stderr
    assert out.read_bytes() == before
    [kept], _ = read_journal(tmp_path / "out.csv.partial.jsonl")
    assert os.path.basename(kept["file"]) == "g.ply" and kept["status"] == "ok"

    again = dentopo(str(tmp_path), "-o", str(out), "--resume")
    assert again.returncode == 0, again.describe()
    assert "resuming: 7 of 7 files already done" in again.stderr  # g.ply was not lost
    table = rows(out)
    assert sorted(table) == [f"{letter}.ply" for letter in "abcdefg"]
    assert table["g.ply"]["seconds"] == repr(kept["seconds"])
    assert not (tmp_path / "out.csv.partial.jsonl").exists()


def test_a_disk_full_for_the_journal_stops_the_batch_and_keeps_the_old_table(tmp_path):
    for letter in "ab":
        write_tooth(tmp_path / f"{letter}.ply", 12)
    out = tmp_path / "out.csv"
    out.write_text("file,status\nold.ply,ok\n")
    before = out.read_bytes()
    ran = start(str(tmp_path), "-o", str(out), preexec_fn=file_size_limit(100)).finish()
    assert ran.returncode == 1, ran.describe()
    assert "cannot keep the finished rows" in ran.stderr, ran.describe()
    assert "stopped after 1 of 2 files" in ran.stderr  # not all the work for nothing
    assert "Traceback" not in ran.stderr
    assert out.read_bytes() == before


# --- the journal -----------------------------------------------------------------------------


def test_journal_rows_read_back_exactly_and_a_line_cut_short_is_skipped(tmp_path):
    from dentopo.formats import Journal

    path = tmp_path / "out.csv.partial.jsonl"
    first = {"file": "ø/a.ply", "dne": 0.1 + 0.2, "vertices": 12, "status": "ok", "error": None}
    second = {"file": "b.ply", "dne": None, "status": "error", "error": "file not found"}
    with Journal(path) as journal:
        journal.append(first)
    with open(path, "a", encoding="utf-8") as stream:
        stream.write('{"file": "c.ply", "dne": 0.12')  # a kill in the middle of a row
    with Journal(path) as journal:  # the next row starts on a line of its own
        journal.append(second)
    records, skipped = read_journal(path)
    assert skipped == 1
    assert [r["file"] for r in records] == ["ø/a.ply", "b.ply"]
    assert records[0]["dne"] == 0.1 + 0.2 and records[0]["vertices"] == 12
    assert records[1]["status"] == "error" and records[1]["error"] == "file not found"
    assert json.loads(path.read_text(encoding="utf-8").splitlines()[-1]) == second
