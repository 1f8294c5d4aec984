"""The R package (bridges/R/dentopo) and the MATLAB/Octave functions (bridges/matlab).

Each bridge's own tests run here, against the dentopo command of the environment under test
(``DENTOPO``: this interpreter's ``-m dentopo``), with the values Python gives written to a
temporary directory (``DENTOPO_PARITY_DIR``) for the parity tests:

- ``expected.csv``: ``set,distance_type,file,dne,positive_dne,negative_dne``, from
  :func:`dentopo.ariaDNE`, on the bundled samples and, when present, the shared meshes;
- ``bad_file.txt`` / ``bad_error.txt``: a corrupt file with commas, quotes and a non-ASCII
  letter in its name, and the message :func:`dentopo.compute_batch` gives for it.

CI (.ci/run) installs R, testthat and Octave; elsewhere these tests skip when they are missing.
"""

from __future__ import annotations

import csv
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import MESHES
from dentopo import ariaDNE, compute_batch
from dentopo.samples import sample_paths

ROOT = Path(__file__).resolve().parents[1]
R_PACKAGE = ROOT / "bridges" / "R" / "dentopo"
MATLAB = ROOT / "bridges" / "matlab"
SHARED_NAMES = ("normal", "low")
#: ariaDNE.m defaults to geodesic distances (the original's default): checked on these.
GEODESIC_SAMPLES = ("sphere", "saddle")


@pytest.fixture(scope="module")
def parity_dir(tmp_path_factory) -> Path:
    directory = tmp_path_factory.mktemp("parity")
    rows = []
    meshes = [("samples", Path(path)) for path in sample_paths().values()]
    meshes += [("shared", MESHES / f"{name}.ply") for name in SHARED_NAMES]
    for group, path in meshes:
        if not path.exists():
            continue  # shared data absent: the bridges' shared-mesh tests skip, saying so
        assert "," not in str(path) and '"' not in str(path)  # read by a plain split
        kinds = ["euclidean"]
        if group == "samples" and path.stem in GEODESIC_SAMPLES:
            kinds.append("geodesic")
        for kind in kinds:
            result = ariaDNE(path, distance_type=kind)
            rows.append(
                [group, kind, str(path), result.dne, result.positive_dne, result.negative_dne]
            )
    with open(directory / "expected.csv", "w", newline="", encoding="utf-8") as handle:
        writer = csv.writer(handle, lineterminator="\n")
        writer.writerow(["set", "distance_type", "file", "dne", "positive_dne", "negative_dne"])
        writer.writerows([*row[:3], *(repr(value) for value in row[3:])] for row in rows)
    bad = directory / 'bad, "quoted" \u00e9.ply'
    bad.write_text("not a mesh\n", encoding="utf-8")
    (record,) = compute_batch([str(bad)])
    assert record["status"] == "error"
    (directory / "bad_file.txt").write_text(str(bad), encoding="utf-8")
    (directory / "bad_error.txt").write_text(record["error"], encoding="utf-8")
    return directory


def bridge_environment(parity_dir: Path) -> dict[str, str]:
    """The environment of a bridge's tests: this interpreter's dentopo, the parity files."""
    env = dict(os.environ)
    env["DENTOPO"] = f"{sys.executable} -m dentopo"
    if " " in sys.executable:  # the bridges split DENTOPO on white space unless it is a file
        script = Path(sys.executable).parent / "dentopo"
        if not script.exists():
            pytest.skip(f"no dentopo script beside {sys.executable} (its path has a space)")
        env["DENTOPO"] = str(script)
    src = str(ROOT / "src")  # the checkout under test, also when dentopo is installed elsewhere
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [src, env.get("PYTHONPATH")]))
    env["DENTOPO_PARITY_DIR"] = str(parity_dir)
    return env


def readme_example(readme: Path, language: str, target: Path) -> Path:
    """The first ``language`` code block of a bridge's README, written to ``target``."""
    blocks = re.findall(rf"```{language}\n(.+?)```", readme.read_text(encoding="utf-8"), re.S)
    assert blocks, f"no {language} example in {readme}"
    target.write_text(blocks[0], encoding="utf-8")
    return target


def run(command: list[str], env: dict[str, str], cwd: Path) -> str:
    done = subprocess.run(command, env=env, cwd=cwd, capture_output=True, text=True)
    output = done.stdout + done.stderr
    assert done.returncode == 0, f"{' '.join(command)} failed:\n{output}"
    return output


def test_r_package(parity_dir, tmp_path):
    if shutil.which("Rscript") is None:
        pytest.skip("R not installed (Debian: r-base-core r-cran-testthat; .ci/run installs them)")
    env = bridge_environment(parity_dir)
    have_testthat = subprocess.run(
        ["Rscript", "-e", "quit(status = !requireNamespace('testthat', quietly = TRUE))"],
        env=env,
        capture_output=True,
    )
    if have_testthat.returncode != 0:
        pytest.skip("R package testthat not installed (Debian: r-cran-testthat)")
    library = tmp_path / "library"
    library.mkdir()
    run(["R", "CMD", "INSTALL", "--no-test-load", "-l", str(library), str(R_PACKAGE)], env, ROOT)
    env["R_LIBS"] = os.pathsep.join(filter(None, [str(library), env.get("R_LIBS")]))
    example = readme_example(R_PACKAGE / "README.md", "r", tmp_path / "example.R")
    output = run(
        [
            "Rscript",
            "-e",
            "testthat::test_dir('tests/testthat', package = 'dentopo', "
            "load_package = 'installed', reporter = 'summary', stop_on_failure = TRUE)",
            "-e",
            f"source({str(example)!r}, echo = TRUE)",  # the README's example runs
        ],
        env,
        R_PACKAGE,
    )
    print(output)  # the parity lines give the largest relative difference found
    assert "R parity, samples" in output
    assert "tooth.ply" in output


def test_matlab_functions_in_octave(parity_dir, tmp_path):
    octave = shutil.which("octave-cli") or shutil.which("octave")
    if octave is None:
        pytest.skip("GNU Octave not installed (Debian: octave; .ci/run installs it)")
    env = bridge_environment(parity_dir)
    example = readme_example(MATLAB / "README.md", "matlab", tmp_path / "readme_example.m")
    script = f"run_tests; run({str(example)!r});"  # then the README's example
    output = run([octave, "--norc", "--quiet", "--eval", script], env, MATLAB / "tests")
    print(output)
    assert "Octave parity, samples" in output
    assert "0 failed" in output
    assert "ariaDNE 0." in output
