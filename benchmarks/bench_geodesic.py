"""Geodesic ariaDNE (``distance_type="geodesic"``): the compiled searches against the old blocks.

Usage (from the repository root, with the project's environment)::

    .venv/bin/python benchmarks/bench_geodesic.py                  # the 40k-vertex crown
    .venv/bin/python benchmarks/bench_geodesic.py --mesh some.ply  # any mesh
    .venv/bin/python benchmarks/bench_geodesic.py --skip-old       # the new code only

The default mesh is the shared ``high.ply`` crown (10,080 vertices) subdivided once by
trimesh (40,159 vertices), written into a temporary folder.  Each variant runs in a fresh
subprocess, which makes one warm-up call on a tiny mesh (compiling or loading numba's
cache), then times ``ariaDNE(mesh, distance_type="geodesic")`` on the loaded mesh: wall
and CPU seconds (user + system, all threads; the machine may be shared) and the process's
peak memory (``ru_maxrss``, interpreter and libraries included).  ``old`` is the block
version this replaced, kept below as the baseline: scipy's ``dijkstra`` from blocks of 128
rows bounded by the kernel radius, dense (rows x n) distance matrices, and moments by
matrix products relative to the block's centre.  The two are then compared: the largest
relative difference of the totals and of the per-vertex values, and the sign changes.
"""

from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
SHARED_MESH = HERE.parent.parent / "shared" / "data" / "meshes" / "high.ply"
TOTALS = ("dne", "positive_dne", "negative_dne")


def old_geodesic_moments(points, faces, bandwidth, cutoff):
    """The geodesic moments before ``dentopo.ariadne._geodesic`` (the baseline)."""
    import numpy as np
    from scipy.sparse.csgraph import dijkstra

    from dentopo.ariadne import _kernel
    from dentopo.mesh import spatial_order

    n = len(points)
    radius = _kernel.kernel_radius(bandwidth, cutoff)
    graph = _kernel.edge_graph(points, faces)
    order = spatial_order(points)
    out = _kernel._empty(n)
    block_rows = max(1, min(128, 4_000_000 // max(n, 1)))
    for start in range(0, n, block_rows):
        rows = order[start : start + block_rows]
        dist = dijkstra(graph, directed=False, indices=rows, limit=radius)
        cols = np.flatnonzero(np.isfinite(dist).any(axis=0))
        sq_dist = dist[:, cols] ** 2  # inf ** 2 = inf, exp(-inf) = 0
        _kernel._accumulate(out, rows, cols, sq_dist, points, bandwidth, cutoff, radius)
    return _kernel.KernelMoments(*out)


def make_crown(folder: Path) -> Path:
    """The shared ``high.ply`` crown subdivided once (about 40k vertices)."""
    import trimesh

    mesh = trimesh.load(SHARED_MESH, process=False)
    vertices, faces = trimesh.remesh.subdivide(mesh.vertices, mesh.faces)
    path = folder / "crown40k.ply"
    trimesh.Trimesh(vertices, faces, process=False).export(path)
    return path


def worker(variant: str, mesh_path: str, out_path: str) -> None:
    import warnings

    import numpy as np
    import trimesh

    from dentopo import ariaDNE
    from dentopo.ariadne import _kernel

    warnings.simplefilter("ignore")
    if variant == "old":
        _kernel.geodesic_moments = old_geodesic_moments
    ariaDNE(trimesh.creation.icosphere(subdivisions=1), distance_type="geodesic")
    mesh = trimesh.load(mesh_path, process=False)
    wall, cpu = time.perf_counter(), time.process_time()
    result = ariaDNE(mesh, distance_type="geodesic")
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    np.save(out_path + ".npy", result.local_curvature)
    row = {
        "variant": variant,
        "vertices": len(result.local_curvature),
        "seconds": wall,
        "cpu_seconds": cpu,
        "peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e3,
        **{name: getattr(result, name) for name in TOTALS},
    }
    Path(out_path).write_text(json.dumps(row))


def run(variant: str, mesh: Path, folder: Path) -> dict:
    out = folder / f"{variant}.json"
    command = [sys.executable, __file__, "_worker", variant, str(mesh), str(out)]
    subprocess.run(command, check=True)
    row = json.loads(out.read_text())
    print(
        f"{variant:4s} {row['vertices']} vertices: {row['seconds']:7.2f} s wall, "
        f"{row['cpu_seconds']:7.2f} s CPU, peak {row['peak_mb']:6.0f} MB, dne {row['dne']!r}",
        flush=True,
    )
    return row


def compare(folder: Path, old: dict, new: dict) -> None:
    import numpy as np

    a, b = np.load(folder / "old.json.npy"), np.load(folder / "new.json.npy")
    totals = max(abs(old[name] - new[name]) / abs(old[name]) for name in TOTALS if old[name] != 0)
    per_vertex = np.abs(a - b) / np.maximum(np.abs(a), np.finfo(float).tiny)
    scaled = np.abs(a - b).max() / np.abs(a).max()
    signs = int(np.count_nonzero(np.sign(a) != np.sign(b)))
    print(
        f"largest relative difference: totals {totals:.2e}, per vertex {per_vertex.max():.2e} "
        f"(to the largest value {scaled:.2e}); sign changes {signs}; "
        f"speed-up {old['seconds'] / new['seconds']:.1f}x wall, "
        f"{old['cpu_seconds'] / new['cpu_seconds']:.1f}x CPU"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mesh", type=Path, help="a mesh file (default: the 40k crown)")
    parser.add_argument("--skip-old", action="store_true", help="time the new code only")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        mesh = args.mesh or make_crown(folder)
        new = run("new", mesh, folder)
        if not args.skip_old:
            old = run("old", mesh, folder)
            compare(folder, old, new)


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "_worker":
        worker(*sys.argv[2:5])
    else:
        main()
