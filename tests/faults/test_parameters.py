"""Numeric parameters out of range: a usage error naming the parameter and its range, never a crash.

Every case runs in a subprocess (``faults.harness``): a segmentation fault or a
hang fails the test instead of ending the test run.  ``-b 1e-155`` used to end
in SIGSEGV: ``1 / h**2`` overflowed to inf, ``0 * inf`` (a vertex against
itself) gave NaN, and the NaN indexed the kernel's exponential table far out
of bounds.
"""

from __future__ import annotations

import json

import pytest

from dentopo.samples import sample_paths
from faults.harness import dentopo, python

BANDWIDTH_WORDS = "bandwidth must lie in [1e-50, 1e+50]"
CUTOFF_WORDS = "cutoff must lie in [0, 1)"


@pytest.fixture(scope="module")
def mesh_file() -> str:
    return str(sample_paths()["tooth"])


def _one_line(stderr: str) -> str:
    lines = [line for line in stderr.splitlines() if line.strip()]
    assert len(lines) == 1, stderr
    return lines[0]


#: Runs ``main(argv)`` for each argv in one process and prints the exit codes and
#: what each printed on stderr (a crash in any fails the whole case).
MANY = """
import contextlib, io, json
from dentopo.cli import main
out = []
for argv in {argvs!r}:
    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        code = main(argv)
    out.append([code, err.getvalue()])
print(json.dumps(out))
"""


def _run_many(argvs):
    ran = python(MANY.format(argvs=argvs))
    assert ran.returncode == 0, ran.describe()
    return json.loads(ran.stdout.strip().splitlines()[-1])


#: Calls the library in one process on a small crown and prints what each raised (its
#: ValueError's words, or "no error"), so that a crash in any fails the whole case.
LIBRARY_WORDS = """
import json
from dentopo import {names}
from dentopo.batch import make_settings
from dentopo.samples import tooth
mesh = tooth(rings=6)
words = []
for call in ({calls}):
    try:
        call()
    except ValueError as exc:
        words.append(str(exc))
    else:
        words.append("no error")
print(json.dumps(words))
"""


def _library_words(names: str, calls: list[str]) -> list[str]:
    """What each of `calls` (source, of `names` from dentopo, ``make_settings`` and ``mesh``)
    raised, run by :data:`LIBRARY_WORDS` in a subprocess."""
    lambdas = "".join(f"lambda: {call}, " for call in calls)
    ran = python(LIBRARY_WORDS.format(names=names, calls=lambdas))
    assert ran.returncode == 0, ran.describe()
    return json.loads(ran.stdout)


def test_cli_refuses_the_reported_bandwidth(mesh_file, tmp_path):
    # the command of the report, as a command: it ended in SIGSEGV
    ran = dentopo(mesh_file, "-b", "1e-155", "-o", str(tmp_path / "t.csv"))
    assert ran.returncode == 2, ran.describe()
    line = _one_line(ran.stderr)
    assert line == f"dentopo: {BANDWIDTH_WORDS}; got 1e-155"
    assert not (tmp_path / "t.csv").exists()


BAD_BANDWIDTHS = ["1e-300", "1e-51", "1e51", "1e155", "1e300", "nan", "inf", "-1", "0"]


def test_cli_refuses_bandwidths_out_of_range(mesh_file, tmp_path):
    argvs = [[mesh_file, f"--bandwidth={b}", "-o", str(tmp_path / "t.csv")] for b in BAD_BANDWIDTHS]
    for value, (code, stderr) in zip(BAD_BANDWIDTHS, _run_many(argvs), strict=True):
        assert code == 2, (value, stderr)
        assert BANDWIDTH_WORDS in _one_line(stderr), (value, stderr)
    assert not (tmp_path / "t.csv").exists()


BAD_CUTOFFS = ["nan", "inf", "-0.5", "1", "2", "1e300"]


