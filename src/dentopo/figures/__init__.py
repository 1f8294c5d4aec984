"""Pictures: colour scales, camera views, pyvista renderings and HTML pages.

``_colors`` (the diverging scale shared by every picture and per-vertex file),
``_views`` (named views along the mesh's axes), ``_camera`` (the occlusal view
and every picture's camera), ``_layout`` (print-ready composition: pyvista 3D
views with matplotlib texts and legends, sized in points), ``_provenance``
(the JSON kept in every PNG and HTML page), ``_render`` (windows and pictures,
pyvista imported only when a picture is drawn), ``_html`` (self-contained WebGL
pages), ``_topography`` (per-face pictures of slope and OPC, and RFI's
footprint outline, drawn from a result's arrays), ``_face_values`` (the
per-face pictures of any value: ARC, angularity, inclination, elevation),
``_face_drawing`` (what those per-face pictures share: checks, the pyvista
window, the composed picture), ``_preparation`` (previews of
:func:`dentopo.prepare`: the raw scan with its found axis and crop plane beside
the prepared crown, and a contact sheet of them).

May import: :mod:`dentopo.mesh`, :mod:`dentopo.sign`, :mod:`dentopo.ariadne`,
:mod:`dentopo.topography` (to compute a result with default settings when none
is given; figures never implement a metric), :mod:`dentopo.prepare` (the prepared
crown drawn by the previews).  Nothing from formats, batch,
study or cli.
"""

from ._camera import DEFAULT_VIEW, VIEW_NAMES, Camera, camera_for
from ._colors import (
    DEFAULT_PERCENTILE,
    NEUTRAL,
    OPC_COLORS,
    ColorScale,
    color_scale,
    diverging_rgb,
    slope_rgb,
)
from ._face_values import FACE_METRICS, FaceMetric, render_face_values
from ._preparation import preview_sheet, render_preparation
from ._provenance import read_provenance
from ._render import (  # pyvista is imported only when a picture is drawn
    DisplayUnavailableError,
    has_display,
    render_bandwidths,
    render_comparison,
    render_curvature,
    render_panel,
)
from ._topography import render_footprint, render_opc, render_slope
from ._views import VIEWS

__all__ = [
    "DEFAULT_PERCENTILE",
    "DEFAULT_VIEW",
    "FACE_METRICS",
    "NEUTRAL",
    "OPC_COLORS",
    "VIEWS",
    "VIEW_NAMES",
    "Camera",
    "ColorScale",
    "DisplayUnavailableError",
    "FaceMetric",
    "camera_for",
    "color_scale",
    "diverging_rgb",
    "has_display",
    "preview_sheet",
    "read_provenance",
    "render_bandwidths",
    "render_comparison",
    "render_curvature",
    "render_face_values",
    "render_footprint",
    "render_opc",
    "render_panel",
    "render_preparation",
    "render_slope",
    "slope_rgb",
]
