"""Preparing a 1M-face scan to 10,000 faces, against reading it and decimating it bare.

Usage (from the repository root, with the project's environment)::

    .venv/bin/python benchmarks/bench_prepare.py                 # 1M faces, 3 runs each
    .venv/bin/python benchmarks/bench_prepare.py --scan-faces 200000 --repeat 5

The scan is a shared crown (``--crown``, default ``high`` from the shared
meshes beside the checkout; the sample tooth without them) refined by
longest-edge bisection (:func:`dentopo.study.refine`) to ``--scan-faces``
faces, turned to a random pose, with three loose specks beside it (what a
scanner leaves), written as binary PLY to a temporary folder.  Then, each as
a fresh Python process (imports, reading and everything included), run in
turn ``--repeat`` times, the median wall time of:

* ``prepare``: the command ``dentopo prepare scan.ply -o out --faces 10000``
  (clean keeping the largest piece, orient, decimate keeping the base, and
  writing the PLY and its record);
* ``baseline``: ``trimesh.load(scan)`` and ``fast_simplification.simplify``
  to the same count, nothing else (no cleaning, no orienting, the base not
  kept).

It prints both and their ratio (the issue's target: at most 3), then with
``--profile`` the time of each stage of the pipeline in this process.
Nothing here is a test: timings depend on the machine and its load.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import trimesh

SHARED_MESHES = Path(__file__).resolve().parents[2] / "shared" / "data" / "meshes"

PREPARE = """
import sys
from dentopo.cli import main
scan, out, faces = sys.argv[1], sys.argv[2], sys.argv[3]
sys.exit(main(["prepare", scan, "-o", out, "--faces", faces, "-q"]))
"""

BASELINE = """
import sys
import fast_simplification, trimesh
scan, faces = sys.argv[1], int(sys.argv[3])
mesh = trimesh.load(scan)
fast_simplification.simplify(mesh.vertices, mesh.faces, target_count=faces)
"""


def make_scan(crown: str, faces: int, seed: int = 1) -> trimesh.Trimesh:
    """A refined crown in a random pose with three specks beside it."""
    from dentopo.study import refine

    path = SHARED_MESHES / f"{crown}.ply"
    if path.exists():
        base = trimesh.load(path, process=False)
    else:
        from dentopo.samples import tooth

        print(f"(no shared mesh at {path}: the sample tooth instead)")
        base = tooth(rings=60)
    v, f = refine(np.asarray(base.vertices), np.asarray(base.faces), faces)
    rng = np.random.default_rng(seed)
    extent = float(np.ptp(v, axis=0).max())
    pieces = [trimesh.Trimesh(v, f, process=False)]
    for k in range(3):
        speck = trimesh.creation.icosphere(subdivisions=1, radius=0.01 * extent)
        speck.apply_translation(v.max(axis=0) + extent * (0.1 + 0.05 * k))
        pieces.append(speck)
    scan = trimesh.util.concatenate(pieces)
    rotation = trimesh.transformations.random_rotation_matrix(rng.random(3))
    scan.apply_transform(rotation)
    return scan


def fresh_process_seconds(code: str, *args: str) -> float:
    start = time.perf_counter()
    subprocess.run([sys.executable, "-c", code, *args], check=True)
    return time.perf_counter() - start


def profile(scan_path: Path, faces: int, orient: str) -> None:
    """Each stage of the pipeline, timed in this process."""
    from dentopo.mesh import clean, load_mesh, merge_vertices
    from dentopo.prepare import _clean, _decimate, _orient

    def timed(label, function, *args, **kwargs):
        start = time.perf_counter()
        out = function(*args, **kwargs)
        print(f"  {label:34s} {time.perf_counter() - start:7.2f} s")
        return out

    mesh = timed("read (load_mesh)", load_mesh, scan_path)
    v, f = np.asarray(mesh.vertices), np.asarray(mesh.faces)
    mv, mf = timed("clean: merge vertices", merge_vertices, v, f)
    cleaned = timed("clean: clean (holes, degenerate)", clean, mv, mf)
    cv, cf = np.asarray(cleaned.vertices), np.asarray(cleaned.faces)
    timed("clean: connected pieces", _clean.face_pieces, cf, len(cv))
    out = timed("clean step (all of it)", _clean.run, v, f, keep="largest")
    if orient != "none":
        out = timed(
            "orient step", _orient.run, out.vertices, out.faces, mode=orient, up=None, spin="none"
        )
    timed("decimate step", _decimate.run, out.vertices, out.faces, faces_target=faces)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--crown", default="high", help="a shared mesh's name")
    parser.add_argument("--scan-faces", type=int, default=1_000_000)
    parser.add_argument("--faces", type=int, default=10_000, help="the target")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--profile", action="store_true", help="time each stage too")
    args = parser.parse_args()
    orient = "occlusal"
    with tempfile.TemporaryDirectory() as folder:
        scan_path = Path(folder) / "scan.ply"
        scan = make_scan(args.crown, args.scan_faces)
        scan_path.write_bytes(scan.export(file_type="ply"))
        size = scan_path.stat().st_size / 1e6
        print(f"scan: {len(scan.faces)} faces, {len(scan.vertices)} vertices ({size:.0f} MB)")
        out_dir = Path(folder) / "out"
        out = str(out_dir / "scan.ply")
        argv = (str(scan_path), str(out_dir), str(args.faces))
        fresh_process_seconds(PREPARE, *argv)  # warm the disk cache and numba's kernel cache
        times = {"prepare": [], "baseline": []}
        for _ in range(args.repeat):
            times["prepare"].append(fresh_process_seconds(PREPARE, *argv))
            times["baseline"].append(fresh_process_seconds(BASELINE, *argv))
        prepared = trimesh.load(out, process=False)
        print(f"prepared: {len(prepared.faces)} faces (target {args.faces})")
        ours = statistics.median(times["prepare"])
        theirs = statistics.median(times["baseline"])
        print(f"  prepare  (fresh process)          {ours:7.2f} s")
        print(f"  baseline (trimesh + fast-simpl.)  {theirs:7.2f} s")
        print(f"  ratio                             {ours / theirs:7.2f}  (target: at most 3)")
        if args.profile:
            print("stages, in this process:")
            profile(scan_path, args.faces, orient)


if __name__ == "__main__":
    main()
