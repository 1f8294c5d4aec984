"""Sign-step benchmark: the inside test of ariaDNE's centroids, stage by stage.

Usage (from the repository root, with the project's environment)::

    .venv/bin/python benchmarks/bench_sign.py                      # low, normal, high
    .venv/bin/python benchmarks/bench_sign.py --sizes 1000000 --repeats 1
    .venv/bin/python benchmarks/bench_sign.py --meshes --cone 10000 100000 --repeats 1
    NUMBA_NUM_THREADS=1 .venv/bin/python benchmarks/bench_sign.py  # CPU time of one thread

The inputs are what ``ariaDNE`` hands to the sign step: the prepared mesh's points and
faces and the kernel-weighted centroids (bandwidth 0.08; the exact kernel below 20,000
vertices, the fast one from there on, as ariaDNE's ``"auto"``).  Generated crowns are
grown as in ``bench_scaling.py``; ``--cone N`` is a cone of N side faces on one apex and
a base fan of N faces on one centre (``tests/faults/test_geometry_cost.py``'s), whose
needles the step cuts where the centroids come near them.  For each mesh the whole step
(``convex_vertices("centroid", ...)``) and its stages are timed, interleaved over
``--repeats`` runs, and the medians of wall and CPU seconds are printed (CPU seconds
count every thread; on a shared machine they vary less).  Stages: ``close_holes``; the
triangles in k-d order (long ones and needles cut); the hierarchy's nodes; the queries'
spatial order; the first, approximate pass over all queries.  With ``--memory`` each
mesh runs in a fresh process and its peak resident memory is reported too.
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
SHARED_MESHES = HERE.parents[1] / "shared" / "data" / "meshes"


def inputs(name: str, folder: Path):
    """``points, faces, centroids`` of the sign step for a shared mesh or a generated size."""
    import numpy as np

    from dentopo.ariadne import _fastgauss, _kernel
    from dentopo.mesh import prepare

    if name.startswith("cone"):
        prepared = prepare(cone(int(name[4:])))
    elif name.isdigit():
        sys.path.insert(0, str(HERE))
        from bench_scaling import make_mesh

        prepared = prepare(str(make_mesh(int(name), folder, 0.05)))
    else:
        prepared = prepare(str(SHARED_MESHES / f"{name}.ply"))
    points = prepared.points
    faces = np.asarray(prepared.mesh.faces)
    if len(points) >= 20_000:
        moments = _fastgauss.fast_euclidean_moments(points, 0.08)
    else:
        moments = _kernel.euclidean_moments(points, 0.08, 0.0)
    return points, faces, moments.centroid(points)


def cone(n: int):
    """``vertices, faces`` of a cone of `n` side faces on one apex, its base a fan of `n`
    faces on one centre (``tests/faults/test_geometry_cost.py``'s ``_cone``)."""
    import numpy as np

    t = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    rim = np.column_stack([np.cos(t), np.sin(t), np.zeros(n)])
    vertices = np.vstack([rim, [[0.0, 0.0, 1.0], [0.0, 0.0, 0.0]]])
    i = np.arange(n)
    j = (i + 1) % n
    side = np.column_stack([i, j, np.full(n, n)])
    base = np.column_stack([j, i, np.full(n, n + 1)])
    return vertices, np.vstack([side, base])


def stages(points, faces, centroids):
    """The stages of the step as (name, thunk) pairs (none modifies its inputs)."""
    import numpy as np

    from dentopo.mesh import close_holes, spatial_order
    from dentopo.sign import _winding as winding
    from dentopo.sign import convex_vertices

    vertices, closed = close_holes(points, faces)
    tri = winding._ordered_triangles(vertices, closed, queries=centroids)
    tree = winding._tree(tri)
    order = spatial_order(centroids)
    queries = np.ascontiguousarray(centroids[order])
    ratio = winding.INSIDE_RATIO
    return [
        ("sign step", lambda: convex_vertices("centroid", points, faces, centroids, 0.08)),
        ("close_holes", lambda: close_holes(points, faces)),
        (
            "ordered triangles",
            lambda: winding._ordered_triangles(vertices, closed, queries=centroids),
        ),
        ("hierarchy", lambda: winding._tree(tri)),
        ("query order", lambda: spatial_order(centroids)),
        ("queries", lambda: winding._approximate(tri, tree, queries, ratio, True)),
    ]


def run(name: str, repeats: int, folder: Path) -> dict:
    import numpy as np
    import trimesh

    from dentopo.sign import convex_vertices

    tiny = trimesh.creation.icosphere(subdivisions=1)  # loads numba's on-disk cache
    convex_vertices("centroid", tiny.vertices, tiny.faces, 0.9 * tiny.vertices, 0.08)
    points, faces, centroids = inputs(name, folder)
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    steps = stages(points, faces, centroids)
    wall = {label: [] for label, _ in steps}
    cpu = {label: [] for label, _ in steps}
    for _ in range(repeats):
        for label, thunk in steps:
            start, start_cpu = time.perf_counter(), time.process_time()
            thunk()
            wall[label].append(time.perf_counter() - start)
            cpu[label].append(time.process_time() - start_cpu)
    return {
        "mesh": name,
        "vertices": len(points),
        "faces": len(faces),
        "wall": {k: float(np.median(v)) for k, v in wall.items()},
        "cpu": {k: float(np.median(v)) for k, v in cpu.items()},
        "maxrss_gb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6,
        "maxrss_before_gb": before / 1e6,
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--meshes", nargs="*", default=["low", "normal", "high"])
    parser.add_argument("--sizes", type=int, nargs="*", default=[])
    parser.add_argument("--cone", type=int, nargs="*", default=[], help="cones of N side faces")
    parser.add_argument("--repeats", type=int, default=20)
    parser.add_argument("--memory", action="store_true", help="one fresh process per mesh")
    parser.add_argument("--json", type=Path, help="also write the rows here")
    args = parser.parse_args(argv)
    names = [*args.meshes, *map(str, args.sizes), *(f"cone{n}" for n in args.cone)]
    rows = []
    with tempfile.TemporaryDirectory() as scratch:
        for name in names:
            if args.memory:
                done = subprocess.run(
                    [sys.executable, __file__, "_worker", name, str(args.repeats), scratch],
                    capture_output=True,
                    text=True,
                    check=True,
                )
                row = json.loads(done.stdout.strip().splitlines()[-1])
            else:
                row = run(name, args.repeats, Path(scratch))
            rows.append(row)
            cells = ", ".join(
                f"{label} {row['wall'][label] * 1e3:.1f} ({row['cpu'][label] * 1e3:.1f})"
                for label in row["wall"]
            )
            memory = f"; peak {row['maxrss_gb']:.2f} GB" if args.memory else ""
            print(f"{name} ({row['vertices']} vertices): ms wall (cpu): {cells}{memory}")
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "_worker":
        print(json.dumps(run(sys.argv[2], int(sys.argv[3]), Path(sys.argv[4]))))
        raise SystemExit(0)
    raise SystemExit(main())
