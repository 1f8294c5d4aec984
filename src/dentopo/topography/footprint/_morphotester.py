"""MorphoTester 1.1.1's outline area: the crown's projection rendered by matplotlib and counted.

MorphoTester (Winchester 2016; GPL-2) is reproduced from a description of its method
(``docs/MORPHOTESTER.md`` of the shared data), never from its code.  It draws the faces'
(x, y) triangles in blue and a vertical red reference line of known length into an 800 x
600 px Agg raster, and counts pixels of exact colours: the outline area is
``blue * L**2 / red**2``, ``L`` the line's length in mesh units.  Agg's antialiasing, its
snapping and the whole-pixel clip box are part of the number (it runs 1.5 to 1.75% above
the exact area of the projected triangles), so the raster is drawn by matplotlib's own Agg
renderer with every setting given explicitly: a ``Figure`` and ``FigureCanvasAgg``
(never pyplot), inside an ``rc_context`` holding matplotlib's default settings, so that a
user's style (``plt.style.use``, ``rcParams``) cannot change a pixel.  The render matches
the reference image of MorphoTester's tests pixel for pixel.

matplotlib is needed (the ``viz`` extra).
"""

from __future__ import annotations

import threading
from dataclasses import dataclass, field

import numpy as np

from ..._optional import MORPHOTESTER_OUTLINE

#: Figure size (inches) and resolution: matplotlib 1.x's defaults, MorphoTester's raster.
FIGSIZE = (8.0, 6.0)
DPI = 100

#: The axes' subplot parameters (matplotlib 1.x's defaults).
SUBPLOT = {"left": 0.125, "right": 0.9, "bottom": 0.1, "top": 0.9}

#: RGBA colours counted as the red line.
RED = ((255, 0, 0, 255), (255, 127, 127, 255))

#: RGBA colours that are not mesh: every other colour (antialiased blends included) is.
NOT_MESH = (
    (255, 0, 0, 255),
    (255, 255, 255, 255),
    (255, 155, 155, 255),
    (255, 188, 188, 255),
    (255, 205, 205, 255),
    (255, 230, 230, 255),
)

#: rcParams that are not a style (backend, windows, servers): left as the user has them.
_NOT_STYLE = frozenset(
    {
        "backend",
        "backend_fallback",
        "interactive",
        "toolbar",
        "timezone",
        "date.epoch",
        "docstring.hardcopy",
        "figure.max_open_warning",
        "figure.raise_window",
        "savefig.directory",
        "tk.window_focus",
        "webagg.address",
        "webagg.open_in_browser",
        "webagg.port",
        "webagg.port_retries",
    }
)

#: rcParams are global: one render at a time holds them (threads of one process).
_LOCK = threading.Lock()


@dataclass(frozen=True)
class OutlineRaster:
    """The counted raster of :func:`render_outline`.

    Attributes
    ----------
    red, blue : int
        Pixels of the red line and of the mesh (MorphoTester's counting rules).
    length : float
        ``L = (ymax - ymin) + 1``: the red line's length, mesh units.
    image : (600, 800, 4) uint8
        The RGBA raster, top row first (read-only).
    """

    red: int
    blue: int
    length: float
    image: np.ndarray = field(repr=False, compare=False)

    def __post_init__(self):
        self.image.flags.writeable = False

    @property
    def scale(self) -> float:
        """Pixels per mesh unit as MorphoTester takes it: ``red / L``."""
        return self.red / self.length


def _codes(colours) -> np.ndarray:
    return np.array([int.from_bytes(bytes(c), "big") for c in colours], dtype=np.uint32)


def _draw(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """The (600, 800, 4) RGBA raster of MorphoTester's outline figure."""
    mpl = MORPHOTESTER_OUTLINE.require()
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.collections import PolyCollection
    from matplotlib.figure import Figure
    from matplotlib.patches import Polygon

    style = {k: v for k, v in mpl.rcParamsDefault.items() if k not in _NOT_STYLE}
    xlo, ylo = vertices[:, 0].min() - 0.5, vertices[:, 1].min() - 0.5
    xhi, yhi = vertices[:, 0].max() + 0.5, vertices[:, 1].max() + 0.5
    with _LOCK, mpl.rc_context(style):
        figure = Figure(
            figsize=FIGSIZE, dpi=DPI, facecolor="white", edgecolor="white", linewidth=0.0
        )
        canvas = FigureCanvasAgg(figure)
        figure.subplots_adjust(**SUBPLOT)
        axes = figure.add_subplot(1, 1, 1)
        axes.set_xlim(xlo, xhi)
        axes.set_ylim(ylo, yhi)
        axes.set_aspect("equal", adjustable="box", anchor="C")
        axes.set_axis_off()
        axes.add_patch(
            Polygon(
                [[xlo, ylo], [xlo, yhi]],
                closed=True,
                facecolor=(1.0, 0.0, 0.0),
                edgecolor=(1.0, 0.0, 0.0),
                linewidth=1.0,
                antialiased=True,
            )
        )
        axes.add_collection(
            PolyCollection(
                vertices[faces][:, :, :2],
                facecolors=[(0.0, 0.0, 1.0)],
                edgecolors=[(0.0, 0.0, 1.0)],
                linewidths=[1.0],
                antialiaseds=[True],
            ),
            autolim=False,
        )
        canvas.draw()
        return np.array(canvas.buffer_rgba(), dtype=np.uint8, copy=True)


def render_outline(vertices: np.ndarray, faces: np.ndarray) -> OutlineRaster:
    """MorphoTester's outline raster of a mesh and its red and blue pixel counts.

    Axis limits run 0.5 units beyond the extremes of *all* vertices; equal aspect, the
    620 x 480 px box shrunk about its centre; the red line is the left edge of the box,
    1 pt wide; every face a blue triangle with a 1 pt blue edge, antialiased.

    Raises
    ------
    ValueError
        If the vertices have no extent in y (MorphoTester's line length ``L`` is then
        1, its error) or in x (the outline has no area), a size too large for the
        arithmetic, or the red line covers no pixel.
    """
    extent = np.ptp(vertices[:, :2], axis=0)
    with np.errstate(over="ignore"):
        length = float(extent[1]) + 1.0
        width = float(extent[0]) + 1.0
    if not (np.isfinite(length) and np.isfinite(width)):
        raise ValueError(
            "MorphoTester's outline area: the mesh is too large for the raster's arithmetic "
            f"(extent {extent[0]:g} x {extent[1]:g})"
        )
    if extent[1] == 0:
        raise ValueError(
            "MorphoTester's outline area: the mesh has no extent in y (every vertex at one y), "
            "so the reference line is L = 1 unit long, which MorphoTester reports as an error"
        )
    if extent[0] == 0:
        raise ValueError(
            "MorphoTester's outline area: the mesh has no extent in x (every vertex at one x): "
            "its projected outline has no area"
        )
    image = _draw(vertices, faces)
    code = image.reshape(-1, 4).view(">u4").ravel()
    red = int(np.count_nonzero(np.isin(code, _codes(RED))))
    blue = int(code.size - np.count_nonzero(np.isin(code, _codes(NOT_MESH))))
    if red == 0:
        raise ValueError(
            "MorphoTester's outline area: the red reference line covers no pixel, so the "
            "pixels have no scale"
        )
    return OutlineRaster(red=red, blue=blue, length=length, image=image)
