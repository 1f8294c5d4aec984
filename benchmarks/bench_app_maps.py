"""The app's four maps of one crown (curvature, slope, OPC, ARC): wall and CPU seconds.

Usage (from the repository root, with the project's environment and the app extra)::

    python benchmarks/bench_app_maps.py                          # the shared normal.ply
    python benchmarks/bench_app_maps.py --mesh scan.ply --repeat 3
    python benchmarks/bench_app_maps.py --no-command             # the workspace only

Two ways of drawing the same four pictures, each into a fresh output folder (nothing cached):

* ``workspace``: :meth:`dentopo.app.Workspace.map_picture`, as the page asks for them, one after
  the other (the page's order).  The app draws them in its warm picture worker; the worker is
  started and warmed first, as the server does when it starts (its warm-up is timed apart).
* ``command``: one ``python -m dentopo ... --screenshot`` process per map, with the arguments the
  app used before it had a worker (what the workspace path replaced).

CPU seconds are this process's, its waited children's and the picture worker's (read from
``/proc``), user and system.  The numba cache should be warm (run ``dentopo`` once on the mesh
first): the cold figures measure compilation, not drawing.  Nothing here is a test: timings
depend on the machine and its load (on a shared machine wall seconds exceed CPU seconds).
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
SHARED = HERE.parent.parent / "shared" / "data" / "meshes" / "normal.ply"
#: The maps, in the page's order: name -> (the metric computed, the command's --color-by).
MAPS = {
    "curvature": ("ariadne", "local_curvature"),
    "slope": ("slope", "slope"),
    "opc": ("opc", "opc"),
    "arc": ("arc", "arc"),
}
#: The target of the performance issue: the four maps of a crown in at most this, wall.
TARGET_SECONDS = 3.0


def process_cpu(pid: int | None) -> float:
    """CPU seconds (user + system) of process `pid` so far, from /proc; 0 if unknown."""
    if pid is None:
        return 0.0
    try:
        with open(f"/proc/{pid}/stat") as stream:
            fields = stream.read().rpartition(")")[2].split()
    except OSError:
        return 0.0
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def own_cpu() -> float:
    """CPU seconds of this process and of its waited-for children."""
    t = os.times()
    return t.user + t.system + t.children_user + t.children_system


def worker_pid(workspace) -> int | None:
    drawer = getattr(workspace, "drawer", None)
    return None if drawer is None else drawer.pid


def bench_workspace(mesh: Path, folder: Path) -> dict:
    from dentopo.app import Workspace

    workspace = Workspace(str(folder), str(folder / "out"))
    try:
        start, cpu = time.perf_counter(), own_cpu()
        drawer = getattr(workspace, "drawer", None)
        if drawer is not None:  # as the server does at its start
            drawer.warm()
            drawer.wait_warm(300)
        warm = (time.perf_counter() - start, own_cpu() - cpu + process_cpu(worker_pid(workspace)))
        pid = worker_pid(workspace)
        before = process_cpu(pid)
        start, cpu = time.perf_counter(), own_cpu()
        for name in MAPS:
            while True:
                found = workspace.map_picture(mesh.name, name)
                if isinstance(found, str):
                    break
                if found.state == "failed":
                    raise SystemExit(f"the {name} map failed: {getattr(found, 'error', '')}")
                time.sleep(0.02)
        wall = time.perf_counter() - start
        cpu = own_cpu() - cpu + process_cpu(pid) - before
        return {"wall": wall, "cpu": cpu, "warm_wall": warm[0], "warm_cpu": warm[1]}
    finally:
        workspace.close()


def bench_command(mesh: Path, folder: Path) -> dict:
    """One ``dentopo`` process per map, as the app ran them before its worker."""
    out = folder / "command"
    out.mkdir()
    start, cpu = time.perf_counter(), own_cpu()
    for name, (metric, color_by) in MAPS.items():
        arguments = ["--metrics", metric, "--bandwidth", "0.08", "--cutoff", "0.0"]
        arguments += ["--distance-type", "euclidean", "--sign-method", "centroid"]
        arguments += ["--method", "auto", "--quiet", "--color-by", color_by]
        arguments += ["--screenshot", str(out / f"{name}.png"), "--size", "900,760"]
        subprocess.run(
            [sys.executable, "-m", "dentopo", *arguments, "--", mesh.name],
            cwd=folder,
            check=True,
            stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL,  # the table: the app never read it
        )
    return {"wall": time.perf_counter() - start, "cpu": own_cpu() - cpu}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mesh", type=Path, default=SHARED, help="the crown (default normal.ply)")
    parser.add_argument("--repeat", type=int, default=1, help="times each case runs (the best)")
    parser.add_argument("--no-command", action="store_true", help="skip the command's case")
    args = parser.parse_args()
    mesh = args.mesh if args.mesh.exists() else None
    if mesh is None:
        from dentopo.samples import sample_paths

        mesh = Path(sample_paths()["tooth"])
        print(f"{args.mesh} not found: the sample tooth instead")
    print(f"four maps of {mesh.name} (cores: {os.cpu_count()}, load: {os.getloadavg()[0]:.2f})")
    cases = {"workspace": bench_workspace}
    if not args.no_command:
        cases["command"] = bench_command
    results = {}
    for case, bench in cases.items():
        runs = []
        for _ in range(args.repeat):
            with tempfile.TemporaryDirectory(prefix="bench-app-maps-") as tmp:
                folder = Path(tmp)
                shutil.copy(mesh, folder / mesh.name)
                runs.append(bench(mesh.with_name(mesh.name), folder))
        results[case] = min(runs, key=lambda r: r["wall"])
    for case, figures in results.items():
        line = f"  {case:10s} {figures['wall']:6.2f} s wall  {figures['cpu']:6.2f} s CPU"
        if "warm_wall" in figures:
            line += (
                f"   (worker warm-up before: {figures['warm_wall']:.2f} s wall, "
                f"{figures['warm_cpu']:.2f} s CPU)"
            )
        print(line)
    wall = results["workspace"]["wall"]
    verdict = "holds" if wall <= TARGET_SECONDS else "missed"
    print(f"  target: the workspace's four maps in at most {TARGET_SECONDS:g} s wall: {verdict}")


if __name__ == "__main__":
    main()
