"""What the per-face topography pictures share: checks, the pyvista window, the output.

The pictures of :mod:`._topography` (slope, OPC, RFI's footprint) and of
:mod:`._face_values` (ARC, angularity, inclination, elevation) all draw one
mesh coloured face by face: this module holds what they do alike.  It checks
the requested outputs (:func:`_check_outputs`) and copies the caller's mesh
(:func:`_mesh_arrays`), builds the interactive pyvista window with its colour
bar or categorical swatches (:func:`_plotter`, :func:`_swatches`), chooses the
camera and resolution (:func:`_options`), records the provenance
(:func:`_record`), and composes and saves the picture or opens the window
(:func:`_show`).  :data:`MISSING_RGB` is the colour of faces without a value.
"""

from __future__ import annotations

import numpy as np

from .._optional import PICTURES, require
from . import _provenance
from ._camera import camera_for
from ._colors import SLOPE_LIMIT, sequential_table
from ._layout import check_dpi, compose, output_format, save
from ._render import (
    _BACKGROUND,
    DisplayUnavailableError,
    _check_view,
    _check_window,
    _need_pictures,
    _quiet_vtk_warnings,
    has_display,
)

#: Colour of faces without a value (NaN, e.g. a face of no area) in per-face maps: a mid
#: grey, apart from both maps (the diverging map's zero is a light grey).
MISSING_RGB = (110, 110, 110)


# ---------------------------------------------------------------------------
# inputs


def _mesh_arrays(mesh) -> tuple[np.ndarray, np.ndarray]:
    """Copies of the mesh's vertices and faces (the caller's mesh is never touched)."""
    from ..mesh import as_arrays

    return as_arrays(mesh)


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
