"""Scaling benchmark: vertices against time and peak memory, exact vs fast (vs published).

Usage (from the repository root, with the project's environment)::

    .venv/bin/python benchmarks/bench_scaling.py                        # 10k .. 1M vertices
    .venv/bin/python benchmarks/bench_scaling.py --sizes 10000 120000 --markdown
    .venv/bin/python benchmarks/bench_scaling.py --sizes 5000000 --methods fast

Meshes are generated reproducibly, never stored in the repository: the sample tooth crown
(``dentopo.samples.tooth``, an open crown of ``3 r (r + 1) + 1`` vertices) at the ring count
closest to each size, with seeded Gaussian noise of ``--noise`` times the mean edge length (a
scan is never perfectly smooth), written as PLY into a temporary folder.

Every run is a fresh subprocess that imports the package and makes one warm-up call on a tiny
mesh (loading numba's on-disk cache), then times ``ariaDNE(path, method=...)`` from loading the
file to the totals.  Peak memory is that process's ``ru_maxrss`` (it includes the interpreter
and libraries, about 0.2 GB).  Wall and CPU seconds are both reported: the machine may be shared,
and CPU seconds are less sensitive to that.  Runs that exceed ``--timeout`` are reported as such.
The fast runs also report each phase (``progress=``: prepare, kernel, bending, sign, totals):
wall and CPU seconds, and the peak memory reached by its end.  ``--mesh-dir`` keeps the generated
meshes (a 5M-vertex one takes a minute to write) for the next run; ``--json`` writes the rows
and the machine (cores, CPU model, RAM); ``plot_scaling.py`` draws them.

The exact sums grow as n**2 at the default bandwidth (the kernel reaches about half the
unit-area surface), so they run only up to ``--exact-max`` vertices.  The published signDNE
0.1.4 forms n x n matrices; it runs (up to ``--published-max`` vertices) only if
``benchmarks/bench_published.py`` has already installed it into ``benchmarks/.published-env``;
its time excludes loading the file.  Fast against exact is compared on every size where both
ran: the largest relative difference of the three totals, and the share of identical signs.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
PUBLISHED_SCRIPT = HERE / "bench_published.py"
PUBLISHED_PYTHON = HERE / ".published-env" / "bin" / "python"
TOTALS = ("dne", "positive_dne", "negative_dne")


def machine() -> dict:
    """Cores, CPU model, RAM and load of this machine (Linux ``/proc``; blanks elsewhere)."""
    import platform

    model, ram_gb = platform.processor() or platform.machine(), None
    try:
        with open("/proc/cpuinfo") as info:
            model = next(
                (line.split(":", 1)[1].strip() for line in info if line.startswith("model name")),
                model,
            )
        with open("/proc/meminfo") as info:
            ram_gb = (
                int(next(line for line in info if line.startswith("MemTotal")).split()[1]) / 1e6
            )
    except (OSError, StopIteration, ValueError):
        pass
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    return {
        "cores": cores,
        "cpu": model,
        "ram_gb": ram_gb,
        "load_average": os.getloadavg()[0] if hasattr(os, "getloadavg") else None,
    }


def describe(host: dict) -> str:
    ram = f"{host['ram_gb']:.0f} GB RAM" if host.get("ram_gb") else "RAM unknown"
    load = host.get("load_average")
    loaded = f", load average {load:.1f}" if load is not None else ""
    return f"{host['cores']} cores, {host['cpu']}, {ram}{loaded}"


def rings_for(vertices: int) -> int:
    """Ring count of the sample tooth whose vertex count is closest to ``vertices``."""
    r = max(1, round((-3 + (9 + 12 * (vertices - 1)) ** 0.5) / 6))
    return min((r - 1, r, r + 1), key=lambda k: abs(3 * k * (k + 1) + 1 - vertices) if k else 1e18)


def make_mesh(vertices: int, folder: Path, noise: float) -> Path:
    """Write the noisy sample tooth closest to ``vertices`` vertices; return its path."""
    import numpy as np
    import trimesh

    from dentopo.samples import tooth

    rings = rings_for(vertices)
    path = folder / f"tooth_r{rings}_n{noise:g}.ply"
    if path.exists():
        return path
    mesh = tooth(rings=rings)
    edges = mesh.vertices[mesh.edges_unique]
    mean_edge = float(np.linalg.norm(edges[:, 0] - edges[:, 1], axis=1).mean())
    rng = np.random.default_rng(rings)
    moved = mesh.vertices + rng.normal(scale=noise * mean_edge, size=mesh.vertices.shape)
    trimesh.Trimesh(moved, mesh.faces, process=False).export(path)
    return path


def make_mesh_apart(vertices: int, folder: Path, noise: float) -> Path:
    """:func:`make_mesh` in a child process, so that this process stays small.

    Linux carries a parent's high-water mark into a child started by (v)fork and exec (the
    exec records the old address space's peak in ``ru_maxrss``), so generating a 5M-vertex
    mesh here would show up as the workers' peak memory.
    """
    command = [sys.executable, __file__, "_make", str(vertices), str(folder), repr(noise)]
    done = subprocess.run(command, capture_output=True, text=True, check=True)
    return Path(done.stdout.strip().splitlines()[-1])


# --------------------------------------------------------------------------------------------
# worker: one timed call in a fresh process
# --------------------------------------------------------------------------------------------


def worker(method: str, mesh_path: str, out_path: str) -> None:
    import warnings

    import numpy as np
    import trimesh

    from dentopo import ariaDNE

    warnings.simplefilter("ignore")
    tiny = trimesh.creation.icosphere(subdivisions=1)
    ariaDNE(tiny, method="exact")
    if method == "fast":
        ariaDNE(tiny, method="fast")
    phases: dict[str, dict] = {}
    current: list = ["", 0.0, 0.0]

    def progress(name: str) -> None:
        now, cpu = time.perf_counter(), time.process_time()
        if current[0]:
            phases[current[0]] = {
                "seconds": now - current[1],
                "cpu_seconds": cpu - current[2],
                "maxrss_gb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6,
            }
        current[:] = [name, now, cpu]

    cpu_start = time.process_time()
    start = time.perf_counter()
    result = ariaDNE(mesh_path, method=method, progress=progress)
    progress("")
    seconds = time.perf_counter() - start
    cpu_seconds = time.process_time() - cpu_start
    meta = {
        "seconds": seconds,
        "cpu_seconds": cpu_seconds,
        "maxrss_gb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6,
        "vertices": result.vertices,
        "faces": result.faces,
        "method": result.method,
        "phases": phases,
        **{name: getattr(result, name) for name in TOTALS},
    }
    np.savez(out_path, meta=np.array(json.dumps(meta)), local_curvature=result.local_curvature)


def _run(command: list[str], out_path: Path, timeout: float) -> tuple[dict, object] | str:
    """Run a worker; return (meta, per-vertex curvature or None) or a short failure note."""
    import numpy as np

    try:
        done = subprocess.run(
            command, capture_output=True, text=True, timeout=timeout, cwd=tempfile.gettempdir()
        )
    except subprocess.TimeoutExpired:
        return f"> {timeout:.0f} s"
    if done.returncode != 0:
        lines = (done.stderr or done.stdout).strip().splitlines()
        return "failed: " + (lines[-1] if lines else f"exit {done.returncode}")
    with np.load(out_path) as data:
        meta = json.loads(str(data["meta"]))
        curvature = data["local_curvature"] if "local_curvature" in data.files else None
    out_path.unlink()
    return meta, curvature


def run_ours(method: str, mesh: Path, scratch: Path, timeout: float):
    out = scratch / f"{method}-{time.monotonic_ns()}.npz"
    command = [
        sys.executable,
        str(Path(__file__).resolve()),
        "_worker",
        method,
        str(mesh),
        str(out),
    ]
    return _run(command, out, timeout)


def run_published(mesh: Path, scratch: Path, timeout: float):
    out = scratch / f"published-{time.monotonic_ns()}.npz"
    command = [str(PUBLISHED_PYTHON), str(PUBLISHED_SCRIPT), "_worker", "published"]
    command += [str(mesh), str(out)]
    outcome = _run(command, out, timeout)
    if isinstance(outcome, str):
        return outcome
    meta, _ = outcome
    return {"seconds": meta["seconds"], "maxrss_gb": meta["maxrss_after_kb"] / 1e6}


# --------------------------------------------------------------------------------------------
# driver
# --------------------------------------------------------------------------------------------


def _cell(ran) -> tuple[str, str]:
    if isinstance(ran, str):
        return ran, ""
    if ran is None:
        return "", ""
    cpu = f" ({ran['cpu_seconds']:.1f})" if "cpu_seconds" in ran else ""
    return f"{ran['seconds']:.1f}{cpu}", f"{ran['maxrss_gb']:.2f}"


def compare(exact, fast) -> tuple[str, str]:
    import numpy as np

    if not (isinstance(exact, tuple) and isinstance(fast, tuple)):
        return "", ""
    (e_meta, e_curv), (f_meta, f_curv) = exact, fast
    rel = max(abs(f_meta[name] - e_meta[name]) / max(abs(e_meta[name]), 1e-300) for name in TOTALS)
    same = float(np.mean(np.sign(e_curv) == np.sign(f_curv)))
    return f"{rel:.1e}", f"{100 * same:.4f} %"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[10_000, 30_000, 100_000, 300_000])
    parser.add_argument("--methods", nargs="+", default=["exact", "fast", "published"])
    parser.add_argument("--exact-max", type=int, default=200_000)
    parser.add_argument("--published-max", type=int, default=12_000)
    parser.add_argument("--timeout", type=float, default=900.0, help="seconds per run")
    parser.add_argument("--noise", type=float, default=0.05, help="noise / mean edge length")
    parser.add_argument("--json", type=Path, help="also write the rows here")
    parser.add_argument(
        "--mesh-dir",
        type=Path,
        help="keep the generated meshes in this folder and reuse them (default: a temporary one)",
    )
    parser.add_argument("--markdown", action="store_true", help="print a Markdown table")
    args = parser.parse_args(argv)

    published_note = None
    if "published" in args.methods and not (
        PUBLISHED_PYTHON.exists() and PUBLISHED_SCRIPT.exists()
    ):
        published_note = (
            "published column skipped: run benchmarks/bench_published.py once to install "
            "signDNE 0.1.4 into benchmarks/.published-env"
        )
    rows = []
    with tempfile.TemporaryDirectory(prefix="bench-scaling-") as tmp:
        scratch = Path(tmp)
        if args.mesh_dir:
            args.mesh_dir.mkdir(parents=True, exist_ok=True)
        for size in args.sizes:
            mesh = make_mesh_apart(size, args.mesh_dir or scratch, args.noise)
            row = {"target": size}
            runs = {}
            for method in args.methods:
                if method == "exact" and size > args.exact_max:
                    continue
                if method == "published":
                    if published_note or size > args.published_max:
                        continue
                    runs[method] = run_published(mesh, scratch, args.timeout)
                else:
                    runs[method] = run_ours(method, mesh, scratch, args.timeout)
                ran = runs[method]
                if isinstance(ran, tuple):
                    row.update(vertices=ran[0]["vertices"], faces=ran[0]["faces"])
                print(
                    f"  {size:>9} {method:9s} {_cell(ran[0] if isinstance(ran, tuple) else ran)}",
                    file=sys.stderr,
                    flush=True,
                )
            for method, ran in runs.items():
                row[method] = ran[0] if isinstance(ran, tuple) else ran
            row["fast_vs_exact"] = compare(runs.get("exact"), runs.get("fast"))
            rows.append(row)
            if not args.mesh_dir:
                mesh.unlink()

    header = ["vertices", "faces"]
    for method in ("exact", "fast", "published"):
        if method in args.methods:
            cpu = " (cpu s)" if method != "published" else ""
            header += [f"{method} s{cpu}", f"{method} GB"]
    header += ["fast vs exact: totals", "identical signs"]
    lines = []
    for row in rows:
        cells = [
            f"{row.get('vertices', row['target']):,}",
            f"{row.get('faces', ''):,}" if "faces" in row else "",
        ]
        for method in ("exact", "fast", "published"):
            if method in args.methods:
                ran = row.get(method)
                cells += list(_cell(ran))
        cells += list(row["fast_vs_exact"])
        lines.append(cells)
    if args.markdown:
        print("| " + " | ".join(header) + " |")
        print("|" + "|".join("---:" for _ in header) + "|")
        for cells in lines:
            print("| " + " | ".join(cells) + " |")
    else:
        widths = [max(len(h), *(len(c[i]) for c in lines)) for i, h in enumerate(header)]
        print("  ".join(h.rjust(w) for h, w in zip(header, widths, strict=True)))
        for cells in lines:
            print("  ".join(c.rjust(w) for c, w in zip(cells, widths, strict=True)))
    for row in rows:
        fast = row.get("fast")
        if isinstance(fast, dict):
            phases = ", ".join(
                f"{k} {v['seconds']:.1f} ({v['cpu_seconds']:.1f}, {v['maxrss_gb']:.2f} GB)"
                for k, v in fast["phases"].items()
            )
            print(f"fast phases at {fast['vertices']:,} vertices, s (CPU s, peak so far): {phases}")
    if published_note:
        print(published_note)
    host = machine()
    print(f"machine: {describe(host)} (at the end)")
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps({"machine": host, "rows": rows}, indent=1, default=str))
    return 0


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "_make":
        print(make_mesh(int(sys.argv[2]), Path(sys.argv[3]), float(sys.argv[4])))
        raise SystemExit(0)
    if len(sys.argv) > 1 and sys.argv[1] == "_worker":
        worker(*sys.argv[2:5])
        raise SystemExit(0)
    raise SystemExit(main())
