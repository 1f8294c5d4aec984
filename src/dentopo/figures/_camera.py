"""Where the camera stands: the occlusal view of a crown, named views, turns from them.

The rule (:func:`occlusal_direction`)
-------------------------------------
The default view, ``"occlusal"``, looks at the occlusal surface along one of
the mesh's principal axes (the eigenvectors of the area-weighted covariance
of its face centroids):

* **An open crown** (a surface with a boundary, the usual cut-off crown) is
  seen from the side away from its open base: the camera looks along the
  principal axis best aligned with the line from the boundary's centroid
  (length-weighted) to the surface's centroid (area-weighted), from the
  surface's side.  A crown pointing to -z (its cut rim faces +z) is seen
  from -z.
* **A closed surface** is seen along its axis of least extent, from the side
  its area faces: with the faces oriented outward, the side whose faces'
  normals point towards it holds more of the area, by at least
  :data:`CLOSED_MARGIN` of the total.  When neither side does, the camera
  takes the side with the larger z (+z), or, for an axis across z, the side
  of the axis's largest positive component.

The picture's up direction is the remaining principal axis of smaller
extent, so that the longer one runs across the picture; its sign makes its
largest component positive.  Named views (``"top"``, ``"bottom"``,
``"front"``, ``"back"``, ``"left"``, ``"right"``, ``"iso"``) look along the
mesh's own coordinate axes, as before.  ``azimuth`` then turns the camera
about the picture's up direction and ``elevation`` about its horizontal
direction, in degrees (as VTK's ``Azimuth`` and ``Elevation`` do).

numpy only.
"""

from __future__ import annotations

from dataclasses import dataclass
from numbers import Real

import numpy as np

from ..mesh import boundary_edges, outward_faces
from ._views import VIEWS

#: The default view: the occlusal surface (see the module's rule).
DEFAULT_VIEW = "occlusal"

#: Every view name: the occlusal view and the presets along the mesh's axes.
VIEW_NAMES = (DEFAULT_VIEW, *VIEWS)

#: A closed surface is seen from one side only if that side has this much more of its area.
CLOSED_MARGIN = 0.2


@dataclass(frozen=True)
class Camera:
    """A camera in the mesh's coordinates, looking with a parallel projection.

    Attributes
    ----------
    position : (float, float, float)
        Where the camera stands.
    focal_point : (float, float, float)
        The point it looks at: the centre of the mesh as seen from there.
    up : (float, float, float)
        The picture's up direction (a unit vector perpendicular to the view).
    view : str
        The view it was made from (``"occlusal"``, ``"top"`` ... or ``"camera"``
        for one given as three points).
    azimuth, elevation : float
        The turns applied after the view, in degrees.
    """

    position: tuple[float, float, float]
    focal_point: tuple[float, float, float]
    up: tuple[float, float, float]
    view: str = DEFAULT_VIEW
    azimuth: float = 0.0
    elevation: float = 0.0

    def rotation(self) -> np.ndarray:
        """(3, 3) rows: the picture's right, up and towards-the-viewer axes in mesh coordinates."""
        towards = np.subtract(self.position, self.focal_point)
        towards = towards / np.linalg.norm(towards)
        up = np.asarray(self.up, dtype=np.float64)
        up = up - np.dot(up, towards) * towards
        up /= np.linalg.norm(up)
        return np.array([np.cross(up, towards), up, towards])

    def half_extent(self, vertices, aspect: float, margin: float = 0.06) -> float:
        """Half the height, in mesh units, of a view of width/height `aspect` showing every vertex.

        The vertices' extent across and up the picture, around the focal point,
        grown by `margin` of the frame on every side.
        """
        rotation = self.rotation()
        offset = np.asarray(vertices, dtype=np.float64) - np.asarray(self.focal_point)
        across = np.abs(offset @ rotation[0]).max()
        upward = np.abs(offset @ rotation[1]).max()
        half = max(upward, across / float(aspect), 1e-12)
        return half / (1.0 - 2.0 * margin)

    def as_dict(self) -> dict:
        """The camera as JSON-ready values (the pictures' provenance)."""
        return {
            "position": [float(x) for x in self.position],
            "focal_point": [float(x) for x in self.focal_point],
            "up": [float(x) for x in self.up],
            "view": self.view,
            "azimuth": float(self.azimuth),
            "elevation": float(self.elevation),
            "projection": "parallel",
        }


