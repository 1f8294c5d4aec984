"""The main command's arguments: its parser, its help, and the values its options take.

:func:`build_parser` is the parser of ``dentopo PATH...`` (its help, examples and
exit codes); :func:`split_pairs` lets the two-value options take ``LOW,HIGH`` as
one word (the R and MATLAB bridges); :func:`metrics_asked` and
:func:`rendering_requested` read what the arguments ask for.  The constants are
the values the options take (``-o -``, the picture formats, ``--color-by``'s
fields), shared with the checks (:mod:`._checks`) and the pictures
(:mod:`._pictures`).
"""

from __future__ import annotations

import argparse
import textwrap

from .._version import __version__
from ..ariadne import METHODS
from ..batch import FORMAT_PACKAGES, MESH_EXTENSIONS
from ..figures import DEFAULT_VIEW, VIEW_NAMES
from ..formats import DEFAULT_PER_VERTEX_FORMATS, FORMATS, LAYOUTS, PER_VERTEX_FORMATS
from ..sign import SIGN_METHODS
from ..topography import (
    BOUNDARY_RULES,
    DUPLICATE_MODES,
    GROUPS,
    METRICS,
    ORIENT_MODES,
    PCV_METHODS,
)
from ._progress import PROG

#: Environment variable naming a Dask scheduler, used when --scheduler is not given.
SCHEDULER_ENV = "DENTOPO_SCHEDULER"

#: Picture formats of --screenshot and --panel (besides .html).
PICTURE_FORMATS = (".png", ".svg", ".pdf")

#: ``--color-by`` fields of ariaDNE, and the metrics that have a picture of their own.
CURVATURE_FIELDS = ("local_curvature", "local_dne")
#: Per-face maps of one value (:data:`dentopo.figures.FACE_METRICS`): ARC on the diverging
#: map, the others on the sequential one.
FACE_PICTURES = ("arc", "angularity", "inclination", "elevation", "pcv")
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
        "areas given back in the mesh's unit), and so is MorphoTester's RFI. Default: "
        "coordinates taken as millimetres, and the rows warn where that matters",
    )
    mt = parser.add_argument_group(
        "MorphoTester 1.1.1 (--metrics morphotester; defaults: its published results' settings)"
    )
    mt.add_argument(
        "--mt-outliers",
        type=str.lower,
        choices=("energy", "energy-area", "off"),
        default="energy",
        help="MorphoTester's DNE: faces above the percentile of their energy density (energy, "
        "as its published results), of energy x area (energy-area, its window's default), "
        "or none removed (off)",
    )
    mt.add_argument(
        "--mt-percentile",
        type=float,
        default=99.9,
        metavar="P",
        help="MorphoTester's DNE: the outlier percentile, in (0, 100] (default 99.9)",
    )
    mt.add_argument(
        "--mt-condition",
        type=str.lower,
        choices=("on", "off"),
        default="on",
        help="MorphoTester's DNE: faces whose first fundamental form has a condition number "
        "above 1e5 get no energy (default on, as MorphoTester)",
    )
    mt.add_argument(
        "--mt-smooth",
        action="store_true",
        help="MorphoTester's DNE on the crown after its implicit fairing (3 iterations, step "
        "0.1; DNE only, as MorphoTester); a crown it cannot fair is that metric's error",
    )
    mt.add_argument(
        "--mt-min-patch",
        type=int,
        default=5,
        metavar="N",
        help="MorphoTester's OPCR: patches of fewer faces are not counted (default 5, as its "
        "published results; its window's default is 3)",
    )
    light = parser.add_argument_group("PCV, ambient occlusion (--metrics pcv)")
    light.add_argument(
        "--pcv-rays",
        type=int,
        default=256,
        metavar="N",
        help="light directions, an equal-area partition of the sphere (default 256, "
        "CloudCompare's)",
    )
    light.add_argument(
        "--pcv-sphere",
        action="store_true",
        help="light from the whole sphere (default: the northern hemisphere only, light from "
        "+z, CloudCompare's default)",
    )
    light.add_argument(
        "--pcv-method",
        type=str.lower,
        choices=PCV_METHODS,
        default="cloudcompare",
        help="cloudcompare (default): its depth buffers, numbers comparable with the "
        "literature; exact: a ray per vertex and direction, no pixels",
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


def metrics_asked(args) -> str:
    """The metrics asked for (``--metrics``, repeatable), or the default of the layout."""
    if args.metrics:
        return ",".join(args.metrics)
    if args.columns == "molar":
        return ",".join(MOLAR_DEFAULT_METRICS)
    return "doolkit" if args.columns == "doolkit" else "ariadne"


def rendering_requested(args) -> bool:
    """Whether a picture is asked for (--show, --screenshot, --html or --panel)."""
    return bool(args.show or args.screenshot or args.html or args.panel)


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
