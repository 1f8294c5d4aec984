"""Camera presets shared by the pictures (pyvista) and the HTML pages."""

from __future__ import annotations

import numpy as np

#: Preset views: direction from the focal point to the camera, and the view-up.
VIEWS = {
    "iso": ((1.0, -1.0, 1.0), (0.0, 0.0, 1.0)),
    "top": ((0.0, 0.0, 1.0), (0.0, 1.0, 0.0)),
    "bottom": ((0.0, 0.0, -1.0), (0.0, 1.0, 0.0)),
    "front": ((0.0, -1.0, 0.0), (0.0, 0.0, 1.0)),
    "back": ((0.0, 1.0, 0.0), (0.0, 0.0, 1.0)),
    "left": ((-1.0, 0.0, 0.0), (0.0, 0.0, 1.0)),
    "right": ((1.0, 0.0, 0.0), (0.0, 0.0, 1.0)),
}


def view_rotation(view: str | None) -> np.ndarray:
    """Rows: the camera's right, up and towards-viewer axes in mesh coordinates."""
    direction, up = (np.asarray(v, dtype=np.float64) for v in VIEWS[view or "iso"])
    z = direction / np.linalg.norm(direction)
    y = up - np.dot(up, z) * z
    y /= np.linalg.norm(y)
    return np.array([np.cross(y, z), y, z])
