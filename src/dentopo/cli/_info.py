"""``dentopo info FILE``: print the provenance kept in a picture written by dentopo.

PNG pictures keep it in a text chunk named ``dentopo``, HTML pages in a
``<script type="application/json" id="dentopo-provenance">`` block
(:func:`dentopo.figures.read_provenance`).  The JSON is printed indented on
stdout; a file without it is an error (one line on stderr, exit code 1) that
says what ``info`` takes, and for a mesh (``dentopo info scan.ply``, as one
might try to see what a scan holds) how to measure it instead.
"""

from __future__ import annotations

import argparse
import json
import os
import shlex
import sys

from ..figures import read_provenance
from ._progress import PROG, say


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog=f"{PROG} info",
        description="Print what a picture or page written by dentopo shows and how it was made: "
        "package version, input file and its SHA-256, metric, parameters and camera (JSON). "
        f"It reads dentopo's PNG pictures and HTML pages, not meshes: to measure a mesh, run "
        f"{PROG} MESH.",
    )
    parser.add_argument(
        "files", nargs="+", metavar="FILE", help="PNG pictures or HTML pages written by dentopo"
    )
    return parser


#: What ``info`` takes, for the message about a file it does not take.
TAKES = "dentopo info reads the record dentopo keeps in the PNG pictures and HTML pages it writes"


def _not_taken(name: str, reason: str) -> str:
    """The line for a file ``info`` does not take: the reason, what it takes, what to run."""
    from ..batch import MESH_EXTENSIONS  # only here: the message of a file it does not take

    extension = os.path.splitext(name)[1].lower().lstrip(".")
    if extension in MESH_EXTENSIONS:
        return (
            f"{name!r} is a mesh, not a picture: {TAKES}; to measure the mesh, run "
            f"{PROG} {shlex.quote(name)} (see {PROG} --help)"
        )
    return f"{reason}: {TAKES}"


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
            if "neither a PNG nor an HTML" in str(exc):  # a file of another kind
                say(_not_taken(name, str(exc)))
            else:
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
