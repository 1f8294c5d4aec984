"""Pictures of the signed field: interactive windows, PNG screenshots, HTML pages.

Each mesh is coloured per vertex by its signed local curvature (or local DNE,
or any per-vertex field) on the diverging scale of ``_colors``: red convex,
blue concave, neutral grey at zero, symmetric limits, with a labelled colour
bar stating the limit rule and a caption with the totals; a map of signs
(values -1 and +1 only) gets two labelled swatches instead.  Panels put
several meshes (or one mesh at several bandwidths, or one mesh under several
sign rules) side by side on one shared scale.

Pictures (``screenshot=``) are composed by ``_layout``: each mesh rendered by
pyvista from its occlusal view (``_camera``), framed with a margin, texts and
legends set by matplotlib in points at the requested size and resolution;
``.png``, ``.svg`` or ``.pdf`` by the file name, the PNG carrying its
provenance (``_provenance``).

pyvista/VTK (the ``viz`` extra) draws windows and screenshots; it is imported
only when a picture is made, before any mesh is computed for it (without it,
:class:`~dentopo._optional.MissingExtraError` names the extra).  Screenshots
are rendered off-screen and need no display (VTK renders through EGL or
OSMesa).  HTML pages are written by ``_html`` with no
dependencies beyond numpy.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import trimesh

from .._optional import PICTURES, require
from . import _provenance
from ._camera import DEFAULT_VIEW, camera_for, check_view
from ._colors import DEFAULT_PERCENTILE, ColorScale, color_scale, diverging_rgb, lookup_table
from ._layout import ColorBar, Panel, Swatches, check_dpi, check_size, compose, output_format, save

FIELDS = ("local_curvature", "local_dne")

#: What the colours mean, under the colour bar.
LEGEND = "blue \u2212 concave, red + convex"

_FIELD_TITLES = {"local_curvature": "local curvature", "local_dne": "local DNE"}
_BACKGROUND = "white"


class DisplayUnavailableError(RuntimeError):
    """An interactive window was requested where there is no display."""


@dataclass(frozen=True)
class _Item:
    """One mesh to draw: its vertices, faces, per-vertex values and texts."""

    vertices: np.ndarray
    faces: np.ndarray
    values: np.ndarray
    label: str
    caption: str
    source: object = None
    parameters: dict | None = None


# ---------------------------------------------------------------------------
# inputs


def _as_trimesh(mesh) -> trimesh.Trimesh:
    from ..mesh import as_arrays

    if isinstance(mesh, trimesh.Trimesh):
        return mesh
    vertices, faces = as_arrays(mesh)
    return trimesh.Trimesh(vertices, faces, process=False)


def _default_label(mesh) -> str:
    if isinstance(mesh, (str, os.PathLike)):
        return Path(mesh).name
    return ""


def _totals(result) -> str:
    return (
        f"DNE {result.dne:.4g} = {result.positive_dne:.4g} (+) + {result.negative_dne:.4g} (\u2212)"
        f"\nh = {result.bandwidth:g}"
    )


def _result_parameters(result) -> dict:
    """The settings of an ariaDNE result, for the provenance."""
    names = ("bandwidth", "cutoff", "distance_type", "sign_method", "method")
    return {name: getattr(result, name) for name in names if hasattr(result, name)}


def _item(mesh, result, field, label: str | None, source=None) -> _Item:
    """Resolve one (mesh, result, field) into arrays to draw."""
    if label is None:
        label = _default_label(mesh)
    if source is None and isinstance(mesh, (str, os.PathLike)):
        source = mesh
    if isinstance(field, str):
        if field not in FIELDS:
            raise ValueError(f"field must be one of {FIELDS} or per-vertex values; got {field!r}")
        if result is None:
            from ..ariadne import ariaDNE

            result = ariaDNE(mesh)
        values = np.asarray(getattr(result, field), dtype=np.float64)
        target = result.mesh
    else:
        target = result.mesh if result is not None else _as_trimesh(mesh)
        values = np.asarray(field, dtype=np.float64)
    vertices = np.asarray(target.vertices, dtype=np.float64)
    faces = np.asarray(target.faces, dtype=np.int64)
    if values.shape != (len(vertices),):
        raise ValueError(
            f"the field must hold one value per vertex of the (cleaned) mesh, shape "
            f"({len(vertices)},); got {values.shape}"
        )
    caption = _totals(result) if result is not None and isinstance(field, str) else ""
    parameters = _result_parameters(result) if result is not None else {}
    return _Item(vertices, faces, values, label, caption, source, parameters)


def _field_title(field) -> str:
    return _FIELD_TITLES.get(field, "value") if isinstance(field, str) else "value"


def _check_view(view):
    return check_view(view)


def _check_window(window_size) -> tuple[int, int]:
    return check_size(window_size)


def _need_pictures(screenshot, interactive) -> None:
    """Import pyvista now if a screenshot or a window is asked for (before any computing)."""
    if screenshot is not None or interactive:
        PICTURES.require()


def has_display() -> bool:
    """Whether an interactive window can be opened here.

    On Linux (and other X11/Wayland systems) this needs ``DISPLAY`` or
    ``WAYLAND_DISPLAY``; macOS and Windows always have one.
    """
    if sys.platform.startswith(("win", "darwin")):
        return True
    return bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))


# ---------------------------------------------------------------------------
# drawing


def _camera(vertices: np.ndarray, faces: np.ndarray, view, azimuth=0.0, elevation=0.0) -> tuple:
    """(position, focal point, view-up) of :func:`~._camera.camera_for`, for pyvista."""
    camera = camera_for(vertices, faces, view, azimuth, elevation)
    return (camera.position, camera.focal_point, camera.up)


def _plotter(
    items: list[_Item],
    scale: ColorScale,
    *,
    title_text,
    legend,
    view,
    window_size,
    off_screen,
    turns=(0.0, 0.0),
):
    """An interactive window of the meshes (pictures are composed by ``_layout``)."""
    pv = PICTURES.require()

    n = len(items)
    cols = n if n <= 4 else int(np.ceil(np.sqrt(n)))
    rows = int(np.ceil(n / cols))
    plotter = pv.Plotter(
        shape=(rows + 1, cols),
        row_weights=[1.0] * rows + [0.28],
        groups=[(rows, np.s_[:])],
        border=False,
        window_size=list(window_size),
        off_screen=off_screen,
        lighting="none",
    )
    plotter.set_background(_BACKGROUND)
    table = pv.LookupTable()
    table.values = lookup_table(scale=scale)
    table.scalar_range = scale.limits
    mapper = None
    for index, item in enumerate(items):
        plotter.subplot(index // cols, index % cols)
        # one white light at the camera: shading never tints the colours
        plotter.add_light(pv.Light(light_type="headlight"), only_active=True)
        poly = pv.PolyData.from_regular_faces(item.vertices, item.faces)
        poly.point_data["value"] = item.values
        actor = plotter.add_mesh(
            poly,
            scalars="value",
            cmap=table,
            clim=scale.limits,
            smooth_shading=True,
            show_scalar_bar=False,
            specular=0.0,
            ambient=0.3,
            diffuse=0.7,
        )
        mapper = actor.mapper
        text = "\n".join(t for t in (item.label, item.caption) if t)
        if text:
            plotter.add_text(text, position="upper_left", font_size=9, color="black")
        plotter.camera_position = list(_camera(item.vertices, item.faces, view, *turns))
        plotter.enable_parallel_projection()
        plotter.reset_camera()
    plotter.subplot(rows, 0)
    plotter.add_scalar_bar(
        title=f"{title_text} {scale.rule}\n{legend}",
        mapper=mapper,
        n_labels=5,
        fmt="%.3g",
        color="black",
        position_x=0.15,
        position_y=0.3,
        width=0.7,
        height=0.4,
        title_font_size=12,
        label_font_size=11,
        vertical=False,
    )
    return plotter


@contextmanager
def _quiet_vtk_warnings():
    """Hide VTK's warnings on stderr (off-screen it warns that there is no X server)."""
    core = require("vtkmodules.vtkCommonCore", extra=PICTURES.extra, purpose=PICTURES.purpose)
    logger = core.vtkLogger
    previous = logger.GetCurrentVerbosityCutoff()
    logger.SetStderrVerbosity(logger.VERBOSITY_ERROR)
    try:
        yield
    finally:
        logger.SetStderrVerbosity(previous)


