"""``dentopo prepare INPUT... -o OUTDIR``: raw scans to prepared crowns, as a protocol says.

A thin shell over :func:`dentopo.prepare` and the batch of :mod:`dentopo.batch`:
finds the mesh files as the main command does, prepares each (clean, orient,
crop, decimate, smooth) and writes ``OUTDIR/NAME.ply`` and
``OUTDIR/NAME.prepare.json`` (the input folders' tree mirrored), and with
``--preview DIR`` a picture of each file and a contact sheet of them all.

Exit codes as the main command's: 0 every file prepared, 1 some file failed
(one line each, the others go on), 2 a usage problem found before any file is
read (a wrong option value, named; a protocol that cannot be read; no mesh
files; an output that would replace an input or cannot be written; the viz
extra missing for --preview), 130 interrupted (the files done are complete:
rerun with --resume to finish).
"""

from __future__ import annotations

import argparse
import os
import re
import signal
import sys
import textwrap
import warnings

from .._optional import PICTURES, MissingExtraError
from ..batch import find_mesh_files, is_done, plan_preparation, run_preparation
from ..formats import atomic_write
from ..prepare import (
    DECIMATORS,
    SMOOTHERS,
    Protocol,
    ProtocolError,
    load_protocol,
    named_protocols,
)
from ._hints import CommandLineHints
from ._output import Planned, output_problem
from ._progress import Progress, counted, say

#: The exit code of a run stopped by Ctrl-C or SIGTERM.
INTERRUPTED = 130

#: The contact sheet of every preview, in the preview folder.
SHEET = "sheet.png"

EXAMPLES = """\
examples:
  dentopo prepare tooth.ply -o prepared/ --faces 10000
  dentopo prepare raw/ -o prepared/ --protocol crown-10k -j 0
  dentopo prepare raw/ -o prepared/ --crop-fraction 0.6 --faces 10000 --smooth implicit:3
  dentopo prepare raw/ -o prepared/ --protocol study.toml --preview previews/ --resume
  dentopo prepare --faces 10000 --smooth taubin:10 --save-protocol study.toml
  dentopo prepare --protocols

Outputs mirror the inputs' folders: a folder given is the root of its files
(raw/a/t.ply given as raw/ is written as OUTDIR/a/t.ply), a file given goes to
the top of OUTDIR. Options given with --protocol override the protocol's.

exit codes: 0 every file prepared; 1 some file failed (its line says why);
2 usage problem, found before any file is read; 130 interrupted (rerun with
--resume to finish).
"""

#: Protocol fields and the options that set them (for messages).
FIELD_OPTIONS = {
    "keep": "--keep",
    "clean": "--no-clean",
    "orient": "--orient",
    "up": "--up",
    "spin": "--spin",
    "crop_below": "--crop-below",
    "crop_fraction": "--crop-fraction",
    "crop_plane": "--crop-plane",
    "faces": "--faces",
    "decimate": "--decimate",
    "smooth": "--smooth",
    "smooth_iterations": "--smooth METHOD:ITERATIONS",
    "smooth_step": "--smooth-step",
    "smooth_mu": "--smooth-mu",
    "smooth_pin_boundary": "--smooth-base",
}


