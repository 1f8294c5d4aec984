"""A new user's first run: compiling from an empty cache, and a warm command's start.

Usage (from the repository root, with the project's environment)::

    .venv/bin/python benchmarks/bench_first_run.py            # every case (about 8 minutes)
    .venv/bin/python benchmarks/bench_first_run.py --only samples,warm

Each case runs the ``dentopo`` command in a fresh process, cold cases with an empty
``NUMBA_CACHE_DIR`` of their own (numba compiles every kernel, as on a fresh install), and
prints its wall seconds and its CPU seconds (user + system of the command and its worker
processes: stable on a shared machine, where wall seconds are not) against the figures the
first-run issue measured before this work (the same machine, a fresh clone):

* ``samples``: ``dentopo --samples`` cold;
* ``all_j1`` / ``all_j0``: ``--metrics all`` on the 13 shared crowns, cold, ``-j 1`` and
  ``-j 0`` (every core);
* ``warm``: ``dentopo normal.ply`` with the kernels in the cache (the best of 5, by CPU);
* ``warm_info`` / ``warm_help``: ``dentopo info normal.ply`` (an error: a mesh, not a
  picture) and ``dentopo --help``, the best of 5 too: commands that load no kernel.

A warm case's command runs once first (numba's cache filled, and Python's bytecode cache
where the environment lets Python write it: ``PYTHONDONTWRITEBYTECODE`` set makes every run
compile dentopo's sources again, about 0.2 s more).

The shared crowns come from ``../shared/data/meshes`` (or ``--mesh-dir``).
"""

from __future__ import annotations

import argparse
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
MESHES = ROOT.parent / "shared" / "data" / "meshes"

#: The issue's figures before the work (wall s, CPU s; None: not measured).
BEFORE = {
    "samples": (26.5, 25.0),
    "all_j1": (139.0, 70.0),
    "all_j0": (240.0, None),
    "warm": (None, 1.8),
    "warm_info": (None, None),
    "warm_help": (None, None),
}
#: The issue's targets, as text.
TARGET = {
    "samples": "CPU <= 12 s",
    "all_j1": "CPU <= 40 s",
    "all_j0": "wall <= 1.2 x all_j1",
    "warm": "CPU <= 1.0 s",
    "warm_info": "-",
    "warm_help": "-",
}


def _command(arguments: list[str], cache: str | None, cwd: str) -> tuple[float, float, int]:
    """Run ``dentopo ARGUMENTS``; its wall and CPU seconds (children included) and exit code."""
    env = dict(os.environ)
    env.pop("NUMBA_CACHE_DIR", None)
    if cache is not None:
        env["NUMBA_CACHE_DIR"] = cache
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    started = time.perf_counter()
    done = subprocess.run(
        [sys.executable, "-m", "dentopo", *arguments],
        cwd=cwd,
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    wall = time.perf_counter() - started
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if done.returncode not in (0, 1):  # 1: a hostile mesh among the shared ones
        print(done.stderr, file=sys.stderr)
    return wall, cpu, done.returncode


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--only", help="comma-separated cases: " + ", ".join(BEFORE))
    parser.add_argument("--mesh-dir", type=Path, default=MESHES)
    args = parser.parse_args()
    cases = args.only.split(",") if args.only else list(BEFORE)
    crowns = sorted(str(p) for p in args.mesh_dir.glob("*.ply"))
    figures = {}
    with tempfile.TemporaryDirectory() as work:

        def cold(name: str, arguments: list[str]) -> None:
            cache = os.path.join(work, "cache-" + name)
            shutil.rmtree(cache, ignore_errors=True)
            os.makedirs(cache)
            figures[name] = _command(arguments, cache, work)

        if "samples" in cases:
            cold("samples", ["--samples", "-o", "samples.csv"])
        if "all_j1" in cases:
            cold("all_j1", [*crowns, "--metrics", "all", "-j", "1", "-o", "all1.csv"])
        if "all_j0" in cases:
            cold("all_j0", [*crowns, "--metrics", "all", "-j", "0", "-o", "all0.csv"])
        crown = str(args.mesh_dir / "normal.ply")
        warm = {
            "warm": [crown, "-o", "warm.csv"],
            "warm_info": ["info", crown],
            "warm_help": ["--help"],
        }
        for name, arguments in warm.items():
            if name in cases:
                _command(arguments, None, work)  # compiled (or loaded) once
                runs = [_command(arguments, None, work) for _ in range(5)]
                figures[name] = min(runs, key=lambda run: run[1])
    print(f"\n{'case':9} {'wall s':>8} {'CPU s':>8} {'before':>14} {'target':>22}")
    for name, (wall, cpu, _) in figures.items():
        was_wall, was_cpu = BEFORE[name]
        was = f"{was_wall or '-'} / {was_cpu or '-'}"
        digits = 2 if name.startswith("warm") else 1
        print(f"{name:9} {wall:8.{digits}f} {cpu:8.{digits}f} {was:>14} {TARGET[name]:>22}")
    if "all_j1" in figures and "all_j0" in figures:
        ratio = figures["all_j0"][0] / figures["all_j1"][0]
        print(f"all_j0 / all_j1 wall: {ratio:.2f}")
    print(f"machine: {os.cpu_count()} cores, load {os.getloadavg()[0]:.1f}")
    if os.environ.get("PYTHONDONTWRITEBYTECODE"):
        print("PYTHONDONTWRITEBYTECODE is set: each run compiled dentopo's sources again")
    return 0


if __name__ == "__main__":
    sys.exit(main())
