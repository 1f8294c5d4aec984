"""Progress on stderr and the summary table on stdout: rich on a terminal, plain otherwise.

The terminal is real where it matters: the command runs in a subprocess whose
stderr (and, for the table, stdout) is a pseudo-terminal.
"""

from __future__ import annotations

import io
import os
import re
import select
import subprocess
import sys
from pathlib import Path

import pytest
import trimesh

import dentopo
from dentopo.cli import _progress, main
from dentopo.cli._progress import Progress
from dentopo.cli._table import TABLE_COLUMNS, plain_table, print_table

rich_console = pytest.importorskip("rich.console", reason="rich is a core dependency")

SOURCE = Path(dentopo.__file__).resolve().parent.parent
ESCAPE = "\x1b"
BOX = re.compile("[\u2500-\u257f]")  # box-drawing characters


def ok_record(file, seconds=0.12):
    record = dict.fromkeys(TABLE_COLUMNS)
    record.update(file=file, dne=0.25, vertices=100, faces=196, seconds=seconds, status="ok")
    return record


def error_record(file, reason):
    record = dict.fromkeys(TABLE_COLUMNS)
    record.update(file=file, seconds=0.01, status="error", error=reason)
    return record


def terminal(width=120):
    return rich_console.Console(file=io.StringIO(), force_terminal=True, width=width)


# --- not a terminal (pytest captures both streams)


def test_plain_progress_lines_and_a_plain_table(capsys):
    assert main(["--samples"]) == 0
    out, err = capsys.readouterr()
    assert ESCAPE not in out and ESCAPE not in err
    assert not BOX.search(out) and not BOX.search(err)
    lines = out.splitlines()
    assert lines[0].split() == list(TABLE_COLUMNS)
    assert len(lines) == 4 and all(line.split()[-1] == "ok" for line in lines[1:])
    # numbers right-aligned: every line's dne ends where the header's does
    end = lines[0].index("dne") + len("dne")
    assert all(line[end - 1] != " " and line[end] == " " for line in lines)
    progress = [line for line in err.splitlines() if re.match(r"dentopo: \[\d/3\] ", line)]
    assert [line[len("dentopo: ") :][:5] for line in progress] == ["[1/3]", "[2/3]", "[3/3]"]
    assert all(line.endswith(" s)") and ": ok (" in line for line in progress)


def test_quiet_keeps_errors_on_stderr_and_results_on_stdout(tmp_path, capsys):
    good = tmp_path / "good.ply"
    trimesh.creation.icosphere(subdivisions=2).export(good)
    bad = tmp_path / "bad.ply"
    bad.write_text("not a mesh")
    assert main([str(good), str(bad), "-q"]) == 1
    out, err = capsys.readouterr()
    [line] = err.splitlines()  # only the problem, no progress
    assert line.startswith(f"dentopo: {bad}: error: ")
    rows = out.splitlines()[1:]
    assert [row.split()[0] for row in rows] == [str(bad), str(good)]
    assert "error" in rows[0] and rows[1].split()[-1] == "ok"


def test_phases_of_a_slow_mesh_are_plain_lines(capsys, monkeypatch):
    monkeypatch.setattr(_progress, "SLOW_MESH_SECONDS", 0.0)
    progress = Progress(1, quiet=False)
    assert not progress.tty  # stderr is captured: not a terminal
    for phase in ("prepare", "kernel"):
        progress.phase("scan/crown.ply", phase)
    progress.update(ok_record("scan/crown.ply"))
    progress.close()
    err = capsys.readouterr().err
    assert err.splitlines() == [
        "dentopo: scan/crown.ply: prepare (0.0 s)",
        "dentopo: scan/crown.ply: kernel (0.0 s)",
        "dentopo: [1/1] scan/crown.ply: ok (0.12 s)",
    ]


# --- on a terminal: a rich console forced to be one


def test_the_bar_shows_done_total_rate_time_left_and_the_current_phase():
    console = terminal()
    progress = Progress(2, quiet=False, console=console)
    assert progress.tty
    progress.phase("scans/[lower] m1.ply", "kernel")
    progress._bar.refresh()
    shown = console.file.getvalue()
    assert "0/2" in shown and "[lower] m1.ply: kernel (" in shown
    assert "-- meshes/s" in shown and "-:--:-- left" in shown
    progress.update(ok_record("scans/[lower] m1.ply"))
    progress._bar.refresh()
    shown = console.file.getvalue()
    assert (
        "1/2" in shown
        and re.search(r"\d meshes/s", shown)
        and re.search(r"\d:\d\d:\d\d left", shown)
    )
    progress.message("scans/m2.ply: warning: 3 vertices have few neighbours")
    progress.update(error_record("scans/m2.ply", "unreadable: not a mesh"))
    progress.close()
    progress.close()  # twice is harmless
    shown = console.file.getvalue()
    assert "2/2" in shown and ESCAPE in shown
    assert "dentopo: scans/m2.ply: warning: 3 vertices have few neighbours" in shown
    assert "dentopo: scans/m2.ply: error: unreadable: not a mesh" in shown


