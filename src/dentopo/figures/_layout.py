"""Print-ready pictures: 3D views (pyvista) composed with texts and legends (matplotlib).

A picture is a grid of panels (one mesh each, its label and caption above
it) with a heading at the top and one legend at the bottom: a colour bar for
continuous data, labelled swatches for categories.  Everything is laid out
in pixels from the requested size and resolution:

* texts are set in points (8 pt by default), so that they grow with the
  resolution; a 600 dpi picture has texts as readable in print as a 150 dpi
  one.  A text wider than its place is wrapped at spaces, then set smaller
  (down to :data:`MIN_POINTS`);
* margins and line widths are in points too;
* each 3D view is rendered by pyvista at exactly its place's pixel size with
  a parallel projection framed so that the whole mesh fits with a margin
  (:meth:`~._camera.Camera.half_extent`), then placed into the figure.

matplotlib reports the box of every text (``Text.get_window_extent``); the
tests check that none intersects another or a 3D view.  ``.svg`` and
``.pdf`` outputs keep the texts and legends as vectors (the 3D views are
images in them); ``.png`` outputs carry the provenance in a text chunk.
"""

from __future__ import annotations

import io
import itertools
import math
import os
import tempfile
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from .._optional import PICTURES, require
from ._camera import Camera

#: Size of texts in points (labels, captions, legends); the heading is a point larger.
BASE_POINTS = 8.0
#: Texts are set no smaller than this, in points, to fit their place.
MIN_POINTS = 5.0
#: Share of a 3D view's frame kept empty on every side around the mesh.
VIEW_MARGIN = 0.06
#: Output formats by file extension: PNG (with provenance), SVG and PDF (texts as vectors).
FORMATS = (".png", ".svg", ".pdf")
#: The default resolution: the picture printed 6.4 inches wide, within 100 to 600 dpi.
PRINT_WIDTH_INCHES = 6.4


@dataclass
class Panel:
    """One mesh to draw in its own frame.

    ``point_rgb`` (per vertex, smooth) or ``cell_rgb`` (per face, flat), uint8.
    ``lines``: (k, 2, 3) segments over the mesh, ``line_points`` wide.
    """

    vertices: np.ndarray
    faces: np.ndarray
    camera: Camera
    point_rgb: np.ndarray | None = None
    cell_rgb: np.ndarray | None = None
    label: str = ""
    caption: str = ""
    lines: np.ndarray | None = None
    line_rgb: tuple = (0, 0, 0)
    line_points: float = 0.8
    ambient: float = 0.3


@dataclass
class ColorBar:
    """A continuous legend: ``rgb_at`` maps [0, 1] to RGB floats; ticks are (position, text)."""

    rgb_at: Callable[[np.ndarray], np.ndarray]
    ticks: Sequence[tuple[float, str]]
    title: str = ""
    note: str = ""


@dataclass
class Swatches:
    """A categorical legend: one labelled square per (label, (r, g, b) 0-255) entry."""

    entries: Sequence[tuple[str, tuple]]
    title: str = ""


@dataclass
class Layout:
    """Where things went: the figure, its 3D views' axes and its texts (for checks)."""

    figure: object
    views: list = field(default_factory=list)
    texts: list = field(default_factory=list)


def check_size(size) -> tuple[int, int]:
    """(width, height) in pixels, each 16 to 16384."""
    try:
        width, height = (int(v) for v in size)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"the size must be (width, height) in pixels; got {size!r}") from exc
    if width < 16 or height < 16 or width > 16384 or height > 16384:
        raise ValueError(f"the size must lie in 16..16384 pixels; got {size!r}")
    return width, height


def check_dpi(dpi, width: int) -> float:
    """The resolution in dots per inch: `dpi`, or by default the width printed 6.4 inches wide."""
    if dpi is None:
        return float(min(600.0, max(100.0, round(width / PRINT_WIDTH_INCHES))))
    if isinstance(dpi, bool) or not isinstance(dpi, (int, float)) or not math.isfinite(dpi):
        raise TypeError(f"dpi must be a number; got {dpi!r}")
    if not 10 <= dpi <= 2400:
        raise ValueError(f"dpi must lie in 10..2400; got {dpi!r}")
    return float(dpi)


