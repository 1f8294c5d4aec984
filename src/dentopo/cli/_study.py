"""``dentopo robustness`` and ``dentopo sweep``: thin shells over `_robustness`.

The figures need the ``study`` extra (matplotlib), checked before anything is
computed unless ``--no-figures``; generated perturbations need it too
(fast-simplification decimates), which the study checks before computing.  A
missing extra ends as one line naming it, with exit code 2.  So does an output
folder that is an input (the mesh, a perturbation) or that holds one under a
name the study writes, or that cannot be written: checked before computing,
as the main command's outputs are (``_output.output_problem``).
"""

from __future__ import annotations

import argparse
import os

from .._optional import STUDY_FIGURES, MissingExtraError
from ..sign import SIGN_METHODS
from ._output import Planned, output_problem
from ._streams import write_stderr


def _robustness_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="dentopo robustness",
        description=(
            "Perturb a mesh (about 2k and 20k triangles, noise 1e-3 and 2e-3, Taubin "
            "smoothing), compute every sign method and classic DNE on each, and write "
            "robustness.csv (totals normalised by the original, area sign agreement) and "
            "figures into DIR."
        ),
    )
    parser.add_argument("mesh", help="the original mesh file")
    parser.add_argument("-o", "--output", required=True, metavar="DIR", help="output directory")
    parser.add_argument("-b", "--bandwidth", type=float, default=0.08)
    parser.add_argument("--seed", type=int, default=0, help="noise seed (default 0)")
    parser.add_argument("--low-faces", type=int, default=2000, metavar="N")
    parser.add_argument("--high-faces", type=int, default=20000, metavar="N")
    parser.add_argument(
        "--sign-method",
        dest="sign_methods",
        action="append",
        type=str.lower,
        choices=SIGN_METHODS,
        help="compare only these sign methods (repeatable; default: all)",
    )
    parser.add_argument(
        "--perturbation",
        action="append",
        metavar="NAME=PATH",
        help="use this mesh file as a perturbation instead of generating them (repeatable)",
    )
    parser.add_argument("--no-classic", action="store_true", help="skip classic DNE")
    parser.add_argument("--no-figures", action="store_true", help="write the CSV only")
    return parser


def _sweep_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="dentopo sweep",
        description=(
            "ariaDNE totals for several bandwidths, with our sign, the Gaussian and the mean "
            "curvature sign; writes sweep.csv and the panel sweep.png into DIR."
        ),
    )
    parser.add_argument("mesh", help="mesh file")
    parser.add_argument(
        "-b",
        "--bandwidth",
        dest="bandwidths",
        type=float,
        nargs="+",
        default=[0.04, 0.06, 0.08, 0.10, 0.12, 0.14],
        metavar="H",
    )
    parser.add_argument("-o", "--output", default=".", metavar="DIR", help="(default: .)")
    parser.add_argument(
        "--sign-method",
        dest="sign_methods",
        action="append",
        type=str.lower,
        choices=SIGN_METHODS,
        help="rows of the panel (repeatable; default: centroid, gaussian, mean)",
    )
    parser.add_argument("--no-figures", action="store_true", help="write the CSV only")
    return parser


def _err(message: str) -> None:
    """One line on stderr (dropped if stderr cannot be written: the files are written anyway)."""
    write_stderr(message + "\n")


def _print_rows(rows, columns) -> None:
    print("\t".join(columns))
    for row in rows:
        print(
            "\t".join(
                f"{row[c]:.6g}" if isinstance(row[c], float) else str(row[c]) for c in columns
            )
        )


def _missing_figures(prog: str, figures: bool) -> bool:
    """Say so and return True if `figures` are asked for without the study extra."""
    if figures:
        try:
            STUDY_FIGURES.check()
        except MissingExtraError as exc:
            _err(f"{prog}: {exc}")
            return True
    return False


