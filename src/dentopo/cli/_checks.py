"""The main command's checks before any file is read: each names one problem, or None.

:func:`usage_problem` (options that contradict each other, a table suffix
without its writer, ``--report`` without ``-o FILE``), :func:`outputs_problem`
(every file and folder the run will write, none onto an input or another
output, each with a suffix its writer writes), :func:`missing_extra` (an extra
the options need and is not installed) and :func:`picture_problem` (a
``--color-by`` that cannot be drawn as asked).  A problem found here ends the
command with exit code 2 before anything is computed or written.
"""

from __future__ import annotations

import os

from .._optional import PICTURES, MissingExtraError
from ..batch import check_extras, plan_batch, planned_per_vertex_files
from ..formats import FORMATS, journal_path, layout, lock_path, table_format
from ._arguments import (
    FACE_PICTURES,
    METRIC_PICTURES,
    PICTURE_FORMATS,
    PICTURE_STEP,
    STDOUT,
    rendering_requested,
)
from ._output import Planned, output_problem


def usage_problem(args) -> str | None:
    """A usage problem with the options (before any file is read), or None."""
    if args.jobs < 0:
        return "--jobs must be 0 (all cores) or more"
    if args.output is not None and args.output != STDOUT:
        try:  # a known suffix, and its optional dependency (openpyxl for .xlsx)
            table_format(args.output).check_available()
        except (ValueError, ImportError) as exc:
            return str(exc)
    problem = _report_problem(args)
    if problem:
        return problem
    if args.resume and args.output is None:
        return "--resume needs --output (the table to resume)"
    if args.resume and args.output == STDOUT:
        return "--resume needs an --output file to resume, not '-' (stdout)"
    if args.resume and not layout(args.columns).resumable:
        return (
            f"--resume matches rows by their settings columns (bandwidth, cutoff, ...), which "
            f"--columns {args.columns} does not write; resume without --columns {args.columns}"
        )
    if args.per_vertex_format and args.per_vertex is None:
        return "--per-vertex-format needs --per-vertex DIR"
    if args.dpi is not None and not 10 <= args.dpi <= 2400:
        return "--dpi must lie in 10..2400"
    return None


def _report_problem(args) -> str | None:
    """A problem with --report (it is made from the --output table), or None."""
    if args.report is None:
        return None
    if args.output in (None, STDOUT):
        return "--report is made from the table written: give -o FILE too"
    from ..report import check_report_extras

    check_report_extras()  # MissingExtraError: one line naming the extra, exit 2
    return None  # its path: see outputs_problem


#: What the HTML page of --html and --report is written as.
HTML_SUFFIXES = (".html", ".htm")


def _planned_outputs(args, files: list[str], settings, per_vertex) -> list[Planned]:
    """Every file and folder this run will write (see :func:`._output.output_problem`)."""
    planned = []
    if args.per_vertex is not None:  # first: another output is then named as "also" one of them
        directory = os.path.abspath(args.per_vertex)
        for task in plan_batch(files, settings, per_vertex_dir=directory, per_vertex=per_vertex):
            what = f"the per-vertex file of {task.file!r} (--per-vertex)"
            for path in planned_per_vertex_files(task, settings.metrics):
                shown = os.path.join(args.per_vertex, os.path.basename(path))
                planned.append(Planned(what, shown))
    if args.output not in (None, STDOUT):
        table = args.output
        planned.append(Planned("--output", table, tuple(FORMATS), "a table", check=True))
        planned.append(Planned("the journal of --output", journal_path(table)))
        planned.append(Planned("the lock of --output", lock_path(table)))
    pages = (("--report", args.report), ("--html", args.html))
    for option, path in pages:
        if path is not None:
            planned.append(Planned(option, path, HTML_SUFFIXES, "an HTML page", check=True))
    if args.screenshot is not None:
        kind = "a picture"
        planned.append(Planned("--screenshot", args.screenshot, PICTURE_FORMATS, kind, check=True))
    if args.panel is not None:
        suffixes = (*PICTURE_FORMATS, ".html")
        planned.append(Planned("--panel", args.panel, suffixes, "a picture or a page", check=True))
    if args.per_vertex is not None:
        planned.append(Planned("--per-vertex", args.per_vertex, check=True, folder=True))
    return planned


def outputs_problem(args, files: list[str], settings, per_vertex) -> str | None:
    """An output that is an input, another output, or has the wrong suffix (or None)."""
    inputs = [("the input mesh", file) for file in files]
    return output_problem(_planned_outputs(args, files, settings, per_vertex), inputs)


def missing_extra(args, settings, scheduler) -> str | None:
    """The one-line message if an extra the options need is not installed, or None.

    Checked before any file is read (cheap: nothing is imported).  HTML pages
    need no extra; ``--method fast`` needs finufft only where the meshes are
    computed (here, unless a scheduler's workers compute them); ``--method
    auto`` falls back to the exact sums silently.
    """
    png_panel = args.panel is not None and not args.panel.lower().endswith(".html")
    try:
        if args.show or args.screenshot or png_panel:
            PICTURES.check()
        check_extras(settings, scheduler=scheduler)
    except MissingExtraError as exc:
        return str(exc)
    return None


def picture_problem(args, metrics) -> str | None:
    """A problem with drawing a metric's picture (--color-by), or None."""
    drawn = args.color_by
    if drawn not in METRIC_PICTURES:
        return None
    if drawn not in PICTURE_STEP and drawn not in metrics:
        return f"--color-by {drawn} draws a metric that is not computed: add --metrics {drawn}"
    if not rendering_requested(args):
        return None
    if args.panel is not None:
        return (
            f"--panel draws ariaDNE's local_curvature or local_dne side by side; --color-by "
            f"{drawn} draws one mesh (--screenshot, --html or --show)"
        )
    if args.limits and drawn in FACE_PICTURES and drawn != "arc":
        return (
            f"--limits sets a diverging scale (ariaDNE's curvature, ARC); --color-by {drawn} "
            "is drawn on its own sequential scale (see --help)"
        )
    return None
