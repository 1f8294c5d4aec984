"""``dentopo robustness`` and ``dentopo sweep``: thin shells over `dentopo.study`.

The figures need the ``study`` extra (matplotlib), checked before anything is
computed unless ``--no-figures`` (decimation, by fast-simplification, is a
dependency: it needs no extra).  A missing extra ends as one line naming it,
with exit code 2.  So does an output
folder that is an input (the mesh, a perturbation) or that holds one under a
name the study writes, or that cannot be written: checked before computing,
as the main command's outputs are (``_output.output_problem``).

``dentopo robustness`` runs the protocol study instead (`protocol_study`:
every metric against the face count, smoothing iterations and noise, relative
to a base protocol) when any of its options is given (``--faces``,
``--smooth-iterations``, ``--smooth``, ``--noise``, ``--base-faces``,
``--metrics``, ``--find-alpha``) or when the input is a folder or several
files.  Its lists are checked here: a wrong value is one line and exit 2.
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
            "figures into DIR.  With the protocol study's options (or several crowns, or a "
            "folder), measure every metric on crowns decimated or refined, smoothed and "
            "roughened, relative to a base protocol, and write sensitivity.csv, "
            "sensitivity_summary.csv and one figure per metric."
        ),
    )
    parser.add_argument(
        "mesh",
        nargs="+",
        help="the original mesh file (the protocol study: mesh files or folders of crowns)",
    )
    parser.add_argument("-o", "--output", required=True, metavar="DIR", help="output directory")
    parser.add_argument("-b", "--bandwidth", type=float, default=0.08)
    parser.add_argument("--seed", type=int, default=0, help="noise seed (default 0)")
    parser.add_argument("--low-faces", type=int, metavar="N", help="(default 2000)")
    parser.add_argument("--high-faces", type=int, metavar="N", help="(default 20000)")
    study = parser.add_argument_group(
        "the protocol study",
        "every metric against the protocol's parameters, relative to a base (any of these "
        "options, or several crowns, run it; writes sensitivity.csv, sensitivity_summary.csv "
        "and sensitivity_METRIC.png)",
    )
    study.add_argument(
        "--faces",
        metavar="N,N,...",
        help="face counts (default 2000,5000,10000,20000,40000; 'none' skips the axis)",
    )
    study.add_argument(
        "--smooth-iterations",
        metavar="K,K,...",
        help="smoothing iterations (default 0,3,10,30,100; 'none' skips the axis)",
    )
    study.add_argument(
        "--smooth",
        metavar="METHOD",
        help="the smoothing method: laplacian, taubin (default), hc or implicit",
    )
    study.add_argument(
        "--smooth-step",
        metavar="X",
        help="the smoothing method's step (lambda; default: the protocol's, see dentopo prepare)",
    )
    study.add_argument(
        "--smooth-mu", metavar="X", help="taubin's nu or hc's beta (default: the protocol's)"
    )
    study.add_argument(
        "--noise",
        metavar="SD,SD,...",
        help="noise sd on the unit-area scale (default 0,0.001,0.002; 'none' skips the axis)",
    )
    study.add_argument(
        "--base-faces",
        metavar="N",
        help="the base protocol: decimate to N faces (default: the crown as given)",
    )
    study.add_argument(
        "--metrics",
        metavar="M,M,...",
        help="metrics (default all; see dentopo --help for the names)",
    )
    study.add_argument(
        "--find-alpha", action="store_true", help="RFI searches for molaR's smallest valid alpha"
    )
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


_STUDY_OPTIONS = (
    ("faces", "--faces"),
    ("smooth_iterations", "--smooth-iterations"),
    ("smooth", "--smooth"),
    ("noise", "--noise"),
    ("smooth_step", "--smooth-step"),
    ("smooth_mu", "--smooth-mu"),
    ("base_faces", "--base-faces"),
    ("metrics", "--metrics"),
    ("find_alpha", "--find-alpha"),
)
_PAPER_OPTIONS = (
    ("low_faces", "--low-faces"),
    ("high_faces", "--high-faces"),
    ("perturbation", "--perturbation"),
    ("sign_methods", "--sign-method"),
    ("no_classic", "--no-classic"),
)


class _UsageError(ValueError):
    """A wrong option value: one line, exit 2."""


def _list(option: str, text: str | None, default, convert, what: str):
    """The levels of a comma-separated option (``none``: no levels)."""
    if text is None:
        return default
    if text.strip().lower() == "none":
        return ()
    items = [item.strip() for item in text.split(",")]
    if not all(items):
        raise _UsageError(f"{option} wants {what} separated by commas; got {text!r}")
    try:
        return tuple(convert(item) for item in items)
    except ValueError:
        raise _UsageError(f"{option} wants {what} separated by commas; got {text!r}") from None


def _whole(minimum: int):
    def convert(text: str) -> int:
        value = int(text)
        if value < minimum:
            raise ValueError(text)
        return value

    return convert


def _non_negative(text: str) -> float:
    value = float(text)
    if not (value >= 0 and value != float("inf")):
        raise ValueError(text)
    return value


def _study_arguments(args) -> dict:
    """`protocol_study`'s keywords from the options, or `_UsageError`."""
    from ..batch._measure import TopographyOptions
    from ..prepare import Protocol, ProtocolError
    from ..study._protocol_study import (
        DEFAULT_FACES,
        DEFAULT_NOISE,
        DEFAULT_SMOOTHING,
        SMOOTH_METHODS,
    )
    from ..topography import METRICS, check_metrics

    faces = _list("--faces", args.faces, DEFAULT_FACES, _whole(4), "face counts (4 or more)")
    smoothing = _list(
        "--smooth-iterations",
        args.smooth_iterations,
        DEFAULT_SMOOTHING,
        _whole(0),
        "iteration counts (0 or more)",
    )
    noise = _list("--noise", args.noise, DEFAULT_NOISE, _non_negative, "sd values (0 or more)")
    if not (faces or smoothing or noise):
        raise _UsageError("--faces, --smooth-iterations and --noise are all none: nothing to study")
    method = "taubin" if args.smooth is None else args.smooth.strip().lower()
    if method not in SMOOTH_METHODS:
        raise _UsageError(
            f"--smooth must be one of {', '.join(SMOOTH_METHODS)}; got {args.smooth!r}"
        )
    numbers = {}
    for name, flag in (("step", "--smooth-step"), ("mu", "--smooth-mu")):
        text = getattr(args, f"smooth_{name}")
        numbers[name] = None
        if text is not None:
            try:
                numbers[name] = float(text)
            except ValueError:
                raise _UsageError(f"{flag} wants a number; got {text!r}") from None
    try:
        Protocol(orient="none", smooth=method, smooth_step=numbers["step"], smooth_mu=numbers["mu"])
    except ProtocolError as exc:
        flags = {"smooth_step": "--smooth-step", "smooth_mu": "--smooth-mu"}
        message = str(exc)
        for name, flag in flags.items():
            message = message.replace(name, flag)
        raise _UsageError(message) from None
    base_faces = None
    if args.base_faces is not None:
        try:
            base_faces = _whole(4)(args.base_faces.strip())
        except ValueError:
            raise _UsageError(
                f"--base-faces wants a face count (4 or more); got {args.base_faces!r}"
            ) from None
    metrics = "all"
    if args.metrics is not None and args.metrics.strip().lower() != "all":
        metrics = tuple(m.strip().lower() for m in args.metrics.split(","))
        try:
            metrics = check_metrics(metrics)
        except (ValueError, TypeError):
            raise _UsageError(
                f"--metrics wants 'all' or names among {', '.join(METRICS)}; got {args.metrics!r}"
            ) from None
    return {
        "faces": faces,
        "smoothing": smoothing,
        "noise": noise,
        "method": method,
        "step": numbers["step"],
        "mu": numbers["mu"],
        "base_faces": base_faces,
        "metrics": metrics,
        "bandwidth": args.bandwidth,
        "options": TopographyOptions(find_alpha=args.find_alpha),
        "seed": args.seed,
    }


