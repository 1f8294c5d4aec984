"""Previews of preparation: what was found and cut, and the crown that came out.

:func:`render_preparation` draws one picture per file, to be checked at a
glance by the hundred: on the left the raw scan seen from the side, its found
occlusal axis pointing up the picture (a blue arrow: a crown lying on its side
there was oriented wrongly), the base plane the orientation found (blue) and
the crop plane (red), the part the crop removes shaded darker; on the right
the prepared crown from the occlusal camera (:func:`camera_for`).  A crown
left as it lies (no orient step, or one that found no axis) has no arrow: it
is seen with its own +z up, and the picture says so.  Both are a neutral grey;
the file name, the face counts and each warning (one short line each) are
written on the picture.  :func:`preview_sheet` tiles many previews on one
contact sheet.

The planes are recorded by the steps in the coordinates of the mesh each
step received: orient's in the raw scan's, crop's in the oriented crown's;
crop's is carried back to the raw scan by the orientation's inverse.
"""

from __future__ import annotations

import io
import math
import os

import numpy as np

from .._optional import PICTURES, require
from ._camera import camera_for
from ._colors import NEUTRAL
from ._layout import write_bytes

#: The size of one preview, pixels (two views side by side).
PREVIEW_SIZE = (880, 440)

#: Colours: the axis and base plane, the crop plane, the part the crop removes.
AXIS_COLOR = (0.12, 0.35, 0.85)
CROP_COLOR = (0.85, 0.15, 0.12)
REMOVED_COLOR = (0.55, 0.45, 0.40)
WARNING_COLOR = (0.70, 0.05, 0.05)


def _step(crown, name: str):
    try:
        return crown.step(name)
    except KeyError:
        return None


def _axis_label(orient) -> str | None:
    """What the blue arrow shows (``"found axis"``, ``"given axis"``), or None: no arrow.

    The orient step draws an arrow only if it turned the crown to an axis it
    found (or was given with ``up``); a crown left as it lies has none to show.
    """
    if orient is None or not orient.details.get("turned"):
        return None
    return "given axis" if orient.details.get("rule") == "up" else "found axis"


def _raw_label(orient, cut) -> str:
    """The raw view's caption: the axis drawn, or why none is; the crop plane, or no crop."""
    shown = _axis_label(orient)
    if shown is not None:
        label = f"raw scan: {shown} (blue)"
    elif orient is None:
        label = "raw scan as it lies, +z up (no orient step)"
    else:
        label = "raw scan as it lies, +z up (no axis found)"
    return label + (", crop plane (red)" if cut is not None else ", no crop")


#: The warnings written on a preview, one line each (the rest counted), and their length.
PREVIEW_WARNINGS = 3
WARNING_CHARACTERS = 70


def _warning_lines(warnings) -> list[str]:
    """The warnings as the preview writes them: a heading, then one short line each."""
    if not warnings:
        return []
    lines = ["warnings:"]
    lines += [_start(text, WARNING_CHARACTERS) for text in warnings[:PREVIEW_WARNINGS]]
    if len(warnings) > PREVIEW_WARNINGS:
        lines.append(f"(and {len(warnings) - PREVIEW_WARNINGS} more: see the .prepare.json)")
    return lines


def _rigid_inverse(transform: np.ndarray) -> np.ndarray:
    inverse = np.eye(4)
    rotation = transform[:3, :3]
    inverse[:3, :3] = rotation.T
    inverse[:3, 3] = -rotation.T @ transform[:3, 3]
    return inverse


def _orientation(crown) -> np.ndarray:
    """The 4x4 motion applied before the crop step (orient's; the identity if none)."""
    transform = np.eye(4)
    for step in crown.steps:
        if step.name == "crop":
            break
        if step.transform is not None:
            transform = np.asarray(step.transform, dtype=np.float64) @ transform
    return transform


def _unit(vector) -> np.ndarray:
    vector = np.asarray(vector, dtype=np.float64)
    norm = float(np.linalg.norm(vector))
    return vector / norm if norm > 0 else np.array([0.0, 0.0, 1.0])


def _side_view(axis: np.ndarray) -> np.ndarray:
    """A horizontal direction to look from, perpendicular to `axis` (a stable choice)."""
    for candidate in ((0.0, -1.0, 0.0), (1.0, 0.0, 0.0), (0.0, 0.0, 1.0)):
        towards = np.asarray(candidate) - np.dot(candidate, axis) * axis
        if np.linalg.norm(towards) > 0.3:
            return _unit(towards)
    return _unit(np.cross(axis, (1.0, 0.0, 0.0)))  # pragma: no cover


