"""The protocol study on the paper's robustness set: how much each metric moves.

Usage (from the repository root, with the project's environment)::

    .venv/bin/python benchmarks/protocol_sensitivity.py                 # prints the table
    .venv/bin/python benchmarks/protocol_sensitivity.py --base-faces 10000
    .venv/bin/python benchmarks/protocol_sensitivity.py -o benchmarks/out/sensitivity  # + files

Spradley et al. (2017) asked how much smoothing and simplification move DNE, RFI and OPCR.
This runs `dentopo.protocol_study` on the paper's robustness set in ``../shared/data/meshes``
(``normal``, ``low``, ``high``, ``noise1``, ``noise2``, ``smooth``: one open crown meshed six
ways; ``--data`` to change the folder, ``--crowns 000119433 ...`` for the closed museum
specimens) with the face counts 2k, 5k, 10k, 20k, 40k, Taubin smoothing (the protocol's
``taubin``: lambda 0.5, nu 0.5, the base pinned; ``--smooth implicit`` for MorphoTester's)
for 2, 10, 30 and 100 iterations (even counts: trimesh counts Taubin's passes singly), and
the robustness study's noise (sd 1e-3 and 2e-3 on the unit-area scale), every metric of
the batch, and prints each quantity's median relative change (%) across the crowns, with the
number of crowns where it was missing.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from dentopo import protocol_study, write_protocol_study
from dentopo.batch._measure import TopographyOptions

ROOT = Path(__file__).resolve().parent.parent
DEFAULT_DATA = ROOT.parent / "shared" / "data" / "meshes"
CROWNS = ("normal", "low", "high", "noise1", "noise2", "smooth")
FACES = (2000, 5000, 10000, 20000, 40000)
SMOOTHING = (0, 2, 10, 30, 100)
NOISE = (0.0, 1e-3, 2e-3)


def _cell(row) -> str:
    median = row["median_relative_change"]
    if median is None:
        return "—"
    text = f"{100 * median:+.1f}"
    return text + (f" ({row['missing']}✗)" if row["missing"] else "")


def markdown_table(study) -> str:
    """One row per quantity; one column per axis level (median % change across crowns)."""
    summary = study.summary()
    levels = [(a, lv) for a, values in study.axes.items() for lv in values if lv != 0]
    names = {"faces": "{:g}k faces", "smoothing": "smooth {}", "noise": "noise {:g}"}
    header = ["metric", "quantity"] + [
        names[a].format(lv / 1000 if a == "faces" else lv) for a, lv in levels
    ]
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join(["---"] * len(header)) + "|"]
    table = {(r["axis"], r["level"], r["quantity"]): r for r in summary}
    quantities = list(dict.fromkeys((r["metric"], r["quantity"]) for r in summary))
    for metric, quantity in quantities:
        cells = [metric, quantity] + [_cell(table[a, lv, quantity]) for a, lv in levels]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", type=Path, default=DEFAULT_DATA, help="shared meshes")
    parser.add_argument(
        "--crowns", nargs="+", default=list(CROWNS), metavar="NAME", help="mesh names in --data"
    )
    parser.add_argument("--base-faces", type=int, help="base: decimate to N faces")
    parser.add_argument("--smooth", default="taubin", help="smoothing method (default taubin)")
    parser.add_argument("--find-alpha", action="store_true", help="RFI searches for an alpha")
    parser.add_argument("-o", "--output", type=Path, help="also write the CSVs and figures here")
    args = parser.parse_args(argv)
    paths = {name: args.data / f"{name}.ply" for name in args.crowns}
    missing = [str(p) for p in paths.values() if not p.exists()]
    if missing:
        print(f"protocol_sensitivity: missing meshes: {', '.join(missing)}", file=sys.stderr)
        return 2
    start = time.perf_counter()
    study = protocol_study(
        {name: str(path) for name, path in paths.items()},
        faces=FACES,
        smoothing=SMOOTHING,
        noise=NOISE,
        method=args.smooth,
        base_faces=args.base_faces,
        options=TopographyOptions(find_alpha=args.find_alpha),
    )
    seconds = time.perf_counter() - start
    print(markdown_table(study))
    print(f"\n{len(study.crowns)} crowns, base {study.base}, {seconds:.0f} s", file=sys.stderr)
    for message in study.warnings:
        print(f"warning: {message}", file=sys.stderr)
    if args.output is not None:
        for path in write_protocol_study(study, args.output):
            print(f"wrote {path}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
