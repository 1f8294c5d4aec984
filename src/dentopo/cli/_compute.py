"""The main command, ``dentopo PATH...``: compute a table with one row per mesh.

Finds the mesh files, computes them as a batch (:mod:`dentopo.batch`), writes
the table (:mod:`dentopo.formats`) and, if asked, draws the curvature
(:mod:`dentopo.figures`, whose pyvista is imported only then).  Only the CLI
prints: results to stdout or files, messages and progress to stderr.

Exit codes: 0 all files ok; 1 some file failed (or the display is unavailable,
or the table could not be written); 2 usage error (including "no mesh files
found", an output that cannot be written and a missing extra, checked before
any file is computed); 130 interrupted by Ctrl-C or SIGTERM (the rows done are
written).  With ``-o FILE`` each finished row is also kept in a journal beside
FILE as it finishes, so that a run killed outright loses only the meshes in
flight (see :mod:`._output`).
"""

from __future__ import annotations

import argparse
import importlib
import os
import signal
import sys
import textwrap
import warnings
from dataclasses import replace

from .._optional import PICTURES, MissingExtraError
from .._version import __version__
from ..ariadne import METHODS
from ..batch import (
    FORMAT_PACKAGES,
    MESH_EXTENSIONS,
    Interrupted,
    Outcome,
    available_cores,
    check_extras,
    find_mesh_files,
    guard_interrupts,
    make_settings,
    merge_records,
    plan_batch,
    planned_per_vertex_files,
    relabel_resumed,
    replaced_message,
    replaced_per_vertex_files,
    resumable_files,
    run_tasks,
)
from ..figures import DEFAULT_VIEW, VIEW_NAMES
from ..formats import (
    DEFAULT_PER_VERTEX_FORMATS,
    FORMATS,
    LAYOUTS,
    PER_VERTEX_FORMATS,
    NotAJournalError,
    PerVertexOptions,
    journal_path,
    layout,
    lock_path,
    read_table,
    table_format,
    write_table,
)
from ..samples import sample_paths
from ..sign import SIGN_METHODS
from ..topography import BOUNDARY_RULES, DUPLICATE_MODES, GROUPS, METRICS, ORIENT_MODES
from ._compiling import CompileNotice, notice_text
from ._hints import CommandLineHints
from ._output import Planned, TableOutput, output_problem
from ._progress import PROG, Progress
from ._progress import say as _say
from ._table import print_layout, print_table, table_columns

#: Environment variable naming a Dask scheduler, used when --scheduler is not given.
SCHEDULER_ENV = "DENTOPO_SCHEDULER"

#: Picture formats of --screenshot and --panel (besides .html).
PICTURE_FORMATS = (".png", ".svg", ".pdf")

#: ``--color-by`` fields of ariaDNE, and the metrics that have a picture of their own.
CURVATURE_FIELDS = ("local_curvature", "local_dne")
#: Per-face maps of one value (:data:`dentopo.figures.FACE_METRICS`): ARC on the diverging
#: map, the others on the sequential one.
FACE_PICTURES = ("arc", "angularity", "inclination", "elevation")
#: Pictures computed in the picture step from the mesh itself (not batch metrics).
PICTURE_STEP = ("elevation",)
METRIC_PICTURES = ("slope", "opc", "rfi", *FACE_PICTURES)

#: The metrics of ``--columns molar`` when --metrics is not given: molaR_Batch's defaults
#: (classic DNE, RFI, OPCR, slope), and ariaDNE.
MOLAR_DEFAULT_METRICS = ("ariadne", "classic", "rfi", "opcr", "slope")

#: ``-o -``: the table goes to stdout (as CSV).
STDOUT = "-"

EXAMPLES = """\
examples:
  dentopo path/to/mesh1.obj path/to/mesh2.ply -o DNEs.csv
  dentopo path/to/mesh/directory -b 0.1
  dentopo path/to/mesh.ply -v
  dentopo "scans/**/*.ply" -j 0 -o results.json --resume
  dentopo scans/ --per-vertex per_vertex/ -o results.csv
  dentopo scans/ -o - | cut -d, -f1,2           # CSV on stdout, messages on stderr
  dentopo scans/ --columns signdne -o DNEs.csv  # the published signDNE CLI's columns
  dentopo scans/ --metrics all --find-alpha -o topography.csv  # crowns turned up if need be
  dentopo scans/ --metrics molar --find-alpha --orient as-is --columns molar -o molar.csv
  dentopo tooth.ply --metrics opc --color-by opc --screenshot opc.png
  dentopo tooth.ply --metrics arc --color-by arc --screenshot arc.png --html arc.html
  dentopo tooth.ply --color-by elevation --screenshot elevation.png
  dentopo scans/ --prepare crown-10k --metrics all -o prepared.csv  # prepared in memory
  dentopo scans/ --scheduler tcp://head-node:8786 -o results.csv --resume

{inputs}
A file named like a subcommand is given as ./NAME.

columns (also in the API and the files): file, dne, positive_dne,
negative_dne, surface_area, positive_surface_area, negative_surface_area,
vertices, faces, bandwidth, cutoff, distance_type, sign_method, method,
protocol, seconds, status, error, warnings; --metrics adds each metric's columns (classic_dne ...,
rfi, area_3d, area_2d, alpha, opcr, opc_0 ... opc_39.375, opc, opc_bin1 ...
opc_bin8, slope, orientation) and its settings. A metric that fails on a mesh
leaves its cells empty, names itself in the error column, and the row's status
is "partial".

exit codes:
  0    every file ok
  1    some file failed or is partial (its row says why), or the table could not
       be written
  2    usage error, found before any file is computed: bad options, no mesh
       files found, an extra the options need is not installed, an --output
       that cannot be written, an output that would replace an input or
       another output of the run, or whose suffix its writer does not write
  130  interrupted by Ctrl-C or SIGTERM: the rows done are written; rerun with
       --resume to finish

with -o FILE each finished row is kept in FILE.partial.jsonl as it finishes and
FILE is written at the end, so a run killed outright (SIGKILL, out of memory)
loses only the meshes in flight: the next run on FILE adds them back. Two runs
on the same FILE take turns: the second waits for the first.
"""