def output_format(path) -> str:
    """The output's format from its extension: ``.png``, ``.svg`` or ``.pdf``."""
    ext = os.path.splitext(os.fspath(path))[1].lower()
    if ext not in FORMATS:
        raise ValueError(
            f"a picture is written as {', '.join(FORMATS)} (from the file name); got {path!r}"
        )
    return ext


# ---------------------------------------------------------------------------
# texts


class _Typesetter:
    """Measures texts in pixels and fits them into widths (wrapping, then shrinking)."""

    def __init__(self, renderer, dpi: float):
        from matplotlib.font_manager import FontProperties

        self._renderer = renderer
        self._font = FontProperties
        self.px = dpi / 72.0  # pixels per point

    def width(self, text: str, points: float) -> float:
        if not text:
            return 0.0
        prop = self._font(size=points)
        return max(
            self._renderer.get_text_width_height_descent(line, prop, ismath=False)[0]
            for line in text.split("\n")
        )

    def line_height(self, points: float) -> float:
        return 1.3 * points * self.px

    def _pieces(self, word: str, width: float, points: float) -> list[str] | None:
        """`word` cut between characters into pieces that fit `width`, or None if none can."""
        pieces, piece = [], ""
        for char in word:
            if self.width(piece + char, points) <= width:
                piece += char
            elif not piece:
                return None
            else:
                pieces.append(piece)
                piece = char
        return [*pieces, piece]

    def _wrap(self, text: str, width: float, points: float, cut: bool = False) -> str | None:
        """Lines broken at spaces (and inside words too wide for a line, if `cut`), or None."""
        lines = []
        for paragraph in text.split("\n"):
            line = ""
            for word in paragraph.split(" "):
                candidate = f"{line} {word}" if line else word
                if self.width(candidate, points) <= width:
                    line = candidate
                    continue
                if line:
                    lines.append(line)
                    line = ""
                if self.width(word, points) <= width:
                    line = word
                    continue
                if not cut:
                    return None
                pieces = self._pieces(word, width, points)
                if pieces is None:
                    return None
                lines.extend(pieces[:-1])
                line = pieces[-1]
            lines.append(line)
        return "\n".join(lines)

    def fit(self, text: str, width: float, points: float = BASE_POINTS) -> tuple[str, float]:
        """`text` wrapped at spaces to `width` pixels, set smaller if a word does not fit.

        Down to three quarters of `points` (and no smaller than :data:`MIN_POINTS`);
        a word still too wide (a long file name) is then cut between characters.
        """
        smallest = max(MIN_POINTS, 0.75 * points)
        size = points
        while True:
            wrapped = self._wrap(text, width, size)
            if wrapped is not None:
                return wrapped, size
            if size <= smallest:
                break
            size = max(smallest, size - 0.5)
        wrapped = self._wrap(text, width, size, cut=True)
        if wrapped is None:
            raise ValueError(
                f"the picture is too small for its texts: {width:.0f} pixels hold no character "
                f"at {size:g} pt; give a larger size or a lower dpi"
            )
        return wrapped, size

    def height(self, text: str, points: float) -> float:
        return (text.count("\n") + 1) * self.line_height(points) if text else 0.0


# ---------------------------------------------------------------------------
# 3D views


#: 3D views up to this many pixels wide and high are rendered twice as large in each
#: direction, then averaged down: anti-aliasing that keeps line widths, unlike VTK's SSAA
#: pass.  Larger views have pixels small enough not to need it.
SUPERSAMPLE_UP_TO = 2048