def _bandwidths_ok(prog: str, bandwidths) -> bool:
    """Say so and return False if a bandwidth is out of range (a usage error)."""
    from ..ariadne import check_bandwidth

    try:
        for bandwidth in bandwidths:
            check_bandwidth(bandwidth)
    except ValueError as exc:
        _err(f"{prog}: {exc}")
        return False
    return True


def _folder_problem(prog: str, folder: str, names, inputs) -> bool:
    """Say so and return True if the files `names` cannot be written into `folder`.

    `inputs` are ``(what, path)``: an output folder that is one of them, or
    whose file of one of `names` is, would replace it.
    """
    planned = [Planned("--output", folder, check=True, folder=True)]
    planned += [Planned(f"{name} in --output", os.path.join(folder, name)) for name in names]
    problem = output_problem(planned, inputs)
    if problem:
        _err(f"{prog}: {problem}")
    return problem is not None


def robustness_main(argv: list[str]) -> int:
    """Run ``dentopo robustness ARGS``; the exit code."""
    from ..study import STUDY_FILES, robustness_study, write_study

    args = _robustness_parser().parse_args(argv)
    if not _bandwidths_ok("dentopo robustness", [args.bandwidth]):
        return 2
    perturbations = None
    if args.perturbation:
        perturbations = {}
        for item in args.perturbation:
            name, sep, path = item.partition("=")
            if not sep or not name or not path:
                _err(f"dentopo robustness: --perturbation wants NAME=PATH; got {item!r}")
                return 2
            perturbations[name] = path
    if _missing_figures("dentopo robustness", not args.no_figures):
        return 2
    inputs = [("the input mesh", args.mesh)]
    inputs += [(f"the perturbation {name!r}", path) for name, path in (perturbations or {}).items()]
    names = STUDY_FILES if not args.no_figures else STUDY_FILES[:1]
    if _folder_problem("dentopo robustness", args.output, names, inputs):
        return 2
    options = {}
    if perturbations is None:
        options = {"low_faces": args.low_faces, "high_faces": args.high_faces, "seed": args.seed}
    try:
        study = robustness_study(
            args.mesh,
            perturbations=perturbations,
            bandwidth=args.bandwidth,
            sign_methods=args.sign_methods or SIGN_METHODS,
            classic=not args.no_classic,
            **options,
        )
        written = write_study(study, args.output, figures=not args.no_figures)
    except MissingExtraError as exc:
        _err(f"dentopo robustness: {exc}")
        return 2
    except (OSError, ValueError, TypeError, ImportError) as exc:
        _err(f"dentopo robustness: {exc}")
        return 1
    _print_rows(
        study.rows,
        (
            "perturbation",
            "method",
            "dne_normalised",
            "positive_normalised",
            "negative_normalised",
            "sign_agreement",
        ),
    )
    for path in written:
        _err(f"wrote {path}")
    return 0


def sweep_main(argv: list[str]) -> int:
    """Run ``dentopo sweep ARGS``; the exit code."""
    from ..study import SWEEP_COLUMNS, SWEEP_FILES, SWEEP_METHODS, bandwidth_sweep, write_sweep

    args = _sweep_parser().parse_args(argv)
    if not _bandwidths_ok("dentopo sweep", args.bandwidths):
        return 2
    if _missing_figures("dentopo sweep", not args.no_figures):
        return 2
    names = SWEEP_FILES if not args.no_figures else SWEEP_FILES[:1]
    if _folder_problem("dentopo sweep", args.output, names, [("the input mesh", args.mesh)]):
        return 2
    try:
        sweep = bandwidth_sweep(
            args.mesh, args.bandwidths, sign_methods=args.sign_methods or SWEEP_METHODS
        )
        written = write_sweep(sweep, args.output, figures=not args.no_figures)
    except MissingExtraError as exc:
        _err(f"dentopo sweep: {exc}")
        return 2
    except (OSError, ValueError, TypeError, ImportError) as exc:
        _err(f"dentopo sweep: {exc}")
        return 1
    _print_rows(sweep.rows, SWEEP_COLUMNS)
    for path in written:
        _err(f"wrote {path}")
    return 0
