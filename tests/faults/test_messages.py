"""Failures named for what they are (issue 22, items 11 and 12).

Before the fix ``dentopo x.ply > /dev/full`` ended in a traceback, and with
``2>/dev/full`` the table of ``-o`` was never written; an unexpected exception in
a metric reached the row as a bare ``ZeroDivisionError: float division by zero``
(and one in reading or an ``IndexError`` in a metric lost the whole row); a FIFO
or a device was "empty" (and reading a FIFO could block); coordinates of 1e200
were "degenerate"; a full disk while writing the per-vertex files was
"unreadable", blaming the input.
"""

from __future__ import annotations

import csv
import os
import resource
import signal
import subprocess
import sys
import textwrap

import numpy as np
import pytest

from dentopo.samples import tooth
from faults.harness import TIME_LIMIT, _environment, dentopo, python
from faults.live import start, write_tooth
from plyfile import write_ply


def rows(path):
    with open(path, newline="", encoding="utf-8") as stream:
        return {os.path.basename(r["file"]): r for r in csv.DictReader(stream)}


def needs(path: str) -> None:
    if not os.path.exists(path):
        pytest.skip(f"no {path} here")


def dentopo_into(argv, *, stdout=subprocess.PIPE, stderr=subprocess.PIPE, cwd=None):
    """Run ``python -m dentopo ARGV`` with stdout and stderr sent where asked."""
    done = subprocess.run(
        [sys.executable, "-m", "dentopo", *argv],
        stdout=stdout,
        stderr=stderr,
        cwd=cwd,
        env=_environment(),
        timeout=TIME_LIMIT,
        text=True,
    )
    assert done.returncode >= 0, f"killed by signal {-done.returncode}"
    return done


@pytest.fixture(scope="module")
def mesh(tmp_path_factory):
    return write_tooth(tmp_path_factory.mktemp("mesh") / "a.ply", 10)


# --- item 11: a full stdout or stderr --------------------------------------------------------


def test_a_full_stdout_is_one_line_and_exit_1(mesh):
    needs("/dev/full")
    with open("/dev/full", "w") as full:
        done = dentopo_into([str(mesh)], stdout=full)
    assert done.returncode == 1, done.stderr
    assert "Traceback" not in done.stderr and "Exception ignored" not in done.stderr, done.stderr
    assert done.stderr.strip().splitlines()[-1] == (
        "dentopo: cannot write to stdout: No space left on device"
    )
    with open("/dev/full", "w") as full:  # the table on stdout, and --help, the same
        for argv in ([str(mesh), "-o", "-"], ["--help"], ["--version"]):
            done = dentopo_into(argv, stdout=full)
            assert done.returncode == 1, (argv, done.stderr)
            assert "Traceback" not in done.stderr and "cannot write to stdout" in done.stderr


def test_a_full_stderr_still_writes_the_table(mesh, tmp_path):
    needs("/dev/full")
    out = tmp_path / "t.csv"
    with open("/dev/full", "w") as full:
        done = dentopo_into([str(mesh), "-o", str(out)], stderr=full)
    assert done.returncode == 1  # the messages were lost: not a clean run
    assert rows(out)["a.ply"]["status"] == "ok"
    assert not (tmp_path / "t.csv.partial.jsonl").exists()


# --- item 11: no bare Python message ---------------------------------------------------------


BROKEN = """
import sys
import dentopo.batch._measure as measure
import dentopo.batch._task as task
from dentopo.cli import main

def fail(kind, message=""):
    def broken(*args, **kwargs):
        raise kind(message)
    return broken

measure.rfi = fail(ZeroDivisionError, "float division by zero")
measure.opc = fail(IndexError, "index 7 is out of bounds for axis 0 with size 3")
measure.slope = fail(MemoryError)
real_load = task.load_mesh

def load_mesh(path, **kwargs):
    if path.endswith("b.ply"):
        raise KeyError("vertex")
    return real_load(path, **kwargs)

task.load_mesh = load_mesh
sys.exit(main(sys.argv[1:]))
"""


def test_an_unexpected_exception_is_an_internal_error_naming_the_step(tmp_path):
    a = write_tooth(tmp_path / "a.ply", 10)
    b = write_tooth(tmp_path / "b.ply", 10)
    out = tmp_path / "t.csv"
    metrics = "ariadne,rfi,opc,slope,classic"
    script = tmp_path / "broken.py"
    script.write_text(textwrap.dedent(BROKEN))
    done = subprocess.run(
        [sys.executable, str(script), str(a), str(b), "--metrics", metrics, "-o", str(out)],
        capture_output=True,
        text=True,
        env=_environment(),
        timeout=TIME_LIMIT,
    )
    assert done.returncode == 1, done.stderr
    assert "Traceback" not in done.stderr, done.stderr
    table = rows(out)
    first = table["a.ply"]
    assert first["status"] == "partial"  # the other metrics are kept
    assert first["dne"] and first["classic_dne"]
    error = first["error"]
    assert "internal error in rfi: ZeroDivisionError: float division by zero; please report" in (
        error
    )
    assert "internal error in opc: IndexError: index 7 is out of bounds" in error
    assert error.endswith("; out of memory in slope")
    second = table["b.ply"]  # the run went on past a file whose reading failed
    assert second["status"] == "error"
    assert second["error"] == "internal error in reading: KeyError: 'vertex'; please report"


