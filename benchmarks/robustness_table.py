"""The paper's robustness comparison on the shared meshes: our sign against classic DNE.

Usage (from the repository root, with the project's environment)::

    .venv/bin/python benchmarks/robustness_table.py                  # prints the README table
    .venv/bin/python benchmarks/robustness_table.py --all-methods    # every sign method
    .venv/bin/python benchmarks/robustness_table.py -o benchmarks/out/robustness  # + CSV, figures

The original is ``normal.ply``; the perturbations are the paper's own robustness set
(``low`` about 2k triangles, ``high`` about 20k, ``noise1``, ``noise2``, ``smooth``), read from
``../shared/data/meshes`` beside the checkout (``--data`` to change), not generated.  Every
value is normalised by the same method on ``normal``.  "Sign agreement" is the fraction of the
perturbed surface's area whose sign (ours: per vertex; classic DNE, molaR's convex/concave
class: per face) equals the original's at the nearest point (see
``dentopo.sign_agreement``).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from dentopo import robustness_study, write_study
from dentopo.sign import SIGN_METHODS

ROOT = Path(__file__).resolve().parent.parent
DEFAULT_DATA = ROOT.parent / "shared" / "data" / "meshes"
PERTURBATIONS = ("low", "high", "noise1", "noise2", "smooth")
QUANTITIES = (
    ("dne_normalised", "DNE"),
    ("positive_normalised", "positive"),
    ("negative_normalised", "negative"),
    ("sign_agreement", "sign agreement"),
)
LABELS = {"centroid": "ours", "classic": "classic"}


def markdown_table(study, methods) -> str:
    """One row per perturbation; for each quantity, one column per method."""
    header = ["mesh"]
    for _, title in QUANTITIES:
        header += [f"{title} ({LABELS.get(m, m)})" for m in methods]
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join(["---"] * len(header)) + "|"]
    for name in PERTURBATIONS:
        cells = [name]
        for key, _ in QUANTITIES:
            cells += [f"{study.row(name, m)[key]:.3f}" for m in methods]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", type=Path, default=DEFAULT_DATA, help="shared meshes")
    parser.add_argument("--all-methods", action="store_true", help="every sign method")
    parser.add_argument("-o", "--output", type=Path, help="also write CSV and figures here")
    args = parser.parse_args(argv)
    paths = {name: args.data / f"{name}.ply" for name in ("normal", *PERTURBATIONS)}
    missing = [str(p) for p in paths.values() if not p.exists()]
    if missing:
        print(f"robustness_table: missing shared meshes: {', '.join(missing)}", file=sys.stderr)
        return 2
    sign_methods = SIGN_METHODS if args.all_methods else ("centroid",)
    study = robustness_study(
        paths["normal"],
        perturbations={name: paths[name] for name in PERTURBATIONS},
        sign_methods=sign_methods,
    )
    print(markdown_table(study, [*sign_methods, "classic"]))
    if args.output is not None:
        for path in write_study(study, args.output):
            print(f"wrote {path}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