def _downsample(image: np.ndarray) -> np.ndarray:
    """Average 2 x 2 blocks of an RGBA image, colours weighted by their alpha."""
    h, w = image.shape[0] // 2, image.shape[1] // 2
    quarters = [
        image[i : 2 * h : 2, j : 2 * w : 2].astype(np.uint32) for i in (0, 1) for j in (0, 1)
    ]
    weight = sum(q[..., 3] for q in quarters)
    rgb = sum(q[..., :3] * q[..., 3:4] for q in quarters)
    out = np.empty((h, w, 4), dtype=np.uint8)
    safe = np.maximum(weight, 1)[..., None]
    out[..., :3] = np.where(weight[..., None] > 0, (rgb + safe // 2) // safe, 255)
    out[..., 3] = (weight + 2) // 4
    return out


def render_view(panel: Panel, width: int, height: int, *, dpi: float, transparent: bool):
    """The panel's 3D view as an (height, width, 4) uint8 RGBA image (alpha 0 off the mesh)."""
    pv = PICTURES.require()
    factor = 2 if max(width, height) <= SUPERSAMPLE_UP_TO else 1
    plotter = pv.Plotter(
        off_screen=True, window_size=[width * factor, height * factor], lighting="none"
    )
    try:
        plotter.set_background("white")
        plotter.add_light(pv.Light(light_type="headlight"))
        poly = pv.PolyData.from_regular_faces(panel.vertices, panel.faces)
        shading = dict(
            specular=0.0,
            ambient=panel.ambient,
            diffuse=1.0 - panel.ambient,
            show_scalar_bar=False,
            rgb=True,
        )
        if panel.cell_rgb is not None:
            poly.cell_data["rgb"] = np.asarray(panel.cell_rgb, dtype=np.uint8)
            plotter.add_mesh(poly, scalars="rgb", **shading)
        else:
            poly.point_data["rgb"] = np.asarray(panel.point_rgb, dtype=np.uint8)
            plotter.add_mesh(poly, scalars="rgb", smooth_shading=True, **shading)
        points = panel.vertices
        if panel.lines is not None and len(panel.lines):
            ends = np.asarray(panel.lines, dtype=np.float64).reshape(-1, 3)
            cells = np.column_stack(
                [np.full(len(panel.lines), 2), np.arange(len(ends)).reshape(-1, 2)]
            )
            plotter.add_mesh(
                pv.PolyData(ends, lines=cells.ravel()),
                color=[c / 255 for c in panel.line_rgb],
                line_width=max(1.0, panel.line_points * dpi / 72.0) * factor,
                lighting=False,
                show_scalar_bar=False,
            )
            points = np.concatenate([points, ends])
        camera = panel.camera
        plotter.enable_parallel_projection()
        plotter.camera.position = camera.position
        plotter.camera.focal_point = camera.focal_point
        plotter.camera.up = camera.up
        plotter.camera.parallel_scale = camera.half_extent(points, width / height, VIEW_MARGIN)
        plotter.renderer.reset_camera_clipping_range()
        image = plotter.screenshot(transparent_background=True, return_img=True)
    finally:
        plotter.close()
    image = np.asarray(image, dtype=np.uint8)
    if factor == 2:
        image = _downsample(image)
    if not transparent:  # on white, as the figure
        alpha = image[..., 3:4] / 255.0
        rgb = np.round(image[..., :3] * alpha + 255.0 * (1.0 - alpha)).astype(np.uint8)
        image = np.concatenate([rgb, np.full_like(image[..., :1], 255)], axis=2)
    return image


# ---------------------------------------------------------------------------
# composing


def _grid(n: int) -> tuple[int, int]:
    cols = n if n <= 4 else math.ceil(math.sqrt(n))
    return cols, math.ceil(n / cols)


def compose(
    panels: Sequence[Panel],
    legend: ColorBar | Swatches | None,
    *,
    size: tuple[int, int],
    dpi: float,
    heading: str = "",
    transparent: bool = False,
    points: float = BASE_POINTS,
) -> Layout:
    """Lay out and draw the picture; the :class:`Layout` (its figure not yet saved).

    Raises
    ------
    ValueError
        If the texts leave no room for the meshes at this size and resolution.
    """
    require("matplotlib", extra=PICTURES.extra, purpose=PICTURES.purpose)
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.patches import Rectangle

    width, height = size
    figure = Figure(figsize=(width / dpi, height / dpi), dpi=dpi)
    FigureCanvasAgg(figure)
    typeset = _Typesetter(figure.canvas.get_renderer(), dpi)
    px = typeset.px
    margin = 0.75 * points * px
    gap = 0.4 * points * px
    layout = Layout(figure)

    def text(x, y, s, size, **kw):  # x, y in pixels from the bottom left
        t = figure.text(x / width, y / height, s, fontsize=size, color="black", **kw)
        layout.texts.append(t)
        return t

    def fraction(x, y, w, h):
        return [x / width, y / height, w / width, h / height]

    inner = width - 2 * margin
    top = height - margin
    if heading:
        heading, size_h = typeset.fit(heading, inner, points + 1)
        text(width / 2, top, heading, size_h, ha="center", va="top", linespacing=1.3)
        top -= typeset.height(heading, size_h) + gap

    bottom = margin
    if isinstance(legend, ColorBar):
        bottom = _colorbar(legend, figure, typeset, text, fraction, width, margin, gap, points)
        bottom += gap
    elif isinstance(legend, Swatches):
        bottom = _swatches(legend, figure, typeset, text, Rectangle, width, margin, gap, points)
        bottom += gap

    cols, rows = _grid(len(panels))
    cell_w = (inner - (cols - 1) * gap) / cols
    cell_h = (top - bottom - (rows - 1) * gap) / rows
    view_w = math.floor(cell_w)
    size_p = points
    texts = ["\n".join(t for t in (panel.label, panel.caption) if t) for panel in panels]
    while True:  # the panels' texts take at most 40 % of a cell's height: smaller, if need be
        sizes = [typeset.fit(words, cell_w, size_p)[1] for words in texts if words]
        common = min(sizes, default=size_p)  # one size for every panel
        fitted = [typeset.fit(words, cell_w, common) if words else ("", common) for words in texts]
        text_h = max(typeset.height(w, s) for w, s in fitted)
        view_h = math.floor(cell_h - text_h - (gap if text_h else 0))
        if text_h <= 0.4 * cell_h or size_p <= MIN_POINTS:
            break
        size_p = max(MIN_POINTS, size_p - 0.5)
    if view_h < 16 or view_w < 16:
        raise ValueError(
            f"the picture ({width} x {height} pixels at {dpi:g} dpi) is too small for its texts: "
            "no room is left for the meshes; give a larger size or a lower dpi"
        )
    for index, (panel, (words, size_t)) in enumerate(zip(panels, fitted, strict=True)):
        row, col = divmod(index, cols)
        x = margin + col * (cell_w + gap)
        y_top = top - row * (cell_h + gap)
        if words:
            text(x, y_top, words, size_t, ha="left", va="top", linespacing=1.3)
        x0 = round(x)
        y0 = round(y_top - cell_h)
        image = render_view(panel, view_w, view_h, dpi=dpi, transparent=transparent)
        axes = figure.add_axes(fraction(x0, y0, view_w, view_h))
        axes.imshow(image, interpolation="none", aspect="auto")
        axes.set_axis_off()
        layout.views.append(axes)
    return layout


def _colorbar(legend, figure, typeset, text, fraction, width, margin, gap, points) -> float:
    from matplotlib.lines import Line2D

    height = figure.bbox.height
    """Draw the colour bar at the bottom; the height (pixels) it takes, margins included."""
    px = typeset.px
    bar_w = min(width - 2 * margin, max(0.6 * width, 30 * points * px))
    bar_h = 0.9 * points * px
    x0 = (width - bar_w) / 2
    y = margin
    if legend.note:
        note, size_n = typeset.fit(legend.note, width - 2 * margin, points)
        text(width / 2, y, note, size_n, ha="center", va="bottom", linespacing=1.3)
        y += typeset.height(note, size_n) + 0.3 * gap
    ticks = list(legend.ticks)
    size_t = points
    while True:  # tick labels must not touch: fewer of them, then smaller
        widths = [typeset.width(t, size_t) for _, t in ticks]
        xs = [x0 + p * bar_w for p, _ in ticks]
        spans = [(x - w / 2, x + w / 2) for x, w in zip(xs, widths, strict=True)]
        crowded = any(a[1] + 0.5 * points * px > b[0] for a, b in itertools.pairwise(spans))
        if not crowded:
            break
        if len(ticks) > 3:
            ticks = ticks[::2] if len(ticks) % 2 else [ticks[0], ticks[len(ticks) // 2], ticks[-1]]
        elif len(ticks) == 3:
            ticks = [ticks[0], ticks[-1]]
        elif size_t > MIN_POINTS:
            size_t -= 0.5
        else:
            break
    # keep the end labels inside the picture
    labels_y = y
    for (position, label), w in zip(
        ticks, [typeset.width(t, size_t) for _, t in ticks], strict=True
    ):
        x = x0 + position * bar_w
        x = min(max(x, margin + w / 2), width - margin - w / 2)
        text(x, labels_y, label, size_t, ha="center", va="bottom")
    y += typeset.line_height(size_t)
    tick_len = 0.35 * points * px
    for position, _ in ticks:
        x = (x0 + position * bar_w) / width
        figure.add_artist(
            Line2D(
                [x, x],
                [y / height, (y + tick_len) / height],
                transform=figure.transFigure,
                color="black",
                linewidth=0.5,
            )
        )
    y += tick_len
    axes = figure.add_axes(fraction(x0, y, bar_w, bar_h))
    gradient = legend.rgb_at(np.linspace(0.0, 1.0, 512))[None, :, :]
    axes.imshow(gradient, aspect="auto", interpolation="bilinear", extent=(0, 1, 0, 1))
    axes.set_xticks([])
    axes.set_yticks([])
    for spine in axes.spines.values():
        spine.set_linewidth(0.5)
    y += bar_h + 0.3 * gap
    if legend.title:
        title, size_h = typeset.fit(legend.title, width - 2 * margin, points)
        text(width / 2, y, title, size_h, ha="center", va="bottom", linespacing=1.3)
        y += typeset.height(title, size_h)
    return y


def _swatches(legend, figure, typeset, text, rectangle, width, margin, gap, points) -> float:
    """Draw labelled swatches at the bottom, in as many columns as fit; the height taken."""
    px = typeset.px
    height = figure.bbox.height
    inner = width - 2 * margin
    size_t = points
    while True:
        side = 0.9 * size_t * px
        entry = [
            side + 0.5 * size_t * px + typeset.width(label, size_t) for label, _ in legend.entries
        ]
        column = max(entry) + 1.5 * size_t * px
        cols = max(1, min(len(entry), int(inner // column)))
        if max(entry) <= inner or size_t <= MIN_POINTS:
            break
        size_t -= 0.5
    if max(entry) > inner:
        raise ValueError(
            "the picture is too small for its legend; give a larger size or a lower dpi"
        )
    rows = math.ceil(len(entry) / cols)
    row_h = 1.4 * size_t * px
    used = cols * column - 1.5 * size_t * px
    x_start = (width - used) / 2
    y = margin
    for index, (label, rgb) in enumerate(legend.entries):
        row, col = divmod(index, cols)
        x = x_start + col * column
        yc = y + (rows - 1 - row) * row_h + row_h / 2
        figure.add_artist(
            rectangle(
                (x / width, (yc - side / 2) / height),
                side / width,
                side / height,
                transform=figure.transFigure,
                facecolor=[c / 255 for c in rgb],
                edgecolor="#444444",
                linewidth=0.5,
            )
        )
        text(x + side + 0.5 * size_t * px, yc, label, size_t, ha="left", va="center_baseline")
    y += rows * row_h
    if legend.title:
        title, size_h = typeset.fit(legend.title, inner, points)
        y += 0.2 * gap
        text(width / 2, y, title, size_h, ha="center", va="bottom", linespacing=1.3)
        y += typeset.height(title, size_h)
    return y


# ---------------------------------------------------------------------------
# saving


def save(layout: Layout, path, *, metadata: str | None, transparent: bool) -> None:
    """Write the figure to `path` (format from its extension), atomically.

    PNG files get `metadata` as a text chunk named ``dentopo``.
    """
    ext = output_format(path)
    figure = layout.figure
    options = {"format": ext[1:], "dpi": figure.dpi, "transparent": transparent}
    if not transparent:
        options["facecolor"] = "white"
    if ext == ".png" and metadata is not None:
        options["metadata"] = {"Software": "dentopo", "dentopo": metadata}
    elif ext == ".pdf":
        options["metadata"] = {"Creator": "dentopo"}
    buffer = io.BytesIO()
    figure.savefig(buffer, **options)
    write_bytes(path, buffer.getvalue())


def write_bytes(path, data: bytes) -> None:
    """Write `data` to `path` atomically: a temporary file beside it, renamed over it."""
    path = os.fspath(path)
    directory = os.path.dirname(os.path.abspath(path))
    handle, temporary = tempfile.mkstemp(
        dir=directory, prefix=f".{os.path.basename(path)}.", suffix=".tmp"
    )
    try:
        with os.fdopen(handle, "wb") as stream:
            stream.write(data)
            mask = os.umask(0o022)
            os.umask(mask)
            if hasattr(os, "fchmod"):  # through the file, never a link planted at its name
                os.fchmod(stream.fileno(), 0o666 & ~mask)
            else:  # pragma: no cover -- Windows before Python 3.13
                os.chmod(temporary, 0o666 & ~mask)
        os.replace(temporary, path)
    except BaseException:
        if os.path.exists(temporary):
            os.unlink(temporary)
        raise