def _is_sign_map(items: list[_Item]) -> bool:
    """Whether every value is -1 or +1: two categories, not a continuous field."""
    return all(np.isin(item.values, (-1.0, 1.0)).all() for item in items)


def _signed(value: float) -> str:
    return f"{value:.3g}".replace("-", "\u2212")


def diverging_bar(scale: ColorScale, title: str, legend: str) -> ColorBar:
    """The colour bar of a signed field: ticks at the limits, halfway and zero; the rule below."""
    low, high = scale.limits
    values = [low, low / 2, 0.0, high / 2, high]
    ticks = [(float(scale.position(v)), "0" if v == 0 else _signed(v)) for v in values]
    return ColorBar(
        scale.bar_rgb,
        ticks,
        title=f"{title} ({legend})" if legend else title,
        note=f"limits {scale.rule}",
    )


#: The two categories of a sign map: (label, value).
SIGN_CATEGORIES = (("concave (\u22121)", -1.0), ("convex (+1)", 1.0))


def sign_swatches(title: str, categories=SIGN_CATEGORIES) -> Swatches:
    """The categorical legend of a sign map: a labelled swatch per sign."""
    entries = [
        (label, tuple(int(c) for c in np.round(255 * diverging_rgb(value))))
        for label, value in categories
    ]
    return Swatches(entries, title=title)


