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
from dentopo.batch import _task, _warmup, make_settings
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


NOTICE = "compiling dentopo's kernels for this machine"


def _notices(err: str) -> list[str]:
    return [line for line in err.splitlines() if NOTICE in line]


@pytest.fixture
def no_stamps(tmp_path, monkeypatch):
    """Stamps kept in a folder of the test's: none at first, as on a fresh install."""
    folder = tmp_path / "numba-cache"
    folder.mkdir()
    monkeypatch.setattr(_warmup, "_stamp_root", lambda: str(folder))
    return folder


def _compiling_first_calls(monkeypatch, calls: int, compilations: int = 2, pause: float = 0.05):
    """measure_mesh that 'compiles' in its first `calls` calls only."""
    real = _task.measure_mesh
    count = [0]

    def measure(*args, **kwargs):
        count[0] += 1
        if count[0] <= calls:
            for _ in range(compilations):
                with event.trigger_event("numba:compile", data={"dispatcher": None, "args": ()}):
                    time.sleep(pause)
        return real(*args, **kwargs)

    monkeypatch.setattr(_task, "measure_mesh", measure)


def test_a_cold_run_compiles_on_the_sample_first_and_says_when_done(
    tooth, no_stamps, monkeypatch, tmp_path, capsys
):
    _compiling_first_calls(monkeypatch, calls=1)  # the sample crown's measurement
    monkeypatch.chdir(tmp_path)
    assert main([tooth, "-o", "t.csv"]) == 0
    lines = capsys.readouterr().err.splitlines()
    [notice] = _notices("\n".join(lines))
    assert notice == "dentopo: " + _compiling.notice_text(["ariadne"])
    [done] = [line for line in lines if line.startswith("dentopo: compiled in ")]
    assert "numba's cache" in done
    row = next(i for i, line in enumerate(lines) if "[1/1]" in line)
    assert lines.index(notice) < lines.index(done) < row  # before the first mesh
    assert not [line for line in lines if _compiling.MORE in line]  # the mesh compiled nothing


def test_a_second_run_finds_the_stamps_and_says_nothing(tooth, no_stamps, monkeypatch, tmp_path):
    monkeypatch.chdir(tmp_path)
    assert main([tooth, "-o", "t.csv"]) == 0
    assert _warmup.missing_metrics(_warmup.Settings()) == ()
    assert list((no_stamps / "dentopo-warm").iterdir())  # the stamp of ariadne


def test_the_second_run_says_nothing(tooth, no_stamps, monkeypatch, tmp_path, capsys):
    monkeypatch.chdir(tmp_path)
    assert main([tooth, "-o", "t.csv"]) == 0
    capsys.readouterr()
    _compiling_first_calls(monkeypatch, calls=0)
    assert main([tooth, "-o", "t.csv"]) == 0
    err = capsys.readouterr().err
    assert _notices(err) == []
    assert "compiled" not in err


def test_a_mesh_that_compiles_after_the_sample_is_named(
    tooth, no_stamps, monkeypatch, tmp_path, capsys
):
    monkeypatch.chdir(tmp_path)
    assert main([tooth, "-o", "t.csv"]) == 0  # the stamps written
    capsys.readouterr()
    _compiling_first_calls(monkeypatch, calls=1, compilations=2, pause=0.3)  # the mesh's
    assert main([tooth, "-o", "t.csv"]) == 0
    lines = capsys.readouterr().err.splitlines()
    assert lines.count("dentopo: " + _compiling.MORE) == 1
    [after] = [line for line in lines if "compiled kernels for" in line]
    assert after.startswith(f"dentopo: {tooth}: compiled kernels for 0.6 s")


def test_quiet_keeps_the_lines_out(tooth, no_stamps, monkeypatch, tmp_path, capsys):
    _compiling_first_calls(monkeypatch, calls=2)
    monkeypatch.chdir(tmp_path)
    assert main([tooth, "-o", "t.csv", "-q"]) == 0
    err = capsys.readouterr().err
    assert _notices(err) == []
    assert "compiled" not in err


def test_the_warmup_command_compiles_once_then_says_where(no_stamps, capsys):
    assert main(["warmup", "--metrics", "opcr"]) == 0
    first = capsys.readouterr().err
    assert "numba's cache" in first
    assert main(["warmup", "--metrics", "opcr"]) == 0
    second = capsys.readouterr().err
    assert "are compiled for this machine" in second
    assert _notices(second) == []


def test_the_warmup_command_takes_no_mesh_files(capsys):
    assert main(["warmup", "tooth.ply"]) == 2
    assert "not mesh files" in capsys.readouterr().err


@pytest.mark.slow
def test_a_warm_up_in_processes_shares_the_metrics_and_stamps_them(no_stamps):
    settings = make_settings(metrics="ariadne,opcr,pcv")
    warm = _warmup.warm_up(settings, jobs=2)
    assert warm.processes == 2
    assert _warmup.missing_metrics(settings) == ()
    again = _warmup.warm_up(settings, jobs=2)
    assert again.processes == 0  # the stamps found: nothing started
    assert again.compiled == 0.0


def test_the_listener_is_removed_after_the_run(tooth, monkeypatch, tmp_path, capsys):
    monkeypatch.chdir(tmp_path)
    assert main([tooth, "-o", "t.csv"]) == 0
    capsys.readouterr()
    with event.trigger_event("numba:compile", data={}):  # after the command: nobody says it
        pass
    assert capsys.readouterr().err == ""


def test_the_estimate_grows_with_the_metrics_asked_for():
    default = _warmup.estimated_seconds(["ariadne"])
    molar = _warmup.estimated_seconds(["ariadne", "slope"])
    everything = _warmup.estimated_seconds(check_metrics("all"))
    assert 0 < default < molar < everything
    assert _warmup.estimated_seconds(check_metrics("all"), 2) < everything  # shared by two
    assert _compiling.notice_text(["ariadne"]).endswith(" s")


@pytest.mark.parametrize("processes", [1, 2, 3, 8, 40])
def test_metric_groups_share_every_metric_once(processes):
    metrics = check_metrics("all")
    groups = _warmup.metric_groups(metrics, processes)
    assert 1 <= len(groups) <= processes
    assert sorted(m for group in groups for m in group) == sorted(metrics)
    if processes > 1:
        costs = [sum(_warmup.COMPILE_SECONDS[m] for m in group) for group in groups]
        assert max(costs) < sum(costs)  # shared, not all in one


def test_the_warm_up_extras_run_without_an_error():
    # the warm-up swallows an extra's error (what ran is compiled); a wrong call there would
    # silently leave a kernel to compile in the middle of a batch: run them as they are
    from dentopo.batch import make_settings
    from dentopo.batch._warmup import _large_mesh_paths, _rfi_arcs
    from dentopo.samples import sample_paths

    tooth = str(sample_paths()["tooth"])
    _large_mesh_paths(tooth, make_settings())
    _rfi_arcs(tooth, make_settings(metrics=["rfi"]))
