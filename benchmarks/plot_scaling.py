"""Plot time and peak memory against vertices (1k to 5M): ours and the published package.

Usage (from the repository root, with the project's environment)::

    .venv/bin/python benchmarks/plot_scaling.py                    # runs bench_scaling.py, plots
    .venv/bin/python benchmarks/plot_scaling.py --from-json rows.json   # plots earlier rows
    .venv/bin/python benchmarks/plot_scaling.py --sizes 1000 10000 100000 --out /tmp/s.png

Without ``--from-json`` it runs ``bench_scaling.py`` (every size a fresh process; ours with the
exact sums up to ``--exact-max`` vertices and the fast ones everywhere; the published signDNE
0.1.4 up to ``--published-max`` if ``bench_published.py`` has installed it) and saves its rows
beside the picture (``scaling.json``).  The picture, ``docs/images/scaling.png`` by default, has
two panels against the vertex count (log scale): wall seconds (log scale; CPU seconds dotted)
and peak resident memory (``ru_maxrss``, interpreter included).  The machine is named in the title.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
DEFAULT_OUT = HERE.parent / "docs" / "images" / "scaling.png"
DEFAULT_SIZES = [1_000, 3_000, 10_000, 30_000, 100_000, 300_000, 1_000_000, 5_000_000]

sys.path.insert(0, str(HERE))
from bench_scaling import describe  # noqa: E402

STYLE = {
    "fast": ("dentopo, fast sums (auto from 20k)", "tab:blue", "o"),
    "exact": ("dentopo, exact sums", "tab:green", "s"),
    "published": ("signDNE 0.1.4 (published)", "tab:red", "^"),
}


def series(rows: list[dict], method: str, key: str) -> tuple[list[int], list[float]]:
    points = []
    for row in rows:
        ran = row.get(method)
        if isinstance(ran, dict) and key in ran:
            points.append((row.get("vertices", row["target"]), ran[key]))
    points.sort()
    return [p[0] for p in points], [p[1] for p in points]


def plot(data: dict, out: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import FormatStrFormatter

    rows = data["rows"]
    figure, (time_axis, memory_axis) = plt.subplots(1, 2, figsize=(11, 4.5))
    for method, (label, colour, marker) in STYLE.items():
        x, seconds = series(rows, method, "seconds")
        if not x:
            continue
        time_axis.plot(x, seconds, marker=marker, color=colour, label=label)
        cx, cpu = series(rows, method, "cpu_seconds")
        shown = [(a, b) for a, b in zip(cx, cpu, strict=True) if b > 0]  # (0: rounded away)
        if shown:
            time_axis.plot(*zip(*shown, strict=True), linestyle=":", color=colour, label="  CPU s")
        mx, memory = series(rows, method, "maxrss_gb")
        memory_axis.plot(mx, memory, marker=marker, color=colour, label=label)
    for size, (seconds, gigabytes) in {1_000_000: (10, 4), 5_000_000: (60, 4)}.items():
        time_axis.plot([size], [seconds], marker="_", markersize=18, color="black")
        memory_axis.plot([size], [gigabytes], marker="_", markersize=18, color="black")
    time_axis.plot([], [], marker="_", color="black", linestyle="", label="targets (1M, 5M)")
    for axis, title in ((time_axis, "seconds, file to totals"), (memory_axis, "peak memory, GB")):
        axis.set_xscale("log")
        axis.set_yscale("log" if axis is time_axis else "linear")
        axis.set_xlabel("vertices")
        axis.set_title(title)
        axis.grid(True, which="both", alpha=0.3)
        axis.yaxis.set_major_formatter(FormatStrFormatter("%g"))
        axis.yaxis.set_minor_formatter(FormatStrFormatter(""))
    time_axis.legend(fontsize=8)
    memory_axis.legend(fontsize=8)
    host = data.get("machine")
    if host:
        figure.suptitle(
            f"each point a fresh process; {describe(host)} (wall seconds grow with the load: "
            "CPU seconds dotted)",
            fontsize=9,
        )
    figure.tight_layout()
    out.parent.mkdir(parents=True, exist_ok=True)
    partial = out.with_suffix(".partial.png")
    figure.savefig(partial, dpi=110)
    partial.replace(out)
    plt.close(figure)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--from-json", type=Path, help="rows written by bench_scaling.py --json")
    parser.add_argument("--sizes", type=int, nargs="+", default=DEFAULT_SIZES)
    parser.add_argument("--exact-max", type=int, default=100_000)
    parser.add_argument("--published-max", type=int, default=12_000)
    parser.add_argument("--mesh-dir", type=Path, help="keep and reuse the generated meshes here")
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT)
    args = parser.parse_args(argv)
    source = args.from_json
    if source is None:
        source = args.out.with_name("scaling.json")
        source.parent.mkdir(parents=True, exist_ok=True)
        command = [sys.executable, str(HERE / "bench_scaling.py"), "--sizes"]
        command += [*map(str, args.sizes), "--json", str(source)]
        command += ["--exact-max", str(args.exact_max), "--published-max", str(args.published_max)]
        if args.mesh_dir:
            command += ["--mesh-dir", str(args.mesh_dir)]
        subprocess.run(command, check=True)
    plot(json.loads(source.read_text()), args.out)
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