def _crown_names(files: list[str]) -> dict:
    """``{name: path}``: the file's stem, or its path below the common folder when stems repeat."""
    stems = [os.path.splitext(os.path.basename(f))[0] for f in files]
    if len(set(stems)) == len(stems):
        return dict(zip(stems, files, strict=True))
    common = os.path.commonpath([os.path.abspath(f) for f in files])
    return {os.path.splitext(os.path.relpath(os.path.abspath(f), common))[0]: f for f in files}


def _protocol_study_main(args) -> int:
    """The protocol study of ``dentopo robustness``; the exit code."""
    from ..batch import find_mesh_files
    from ..mesh import load_mesh
    from ..study import SUMMARY_COLUMNS, protocol_study, protocol_study_files, write_protocol_study

    prog = "dentopo robustness"
    given = [(flag, getattr(args, name)) for name, flag in _PAPER_OPTIONS]
    mixed = [flag for flag, value in given if value not in (None, False)]
    if mixed:
        _err(f"{prog}: {', '.join(mixed)} belong to the paper's study, not the protocol study")
        return 2
    try:
        keywords = _study_arguments(args)
    except _UsageError as exc:
        _err(f"{prog}: {exc}")
        return 2
    if _missing_figures(prog, not args.no_figures):
        return 2
    found = find_mesh_files(args.mesh)
    if not found.files:
        _err(f"{prog}: no mesh files in {', '.join(args.mesh)}")
        return 2
    crowns = _crown_names(found.files)
    inputs = [(f"the input mesh {name!r}", path) for name, path in crowns.items()]
    names = protocol_study_files(keywords["metrics"], figures=not args.no_figures)
    if _folder_problem(prog, args.output, names, inputs):
        return 2
    meshes = {}
    for name, path in crowns.items():
        try:
            meshes[name] = load_mesh(path)
        except (OSError, ValueError) as exc:
            _err(f"{prog}: {path}: {exc}")
            return 1
    try:
        study = protocol_study(meshes, **keywords)
        written = write_protocol_study(study, args.output, figures=not args.no_figures)
    except MissingExtraError as exc:
        _err(f"{prog}: {exc}")
        return 2
    except (OSError, ValueError, TypeError, ImportError, NotImplementedError) as exc:
        _err(f"{prog}: {exc}")
        return 1
    _print_rows(study.summary(), SUMMARY_COLUMNS)
    for message in study.warnings:
        _err(f"warning: {message}")
    for path in written:
        _err(f"wrote {path}")
    return 0


def _is_protocol_study(args) -> bool:
    chosen = any(getattr(args, name) not in (None, False) for name, _ in _STUDY_OPTIONS)
    return chosen or len(args.mesh) > 1 or os.path.isdir(args.mesh[0])


def robustness_main(argv: list[str]) -> int:
    """Run ``dentopo robustness ARGS``; the exit code."""
    from ..study import STUDY_FILES, robustness_study, write_study

    args = _robustness_parser().parse_args(argv)
    if not _bandwidths_ok("dentopo robustness", [args.bandwidth]):
        return 2
    if _is_protocol_study(args):
        return _protocol_study_main(args)
    args.mesh = args.mesh[0]
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
        options = {
            "low_faces": 2000 if args.low_faces is None else args.low_faces,
            "high_faces": 20000 if args.high_faces is None else args.high_faces,
            "seed": args.seed,
        }
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