def test_the_library_names_an_internal_error_and_keeps_its_own_messages():
    from dentopo.batch._errors import failure_reason

    assert failure_reason("rfi", ZeroDivisionError("float division by zero")) == (
        "internal error in rfi: ZeroDivisionError: float division by zero; please report"
    )
    assert failure_reason("rfi", ValueError("alpha adjustment required")) == (
        "alpha adjustment required"
    )
    assert failure_reason("opcr", MemoryError()) == "out of memory in opcr"
    assert failure_reason("classic", np.linalg.LinAlgError("Singular matrix")) == (
        "internal error in classic: LinAlgError: Singular matrix; please report"
    )
    assert failure_reason("slope", FloatingPointError("overflow")).startswith(
        "internal error in slope: FloatingPointError"
    )


# --- item 12: a FIFO, a device ---------------------------------------------------------------


def test_a_fifo_and_a_device_are_not_regular_files_and_never_block(tmp_path, mesh):
    if not hasattr(os, "mkfifo"):
        pytest.skip("no FIFOs here")
    needs("/dev/zero")
    fifo = tmp_path / "pipe.ply"
    os.mkfifo(fifo)
    ran = dentopo(str(fifo), "/dev/zero", str(mesh), "--metrics", "ariadne,slope", timeout=60)
    assert ran.returncode == 1, ran.describe()
    assert "empty" not in ran.stderr, ran.describe()
    assert f"{str(fifo)!r} is not a regular file (a FIFO)" in ran.stderr, ran.describe()
    assert "'/dev/zero' is not a regular file (a character device)" in ran.stderr, ran.describe()
    assert "a.ply: ok" in ran.stderr, ran.describe()
    code = f"""
from dentopo.mesh._ply import read_ply
try:
    read_ply({str(fifo)!r})
except ValueError as exc:
    print(exc)
"""
    ran = python(code, timeout=30)  # the strict reader itself: no wait for a writer
    assert "is not a regular file (a FIFO)" in ran.stdout, ran.describe()


# --- item 12: coordinates whose squares overflow ---------------------------------------------


def test_coordinates_too_large_or_too_small_for_double_precision_are_named(tmp_path):
    crown = tooth(rings=8)
    huge = write_ply(tmp_path / "huge.ply", crown.vertices * 1e200, crown.faces)
    tiny = write_ply(tmp_path / "tiny.ply", crown.vertices * 1e-200, crown.faces)
    ran = dentopo(str(huge), str(tiny), "--metrics", "all", "-o", str(tmp_path / "t.csv"))
    assert ran.returncode == 1, ran.describe()
    table = rows(tmp_path / "t.csv")
    assert table["huge.ply"]["status"] == "error"
    assert "coordinates too large" in table["huge.ply"]["error"]
    assert "overflows double precision" in table["huge.ply"]["error"]
    assert "rescale the mesh" in table["huge.ply"]["error"]
    assert "degenerate" not in table["huge.ply"]["error"]
    assert table["tiny.ply"]["status"] == "error"
    assert "coordinates too small" in table["tiny.ply"]["error"]
    assert "underflows double precision" in table["tiny.ply"]["error"]


def test_the_range_limit_refuses_no_mesh_that_is_measured_right():
    from dentopo import ariaDNE, classic_dne
    from dentopo.mesh._validate import MAX_COORDINATE, MIN_EXTENT

    crown = tooth(rings=6)
    vertices, faces = np.asarray(crown.vertices), np.asarray(crown.faces)
    size = np.ptp(vertices, axis=0).max()
    base, classic = ariaDNE((vertices, faces)).dne, classic_dne((vertices, faces)).dne
    for scale in (0.99 * MAX_COORDINATE / np.abs(vertices).max(), 1.01 * MIN_EXTENT / size):
        scaled = (vertices * scale, faces)
        assert ariaDNE(scaled).dne == pytest.approx(base, rel=1e-9)
        assert classic_dne(scaled).dne == pytest.approx(classic, rel=1e-9)


# --- item 12: a full disk while writing the per-vertex files ---------------------------------


def file_size_limit(size: int):
    def limit():
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (size, size))

    return limit


def test_a_full_disk_for_the_per_vertex_files_blames_the_output_not_the_input(tmp_path):
    mesh = write_tooth(tmp_path / "a.ply", 12)
    out, pv = tmp_path / "t.csv", tmp_path / "pv"
    # the journal and the table fit (about 1 kB), the per-vertex PLY (about 30 kB) does not
    ran = start(
        str(mesh), "-o", str(out), "--per-vertex", str(pv), preexec_fn=file_size_limit(8000)
    )
    ran = ran.finish()
    assert ran.returncode == 1, ran.describe()
    assert "unreadable" not in ran.stderr, ran.describe()
    error = rows(out)["a.ply"]["error"]
    assert error.startswith(f"cannot write the per-vertex file {str(pv / 'a.dentopo.ply')!r}: ")
    assert "File too large" in error and "not the input" in error