def _inputs_help() -> str:
    """The epilog's paragraph on inputs, naming every format searched in directories."""
    formats = ", ".join(MESH_EXTENSIONS)
    needs = "; ".join(f"{ext} needs {package}" for ext, package in FORMAT_PACKAGES.items())
    return textwrap.fill(
        f"inputs are files, directories (searched recursively for {formats} ({needs}); "
        "hidden files and *.dentopo.* outputs skipped) and quoted glob patterns.",
        width=79,
    )


def build_parser(subcommands: tuple[str, ...] = ()) -> argparse.ArgumentParser:
    """The argument parser of the main command (`subcommands`: names listed in its help)."""
    description = (
        "Compute ariaDNE and its sign-oriented (convex/concave) split for triangle meshes,\n"
        "and molaR 6.0's classic DNE, RFI, OPCR, OPC and slope (--metrics): one row per mesh."
    )
    if subcommands:
        names = ", ".join(sorted(subcommands))
        description += f"\n\nsubcommands: {names} (dentopo NAME --help)"
    parser = argparse.ArgumentParser(
        prog=PROG,
        description=description,
        epilog=EXAMPLES.replace("{inputs}", _inputs_help()),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("paths", nargs="*", metavar="PATH", help="mesh files, directories, globs")
    parser.add_argument("--samples", action="store_true", help="add the bundled sample meshes")
    compute = parser.add_argument_group("computation")
    compute.add_argument(
        "-b", "--bandwidth", type=float, default=0.08, help="kernel bandwidth (default 0.08)"
    )
    compute.add_argument(
        "-c", "--cutoff", type=float, default=0.0, help="kernel weight cutoff (default 0)"
    )
    compute.add_argument(
        "-d",
        "--distance-type",
        type=str.lower,
        choices=("euclidean", "geodesic"),
        default="euclidean",
        help="distance between vertices (default euclidean)",
    )
    compute.add_argument(
        "--sign-method",
        type=str.lower,
        choices=SIGN_METHODS,
        default="centroid",
        help="how the sign is decided (default centroid, the paper's method)",
    )
    compute.add_argument(
        "--method",
        type=str.lower,
        choices=METHODS,
        default="auto",
        help="kernel sums: exact, fast (FFT-based, for large meshes) or auto (default: "
        "fast from 20,000 vertices)",
    )
    compute.add_argument(
        "--metrics",
        action="append",
        metavar="NAMES",
        help="what each row holds, repeatable or comma-separated: "
        f"{', '.join(METRICS)}; molaR's and doolkit's names in any case (DNE, RFI, OPCr, "
        f"inclin, rrate, shape.index ...); or a set: {', '.join(GROUPS)} (default ariadne; "
        "with --columns molar, molaR_Batch's classic,rfi,opcr,slope and ariadne; with "
        "--columns doolkit, doolkit)",
    )
    topo = parser.add_argument_group("topography (molaR 6.0's and doolkit 1.42's definitions)")
    topo.add_argument(
        "--alpha", type=float, default=0.075, help="RFI's alpha (default 0.075, molaR's)"
    )
    topo.add_argument(
        "--find-alpha",
        action="store_true",
        help="RFI: find molaR's smallest valid alpha, starting from --alpha (molaR's findAlpha)",
    )
    topo.add_argument(
        "--opcr-steps",
        type=int,
        default=8,
        metavar="N",
        help="OPCR's rotations, 1 to 360 (default 8)",
    )
    topo.add_argument(
        "--opcr-step",
        type=float,
        default=5.625,
        metavar="DEGREES",
        help="OPCR's rotation step, above 0 and at most 360/N (default 5.625)",
    )
    topo.add_argument(
        "--min-faces",
        type=int,
        default=3,
        metavar="N",
        help="OPC: patches of fewer faces are not counted (default 3)",
    )
    topo.add_argument(
        "--min-area",
        type=float,
        default=0.0,
        metavar="FRACTION",
        help="OPC: count patches larger than this fraction of the surface area instead of by "
        "--min-faces (default 0, molaR's minimum_area)",
    )
    topo.add_argument(
        "--dne-outliers",
        type=float,
        default=0.1,
        metavar="PERCENT",
        help="classic DNE: the highest energies discarded, percent in [0, 50] "
        "(default 0.1, molaR's)",
    )
    topo.add_argument(
        "--dne-boundary",
        type=str.lower,
        choices=BOUNDARY_RULES,
        default="vertex",
        help="classic DNE: which boundary faces are discarded (default vertex, molaR's "
        "BoundaryDiscard)",
    )
    topo.add_argument(
        "--dne-kappa",
        type=float,
        default=0.0,
        metavar="K",
        help="classic DNE: the curvature threshold between concave and convex (default 0)",
    )
    topo.add_argument(
        "--arc-boundary",
        type=str.lower,
        choices=BOUNDARY_RULES,
        default="vertex",
        help="ARC: which boundary faces are set to 0 (default vertex, molaR's BoundaryDiscard)",
    )
    topo.add_argument(
        "--arc-range",
        type=float,
        nargs=2,
        default=(0.01, 0.99),
        metavar=("LOW", "HIGH"),
        help="ARC: the quantiles beyond which faces are set to 0 (default 0.01 0.99, molaR's)",
    )
    topo.add_argument(
        "--orient",
        type=str.lower,
        choices=ORIENT_MODES,
        default="auto",
        help="auto (default: turn a crown pointing to -z, away from its open base, before "
        "slope, OPC, OPCR, RFI and doolkit's oriented metrics, and rewind faces wound inward "
        "before those and classic DNE; a closed or flat surface is measured as it lies, with "
        "a warning) or as-is (molaR's and doolkit's way, to reproduce their numbers: measure "
        "the crown as it lies, and warn if it points to -z or its faces are wound inward)",
    )
    topo.add_argument(
        "--duplicates",
        type=str.lower,
        choices=DUPLICATE_MODES,
        default="drop",
        help="faces listed more than once: drop (default: each triangle measured once, as "
        "ariaDNE and the faces column count it) or keep (molaR's: measured as listed); "
        "warned about either way",
    )
    topo.add_argument(
        "--unit",
        metavar="UNIT",
        help="the meshes' length unit: um, mm, cm, m, in, or millimetres per unit (0.02). "
        "doolkit's definitions assume millimetres: its angularity, relief index, ARC, shape "
        "index, footprint and hypsodonty are measured on the crown in millimetres (lengths and "
        "areas given back in the mesh's unit). Default: coordinates taken as millimetres, "
        "and the rows warn where that matters",
    )
    compute.add_argument(
        "--geometry",
        metavar="NAME",
        help="in files holding several meshes (GLB, glTF, 3MF, OBJ objects), measure the one "
        "named NAME, or 'all' joined into one surface (default: such a file is an error row "
        "listing its meshes)",
    )
    compute.add_argument(
        "--prepare",
        metavar="PROTOCOL",
        help="prepare each mesh in memory with this protocol (a TOML file, or a shipped name: "
        "dentopo prepare --protocols) before measuring it: clean, orient, crop, decimate, "
        "smooth, as dentopo prepare does; the protocol column records its name and digest, "
        "and --resume reuses a row only for the same protocol",
    )
    run = parser.add_argument_group("running")
    run.add_argument(
        "-j", "--jobs", type=int, default=1, metavar="N", help="worker processes (0: all cores)"
    )
    run.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        default=None,
        help=f"run on this Dask scheduler (default: ${SCHEDULER_ENV} if set)",
    )
    run.add_argument("-q", "--quiet", action="store_true", help="no progress, only problems")
    run.add_argument("--version", action="version", version=f"{PROG} {__version__}")
    out = parser.add_argument_group("output")
    out.add_argument(
        "-o",
        "--output",
        metavar="FILE",
        help=f"write the table to FILE ({', '.join(FORMATS)}; '-': CSV on stdout)",
    )
    out.add_argument(
        "--columns",
        type=str.lower,
        choices=tuple(LAYOUTS),
        default="dentopo",
        help="the table's columns: dentopo (default, every column), signdne (the published "
        "signDNE CLI's File, DNE, positive_DNE, ...; failed files left out), molar "
        "(molaR_Batch's File, DNE, ..., Slope, then ARC, ariaDNE's, status and error) or "
        "doolkit (doolkit's file, n_vertices, n_faces, area3d, slope_mean, ..., hypso_width, "
        "then status and error)",
    )
    out.add_argument(
        "--resume",
        action="store_true",
        help="keep the ok rows of the existing --output and compute only the rest",
    )
    out.add_argument(
        "--per-vertex",
        metavar="DIR",
        help="write each mesh's per-vertex values (local_curvature, local_dne, sign) and "
        "colours into DIR as NAME.dentopo.<format>",
    )
    out.add_argument(
        "--per-vertex-format",
        action="append",
        metavar="FORMAT",
        help=f"per-vertex formats, repeatable or comma-separated: {', '.join(PER_VERTEX_FORMATS)} "
        f"(default {','.join(DEFAULT_PER_VERTEX_FORMATS)})",
    )
    out.add_argument(
        "--report",
        metavar="HTML",
        help="then write a report of the table: one self-contained HTML page (needs -o FILE; "
        "see dentopo report --help)",
    )
    view = parser.add_argument_group("visualisation")
    view.add_argument(
        "--show",
        "-v",
        "--visualize",
        dest="show",
        action="store_true",
        help="show the mesh in a window (one input; -v and --visualize are aliases)",
    )
    view.add_argument(
        "--screenshot",
        metavar="FILE",
        help="save a picture, off-screen (one input): .png (with its provenance, see dentopo "
        "info), or .svg/.pdf (texts and legend as vectors, the 3D view as an image)",
    )
    view.add_argument("--html", metavar="FILE", help="save an interactive HTML view (one input)")
    view.add_argument(
        "--panel",
        metavar="FILE",
        help="all inputs side by side on one colour scale (.png, .svg, .pdf or .html)",
    )
    view.add_argument(
        "--color-by",
        choices=(*CURVATURE_FIELDS, *METRIC_PICTURES),
        default="local_curvature",
        help="what to draw: local_curvature (default) or local_dne (ariaDNE), slope (per face), "
        "opc (the patches), rfi (the footprint outline over the top view), or per face arc "
        "(diverging, centred on 0; --limits and --percentile apply), angularity (0 to 90 "
        "degrees), inclination (0 to 180 degrees) or elevation (mesh units, 0 to its highest "
        "face); the metric must be among --metrics, except elevation (doolkit's height above "
        "the lowest vertex), which the picture step computes from the mesh file itself (a "
        "crown pointing to -z is turned first, unless --orient as-is)",
    )
    view.add_argument(
        "--view",
        type=str.lower,
        choices=VIEW_NAMES,
        default=DEFAULT_VIEW,
        help="camera: occlusal (default: the occlusal surface, an open crown seen from the side "
        "away from its open base), or top, bottom, front, back, left, right, iso along the "
        "mesh's own axes",
    )
    view.add_argument(
        "--azimuth",
        type=float,
        default=0.0,
        metavar="DEG",
        help="turn the camera from --view about the picture's up direction (degrees)",
    )
    view.add_argument(
        "--elevation",
        type=float,
        default=0.0,
        metavar="DEG",
        help="turn the camera from --view up or down (degrees)",
    )
    view.add_argument(
        "--size",
        "--window-size",
        dest="window_size",
        nargs=2,
        type=int,
        metavar=("W", "H"),
        help="picture size in pixels (--window-size is an alias)",
    )
    view.add_argument(
        "--dpi",
        type=float,
        help="picture resolution; texts are set in points, so they keep their printed size "
        "(default: the width printed 6.4 inches wide, 100 to 600 dpi)",
    )
    view.add_argument(
        "--transparent", action="store_true", help="a transparent background (PNG, SVG, PDF)"
    )
    view.add_argument(
        "--limits", nargs=2, type=float, metavar=("LO", "HI"), help="fixed colour limits"
    )
    view.add_argument(
        "--percentile",
        type=float,
        default=98.0,
        help="colour limits at this percentile of |value| (default 98)",
    )
    return parser


