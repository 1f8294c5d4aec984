"""Benchmark PCV (ambient occlusion) against CloudCompare's own qPCV on the same crowns, in one run.

Usage (from the repository root, with the project's environment)::

    .venv/bin/python benchmarks/bench_pcv.py                       # the six robustness crowns
    .venv/bin/python benchmarks/bench_pcv.py --meshes normal high --rays 1024
    .venv/bin/python benchmarks/bench_pcv.py --scaling             # also 16k-1M vertices

For each crown, alternately (so that a change of load touches both):

* CloudCompare 2.11.3 (``apt-get install cloudcompare xvfb``), headless, as the studies ran it:
  ``xvfb-run -a CloudCompare -SILENT -AUTO_SAVE OFF -O crown.ply -PCV -N_RAYS 256 -180
  -M_EXPORT_FMT PLY -SAVE_MESHES FILE out.ply``: the wall seconds of the whole command and its
  CPU seconds (user + system of the child processes);
* dentopo, as a batch row computes it (``measure_mesh(path, ("pcv",))``: the file read, cleaned,
  oriented, measured), in this process after one warm-up (the kernel compiled or loaded from
  numba's cache): the wall seconds and the CPU seconds (``time.process_time``, every thread),
  the best of ``--repeat``.

It prints both, their ratios, and the share of vertices within 0.02 of CloudCompare's value.
``--scaling`` times the kernel alone on a crown subdivided to 16k-1M vertices and prints the
seconds per million vertex-directions (flat when the cost is linear in vertices x rays).
Without CloudCompare, only dentopo's seconds are printed.  Nothing here is a test: timings depend
on the machine and its load (CPU seconds are steadier than wall seconds on a shared machine).
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

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

from dentopo.batch._measure import TopographyOptions, measure_mesh  # noqa: E402
from dentopo.mesh import read_ply  # noqa: E402

MESHES = ROOT.parent / "shared" / "data" / "meshes"
CROWNS = ("normal", "high", "low", "noise1", "noise2", "smooth")


def _children_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def cloudcompare(path: Path, rays: int, work: Path) -> tuple[float, float, np.ndarray]:
    """Wall and CPU seconds of CloudCompare's whole run, and its per-vertex PCV."""
    out = work / "cc.ply"
    if out.exists():
        out.unlink()
    command = ["xvfb-run", "-a", "CloudCompare", "-SILENT", "-AUTO_SAVE", "OFF", "-O", str(path)]
    command += ["-PCV", "-N_RAYS", str(rays), "-180", "-M_EXPORT_FMT", "PLY"]
    command += ["-SAVE_MESHES", "FILE", str(out)]
    cpu, wall = _children_cpu(), time.perf_counter()
    subprocess.run(command, capture_output=True, check=True, timeout=3600)
    wall, cpu = time.perf_counter() - wall, _children_cpu() - cpu
    data = out.read_bytes()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode()
    n = int(header.split("element vertex ")[1].split()[0])
    fields = [line.split()[-1] for line in header.splitlines() if line.startswith("property float")]
    values = np.frombuffer(data[end : end + n * 4 * len(fields)], dtype="<f4")
    return wall, cpu, values.reshape(n, len(fields))[:, fields.index("scalar_Illuminance_(PCV)")]


def ours(path: Path, rays: int, repeat: int) -> tuple[float, float, float]:
    """Best wall and CPU seconds of a batch row of PCV, and the crown's value."""
    options = TopographyOptions(pcv_rays=rays, orient="as-is")
    measure_mesh(str(path), ("pcv",), options=options)  # warm-up: compiled or loaded
    best_wall = best_cpu = float("inf")
    for _ in range(repeat):
        cpu, wall = time.process_time(), time.perf_counter()
        record = measure_mesh(str(path), ("pcv",), options=options)
        best_wall = min(best_wall, time.perf_counter() - wall)
        best_cpu = min(best_cpu, time.process_time() - cpu)
    return best_wall, best_cpu, record.record["pcv"]


def scaling(rays: int) -> None:
    import trimesh

    from dentopo.topography.occlusion._depth import lit_counts_depth_buffer
    from dentopo.topography.occlusion._directions import light_directions

    directions = light_directions(rays)
    vertices, faces = read_ply(MESHES / "normal.ply")
    mesh = trimesh.Trimesh(vertices, faces, process=False)
    print(f"\nscaling: the kernel alone, {len(directions)} directions")
    print(
        f"{'vertices':>10} {'faces':>10} {'wall s':>8} {'cpu s':>8} {'ns per vertex-direction':>24}"
    )
    while len(mesh.vertices) < 1_100_000:
        mesh = mesh.subdivide()
        v, f = np.asarray(mesh.vertices), np.asarray(mesh.faces)
        lit_counts_depth_buffer(v, f, directions[:2])
        cpu, wall = time.process_time(), time.perf_counter()
        lit_counts_depth_buffer(v, f, directions)
        wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
        per = cpu / (len(v) * len(directions)) * 1e9
        print(f"{len(v):>10} {len(f):>10} {wall:>8.2f} {cpu:>8.2f} {per:>24.1f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--meshes", nargs="+", default=list(CROWNS))
    parser.add_argument("--rays", type=int, default=256)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--scaling", action="store_true")
    args = parser.parse_args()
    have_cc = shutil.which("CloudCompare") is not None and shutil.which("xvfb-run") is not None
    print(f"PCV, {args.rays} rays over the northern hemisphere; {os.cpu_count()} cores")
    if not have_cc:
        print("CloudCompare or xvfb-run not found: dentopo's seconds only")
    head = f"{'crown':>8} {'vertices':>8} {'dentopo wall':>12} {'cpu':>6}"
    if have_cc:
        head += f" {'CC wall':>8} {'cpu':>6} {'x wall':>7} {'x cpu':>6} {'within 0.02':>11}"
    print(head)
    ratios = []
    with tempfile.TemporaryDirectory() as work:
        for name in args.meshes:
            path = MESHES / f"{name}.ply"
            n = len(read_ply(path)[0])
            wall, cpu, _ = ours(path, args.rays, args.repeat)
            line = f"{name:>8} {n:>8} {wall:>12.3f} {cpu:>6.3f}"
            if have_cc:
                cc_wall, cc_cpu, theirs = cloudcompare(path, args.rays, Path(work))
                from dentopo.topography import pcv

                mine = pcv(read_ply(path), rays=args.rays, orient="as-is").vertex_pcv
                close = float(np.mean(np.abs(mine - theirs) <= 0.02))
                ratios.append((cc_wall / wall, cc_cpu / cpu))
                line += f" {cc_wall:>8.2f} {cc_cpu:>6.2f} {cc_wall / wall:>7.1f}"
                line += f" {cc_cpu / cpu:>6.1f} {close:>11.2%}"
            print(line, flush=True)
    if ratios:
        walls, cpus = zip(*ratios, strict=True)
        print(
            f"times faster than CloudCompare: wall {min(walls):.1f}-{max(walls):.1f}, "
            f"CPU {min(cpus):.1f}-{max(cpus):.1f} (issue target: 20)"
        )
    if args.scaling:
        scaling(args.rays)


if __name__ == "__main__":
    main()