def _record(metric, items, cameras, scale, percentile, categorical, extra=None) -> dict:
    parameters = dict(items[0].parameters or {})
    for item in items[1:]:  # settings that differ between panels (bandwidths) become lists
        for key, value in (item.parameters or {}).items():
            if key in parameters and parameters[key] != value:
                parameters[key] = [i.parameters.get(key) for i in items]
    if categorical:
        parameters["categories"] = {"-1": "blue", "+1": "red"}
    else:
        parameters["limits"] = list(scale.limits)
        parameters["limit_rule"] = scale.rule
        parameters["percentile"] = percentile
        parameters["colour_map"] = "dentopo diverging (cool to warm)"
    parameters.update(extra or {})
    panels = [(i.label, i.source, c) for i, c in zip(items, cameras, strict=True)]
    return _provenance.build(metric, parameters, panels)


def _draw(
    items: list[_Item],
    *,
    field,
    limits,
    percentile,
    view,
    window_size,
    title,
    screenshot,
    html,
    interactive,
    legend=None,
    azimuth=0.0,
    elevation=0.0,
    dpi=None,
    transparent=False,
    categories=None,
    metric=None,
    extra=None,
) -> None:
    view = _check_view(view)
    legend = LEGEND if legend is None else str(legend)
    window_size = _check_window(window_size)
    dpi = check_dpi(dpi, window_size[0])
    if screenshot is None and html is None and not interactive:
        raise ValueError("nothing to draw to: give screenshot=, html= or interactive=True")
    if screenshot is not None:
        output_format(screenshot)
    _need_pictures(screenshot, interactive)  # before the HTML page is written
    if interactive and not has_display():
        raise DisplayUnavailableError(
            "no display is available for an interactive window (DISPLAY and WAYLAND_DISPLAY "
            "are unset); write a picture with screenshot= (PNG) or html= instead"
        )
    cameras = [camera_for(i.vertices, i.faces, view, azimuth, elevation) for i in items]
    scale = color_scale([item.values for item in items], limits=limits, percentile=percentile)
    if isinstance(field, str):
        title_text = f"{title}: {_field_title(field)}" if title else _field_title(field)
    else:
        title_text = title or "value"
    categorical = categories is not None or _is_sign_map(items)
    if categorical:
        scale = color_scale(limits=1.0)
    metric = metric or (field if isinstance(field, str) else "values")
    record = _record(metric, items, cameras, scale, percentile, categorical, extra)
    if html is not None:
        from ._html import swatch_bar, write_html

        bar = None
        if categorical:
            swatches = sign_swatches(title_text, categories or SIGN_CATEGORIES)
            bar = swatch_bar(swatches.title, swatches.entries)
        write_html(
            html,
            [(i.vertices, i.faces, scale.rgb(i.values), i.label, i.caption) for i in items],
            scale=scale,
            title=title_text,
            legend=legend,
            cameras=cameras,
            bar=bar,
            provenance=record,
        )
    if screenshot is not None:
        panels = [
            Panel(
                i.vertices,
                i.faces,
                c,
                point_rgb=scale.rgb(i.values),
                label=i.label,
                caption=i.caption,
            )
            for i, c in zip(items, cameras, strict=True)
        ]
        if categorical:
            key = sign_swatches(title_text, categories or SIGN_CATEGORIES)
        else:
            key = diverging_bar(scale, title_text, legend)
        with _quiet_vtk_warnings():
            layout = compose(panels, key, size=window_size, dpi=dpi, transparent=transparent)
        save(layout, screenshot, metadata=_provenance.dumps(record), transparent=transparent)
    if interactive:
        plotter = _plotter(
            items,
            scale,
            title_text=title_text,
            legend=legend,
            view=view,
            window_size=window_size,
            off_screen=False,
            turns=(azimuth, elevation),
        )
        if len(items) > 1:
            plotter.link_views()
        plotter.show(title=title or "dentopo")