def test_cli_refuses_cutoffs_out_of_range(mesh_file):
    argvs = [[mesh_file, f"--cutoff={c}", "-o", "-"] for c in BAD_CUTOFFS]
    for value, (code, stderr) in zip(BAD_CUTOFFS, _run_many(argvs), strict=True):
        assert code == 2, (value, stderr)
        assert CUTOFF_WORDS in _one_line(stderr), (value, stderr)


BAD_OTHERS = [
    ["--percentile=nan"],
    ["--percentile=inf"],
    ["--percentile=0"],
    ["--percentile=-5"],
    ["--percentile=1e300"],
    ["--limits", "nan", "1"],
    ["--limits", "-1", "inf"],
    ["--limits", "0.1", "0.3"],  # zero not inside (asymmetric pairs around zero are honoured)
    ["--limits", "1", "-1"],
    ["--jobs=-1"],
]


def test_cli_refuses_other_numbers_out_of_range(mesh_file):
    argvs = [[mesh_file, *options, "-o", "-"] for options in BAD_OTHERS]
    for options, (code, stderr) in zip(BAD_OTHERS, _run_many(argvs), strict=True):
        assert code == 2, (options, stderr)
        _one_line(stderr)


@pytest.mark.parametrize("subcommand", ["sweep", "robustness"])
def test_study_commands_refuse_a_bandwidth_out_of_range(mesh_file, tmp_path, subcommand):
    ran = dentopo(subcommand, mesh_file, "-b", "1e-155", "-o", str(tmp_path), "--no-figures")
    assert ran.returncode == 2, ran.describe()
    assert BANDWIDTH_WORDS in _one_line(ran.stderr)
    assert list(tmp_path.iterdir()) == []


def test_library_raises_the_same_words():
    words = _library_words(
        "ariaDNE",
        [
            "ariaDNE(mesh, bandwidth=1e-155)",
            'ariaDNE(mesh, bandwidth=float("nan"))',
            'ariaDNE(mesh, bandwidth=1e300, method="exact")',
            'ariaDNE(mesh, cutoff=float("inf"))',
            "make_settings(bandwidth=1e-155)",
        ],
    )
    assert [w.startswith(BANDWIDTH_WORDS) for w in words] == [True, True, True, False, True]
    assert words[3].startswith(CUTOFF_WORDS)


def test_the_kernel_never_reads_outside_its_table():
    # the compiled loop itself, given what validation now keeps from it: an
    # infinite 1/h**2 (h = 1e-155) and NaN distances must not crash it
    code = """
import numpy as np
from dentopo.ariadne import _kernel
points = np.random.default_rng(0).normal(size=(300, 3))
points[5] = np.nan
ordered = np.ascontiguousarray(points.T)
runs = (np.array([0, 1]), np.array([0]), np.array([300]))
block_of = np.zeros(300, dtype=np.int64)
for inv_h2 in (np.inf, 1e300, 1.0):
    sums = np.full((300, 10), np.inf)
    parts = np.array([0, 150, 300])
    _kernel._run_sums(*ordered, block_of, *runs, inv_h2, 0.0, 37.21, parts, sums)
    assert (sums[:, 0] != np.inf).all()  # every row written
    # the pairs kernel: one task of all rows, its columns from 0 on
    tasks, offset, width = np.array([0, 300]), np.array([0]), np.array([0, 10 * 300])
    rows, columns = np.zeros((10, 300)), np.zeros(10 * 300)
    _kernel._half_sums(*ordered, block_of, *runs, tasks, offset, width, 0, 1, inv_h2, 0.0,
                       37.21, rows, columns, 0, 1)
    assert (rows[0] >= 1).all()  # every row written, the vertex's own weight 1 first
print("ok")
"""
    ran = python(code)
    assert ran.returncode == 0, ran.describe()
    assert ran.stdout.strip() == "ok"


