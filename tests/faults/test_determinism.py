"""The same input and options give bit-identical results on every run, at any thread count.

The exact and geodesic sums always did (each vertex's sum is one thread's, in a
fixed order).  The fast method did not: FINUFFT's multithreaded spreading adds
the threads' subgrids in whichever order they finish, and its FFTs round
differently with the number of threads, so ``--method fast`` moved by about
1e-15 between ``-j 1`` (two threads per mesh here) and ``-j 2`` (one each).
Every run is a fresh process (``faults.harness``) with its own thread count.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from dentopo.samples import sample_paths
from faults.harness import python

pytest.importorskip("finufft")

SCRIPT = """
import os
os.environ["NUMBA_NUM_THREADS"] = os.environ["OMP_NUM_THREADS"] = "{threads}"
import hashlib, json
from dentopo import ariaDNE
from dentopo.samples import tooth

digests = {{}}
for rings in (30, 60):
    result = ariaDNE(tooth(rings=rings), method="fast")
    assert result.method == "fast"
    digests[rings] = [
        hashlib.sha256(result.local_curvature.tobytes()).hexdigest(),
        result.dne.hex(),
    ]
print(json.dumps(digests))
"""

CLI = """
import os
os.environ["NUMBA_NUM_THREADS"] = os.environ["OMP_NUM_THREADS"] = "{threads}"
from dentopo.cli import main
raise SystemExit(main({argv!r}))
"""


def test_fast_method_is_bit_identical_across_runs_and_thread_counts():
    digests = {}
    for threads in (1, 2, 3, 2, 1):
        ran = python(SCRIPT.format(threads=threads))
        assert ran.returncode == 0, ran.describe()
        digests.setdefault(threads, []).append(json.loads(ran.stdout))
    runs = [run for per_count in digests.values() for run in per_count]
    assert all(run == runs[0] for run in runs), digests


def test_cli_per_vertex_values_are_identical_at_any_jobs(tmp_path):
    tooth = sample_paths()["tooth"]
    copy = tmp_path / "copy.ply"
    copy.write_bytes(tooth.read_bytes())
    arrays = {}
    for jobs, threads in (("1", 2), ("2", 2), ("1", 1)):
        out = tmp_path / f"j{jobs}t{threads}"
        argv = [str(tooth), str(copy), "--method", "fast", "-j", jobs, "-q"]
        argv += ["-o", str(out / "t.csv"), "--per-vertex", str(out), "--per-vertex-format", "npz"]
        out.mkdir()
        ran = python(CLI.format(threads=threads, argv=argv))
        assert ran.returncode == 0, ran.describe()
        for name in ("tooth", "copy"):
            with np.load(out / f"{name}.dentopo.npz") as data:
                arrays[jobs, threads, name] = data["local_curvature"].tobytes()
    assert len(set(arrays.values())) == 1, sorted(arrays)