def _frame(plotter, vertices: np.ndarray, towards: np.ndarray, up: np.ndarray, extra=()):
    """Point the active subplot's camera along -`towards`, `up` up, framing the points.

    Framed on the points given (the mesh, the arrow), not on every actor: the
    planes, drawn larger than the crown, run off the edges.
    """
    points = np.vstack([vertices, *extra]) if len(extra) else vertices
    right = np.cross(up, towards)
    across, upward = points @ right, points @ up
    centre = (
        0.5 * (across.min() + across.max()) * right
        + 0.5 * (upward.min() + upward.max()) * up
        + float(np.mean(points @ towards)) * towards
    )
    distance = 3.0 * max(float(np.linalg.norm(np.ptp(points, axis=0))), 1e-12)
    plotter.camera_position = [tuple(centre + distance * towards), tuple(centre), tuple(up)]
    plotter.enable_parallel_projection()
    plotter.reset_camera_clipping_range()
    half = 0.5 * max(float(np.ptp(upward)), float(np.ptp(across)), 1e-12)
    plotter.camera.parallel_scale = 1.12 * half


def _crown_points(raw_vertices: np.ndarray, vertices: np.ndarray, inverse: np.ndarray):
    """The raw scan's points that frame the picture: the crown, not the specks cleaning removed.

    The prepared crown carried back into the raw scan's coordinates, and the
    raw points near it (within half again its size of its centre: the base a
    crop removed), so that loose specks far away do not shrink the crown.
    """
    back = vertices @ inverse[:3, :3].T + inverse[:3, 3]
    centre = 0.5 * (back.min(axis=0) + back.max(axis=0))
    radius = 0.5 * float(np.linalg.norm(np.ptp(back, axis=0)))
    near = raw_vertices[np.linalg.norm(raw_vertices - centre, axis=1) <= 1.5 * radius]
    return np.vstack([back, near]) if len(near) else back


def _plane_patch(pv, point, normal, size: float):
    return pv.Plane(center=point, direction=normal, i_size=size, j_size=size)


def render_preparation(
    raw_vertices,
    raw_faces,
    crown,
    path,
    *,
    title: str | None = None,
    window_size: tuple[int, int] = PREVIEW_SIZE,
) -> None:
    """Draw a preparation's preview into the PNG `path` (written atomically).

    Parameters
    ----------
    raw_vertices : (n, 3) array_like of float
    raw_faces : (m, 3) array_like of int
        The raw scan as read (never modified).
    crown : dentopo.PreparedCrown
        What :func:`dentopo.prepare` made of it.
    path : path-like
        The PNG file.
    title : str, optional
        The text at the top (the file name; default: the crown's source).
    window_size : (int, int)
        Pixels.

    Raises
    ------
    dentopo._optional.MissingExtraError
        Without the viz extra (pyvista).
    """
    pv = PICTURES.require()
    image = require("PIL.Image", extra=PICTURES.extra, purpose=PICTURES.purpose)
    from ._render import _quiet_vtk_warnings

    raw_vertices = np.array(raw_vertices, dtype=np.float64)
    raw_faces = np.array(raw_faces, dtype=np.int64)
    vertices = np.array(crown.vertices, dtype=np.float64)
    faces = np.array(crown.faces, dtype=np.int64)
    title = title if title is not None else (crown.source or "")
    orientation = _orientation(crown)
    inverse = _rigid_inverse(orientation)
    axis = _unit(orientation[:3, :3].T @ np.array([0.0, 0.0, 1.0]))  # +z in raw coordinates
    inverse_all = _rigid_inverse(np.asarray(crown.transform, dtype=np.float64))
    framed = _crown_points(raw_vertices, vertices, inverse_all)
    extent = max(float(np.linalg.norm(np.ptp(framed, axis=0))), 1e-12)
    orient = _step(crown, "orient")
    crop = _step(crown, "crop")

    with _quiet_vtk_warnings():
        plotter = pv.Plotter(
            shape=(1, 2),
            off_screen=True,
            window_size=list(window_size),
            border=False,
            lighting="none",
        )
        try:
            plotter.set_background("white")
            # left: the raw scan from the side, its axis up
            plotter.subplot(0, 0)
            plotter.add_light(pv.Light(light_type="headlight"), only_active=True)
            raw = pv.PolyData.from_regular_faces(raw_vertices, raw_faces)
            colors = np.tile(np.asarray(NEUTRAL), (len(raw_vertices), 1))
            cut = None
            if crop is not None and crop.plane is not None:
                point = (inverse @ np.append(crop.plane["point"], 1.0))[:3]
                normal = _unit(inverse[:3, :3] @ np.asarray(crop.plane["normal"], float))
                cut = (point, normal)
                below = (raw_vertices - point) @ normal < 0
                colors[below] = REMOVED_COLOR
            raw.point_data["rgb"] = (colors * 255).astype(np.uint8)
            plotter.add_mesh(
                raw,
                scalars="rgb",
                rgb=True,
                smooth_shading=True,
                specular=0.0,
                ambient=0.3,
                diffuse=0.7,
            )
            base = None
            if orient is not None and orient.plane is not None:
                base = np.asarray(orient.plane["point"], float)
                patch = _plane_patch(pv, base, _unit(orient.plane["normal"]), 1.0 * extent)
                plotter.add_mesh(patch, color=AXIS_COLOR, opacity=0.18)
                plotter.add_mesh(patch.extract_feature_edges(), color=AXIS_COLOR, line_width=2)
            if cut is not None:
                patch = _plane_patch(pv, cut[0], cut[1], 1.3 * extent)
                plotter.add_mesh(patch, color=CROP_COLOR, opacity=0.25)
                plotter.add_mesh(patch.extract_feature_edges(), color=CROP_COLOR, line_width=3)
            extra = []
            if _axis_label(orient) is not None:  # a crown left as it lies has no axis to show
                heights = framed @ axis
                start = base if base is not None else framed.mean(axis=0)
                start = start + (heights.min() - float(start @ axis)) * axis
                length = 1.25 * max(float(np.ptp(heights)), 1e-12)
                arrow = pv.Arrow(
                    start=start,
                    direction=axis,
                    scale=length,
                    tip_length=0.12,
                    tip_radius=0.04,
                    shaft_radius=0.012,
                )
                plotter.add_mesh(arrow, color=AXIS_COLOR)
                extra = [arrow.points]
            _frame(plotter, framed, _side_view(axis), axis, extra=extra)
            plotter.add_text(
                f"{len(raw_faces):,} faces\n{_raw_label(orient, cut)}",
                position="lower_left",
                font_size=8,
                color="black",
            )
            plotter.add_text(_short(title), position="upper_left", font_size=11, color="black")
            for row, line in enumerate(_warning_lines(crown.warnings)):
                plotter.add_text(
                    line,
                    position=(6, window_size[1] - 44 - 13 * row),
                    font_size=6,
                    color=WARNING_COLOR,
                )
            # right: the prepared crown from the occlusal camera
            plotter.subplot(0, 1)
            plotter.add_light(pv.Light(light_type="headlight"), only_active=True)
            prepared = pv.PolyData.from_regular_faces(vertices, faces)
            plotter.add_mesh(
                prepared, color=NEUTRAL, smooth_shading=True, specular=0.0, ambient=0.3, diffuse=0.7
            )
            camera = camera_for(vertices, faces)
            rotation = camera.rotation()
            _frame(plotter, vertices, rotation[2], rotation[1])
            plotter.add_text(
                f"prepared, occlusal view: {len(faces):,} faces\n{crown.protocol.label}",
                position="lower_left",
                font_size=8,
                color="black",
            )
            pixels = plotter.screenshot(return_img=True)
        finally:
            plotter.close()
    buffer = io.BytesIO()
    picture = image.fromarray(np.ascontiguousarray(pixels))
    _outline(picture)
    picture.save(buffer, "PNG")
    write_bytes(path, buffer.getvalue())