ENDS_OPTIONS = [
    ["--method", "exact"],
    ["-d", "geodesic", "-c", "0.5"],
    ["--sign-method", "winding", "-c", "5e-324"],
    ["--sign-method", "gaussian_curvature"],
]


def test_the_ends_of_the_range_compute(mesh_file, tmp_path):
    cases = [(b, options) for b in ("1e-50", "1e50") for options in ENDS_OPTIONS]
    tables = [tmp_path / f"{k}.csv" for k in range(len(cases))]
    argvs = [
        [mesh_file, "-b", b, *options, "-q", "-o", str(table)]
        for (b, options), table in zip(cases, tables, strict=True)
    ]
    for case, table, (code, stderr) in zip(cases, tables, _run_many(argvs), strict=True):
        assert code == 0, (case, stderr)
        header, row = (line.split(",") for line in table.read_text().splitlines()[:2])
        assert row[header.index("status")] == "ok", (case, row)
        assert 0 <= float(row[header.index("dne")]) < 1e3, (
            case,
            row,
        )  # no more than a surface bends


def test_fast_method_at_the_ends_of_the_range():
    # h = 1e-50: every vertex alone (each one summed exactly: weight 1); h = 1e50:
    # every weight 1 (the raw sums, not the derivatives, which cancel there)
    code = """
import numpy as np
from dentopo.ariadne import _fastgauss
from dentopo.mesh import prepare
from dentopo.samples import tooth
points = prepare(tooth(rings=10)).points
alone = _fastgauss.fast_euclidean_moments(points, 1e-50)
assert np.array_equal(alone.weight, np.ones(len(points)))
assert not alone.first.any() and not alone.second.any()
every = _fastgauss.fast_euclidean_moments(points, 1e50)
assert np.allclose(every.weight, len(points), rtol=1e-9, atol=0)
spread = ((points - points.mean(axis=0)) ** 2).sum()
trace = np.trace(every.covariance, axis1=1, axis2=2) * len(points)
assert np.allclose(trace, spread + len(points) * ((points - points.mean(axis=0)) ** 2).sum(1))
print("ok")
"""
    pytest.importorskip("finufft")
    ran = python(code)
    assert ran.returncode == 0, ran.describe()
    assert ran.stdout.strip() == "ok"


#: Topography options out of range, each with the words of its one line (the option's name
#: and its range).  ``--dne-outliers 100`` used to be accepted and gave classic DNE 0.0 as ok,
#: a step of 0 eight identical OPCR rotations, and 1e8 steps a table of 1e8 columns.
OUTLIERS_WORDS = "dne_outliers is a percentage and must lie in [0, 50]"
STEPS_WORDS = "opcr_steps must lie in [1, 360]"
STEP_WORDS = "opcr_step must lie in (0, 360 / opcr_steps] degrees"
BAD_TOPOGRAPHY = [
    (["--dne-outliers=100"], OUTLIERS_WORDS),
    (["--dne-outliers=99.99"], OUTLIERS_WORDS),
    (["--dne-outliers=50.5"], OUTLIERS_WORDS),
    (["--dne-outliers=-0.1"], OUTLIERS_WORDS),
    (["--dne-outliers=nan"], OUTLIERS_WORDS),
    (["--dne-outliers=inf"], OUTLIERS_WORDS),
    (["--opcr-steps=0"], STEPS_WORDS),
    (["--opcr-steps=361"], STEPS_WORDS),
    (["--opcr-steps=100000000"], STEPS_WORDS),
    (["--opcr-step=0"], STEP_WORDS),
    (["--opcr-step=-5.625"], STEP_WORDS),
    (["--opcr-step=45.5"], STEP_WORDS),  # 8 rotations past one turn
    (["--opcr-step=nan"], STEP_WORDS),
    (["--opcr-step=1e300"], STEP_WORDS),
    (["--opcr-steps=2", "--opcr-step=181"], STEP_WORDS),
]