# ---------------------------------------------------------------------------
# public


def render_curvature(
    mesh,
    result=None,
    *,
    field="local_curvature",
    limits=None,
    percentile: float = DEFAULT_PERCENTILE,
    view=DEFAULT_VIEW,
    window_size: tuple[int, int] = (1024, 768),
    title: str | None = None,
    screenshot=None,
    html=None,
    interactive: bool = False,
    azimuth: float = 0.0,
    elevation: float = 0.0,
    dpi: float | None = None,
    transparent: bool = False,
    source=None,
    parameters: dict | None = None,
) -> None:
    """Draw one mesh coloured by its signed curvature.

    Red is convex (positive), blue concave (negative), neutral grey exactly
    zero; limits are symmetric about zero unless given.  The picture has a labelled colour
    bar stating the limit rule and a caption with the totals.

    Parameters
    ----------
    mesh : trimesh.Trimesh, str, path-like, or (vertices, faces)
        The mesh.  Never modified.
    result : AriaDNEResult, optional
        Its result; computed with ``ariaDNE(mesh)`` (default settings) when
        None and `field` names a result field.  The cleaned ``result.mesh``
        is drawn, since the per-vertex arrays refer to it.
    field : {"local_curvature", "local_dne"} or (n,) array_like
        What to colour by.  An array gives one value per vertex of
        ``result.mesh`` (or of `mesh` as given, when `result` is None).
    limits : float or (float, float), optional
        Fixed colour limits ``L`` for ``(-L, L)``, or ``(LO, HI)`` with
        ``LO < 0 < HI`` (zero stays neutral; share them across specimens to
        compare them on one scale).  Default: ``±`` the `percentile` of
        ``|value|``.
    percentile : float, default 98.0
        Percentile of ``|value|`` used as the limit when `limits` is None.
    view : str or (3, 3), default "occlusal"
        ``"occlusal"`` looks at the occlusal surface (an open crown from the
        side away from its open base; see :func:`camera_for`); ``"top"``
        (from +z), ``"bottom"``, ``"front"`` (from -y), ``"back"``,
        ``"left"`` (from -x), ``"right"`` and ``"iso"`` look along the mesh's
        own axes; or a camera ``(position, focal_point, view_up)`` in mesh
        units.  The projection is parallel.
    window_size : (int, int), default (1024, 768)
        Width and height in pixels of the window and of the picture.
    title : str, optional
        The mesh's label (above it) and the window's title.
    screenshot : str or path-like, optional
        Write a picture, rendered off-screen (no display needed): ``.png``
        (with its provenance in a ``dentopo`` text chunk), or ``.svg`` /
        ``.pdf`` (texts and legend as vectors, the 3D view as an image).
    html : str or path-like, optional
        Write a self-contained interactive HTML page (no network needed).
    interactive : bool, default False
        Open a window to rotate and inspect the mesh (blocks until closed).
    azimuth, elevation : float, default 0
        Turn the camera from `view`, in degrees: about the picture's up
        direction, then about its horizontal direction.
    dpi : float, optional
        Resolution of the picture: texts are set in points (8 pt), so that
        they keep their printed size.  Default: the width printed 6.4 inches
        wide (100 to 600 dpi).
    transparent : bool, default False
        A transparent background in place of white.
    source : str or path-like, optional
        The file the mesh was read from, named with its SHA-256 in the
        picture's provenance (default: `mesh`, when it is a path).
    parameters : dict, optional
        More settings for the provenance's ``parameters`` (the command adds
        ``protocol``: the preparation protocol of a mesh prepared before it
        was measured, whose vertices the picture shows).

    Raises
    ------
    DisplayUnavailableError
        If `interactive` is True and there is no display.
    ValueError, TypeError
        For bad options, or when no output is requested.
    dentopo._optional.MissingExtraError
        An ``ImportError``: a screenshot or a window without pyvista
        (``pip install 'dentopo[viz]'``, in a clone ``pip install '.[viz]'``); HTML pages need no
        extra.

    Examples
    --------
    >>> from dentopo import render_curvature
    >>> render_curvature("tooth.ply", screenshot="tooth.png", view="top")  # doctest: +SKIP
    """
    _need_pictures(screenshot, interactive)
    items = [_item(mesh, result, field, title, source)]
    _draw(
        items,
        field=field,
        limits=limits,
        percentile=percentile,
        view=view,
        window_size=window_size,
        title=None,
        screenshot=screenshot,
        html=html,
        interactive=interactive,
        azimuth=azimuth,
        elevation=elevation,
        dpi=dpi,
        transparent=transparent,
        extra=parameters,
    )


