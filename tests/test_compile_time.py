"""A fresh install's compilation: counted apart from a row's seconds, and said once by the command.

numba raises its ``numba:compile`` event only when a kernel is really compiled
(not when it comes from the cache).  Compilations are simulated here by raising
that event around a pause, inside the measurement of a mesh, so that the tests
do not depend on the state of numba's cache; one test compiles a real function.
"""

from __future__ import annotations

import time

import numpy as np
import pytest
from numba import njit
from numba.core import event

from dentopo import compute_batch
from dentopo._jit import compile_seconds
from dentopo.batch import _task
from dentopo.cli import _compiling, main
from dentopo.samples import sample_paths
from dentopo.topography import check_metrics

PAUSE = 0.6  # seconds of simulated compilation


@pytest.fixture(scope="module")
def tooth():
    path = str(sample_paths()["tooth"])
    compute_batch(path)  # the real kernels compiled (or loaded) before anything is timed
    return path


def _compiling_measure(monkeypatch, compilations: int, pause: float = PAUSE):
    """measure_mesh that first 'compiles' `compilations` times for `pause` seconds each."""
    real = _task.measure_mesh

    def measure(*args, **kwargs):
        for _ in range(compilations):
            with event.trigger_event("numba:compile", data={"dispatcher": None, "args": ()}):
                time.sleep(pause)
        return real(*args, **kwargs)

    monkeypatch.setattr(_task, "measure_mesh", measure)


def test_compile_seconds_counts_a_real_compilation_and_not_a_compiled_call():
    def square_plus(x):
        return x * x + 1.0

    kernel = njit(cache=False)(square_plus)  # new: compiled on its first call
    before = compile_seconds()
    started = time.perf_counter()
    assert kernel(np.float64(3.0)) == 10.0
    spent = time.perf_counter() - started
    compiled = compile_seconds() - before
    assert 0.0 < compiled <= spent
    again = compile_seconds()
    assert kernel(np.float64(2.0)) == 5.0  # compiled already: no compilation
    assert compile_seconds() == again


def test_nested_compilations_count_once():
    before = compile_seconds()
    with event.trigger_event("numba:compile", data={}):
        with event.trigger_event("numba:compile", data={}):  # a callee, inside its caller
            time.sleep(0.2)
        time.sleep(0.1)
    compiled = compile_seconds() - before
    assert 0.3 <= compiled < 0.5


def test_a_rows_seconds_leave_out_the_compilation(tooth, monkeypatch):
    [warm] = compute_batch(tooth)
    _compiling_measure(monkeypatch, compilations=2)
    started = time.perf_counter()
    [row] = compute_batch(tooth)
    wall = time.perf_counter() - started
    assert row["status"] == "ok"
    assert wall >= 2 * PAUSE  # the compilations did take their time...
    assert row["seconds"] < wall - 2 * PAUSE + 0.05  # ...but not in the row's seconds
    assert row["dne"] == warm["dne"]


def test_without_a_compilation_the_pause_is_in_the_seconds(tooth, monkeypatch):
    """The control: time that is not compilation stays in ``seconds`` (the test above can fail)."""
    real = _task.measure_mesh

    def slow(*args, **kwargs):
        time.sleep(PAUSE)
        return real(*args, **kwargs)

    monkeypatch.setattr(_task, "measure_mesh", slow)
    [row] = compute_batch(tooth)
    assert row["seconds"] >= PAUSE


NOTICE = "compiling dentopo's kernels for this machine, once: about"


def _notices(err: str) -> list[str]:
    return [line for line in err.splitlines() if NOTICE in line]


def test_the_command_says_once_that_it_compiles(tooth, monkeypatch, tmp_path, capsys):
    _compiling_measure(monkeypatch, compilations=3, pause=0.05)
    monkeypatch.chdir(tmp_path)
    assert main([tooth, "-o", "t.csv"]) == 0
    [line] = _notices(capsys.readouterr().err)
    assert line == "dentopo: " + _compiling.notice_text(["ariadne"])


def test_the_command_says_nothing_when_nothing_compiles(tooth, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main([tooth, "-o", "t.csv"]) == 0  # the kernels are compiled (fixture)
    assert _notices(capsys.readouterr().err) == []


def test_quiet_keeps_the_line_out(tooth, monkeypatch, tmp_path, capsys):
    _compiling_measure(monkeypatch, compilations=1, pause=0.05)
    monkeypatch.chdir(tmp_path)
    assert main([tooth, "-o", "t.csv", "-q"]) == 0
    assert _notices(capsys.readouterr().err) == []


def test_the_listener_is_removed_after_the_run(tooth, monkeypatch, tmp_path, capsys):
    monkeypatch.chdir(tmp_path)
    assert main([tooth, "-o", "t.csv"]) == 0
    capsys.readouterr()
    with event.trigger_event("numba:compile", data={}):  # after the command: nobody says it
        pass
    assert capsys.readouterr().err == ""


def test_the_estimate_grows_with_the_metrics_asked_for():
    default = _compiling.estimated_seconds(["ariadne"])
    molar = _compiling.estimated_seconds(["ariadne", "slope"])
    everything = _compiling.estimated_seconds(check_metrics("all"))
    assert 0 < default < molar < everything
    assert _compiling.notice_text(["ariadne"]).endswith(" s")