def _metrics(args) -> str:
    """The metrics asked for (``--metrics``, repeatable), or the default of the layout."""
    if args.metrics:
        return ",".join(args.metrics)
    if args.columns == "molar":
        return ",".join(MOLAR_DEFAULT_METRICS)
    return "doolkit" if args.columns == "doolkit" else "ariadne"


def _rendering_requested(args) -> bool:
    return bool(args.show or args.screenshot or args.html or args.panel)


def _check_usage(args) -> str | None:
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
    return None  # its path: see _output_problem


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


def _output_problem(args, files: list[str], settings, per_vertex) -> str | None:
    """An output that is an input, another output, or has the wrong suffix (or None)."""
    inputs = [("the input mesh", file) for file in files]
    return output_problem(_planned_outputs(args, files, settings, per_vertex), inputs)


def _missing_extra(args, settings, scheduler) -> str | None:
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


def _picture_problem(args, metrics) -> str | None:
    """A problem with drawing a metric's picture (--color-by), or None."""
    drawn = args.color_by
    if drawn not in METRIC_PICTURES:
        return None
    if drawn not in PICTURE_STEP and drawn not in metrics:
        return f"--color-by {drawn} draws a metric that is not computed: add --metrics {drawn}"
    if not _rendering_requested(args):
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


