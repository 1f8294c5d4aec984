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

Each writes a picture (PNG with its provenance, or SVG/PDF; pyvista,
off-screen, the ``viz`` extra, composed by ``_layout``) and/or a
self-contained HTML page (no extra), or opens a window, as
:func:`~dentopo.figures.render_curvature` does.  The default view is the
occlusal one (:func:`~dentopo.figures.camera_for`).  What these pictures
share with :func:`~dentopo.figures.render_face_values` (``_face_values``:
ARC, angularity, inclination, elevation) is in ``_face_drawing``: the checks
of the outputs, the pyvista window, the composed and saved picture.
"""

from __future__ import annotations

import numpy as np
import trimesh

from ._camera import DEFAULT_VIEW, occlusal_direction
from ._colors import (
    OPC_BINS,
    OPC_COLORS,
    SLOPE_LIMIT,
    opc_bin_label,
    sequential_rgb,
    slope_rgb,
)
from ._face_drawing import (
    _check_outputs,
    _heading,
    _mesh_arrays,
    _options,
    _plotter,
    _record,
    _show,
)
from ._layout import ColorBar, Panel, Swatches

#: Colour of the patch borders of OPC pictures.
BORDER_RGB = (25, 25, 25)
#: Colour of the footprint outline: a bright red-orange, far from the grey mesh.
OUTLINE_RGB = (255, 40, 0)
#: Colour of the mesh under the footprint outline.
PLAIN_RGB = (205, 205, 205)

_SLOPE_TITLE = "slope (degrees; 0 = facing up, 90 = vertical)"
#: The slope colour bar's ticks, degrees (the PNG's and the HTML page's).
_SLOPE_TICKS = tuple(range(0, 91, 15))
_OPC_TITLE = "OPC aspect bins (aspect = atan2(n_y, n_x) of the face normal)"
_FOOTPRINT_TITLE = "footprint outline (top view, x-y plane)"


# ---------------------------------------------------------------------------
# inputs


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
