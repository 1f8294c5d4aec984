"""``dentopo app [FOLDER]``: the local web app, started from the command line.

Prints one line, ``dentopo app: http://127.0.0.1:PORT/?token=SECRET`` (the
address carries the secret every request needs), opens the browser on it unless
``--no-browser``, and serves until Ctrl-C (a run in progress is stopped and
writes the rows it finished).  Exit codes: 0 stopped; 2 usage error (not a
folder, a port taken, the app extra missing).
"""

from __future__ import annotations

import argparse
import os
import sys

from .._optional import APP, APP_SERVER
from ._progress import PROG
from ._progress import say as _say

EXAMPLES = """\
examples:
  dentopo app scans/                     # opens the browser on the app
  dentopo app scans/ --no-browser --port 8800
  dentopo app scans/ --output results/   # write somewhere else than scans/dentopo-app

Everything the app writes goes into the output folder (default FOLDER/dentopo-app; --output
chooses it at start, the page another folder inside FOLDER): the results table (results.csv,
as the command writes it), protocols, pictures, the report and the prepared meshes.
Reopening the folder shows what is done.
"""


def build_parser() -> argparse.ArgumentParser:
    """The parser of ``dentopo app``."""
    parser = argparse.ArgumentParser(
        prog=f"{PROG} app",
        description="Run the whole study in the browser: see a folder's meshes, prepare them, "
        "measure them, look at the results and export them, without writing code.",
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument(
        "folder", nargs="?", default=".", help="the folder of meshes (default: here)"
    )
    parser.add_argument(
        "-o", "--output", metavar="DIR", help="where the app writes (default FOLDER/dentopo-app)"
    )
    parser.add_argument(
        "--port", type=int, metavar="N", help="the port (default 8765, or any free one if taken)"
    )
    parser.add_argument(
        "--host",
        default="127.0.0.1",
        help="the address to listen on (default 127.0.0.1, this computer only; another address "
        "lets other computers reach the app, with its secret: a warning says so)",
    )
    parser.add_argument("--no-browser", action="store_true", help="do not open the browser")
    return parser


def app_main(argv: list[str]) -> int:
    """Run ``dentopo app`` with `argv`; the exit code."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as stop:
        return stop.code if isinstance(stop.code, int) else 0
    APP.check()
    APP_SERVER.check()
    from ..app import AppError, AppServer, is_loopback

    if not os.path.isdir(args.folder):
        _say(f"not a folder: {args.folder!r}")
        return 2
    if args.port is not None and not 0 <= args.port <= 65535:
        _say(f"--port must be from 0 to 65535; got {args.port}")
        return 2
    try:
        server = AppServer(args.folder, output=args.output, host=args.host, port=args.port)
    except AppError as exc:
        _say(str(exc))
        return 2
    except OSError as exc:
        _say(f"cannot listen on {args.host}:{args.port}: {exc.strerror or exc}")
        return 2
    if not is_loopback(args.host):
        _say(
            f"warning: listening on {args.host}, not only this computer: anyone who can reach "
            "this address and has the secret can read and write the folder"
        )
    print(f"{PROG} app: {server.url}")
    print(f"{PROG} app: the folder {server.workspace.root}; writing to {server.workspace.output}")
    print(f"{PROG} app: Ctrl-C to stop")
    sys.stdout.flush()
    if not args.no_browser:
        import webbrowser

        webbrowser.open(server.url)
    server.serve()
    return 0