def render_panel(
    items: Sequence,
    *,
    labels: Sequence[str] | None = None,
    field="local_curvature",
    limits=None,
    percentile: float = DEFAULT_PERCENTILE,
    view=DEFAULT_VIEW,
    window_size: tuple[int, int] | None = None,
    screenshot=None,
    html=None,
    interactive: bool = False,
    title: str | None = None,
    legend: str | None = None,
    azimuth: float = 0.0,
    elevation: float = 0.0,
    dpi: float | None = None,
    transparent: bool = False,
    sources: Sequence | None = None,
    categories: Sequence[tuple[str, float]] | None = None,
    metric: str | None = None,
    parameters: dict | None = None,
) -> None:
    """Draw several meshes side by side on one shared colour scale.

    Parameters
    ----------
    items : sequence of (mesh, result) pairs
        Each mesh as accepted by :func:`render_curvature`, with its result or
        None (then computed with default settings).  Up to four are drawn in a
        row, more in a near-square grid.
    labels : sequence of str, optional
        One label per item (default: file names, if paths).
    field : {"local_curvature", "local_dne"} or sequence of (n,) arrays
        What to colour by; per-vertex arrays are given one per item.
    limits, percentile, view, screenshot, html, interactive
        As in :func:`render_curvature` (screenshots and windows need the
        ``viz`` extra).  Default limits pool ``|value|`` over all items, so
        the scale is shared.
    azimuth, elevation, dpi, transparent
        As in :func:`render_curvature`; each mesh gets its own occlusal view.
    window_size : (int, int), optional
        Default: 400 x 400 pixels per mesh, and 200 pixels for the legend.
    title : str, optional
        Shown before the field name on the colour bar.
    legend : str, optional
        What the colours mean, beside the colour bar's title (default
        "blue \u2212 concave, red + convex" in text).
    sources : sequence of path-like or None, optional
        The file each mesh was read from, for the provenance (default: the
        mesh itself, when it is a path).
    categories : sequence of (str, float), optional
        A categorical legend for fields of a few values: a labelled swatch
        per (label, value).  Fields holding only -1 and +1 get
        ``concave (-1)`` and ``convex (+1)`` by default.
    metric : str, optional
        What the colours show, for the provenance (default: the field's name).
    parameters : dict, optional
        More settings for the provenance's ``parameters`` (as in :func:`render_curvature`).

    Examples
    --------
    >>> from dentopo import ariaDNE, render_panel
    >>> pairs = [(path, ariaDNE(path)) for path in ["a.ply", "b.ply"]]  # doctest: +SKIP
    >>> render_panel(pairs, screenshot="panel.png", limits=0.3)  # doctest: +SKIP
    """
    _need_pictures(screenshot, interactive)
    items = list(items)
    if not items:
        raise ValueError("render_panel needs at least one (mesh, result) pair")
    for index, pair in enumerate(items):
        if not isinstance(pair, (tuple, list)) or len(pair) != 2:
            raise TypeError(f"items[{index}] must be a (mesh, result) pair; got {pair!r:.60}")
    if labels is not None:
        labels = [str(label) for label in labels]
        if len(labels) != len(items):
            raise ValueError(f"got {len(labels)} labels for {len(items)} items")
    if isinstance(field, str):
        fields = [field] * len(items)
    else:
        fields = list(field)
        if len(fields) != len(items):
            raise ValueError(f"got {len(fields)} per-vertex fields for {len(items)} items")
    if sources is not None:
        sources = list(sources)
        if len(sources) != len(items):
            raise ValueError(f"got {len(sources)} sources for {len(items)} items")
    drawn = [
        _item(
            mesh,
            result,
            f,
            None if labels is None else labels[i],
            None if sources is None else sources[i],
        )
        for i, ((mesh, result), f) in enumerate(zip(items, fields, strict=True))
    ]
    if window_size is None:
        cols = len(drawn) if len(drawn) <= 4 else int(np.ceil(np.sqrt(len(drawn))))
        rows = int(np.ceil(len(drawn) / cols))
        window_size = (400 * cols, 400 * rows + 200)
    _draw(
        drawn,
        field=field if isinstance(field, str) else None,
        limits=limits,
        percentile=percentile,
        view=view,
        window_size=window_size,
        title=title,
        screenshot=screenshot,
        html=html,
        interactive=interactive,
        legend=legend,
        azimuth=azimuth,
        elevation=elevation,
        dpi=dpi,
        transparent=transparent,
        categories=categories,
        metric=metric,
        extra=parameters,
    )