def check_view(view):
    """A view name (any case) or a camera of three points, validated; else ValueError/TypeError."""
    if isinstance(view, str):
        if view.lower() not in VIEW_NAMES:
            raise ValueError(f"view must be one of {VIEW_NAMES} or a camera; got {view!r}")
        return view.lower()
    if isinstance(view, Camera):
        return view
    try:
        camera = np.asarray(view, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"view must be a view name or a camera; got {view!r:.60}") from exc
    if camera.shape != (3, 3) or not np.isfinite(camera).all():
        raise ValueError(
            "a camera view is three points: (position, focal_point, view_up), shape (3, 3); "
            f"got shape {camera.shape}"
        )
    return camera


def _angle(value, name: str) -> float:
    if isinstance(value, bool) or not isinstance(value, Real) or not np.isfinite(value):
        raise TypeError(f"{name} must be a finite number of degrees; got {value!r}")
    return float(value)


def _principal_axes(vertices: np.ndarray, faces: np.ndarray):
    """Area-weighted centroid, principal axes (columns) and extents along them."""
    tri = vertices[faces]
    area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
    centres = tri.mean(axis=1)
    weight = area / area.sum() if area.sum() > 0 else np.full(len(area), 1.0 / len(area))
    centroid = weight @ centres
    offset = centres - centroid
    _, axes = np.linalg.eigh((offset * weight[:, None]).T @ offset)
    extent = np.ptp(vertices @ axes, axis=0)
    return centroid, axes, extent, area


def _positive(axis: np.ndarray) -> np.ndarray:
    """`axis` signed so that its largest component is positive."""
    return axis if axis[np.argmax(np.abs(axis))] > 0 else -axis


def occlusal_direction(vertices, faces) -> tuple[np.ndarray, np.ndarray]:
    """Unit vectors (towards the camera, picture up) of the occlusal view (see the module).

    Parameters
    ----------
    vertices : (n, 3) array_like of float
    faces : (m, 3) array_like of int

    Returns
    -------
    towards, up : (3,) float
        From the focal point towards the camera, and the picture's up direction.
    """
    vertices = np.asarray(vertices, dtype=np.float64)
    faces = np.asarray(faces, dtype=np.int64)
    centroid, axes, extent, area = _principal_axes(vertices, faces)
    edges = boundary_edges(faces, len(vertices))
    if len(edges):
        ends = vertices[edges]
        length = np.linalg.norm(ends[:, 1] - ends[:, 0], axis=1)
        base = (length @ ends.mean(axis=1)) / length.sum()
        away = centroid - base
        along = axes.T @ away
        index = int(np.argmax(np.abs(along)))
        towards = axes[:, index] * (1.0 if along[index] >= 0 else -1.0)
    else:
        index = int(np.argmin(extent))
        axis = axes[:, index]
        out = vertices[outward_faces(vertices, faces)]
        normal = np.cross(out[:, 1] - out[:, 0], out[:, 2] - out[:, 0])
        side = normal @ axis
        plus, minus = area[side > 0].sum(), area[side < 0].sum()
        if abs(plus - minus) >= CLOSED_MARGIN * (plus + minus):
            towards = axis if plus > minus else -axis
        elif abs(axis[2]) > 1e-9:
            towards = axis if axis[2] > 0 else -axis
        else:
            towards = _positive(axis)
    rest = [k for k in range(3) if k != index]
    up = _positive(axes[:, min(rest, key=lambda k: (extent[k], k))])
    return towards / np.linalg.norm(towards), up


