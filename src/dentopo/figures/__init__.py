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

from typing import TYPE_CHECKING

from .._lazy_exports import lazy_exports

if TYPE_CHECKING:  # the real imports, for type checkers and IDEs
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

#: Where each public name lives: imported on its first use (PEP 562).
_EXPORTS = {
    "DEFAULT_VIEW": "._camera",
    "VIEW_NAMES": "._camera",
    "Camera": "._camera",
    "camera_for": "._camera",
    "DEFAULT_PERCENTILE": "._colors",
    "NEUTRAL": "._colors",
    "OPC_COLORS": "._colors",
    "ColorScale": "._colors",
    "color_scale": "._colors",
    "diverging_rgb": "._colors",
    "slope_rgb": "._colors",
    "FACE_METRICS": "._face_values",
    "FaceMetric": "._face_values",
    "render_face_values": "._face_values",
    "preview_sheet": "._preparation",
    "render_preparation": "._preparation",
    "read_provenance": "._provenance",
    "DisplayUnavailableError": "._render",
    "has_display": "._render",
    "render_bandwidths": "._render",
    "render_comparison": "._render",
    "render_curvature": "._render",
    "render_panel": "._render",
    "render_footprint": "._topography",
    "render_opc": "._topography",
    "render_slope": "._topography",
    "VIEWS": "._views",
}

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


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, __all__)
