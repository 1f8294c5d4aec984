"""Benchmark doolkit 1.42's metrics and molaR's ARC as dentopo computes them, against their seconds.

Usage (from the repository root, with the project's environment)::

    .venv/bin/python benchmarks/bench_doolkit.py                      # normal.ply
    .venv/bin/python benchmarks/bench_doolkit.py --meshes normal high low --repeat 31

doolkit and molaR are R packages and are not run here: their seconds come from the reference files
``../shared/data/reference/doolkit_1.42.2_topography.csv`` and ``molaR_6.0_topography.csv``
(columns ``s_*``), measured on a 2-core machine, one metric call on a mesh already read
(``vcgImport``).  doolkit's relief indices are three calls (``s_rfi_ungar``, ``s_rfi_boyer``,
``s_rfi_guy``), each computing the footprint again; ours is one call giving the three, so its
seconds are compared with their sum; likewise the footprint (concave and convex areas).

Ours are CPU seconds of this process (``time.process_time``), the median over ``--repeat`` rounds
after one warm-up round, every round calling every metric in turn, each metric timed two ways:

* ``mesh``: on a ``trimesh.Trimesh`` already in memory (``dentopo.load_mesh`` once): each call
  includes the input checks, the cleaning and (inclination, OPC, OPCR, relief indices, relief
  rate, footprints) the orientation check, which doolkit does not count: the conservative figure;
* ``surface``: on a :class:`dentopo.topography.Surface` already prepared (cleaned, its
  orientation found), nothing else kept with it (made afresh, untimed, before every call: the
  mesh as doolkit reads it, its normals, edges and everything else a metric derives are computed
  in the call).  doolkit's seconds cover one metric call on a mesh ``vcgImport`` has already read
  and cleaned, so this is the like-for-like figure, and the ratio the target applies to;
* the whole set as one batch row computes it (``dentopo.batch.measure_mesh(mesh, "doolkit")``
  from the mesh: cleaned once for every metric), against doolkit's summed seconds: the issue's
  target is at least 20 times, the aim 100 times.

The ratio is doolkit's (molaR's) seconds divided by ours.  The R tools' seconds are timed at a
millisecond's resolution: where one is recorded as 0.000 no ratio can be computed (``-``).

The reference crowns point to -z and doolkit and molaR measured them as they lie (nothing in
either reorients a mesh), so every metric that looks at the orientation is called with
``orient="as-is"``: the default ``"auto"`` would turn them over first and measure another crown
(inclination 180 minus doolkit's, Guy's relief index and the relief rate of the upturned crown).

Every value is compared with the tool's, so a fast wrong answer shows.  Nothing here is a test:
timings depend on the machine and its load.
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import json
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
from dentopo.batch._measure import TopographyOptions, measure_mesh  # noqa: E402
from dentopo.topography import (  # noqa: E402
    Surface,
    angularity,
    arc,
    doolkit_arc,
    doolkit_dne,
    doolkit_opc,
    doolkit_opcr,
    doolkit_slope,
    footprint_area,
    hypsodonty,
    inclination,
    prepare_surface,
    relief_index,
    relief_rate_below_median,
    shape_index,
)

SHARED = ROOT.parent / "shared" / "data"

#: the crowns measured as they lie, as the tools measured them (see the module)
AS_IS = "as-is"

#: a batch row's options: as they lie, in millimetres (the reference crowns' unit)
ROW = TopographyOptions(orient=AS_IS, unit="mm")

#: name -> (our call, the tool's seconds columns, [(our value, the tool's column)])
DOOLKIT = {
    "slope": (doolkit_slope, ("s_slope",), [(lambda r: r.slope_mean, "slope_mean")]),
    "angularity": (
        angularity,
        ("s_angularity",),
        [(lambda r: r.angularity_mean, "angularity_mean")],
    ),
    "relief indices": (
        lambda m: relief_index(m, orient=AS_IS),
        ("s_rfi_ungar", "s_rfi_boyer", "s_rfi_guy"),
        [(lambda r: r.rfi_ungar, "rfi_ungar"), (lambda r: r.rfi_guy, "rfi_guy")],
    ),
    "inclination": (
        lambda m: inclination(m, orient=AS_IS),
        ("s_inclin",),
        [(lambda r: r.inclination_mean, "inclin_mean")],
    ),
    "OPC": (lambda m: doolkit_opc(m, orient=AS_IS), ("s_opc",), [(lambda r: r.opc, "opc")]),
    "OPCR": (lambda m: doolkit_opcr(m, orient=AS_IS), ("s_opcr",), [(lambda r: r.opcr, "opcr")]),
    "ARC": (doolkit_arc, ("s_arc",), [(lambda r: r.arc_mean, "arc_mean")]),
    "DNE": (doolkit_dne, ("s_dne",), [(lambda r: r.dne_total_unrounded, "dne_total_unrounded")]),
    "relief rate": (
        lambda m: relief_rate_below_median(m, orient=AS_IS),
        ("s_rrate",),
        [(lambda r: r.rrate, "rrate_below_median")],
    ),
    "shape index": (
        shape_index,
        ("s_shape_index",),
        [(lambda r: r.formfactor, "shape_formfactor")],
    ),
    "footprints": (
        lambda m: (
            footprint_area(m, hull="concave", orient=AS_IS),
            footprint_area(m, hull="convex", orient=AS_IS),
        ),
        ("s_area2d", "s_area2d_convex"),
        [(lambda r: r[0].area, "area2d"), (lambda r: r[1].area, "area2d_convex")],
    ),
    "hypsodonty": (hypsodonty, ("s_hypso",), [(lambda r: r.hypsodonty, "hypso_hypsodonty")]),
}

#: molaR's ARC, as an entry of DOOLKIT (its seconds and value from molaR's table)
MOLAR_ARC = (arc, ("s_ARC",), [(lambda r: r.arc, "ARC")])


def _reference(path: Path) -> dict:
    with path.open(newline="") as handle:
        return {row["file"].removesuffix(".ply"): row for row in csv.DictReader(handle)}


def _agreement(ours: float, theirs: str) -> str:
    if theirs == "NA":
        return "NA"
    expected = float(theirs)
    if expected == 0:
        return f"abs. diff {abs(ours):.1e}"
    return f"rel. diff {abs(ours - expected) / abs(expected):.1e}"


def _median_cpu(calls: dict, targets: dict, repeat: int) -> dict:
    """Median CPU seconds of every ``(metric, target)``, rounds interleaved.

    `targets` maps a name to a function making the metric's argument, called untimed.
    """
    times: dict = {}
    for round_ in range(repeat + 1):  # round 0 is the warm-up
        for name, call in calls.items():
            for target, make in targets.items():
                given = make()
                start = time.process_time()
                call(given)
                elapsed = time.process_time() - start
                if round_:
                    times.setdefault((name, target), []).append(elapsed)
    return {key: statistics.median(values) for key, values in times.items()}


def _fresh(surface: Surface) -> Surface:
    """`surface` prepared and its orientation found, nothing else kept (as a batch row has it)."""
    cleaned = dataclasses.replace(surface.cleaned)
    cleaned._cache["orientation"] = surface.cleaned._cache["orientation"]  # found, inward faces
    return cleaned.oriented(AS_IS)


def _ratio(theirs: float, ours: float) -> str:
    return f"{theirs / ours:7.0f}" if theirs > 0 else f"{'-':>7}"


def _seconds(row: dict, columns) -> float:
    return sum(float(row[column]) for column in columns)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--meshes", nargs="+", default=["normal"])
    parser.add_argument("--repeat", type=int, default=21)
    parser.add_argument("--data", type=Path, default=SHARED)
    parser.add_argument("--json", type=Path, help="also write the figures to this JSON file")
    args = parser.parse_args(argv)
    # the reference crowns point to -z and the tools measured them as they lie: so do we
    warnings.filterwarnings("ignore", "the crown points to -z", UserWarning)
    doolkit_path = args.data / "reference" / "doolkit_1.42.2_topography.csv"
    molar_path = args.data / "reference" / "molaR_6.0_topography.csv"
    for path in (doolkit_path, molar_path):
        if not path.exists():
            print(f"reference values not found at {path}", file=sys.stderr)
            return 2
    doolkit, molar = _reference(doolkit_path), _reference(molar_path)

    cpus = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    print(f"dentopo {dentopo.__version__}, Python {platform.python_version()}, {cpus} cores, "
          f"CPU seconds, median of {args.repeat} interleaved rounds after one warm-up")  # fmt: skip
    print(f"{'mesh':8} {'metric':16} {'tool s':>8} {'mesh s':>9} {'ratio':>7} "
          f"{'surface s':>9} {'ratio':>7}  agreement")  # fmt: skip
    figures = []
    for name in args.meshes:
        mesh = dentopo.load_mesh(args.data / "meshes" / f"{name}.ply")
        surface = prepare_surface(mesh, orient=AS_IS)
        row, molar_row = doolkit[name], molar[name]
        calls = {metric: call for metric, (call, _, _) in DOOLKIT.items()}
        calls["molaR ARC"] = arc
        targets = {"mesh": lambda mesh=mesh: mesh, "surface": lambda s=surface: _fresh(s)}
        times = _median_cpu(calls, targets, args.repeat)
        whole = _median_cpu(
            {"whole set": lambda m: measure_mesh(m, "doolkit", options=ROW)},
            {"mesh": lambda mesh=mesh: mesh},
            args.repeat,
        )[("whole set", "mesh")]
        for metric, (call, columns, checks) in [*DOOLKIT.items(), ("molaR ARC", MOLAR_ARC)]:
            tool = molar_row if metric == "molaR ARC" else row
            theirs = _seconds(tool, columns)
            ours, prepared = times[(metric, "mesh")], times[(metric, "surface")]
            result = call(mesh)
            agreement = "; ".join(
                f"{column} {_agreement(value(result), tool[column])}" for value, column in checks
            )
            ratios = {"ratio": ours, "surface_ratio": prepared}
            ratios = {key: theirs / value if theirs > 0 else None for key, value in ratios.items()}
            figures.append(
                {"mesh": name, "metric": metric, "tool_seconds": theirs, "seconds": ours}
                | {"surface_seconds": prepared}
                | ratios
            )
            print(f"{name:8} {metric:16} {theirs:8.3f} {ours:9.5f} {_ratio(theirs, ours)} "
                  f"{prepared:9.5f} {_ratio(theirs, prepared)}  {agreement}")  # fmt: skip
        total = sum(_seconds(row, columns) for _, columns, _ in DOOLKIT.values())
        figures.append({"mesh": name, "metric": "doolkit set", "tool_seconds": total,
                        "seconds": whole, "ratio": total / whole})  # fmt: skip
        print(
            f"{name:8} {'doolkit, a row':16} {total:8.3f} {whole:9.5f} {_ratio(total, whole)}  "
            f"{'':17}  (the whole set as a batch row computes it; target 20x, aim 100x)"
        )
    if args.json:
        args.json.write_text(json.dumps({"cores": cpus, "rows": figures}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
