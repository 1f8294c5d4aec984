"""The main command's picture step: what it draws after the batch, and its provenance.

:func:`load_renderer` imports :mod:`dentopo.figures` (and so pyvista) only when
a picture is asked for; :func:`draw_pictures` draws ariaDNE's curvature
(``--show``, ``--screenshot``, ``--html``, ``--panel``) or one topography
metric's picture from the results of the batch, or computes a picture's metric
from the mesh file itself (elevation); the pictures carry the settings they
were drawn with (and ``--prepare``'s protocol) as their provenance.
"""

from __future__ import annotations

import importlib
import os

from .._optional import MissingExtraError
from ..batch import Outcome
from ._arguments import CURVATURE_FIELDS, PICTURE_STEP
from ._progress import say as _say

#: Why ``--show`` cannot open its window here, and what to use instead.
NO_DISPLAY = (
    "--show needs a display and there is none here (DISPLAY and WAYLAND_DISPLAY are unset); "
    "nothing was computed: save a picture with --screenshot FILE.png, or a 3D page to open "
    "in a browser with --html FILE.html"
)


def load_renderer():
    """The pictures package (pyvista is imported only when a picture is drawn), or None."""
    try:
        return importlib.import_module("dentopo.figures")
    except ImportError as exc:
        _say(f"cannot load the renderer: {exc}")
        return None


def draw_pictures(render, args, files: list[str], outcomes: dict[int, Outcome]) -> int:
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