#: Why ``--show`` cannot open its window here, and what to use instead.
NO_DISPLAY = (
    "--show needs a display and there is none here (DISPLAY and WAYLAND_DISPLAY are unset); "
    "nothing was computed: save a picture with --screenshot FILE.png, or a 3D page to open "
    "in a browser with --html FILE.html"
)


def _load_renderer():
    """The pictures package (pyvista is imported only when a picture is drawn), or None."""
    try:
        return importlib.import_module("dentopo.figures")
    except ImportError as exc:
        _say(f"cannot load the renderer: {exc}")
        return None


def _render(render, args, files: list[str], outcomes: dict[int, Outcome]) -> int:
    """Draw what was asked for; an exit code (0, 1 display unavailable, 2 bad option)."""
    drawn = "ariadne" if args.color_by in CURVATURE_FIELDS else args.color_by
    ok = [
        (files[i], None if drawn in PICTURE_STEP else o.result.results[drawn])
        for i, o in sorted(outcomes.items())
        if o.result is not None and (drawn in PICTURE_STEP or drawn in o.result.results)
    ]
    if not ok:
        _say(
            "nothing to draw: no mesh was computed" + ("" if drawn == "ariadne" else f" ({drawn})")
        )
        return 1
    camera = {
        "view": args.view,
        "azimuth": args.azimuth,
        "elevation": args.elevation,
        "dpi": args.dpi,
        "transparent": args.transparent,
    }
    options = {
        "field": args.color_by,
        "limits": tuple(args.limits) if args.limits else None,
        "percentile": args.percentile,
        **camera,
    }
    size = {"window_size": tuple(args.window_size)} if args.window_size else {}
    try:
        if args.panel:
            ext = os.path.splitext(args.panel)[1].lower()
            render.render_panel(
                [(result.mesh, result) for _, result in ok],
                labels=[os.path.basename(file) for file, _ in ok],
                screenshot=args.panel if ext != ".html" else None,
                html=args.panel if ext == ".html" else None,
                sources=[file for file, _ in ok],
                **options,
                **size,
                **_prepared_parameters(args),
            )
        if args.show or args.screenshot or args.html:
            file, result = ok[0]
            single = {
                "title": os.path.basename(file),
                "screenshot": args.screenshot,
                "html": args.html,
                "interactive": args.show,
                "source": file,
                **size,
            }
            if drawn == "ariadne":
                render.render_curvature(
                    result.mesh, result, **options, **single, **_prepared_parameters(args)
                )
            else:
                _render_metric(render, drawn, result, args, {**single, **camera})
    except render.DisplayUnavailableError as exc:
        _say(f"cannot draw: {exc}")
        return 1
    except MissingExtraError as exc:  # installed but incomplete: found only when drawing
        _say(str(exc))
        return 2
    except (ValueError, TypeError) as exc:
        _say(f"cannot draw: {exc}")
        return 2
    except OSError as exc:  # a full disk: the picture's file, not the input
        where = f" {exc.filename!r}" if exc.filename is not None else ""
        _say(f"cannot write the picture{where}: {exc.strerror or exc}")
        return 1
    return 0