class _Parser(argparse.ArgumentParser):
    """A usage error is one line naming the option (``dentopo: argument --keep: ...``), exit 2."""

    def error(self, message: str):
        say(f"prepare: {message} (see dentopo prepare --help)")
        raise SystemExit(2)


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="dentopo prepare",
        description=textwrap.fill(
            "Prepare raw scans for measuring: clean (keep the largest piece), orient occlusal "
            "side up, crop, decimate and smooth, as a protocol says; writes OUTDIR/NAME.ply "
            "and OUTDIR/NAME.prepare.json (what was done, with the input's SHA-256).",
            width=79,
        ),
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("paths", nargs="*", metavar="INPUT", help="mesh files, folders, globs")
    parser.add_argument("-o", "--output", metavar="OUTDIR", help="the folder of the outputs")
    protocol = parser.add_argument_group(
        "protocol (defaults: clean keeping the largest piece, orient occlusal side up)"
    )
    protocol.add_argument(
        "--protocol",
        metavar="FILE|NAME",
        help="read the protocol from a TOML file or a shipped name (see --protocols); the "
        "options below override it",
    )
    protocol.add_argument(
        "--save-protocol",
        metavar="FILE",
        help="write the protocol used as TOML (read back by --protocol); with no INPUT, only that",
    )
    protocol.add_argument(
        "--protocols", action="store_true", help="list the shipped protocols and exit"
    )
    protocol.add_argument(
        "--keep",
        type=str.lower,
        choices=("largest", "all"),
        help="after cleaning keep the largest piece by area (default) or all",
    )
    protocol.add_argument(
        "--no-clean",
        dest="clean",
        action="store_const",
        const=False,
        help="do not clean (merge coincident vertices, drop degenerate and duplicate faces)",
    )
    protocol.add_argument(
        "--orient",
        type=str.lower,
        choices=("occlusal", "none"),
        help="occlusal (default: turn the crown occlusal side up, +z, its open base on x-y) "
        "or none (keep the pose)",
    )
    protocol.add_argument("--up", metavar="X,Y,Z", help="the occlusal direction, by hand")
    protocol.add_argument(
        "--spin",
        type=str.lower,
        choices=("none", "footprint"),
        help="footprint: also turn about z so that the footprint's long axis lies along y "
        "(default none)",
    )
    protocol.add_argument(
        "--crop-below",
        dest="crop_below",
        type=float,
        metavar="H",
        help="remove what lies less than H (mesh units) above the lowest point, after orienting",
    )
    protocol.add_argument(
        "--crop-fraction",
        dest="crop_fraction",
        type=float,
        metavar="F",
        help="keep the top fraction F (0 to 1] of the crown's height, after orienting",
    )
    protocol.add_argument(
        "--crop-plane",
        dest="crop_plane",
        metavar="PX,PY,PZ,NX,NY,NZ",
        help="keep the side of the plane through P that N points to",
    )
    protocol.add_argument(
        "--faces", type=int, metavar="N", help="decimate to N faces (default: no decimation)"
    )
    protocol.add_argument(
        "--decimate",
        type=str.lower,
        choices=DECIMATORS,
        help="quadric (default: fast-simplification's quadric edge collapse) or meshlab "
        "(pymeshlab's, an optional GPL package)",
    )
    protocol.add_argument(
        "--smooth",
        metavar="METHOD[:ITERATIONS]",
        help=f"smooth: {', '.join(SMOOTHERS)} (implicit: implicit fairing as MorphoTester "
        "applies it), with ITERATIONS (default: the method's)",
    )
    protocol.add_argument(
        "--smooth-step",
        dest="smooth_step",
        type=float,
        metavar="S",
        help="the smoothing step (Laplacian's and Taubin's lambda, HC's alpha, implicit "
        "fairing's time step)",
    )
    protocol.add_argument(
        "--smooth-mu",
        dest="smooth_mu",
        type=float,
        metavar="MU",
        help="Taubin's nu, HC's beta",
    )
    protocol.add_argument(
        "--smooth-base",
        choices=("pinned", "free"),
        help="pinned (the default): the open base's vertices stay where they are; free: the "
        "filter as published, which pulls the base inwards",
    )
    run = parser.add_argument_group("running")
    run.add_argument(
        "--preview",
        metavar="DIR",
        help=f"write a picture of each file into DIR (NAME.png: the raw scan with its axis and "
        f"crop plane beside the prepared crown) and {SHEET}, all of them on one sheet "
        "(needs the viz extra)",
    )
    run.add_argument(
        "-j", "--jobs", type=int, default=1, metavar="N", help="worker processes (0: all cores)"
    )
    run.add_argument(
        "--resume",
        action="store_true",
        help="skip the files whose outputs exist for the same input bytes and protocol",
    )
    run.add_argument(
        "--geometry",
        metavar="NAME",
        help="in files holding several meshes, prepare the one named NAME, or 'all' joined",
    )
    run.add_argument("-q", "--quiet", action="store_true", help="no progress, only problems")
    return parser


class UsageError(Exception):
    """A problem with the options: one line, exit 2."""


def _smooth(text: str) -> tuple[str, int | None]:
    method, colon, count = text.partition(":")
    method = method.strip().lower()
    if method not in SMOOTHERS:
        raise UsageError(
            f"--smooth must be one of {', '.join(SMOOTHERS)} (with :ITERATIONS); got {text!r}"
        )
    if not colon:
        return method, None
    try:
        iterations = int(count)
    except ValueError:
        raise UsageError(
            f"--smooth {method}:ITERATIONS needs a whole number of iterations; got {count!r}"
        ) from None
    return method, iterations


