"""Worker processes start from a plain script, and say why when they cannot.

``spawn`` runs a script's top level again in each child (as ``__mp_main__``), so a
script that called the library without an ``if __name__ == "__main__":`` guard
re-ran itself in every worker, each of which failed to start: the report came
out without a picture, "out of memory?" on every row, and exit status 0.  The
scripts here are real files run by a fresh interpreter, as a reader runs them.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from dentopo.batch import run_pool
from dentopo.report._fields import POOL_FROM
from dentopo.samples import tooth

ROOT = Path(__file__).resolve().parents[1]


def _run_script(directory: Path, code: str) -> subprocess.CompletedProcess:
    script = directory / "script.py"
    script.write_text(textwrap.dedent(code), encoding="utf-8")
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"), MPLBACKEND="Agg")
    for name in ("DISPLAY", "WAYLAND_DISPLAY", "DENTOPO_SCHEDULER"):
        env.pop(name, None)
    return subprocess.run(
        [sys.executable, str(script)],
        cwd=directory,
        env=env,
        stdin=subprocess.DEVNULL,
        capture_output=True,
        text=True,
        timeout=600,
    )


def test_a_script_without_a_main_guard_computes_and_reports_on_workers_running_once(tmp_path):
    pytest.importorskip("plotly", reason="the report needs the report extra (plotly)")
    pytest.importorskip("pyvista", reason="the report's thumbnails need the viz extra (pyvista)")
    mesh = tooth()
    for k in range(POOL_FROM):  # enough files for the report's workers
        mesh.export(tmp_path / f"crown{k:02d}.ply")
    done = _run_script(
        tmp_path,
        """
        import glob, json
        from dentopo import compute_batch, write_report

        with open("top-level-runs.txt", "a") as log:  # once per run of this top level
            log.write("ran\\n")
        records = compute_batch(sorted(glob.glob("crown*.ply")), jobs=2)
        summary = write_report(records, "report.html", jobs=2)
        statuses = [r["status"] for r in records]
        print(json.dumps([statuses, summary.pictured, summary.problems]))
        """,
    )
    assert done.returncode == 0, done.stderr[-3000:]
    assert "Traceback" not in done.stderr, done.stderr[-3000:]
    assert (tmp_path / "top-level-runs.txt").read_text() == "ran\n"  # no worker ran it again
    statuses, pictured, problems = json.loads(done.stdout.strip().splitlines()[-1])
    assert statuses == ["ok"] * POOL_FROM
    assert (pictured, problems) == (POOL_FROM, {})


def _fails_on_negative(value: int) -> int:
    if value < 0:
        raise ValueError(f"negative value {value}")
    return value * 10


def _keep(task, reason, seconds):
    return ("failed", task, reason)


def test_an_exception_in_a_worker_names_its_cause_and_the_worker_goes_on():
    results = list(run_pool([1, -2, 3, 4], _fails_on_negative, (), workers=2, failed=_keep))
    failures = [r for r in results if isinstance(r, tuple)]
    assert sorted(r for r in results if not isinstance(r, tuple)) == [10, 30, 40]
    assert failures == [("failed", -2, "the worker process failed: ValueError: negative value -2")]


def test_a_worker_that_cannot_start_says_why_and_no_other_is_started(tmp_path, monkeypatch):
    (tmp_path / "only_here.py").write_text("def square(x):\n    return x * x\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    import only_here  # importable here, not in the workers once its folder leaves the path

    monkeypatch.setattr(sys, "path", [p for p in sys.path if p != str(tmp_path)])
    try:
        results = list(run_pool(range(6), only_here.square, (), workers=2, failed=_keep))
    finally:
        sys.modules.pop("only_here", None)
    assert sorted(task for _, task, _ in results) == list(range(6))
    reasons = {reason for _, _, reason in results}
    assert reasons == {
        "the worker process could not start: ModuleNotFoundError: No module named 'only_here'"
    }
