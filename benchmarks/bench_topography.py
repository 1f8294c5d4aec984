"""Benchmark molaR 6.0's topography metrics as dentopo computes them against molaR's own seconds.

Usage (from the repository root, with the project's environment)::

    .venv/bin/python benchmarks/bench_topography.py                  # normal.ply
    .venv/bin/python benchmarks/bench_topography.py --meshes normal high low --repeat 31

molaR is an R package and is not run here: its seconds come from the reference file
``../shared/data/reference/molaR_6.0_topography.csv`` (columns ``s_*``), measured by molaR 6.0 on
a 2-core machine with its defaults, one metric call on a mesh already read: molaR's functions
take a ``mesh3d`` that its reader has already read *and cleaned* (zero-area faces and unused
vertices dropped, vertex normals attached), so molaR's seconds cover the metric alone.

Ours are timed two ways, each the median over ``--repeat`` rounds after one warm-up round, every
round calling every metric in turn (so that the load of a busy machine spreads over all of them),
each call timed in CPU seconds of this process (``time.process_time``; every metric here is
single-threaded):

* ``mesh``: the metric called on a ``trimesh.Trimesh`` already in memory (``dentopo.load_mesh``
  once).  Each call includes everything dentopo does to a mesh it is given and molaR does not
  count: the input checks and copies, molaR's cleaning, and (slope, OPC, OPCR, RFI) the
  orientation check, which molaR does not have.  This is the ratio printed and the conservative
  one.
* ``surface``: the metric called on a :class:`dentopo.topography.Surface` already prepared, with
  its orientation already found, and nothing else kept with it (made afresh, untimed, before
  every call; what a Surface keeps for later calls, such as OPC's edge incidence, is computed
  in the call): what each metric adds in a batch row, where the surface is prepared and
  checked once for all of molaR's metrics.  This is the closest match to what molaR's seconds
  cover (molaR's reader cleaned its mesh; molaR has no orientation check).

The ratio is molaR's seconds divided by ours; the target of issue 13 is at least 100 for every
metric on ``normal``.  Where molaR stopped (RFI at alpha 0.075 on a pinched footprint, ``NA``)
there is no ratio.  Every value is also compared with molaR's, so a fast wrong answer shows.

The reference crowns point to -z and molaR measured them as they lie (it never reorients a mesh),
so the metrics that look at the orientation (slope, OPC, OPCR, RFI) are called with
``orient="as-is"``: the default ``"auto"`` would turn them over first and measure another crown
(a slope of 74 degrees where molaR's is 106).
Nothing here is a test: timings depend on the machine and its load.
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import json
import math
import os
import platform
import statistics
import sys
import time
import warnings
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

import dentopo  # noqa: E402
from dentopo.topography import (  # noqa: E402
    Surface,
    classic_dne,
    opc,
    opcr,
    prepare_surface,
    rfi,
    slope,
)

SHARED = ROOT.parent / "shared" / "data"

#: the crowns measured as they lie, as molaR measured them (see the module)
AS_IS = "as-is"

#: metric name -> (our call, molaR's seconds column, [(our value, molaR's column, kind)])
METRICS = {
    "OPCR": (
        lambda m: opcr(m, orient=AS_IS),
        "s_OPCR",
        [(lambda r: r.opcr, "OPCR", "float")],
    ),
    "OPC": (lambda m: opc(m, orient=AS_IS), "s_OPC", [(lambda r: r.opc, "OPC", "int")]),
    "RFI": (
        lambda m: rfi(m, orient=AS_IS),
        "s_RFI",
        [(lambda r: r.rfi, "RFI", "float"), (lambda r: r.area_2d, "area_2d", "float")],
    ),
    "RFI find_alpha": (
        lambda m: rfi(m, find_alpha=True, orient=AS_IS),
        "s_RFI_findalpha",
        [(lambda r: r.rfi, "RFI_findalpha", "float"), (lambda r: r.alpha, "alpha_found", "float")],
    ),
    "slope": (lambda m: slope(m, orient=AS_IS), "s_slope", [(lambda r: r.slope, "slope", "float")]),
    "classic DNE": (lambda m: classic_dne(m), "s_DNE", [(lambda r: r.dne, "DNE", "float")]),
}


def _agrees(ours, theirs: str, kind: str) -> str:
    if theirs == "NA":
        return "molaR: NA"
    if kind == "int":
        return "equal" if int(ours) == int(theirs) else f"DIFFERS ({ours} vs {theirs})"
    rel = abs(ours - float(theirs)) / abs(float(theirs))
    return f"rel. diff {rel:.1e}"


def _median_times(calls: dict, targets: dict, repeat: int) -> dict:
    """Median CPU seconds of every ``(metric, target)``, rounds interleaved; None if it raised.

    `targets` maps a name to a function making the metric's argument, called untimed.
    """
    times: dict = {}
    for round_ in range(repeat + 1):  # round 0 is the warm-up
        for metric, call in calls.items():
            for target, make in targets.items():
                if (metric, target) in times and times[(metric, target)] is None:
                    continue
                given = make()
                start = time.process_time()
                try:
                    call(given)
                except ValueError:
                    times[(metric, target)] = None
                    continue
                elapsed = time.process_time() - start
                if round_:
                    times.setdefault((metric, target), []).append(elapsed)
    return {k: None if v is None else statistics.median(v) for k, v in times.items()}


def _fresh(surface: Surface) -> Surface:
    """`surface` prepared and its orientation found, nothing else kept (as a batch row has it)."""
    cleaned = dataclasses.replace(surface.cleaned)
    cleaned._cache["orientation"] = surface.cleaned._cache["orientation"]  # found, inward faces
    return cleaned.oriented(AS_IS)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--meshes", nargs="+", default=["normal"])
    parser.add_argument("--repeat", type=int, default=21)
    parser.add_argument("--data", type=Path, default=SHARED)
    parser.add_argument("--json", type=Path, help="also write the figures to this JSON file")
    args = parser.parse_args(argv)
    # the reference crowns point to -z, and molaR measured them as they lie: so do we, without
    # the warning that says so
    warnings.filterwarnings("ignore", "the crown points to -z", UserWarning)

    reference_path = args.data / "reference" / "molaR_6.0_topography.csv"
    if not reference_path.exists():
        print(f"molaR's reference values not found at {reference_path}", file=sys.stderr)
        return 2
    with reference_path.open(newline="") as handle:
        reference = {row["file"].removesuffix(".ply"): row for row in csv.DictReader(handle)}

    cpus = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    print(f"dentopo {dentopo.__version__}, Python {platform.python_version()}, {cpus} cores, "
          f"CPU seconds, median of {args.repeat} interleaved rounds after one warm-up")  # fmt: skip
    print(f"{'mesh':8} {'metric':16} {'molaR s':>9} {'mesh s':>10} {'ratio':>7} "
          f"{'surface s':>10} {'ratio':>7}  agreement")  # fmt: skip
    worst = math.inf
    figures = []
    for name in args.meshes:
        row = reference[name]
        mesh = dentopo.load_mesh(args.data / "meshes" / f"{name}.ply")
        surface = prepare_surface(mesh, orient="as-is")
        calls = {metric: call for metric, (call, _, _) in METRICS.items()}
        targets = {
            "mesh": lambda mesh=mesh: mesh,
            "surface": lambda surface=surface: _fresh(surface),
        }
        times = _median_times(calls, targets, args.repeat)
        for metric, (call, seconds_column, checks) in METRICS.items():
            theirs = float(row[seconds_column])
            ours, prepared = times[(metric, "mesh")], times[(metric, "surface")]
            if ours is None:
                try:
                    call(mesh)
                except ValueError as exc:
                    agreement = "ours: error (" + str(exc)[:60] + ")"
                stopped = all(row[column] == "NA" for _, column, _ in checks)
                print(f"{name:8} {metric:16} {theirs:9.3f} {'-':>10} {'-':>7} {'-':>10} {'-':>7}  "
                      + agreement + ("; molaR: NA" if stopped else ""))  # fmt: skip
                continue
            result = call(mesh)
            agreement = "; ".join(
                f"{column} {_agrees(value(result), row[column], kind)}"
                for value, column, kind in checks
            )
            na = any(row[column] == "NA" for _, column, _ in checks)
            ratio, ratio_prepared = theirs / ours, theirs / prepared
            figures.append(
                {"mesh": name, "metric": metric, "molar_seconds": theirs, "seconds": ours}
                | {"ratio": None if na else ratio, "surface_seconds": prepared}
                | {"surface_ratio": None if na else ratio_prepared}
            )
            if not na:
                worst = min(worst, ratio)
            shown = f"{ratio:7.0f}" if not na else f"{'-':>7}"
            shown_prepared = f"{ratio_prepared:7.0f}" if not na else f"{'-':>7}"
            print(f"{name:8} {metric:16} {theirs:9.3f} {ours:10.5f} {shown} "
                  f"{prepared:10.5f} {shown_prepared}  {agreement}")  # fmt: skip
    if math.isfinite(worst):
        print(f"smallest ratio (mesh) over every metric: {worst:.0f}x")
    if args.json:
        args.json.write_text(json.dumps({"cores": cpus, "rows": figures}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
