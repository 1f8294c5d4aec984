"""Benchmark dentopo against the published signDNE 0.1.4 on the same meshes, in the same run.

Usage (from the repository root, with the project's environment)::

    .venv/bin/python benchmarks/bench_published.py                 # normal and high
    .venv/bin/python benchmarks/bench_published.py --meshes low normal high noise1 --repeat 5

The published package is installed from PyPI (``pip install signDNE==0.1.4``) into its own
environment, ``benchmarks/.published-env``, the first time this runs.  It is used only through its
public entry point, ``signDNE.signDNE(mesh)``; its outputs are identified by comparing them with
ours (see ``PUBLISHED_OUTPUTS``) and that identification is checked on every call.

Every run of either implementation is a fresh subprocess that imports its package, loads the
mesh with ``trimesh.load`` defaults, makes one warm-up call on an open dome of 2,165 vertices (for
ours this loads numba's on-disk compilation cache for every kernel a crown's call uses,
including the exact winding-number fallback; the published package gets the same warm-up
call), and then times exactly one call on the mesh with
``time.perf_counter``: imports, mesh loading and the warm-up are excluded.  Memory is the
process's peak resident set size (``ru_maxrss``) and its increase over the resident set size
right before the timed call.  Reported numbers are medians over the repetitions.

The shared meshes are read from ``../shared/data/meshes`` beside the checkout (``--data`` to
change).  Nothing here is a test: timings depend on the machine and its load.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
DEFAULT_DATA = ROOT.parent / "shared" / "data" / "meshes"
DEFAULT_ENV = HERE / ".published-env"
PUBLISHED_REQUIREMENT = "signDNE==0.1.4"

#: The scalar outputs, in our names (relative differences are reported for these).
SCALARS = (
    "dne",
    "positive_dne",
    "negative_dne",
    "surface_area",
    "positive_surface_area",
    "negative_surface_area",
)
PER_VERTEX = ("local_curvature", "local_dne")

#: What the published ``signDNE(mesh)`` returns, position by position.  Its documentation lists
#: ``local_curvature`` first; calling it and comparing with our outputs shows that position 0 is
#: the area-weighted ``local_dne`` and position 1 the ``local_curvature``.  ``_published_run``
#: re-checks this on every call (``local_dne / local_curvature`` is the vertex area, and the
#: scalars add up) and stops with a message if a future version returns something else.
PUBLISHED_OUTPUTS = ("local_dne", "local_curvature", *SCALARS)


class BenchmarkError(RuntimeError):
    """A problem the user can fix (missing data, no network, ...): reported without traceback."""


# --------------------------------------------------------------------------------------------
# worker side: runs in a fresh interpreter, in either environment
# --------------------------------------------------------------------------------------------


def _rss_kb() -> int:
    """Current resident set size of this process, in KiB (Linux ``/proc``; 0 if unavailable)."""
    try:
        with open("/proc/self/status") as status:
            for line in status:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1])
    except OSError:
        pass
    return 0


def _maxrss_kb() -> int:
    import resource

    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return peak // 1024 if sys.platform == "darwin" else peak  # macOS reports bytes


def _warm_up_mesh():
    """An open dome of 2,165 vertices (an icosphere cut above its equator) to warm up.

    It takes the code paths a crown of the shared set takes (ours: the inside test in
    parallel from 2,048 points on, the hole's long cap triangles cut into strips), so the
    warm-up loads every compiled kernel the timed call uses; and it is small, so quick.
    """
    import trimesh

    sphere = trimesh.creation.icosphere(subdivisions=4)
    keep = sphere.vertices[sphere.faces][:, :, 2].max(axis=1) < 0.7
    return trimesh.Trimesh(sphere.vertices, sphere.faces[keep], process=True)


def _published_run(mesh):
    import numpy as np
    from signDNE import signDNE

    returned = signDNE(mesh.copy())  # it rescales the mesh it is given, so hand it a copy
    if not isinstance(returned, tuple) or len(returned) != len(PUBLISHED_OUTPUTS):
        raise BenchmarkError(
            f"the published signDNE returned {type(returned).__name__} of length "
            f"{len(returned) if hasattr(returned, '__len__') else '?'}; expected a tuple of "
            f"{len(PUBLISHED_OUTPUTS)} ({', '.join(PUBLISHED_OUTPUTS)})"
        )
    return dict(zip(PUBLISHED_OUTPUTS, (np.asarray(value) for value in returned), strict=True))


def _check_published_outputs(out, mesh) -> None:
    """Check that the published outputs mean what ``PUBLISHED_OUTPUTS`` says they mean."""
    import numpy as np

    k, w = out["local_curvature"], out["local_dne"]
    problems = []
    if k.shape != w.shape or k.ndim != 1:
        problems.append(f"per-vertex shapes {k.shape} and {w.shape}")
    else:
        if not np.isclose(np.abs(w).sum(), out["dne"], rtol=1e-9, atol=0):
            problems.append("dne is not the sum of |local_dne|")
        if not np.isclose(out["positive_dne"] + out["negative_dne"], out["dne"], rtol=1e-9):
            problems.append("positive_dne + negative_dne != dne")
        # local_dne is local_curvature times the unit-scale vertex area, so the ratio is in (0, 1)
        nonzero = k != 0
        ratio = w[nonzero] / k[nonzero]
        if not (np.all(ratio > 0) and np.all(ratio < 1)):
            problems.append("local_dne / local_curvature is not a vertex area")
        parts = out["positive_surface_area"] + out["negative_surface_area"]
        if not np.isclose(parts, out["surface_area"], rtol=1e-9):
            problems.append("positive + negative surface_area != surface_area")
        if not np.isclose(out["surface_area"], mesh.area, rtol=0.1):
            problems.append(f"surface_area {out['surface_area']} is not the mesh area {mesh.area}")
    if problems:
        raise BenchmarkError(
            "the published package's outputs are not in the expected order "
            f"({', '.join(PUBLISHED_OUTPUTS)}): " + "; ".join(problems)
        )


def _ours_run(mesh):
    import numpy as np

    from dentopo import ariaDNE

    result = ariaDNE(mesh)
    out = {name: np.asarray(getattr(result, name)) for name in PER_VERTEX + SCALARS}
    out["method"] = np.asarray(str(getattr(result, "method", "")))  # kernel sums: exact or fast
    return out


class _StageTimer:
    """Wraps the stage functions that ``dentopo.ariaDNE`` calls and sums their wall time.

    Each function is replaced, for the rest of the worker process, in the modules that call it,
    so the timed call runs the real code path with one ``perf_counter`` pair per stage.
    """

    #: (stage label, function name), looked up in ``MODULES``
    STAGES = (
        ("prepare", "prepare"),
        ("kernel", "euclidean_moments"),
        ("kernel", "geodesic_moments"),
        ("kernel", "fast_euclidean_moments"),
        ("eigen", "unsigned_bending"),
        ("close holes", "close_holes"),
        ("inside test", "inside"),
    )
    MODULES = (
        "dentopo.ariadne._ariadne",
        "dentopo.sign._methods",
        "dentopo.ariadne._kernel",
        "dentopo.ariadne._fastgauss",
    )

    def __init__(self):
        self.seconds: dict[str, float] = {}
        self.missing: list[str] = []

    def install(self) -> None:
        import importlib

        modules = []
        for module_name in self.MODULES:
            try:
                modules.append(importlib.import_module(module_name))
            except ImportError:
                continue
        for label, name in self.STAGES:
            found = False
            for module in modules:
                function = getattr(module, name, None)
                if callable(function):
                    setattr(module, name, self._wrap(label, function))
                    found = True
            if not found:
                self.missing.append(name)

    def _wrap(self, label, function):
        def timed(*args, **kwargs):
            start = time.perf_counter()
            try:
                return function(*args, **kwargs)
            finally:
                elapsed = time.perf_counter() - start
                self.seconds[label] = self.seconds.get(label, 0.0) + elapsed

        return timed


def _preload_exact_fallback(mesh) -> None:
    """Load the compiled exact winding-number fallback too (best effort, private name).

    The warm-up call only runs it if some centroid is ambiguous; a mesh that needs it would
    otherwise pay for loading it from numba's cache inside the timed call.
    """
    import numpy as np

    try:
        from dentopo.sign._winding import exact_winding_number
    except ImportError:
        return
    exact_winding_number(np.asarray(mesh.vertices), np.asarray(mesh.faces), np.zeros((1, 3)))


def worker(impl: str, mesh_path: str, out_path: str, stages: bool) -> None:
    """Time one call of one implementation on one mesh; write everything to ``out_path``."""
    import warnings

    warnings.simplefilter("ignore")  # the published package warns about PLY metadata
    import numpy as np
    import trimesh

    try:
        if impl == "published":
            import signDNE  # noqa: F401
        else:
            import dentopo  # noqa: F401
    except ImportError as exc:
        where = sys.executable
        raise BenchmarkError(f"cannot import the {impl} package in {where}: {exc}") from exc
    run = _published_run if impl == "published" else _ours_run

    start = time.perf_counter()
    mesh = trimesh.load(mesh_path)
    load_seconds = time.perf_counter() - start

    tiny = _warm_up_mesh()
    run(tiny)  # warm-up: loads numba's compiled-code cache (ours), every kernel the call uses
    if impl == "ours":
        _preload_exact_fallback(tiny)
    timer = None
    if stages and impl == "ours":
        timer = _StageTimer()
        timer.install()

    rss_before = _rss_kb()
    maxrss_before = _maxrss_kb()
    cpu_start = time.process_time()
    start = time.perf_counter()
    out = run(mesh)
    seconds = time.perf_counter() - start
    cpu_seconds = time.process_time() - cpu_start
    maxrss_after = _maxrss_kb()

    if impl == "published":
        _check_published_outputs(out, mesh)
    meta = {
        "seconds": seconds,
        "cpu_seconds": cpu_seconds,
        "load_seconds": load_seconds,
        "rss_before_kb": rss_before,
        "maxrss_before_kb": maxrss_before,
        "maxrss_after_kb": maxrss_after,
        "input_vertices": len(mesh.vertices),
        "stages": timer.seconds if timer else {},
        "stages_missing": timer.missing if timer else [],
    }
    np.savez(out_path, meta=np.array(json.dumps(meta)), **out)


# --------------------------------------------------------------------------------------------
# driver side: runs in the project's environment
# --------------------------------------------------------------------------------------------


def _env_python(env: Path) -> Path:
    return env / ("Scripts/python.exe" if os.name == "nt" else "bin/python")


def ensure_published_env(env: Path) -> Path:
    """Create ``env`` with the published package if it is not there yet; return its python."""
    python = _env_python(env)
    code = "import signDNE, importlib.metadata as m; print(m.version('signDNE'))"
    check = [str(python), "-c", code]
    if python.exists():
        done = subprocess.run(check, capture_output=True, text=True, cwd=tempfile.gettempdir())
        if done.returncode == 0 and done.stdout.strip() == PUBLISHED_REQUIREMENT.split("==")[1]:
            return python
    print(f"installing {PUBLISHED_REQUIREMENT} into {env} (once; about a minute) ...", flush=True)
    steps = []
    if not python.exists():
        steps.append([sys.executable, "-m", "venv", str(env)])
    steps.append([str(python), "-m", "pip", "install", "-q", PUBLISHED_REQUIREMENT])
    for step in steps:
        done = subprocess.run(step, capture_output=True, text=True)
        if done.returncode != 0:
            tail = "\n".join((done.stderr or done.stdout).strip().splitlines()[-8:])
            raise BenchmarkError(
                f"could not set up the published package ({' '.join(step)} failed; "
                f"is PyPI reachable?):\n{tail}"
            )
    done = subprocess.run(check, capture_output=True, text=True, cwd=tempfile.gettempdir())
    if done.returncode != 0:
        raise BenchmarkError(
            f"{PUBLISHED_REQUIREMENT} was installed into {env} but cannot be imported:\n"
            + done.stderr.strip()[-1000:]
        )
    return python


def run_once(python, impl, mesh_path, scratch, *, stages=False):
    """Run one fresh worker subprocess; return (outputs, meta)."""
    import numpy as np

    out_path = Path(scratch) / f"{impl}-{os.getpid()}-{time.monotonic_ns()}.npz"
    command = [str(python), str(Path(__file__).resolve()), "_worker", impl, str(mesh_path)]
    command += [str(out_path)] + (["--stages"] if stages else [])
    # run outside the checkout so that neither environment picks up files from the tree
    done = subprocess.run(command, capture_output=True, text=True, cwd=scratch)
    if done.returncode != 0:
        message = done.stderr.strip().splitlines()
        raise BenchmarkError(
            f"the {impl} run on {Path(mesh_path).name} failed:\n" + "\n".join(message[-12:])
        )
    with np.load(out_path) as data:
        meta = json.loads(str(data["meta"]))
        outputs = {name: data[name] for name in data.files if name != "meta"}
    out_path.unlink()
    return outputs, meta


def compare(published, ours):
    """Largest differences between the two implementations' outputs."""
    import numpy as np

    diff = {}
    for name in SCALARS:
        a, b = float(ours[name]), float(published[name])
        diff[name] = abs(a - b) / abs(b) if b != 0 else abs(a - b)
    k_ours, k_pub = ours["local_curvature"], published["local_curvature"]
    if k_ours.shape != k_pub.shape:
        diff["shape_mismatch"] = f"{k_ours.shape} vs {k_pub.shape}"
        return diff
    flipped = np.flatnonzero((k_ours >= 0) != (k_pub >= 0))
    same = np.ones(len(k_ours), dtype=bool)
    same[flipped] = False
    for name in PER_VERTEX:
        a, b = ours[name], published[name]
        diff[name + "_magnitude"] = float(np.max(np.abs(np.abs(a) - np.abs(b))))
        diff[name] = float(np.max(np.abs(a[same] - b[same]), initial=0.0))
    diff["sign_differences"] = flipped.tolist()
    return diff


def known_published_errors(data: Path) -> dict[str, list[int]]:
    """Vertices where the reference data records the published sign as wrong, by mesh name."""
    reference = data.parent / "reference" / "signdne_0.1.4.json"
    try:
        meshes = json.loads(reference.read_text())["meshes"]
    except (OSError, ValueError, KeyError):
        return {}
    return {name: list(entry.get("published_sign_wrong_at", [])) for name, entry in meshes.items()}


def run_to_run(runs):
    """How much one implementation's outputs vary between its runs on one mesh."""
    import numpy as np

    first = runs[0][0]
    flipped, largest = set(), 0.0
    for out, _ in runs[1:]:
        a, b = first["local_curvature"], out["local_curvature"]
        flipped.update(np.flatnonzero((a >= 0) != (b >= 0)).tolist())
        largest = max(largest, float(np.max(np.abs(np.abs(a) - np.abs(b)))))
        for name in SCALARS:
            largest = max(largest, abs(float(first[name]) - float(out[name])))
    return {"sign_flips": sorted(flipped), "largest_difference": largest}


def _sign_notes(results, known) -> list[str]:
    notes = []
    for name, entry in results.items():
        diff = entry["diff"]
        if "sign_differences" not in diff:
            continue
        expected = set(known.get(name, []))
        for vertex in sorted(expected):
            ours = entry["our_signs"].get(str(vertex), "?")
            published = entry["published_signs"].get(str(vertex), "?")
            notes.append(
                f"{name} vertex {vertex}: the reference data records the published ray test as "
                f"wrong here; ours says {ours} (exact winding number), the published runs said "
                f"{published}."
            )
        unexpected = sorted(set(diff["sign_differences"]) - expected)
        if unexpected:
            notes.append(f"{name}: sign differences not known from the reference: {unexpected}")
        for who in ("published", "ours"):
            variation = entry[f"{who}_run_to_run"]
            if variation["sign_flips"] or variation["largest_difference"] > 0:
                notes.append(
                    f"{name}: {who} outputs vary between runs: signs at vertices "
                    f"{variation['sign_flips']}, other outputs by up to "
                    f"{variation['largest_difference']:.1e}."
                )
    return notes


def _median(values):
    return statistics.median(values)


def summarise(runs):
    """Medians over the runs of one implementation on one mesh."""
    metas = [meta for _, meta in runs]
    return {
        "seconds": _median([m["seconds"] for m in metas]),
        "seconds_all": [m["seconds"] for m in metas],
        "cpu_seconds": _median([m["cpu_seconds"] for m in metas]),
        "peak_mb": _median([m["maxrss_after_kb"] for m in metas]) / 1024,
        "increase_mb": _median([m["maxrss_after_kb"] - m["rss_before_kb"] for m in metas]) / 1024,
        "runs": len(metas),
    }


def _format_table(header, rows):
    widths = [max(len(str(cell)) for cell in column) for column in zip(header, *rows, strict=True)]
    line = "| " + " | ".join(str(h).ljust(w) for h, w in zip(header, widths, strict=True)) + " |"
    rule = "|" + "|".join("-" * (w + 2) for w in widths) + "|"
    body = []
    for row in rows:
        cells = (str(c).rjust(w) for c, w in zip(row, widths, strict=True))
        body.append("| " + " | ".join(cells) + " |")
    return "\n".join([line, rule, *body])


def _g(value):
    return "0" if value == 0 else f"{value:.1e}"


def report(results, args):
    timing_rows, diff_rows = [], []
    for name, entry in results.items():
        pub, ours, diff = entry["published"], entry["ours"], entry["diff"]
        timing_rows.append(
            [
                name,
                f"{entry['vertices']:,}",
                f"{pub['seconds']:.2f}",
                f"{ours['seconds']:.3f}",
                f"{pub['seconds'] / ours['seconds']:.0f}x",
                f"{pub['cpu_seconds']:.2f}",
                f"{ours['cpu_seconds']:.3f}",
                f"{pub['peak_mb']:.0f} (+{pub['increase_mb']:.0f})",
                f"{ours['peak_mb']:.0f} (+{ours['increase_mb']:.0f})",
            ]
        )
        if "shape_mismatch" in diff:
            diff_rows.append([name, *["-"] * 9, f"vertex counts differ: {diff['shape_mismatch']}"])
            continue
        signs = diff["sign_differences"]
        shown = ", ".join(map(str, signs[:10])) + (" ..." if len(signs) > 10 else "")
        diff_rows.append(
            [
                name,
                *(_g(diff[s]) for s in SCALARS),
                _g(diff["local_curvature_magnitude"]),
                _g(diff["local_curvature"]),
                _g(diff["local_dne"]),
                f"{len(signs)}" + (f" (vertex {shown})" if signs else ""),
            ]
        )
    print()
    print(
        f"Compute time in seconds (median of {args.repeat} runs of ours, "
        f"{args.repeat_published} of the published package; each run a fresh process, "
        "imports, mesh loading and one warm-up call on a 2,165-vertex open dome excluded — the "
        "warm-up loads numba's on-disk compilation cache for ours; the published package gets "
        "one too); "
        "peak memory of the process in MB "
        "(ru_maxrss), in brackets its increase over the resident set right before the call. "
        "CPU s is the process's CPU time during the call, all threads (ours runs numba's "
        "parallel loops on every core; the published package is mostly single-threaded), a "
        "steadier measure than wall time on a shared machine."
    )
    print()
    print(
        _format_table(
            [
                "mesh",
                "vertices",
                "published s",
                "ours s",
                "speed-up",
                "published CPU s",
                "ours CPU s",
                "published MB",
                "ours MB",
            ],
            timing_rows,
        )
    )
    methods = {name: entry["method"] for name, entry in results.items() if entry.get("method")}
    if methods:
        print("our kernel sums: " + ", ".join(f"{k} {v}" for k, v in methods.items()))
    print()
    print(
        "Largest differences, ours vs published: totals relative; per-vertex absolute "
        "(|k|: magnitudes at all vertices; k and local_dne: signed, where the signs agree); "
        "signs: vertices (0-based) whose sign differs."
    )
    print()
    print(
        _format_table(
            [
                "mesh",
                "dne",
                "pos dne",
                "neg dne",
                "area",
                "pos area",
                "neg area",
                "|k|",
                "k",
                "local_dne",
                "signs differ",
            ],
            diff_rows,
        )
    )


def report_stages(results):
    rows = []
    for name, entry in results.items():
        stages = entry.get("stages")
        if not stages:
            continue
        total = stages["total"]
        accounted = sum(v for k, v in stages.items() if k not in ("total", "load"))
        cells = [stages.get(label, float("nan")) for label in _STAGE_LABELS]
        rows.append(
            [
                name,
                f"{stages['load'] * 1000:.0f}",
                *(f"{c * 1000:.0f}" for c in cells),
                f"{(total - accounted) * 1000:.0f}",
                f"{total * 1000:.0f}",
            ]
        )
    if not rows:
        return
    print()
    print(
        "Where our time goes, ms (the stage-timed run with the median total; load is "
        "trimesh.load and is not part of the compute time; other = validation, centroids, totals):"
    )
    print()
    print(_format_table(["mesh", "load", *_STAGE_LABELS, "other", "total"], rows))
    missing = {m for entry in results.values() for m in entry.get("stages_missing", [])}
    missing -= {"geodesic_moments", "fast_euclidean_moments"}
    if missing:
        print(f"(stages not found in dentopo, counted in 'other': {sorted(missing)})")


_STAGE_LABELS = ("prepare", "kernel", "eigen", "close holes", "inside test")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        description="Time dentopo against the published signDNE 0.1.4 and compare every output."
    )
    parser.add_argument(
        "--meshes",
        nargs="+",
        default=["normal", "high"],
        metavar="NAME",
        help="shared mesh names (file stems in --data), default: normal high",
    )
    parser.add_argument("--data", type=Path, default=DEFAULT_DATA, help="folder of the meshes")
    parser.add_argument("--repeat", type=int, default=3, help="runs of ours per mesh (default 3)")
    parser.add_argument(
        "--repeat-published",
        type=int,
        default=1,
        help="runs of the published package per mesh (default 1; ~13 s on normal, ~58 s on high)",
    )
    parser.add_argument(
        "--no-stages", action="store_true", help="skip the per-stage breakdown of ours"
    )
    parser.add_argument("--env", type=Path, default=DEFAULT_ENV, help="published package's venv")
    parser.add_argument("--json", type=Path, help="also write all measurements to this JSON file")
    args = parser.parse_args(argv)
    if args.repeat < 1 or args.repeat_published < 1:
        parser.error("--repeat and --repeat-published must be at least 1")

    if not args.data.is_dir():
        raise BenchmarkError(
            f"shared mesh data not found at {args.data} (expected ../shared/data/meshes beside "
            "the checkout; pass --data)"
        )
    paths = {name: args.data / f"{name}.ply" for name in args.meshes}
    absent = [str(p) for p in paths.values() if not p.is_file()]
    if absent:
        available = sorted(p.stem for p in args.data.glob("*.ply"))
        raise BenchmarkError(f"mesh files not found: {absent}; available: {available}")
    published_python = ensure_published_env(args.env)

    load = os.getloadavg() if hasattr(os, "getloadavg") else None
    print(
        f"machine: {platform.machine()}, {os.cpu_count()} cores, Python "
        f"{platform.python_version()}; load average at start: "
        + (", ".join(f"{x:.2f}" for x in load) if load else "n/a")
    )
    known = known_published_errors(args.data)
    results = {}
    with tempfile.TemporaryDirectory(prefix="bench-dentopo-") as scratch:
        for name, path in paths.items():
            print(f"{name}: published x{args.repeat_published}", end="", flush=True)
            pub_runs = [
                run_once(published_python, "published", path, scratch)
                for _ in range(args.repeat_published)
            ]
            print(f", ours x{args.repeat}", end="", flush=True)
            our_runs = [run_once(sys.executable, "ours", path, scratch) for _ in range(args.repeat)]
            entry = {
                "vertices": len(our_runs[0][0]["local_curvature"]),
                "published": summarise(pub_runs),
                "ours": summarise(our_runs),
                # the first run of each; variation between runs is reported separately
                "diff": compare(pub_runs[0][0], our_runs[0][0]),
                "method": str(our_runs[0][0].get("method", "")),
            }
            for who, label, runs in (
                ("published", "published_signs", pub_runs),
                ("ours", "our_signs", our_runs),
            ):
                entry[label] = {
                    str(v): ", ".join(
                        "+" if out["local_curvature"][v] >= 0 else "-" for out, _ in runs
                    )
                    for v in known.get(name, [])
                    if v < entry["vertices"]
                }
                entry[f"{who}_run_to_run"] = run_to_run(runs)
            if not args.no_stages:
                print(", ours with stage timers", end="", flush=True)
                stage_runs = [
                    run_once(sys.executable, "ours", path, scratch, stages=True)
                    for _ in range(args.repeat)
                ]
                # the breakdown of the run with the median total, so that the stages add up
                metas = sorted((meta for _, meta in stage_runs), key=lambda m: m["seconds"])
                middle = metas[(len(metas) - 1) // 2]
                entry["stages"] = dict(middle["stages"])
                entry["stages"]["load"] = middle["load_seconds"]
                entry["stages"]["total"] = middle["seconds"]
                entry["stages_missing"] = metas[0]["stages_missing"]
            print(f": {entry['published']['seconds']:.1f} s vs {entry['ours']['seconds']:.3f} s")
            results[name] = entry
    report(results, args)
    for note in _sign_notes(results, known):
        print(note)
    report_stages(results)
    load = os.getloadavg() if hasattr(os, "getloadavg") else None
    if load:
        print(f"\nload average at end: {', '.join(f'{x:.2f}' for x in load)}")
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(results, indent=1))
    return 0


def _cli() -> int:
    try:
        if len(sys.argv) > 1 and sys.argv[1] == "_worker":
            worker_args = argparse.ArgumentParser(prog="bench_published.py _worker")
            worker_args.add_argument("impl", choices=["published", "ours"])
            worker_args.add_argument("mesh")
            worker_args.add_argument("out")
            worker_args.add_argument("--stages", action="store_true")
            parsed = worker_args.parse_args(sys.argv[2:])
            worker(parsed.impl, parsed.mesh, parsed.out, parsed.stages)
            return 0
        return main()
    except BenchmarkError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return 130


if __name__ == "__main__":
    sys.exit(_cli())