def test_cli_refuses_topography_options_out_of_range(mesh_file, tmp_path):
    argvs = [
        [mesh_file, "--metrics", "classic,opcr", *options, "-o", str(tmp_path / "t.csv")]
        for options, _ in BAD_TOPOGRAPHY
    ]
    for (options, words), (code, stderr) in zip(BAD_TOPOGRAPHY, _run_many(argvs), strict=True):
        assert code == 2, (options, stderr)
        assert words in _one_line(stderr), (options, stderr)
    assert not (tmp_path / "t.csv").exists()


def test_the_ends_of_the_topography_ranges_compute(mesh_file, tmp_path):
    cases = [["--dne-outliers=0"], ["--dne-outliers=50"], ["--opcr-steps=360", "--opcr-step=1"]]
    cases += [["--opcr-steps=1", "--opcr-step=360"], ["--opcr-steps=8", "--opcr-step=45"]]
    tables = [tmp_path / f"{k}.csv" for k in range(len(cases))]
    argvs = [
        [mesh_file, "--metrics", "classic,opcr", *options, "-q", "-o", str(table)]
        for options, table in zip(cases, tables, strict=True)
    ]
    for options, table, (code, stderr) in zip(cases, tables, _run_many(argvs), strict=True):
        assert code == 0, (options, stderr)
        header, row = (line.split(",") for line in table.read_text().splitlines()[:2])
        assert row[header.index("status")] == "ok", (options, row)
        assert float(row[header.index("classic_dne")]) > 0, (options, row)


def test_library_refuses_outliers_and_rotations_out_of_range():
    words = _library_words(
        "classic_dne, opcr",
        [
            "classic_dne(mesh, outliers=100)",
            'classic_dne(mesh, outliers=float("nan"))',
            "opcr(mesh, step=0)",
            "opcr(mesh, steps=1000)",
            "make_settings(dne_outliers=100)",
            "make_settings(opcr_step=-1)",
        ],
    )
    assert words[0].startswith("outliers is a percentage and must lie in [0, 50]"), words
    assert words[1].startswith("outliers is a percentage and must lie in [0, 50]"), words
    assert words[2].startswith("step must lie in (0, 360 / steps]"), words
    assert words[3].startswith("steps must lie in [1, 360]"), words
    assert words[4].startswith(OUTLIERS_WORDS), words
    assert words[5].startswith(STEP_WORDS), words


def test_classic_dne_that_measures_no_face_is_an_error_never_zero():
    # a flat plate with one raised vertex: most faces have no energy, so at the top 50 % the
    # cut falls at 0 and takes every face with energy; a cap whose faces are all boundary
    # faces leaves none at all.  Both gave DNE 0.0 as ok; a flat plate rightly measures 0.0.
    code = """
import json
import numpy as np
from scipy.spatial import Delaunay
from dentopo import classic_dne
grid = np.stack(np.meshgrid(np.arange(8.0), np.arange(8.0)), -1).reshape(-1, 2)
faces = Delaunay(grid).simplices
flat = np.c_[grid, np.zeros(len(grid))]
bump = flat.copy()
bump[27, 2] = 1.0
cap = (np.array([[1, 0, 0], [0, 1, 0], [-1, 0, 0], [0, -1, 0], [0, 0, 1.0]]),
       np.array([[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]))
out = []
for mesh, outliers in (((bump, faces), 50), (cap, 0.1), ((bump, faces), 0.1), ((flat, faces), 50)):
    try:
        out.append(classic_dne(mesh, outliers=outliers).dne)
    except ValueError as exc:
        out.append(str(exc))
print(json.dumps(out))
"""
    ran = python(code)
    assert ran.returncode == 0, ran.describe()
    cut, cap, kept, flat = json.loads(ran.stdout)
    assert isinstance(cut, str) and "choose fewer outliers (dne_outliers)" in cut, cut
    assert isinstance(cap, str) and "4 of its 4 faces are boundary faces" in cap, cap
    assert isinstance(kept, float) and kept > 0
    assert flat == 0.0
