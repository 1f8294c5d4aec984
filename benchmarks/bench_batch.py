"""Batch throughput: 200 generated tooth-like meshes of about 4k vertices, -j 1 and -j 2.

Usage (from the repository root, with the project's environment)::

    .venv/bin/python benchmarks/bench_batch.py              # 200 meshes, rings=36 (3997 vertices)
    .venv/bin/python benchmarks/bench_batch.py --count 50 --rings 20

The meshes are the sample tooth with each specimen's own cusp heights (the crown's
height scaled by a seeded random factor) and a little seeded noise, written as
binary PLY to a temporary directory.  Each configuration runs the whole batch
through the public batch API (``dentopo.compute_batch``), reading the files, as
the ``dentopo`` command does:

* ``1 process, 1 thread``: the single-core baseline;
* ``1 process, numba threads``: ``-j 1``, numba's kernels on every core;
* ``2 processes``: ``-j 2``, one numba thread per process.

Throughput is meshes per second of wall-clock time, worker start-up included.
Parallel efficiency is the ``-j 2`` throughput over twice the single-core one.
CPU seconds per mesh (this process and its workers, start-up included) give
the throughput two idle cores would reach, for a machine shared with other work.
Also printed: the time of the first mesh in each worker against the median, to
show that workers load numba's on-disk cache instead of compiling again.
Nothing here is a test: timings depend on the machine and its load.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np
import trimesh

from dentopo import compute_batch
from dentopo.batch import available_cores
from dentopo.samples import tooth


def write_meshes(directory: Path, count: int, rings: int) -> list[Path]:
    """`count` varied tooth-like meshes as PLY files in `directory`."""
    rng = np.random.default_rng(0)
    base = tooth(rings=rings)
    paths = []
    for i in range(count):
        vertices = np.array(base.vertices)
        vertices[:, 2] *= rng.uniform(0.7, 1.3)  # the crown's relief, specimen to specimen
        vertices += rng.normal(scale=0.002, size=vertices.shape)  # scanner noise
        path = directory / f"tooth_{i:04d}.ply"
        trimesh.Trimesh(vertices, base.faces, process=False).export(path)
        paths.append(path)
    return paths


def cpu_seconds() -> float:
    """CPU time of this process and of its finished worker processes."""
    own = resource.getrusage(resource.RUSAGE_SELF)
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def run(directory: Path, *, jobs: int, threads: int | None) -> tuple[float, float, list[dict]]:
    """Wall-clock and CPU seconds of one batch, and its records."""
    cpu = cpu_seconds()
    start = time.perf_counter()
    records = compute_batch(directory, jobs=jobs, threads=threads)
    wall = time.perf_counter() - start
    cpu = cpu_seconds() - cpu
    failed = [r for r in records if r["status"] != "ok"]
    if failed:
        raise RuntimeError(f"{len(failed)} meshes failed, e.g. {failed[0]['error']}")
    return wall, cpu, records


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--count", type=int, default=200, help="meshes (default 200)")
    parser.add_argument("--rings", type=int, default=36, help="mesh size (default 36: 3997 v.)")
    parser.add_argument("--json", type=Path, help="also write the figures to this JSON file")
    args = parser.parse_args()

    with tempfile.TemporaryDirectory(prefix="dentopo-bench-") as tmp:
        directory = Path(tmp)
        paths = write_meshes(directory, args.count, args.rings)
        vertices = len(trimesh.load(paths[0], process=False).vertices)
        print(f"{args.count} meshes of {vertices} vertices; {available_cores()} cores available")
        compute_batch(paths[:1])  # load numba's compiled kernels once in this process

        configurations = [
            ("1 process, 1 thread", 1, 1),
            ("1 process, numba threads (-j 1)", 1, None),
            ("2 processes (-j 2)", 2, None),
        ]
        rates = {}
        results = {}
        cpu_per_mesh = {}
        print(f"load average before: {os.getloadavg()[0]:.2f} (other work on the machine)")
        for label, jobs, threads in configurations:
            wall, cpu, records = run(directory, jobs=jobs, threads=threads)
            rates[label] = args.count / wall
            results[label] = records
            seconds = [r["seconds"] for r in records]
            print(
                f"{label:34s} {wall:6.1f} s  {rates[label]:6.2f} meshes/s  "
                f"CPU {cpu / args.count:.3f} s/mesh  "
                f"(per mesh: median {statistics.median(seconds):.3f} s, max {max(seconds):.3f} s)"
            )
            cpu_per_mesh[label] = cpu / args.count
        print(f"load average after: {os.getloadavg()[0]:.2f}")

        baseline = rates["1 process, 1 thread"]
        parallel = rates["2 processes (-j 2)"]
        print(f"speed-up of -j 2 over one core: {parallel / baseline:.2f}")
        print(f"parallel efficiency of -j 2:     {parallel / (2 * baseline):.0%}")
        one_core = cpu_per_mesh["1 process, 1 thread"]
        two_procs = cpu_per_mesh["2 processes (-j 2)"]
        print(
            f"CPU-time efficiency of -j 2 (1-core CPU per mesh over -j 2's, start-up included): "
            f"{one_core / two_procs:.0%}"
        )
        print(
            f"CPU-bound estimate for -j 2 on 2 idle cores: {2 / two_procs:.2f} meshes/s "
            "(wall-clock figures above suffer from other work on a shared machine)"
        )
        first = sorted(results["2 processes (-j 2)"], key=lambda r: r["seconds"])[-2:]
        print(
            "slowest two meshes under -j 2 (the first in each worker, if compiling): "
            + ", ".join(f"{r['seconds']:.3f} s" for r in first)
        )
        reference = [{k: v for k, v in r.items() if k != "seconds"} for r in results[label]]
        same = all(
            [{k: v for k, v in r.items() if k != "seconds"} for r in records] == reference
            for records in results.values()
        )
        print(f"rows identical in all configurations: {same}")
        if args.json:
            figures = {
                "meshes": args.count,
                "vertices": vertices,
                "meshes_per_second": rates,
                "cpu_seconds_per_mesh": cpu_per_mesh,
                "cpu_bound_j2_meshes_per_second": 2 / two_procs,
                "parallel_efficiency_j2": parallel / (2 * baseline),
                "identical_rows": same,
            }
            args.json.write_text(json.dumps(figures, indent=1))


if __name__ == "__main__":
    main()
