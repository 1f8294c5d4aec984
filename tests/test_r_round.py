"""R's ``round(x, 2)``, which doolkit's hypsodonty and shape index use, against R itself."""

from __future__ import annotations

import shutil
import subprocess

import numpy as np
import pytest

from dentopo.topography import r_round


def _values() -> np.ndarray:
    rng = np.random.default_rng(7)
    # decimal halves and their neighbours (where R and Python differ), and ordinary values
    halves = (np.arange(0, 20000) + 0.5) / 100.0
    near = np.concatenate([np.nextafter(halves, 0), np.nextafter(halves, 1)])
    return np.concatenate([halves, near, rng.uniform(0, 50, 5000), -halves[:500]])


def test_r_round_gives_rs_own_round():
    rscript = shutil.which("Rscript")
    if rscript is None:
        pytest.skip("Rscript not found: R's round cannot be asked (CI installs r-base-core)")
    values = _values()
    text = "\n".join(repr(float(v)) for v in values)
    ran = subprocess.run(
        [
            rscript,
            "-e",
            "x <- scan(file('stdin'), quiet = TRUE); writeLines(sprintf('%.17g', round(x, 2)))",
        ],
        input=text,
        capture_output=True,
        text=True,
        check=True,
        timeout=120,
    )
    theirs = np.array([float(line) for line in ran.stdout.split()])
    ours = np.array([r_round(v, 2) for v in values])
    assert len(theirs) == len(values)
    differ = np.flatnonzero(ours != theirs)
    assert len(differ) == 0, [(values[i], ours[i], theirs[i]) for i in differ[:5]]
    # and R's round is not Python's: the test would catch a plain round()
    assert any(round(float(v), 2) != t for v, t in zip(values, theirs, strict=True))
