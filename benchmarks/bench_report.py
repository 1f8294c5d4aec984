"""The collection report: 200 crowns of about 4,000 vertices, from their table to the page.

Usage (from the repository root, with the project's environment and the report extra)::

    python benchmarks/bench_report.py                       # 200 meshes, rings=36 (3997 vertices)
    python benchmarks/bench_report.py --count 50 --jobs 1 2
    python benchmarks/bench_report.py --screenshot report.png   # also a picture of the page

The meshes are the sample tooth with seeded cusp heights and noise (as in
``bench_batch.py``), in four folders (the groups), each with its own relief.
Their table is computed once with ``dentopo.compute_batch`` (not timed); then
``dentopo.write_report`` turns the table into the page, once per ``--jobs``
value (worker processes recomputing the curvature), and the wall-clock
seconds, CPU seconds (this process and its workers) and the page's size are
printed.  The budget: under 60 s on 2 cores, a page under 50 MB.  Nothing here
is a test: timings depend on the machine and its load.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import trimesh

from dentopo import compute_batch, write_report, write_table
from dentopo.formats import layout
from dentopo.samples import tooth

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_batch import cpu_seconds

#: Folder (group) -> how much higher its crowns' relief is.
GROUPS = {"Alouatta": 1.25, "Ateles": 1.0, "Cebus": 0.8, "Pithecia": 0.9}


def write_collection(directory: Path, count: int, rings: int) -> list[Path]:
    """`count` varied tooth-like meshes as PLY files in one folder per group of :data:`GROUPS`."""
    rng = np.random.default_rng(0)
    base = tooth(rings=rings)
    names = list(GROUPS)
    paths = []
    for i in range(count):
        group = names[i % len(names)]
        vertices = np.array(base.vertices)
        vertices[:, 2] *= GROUPS[group] * rng.uniform(0.85, 1.15)
        vertices += rng.normal(scale=0.002, size=vertices.shape)
        path = directory / group / f"{group.lower()}_{i:04d}.ply"
        path.parent.mkdir(parents=True, exist_ok=True)
        trimesh.Trimesh(vertices, base.faces, process=False).export(path)
        paths.append(path)
    return paths


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--count", type=int, default=200)
    parser.add_argument("--rings", type=int, default=36)
    parser.add_argument("--jobs", type=int, nargs="+", default=[2])
    parser.add_argument("--screenshot", metavar="PNG", help="also save a picture of the page")
    parser.add_argument("--keep", metavar="HTML", help="copy the last page here")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        directory = Path(tmp)
        paths = write_collection(directory / "scans", args.count, args.rings)
        vertices = len(trimesh.load(paths[0], process=False).vertices)
        start = time.perf_counter()
        metrics = ("ariadne", "slope")
        records = compute_batch(directory / "scans", jobs=2, metrics=metrics)
        table = directory / "results.csv"
        write_table(table, records, columns=layout("dentopo", metrics))
        print(
            f"{len(paths)} meshes of {vertices} vertices in {len(GROUPS)} groups; "
            f"table computed in {time.perf_counter() - start:.1f} s (not timed below); "
            f"{os.cpu_count()} cores"
        )
        page = directory / "report.html"
        for jobs in args.jobs:
            cpu = cpu_seconds()
            start = time.perf_counter()
            summary = write_report(table, page, jobs=jobs)
            wall = time.perf_counter() - start
            cpu = cpu_seconds() - cpu
            print(
                f"jobs={jobs}: table -> report {wall:.1f} s wall, {cpu:.1f} s CPU; "
                f"page {summary.size / 1e6:.1f} MB ({summary.pictured} pictured, "
                f"{summary.size / 1e3 / max(summary.pictured, 1):.0f} kB per specimen with "
                "plotly.js shared)"
            )
        if args.keep:
            Path(args.keep).write_bytes(page.read_bytes())
        if args.screenshot:
            from report_screenshot import screenshot

            print(f"screenshot: {screenshot(page, args.screenshot)}")


if __name__ == "__main__":
    main()
