"""``dentopo info FILE``: print the provenance kept in a picture written by dentopo.

PNG pictures keep it in a text chunk named ``dentopo``, HTML pages in a
``<script type="application/json" id="dentopo-provenance">`` block
(:func:`dentopo.figures.read_provenance`).  The JSON is printed indented on
stdout; a file without it is an error (one line on stderr, exit code 1).
"""

from __future__ import annotations

import argparse
import json
import sys

from ..figures import read_provenance
from ._progress import PROG, say


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog=f"{PROG} info",
        description="Print what a picture written by dentopo shows and how it was made: package "
        "version, input file and its SHA-256, metric, parameters and camera (JSON).",
    )
    parser.add_argument("files", nargs="+", metavar="FILE", help="PNG pictures or HTML pages")
    return parser


def info_main(argv: list[str]) -> int:
    """Run ``dentopo info`` with `argv`; the exit code (0, 1 a file without provenance, 2 usage)."""
    try:
        args = build_parser().parse_args(argv)
    except SystemExit as stop:
        return stop.code if isinstance(stop.code, int) else 0
    code = 0
    records = {}
    for name in args.files:
        try:
            records[name] = read_provenance(name)
        except ValueError as exc:
            say(f"cannot read the provenance: {exc}")
            code = 1
        except OSError as exc:
            say(f"cannot read {name!r}: {exc.strerror or exc}")
            code = 1
    if len(args.files) == 1 and records:
        print(json.dumps(records[args.files[0]], indent=2, ensure_ascii=False))
    elif records:
        print(json.dumps(records, indent=2, ensure_ascii=False))
    sys.stdout.flush()
    return code
