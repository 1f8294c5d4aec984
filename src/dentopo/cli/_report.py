"""``dentopo report TABLE``: one self-contained HTML page for a table already computed.

Also :func:`report_after_batch`, which the main command's ``--report FILE`` calls
once its table is written.  Exit codes: 0 written; 1 the page could not be
written; 2 usage error (bad options, a table or groups file that cannot be
read, a missing extra).
"""

from __future__ import annotations

import argparse
import os

from ..report import check_report_extras, write_report
from ._output import Planned, output_problem
from ._progress import PROG
from ._progress import say as _say

EXAMPLES = """\
examples:
  dentopo report results.csv -o report.html
  dentopo report results.csv -o report.html --groups groups.csv
  dentopo scans/ -o results.csv --report report.html   # compute, then the report

groups are the folders of the files (relative to their common root), or the
'group' column of --groups FILE.csv, whose 'file' column names each mesh by
path (relative to the CSV's folder) or by base name.
"""


def build_parser() -> argparse.ArgumentParser:
    """The parser of ``dentopo report``."""
    parser = argparse.ArgumentParser(
        prog=f"{PROG} report",
        description="Write one self-contained HTML page about a results table: a sortable, "
        "filterable table with a picture of each specimen, each metric's distribution by "
        "group, a scatter matrix, and a 3D view of any specimen on click.",
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("table", metavar="TABLE", help="a results table (csv, tsv, json, xlsx)")
    parser.add_argument(
        "-o", "--output", metavar="FILE", help="the page to write (default: TABLE's name, .html)"
    )
    parser.add_argument("--groups", metavar="CSV", help="a CSV of file,group")
    parser.add_argument("--title", help="the page's title")
    parser.add_argument(
        "--limits", type=float, metavar="L", help="fixed colour limits (-L, L) for every picture"
    )
    parser.add_argument(
        "--percentile",
        type=float,
        default=98.0,
        help="colour limits at this percentile of |value| over the collection (default 98)",
    )
    parser.add_argument(
        "-j", "--jobs", type=int, default=0, metavar="N", help="worker processes (0: all cores)"
    )
    parser.add_argument(
        "--prepare",
        metavar="PROTOCOL",
        action="append",
        help="the protocol (a TOML file) the rows were prepared with by dentopo --prepare, "
        "to picture the prepared crowns (repeatable: rows prepared with several); shipped "
        "protocols are found by the digest in the protocol column",
    )
    parser.add_argument("-q", "--quiet", action="store_true", help="no summary line")
    return parser


def _plural(count: int, noun: str) -> str:
    return f"{count} {noun}{'' if count == 1 else 's'}"


def _default_output(table: str) -> str:
    return os.path.splitext(table)[0] + ".html"


def make_report(table, output: str, *, quiet: bool = False, **options) -> int:
    """Write the report of `table` to `output` and say so; the exit code (0, 1 or 2).

    1: the page is written, but rows measured ``ok`` have no picture (a file
    moved or unreadable since, a worker that failed): the first is named.
    """
    try:
        summary = write_report(table, output, **options)
    except (TypeError, ValueError) as exc:
        _say(str(exc))
        return 2
    except OSError as exc:
        _say(f"cannot write the report {output!r}: {exc.strerror or exc}")
        return 1
    if not quiet:
        missing = summary.specimens - summary.pictured
        detail = f", {missing} without a picture" if missing else ""
        _say(
            f"wrote {summary.path}: {_plural(summary.specimens, 'specimen')} in "
            f"{_plural(len(summary.groups), 'group')}{detail}, {summary.size / 1e6:.1f} MB, "
            f"{summary.seconds:.1f} s"
        )
    if summary.unpictured:  # rows measured ok that the page cannot show: a failure, named
        file, why = next(iter(summary.unpictured.items()))
        more = len(summary.unpictured) - 1
        _say(
            f"{_plural(len(summary.unpictured), 'specimen')} measured ok but without a picture: "
            f"{file}: {why}" + (f" (and {more} more, listed in the report)" if more else "")
        )
        return 1
    return 0


def report_main(argv: list[str]) -> int:
    """Run ``dentopo report`` with `argv`; the exit code."""
    try:
        args = build_parser().parse_args(argv)
    except SystemExit as stop:
        return stop.code if isinstance(stop.code, int) else 0
    if args.jobs < 0:
        _say("--jobs must be 0 (all cores) or more")
        return 2
    check_report_extras()  # a missing extra: one line (the entry point prints it), exit 2
    output = args.output or _default_output(args.table)
    problem = report_problem(output, "-o" if args.output else "the report", args.table, args.groups)
    if problem:
        _say(problem)
        return 2
    return make_report(
        args.table,
        output,
        quiet=args.quiet,
        groups=args.groups,
        title=args.title,
        limits=args.limits,
        percentile=args.percentile,
        jobs=args.jobs or None,
        prepare=args.prepare,
    )


#: What a report is written as.
REPORT_SUFFIXES = (".html", ".htm")


def report_problem(output: str, what: str, table: str, groups: str | None = None) -> str | None:
    """Why the report cannot be written at `output` (an input, not .html, ...), or None."""
    inputs = [("the table", table)] + ([("--groups", groups)] if groups else [])
    page = Planned(what, output, REPORT_SUFFIXES, "an HTML page", check=True)
    return output_problem([page], inputs)


def report_after_batch(table: str, output: str, *, quiet: bool = False, prepare=None) -> int:
    """The main command's ``--report``: the report of the table just written.

    `prepare` is the batch's protocol (``--prepare``), if any: the pictures
    are then of the prepared crowns.
    """
    return make_report(table, output, quiet=quiet, prepare=prepare)