#: A protocol field's name in a message (whole words; ``smooth`` is not inside ``smooth_mu``).
_FIELD = re.compile(
    r"(?<![\w\-])(" + "|".join(sorted(FIELD_OPTIONS, key=len, reverse=True)) + r")(?![\w\-])"
)


def option_message(message: str, parser: argparse.ArgumentParser) -> str:
    """A :class:`ProtocolError` message about the options, in the command's words."""
    if message.startswith("smoothing parameters need"):
        return "--smooth-step, --smooth-mu and --smooth-base need --smooth METHOD"
    message = CommandLineHints(parser)(message)  # orient='occlusal' -> --orient occlusal

    def named(match: re.Match) -> str:
        word = match.group(1)
        plain = "_" not in word
        start = match.start()
        lead = message[:start]
        if plain and not (start == 0 or (lead.endswith(" and ") and _FIELD.match(message))):
            return word  # an English word, not the field (unless it leads the message)
        return FIELD_OPTIONS[word]

    return _FIELD.sub(named, message)


def _changes(args) -> dict:
    """The protocol fields given on the command line."""
    changes = {}
    for name in (
        "keep",
        "clean",
        "orient",
        "up",
        "spin",
        "crop_below",
        "crop_fraction",
        "crop_plane",
        "faces",
        "decimate",
        "smooth_step",
        "smooth_mu",
    ):
        value = getattr(args, name)
        if value is not None:
            changes[name] = value
    if args.smooth_base is not None:
        changes["smooth_pin_boundary"] = args.smooth_base == "pinned"
    if args.smooth is not None:
        method, iterations = _smooth(args.smooth)
        changes["smooth"] = method
        if iterations is not None:
            changes["smooth_iterations"] = iterations
    return changes


def make_protocol(args, parser):
    """The protocol of this run: --protocol's (or the defaults), then the options given.

    Raises
    ------
    UsageError
        Naming the option, or the protocol file and its key.
    """
    try:
        base = load_protocol(args.protocol)
    except ProtocolError as exc:
        raise UsageError(f"--protocol: {exc}") from None
    except OSError as exc:
        raise UsageError(
            f"--protocol: cannot read {args.protocol!r}: {exc.strerror or exc}"
        ) from None
    changes = _changes(args)
    if not changes:
        return base
    if base.crop_below is not None or base.crop_fraction is not None or base.crop_plane is not None:
        if any(key.startswith("crop_") for key in changes):  # the option replaces the file's crop
            changes = {"crop_below": None, "crop_fraction": None, "crop_plane": None, **changes}
    if base.smooth is not None and "smooth" in changes and changes["smooth"] != base.smooth:
        # another method: the file's parameters were for its own method
        for key in ("smooth_iterations", "smooth_step", "smooth_mu"):
            changes.setdefault(key, None)
        changes.setdefault("smooth_pin_boundary", True)
    if changes.get("orient") == "none":
        changes.setdefault("up", None)
        changes.setdefault("spin", "none")
    try:
        return base.replace(**changes)
    except ProtocolError as exc:
        raise UsageError(option_message(str(exc), parser)) from None


def stated(protocol):
    """`protocol` with every step's parameters stated, as :meth:`Protocol.to_toml` writes them.

    The same steps (and digest) with the defaults filled in, so that the
    record of a run and the record of a run of its ``--save-protocol`` file
    are the same bytes.
    """
    try:  # Python 3.11+
        import tomllib
    except ModuleNotFoundError:  # pragma: no cover - Python 3.10
        import tomli as tomllib

    try:  # what is written reads back (tested); were it not, a usage error, not a traceback
        return Protocol.from_mapping(tomllib.loads(protocol.to_toml()))
    except (ProtocolError, tomllib.TOMLDecodeError) as exc:  # pragma: no cover
        raise UsageError(f"the protocol cannot be written as TOML: {exc}") from None


def list_protocols() -> int:
    """``--protocols``: each shipped protocol's name, digest, description and source."""
    for name, protocol in named_protocols().items():
        print(f"{name} ({protocol.digest[:12]})")
        if protocol.description:
            print(f"  {protocol.description}")
        if protocol.source:
            print(f"  source: {protocol.source}")
        steps = ", ".join(
            f"{step} {' '.join(f'{k}={v}' for k, v in parameters.items() if v is not None)}"
            for step, parameters in protocol.steps().items()
        )
        print(f"  steps: {steps}")
    sys.stdout.flush()
    return 0


