"""Pictures of the signed field: interactive windows, PNG screenshots, HTML pages.

Each mesh is coloured per vertex by its signed local curvature (or local DNE,
or any per-vertex field) on the diverging scale of ``_colors``: red convex,
blue concave, neutral grey at zero, symmetric limits, with a labelled colour
bar stating the limit rule and a caption with the totals.  Panels put several
meshes (or one mesh at several bandwidths, or one mesh under several sign
rules) side by side on one shared scale.

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
from ._colors import DEFAULT_PERCENTILE, ColorScale, color_scale, lookup_table
from ._views import VIEWS

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
        f"   h = {result.bandwidth:g}"
    )


def _item(mesh, result, field, label: str | None) -> _Item:
    """Resolve one (mesh, result, field) into arrays to draw."""
    if label is None:
        label = _default_label(mesh)
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
    return _Item(vertices, faces, values, label, caption)


def _field_title(field) -> str:
    return _FIELD_TITLES.get(field, "value") if isinstance(field, str) else "value"


def _check_view(view):
    if isinstance(view, str):
        if view not in VIEWS:
            raise ValueError(f"view must be one of {tuple(VIEWS)} or a camera; got {view!r}")
        return view
    try:
        camera = np.asarray(view, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"view must be a preset name or a camera; got {view!r}") from exc
    if camera.shape != (3, 3) or not np.isfinite(camera).all():
        raise ValueError(
            "a camera view is three points: (position, focal_point, view_up), shape (3, 3); "
            f"got shape {camera.shape}"
        )
    return camera


def _check_window(window_size) -> tuple[int, int]:
    try:
        width, height = (int(v) for v in window_size)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"window_size must be (width, height); got {window_size!r}") from exc
    if width < 16 or height < 16 or width > 16384 or height > 16384:
        raise ValueError(f"window_size must lie in 16..16384 pixels; got {window_size!r}")
    return width, height


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


def _camera(item_vertices: np.ndarray, view) -> tuple:
    """(position, focal point, view-up) framing the vertices from a preset direction."""
    if not isinstance(view, str):
        return tuple(tuple(float(x) for x in row) for row in view)
    direction, up = (np.asarray(v, dtype=np.float64) for v in VIEWS[view])
    low, high = item_vertices.min(axis=0), item_vertices.max(axis=0)
    centre = 0.5 * (low + high)
    distance = 3.0 * max(float(np.linalg.norm(high - low)), 1e-12)
    position = centre + distance * direction / np.linalg.norm(direction)
    return (tuple(position), tuple(centre), tuple(up))


def _plotter(
    items: list[_Item], scale: ColorScale, *, title_text, legend, view, window_size, off_screen
):
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
    table.values = lookup_table()
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
        position, focal, up = _camera(item.vertices, view)
        plotter.camera_position = [position, focal, up]
        plotter.reset_camera()
        plotter.camera.zoom(1.1)
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


def _screenshot(items, scale, title_text, legend, view, window_size, path) -> None:
    plotter = _plotter(
        items,
        scale,
        title_text=title_text,
        legend=legend,
        view=view,
        window_size=window_size,
        off_screen=True,
    )
    try:
        plotter.screenshot(os.fspath(path))
    finally:
        plotter.close()


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
) -> None:
    view = _check_view(view)
    legend = LEGEND if legend is None else str(legend)
    window_size = _check_window(window_size)
    if screenshot is None and html is None and not interactive:
        raise ValueError("nothing to draw to: give screenshot=, html= or interactive=True")
    _need_pictures(screenshot, interactive)  # before the HTML page is written
    if interactive and not has_display():
        raise DisplayUnavailableError(
            "no display is available for an interactive window (DISPLAY and WAYLAND_DISPLAY "
            "are unset); write a picture with screenshot= (PNG) or html= instead"
        )
    scale = color_scale([item.values for item in items], limits=limits, percentile=percentile)
    if isinstance(field, str):
        title_text = f"{title}: {_field_title(field)}" if title else _field_title(field)
    else:
        title_text = title or "value"
    if html is not None:
        from ._html import write_html

        write_html(
            html,
            [(i.vertices, i.faces, scale.rgb(i.values), i.label, i.caption) for i in items],
            scale=scale,
            title=title_text,
            legend=legend,
            view=view if isinstance(view, str) else None,
        )
    if screenshot is not None:
        with _quiet_vtk_warnings():
            _screenshot(items, scale, title_text, legend, view, window_size, screenshot)
    if interactive:
        plotter = _plotter(
            items,
            scale,
            title_text=title_text,
            legend=legend,
            view=view,
            window_size=window_size,
            off_screen=False,
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
    view="iso",
    window_size: tuple[int, int] = (1024, 768),
    title: str | None = None,
    screenshot=None,
    html=None,
    interactive: bool = False,
) -> None:
    """Draw one mesh coloured by its signed curvature.

    Red is convex (positive), blue concave (negative), neutral grey exactly
    zero; limits are symmetric about zero.  The picture has a labelled colour
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
        Fixed colour limits ``L`` or ``(-L, L)`` (share them across
        specimens to compare them on one scale).  Default: the `percentile`
        of ``|value|``.
    percentile : float, default 98.0
        Percentile of ``|value|`` used as the limit when `limits` is None.
    view : {"iso", "top", "bottom", "front", "back", "left", "right"} or (3, 3)
        A preset direction (the camera looks at the mesh's centre from that
        side; "top" looks down the z axis), or a camera
        ``(position, focal_point, view_up)`` in mesh units.
    window_size : (int, int), default (1024, 768)
        Width and height in pixels of the window and of the screenshot.
    title : str, optional
        Shown before the field name on the colour bar and as window title.
    screenshot : str or path-like, optional
        Write a PNG, rendered off-screen (no display needed).
    html : str or path-like, optional
        Write a self-contained interactive HTML page (no network needed).
    interactive : bool, default False
        Open a window to rotate and inspect the mesh (blocks until closed).

    Raises
    ------
    DisplayUnavailableError
        If `interactive` is True and there is no display.
    ValueError, TypeError
        For bad options, or when no output is requested.
    dentopo._optional.MissingExtraError
        An ``ImportError``: a screenshot or a window without pyvista
        (``pip install 'dentopo[viz]'``); HTML pages need no extra.

    Examples
    --------
    >>> from dentopo import render_curvature
    >>> render_curvature("tooth.ply", screenshot="tooth.png", view="top")  # doctest: +SKIP
    """
    _need_pictures(screenshot, interactive)
    items = [_item(mesh, result, field, title)]
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
    )


def render_panel(
    items: Sequence,
    *,
    labels: Sequence[str] | None = None,
    field="local_curvature",
    limits=None,
    percentile: float = DEFAULT_PERCENTILE,
    view="iso",
    window_size: tuple[int, int] | None = None,
    screenshot=None,
    html=None,
    interactive: bool = False,
    title: str | None = None,
    legend: str | None = None,
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
    window_size : (int, int), optional
        Default: 400 x 400 pixels per mesh, plus the colour bar.
    title : str, optional
        Shown before the field name on the colour bar.
    legend : str, optional
        What the colours mean, under the colour bar (default
        "blue \u2212 concave, red + convex" in text).

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
    drawn = [
        _item(mesh, result, f, None if labels is None else labels[i])
        for i, ((mesh, result), f) in enumerate(zip(items, fields, strict=True))
    ]
    if window_size is None:
        cols = len(drawn) if len(drawn) <= 4 else int(np.ceil(np.sqrt(len(drawn))))
        rows = int(np.ceil(len(drawn) / cols))
        window_size = (400 * cols, 400 * rows + 120)
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
        Kernel bandwidths (unit-area scale), one panel each, labelled ``h = ...``.
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
    if isinstance(mesh, (str, os.PathLike)):
        from ..mesh import load_mesh

        name, mesh = Path(mesh).name, load_mesh(mesh)
    else:
        name = ""
    bandwidths = [float(h) for h in bandwidths]
    if not bandwidths:
        raise ValueError("render_bandwidths needs at least one bandwidth")
    results = [ariaDNE(mesh, bandwidth=h, **(ariadne_options or {})) for h in bandwidths]
    labels = [f"{name}  h = {h:g}".strip() for h in bandwidths]
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
        the limits are fixed at ±1.
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
        "legend",
        "\u22121 / +1; ariaDNE and mean: concave / convex; Gaussian: saddle / elliptic",
    )
    render_panel([(result.mesh, result)] * 3, labels=labels, field=signs, limits=1.0, **options)