def test_quiet_on_a_terminal_draws_no_bar_but_shows_problems():
    console = terminal()
    progress = Progress(2, quiet=True, console=console)
    progress.phase("a.ply", "kernel")
    progress.update(ok_record("a.ply"))
    progress.update(error_record("b.ply", "file not found"))
    progress.close()
    shown = console.file.getvalue()
    assert "/2" not in shown and "meshes/s" not in shown
    assert "dentopo: b.ply: error: file not found" in shown


def test_tables_plain_and_rich():
    records = [ok_record("/data/scans/a.ply"), error_record("/data/scans/sub/b.ply", "bad")]
    plain = plain_table(records)
    assert not BOX.search(plain) and ESCAPE not in plain
    assert plain.splitlines()[1].split()[0] == "/data/scans/a.ply"  # full paths for scripts
    stream = io.StringIO()
    print_table(records, file=stream)  # not a terminal: plain
    assert stream.getvalue() == plain
    console = terminal()
    print_table(records, console=console)
    shown = console.file.getvalue()
    assert BOX.search(shown) and ESCAPE in shown
    assert f"in {os.sep}data{os.sep}scans{os.sep}" in shown  # the common directory, once
    assert "a.ply" in shown and f"sub{os.sep}b.ply" in shown and "0.25" in shown
    assert "error" in shown and "bad" in shown


def test_a_narrow_terminal_never_cuts_numbers():
    records = [ok_record("a.ply") | {"dne": 0.00296938, "positive_dne": 4.98758e-05}]
    console = terminal(width=60)
    print_table(records, console=console)
    shown = console.file.getvalue()
    assert "0.00296938" in shown and "4.98758e-05" in shown and "\u2026" not in shown


# --- the command on a pseudo-terminal


def run_on_terminal(args, *, stdout_tty: bool):
    """Run ``python -m dentopo ARGS`` with stderr (and maybe stdout) on a pseudo-terminal."""
    import pty

    err_master, err_slave = pty.openpty()
    if stdout_tty:
        out_master, out_slave = pty.openpty()
    else:
        out_master, out_slave = os.pipe()
    env = {
        k: v
        for k, v in os.environ.items()
        if k not in ("NO_COLOR", "FORCE_COLOR", "TTY_COMPATIBLE", "TTY_INTERACTIVE", "TERM")
    }
    env.update(PYTHONPATH=str(SOURCE), COLUMNS="160", LINES="40", TERM="xterm-256color")
    process = subprocess.Popen(
        [sys.executable, "-m", "dentopo", *args],
        stdin=subprocess.DEVNULL,
        stdout=out_slave,
        stderr=err_slave,
        env=env,
    )
    os.close(err_slave)
    os.close(out_slave)
    data = {err_master: b"", out_master: b""}
    reading = set(data)
    while reading:
        ready, _, _ = select.select(list(reading), [], [], 120)
        if not ready:
            process.kill()
            break
        for fd in ready:
            try:
                chunk = os.read(fd, 65536)
            except OSError:  # a pty whose other end is closed
                chunk = b""
            if chunk:
                data[fd] += chunk
            else:
                reading.discard(fd)
    code = process.wait(timeout=60)
    for fd in data:
        os.close(fd)
    return code, data[out_master].decode(), data[err_master].decode()


@pytest.mark.skipif(sys.platform.startswith("win"), reason="pseudo-terminals are POSIX")
def test_the_command_on_a_terminal_draws_a_bar_and_keeps_stdout_plain_when_piped():
    code, out, err = run_on_terminal(["--samples"], stdout_tty=False)
    assert code == 0, err
    assert "3/3" in err and "meshes/s" in err and ESCAPE in err  # the bar, drawn by rich
    assert "[1/3]" not in err  # not the plain lines
    assert ESCAPE not in out and not BOX.search(out)  # results only, parseable
    lines = out.splitlines()
    assert lines[0].split()[:4] == ["file", "dne", "positive_dne", "negative_dne"]
    assert len(lines) == 4 and all(line.split()[-1] == "ok" for line in lines[1:])


@pytest.mark.skipif(sys.platform.startswith("win"), reason="pseudo-terminals are POSIX")
def test_the_command_on_a_terminal_prints_a_rich_table():
    code, out, err = run_on_terminal(["--samples"], stdout_tty=True)
    assert code == 0, err
    assert BOX.search(out) and "positive_dne" in out
    assert all(name in out for name in ("saddle.ply", "sphere.ply", "tooth.ply"))
    samples = Path(dentopo.__file__).parent / "samples"
    assert f"in {samples}{os.sep}" in out
    assert "3/3" in err and "meshes/s" in err