def _save_protocol(path: str, protocol) -> None:
    text = protocol.to_toml()
    atomic_write(path, lambda stream: stream.write(text))


def _searched_folders(paths) -> list[str]:
    """The folders a later ``dentopo FOLDER`` of these inputs would search: each folder given,
    and the folder of each file (or pattern) given (``raw/*.ply`` is the folder ``raw``)."""
    folders = []
    for path in paths:
        folder = path if os.path.isdir(path) else os.path.dirname(os.path.abspath(path))
        if os.path.isdir(folder):
            folders.append(folder)
    return folders


def _inside(path: str, folder: str) -> bool:
    path, folder = os.path.realpath(path), os.path.realpath(folder)
    return os.path.commonpath([path, folder]) == folder


def _planned(args, tasks) -> list[Planned]:
    planned = []
    for task in tasks:
        planned.append(Planned(f"the prepared mesh of {task.file!r}", task.mesh_path))
        planned.append(Planned(f"the record of {task.file!r}", task.record_path))
        if task.preview_path is not None:
            planned.append(Planned(f"the preview of {task.file!r}", task.preview_path))
    if args.preview is not None:
        planned.append(Planned("the preview sheet", os.path.join(args.preview, SHEET)))
    if args.save_protocol is not None:
        planned.append(
            Planned("--save-protocol", args.save_protocol, (".toml",), "a protocol", check=True)
        )
    planned.append(Planned("--output", args.output, check=True, folder=True))
    if args.preview is not None:
        planned.append(Planned("--preview", args.preview, check=True, folder=True))
    return planned


