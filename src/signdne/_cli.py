"""The ``signDNE`` command: a thin shell over the public API."""

from __future__ import annotations

import argparse
import sys

from ._ariadne import ariaDNE
from ._version import __version__
from .samples import sample_paths

COLUMNS = ("file", "dne", "positive_dne", "negative_dne", "surface_area")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="signDNE", description="ariaDNE and its sign-oriented extension for triangle meshes."
    )
    parser.add_argument("paths", nargs="*", help="mesh files")
    parser.add_argument("--samples", action="store_true", help="add the bundled sample meshes")
    parser.add_argument("-b", "--bandwidth", type=float, default=0.08)
    parser.add_argument("--version", action="version", version=f"signDNE {__version__}")
    return parser


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    paths = list(args.paths)
    if args.samples:
        paths += [str(path) for path in sample_paths().values()]
    if not paths:
        print("signDNE: no mesh files given", file=sys.stderr)
        return 2
    print("\t".join(COLUMNS))
    failed = False
    for path in paths:
        try:
            row = ariaDNE(path, bandwidth=args.bandwidth).to_dict()
        except (OSError, ValueError, TypeError) as exc:
            print(f"signDNE: {path}: {exc}", file=sys.stderr)
            failed = True
            continue
        print("\t".join([path] + [f"{row[key]:.6g}" for key in COLUMNS[1:]]))
    return 1 if failed else 0


def run() -> None:  # console-script entry point
    sys.exit(main())