def _render_metric(render, metric: str, result, args, options: dict) -> None:
    """One topography metric's picture: slope per face, OPC patches, the RFI footprint, or
    one value per face (ARC, angularity, inclination, elevation)."""
    options["parameters"] = _metric_parameters(metric, args)
    if metric == "slope":
        render.render_slope(result.mesh, result.face_slope, **options)
    elif metric == "opc":
        render.render_opc(result.mesh, result.face_bin, result.face_patch, **options)
    elif metric == "rfi":
        render.render_footprint(result.mesh, result.footprint, **options)
    else:
        if metric in PICTURE_STEP:
            result = _picture_step_result(metric, options["source"], args)
        spec = render.FACE_METRICS[metric]
        keywords = spec.keywords()
        note = ""
        if metric == "arc":
            keywords.update(
                limits=tuple(args.limits) if args.limits else None, percentile=args.percentile
            )
            low, high = result.range
            note = (
                f"set to 0: {result.boundary_faces} border faces ({result.boundary} rule), "
                f"{result.cut_faces} beyond the {low:g} and {high:g} quantiles"
            )
        render.render_face_values(
            result.mesh, getattr(result, spec.field), note=note, **keywords, **options
        )


def _prepared_parameters(args) -> dict:
    """``parameters={"protocol": ...}`` for a picture of a prepared mesh, else nothing."""
    if args.prepare is None:
        return {}
    return {"parameters": {"protocol": _protocol_record(args)}}


def _protocol_record(args) -> dict:
    """The protocol of --prepare for a picture's provenance: its label and steps."""
    from ..prepare import load_protocol

    protocol = load_protocol(args.prepare)  # checked before the batch: it reads
    return {"label": protocol.label, "digest": protocol.digest, "steps": protocol.steps()}


