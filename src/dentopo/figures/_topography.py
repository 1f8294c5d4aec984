"""Pictures of molaR's per-face topography: slope, OPC orientation patches, RFI's footprint.

Each function takes the cleaned mesh a result refers to (``result.mesh``) and
the result's arrays, so that it needs nothing of the metric itself:

* :func:`render_slope` colours each face flat by its slope in degrees on a
  sequential scale (viridis: dark blue-purple flat, yellow vertical), fixed
  from 0 to 90 degrees so that specimens compare; overhangs (over 90) are
  drawn in the 90 degree colour and counted under the colour bar.
* :func:`render_opc` colours each face by its OPC aspect bin, eight hues
  evenly around the colour wheel in the bins' order (so that neighbouring
  directions have neighbouring hues), and draws the borders between patches
  as dark lines.
* :func:`render_footprint` looks straight along the z axis (parallel
  projection), from the side of the occlusal surface, at the plainly shaded
  mesh and draws the footprint outline over it, just beyond the mesh on the
  camera's side, as a thick bright line.
* :func:`render_face_values` colours each face flat by any per-face value:
  on the diverging map centred on 0 (signed values: ARC) or on the
  sequential one (ordered values: angularity, inclination, elevation), with
  a colour bar in the metric's units.  :data:`FACE_METRICS` says how each of
  those four is drawn (its array, name, units, map and scale).

Each writes a picture (PNG with its provenance, or SVG/PDF; pyvista,
off-screen, the ``viz`` extra, composed by ``_layout``) and/or a
self-contained HTML page (no extra), or opens a window, as
:func:`~dentopo.figures.render_curvature` does.  The default view is the
occlusal one (:func:`~dentopo.figures.camera_for`).
"""

from __future__ import annotations

import html as html_escape
import math
from dataclasses import dataclass
from numbers import Real

import numpy as np
import trimesh

from .._optional import PICTURES, require
from . import _provenance
from ._camera import DEFAULT_VIEW, camera_for, occlusal_direction
from ._colors import (
    DEFAULT_PERCENTILE,
    OPC_BINS,
    OPC_COLORS,
    SLOPE_LIMIT,
    ColorScale,
    color_scale,
    lookup_table,
    opc_bin_label,
    sequential_rgb,
    sequential_table,
    slope_rgb,
)
from ._layout import ColorBar, Panel, Swatches, check_dpi, compose, output_format, save
from ._render import (
    _BACKGROUND,
    DisplayUnavailableError,
    _check_view,
    _check_window,
    _need_pictures,
    _quiet_vtk_warnings,
    has_display,
)

#: Colour of the patch borders of OPC pictures.
BORDER_RGB = (25, 25, 25)
#: Colour of the footprint outline: a bright red-orange, far from the grey mesh.
OUTLINE_RGB = (255, 40, 0)
#: Colour of the mesh under the footprint outline.
PLAIN_RGB = (205, 205, 205)
#: Colour of faces without a value (NaN, e.g. a face of no area) in per-face maps: a mid
#: grey, apart from both maps (the diverging map's zero is a light grey).
MISSING_RGB = (110, 110, 110)

_SLOPE_TITLE = "slope (degrees; 0 = facing up, 90 = vertical)"
#: The slope colour bar's ticks, degrees (the PNG's and the HTML page's).
_SLOPE_TICKS = tuple(range(0, 91, 15))
_OPC_TITLE = "OPC aspect bins (aspect = atan2(n_y, n_x) of the face normal)"
_FOOTPRINT_TITLE = "footprint outline (top view, x-y plane)"


# ---------------------------------------------------------------------------
# inputs


def _mesh_arrays(mesh) -> tuple[np.ndarray, np.ndarray]:
    """Copies of the mesh's vertices and faces (the caller's mesh is never touched)."""
    from ..mesh import as_arrays

    return as_arrays(mesh)


def _per_face(values, m: int, name: str) -> np.ndarray:
    """`values` as an (m,) float array, one finite number per face."""
    try:
        array = np.array(values, dtype=np.float64)  # a copy
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{name} must be an array of numbers, one per face") from exc
    if array.shape != (m,):
        raise ValueError(
            f"{name} must hold one value per face of the mesh, shape ({m},); got {array.shape}"
        )
    if not np.isfinite(array).all():
        raise ValueError(f"{name} holds {int((~np.isfinite(array)).sum())} non-finite values")
    return array


def _per_face_int(values, m: int, name: str) -> np.ndarray:
    array = _per_face(values, m, name)
    if not np.array_equal(array, np.round(array)):
        raise ValueError(f"{name} must hold whole numbers")
    return array.astype(np.int64)


def _check_outputs(screenshot, html, interactive, view, window_size):
    view = _check_view(view)
    window_size = _check_window(window_size)
    if screenshot is None and html is None and not interactive:
        raise ValueError("nothing to draw to: give screenshot=, html= or interactive=True")
    if screenshot is not None:
        output_format(screenshot)
    _need_pictures(screenshot, interactive)
    if interactive and not has_display():
        raise DisplayUnavailableError(
            "no display is available for an interactive window (DISPLAY and WAYLAND_DISPLAY "
            "are unset); write a picture with screenshot= (PNG) or html= instead"
        )
    return view, window_size