def _short(text: str, limit: int = 70) -> str:
    """A title that fits: the end of a long path (where the file name is)."""
    text = " ".join(str(text).split())
    return text if len(text) <= limit else "..." + text[-(limit - 3) :]


def _start(text: str, limit: int) -> str:
    """The start of a long message (where it says what happened)."""
    text = " ".join(str(text).split())
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _outline(picture) -> None:
    """A thin grey line between the two views and around the picture (for the sheet)."""
    pixels = picture.load()
    width, height = picture.size
    grey = (200, 200, 200)
    for y in range(height):
        for x in (0, width // 2, width - 1):
            pixels[x, y] = grey
    for x in range(width):
        for y in (0, height - 1):
            pixels[x, y] = grey


def preview_sheet(paths, path, *, labels=None, columns: int | None = None, width: int = 440):
    """Tile the preview PNGs `paths` on one contact sheet, the PNG `path` (written atomically).

    Each preview is shrunk to `width` pixels (its file name is written on it);
    `columns` defaults to a roughly square sheet.  `labels` is accepted for callers
    that name the pictures otherwise (unused: the name is on each picture).
    """
    image = require("PIL.Image", extra=PICTURES.extra, purpose=PICTURES.purpose)
    paths = [os.fspath(p) for p in paths]
    if not paths:
        raise ValueError("no previews to put on a sheet")
    tiles = []
    for item in paths:
        with image.open(item) as picture:
            picture = picture.convert("RGB")
            height = max(1, round(picture.height * width / picture.width))
            tiles.append(picture.resize((width, height), image.LANCZOS))
    tile_height = max(t.height for t in tiles)
    if columns is None:
        columns = max(1, min(len(tiles), math.ceil(math.sqrt(len(tiles) * tile_height / width))))
    rows = math.ceil(len(tiles) / columns)
    sheet = image.new("RGB", (columns * width, rows * tile_height), "white")
    for index, tile in enumerate(tiles):
        sheet.paste(tile, ((index % columns) * width, (index // columns) * tile_height))
    buffer = io.BytesIO()
    sheet.save(buffer, "PNG")
    write_bytes(path, buffer.getvalue())