def _picture_step_result(metric: str, file: str, args):
    """A picture's metric computed here from the mesh file (elevation: not a batch metric)."""
    import warnings

    from ..mesh import load_mesh
    from ..topography import elevation

    mesh = load_mesh(file, geometry=args.geometry)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        if args.prepare is not None:  # the picture of the mesh measured: the prepared one
            from ..batch import prepared_mesh
            from ..prepare import load_protocol

            mesh = prepared_mesh(mesh, load_protocol(args.prepare))
        result = elevation(mesh, orient=args.orient)
    for warning in caught:
        _say(f"{file}: warning: {warning.message}")
    return result


def _metric_parameters(metric: str, args) -> dict:
    """The settings of a topography metric's picture, for its provenance."""
    if metric in ("arc", "angularity"):  # orientation-free
        parameters = {}
    else:
        parameters = {"orient": args.orient}
    if metric == "opc":
        parameters["min_faces"] = args.min_faces
    elif metric == "rfi":
        parameters.update(alpha=args.alpha, find_alpha=args.find_alpha)
    elif metric == "arc":
        parameters.update(arc_boundary=args.arc_boundary, arc_range=list(args.arc_range))
    elif metric in PICTURE_STEP:
        parameters["computed"] = "in the picture step, from the mesh file"
        if args.geometry is not None:
            parameters["geometry"] = args.geometry
    if args.prepare is not None:  # the picture shows the prepared mesh
        parameters["protocol"] = _protocol_record(args)
    return parameters


#: Options that take two values; each also takes them as one word, ``LOW,HIGH``.
PAIRS = ("--arc-range", "--limits", "--size", "--window-size")


def split_pairs(argv: list[str]) -> list[str]:
    """`argv` with ``--arc-range 0.05,0.95`` (or ``--arc-range=0.05,0.95``) as two words.

    The R and MATLAB bridges pass a vector as one comma-separated value, as
    every other list option of the command takes it (``--metrics``, ``--up``).
    """
    out: list[str] = []
    words = iter(argv)
    for word in words:
        option, equals, value = word.partition("=")
        if option in PAIRS and equals and "," in value:
            out += [option, *value.split(",", 1)]
            continue
        out.append(word)
        if word == "--":
            out += list(words)
            break
        if word in PAIRS:
            value = next(words, None)
            if value is not None:
                out += value.split(",", 1) if "," in value else [value]
    return out


def compute_main(argv: list[str], subcommands: tuple[str, ...] = ()) -> int:
    """Run the main command with `argv`; the exit code."""
    parser = build_parser(subcommands)
    try:
        args = parser.parse_args(split_pairs(argv))
    except SystemExit as stop:  # --help, --version, or a usage error (2)
        return stop.code if isinstance(stop.code, int) else 0

    problem = _check_usage(args)
    if problem:
        _say(problem)
        return 2
    try:
        settings = make_settings(
            bandwidth=args.bandwidth,
            cutoff=args.cutoff,
            distance_type=args.distance_type,
            sign_method=args.sign_method,
            method=args.method,
            geometry=args.geometry,
            metrics=_metrics(args),
            alpha=args.alpha,
            find_alpha=args.find_alpha,
            opcr_steps=args.opcr_steps,
            opcr_step=args.opcr_step,
            min_faces=args.min_faces,
            min_area=args.min_area,
            dne_outliers=args.dne_outliers,
            dne_boundary=args.dne_boundary,
            dne_kappa=args.dne_kappa,
            arc_boundary=args.arc_boundary,
            arc_range=tuple(args.arc_range),
            orient=args.orient,
            duplicates=args.duplicates,
            prepare=args.prepare,
            unit=args.unit,
        )
    except (TypeError, ValueError) as exc:
        _say(str(exc))
        return 2
    problem = _picture_problem(args, settings.metrics)
    if problem:
        _say(problem)
        return 2
    if (
        args.color_by in CURVATURE_FIELDS
        and "ariadne" not in settings.metrics
        and (_rendering_requested(args))
    ):
        _say(
            f"--color-by {args.color_by} (the default) draws ariaDNE, which is not among "
            f"--metrics: add ariadne, or choose --color-by {', '.join(METRIC_PICTURES)}"
        )
        return 2
    try:  # also checks --limits and --percentile before any work
        per_vertex = PerVertexOptions(
            formats=args.per_vertex_format or DEFAULT_PER_VERTEX_FORMATS,
            limits=tuple(args.limits) if args.limits else None,
            percentile=args.percentile,
        )
    except (TypeError, ValueError) as exc:
        _say(str(exc))
        return 2
    scheduler = args.scheduler or os.environ.get(SCHEDULER_ENV) or None
    problem = _missing_extra(args, settings, scheduler)
    if problem:  # now, not after a batch has been computed
        _say(problem)
        return 2

    paths = list(args.paths)
    if args.samples:
        paths += [str(path) for path in sample_paths().values()]
    if not paths:
        _say("no mesh files given (try --help, or --samples)")
        return 2
    with warnings.catch_warnings(record=True) as caught:  # e.g. .dae files without pycollada
        warnings.simplefilter("always")
        found = find_mesh_files(paths)
    for warning in caught:
        _say(f"warning: {warning.message}")
    for pattern in found.unmatched:
        _say(f"no mesh files in {pattern!r}")
    if not found.files:
        _say("no mesh files found")
        return 2
    files = found.files

    rendering = _rendering_requested(args)
    single = args.show or args.screenshot or args.html
    if single and len(files) != 1:
        _say(
            f"--show, --screenshot and --html draw one mesh; {len(files)} were given (see --panel)"
        )
        return 2
    problem = _output_problem(args, files, settings, per_vertex)  # before anything is written
    if problem:
        _say(problem)
        return 2
    render = _load_renderer() if rendering else None
    if rendering and render is None:
        return 2
    if args.show and not render.has_display():  # now, not after the meshes are computed
        _say(NO_DISPLAY)
        return 2

    output = None
    if args.output not in (None, STDOUT):
        columns = layout(args.columns, settings.metrics, settings.rotations())
        output = TableOutput(args.output, columns, quiet=args.quiet)
    # Ctrl-C and SIGTERM (a scheduler's time limit) stop the run, never while a row or the
    # table is being written; the rows done are written, and the exit code is 130.
    with guard_interrupts(signal.SIGINT, signal.SIGTERM) as guard:
        try:
            code = _run(args, files, settings, per_vertex, scheduler, render, output, guard)
        except KeyboardInterrupt as exc:  # before the first mesh: waiting for the lock, ...
            _say(f"{_interruption(exc)} before any file was computed")
            code = INTERRUPTED
        finally:
            if output is not None:
                output.close()
        guard.pending = None  # everything is done and said
    return code