def _heading(title: str | None, what: str) -> str:
    return f"{title}: {what}" if title else what


# ---------------------------------------------------------------------------
# geometry of the lines


def patch_borders(vertices, faces, face_label) -> np.ndarray:
    """Segments along the edges whose two faces have different labels.

    Parameters
    ----------
    vertices : (n, 3) float
    faces : (m, 3) int
    face_label : (m,) int
        A label per face (the OPC patch).

    Returns
    -------
    (k, 2, 3) float
        One segment per such edge, lifted off the surface by 0.2% of the
        mesh's bounding-box diagonal along the mean normal of its two faces,
        so that it is drawn over the faces rather than inside them.
    """
    shape = trimesh.Trimesh(vertices, faces, process=False, validate=False)
    pairs = shape.face_adjacency
    if len(pairs) == 0:
        return np.zeros((0, 2, 3))
    differ = face_label[pairs[:, 0]] != face_label[pairs[:, 1]]
    edges = shape.face_adjacency_edges[differ]
    normals = shape.face_normals[pairs[differ]].sum(axis=1)
    length = np.linalg.norm(normals, axis=1, keepdims=True)
    normals = np.divide(normals, length, out=np.zeros_like(normals), where=length > 0)
    lift = 2e-3 * float(np.linalg.norm(np.ptp(vertices, axis=0)))
    return vertices[edges] + lift * normals[:, None, :]


