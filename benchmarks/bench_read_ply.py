"""Reading a large PLY: dentopo's strict reader against trimesh's, binary and ASCII.

Usage (from the repository root, with the project's environment)::

    .venv/bin/python benchmarks/bench_read_ply.py      # rings=300, subdivided: 1.08M vertices
    .venv/bin/python benchmarks/bench_read_ply.py --rings 100 --repeat 3

The mesh is the sample tooth (``dentopo.samples.tooth``) subdivided once,
written by trimesh as binary and as ASCII PLY to a temporary directory.  For
each file, the median of ``--repeat`` runs in this process of:

* ``read_ply``: dentopo's strict reader alone (header, data, every check);
* ``load_mesh``: what every path goes through: read, validate, merge vertices
  with the relative tolerance;
* ``trimesh.load``: trimesh's default (its reader, then merging vertices);
* ``trimesh.load(process=False)``: trimesh's reader alone (no check, no merge).

It also checks that ``load_mesh`` and ``trimesh.load`` give identical arrays.
Nothing here is a test: timings depend on the machine and its load.
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np
import trimesh

from dentopo.mesh import load_mesh, read_ply
from dentopo.samples import tooth


def median_seconds(function, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rings", type=int, default=300)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    mesh = tooth(rings=args.rings).subdivide()
    print(f"{len(mesh.vertices)} vertices, {len(mesh.faces)} faces")
    with tempfile.TemporaryDirectory() as folder:
        for encoding in ("binary", "ascii"):
            path = Path(folder) / f"big_{encoding}.ply"
            path.write_bytes(mesh.export(file_type="ply", encoding=encoding))
            ours, theirs = load_mesh(path), trimesh.load(path)
            same = np.array_equal(ours.vertices, theirs.vertices) and np.array_equal(
                ours.faces, theirs.faces
            )
            times = {
                "read_ply": median_seconds(lambda p=path: read_ply(p), args.repeat),
                "load_mesh": median_seconds(lambda p=path: load_mesh(p), args.repeat),
                "trimesh.load": median_seconds(lambda p=path: trimesh.load(p), args.repeat),
                "trimesh.load(process=False)": median_seconds(
                    lambda p=path: trimesh.load(p, process=False), args.repeat
                ),
            }
            size = path.stat().st_size / 1e6
            print(f"{encoding} ({size:.0f} MB), identical to trimesh.load: {same}")
            for name, seconds in times.items():
                print(f"  {name:30s} {seconds:7.3f} s")


if __name__ == "__main__":
    main()