#: The exit code of a run stopped by Ctrl-C or SIGTERM (the rows done are written).
INTERRUPTED = 130


def _interruption(exc: BaseException) -> str:
    """``interrupted`` (Ctrl-C) or ``interrupted (SIGTERM)``."""
    name = getattr(exc, "name", "SIGINT")
    return "interrupted" if name == "SIGINT" else f"interrupted ({name})"


def _run(args, files, settings, per_vertex, scheduler, render, output, guard) -> int:
    """Compute the batch and write its table; the exit code."""
    rendering = render is not None
    previous: list[dict] = []
    if output is not None:
        try:
            output.lock()
        except OSError as exc:
            _say(f"cannot lock {args.output!r} for this run: {exc}")
            return 2
        try:
            output.recover()
        except NotAJournalError as exc:  # not a killed run's rows: say what it is
            _say(str(exc))
            return 2
        except (OSError, ValueError) as exc:
            _say(f"cannot add the rows of an earlier run kept in {output.journal_path!r}: {exc}")
            return 2
    if args.resume:
        if os.path.exists(args.output):
            try:
                previous = read_table(args.output)
            except (OSError, ValueError) as exc:
                _say(f"cannot resume from {args.output!r}: {exc}")
                return 2
        elif not args.quiet:
            _say(f"{args.output!r} does not exist yet: computing every file")
    done = set() if rendering else resumable_files(previous, settings)  # drawing needs results
    todo = [f for f in files if os.path.abspath(f) not in done]
    if args.resume and not args.quiet:
        if args.geometry is not None:  # the table does not record it: nothing can be reused
            _say("--geometry: the table does not record which mesh was read; computing every file")
        _say(f"resuming: {len(files) - len(todo)} of {len(files)} files already done")

    if args.per_vertex is not None:
        try:
            os.makedirs(args.per_vertex, exist_ok=True)
        except OSError as exc:
            _say(f"cannot create --per-vertex {args.per_vertex!r}: {exc}")
            return 2
    if output is not None and todo:
        try:
            output.start_journal()
        except NotAJournalError as exc:  # planted since it was checked
            _say(str(exc))
            return 2
        except OSError as exc:
            _say(f"cannot write {output.journal_path!r}: {exc}")
            return 2
    jobs = args.jobs or available_cores()
    tasks = plan_batch(
        todo,
        settings,
        per_vertex_dir=args.per_vertex,
        per_vertex=per_vertex,
        keep_results=rendering,
        absolute=scheduler is not None,
        batch=files,  # the names checked by _output_problem, whichever files are left
    )
    replaced = replaced_per_vertex_files(tasks)
    if replaced:  # two runs into one folder: say so (one line), then replace
        more = f" (and the files of {len(replaced) - 1} more meshes)" if len(replaced) > 1 else ""
        _say(f"warning: {replaced_message(*replaced[0])}{more}")

    hints = CommandLineHints(build_parser())

    def in_command_words(outcome: Outcome) -> Outcome:
        return replace(
            outcome,
            record=hints.record(outcome.record),
            warnings=tuple(hints(message) for message in outcome.warnings),
        )

    progress = Progress(len(tasks), quiet=args.quiet)
    outcomes: dict[int, Outcome] = {}
    interrupted: BaseException | None = None
    unrecorded: OSError | None = None
    notice = CompileNotice(notice_text(settings.metrics), progress.message)
    if not args.quiet and jobs == 1 and scheduler is None:  # compiled here, not in workers
        notice.start()
    running = run_tasks(tasks, settings, jobs=jobs, scheduler=scheduler, on_phase=progress.phase)
    try:
        for outcome in running:
            outcome = in_command_words(outcome)  # hints name options, not keyword arguments
            outcomes[outcome.index] = outcome
            try:
                with guard.held():  # a row is appended whole
                    if output is not None:
                        output.record(outcome.record)
            except OSError as exc:  # a full disk: the rows could not be kept, so stop
                unrecorded = exc
                break
            for message in outcome.warnings:
                progress.message(f"{outcome.record['file']}: warning: {message}")
            progress.update(outcome.record)
            guard.check()
    except KeyboardInterrupt as exc:
        interrupted = exc
    except MissingExtraError as exc:  # found only when running (installed but incomplete)
        progress.close()
        _say(str(exc))
        return 2
    except (ImportError, OSError) as exc:  # no dask, or the scheduler cannot be reached
        progress.close()
        _say(f"cannot run on scheduler {scheduler!r}: {exc}" if scheduler else str(exc))
        return 2
    finally:
        notice.stop()
        with guard.held():
            running.close()  # stops the workers, also on Ctrl-C
            progress.close()

    with guard.held():  # the table is written whole, even if Ctrl-C comes now
        code = _write(
            args, settings, output, files, tasks, previous, outcomes, interrupted, unrecorded
        )
    if interrupted is None and guard.pending is not None:  # came while writing: rows are safe
        interrupted = Interrupted(guard.pending)
        guard.pending = None
        _say(f"{_interruption(interrupted)} after the table was written")
    if interrupted is not None:
        return INTERRUPTED
    if args.report is not None and os.path.exists(args.output):
        from ._report import report_after_batch

        report = report_after_batch(
            args.output, args.report, quiet=args.quiet, prepare=settings.prepare
        )
        code = max(code, report)
    if code or not rendering:
        return code
    try:
        return max(code, _render(render, args, todo, outcomes))
    except KeyboardInterrupt as exc:  # e.g. in the window of --show
        _say(_interruption(exc))
        return INTERRUPTED