def _footprint_segments(footprint, vertices, above: bool = True) -> np.ndarray:
    """The (k, 2, 2) outline as (k, 2, 3) segments just beyond the mesh along z.

    Above its highest point if `above`, else below its lowest.
    """
    try:
        segments = np.array(footprint, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise TypeError("footprint must be an array of x-y segments, shape (k, 2, 2)") from exc
    if segments.ndim != 3 or segments.shape[1:] != (2, 2):
        raise ValueError(f"footprint must hold x-y segments, shape (k, 2, 2); got {segments.shape}")
    if len(segments) == 0:
        raise ValueError("footprint holds no segments")
    if not np.isfinite(segments).all():
        raise ValueError("footprint holds non-finite coordinates")
    lift = 0.01 * float(np.linalg.norm(np.ptp(vertices, axis=0)))
    level = vertices[:, 2].max() + lift if above else vertices[:, 2].min() - lift
    z = np.full((*segments.shape[:2], 1), float(level))
    return np.concatenate([segments, z], axis=2)


# ---------------------------------------------------------------------------
# pyvista


def _plotter(
    vertices,
    faces,
    *,
    off_screen,
    window_size,
    view,
    heading,
    cell_rgb=None,
    cell_values=None,
    point_rgb=None,
    lines=None,
    line_rgb=(0, 0, 0),
    line_width=2.0,
    legend="bar",
    bar_title="",
    note="",
    entries=(),
    parallel=False,
    table=None,
    clim=(0.0, SLOPE_LIMIT),
    fmt="%.0f",
):
    """One mesh with optional lines and a legend: a colour bar below or swatches beside.

    `cell_values` are mapped through `table` ((k, 4) uint8 RGBA rows, default
    the sequential map) over `clim`; NaN values are drawn in :data:`MISSING_RGB`.
    """
    pv = PICTURES.require()

    side = legend == "swatches"
    if legend is None:
        layout = dict(shape=(1, 1))
    elif side:
        layout = dict(shape=(1, 2), col_weights=[1.0, 0.5])
    else:
        layout = dict(shape=(2, 1), row_weights=[1.0, 0.25])
    plotter = pv.Plotter(
        **layout,
        border=False,
        window_size=list(window_size),
        off_screen=off_screen,
        lighting="none",
    )
    plotter.set_background(_BACKGROUND)
    plotter.subplot(0, 0)
    plotter.add_light(pv.Light(light_type="headlight"), only_active=True)
    poly = pv.PolyData.from_regular_faces(vertices, faces)
    # colour maps: mostly ambient light, so that steep faces keep their colour from above
    lit = (0.3, 0.7) if point_rgb is not None else (0.6, 0.4)
    shading = dict(specular=0.0, ambient=lit[0], diffuse=lit[1], show_scalar_bar=False)
    if cell_values is not None:
        lut = pv.LookupTable()
        lut.values = sequential_table() if table is None else table
        lut.scalar_range = tuple(clim)
        lut.nan_color = [c / 255 for c in MISSING_RGB]
        poly.cell_data["value"] = cell_values
        actor = plotter.add_mesh(
            poly,
            scalars="value",
            cmap=lut,
            clim=tuple(clim),
            nan_color=[c / 255 for c in MISSING_RGB],
            **shading,
        )
    elif cell_rgb is not None:
        poly.cell_data["rgb"] = cell_rgb
        actor = plotter.add_mesh(poly, scalars="rgb", rgb=True, **shading)
    else:
        poly.point_data["rgb"] = point_rgb
        actor = plotter.add_mesh(poly, scalars="rgb", rgb=True, smooth_shading=True, **shading)
    if lines is not None and len(lines):
        points = lines.reshape(-1, 3)
        cells = np.column_stack([np.full(len(lines), 2), np.arange(0, len(points)).reshape(-1, 2)])
        segments = pv.PolyData(points, lines=cells.ravel())
        plotter.add_mesh(
            segments,
            color=[c / 255 for c in line_rgb],
            line_width=line_width,
            lighting=False,
            show_scalar_bar=False,
        )
    if heading:
        plotter.add_text(heading, position="upper_left", font_size=10, color="black")
    camera = view
    plotter.enable_parallel_projection()
    plotter.camera_position = [camera.position, camera.focal_point, camera.up]
    plotter.reset_camera()
    if legend == "bar":
        plotter.subplot(1, 0)
        plotter.add_scalar_bar(
            title=" ",
            mapper=actor.mapper,
            n_labels=7,
            fmt=fmt,
            color="black",
            position_x=0.1,
            position_y=0.5,
            width=0.8,
            height=0.32,
            label_font_size=15,
            vertical=False,
        )
        for y, text in ((0.3, bar_title), (0.1, note)):
            if text:
                plotter.add_text(
                    text,
                    position=(0.5, y),
                    viewport=True,
                    font_size=max(7, min(12, round(window_size[0] / 70))),
                    color="black",
                ).GetTextProperty().SetJustificationToCentered()
    elif side:
        plotter.subplot(0, 1)
        _swatches(plotter, entries, bar_title, (window_size[0] / 3, window_size[1]))
    return plotter


def _swatches(plotter, entries, title, size) -> None:
    """A categorical legend in the active subplot: a coloured square and black text per entry.

    `size` is the subplot's (width, height) in pixels.
    """
    core = require("vtkmodules.vtkCommonCore", extra=PICTURES.extra, purpose=PICTURES.purpose)
    data = require("vtkmodules.vtkCommonDataModel", extra=PICTURES.extra, purpose=PICTURES.purpose)
    rendering = require(
        "vtkmodules.vtkRenderingCore", extra=PICTURES.extra, purpose=PICTURES.purpose
    )
    width, height = size
    step = min(0.06, 0.7 / max(len(entries), 1))  # of the height, per entry
    side = 0.6 * step * height  # the square, in pixels
    font = max(9, round(0.3 * step * height))
    top = 0.5 + 0.5 * step * len(entries)
    x0 = 0.04 * width
    if title:
        plotter.add_text(
            title, position=(0.04, top + 0.4 * step), viewport=True, font_size=font, color="black"
        )
    points, colours, cells = core.vtkPoints(), core.vtkUnsignedCharArray(), data.vtkCellArray()
    colours.SetNumberOfComponents(3)
    for index, (label, rgb) in enumerate(entries):
        y = (top - (index + 1) * step) * height
        cells.InsertNextCell(4)
        for dx, dy in ((0, 0), (1, 0), (1, 1), (0, 1)):
            cells.InsertCellPoint(points.InsertNextPoint(x0 + dx * side, y + dy * side, 0.0))
        colours.InsertNextTuple3(*(float(c) for c in rgb))
        plotter.add_text(
            label,
            position=((x0 + 1.6 * side) / width, y / height),
            viewport=True,
            font_size=font,
            color="black",
        )
    poly = data.vtkPolyData()
    poly.SetPoints(points)
    poly.SetPolys(cells)
    poly.GetCellData().SetScalars(colours)
    coordinate = rendering.vtkCoordinate()
    coordinate.SetCoordinateSystemToViewport()
    mapper = rendering.vtkPolyDataMapper2D()
    mapper.SetInputData(poly)
    mapper.SetTransformCoordinate(coordinate)
    mapper.SetColorModeToDirectScalars()
    squares = rendering.vtkActor2D()
    squares.SetMapper(mapper)
    plotter.add_actor(squares, reset_camera=False, pickable=False)


def _show(window, *, screenshot, interactive, title, panel, legend, options, record) -> None:
    """Compose the picture into `screenshot` and/or open ``window()``'s plotter."""
    if screenshot is not None:
        with _quiet_vtk_warnings():
            layout = compose(
                [panel],
                legend,
                size=options["size"],
                dpi=options["dpi"],
                transparent=options["transparent"],
            )
        save(
            layout,
            screenshot,
            metadata=_provenance.dumps(record),
            transparent=options["transparent"],
        )
    if interactive:
        window().show(title=title or "dentopo")


def _options(view, window_size, azimuth, elevation, dpi, transparent, vertices, faces) -> dict:
    camera = camera_for(vertices, faces, view, azimuth, elevation)
    return {
        "camera": camera,
        "size": window_size,
        "dpi": check_dpi(dpi, window_size[0]),
        "transparent": bool(transparent),
    }


def _record(metric, title, source, camera, parameters) -> dict:
    return _provenance.build(metric, dict(parameters or {}), [(title or "", source, camera)])


# ---------------------------------------------------------------------------
# public


def render_slope(
    mesh,
    face_slope,
    *,
    view=DEFAULT_VIEW,
    window_size: tuple[int, int] = (900, 900),
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
    """Draw a mesh with each face coloured by its slope.

    Faces are coloured flat (one colour per face, not interpolated) on a
    sequential scale fixed from 0 degrees (facing straight up, dark
    blue-purple) to 90 degrees (vertical, yellow), the same for every
    specimen.  Overhangs (slopes over 90 degrees) are drawn in the 90 degree
    colour; how many there are is stated under the colour bar.

    Parameters
    ----------
    mesh : trimesh.Trimesh or (vertices, faces)
        The mesh the slopes refer to: the slope result's cleaned ``mesh``.
        Never modified.
    face_slope : (m,) array_like of float
        Slope of each face in degrees, in [0, 180] (the result's
        ``face_slope``).  Never modified.
    view : str or (3, 3), default "occlusal"
        The occlusal view (:func:`camera_for`), a named view along the
        mesh's axes ("top", "bottom", "front", "back", "left", "right",
        "iso") or a camera ``(position, focal_point, view_up)``.
    window_size : (int, int), default (900, 900)
        Width and height in pixels of the window and of the picture.
    title : str, optional
        Shown before "slope" above the mesh, and as window title.
    screenshot : str or path-like, optional
        Write a picture, rendered off-screen (no display needed): ``.png``,
        or ``.svg`` / ``.pdf`` (texts and legend as vectors).
    html : str or path-like, optional
        Write a self-contained interactive HTML page (no network needed).
    interactive : bool, default False
        Open a window to rotate and inspect the mesh (blocks until closed).
    azimuth, elevation : float, default 0
        Turn the camera from `view`, in degrees (see :func:`camera_for`).
    dpi : float, optional
        Resolution of the picture; texts are set in points.  Default: the
        width printed 6.4 inches wide (100 to 600 dpi).
    transparent : bool, default False
        A transparent background in place of white.
    source : str or path-like, optional
        The mesh's file, named with its SHA-256 in the picture's provenance.
    parameters : dict, optional
        The metric's settings, recorded in the picture's provenance.

    Raises
    ------
    ValueError
        If `face_slope` does not hold one finite value per face in [0, 180],
        or for bad options, or when no output is requested.
    DisplayUnavailableError
        If `interactive` is True and there is no display.
    dentopo._optional.MissingExtraError
        A screenshot or a window without pyvista (``pip install 'dentopo[viz]'``, in a clone
        ``pip install '.[viz]'``).

    Examples
    --------
    >>> from dentopo.figures import render_slope
    >>> render_slope(result.mesh, result.face_slope, screenshot="slope.png")  # doctest: +SKIP
    """
    view, window_size = _check_outputs(screenshot, html, interactive, view, window_size)
    vertices, faces = _mesh_arrays(mesh)
    slope = _per_face(face_slope, len(faces), "face_slope")
    if slope.min() < 0 or slope.max() > 180:
        raise ValueError(
            f"face_slope must lie in [0, 180] degrees; got {slope.min():g} to {slope.max():g}"
        )
    options = _options(view, window_size, azimuth, elevation, dpi, transparent, vertices, faces)
    camera = options["camera"]
    overhangs = int((slope > SLOPE_LIMIT).sum())
    note = (
        f"overhangs (over 90\u00b0, up to {slope.max():.0f}\u00b0): {overhangs} faces, "
        "drawn in the 90\u00b0 colour"
        if overhangs
        else ""
    )
    heading = _heading(title, "slope")
    record = _record(
        "slope", title, source, camera, {"scale": [0.0, SLOPE_LIMIT], **(parameters or {})}
    )
    if html is not None:
        from ._html import sequential_bar, write_html

        write_html(
            html,
            [(vertices, faces, slope_rgb(slope), title or "", "", {"face_colors": True})],
            title=heading,
            cameras=[camera],
            bar=sequential_bar(
                _heading(title, _SLOPE_TITLE),
                [f"{d}\u00b0" for d in _SLOPE_TICKS],
                lambda t: np.round(255 * sequential_rgb(t)).astype(np.uint8),
                note,
            ),
            provenance=record,
        )
    panel = Panel(vertices, faces, camera, cell_rgb=slope_rgb(slope), label=heading, ambient=0.6)
    legend = ColorBar(
        lambda t: sequential_rgb(t),
        [(d / SLOPE_LIMIT, f"{d}\u00b0") for d in _SLOPE_TICKS],
        title=_SLOPE_TITLE,
        note=note,
    )

    def window():
        return _plotter(
            vertices,
            faces,
            off_screen=False,
            window_size=window_size,
            view=camera,
            heading=heading,
            cell_values=slope,
            legend="bar",
            bar_title=_SLOPE_TITLE,
            note=note,
        )

    _show(
        window,
        screenshot=screenshot,
        interactive=interactive,
        title=heading,
        panel=panel,
        legend=legend,
        options=options,
        record=record,
    )


def render_opc(
    mesh,
    face_bin,
    face_patch,
    *,
    borders: bool = True,
    view=DEFAULT_VIEW,
    window_size: tuple[int, int] = (1200, 850),
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
    """Draw a mesh with each face coloured by its OPC aspect bin, patch borders in dark lines.

    The eight bins (aspect ``atan2(n_y, n_x)`` of the face normal in steps of
    45 degrees from -180) get eight hues evenly around the colour wheel, in
    the bins' order, so that neighbouring directions (bins 8 and 1 included)
    have neighbouring hues: bin 1 red, 2 orange, 3 yellow-green, 4 green,
    5 cyan, 6 azure, 7 violet, 8 magenta.  A legend of eight labelled
    swatches names each bin's range.

    Parameters
    ----------
    mesh : trimesh.Trimesh or (vertices, faces)
        The mesh the bins refer to: the OPC result's cleaned ``mesh``.  Never
        modified.
    face_bin : (m,) array_like of int
        Aspect bin of each face, 1 to 8 (the result's ``face_bin``).
    face_patch : (m,) array_like of int
        Patch label of each face (the result's ``face_patch``); borders are
        drawn along the edges whose two faces have different labels.
    borders : bool, default True
        Draw the patch borders.
    view, window_size, title, screenshot, html, interactive
        As in :func:`render_slope` (default picture 1200 x 850 pixels).
    azimuth, elevation, dpi, transparent, source, parameters
        As in :func:`render_slope`.

    Raises
    ------
    ValueError
        If `face_bin` or `face_patch` does not hold one whole number per
        face, or a bin lies outside 1 to 8; for bad options, or when no
        output is requested.
    DisplayUnavailableError, dentopo._optional.MissingExtraError
        As in :func:`render_slope`.
    """
    view, window_size = _check_outputs(screenshot, html, interactive, view, window_size)
    vertices, faces = _mesh_arrays(mesh)
    bins = _per_face_int(face_bin, len(faces), "face_bin")
    outside = np.unique(bins[(bins < 1) | (bins > OPC_BINS)])
    if outside.size:
        shown = ", ".join(str(b) for b in outside[:5]) + (", ..." if outside.size > 5 else "")
        raise ValueError(f"face_bin must hold OPC bins 1 to {OPC_BINS}; got {shown}")
    patches = _per_face_int(face_patch, len(faces), "face_patch")
    options = _options(view, window_size, azimuth, elevation, dpi, transparent, vertices, faces)
    camera = options["camera"]
    rgb = np.asarray(OPC_COLORS)[bins - 1]
    lines = patch_borders(vertices, faces, patches) if borders else None
    heading = _heading(title, "OPC")
    entries = [(opc_bin_label(k), tuple(int(c) for c in OPC_COLORS[k - 1])) for k in range(1, 9)]
    if borders:
        entries.append(("patch border", BORDER_RGB))
    record = _record("opc", title, source, camera, {"borders": borders, **(parameters or {})})
    if html is not None:
        from ._html import swatch_bar, write_html

        page = {"face_colors": True}
        if borders:
            page.update(lines=lines, line_rgb=BORDER_RGB, line_width=1.5)
        write_html(
            html,
            [(vertices, faces, rgb, title or "", "", page)],
            title=heading,
            cameras=[camera],
            bar=swatch_bar(_heading(title, _OPC_TITLE), entries),
            provenance=record,
        )
    panel = Panel(
        vertices,
        faces,
        camera,
        cell_rgb=rgb,
        label=heading,
        lines=lines,
        line_rgb=BORDER_RGB,
        line_points=0.6,
        ambient=0.6,
    )
    legend = Swatches(entries, title=_OPC_TITLE)

    def window():
        return _plotter(
            vertices,
            faces,
            off_screen=False,
            window_size=window_size,
            view=camera,
            heading=f"{heading}\naspect bins; dark lines: patch borders" if borders else heading,
            cell_rgb=rgb,
            lines=lines,
            line_rgb=BORDER_RGB,
            line_width=max(1.0, min(window_size) / 400),
            legend="swatches",
            bar_title="aspect bins",
            entries=entries,
        )

    _show(
        window,
        screenshot=screenshot,
        interactive=interactive,
        title=heading,
        panel=panel,
        legend=legend,
        options=options,
        record=record,
    )


def render_footprint(
    mesh,
    footprint,
    *,
    view=DEFAULT_VIEW,
    window_size: tuple[int, int] = (900, 900),
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
    """Draw the mesh from the occlusal side along z with its footprint outline over it.

    The footprint lies in the x-y plane, so the default view looks straight
    along the z axis (parallel projection) from the side of the occlusal
    surface: from +z for a crown pointing to +z, from -z for one pointing to
    -z (:func:`camera_for`'s rule decides which).  The outline is drawn just
    beyond the mesh on the camera's side, so that it lies over the mesh's x-y
    projection exactly.  The mesh is shaded plain grey; the outline is a
    thick red-orange line.

    Parameters
    ----------
    mesh : trimesh.Trimesh or (vertices, faces)
        The mesh: the RFI result's cleaned ``mesh``.  Never modified.
    footprint : (k, 2, 2) array_like of float
        The outline as x-y segments in the mesh's units and position (the
        result's ``footprint``).  Never modified.
    view, window_size, title, screenshot, html, interactive
        As in :func:`render_slope`; "occlusal" here means along z (the
        default), in which the outline is the footprint's boundary.
    azimuth, elevation, dpi, transparent, source, parameters
        As in :func:`render_slope`.

    Raises
    ------
    ValueError
        If `footprint` is not a non-empty finite (k, 2, 2) array; for bad
        options, or when no output is requested.
    DisplayUnavailableError, dentopo._optional.MissingExtraError
        As in :func:`render_slope`.
    """
    view, window_size = _check_outputs(screenshot, html, interactive, view, window_size)
    vertices, faces = _mesh_arrays(mesh)
    if isinstance(view, str) and view == DEFAULT_VIEW:
        towards, _ = occlusal_direction(vertices, faces)
        view = "top" if towards[2] >= 0 else "bottom"
    options = _options(view, window_size, azimuth, elevation, dpi, transparent, vertices, faces)
    camera = options["camera"]
    above = camera.rotation()[2][2] >= 0
    lines = _footprint_segments(footprint, vertices, above)
    heading = _heading(title, "footprint")
    grey = np.tile(np.array(PLAIN_RGB, dtype=np.uint8), (len(vertices), 1))
    record = _record("rfi footprint", title, source, camera, parameters)
    if html is not None:
        from ._html import swatch_bar, write_html

        write_html(
            html,
            [
                (
                    vertices,
                    faces,
                    grey,
                    title or "",
                    "",
                    {"lines": lines, "line_rgb": OUTLINE_RGB, "line_width": 3.0},
                )
            ],
            title=heading,
            cameras=[camera],
            bar=swatch_bar(_heading(title, _FOOTPRINT_TITLE), [("outline", OUTLINE_RGB)]),
            provenance=record,
        )
    panel = Panel(
        vertices,
        faces,
        camera,
        point_rgb=grey,
        label=heading,
        lines=lines,
        line_rgb=OUTLINE_RGB,
        line_points=1.5,
        ambient=0.6,
    )
    legend = Swatches([("footprint outline (x-y plane)", OUTLINE_RGB)], title="")

    def window():
        return _plotter(
            vertices,
            faces,
            off_screen=False,
            window_size=window_size,
            view=camera,
            heading=f"{heading}\nred-orange: footprint outline (x-y plane)",
            point_rgb=grey,
            lines=lines,
            line_rgb=OUTLINE_RGB,
            line_width=max(2.0, round(min(window_size) / 200)),
            legend=None,
        )

    _show(
        window,
        screenshot=screenshot,
        interactive=interactive,
        title=heading,
        panel=panel,
        legend=legend,
        options=options,
        record=record,
    )


# ---------------------------------------------------------------------------
# any per-face value: ARC, angularity, inclination, elevation


@dataclass(frozen=True)
class FaceMetric:
    """How :func:`render_face_values` draws one metric's per-face values.

    Attributes
    ----------
    field : str
        The result's per-face array (``face_arc``, ...), which follows the
        faces of the result's ``mesh``.
    label : str
        The quantity's name, on the colour bar and above the mesh.
    units : str
        Its units, on the colour bar: ``"degrees"``, ``"mesh units"``, or
        ``"dimensionless"``.
    meaning : str
        What the ends of the scale mean, on the colour bar.
    diverging : bool
        Signed values on the diverging map centred on 0 (True), or ordered
        ones on the sequential map (False).
    limits : (float, float), optional
        The sequential scale, fixed; None: from 0 to the largest value (or,
        diverging, symmetric limits from the values' magnitude).
    """

    field: str
    label: str
    units: str
    meaning: str
    diverging: bool = False
    limits: tuple[float, float] | None = None

    def keywords(self) -> dict:
        """The keywords of :func:`render_face_values` for this metric (``limits`` included)."""
        return {
            "metric": self.label.lower(),
            "label": self.label,
            "units": self.units,
            "meaning": self.meaning,
            "diverging": self.diverging,
            "limits": self.limits,
        }


#: The per-face pictures of ARC (molaR), angularity, inclination and elevation (doolkit).
FACE_METRICS = {
    "arc": FaceMetric(
        "face_arc",
        "ARC",
        "dimensionless",
        "blue \u2212 concave, red + convex, zeroed faces neutral",
        diverging=True,
    ),
    "angularity": FaceMetric(
        "face_angularity",
        "angularity",
        "degrees",
        "the slope of the slope: 0 = even, 90 = abrupt",
        limits=(0.0, 90.0),
    ),
    "inclination": FaceMetric(
        "face_inclination",
        "inclination",
        "degrees",
        "0 = facing down, 90 = vertical, 180 = facing up",
        limits=(0.0, 180.0),
    ),
    "elevation": FaceMetric(
        "face_elevation",
        "elevation",
        "mesh units",
        "height above the lowest vertex",
    ),
}


@dataclass(frozen=True)
class _SequentialScale:
    """Linear limits ``(low, high)`` on the sequential map, and how they were chosen."""

    low: float
    high: float
    rule: str

    @property
    def limits(self) -> tuple[float, float]:
        return (self.low, self.high)

    def position(self, values) -> np.ndarray:
        return (np.asarray(values, dtype=np.float64) - self.low) / (self.high - self.low)

    def bar_rgb(self, t) -> np.ndarray:
        return sequential_rgb(t)

    def rgb(self, values) -> np.ndarray:
        return np.round(255 * sequential_rgb(self.position(values))).astype(np.uint8)


def _number(value: float, digits: int = 4) -> str:
    """A tick or limit as text: `digits` significant digits, a true minus sign, never ``-0``."""
    return f"{value + 0.0:.{digits}g}".replace("-", "\u2212")


def _sequential_scale(values: np.ndarray, limits, unit: str) -> _SequentialScale:
    """The sequential scale: `limits` (``HI`` for ``(0, HI)``, or ``(LO, HI)``) or 0 to the max."""
    if limits is None:
        finite = values[np.isfinite(values)]
        low = min(0.0, float(finite.min())) if finite.size else 0.0
        high = float(finite.max()) if finite.size else 1.0
        if high <= low:
            return _SequentialScale(low, low + 1.0, f"{_number(low)} to {_number(low + 1)}")
        return _SequentialScale(
            low, high, f"{_number(low)} to {_number(high)}{unit} (the largest value)"
        )
    if isinstance(limits, Real) and not isinstance(limits, bool):
        low, high = 0.0, float(limits)
    else:
        try:
            low, high = (float(v) for v in limits)
        except (TypeError, ValueError) as exc:
            raise TypeError(
                f"limits must be a number HI (for 0 to HI) or a pair (LO, HI); got {limits!r}"
            ) from exc
    if not (math.isfinite(low) and math.isfinite(high)) or not low < high:
        raise ValueError(f"the limits must be finite with LO < HI; got ({low!r}, {high!r})")
    return _SequentialScale(low, high, f"{_number(low)} to {_number(high)}{unit} (fixed)")


def _nice_ticks(low: float, high: float, most: int = 7) -> list[float]:
    """Round values from `low` to `high` (both ends when they are round), at most `most`."""
    span = high - low
    raw = span / (most - 1)
    magnitude = 10.0 ** math.floor(math.log10(raw))
    for multiple in (1.0, 1.5, 2.0, 2.5, 3.0, 5.0, 10.0):
        step = multiple * magnitude
        if span / step <= most - 1 + 1e-9:
            break
    first = math.ceil(low / step - 1e-9)
    last = math.floor(high / step + 1e-9)
    return [k * step for k in range(first, last + 1)]


def _tick_text(value: float, degrees: bool, digits: int = 4) -> str:
    return _number(value, digits) + ("\u00b0" if degrees else "")


def _placed_bar_html(title: str, scale, ticks, note: str) -> str:
    """A colour bar's HTML block with ticks placed at their values (as the pictures do)."""
    t = np.linspace(0, 1, 41)
    rgb = np.round(255 * np.asarray(scale.bar_rgb(t))).astype(int)
    stops = zip(t, rgb, strict=True)
    gradient = ", ".join(f"rgb({r},{g},{b}) {100 * p:.1f}%" for p, (r, g, b) in stops)
    spans = "".join(
        f'<span style="left: {100 * p:.2f}%">{html_escape.escape(text)}</span>' for p, text in ticks
    )
    block = (
        f'<div id="rule">{html_escape.escape(title)}</div>\n'
        f'<div id="gradient" style="background: linear-gradient(to right, {gradient})"></div>\n'
        f'<div id="ticks" class="placed">{spans}</div>'
    )
    if note:
        lines = "<br>".join(html_escape.escape(line) for line in note.splitlines())
        block += f'\n<div id="note">{lines}</div>'
    return block


def render_face_values(
    mesh,
    values,
    *,
    metric: str,
    label: str,
    units: str = "",
    meaning: str = "",
    diverging: bool = False,
    limits=None,
    percentile: float = DEFAULT_PERCENTILE,
    note: str = "",
    view=DEFAULT_VIEW,
    window_size: tuple[int, int] = (900, 900),
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
    """Draw a mesh with each face coloured flat by a value of its own, with a colour bar.

    One renderer for every per-face metric: signed values (ARC) on the
    diverging map centred on 0 (Moreland's cool to warm: blue negative, light
    grey exactly 0, red positive; the curvature pictures' map), ordered ones
    (angularity, inclination, elevation) on the sequential map (viridis: dark
    blue-purple low, yellow high; the slope picture's map).  Faces are
    coloured flat, one colour per face.  Values beyond the limits get the end
    colours (counted under the colour bar on the sequential map; on the
    diverging one a few are expected, its default limit being a percentile);
    faces without a value (NaN) are drawn mid grey (:data:`MISSING_RGB`) and
    counted.
    :data:`FACE_METRICS` holds the settings of the four metrics drawn by
    ``dentopo --color-by``: ``render_face_values(r.mesh, r.face_arc,
    **FACE_METRICS["arc"].keywords())``.

    Parameters
    ----------
    mesh : trimesh.Trimesh or (vertices, faces)
        The mesh the values refer to: the result's ``mesh``.  Never modified.
    values : (m,) array_like of float
        One value per face (NaN allowed: drawn grey).  Never modified.
    metric : str
        What the colours show, for the provenance (``"arc"``, ...).
    label : str
        The quantity's name, above the mesh and on the colour bar.
    units : str, default ""
        Its units, on the colour bar (``"degrees"``: ticks get a degree sign).
    meaning : str, default ""
        What the colours mean, on the colour bar after the units.
    diverging : bool, default False
        The diverging map centred on 0 (signed values) instead of the
        sequential one.
    limits : float or (float, float), optional
        Diverging: ``L`` for ``±L`` or ``(LO, HI)`` with ``LO < 0 < HI``
        (:func:`~dentopo.figures.color_scale`); default symmetric, ``±`` the
        `percentile` of ``|value|``.  Sequential: ``HI`` for 0 to ``HI`` or
        ``(LO, HI)`` with ``LO < HI``; default from 0 (or the smallest value,
        if negative) to the largest value.  Fix them to compare specimens.
    percentile : float, default 98
        Diverging, without `limits`: the percentile of ``|value|`` taken as
        the limit.
    note : str, default ""
        A further line under the colour bar (e.g. how many faces were zeroed).
    view, window_size, title, screenshot, html, interactive
        As in :func:`render_slope`.
    azimuth, elevation, dpi, transparent, source, parameters
        As in :func:`render_slope` (`elevation` turns the camera).

    Raises
    ------
    ValueError
        If `values` does not hold one value per face or holds infinities,
        or no finite value; for bad limits or options, or when no output is
        requested.
    DisplayUnavailableError, dentopo._optional.MissingExtraError
        As in :func:`render_slope`.

    Examples
    --------
    >>> from dentopo.figures import FACE_METRICS, render_face_values
    >>> from dentopo.topography import arc
    >>> result = arc("tooth.ply")  # doctest: +SKIP
    >>> render_face_values(result.mesh, result.face_arc, screenshot="arc.png",
    ...                    **FACE_METRICS["arc"].keywords())  # doctest: +SKIP
    """
    view, window_size = _check_outputs(screenshot, html, interactive, view, window_size)
    vertices, faces = _mesh_arrays(mesh)
    name = str(label)
    per_face = _face_values(values, len(faces), name)
    missing = np.isnan(per_face)
    degrees = units == "degrees"
    unit = "\u00b0" if degrees else ""
    if diverging:
        scale: ColorScale | _SequentialScale = color_scale(
            per_face[~missing], limits=limits, percentile=percentile
        )
        low, high = scale.limits
        tick_values = [low, low / 2, 0.0, high / 2, high]
        rule = f"limits {scale.rule}"
    else:
        scale = _sequential_scale(per_face, limits, unit)
        low, high = scale.limits
        tick_values = _nice_ticks(low, high)
        rule = f"scale {scale.rule}"
    digits = 3 if diverging else 4  # the diverging ticks as the curvature pictures' ones
    ticks = [(float(scale.position(v)), _tick_text(v, degrees, digits)) for v in tick_values]
    rgb = scale.rgb(np.where(missing, 0.0, per_face))
    rgb[missing] = MISSING_RGB
    finite = per_face[~missing]
    notes = [rule]
    # beyond the limits: by design on the diverging map (a percentile), so counted on the other
    above, below = int((finite > high).sum()), int((finite < low).sum())
    if diverging:
        above = below = 0
    if above:
        notes.append(f"{above} faces above {_tick_text(high, degrees)} in the top colour")
    if below:
        notes.append(f"{below} faces below {_tick_text(low, degrees)} in the bottom colour")
    if missing.any():
        notes.append(f"{int(missing.sum())} faces without a value in grey")
    full_note = "; ".join(notes) + (f"\n{note}" if note else "")
    inside = "; ".join(part for part in (units, meaning) if part)
    bar_title = f"{name} ({inside})" if inside else name
    options = _options(view, window_size, azimuth, elevation, dpi, transparent, vertices, faces)
    camera = options["camera"]
    heading = _heading(title, name)
    record = _record(
        metric,
        title,
        source,
        camera,
        {
            "scale": [low, high],
            "map": "diverging" if diverging else "sequential",
            "units": units,
            **({"percentile": percentile} if diverging and limits is None else {}),
            **(parameters or {}),
        },
    )
    if html is not None:
        from ._html import write_html

        write_html(
            html,
            [(vertices, faces, rgb, title or "", "", {"face_colors": True})],
            title=heading,
            cameras=[camera],
            bar=_placed_bar_html(_heading(title, bar_title), scale, ticks, full_note),
            provenance=record,
        )
    panel = Panel(vertices, faces, camera, cell_rgb=rgb, label=heading, ambient=0.6)
    legend = ColorBar(scale.bar_rgb, ticks, title=bar_title, note=full_note)

    def window():
        table = lookup_table(255, scale) if diverging else sequential_table()
        return _plotter(
            vertices,
            faces,
            off_screen=False,
            window_size=window_size,
            view=camera,
            heading=heading,
            cell_values=per_face,
            legend="bar",
            bar_title=bar_title,
            note=full_note,
            table=table,
            clim=(low, high),
            fmt="%.3g",
        )

    _show(
        window,
        screenshot=screenshot,
        interactive=interactive,
        title=heading,
        panel=panel,
        legend=legend,
        options=options,
        record=record,
    )


def _face_values(values, m: int, name: str) -> np.ndarray:
    """`values` as an (m,) float array: NaN allowed (no value), infinities not."""
    try:
        array = np.array(values, dtype=np.float64)  # a copy
    except (TypeError, ValueError) as exc:
        raise TypeError(f"the {name} values must be an array of numbers, one per face") from exc
    if array.shape != (m,):
        raise ValueError(
            f"the {name} values must hold one value per face of the mesh, shape ({m},); "
            f"got {array.shape}"
        )
    if np.isinf(array).any():
        raise ValueError(f"the {name} values hold {int(np.isinf(array).sum())} infinite values")
    if np.isnan(array).all():
        raise ValueError(f"the {name} values hold no number (every face is NaN)")
    return array