def render_bandwidths(
    mesh,
    bandwidths: Sequence[float] = (0.04, 0.08, 0.16),
    *,
    field: str = "local_curvature",
    ariadne_options: dict | None = None,
    **options,
) -> list:
    """Draw one mesh at several bandwidths side by side, on one shared scale.

    Parameters
    ----------
    mesh : trimesh.Trimesh, str, path-like, or (vertices, faces)
        The mesh.  Never modified.
    bandwidths : sequence of float, default (0.04, 0.08, 0.16)
        Kernel bandwidths (unit-area scale), one panel each, captioned ``h = ...``.
    field : {"local_curvature", "local_dne"}
        What to colour by.
    ariadne_options : dict, optional
        Further keyword options for ``ariaDNE`` (``cutoff``, ``distance_type``...).
    **options
        Passed to :func:`render_panel` (``limits``, ``view``, ``screenshot``,
        ``html``, ``interactive``...).

    Returns
    -------
    list of AriaDNEResult
        The results drawn, one per bandwidth.
    """
    from ..ariadne import ariaDNE

    _need_pictures(options.get("screenshot"), options.get("interactive", False))
    bandwidths = [float(h) for h in bandwidths]
    if isinstance(mesh, (str, os.PathLike)):
        from ..mesh import load_mesh

        options.setdefault("sources", [mesh] * len(bandwidths))
        name, mesh = Path(mesh).name, load_mesh(mesh)
    else:
        name = ""
    if not bandwidths:
        raise ValueError("render_bandwidths needs at least one bandwidth")
    results = [ariaDNE(mesh, bandwidth=h, **(ariadne_options or {})) for h in bandwidths]
    labels = [name] * len(bandwidths)  # the caption under each names its bandwidth
    render_panel([(mesh, r) for r in results], labels=labels, field=field, **options)
    return results