def _write(
    args, settings, output, files, tasks, previous, outcomes, interrupted, unrecorded
) -> int:
    """Write the table (or print it); the exit code so far (0, or 1 if a file failed)."""
    new = [outcomes[i].record for i in sorted(outcomes)]
    if interrupted is not None:
        _say(
            f"{_interruption(interrupted)}: {len(new)} of {len(tasks)} files done; "
            "rerun with --resume to finish"
        )
    if unrecorded is not None:
        _say(
            f"cannot keep the finished rows in {output.journal_path!r}: {unrecorded}; "
            f"stopped after {len(new)} of {len(tasks)} files"
        )
    if (interrupted or unrecorded) and output is not None and not previous:
        if os.path.exists(args.output):
            try:  # keep the old rows of the files not reached, so that nothing is lost
                previous = read_table(args.output)
            except (OSError, ValueError):
                previous = []
    relabelled = relabel_resumed(previous, settings)  # a protocol renamed since
    renamed = any(row is not was for row, was in zip(relabelled, previous, strict=True))
    records = merge_records(relabelled, new)
    mine = {os.path.abspath(f) for f in files}
    statuses = [r["status"] for r in records if os.path.abspath(r["file"]) in mine]
    failed = sum(status != "ok" for status in statuses)  # partial rows too: a metric is missing
    partial = statuses.count("partial")
    code = 1 if failed or unrecorded else 0

    columns = layout(args.columns, settings.metrics, settings.rotations())
    if failed and not columns.failed_rows:
        _say(f"{failed} failed file(s) left out of the table (--columns {columns.name})")
    computed = any(r["status"] != "error" for r in new)  # a partial row is a computed row
    if args.output == STDOUT:
        write_table(sys.stdout, records, columns=columns)
        sys.stdout.flush()
    elif output is not None and not new and interrupted is not None:
        output.discard_journal()  # nothing done, nothing to write
    elif (
        output is not None
        and not computed
        and os.path.exists(args.output)
        and (tasks or not renamed)  # every file done, a protocol renamed: written anew
    ):
        if tasks:  # every file failed (or none was reached): keep the old table as it is
            _say(f"no mesh was computed (every file failed): {args.output} left as it was")
        elif not args.quiet:
            _say(f"every file was already done: {args.output} left as it was")
        output.discard_journal()
    elif output is not None:
        try:
            written = output.write(records)
        except OSError as exc:
            kept = f"; the rows computed are kept in {output.journal_path}"
            _say(
                f"cannot write {args.output!r}: {exc}; it was left as it was"
                + (f"{kept}: rerun with --resume to add them" if new else "")
            )
            return 1
        if not args.quiet:
            detail = f"{failed - partial} failed" + (f", {partial} partial" if partial else "")
            _say(f"wrote {written} rows to {args.output} ({detail})")
    elif columns.name != "dentopo":
        print_layout(records, columns)
    else:
        print_table(records, columns=table_columns(settings.metrics))
    return code
