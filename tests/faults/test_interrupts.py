"""Ctrl-C and SIGTERM at any moment: exit 130, one line, the rows done on disk, no traceback.

Each test starts ``dentopo`` in the background, waits for a moment of a mesh
(reported by the test hook ``DENTOPO_TEST_PHASES``, see ``live.py``), sends
the signal there and checks how the run ended.  Before the fix a Ctrl-C while
the ariaDNE kernel ran crashed the process (SIGSEGV: numba boxes the kernel's
results after a pending KeyboardInterrupt and unpacks a NULL), and SIGTERM
killed it without writing a row.
"""

from __future__ import annotations

import csv
import os
import signal
import time

import pytest

from faults.harness import python
from faults.live import alive, environment, start, write_tooth

EXACT = ("--method", "exact")  # the compiled kernel, whatever the number of vertices


@pytest.fixture(scope="module")
def meshes(tmp_path_factory):
    """Small meshes (a, c), one whose kernel runs for seconds (b), and a larger one (big)."""
    folder = tmp_path_factory.mktemp("meshes")
    write_tooth(folder / "a.ply", 20)
    write_tooth(folder / "b.ply", 100)
    write_tooth(folder / "c.ply", 20)
    write_tooth(folder / "big.ply", 150)
    return folder


def rows(path):
    with open(path, newline="", encoding="utf-8") as stream:
        return {os.path.basename(r["file"]): r for r in csv.DictReader(stream)}


def assert_clean_stop(ran, message="interrupted: "):
    assert ran.returncode == 130, ran.describe()
    assert message in ran.stderr, ran.describe()
    assert "Traceback" not in ran.stderr, ran.describe()
    assert "Fatal Python error" not in ran.stderr, ran.describe()


def assert_no_leftovers(out):
    folder = out.parent
    assert not (folder / f"{out.name}.partial.jsonl").exists()  # its rows are in the table
    assert not (folder / f".{out.name}.lock").exists()


def test_ctrl_c_during_the_kernel_stops_cleanly_and_keeps_the_rows_done(meshes, tmp_path):
    out = tmp_path / "out.csv"
    files = [str(meshes / n) for n in ("a.ply", "b.ply", "c.ply")]
    run = start(*files, *EXACT, "-o", str(out), env=environment(DENTOPO_TEST_PHASES="1"))
    run.wait_for(r"b\.ply: kernel")
    time.sleep(0.5)  # well inside the compiled loop (about 3 s)
    run.send(signal.SIGINT)
    ran = run.finish()
    assert_clean_stop(ran, "interrupted: 1 of 3 files done")
    assert "b.ply: bending" not in ran.stderr  # stopped as the kernel returned
    table = rows(out)
    assert list(table) == ["a.ply"] and table["a.ply"]["status"] == "ok"
    assert_no_leftovers(out)


def test_ctrl_c_while_reading_stops_at_once(meshes, tmp_path):
    out = tmp_path / "out.csv"
    files = [str(meshes / n) for n in ("a.ply", "big.ply")]
    run = start(*files, *EXACT, "-o", str(out), env=environment(DENTOPO_TEST_PHASES="1"))
    run.wait_for(r"big\.ply: prepare")
    run.send(signal.SIGINT)
    ran = run.finish()
    assert_clean_stop(ran, "interrupted: 1 of 2 files done")
    assert "big.ply: kernel" not in ran.stderr  # did not wait for the next phase
    assert list(rows(out)) == ["a.ply"]


def test_ctrl_c_during_the_sign_step_stops_cleanly(meshes, tmp_path):
    out = tmp_path / "out.csv"
    files = [str(meshes / n) for n in ("a.ply", "b.ply")]
    run = start(*files, *EXACT, "-o", str(out), env=environment(DENTOPO_TEST_PHASES="1"))
    run.wait_for(r"b\.ply: sign")
    run.send(signal.SIGINT)
    ran = run.finish()
    assert_clean_stop(ran, "interrupted: 1 of 2 files done")
    assert "SystemError" not in ran.stderr  # never a wrong error row instead of stopping
    assert list(rows(out)) == ["a.ply"]


def test_ctrl_c_while_the_table_is_written_still_writes_it_whole(meshes, tmp_path):
    out = tmp_path / "out.csv"
    files = [str(meshes / n) for n in ("a.ply", "c.ply")]
    run = start(*files, "-o", str(out), env=environment(DENTOPO_TEST_SLOW_WRITE="2"))
    run.wait_for("dentopo-test: writing")
    run.send(signal.SIGINT)
    ran = run.finish()
    assert_clean_stop(ran, "interrupted after the table was written")
    table = rows(out)
    assert list(table) == ["a.ply", "c.ply"]
    assert {r["status"] for r in table.values()} == {"ok"}
    assert_no_leftovers(out)


def test_sigterm_ends_like_ctrl_c(meshes, tmp_path):
    out = tmp_path / "out.csv"
    files = [str(meshes / n) for n in ("a.ply", "b.ply", "c.ply")]
    run = start(*files, *EXACT, "-o", str(out))
    run.wait_for(r"\[1/3\] .*a\.ply: ok")
    run.send(signal.SIGTERM)
    ran = run.finish()
    assert_clean_stop(ran, "interrupted (SIGTERM): 1 of 3 files done")
    assert list(rows(out)) == ["a.ply"]
    assert_no_leftovers(out)


def test_ctrl_c_with_workers_stops_them_at_once(meshes, tmp_path):
    out = tmp_path / "out.csv"
    files = [str(meshes / n) for n in ("a.ply", "big.ply", "c.ply")]
    run = start(*files, *EXACT, "-j", "2", "-o", str(out))
    run.wait_for(r"\[2/3\] .*: ok")  # a and c done; big's kernel runs for seconds
    workers = run.workers()
    sent = time.monotonic()
    run.send(signal.SIGINT)
    ran = run.finish()
    assert time.monotonic() - sent < 5.0  # did not wait for big.ply
    assert_clean_stop(ran, "interrupted: 2 of 3 files done")
    assert sorted(rows(out)) == ["a.ply", "c.ply"]
    assert workers and not [pid for pid in workers if alive(pid)]


LIBRARY = """
import os, signal, threading
from dentopo import compute_batch
threading.Timer(1.0, os.kill, (os.getpid(), signal.SIGINT)).start()  # during the kernel
try:
    compute_batch([{path!r}], method="exact")
except KeyboardInterrupt:
    print("KeyboardInterrupt")
"""


def test_compute_batch_raises_keyboard_interrupt_not_a_crash(meshes):
    ran = python(LIBRARY.format(path=str(meshes / "b.ply")))
    assert ran.returncode == 0, ran.describe()
    assert ran.stdout.strip() == "KeyboardInterrupt", ran.describe()
