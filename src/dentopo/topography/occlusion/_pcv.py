"""PCV: the share of the sky each vertex sees, and the crown's mean (Berthaume et al. 2019).

The studies measured PCV with CloudCompare's qPCV plugin (after ShadeVis): light from an
equal-area set of directions, a vertex counted lit from a direction when the depth buffer
seen from it does not hide the vertex; a vertex's PCV is its lit count over the number of
directions, the crown's the mean over vertices.  ``method="cloudcompare"`` follows that
depth buffer (:mod:`._depth`); ``method="exact"`` casts one ray per vertex and direction
(:mod:`._rays`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import trimesh

from ..._html_repr import result_html
from ...mesh import as_arrays, vertex_areas
from .._parameters import check_int, check_pcv_options
from ..surface._molar import Surface
from ..surface._orientation import Orientation, check_orient, orient_vertices
from ._depth import MAX_RESOLUTION
from ._directions import light_directions

#: Scalar fields, in the order of output tables.
PCV_FIELDS = ("pcv", "pcv_area")

#: The smallest depth-buffer side accepted.
MIN_RESOLUTION = 16


class PCVParameterError(ValueError):
    """An unusable parameter of :func:`pcv` (named in the message)."""


@dataclass(frozen=True)
class PCVResult:
    """PCV of one mesh.

    Attributes
    ----------
    pcv : float
        Mean of ``vertex_pcv`` over the vertices (CloudCompare's crown value).
    pcv_area : float
        Mean of ``vertex_pcv`` weighted by each vertex's area (a third of its faces').
    vertex_pcv : (n,) float64
        Lit count over ``n_directions``, in [0, 1], vertices in the order given.
    face_pcv : (m,) float64
        Mean of each face's three corners (for pictures).
    directions : (k, 3) float64
        The unit vectors towards the light that were used.
    rays : int
        The number of rays asked for.
    n_directions : int
        How many directions were used (236 for 256 rays over the northern hemisphere).
    hemisphere : bool
    method : str
    resolution : int
        The depth buffer's side, pixels (``method="cloudcompare"``).
    orientation : Orientation
        Which way the crown points, and whether it was turned before measuring.
    mesh : trimesh.Trimesh
        The mesh the per-vertex and per-face arrays refer to, as measured (turned where
        ``orientation`` says so; a copy).
    """

    pcv: float
    pcv_area: float
    vertex_pcv: np.ndarray = field(repr=False, compare=False)
    face_pcv: np.ndarray = field(repr=False, compare=False)
    directions: np.ndarray = field(repr=False, compare=False)
    rays: int = 256
    n_directions: int = 0
    hemisphere: bool = True
    method: str = "cloudcompare"
    resolution: int = 1024
    orientation: Orientation | None = field(default=None, compare=False)
    mesh: trimesh.Trimesh | None = field(default=None, repr=False, compare=False)

    def __post_init__(self):
        for name in ("vertex_pcv", "face_pcv", "directions"):
            getattr(self, name).flags.writeable = False

    def to_dict(self) -> dict:
        """The scalar table fields as a plain dict (``{"pcv": ..., "pcv_area": ...}``)."""
        return {name: getattr(self, name) for name in PCV_FIELDS}

    def _repr_html_(self) -> str:
        """A compact table for notebooks: values, settings, arrays summarised."""
        return result_html(self, histogram="vertex_pcv")


def pcv(
    mesh,
    *,
    rays: int = 256,
    hemisphere: bool = True,
    method: str = "cloudcompare",
    orient: str = "auto",
    resolution: int = 1024,
) -> PCVResult:
    """PCV (portion de ciel visible): the share of sky directions that light each vertex.

    1. **Directions.** CloudCompare's: the centres of an equal-area partition of the sphere
       into `rays` regions after Leopardi's; with `hemisphere` (CloudCompare's "northern
       hemisphere only"), ``2 * rays`` regions and the centres strictly north of the
       equator (236 for 256).  At 256 over the hemisphere, CloudCompare's own longitudes
       (measured); elsewhere Leopardi's (:mod:`dentopo.topography.occlusion._directions`).
    2. **Lit.** ``"cloudcompare"``: an orthographic depth buffer of `resolution` pixels a
       side per direction (:mod:`dentopo.topography.occlusion._depth`); ``"exact"``: a ray
       from each vertex towards each direction (needs the ``embreex`` package).
    3. **Means.** ``vertex_pcv`` = lit count / directions; ``pcv`` their mean,
       ``pcv_area`` their mean weighted by a third of each vertex's faces' areas.

    The mesh is measured as given (no vertex merged or dropped when given as arrays or a
    Trimesh; a file is read by :func:`dentopo.mesh.load_mesh`); the crown is assumed to
    point to +z: ``orient="auto"`` turns one pointing to -z first, by ``(x, -y, -z)``.

    Raises
    ------
    PCVParameterError (a ValueError)
        `rays` not an integer >= 1, `resolution` not an integer in [16, 32768], an unknown
        `method`, `hemisphere` not a bool; ValueError, TypeError for an unusable mesh
        (one without faces included) or `orient`.
    """
    try:  # the batch's checks, one error class for every parameter of this function
        rays, hemisphere, method = check_pcv_options(rays, hemisphere, method)
        resolution = check_int("resolution", resolution, low=MIN_RESOLUTION, high=MAX_RESOLUTION)
    except (TypeError, ValueError) as error:
        raise PCVParameterError(str(error)) from None
    orient = check_orient(orient)
    if isinstance(mesh, Surface):
        vertices, faces = np.array(mesh.vertices), np.array(mesh.faces)
    else:
        vertices, faces = as_arrays(mesh)
    if len(faces) == 0:
        raise ValueError("the mesh has no faces: PCV needs a triangle mesh")
    vertices, orientation = orient_vertices(vertices, faces, orient)
    directions = light_directions(rays, hemisphere)
    if method == "exact":
        from ._rays import lit_counts_rays

        lit = lit_counts_rays(vertices, faces, directions)
    else:
        from ._depth import lit_counts_depth_buffer

        lit = lit_counts_depth_buffer(vertices, faces, directions, resolution)
    vertex_pcv = lit / float(len(directions))
    weight = vertex_areas(vertices, faces)
    total = float(weight.sum())
    if not total > 0:
        raise ValueError("the mesh has no face of non-zero area: PCV needs a surface")
    return PCVResult(
        pcv=float(vertex_pcv.mean()),
        pcv_area=float(np.dot(weight, vertex_pcv) / total),
        vertex_pcv=vertex_pcv,
        face_pcv=vertex_pcv[faces].mean(axis=1),
        directions=directions,
        rays=rays,
        n_directions=len(directions),
        hemisphere=hemisphere,
        method=method,
        resolution=resolution,
        orientation=orientation,
        mesh=trimesh.Trimesh(vertices.copy(), faces.copy(), process=False),
    )