def render_comparison(
    mesh,
    result=None,
    *,
    bandwidth: float | None = None,
    factor: float | None = None,
    **options,
) -> None:
    """Signed ariaDNE beside the signs of discrete mean and Gaussian curvature.

    As in the paper's Figure 6: three copies of the mesh coloured by the sign
    of ``local_curvature`` (+1 red, -1 blue), the sign of trimesh's discrete
    mean curvature measure, and the sign of its discrete Gaussian curvature
    measure, the measures taken in a ball of radius
    ``factor * bandwidth * sqrt(area)`` around each vertex (see
    :func:`curvature_measure`).

    Parameters
    ----------
    mesh : trimesh.Trimesh, str, path-like, or (vertices, faces)
        The mesh.  Never modified.
    result : AriaDNEResult, optional
        Its result; computed with ``ariaDNE(mesh, bandwidth=...)`` when None.
    bandwidth : float, optional
        Bandwidth for the result (when computed) and for the measures' radius;
        default: ``result.bandwidth``, or 0.08.
    factor : float, optional
        Radius in units of the bandwidth (default 1.0).
    **options
        Passed to :func:`render_panel` (``view``, ``screenshot``, ``html``...);
        the legend is two labelled swatches, -1 and +1.
    """
    from ..sign import DEFAULT_RADIUS_FACTOR, curvature_measure_sign

    _need_pictures(options.get("screenshot"), options.get("interactive", False))
    if result is None:
        from ..ariadne import ariaDNE

        result = ariaDNE(mesh, bandwidth=0.08 if bandwidth is None else bandwidth)
    if bandwidth is None:
        bandwidth = result.bandwidth
    factor = DEFAULT_RADIUS_FACTOR if factor is None else factor
    signs = [
        np.where(result.local_curvature >= 0, 1.0, -1.0),
        curvature_measure_sign(result.mesh, "mean", bandwidth, factor=factor),
        curvature_measure_sign(result.mesh, "gaussian", bandwidth, factor=factor),
    ]
    labels = [
        f"sign of ariaDNE (h = {bandwidth:g})",
        f"sign of mean curvature (r = {factor:g} h)",
        f"sign of Gaussian curvature (r = {factor:g} h)",
    ]
    options.setdefault("title", "sign")
    options.setdefault(
        "categories",
        (
            ("\u22121: concave (Gaussian: saddle)", -1.0),
            ("+1: convex (Gaussian: elliptic)", 1.0),
        ),
    )
    options.setdefault("metric", "sign comparison")
    if isinstance(mesh, (str, os.PathLike)):
        options.setdefault("sources", [mesh] * 3)
    render_panel([(result.mesh, result)] * 3, labels=labels, field=signs, limits=1.0, **options)
