"""Pictures: colour scales, camera views, pyvista renderings and HTML pages.

``_colors`` (the diverging scale shared by every picture and per-vertex file),
``_views`` (camera presets), ``_render`` (windows and PNGs through pyvista,
imported only when a picture is drawn), ``_html`` (self-contained WebGL pages),
``_topography`` (per-face pictures of slope and OPC, and RFI's footprint outline,
drawn from a result's arrays).

May import: :mod:`dentopo.mesh`, :mod:`dentopo.sign`, :mod:`dentopo.ariadne`,
:mod:`dentopo.topography` (to compute a result with default settings when none
is given; figures never implement a metric).  Nothing from formats, batch,
study or cli.
"""

from ._colors import (
    DEFAULT_PERCENTILE,
    NEUTRAL,
    OPC_COLORS,
    ColorScale,
    color_scale,
    diverging_rgb,
    slope_rgb,
)
from ._render import (  # pyvista is imported only when a picture is drawn
    DisplayUnavailableError,
    render_bandwidths,
    render_comparison,
    render_curvature,
    render_panel,
)
from ._topography import render_footprint, render_opc, render_slope
from ._views import VIEWS

__all__ = [
    "DEFAULT_PERCENTILE",
    "NEUTRAL",
    "OPC_COLORS",
    "VIEWS",
    "ColorScale",
    "DisplayUnavailableError",
    "color_scale",
    "diverging_rgb",
    "render_bandwidths",
    "render_comparison",
    "render_curvature",
    "render_footprint",
    "render_opc",
    "render_panel",
    "render_slope",
    "slope_rgb",
]