def prepare_main(argv: list[str]) -> int:
    """Run ``dentopo prepare`` with `argv`; the exit code."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as stop:
        return stop.code if isinstance(stop.code, int) else 0
    if args.protocols:
        return list_protocols()
    try:
        protocol = stated(make_protocol(args, parser))
    except UsageError as exc:
        say(str(exc))
        return 2
    if args.jobs < 0:
        say("--jobs must be 0 (all cores) or more")
        return 2
    if not args.paths:
        if args.save_protocol is None:
            say("no mesh files given (try --help)")
            return 2
        problem = output_problem(_planned_save_only(args))
        if problem:
            say(problem)
            return 2
        try:
            _save_protocol(args.save_protocol, protocol)
        except OSError as exc:
            say(f"cannot write --save-protocol {args.save_protocol!r}: {exc.strerror or exc}")
            return 1
        if not args.quiet:
            say(f"wrote the protocol {protocol.label} to {args.save_protocol}")
        return 0
    if args.output is None:
        say("give the output folder: -o OUTDIR")
        return 2
    render = None
    if args.preview is not None:
        try:
            PICTURES.check()
        except MissingExtraError as exc:
            say(f"--preview: {exc}")
            return 2
        from ..figures import render_preparation

        render = render_preparation

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        found = find_mesh_files(args.paths)
    for warning in caught:
        say(f"warning: {warning.message}")
    for pattern in found.unmatched:
        say(f"no mesh files in {pattern!r}")
    own = [d for d in (args.output, args.preview) if d is not None and os.path.isdir(d)]
    given = {os.path.abspath(p) for p in args.paths}  # a file named is kept (and refused below)
    files = [
        f for f in found.files if os.path.abspath(f) in given or not any(_inside(f, d) for d in own)
    ]
    left_out = len(found.files) - len(files)
    if left_out and files and not args.quiet:
        say(f"{counted(left_out, 'file')} in the output folders left out")
    if not files:
        if left_out:  # every file found lies in the output folder: it holds the inputs
            folders = " and ".join(repr(d) for d in own)
            say(
                f"no mesh files found outside the output folder {folders}: its {left_out} "
                "file(s) count as outputs, not inputs; give an output folder that does not "
                "hold the inputs"
            )
        else:
            say("no mesh files found")
        return 2
    tasks = plan_preparation(files, args.paths, args.output, preview=args.preview)
    problem = output_problem(_planned(args, tasks), [("the input mesh", f) for f in files])
    if problem:
        say(problem)
        return 2
    if args.save_protocol is not None:
        try:
            _save_protocol(args.save_protocol, protocol)
        except OSError as exc:
            say(f"cannot write --save-protocol {args.save_protocol!r}: {exc.strerror or exc}")
            return 2
    try:
        if any(_inside(args.output, folder) for folder in _searched_folders(args.paths)):
            mark_output_folder(args.output)
    except OSError as exc:
        say(f"cannot write into --output {args.output!r}: {exc.strerror or exc}")
        return 2
    with guard_interrupts_all() as guard:
        try:
            code = _run(args, parser, protocol, tasks, render)
        except KeyboardInterrupt as exc:
            say(f"{_interruption(exc)}: the files done are complete; rerun with --resume to finish")
            code = INTERRUPTED
        guard.pending = None
    return code


#: What the mark of a folder ``dentopo prepare`` writes into says.
MARK_TEXT = (
    "dentopo prepare writes into this folder. The dentopo command, searching a folder for\n"
    "meshes, skips a subfolder holding this file, so that the prepared meshes here are not\n"
    "measured again as scans.\n"
)


def mark_output_folder(folder: str) -> None:
    """Mark `folder` as this tool's output (:data:`dentopo.batch.OUTPUT_FOLDER_MARK`), if new.

    Called for an output folder inside an input folder, so that a later
    ``dentopo INPUT`` does not measure the prepared copies again as scans
    (as ``dentopo app`` marks its own).  Only a folder this run creates, or
    finds empty, or already marked: a folder holding other files may hold
    scans, which a mark would hide.  Raises OSError if it cannot be written.
    """
    from ..batch import OUTPUT_FOLDER_MARK

    mark = os.path.join(folder, OUTPUT_FOLDER_MARK)
    if os.path.isdir(folder) and (os.path.lexists(mark) or os.listdir(folder)):
        return
    os.makedirs(folder, exist_ok=True)
    atomic_write(mark, lambda stream: stream.write(MARK_TEXT))


def _planned_save_only(args) -> list[Planned]:
    return [Planned("--save-protocol", args.save_protocol, (".toml",), "a protocol", check=True)]


def guard_interrupts_all():
    from ..batch import guard_interrupts

    return guard_interrupts(signal.SIGINT, signal.SIGTERM)


def _interruption(exc: BaseException) -> str:
    name = getattr(exc, "name", "SIGINT")
    return "interrupted" if name == "SIGINT" else f"interrupted ({name})"


def _run(args, parser, protocol, tasks, render) -> int:
    if args.resume:
        todo = [t for t in tasks if not is_done(t, protocol, geometry=args.geometry)]
        if not args.quiet:
            say(f"resuming: {len(tasks) - len(todo)} of {len(tasks)} files already done")
    else:
        todo = list(tasks)
    jobs = args.jobs or _cores()
    hints = CommandLineHints(parser)
    progress = Progress(len(todo), quiet=args.quiet)
    failed = 0
    done = 0
    running = run_preparation(todo, protocol, jobs=jobs, geometry=args.geometry, render=render)
    try:
        for outcome in running:
            record = hints.record(outcome.record)
            for message in outcome.warnings:  # one short line each; the record keeps them whole
                progress.warning(outcome.file, hints(message))
            progress.update(record)
            done += 1
            failed += outcome.status != "ok"
    except KeyboardInterrupt:
        running.close()
        progress.close()
        progress.explain()
        say(f"{done} of {len(todo)} files done")
        raise
    finally:
        running.close()
        progress.close()
    progress.explain()  # each long warning's explanation, once per run
    code = 1 if failed else 0
    if render is not None:
        code = max(code, _sheet(args, tasks))
    if not args.quiet:
        skipped = len(tasks) - len(todo)
        more = f", {skipped} already done" if skipped else ""
        say(
            f"prepared {done - failed} of {len(todo)} files into {args.output} "
            f"({failed} failed{more}); protocol {protocol.label}"
        )
    return code


def _cores() -> int:
    from ..batch import available_cores

    return available_cores()


def _sheet(args, tasks) -> int:
    """The contact sheet of every preview there is (this run's and earlier ones')."""
    from ..figures import preview_sheet

    pictures = [(t.preview_path, t.file) for t in tasks if os.path.isfile(t.preview_path)]
    if not pictures:
        return 0
    path = os.path.join(args.preview, SHEET)
    try:
        preview_sheet([p for p, _ in pictures], path, labels=[label for _, label in pictures])
    except (OSError, ValueError) as exc:
        say(f"cannot write the preview sheet {path!r}: {getattr(exc, 'strerror', None) or exc}")
        return 1
    if not args.quiet:
        say(f"wrote {counted(len(pictures), 'preview')} on {path}")
    return 0