def _turn(towards: np.ndarray, up: np.ndarray, azimuth: float, elevation: float):
    """`towards` and `up` turned by `azimuth` about up, then by `elevation` about the right axis."""
    a, e = np.radians(azimuth), np.radians(elevation)
    right = np.cross(up, towards)
    towards = np.cos(a) * towards + np.sin(a) * right
    towards, up = np.cos(e) * towards + np.sin(e) * up, np.cos(e) * up - np.sin(e) * towards
    return towards, up


def camera_for(
    vertices,
    faces,
    view=DEFAULT_VIEW,
    azimuth: float = 0.0,
    elevation: float = 0.0,
) -> Camera:
    """The camera of a picture of the mesh ``(vertices, faces)``.

    Parameters
    ----------
    vertices : (n, 3) array_like of float
    faces : (m, 3) array_like of int
        The mesh, as drawn.  Never modified.
    view : str, Camera or (3, 3) array_like, default "occlusal"
        ``"occlusal"`` (the module's rule), a named view along the mesh's own
        axes (``"top"`` looks down from +z, ``"bottom"``, ``"front"`` from -y,
        ``"back"``, ``"left"`` from -x, ``"right"``, ``"iso"``), or a camera
        ``(position, focal_point, view_up)`` in mesh units, used as given.
    azimuth, elevation : float, default 0
        Turns in degrees from the view: about the picture's up direction,
        then about its horizontal direction.

    Returns
    -------
    Camera
        Looking at the centre of the mesh's extent across the picture, from
        three bounding-box diagonals away.

    Examples
    --------
    >>> from dentopo.samples import tooth
    >>> from dentopo.figures import camera_for
    >>> mesh = tooth()
    >>> towards = camera_for(mesh.vertices, mesh.faces).rotation()[2]
    >>> bool(towards[2] > 0.99)  # the sample crown points to +z: seen from +z
    True
    """
    view = check_view(view)
    azimuth, elevation = _angle(azimuth, "azimuth"), _angle(elevation, "elevation")
    vertices = np.asarray(vertices, dtype=np.float64)
    if vertices.ndim != 2 or vertices.shape[1] != 3 or not len(vertices):
        raise ValueError(f"vertices must have shape (n, 3); got {vertices.shape}")
    if isinstance(view, Camera):
        view = np.array([view.position, view.focal_point, view.up], dtype=np.float64)
    if not isinstance(view, str):
        position, focal, up = view
    if isinstance(view, str):
        if view == DEFAULT_VIEW:
            towards, up = occlusal_direction(vertices, faces)
        else:
            towards, up = (np.asarray(v, dtype=np.float64) for v in VIEWS[view])
            towards = towards / np.linalg.norm(towards)
            up = up - np.dot(up, towards) * towards
            up = up / np.linalg.norm(up)
    else:
        towards = np.asarray(position, dtype=np.float64) - focal
        if np.linalg.norm(towards) == 0:
            raise ValueError("a camera's position must differ from its focal point")
        distance = float(np.linalg.norm(towards))
        towards = towards / distance
        up = np.asarray(up, dtype=np.float64)
        up = up - np.dot(up, towards) * towards
        if np.linalg.norm(up) < 1e-12:
            raise ValueError("a camera's view-up must not lie along its line of sight")
        up = up / np.linalg.norm(up)
    name = view if isinstance(view, str) else "camera"
    towards, up = _turn(towards, up, azimuth, elevation)
    right = np.cross(up, towards)
    if isinstance(view, str):
        across, upward, depth = vertices @ right, vertices @ up, vertices @ towards
        centre = (
            0.5 * (across.min() + across.max()) * right
            + 0.5 * (upward.min() + upward.max()) * up
            + 0.5 * (depth.min() + depth.max()) * towards
        )
        distance = 3.0 * max(float(np.linalg.norm(np.ptp(vertices, axis=0))), 1e-12)
        focal = centre
    position = np.asarray(focal, dtype=np.float64) + distance * towards
    return Camera(
        tuple(float(x) for x in position),
        tuple(float(x) for x in focal),
        tuple(float(x) for x in up),
        name,
        azimuth,
        elevation,
    )
