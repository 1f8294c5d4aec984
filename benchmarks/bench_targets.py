"""Every measure of the performance issue in one run: measure, target, figure, holds.

Usage (from the repository root, with the project's environment)::

    .venv/bin/python benchmarks/bench_targets.py                 # everything (about 15 minutes)
    .venv/bin/python benchmarks/bench_targets.py --skip-5m --skip-published   # a few minutes
    .venv/bin/python benchmarks/bench_targets.py --only scaling --mesh-dir /tmp/meshes

It runs the other benchmark scripts, each in its own process with ``--json``, and prints one
table from their figures:

* ``bench_published.py``: dentopo against the published signDNE 0.1.4 (installed beside ours in
  ``benchmarks/.published-env`` on first use) on the shared meshes ``low``, ``normal`` and
  ``high``: the speed-up is the published package's seconds over ours, both in the same run;
* ``bench_batch.py``: ``-j 2`` throughput on generated 4k-vertex crowns (wall-clock, and the
  CPU-bound figure two idle cores would reach);
* ``bench_topography.py`` and ``bench_doolkit.py``: each molaR 6.0 and doolkit 1.42 metric
  (ARC included) on ``low``, ``normal`` and ``high`` against the tool's own seconds from the
  reference files, on a prepared surface (what the tools' seconds cover: one call on a mesh
  already read and cleaned), and doolkit's whole set as one batch row;
* ``bench_scaling.py``: a binary PLY of about 1M and 5M vertices, from the file to the ariaDNE
  totals in a fresh process (``method="auto"``, hence the fast kernel sums): wall and CPU
  seconds, and the process's peak resident memory (``ru_maxrss``, interpreter included);
* ``bench_sign.py --cone 100000``: the sign step on a cone of 1e5 side faces on one apex.

The machine (cores, CPU model, RAM, load) is printed with the table: on a machine shared with
other work, wall-clock seconds are longer than the CPU seconds printed beside them.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from bench_scaling import describe, machine  # noqa: E402

#: (measure, target as text, test of a figure): the performance issue's table.
TARGETS = {
    "published": ("speed-up over signDNE 0.1.4", ">= 250x", lambda x: x >= 250),
    "published_low": ("speed-up over signDNE 0.1.4", ">= 150x", lambda x: x >= 150),
    "batch": ("-j 2 throughput, 4k-vertex crowns", ">= 25 meshes/s", lambda x: x >= 25),
    "topography": ("molaR 6.0 metric over molaR, prepared surface", ">= 20x", lambda x: x >= 20),
    "doolkit": ("doolkit 1.42 metric over doolkit, prepared surface", ">= 20x", lambda x: x >= 20),
    "seconds_1m": ("1M-vertex PLY to totals, wall", "<= 3 s", lambda x: x <= 3),
    "memory_1m": ("1M-vertex PLY to totals, peak memory", "<= 2 GB", lambda x: x <= 2),
    "seconds_5m": ("5M-vertex PLY to totals, wall", "<= 15 s", lambda x: x <= 15),
    "memory_5m": ("5M-vertex PLY to totals, peak memory", "<= 3 GB", lambda x: x <= 3),
    "cone": ("sign step, cone of 1e5 faces on one apex, wall", "<= 5 s", lambda x: x <= 5),
}

SECTIONS = ("published", "batch", "topography", "doolkit", "scaling", "cone")


def _run(script: str, options: list[str], out: Path, timeout: float) -> dict | str:
    """Run one benchmark script with ``--json out``; its figures, or why there are none."""
    command = [sys.executable, str(HERE / script), *options, "--json", str(out)]
    print("$ " + " ".join(command[1:]), flush=True)
    try:
        done = subprocess.run(command, timeout=timeout, capture_output=True, text=True)
    except subprocess.TimeoutExpired:
        return f"{script} took more than {timeout:.0f} s"
    sys.stdout.write(done.stdout)
    if done.returncode != 0 or not out.exists():
        lines = (done.stderr or done.stdout).strip().splitlines()
        return f"{script} failed: {lines[-1] if lines else done.returncode}"
    return json.loads(out.read_text())


def _row(key: str, figure: float | None, shown: str, note: str = "") -> list[str]:
    measure, target, holds = TARGETS[key]
    verdict = "-" if figure is None else ("yes" if holds(figure) else "no")
    return [measure + (f" ({note})" if note else ""), target, shown, verdict]


def published_rows(figures) -> list[list[str]]:
    if isinstance(figures, str):
        return [_row("published", None, figures)]
    rows = []
    for name, entry in figures.items():
        ratio = entry["published"]["seconds"] / entry["ours"]["seconds"]
        cpu = entry["published"]["cpu_seconds"] / entry["ours"]["cpu_seconds"]
        shown = f"{ratio:.0f}x ({entry['published']['seconds']:.2f} s / "
        shown += f"{entry['ours']['seconds']:.3f} s; CPU {cpu:.0f}x)"
        key = "published_low" if name == "low" else "published"
        rows.append(_row(key, ratio, shown, f"{name}, {entry['vertices']:,} vertices"))
    return rows


def batch_rows(figures) -> list[list[str]]:
    if isinstance(figures, str):
        return [_row("batch", None, figures)]
    wall = figures["meshes_per_second"]["2 processes (-j 2)"]
    cpu_bound = figures["cpu_bound_j2_meshes_per_second"]
    shown = f"{wall:.1f} meshes/s (CPU-bound: {cpu_bound:.1f})"
    return [_row("batch", wall, shown, f"{figures['meshes']} meshes")]


def topography_rows(figures, key: str = "topography") -> list[list[str]]:
    """One row per metric and mesh: the tool's seconds over ours on a prepared surface.

    The tools' seconds cover one metric call on a mesh already read and cleaned, so the
    prepared surface is the like-for-like figure; the figure on a mesh in memory (which
    adds the cleaning and the checks) is shown beside it.  A tool's time recorded as 0
    (below its clock's millisecond) gives no ratio.
    """
    if isinstance(figures, str):
        return [_row(key, None, figures)]
    rows = []
    for row in figures["rows"]:
        tool = row.get("molar_seconds", row.get("tool_seconds"))
        note = f"{row['metric']}, {row['mesh']}"
        if row.get("surface_ratio") is None:
            if row.get("ratio"):  # a whole batch row: no prepared-surface figure
                shown = f"{row['ratio']:.0f}x ({tool:.3f} s / {row['seconds'] * 1e3:.2f} ms)"
                rows.append(_row(key, row["ratio"], shown, note))
            else:
                rows.append(_row(key, None, f"no ratio: the tool's time is {tool:.3f} s", note))
            continue
        shown = f"{row['surface_ratio']:.0f}x ({tool:.3f} s / "
        shown += f"{row['surface_seconds'] * 1e3:.2f} ms; on a mesh {row['ratio']:.0f}x)"
        rows.append(_row(key, row["surface_ratio"], shown, note))
    return rows or [_row(key, None, "no ratio")]


def cone_rows(figures) -> list[list[str]]:
    if isinstance(figures, str):
        return [_row("cone", None, figures)]
    rows = []
    for row in figures:
        wall, cpu = row["wall"]["sign step"], row["cpu"]["sign step"]
        note = f"{row['faces']:,} faces"
        rows.append(_row("cone", wall, f"{wall:.1f} s (CPU {cpu:.1f} s)", note))
    return rows


def scaling_rows(figures, sizes: list[int]) -> list[list[str]]:
    labels = {1_000_000: "1m", 5_000_000: "5m"}
    if isinstance(figures, str):
        return [_row(f"seconds_{labels[s]}", None, figures) for s in sizes]
    rows = []
    for size, row in zip(sizes, figures["rows"], strict=True):
        label = labels[size]
        fast = row.get("fast")
        if not isinstance(fast, dict):
            rows.append(_row(f"seconds_{label}", None, str(fast)))
            continue
        phases = ", ".join(
            f"{name} {phase['seconds']:.1f}/{phase['cpu_seconds']:.1f}"
            for name, phase in fast["phases"].items()
            if name != "totals"
        )
        note = f"{fast['vertices']:,} vertices"
        shown = f"{fast['seconds']:.1f} s (CPU {fast['cpu_seconds']:.1f} s; {phases})"
        rows.append(_row(f"seconds_{label}", fast["seconds"], shown, note))
        rows.append(_row(f"memory_{label}", fast["maxrss_gb"], f"{fast['maxrss_gb']:.2f} GB"))
    return rows


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--only", nargs="+", choices=SECTIONS, help="run only these parts")
    parser.add_argument("--skip-published", action="store_true", help="no published ratios")
    parser.add_argument("--skip-batch", action="store_true", help="no -j 2 throughput")
    parser.add_argument("--skip-topography", action="store_true", help="no molaR ratios")
    parser.add_argument("--skip-doolkit", action="store_true", help="no doolkit ratios")
    parser.add_argument("--skip-cone", action="store_true", help="no cone through the sign step")
    parser.add_argument("--skip-1m", action="store_true", help="no 1M-vertex run")
    parser.add_argument("--skip-5m", action="store_true", help="no 5M-vertex run (the slowest)")
    parser.add_argument("--repeat", type=int, default=3, help="runs of ours per shared mesh")
    parser.add_argument("--batch-count", type=int, default=200, help="meshes in the batch")
    parser.add_argument("--mesh-dir", type=Path, help="keep and reuse the 1M/5M meshes here")
    parser.add_argument("--timeout", type=float, default=3600.0, help="seconds per script")
    parser.add_argument("--json", type=Path, help="also write the table here")
    args = parser.parse_args(argv)
    wanted = set(args.only or SECTIONS)
    skip = {
        "published": args.skip_published,
        "batch": args.skip_batch,
        "topography": args.skip_topography,
        "doolkit": args.skip_doolkit,
        "cone": args.skip_cone,
    }
    sizes = [s for s, off in ((1_000_000, args.skip_1m), (5_000_000, args.skip_5m)) if not off]
    if not sizes:
        wanted.discard("scaling")

    rows: list[list[str]] = []
    with tempfile.TemporaryDirectory(prefix="bench-targets-") as tmp:
        out = Path(tmp)
        if "published" in wanted and not skip["published"]:
            options = ["--meshes", "low", "normal", "high", "--repeat", str(args.repeat)]
            options += ["--no-stages"]
            figures = _run("bench_published.py", options, out / "published.json", args.timeout)
            rows += published_rows(figures)
        if "batch" in wanted and not skip["batch"]:
            options = ["--count", str(args.batch_count)]
            rows += batch_rows(_run("bench_batch.py", options, out / "batch.json", args.timeout))
        if "topography" in wanted and not skip["topography"]:
            options = ["--meshes", "low", "normal", "high", "--repeat", "11"]
            figures = _run("bench_topography.py", options, out / "topography.json", args.timeout)
            rows += topography_rows(figures)
        if "doolkit" in wanted and not skip["doolkit"]:
            options = ["--meshes", "low", "normal", "high", "--repeat", "11"]
            figures = _run("bench_doolkit.py", options, out / "doolkit.json", args.timeout)
            rows += topography_rows(figures, "doolkit")
        if "scaling" in wanted:
            options = ["--sizes", *map(str, sizes), "--methods", "fast"]
            options += ["--timeout", str(args.timeout)]
            if args.mesh_dir:
                options += ["--mesh-dir", str(args.mesh_dir)]
            figures = _run("bench_scaling.py", options, out / "scaling.json", args.timeout * 2)
            rows += scaling_rows(figures, sizes)
        if "cone" in wanted and not skip["cone"]:
            options = ["--meshes", "--cone", "100000", "--repeats", "1"]
            rows += cone_rows(_run("bench_sign.py", options, out / "cone.json", args.timeout))

    host = machine()
    header = ["measure", "target", "figure", "holds"]
    widths = [max(len(r[i]) for r in [header, *rows]) for i in range(4)]
    print()
    print("| " + " | ".join(h.ljust(w) for h, w in zip(header, widths, strict=True)) + " |")
    print("|" + "|".join("-" * (w + 2) for w in widths) + "|")
    for row in rows:
        print("| " + " | ".join(c.ljust(w) for c, w in zip(row, widths, strict=True)) + " |")
    print(f"\nmachine: {describe(host)} (at the end)")
    print("phases: wall/CPU seconds of prepare (read, clean, normalise), kernel, bending, sign")
    if args.json:
        table = [dict(zip(header, row, strict=True)) for row in rows]
        args.json.write_text(json.dumps({"machine": host, "rows": table}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
