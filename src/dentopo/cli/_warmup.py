"""``dentopo warmup [OPTIONS]``: compile the kernels a run with OPTIONS needs, and say where.

It takes the options of a run (``--metrics``, ``-j``, ``-d``, ``--prepare`` ...)
without mesh files, computes the bundled sample crown with them
(:func:`dentopo.batch.warm_up`) and says where numba keeps the kernels: for an
image built for a cluster, a shared ``NUMBA_CACHE_DIR``, or a first run that
starts at once.  ``--force`` compiles (or loads) again what a stamp says is done.
"""

from __future__ import annotations

import argparse

from ..batch import available_cores, kernel_cache, metric_groups, missing_metrics, warm_up
from ._arguments import build_parser, split_pairs
from ._compiling import done_text, notice_text
from ._compute import settings_from_args
from ._progress import PROG, say

DESCRIPTION = (
    "Compile the kernels that a run with these options needs (the metrics, -d, --method, "
    "--pcv-method, --prepare ...), on the bundled sample crown, in up to -j processes at once; "
    "say where numba keeps them. Later runs, and the worker processes of a -j run, load them "
    "instead of compiling. Set NUMBA_CACHE_DIR to choose the folder (a cluster's shared one)."
)


def build_warmup_parser() -> argparse.ArgumentParser:
    """The main command's parser, as ``dentopo warmup`` (no mesh files; ``--force``)."""
    parser = build_parser()
    parser.prog = f"{PROG} warmup"
    parser.usage = f"{PROG} warmup [--metrics NAMES] [-j N] [--force] [other options of a run]"
    parser.description = DESCRIPTION
    parser.epilog = (
        f"examples:\n  {PROG} warmup                      ariaDNE's kernels\n"
        f"  {PROG} warmup --metrics all -j 0   every metric's, on every core\n"
        f"  NUMBA_CACHE_DIR=/shared/numba {PROG} warmup --metrics all"
    )
    parser.add_argument(
        "--force",
        action="store_true",
        help="compute the sample even where a stamp says its kernels are compiled",
    )
    return parser


def warmup_main(argv: list[str]) -> int:
    """Run ``dentopo warmup`` with `argv`; the exit code (0, or 2: a usage error)."""
    parser = build_warmup_parser()
    try:
        args = parser.parse_args(split_pairs(argv))
    except SystemExit as stop:
        return stop.code if isinstance(stop.code, int) else 0
    if args.paths or args.samples:
        say("warmup takes the options of a run (--metrics, -j, ...), not mesh files")
        return 2
    if args.jobs < 0:
        say(f"-j must be 0 (all cores) or more; got {args.jobs}")
        return 2
    try:
        settings = settings_from_args(args)
    except (TypeError, ValueError) as exc:
        say(str(exc))
        return 2
    jobs = args.jobs or available_cores()
    missing = settings.metrics if args.force else missing_metrics(settings)
    if not missing:
        say(
            f"the kernels of {', '.join(settings.metrics)} are compiled for this machine "
            f"(numba's cache: {kernel_cache()}; --force computes the sample again)"
        )
        return 0
    if not args.quiet:
        say(notice_text(missing, len(metric_groups(missing, jobs))))
    warm = warm_up(settings, jobs=jobs, force=args.force)
    say(done_text(warm))
    return 0
