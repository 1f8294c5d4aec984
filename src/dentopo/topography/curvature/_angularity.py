"""Angularity as doolkit 1.42.2's ``angularity`` computes it: the slope of the slope.

Each vertex's slope (the angle of its float32 VCG vertex normal from the z
axis, folded into [0, 90] degrees) replaces the vertex's z coordinate; the
angularity of a face is then its slope on that new surface.  x and y stay
in mesh units while z becomes degrees, so the value is **scale dependent by
design** (doolkit's definition): shrinking a crown steepens the new surface
(noise1 and noise2, about 8 times smaller than normal.ply, give about 89.9
against 89.0).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import trimesh

from ..._html_repr import result_html
from ..._jit import njit
from .._lazy import LazyMesh
from ..surface import _vcg
from ..surface._molar import prepare_surface

#: Scalar fields, in the order of output tables.
ANGULARITY_FIELDS = ("angularity_mean",)


@dataclass(frozen=True)
class AngularityResult:
    """doolkit's angularity for one mesh.

    Attributes
    ----------
    angularity_mean : float
        Mean of ``face_angularity`` over all faces (unweighted).
    vertices, faces : int
        Vertex and face counts of the mesh used.
    vertex_slope : (n,) float64
        Each vertex's slope in degrees, [0, 90]: the new surface's z.
    face_angularity : (m,) float64
        Each face's slope on the new surface, degrees, [0, 90].
    mesh : trimesh.Trimesh
        The mesh the per-face arrays refer to (a copy, in its own units).
    """

    angularity_mean: float
    vertices: int
    faces: int
    vertex_slope: np.ndarray = field(repr=False, compare=False)
    face_angularity: np.ndarray = field(repr=False, compare=False)
    mesh: trimesh.Trimesh = field(default=LazyMesh(), repr=False, compare=False)

    def to_dict(self) -> dict:
        """The scalar table fields as a plain dict (``ANGULARITY_FIELDS``)."""
        return {name: getattr(self, name) for name in ANGULARITY_FIELDS}

    def _repr_html_(self) -> str:
        """A compact table for notebooks: values, settings, arrays summarised."""
        return result_html(self, histogram="face_angularity")


@njit(cache=True, inline="always")
def _slope(nx, ny, nz):  # pragma: no cover
    """doolkit's slope of a normal: ``90 - acos(sqrt(nx^2 + ny^2) / |n|)`` in degrees (0/0: NaN)."""
    horizontal = math.sqrt(nx * nx + ny * ny)
    length = math.sqrt(nx * nx + ny * ny + nz * nz)
    if length == 0.0:
        return math.nan
    return 90.0 - math.acos(min(horizontal / length, 1.0)) * 180.0 / math.pi


@njit(cache=True)
def _angularity(v32, faces, normals32, vertex_slope, face_slope):  # pragma: no cover
    n = v32.shape[0]
    z = np.empty(n)
    for w in range(n):
        z[w] = _slope(
            np.float64(normals32[w, 0]), np.float64(normals32[w, 1]), np.float64(normals32[w, 2])
        )
        vertex_slope[w] = z[w]
    for f in range(faces.shape[0]):
        i, j, k = faces[f, 0], faces[f, 1], faces[f, 2]
        x0, y0 = np.float64(v32[i, 0]), np.float64(v32[i, 1])
        ax, ay, az = np.float64(v32[j, 0]) - x0, np.float64(v32[j, 1]) - y0, z[j] - z[i]
        bx, by, bz = np.float64(v32[k, 0]) - x0, np.float64(v32[k, 1]) - y0, z[k] - z[i]
        cx = ay * bz - az * by
        cy = az * bx - ax * bz
        cz = ax * by - ay * bx
        length = math.sqrt(cx * cx + cy * cy + cz * cz)
        if length == 0.0:
            face_slope[f] = math.nan  # a zero normal, as Morpho leaves it: doolkit's NaN
        else:
            face_slope[f] = _slope(cx / length, cy / length, cz / length)


def angularity(mesh) -> AngularityResult:
    """Angularity, as doolkit 1.42.2's ``angularity(mesh, ratio = FALSE)`` computes it.

    1. **Vertex normals** as doolkit's mesh carries them: float32 VCG normals
       (area-weighted sums of the face cross products, normalised) of the
       float32 coordinates.
    2. **Vertex slope** ``90 - acos(sqrt(nx^2 + ny^2) / |n|)`` in degrees, in
       double precision: 0 for a horizontal surface, 90 for a vertical one.
    3. Each vertex's **z is replaced** by its slope (x, y unchanged).
    4. **Face angularity**: the same slope formula on each face's normal of
       the new surface, ``(v1 - v0) x (v2 - v0)`` in double precision.
    5. ``angularity_mean`` is the plain mean over faces.

    Orientation-free (slopes are folded: turning the crown over changes
    nothing) and independent of translation and vertex or face order, but
    **scale dependent**: x and y are lengths while the new z is in degrees,
    so doolkit's value is that of the crown in millimetres, its unit (a batch
    given the mesh's unit measures it so: :mod:`dentopo.topography._units`).

    Parameters
    ----------
    mesh : trimesh.Trimesh, str, path-like, (vertices, faces), or Surface
        Never modified.  Faces of zero area and unused vertices are dropped
        first (the shared reader).

    Returns
    -------
    AngularityResult

    Raises
    ------
    TypeError, ValueError
        For an unusable mesh; ValueError when a face of the new surface has
        no area (doolkit's mean is NaN then: a vertical wall, whose faces'
        footprint is a line and whose vertices all have slope 90).

    References
    ----------
    Thiery G., Guy F., Lazzari V. (2019-). doolkit: a toolkit for dental
    topography (R package), version 1.42.2.

    Examples
    --------
    >>> import numpy as np
    >>> from dentopo.topography import angularity
    >>> x, y = np.meshgrid(np.linspace(0, 1, 5), np.linspace(0, 1, 5))
    >>> vertices = np.column_stack([x.ravel(), y.ravel(), 0.5 * x.ravel()])  # a tilted plane
    >>> faces = np.array([[i, i + 1, i + 6] for i in range(19) if i % 5 != 4]
    ...                  + [[i, i + 6, i + 5] for i in range(19) if i % 5 != 4])
    >>> angularity((vertices, faces)).angularity_mean  # constant slope: a flat new surface
    0.0
    """
    surface = prepare_surface(mesh)
    faces = surface.faces
    v32, normals32 = _vcg.surface_normals32(surface)
    vertex_slope = np.empty(len(v32))
    per_face = np.empty(len(faces))
    _angularity(v32, faces, normals32, vertex_slope, per_face)
    flat = int(np.isnan(per_face).sum())
    if flat:
        raise ValueError(
            f"angularity is undefined: {flat} of {len(faces)} faces have no area on doolkit's "
            "slope surface (x, y and each vertex's slope as z), where doolkit gives NaN: their "
            "x-y footprint is a line and their vertices' slopes are equal (a vertical wall)"
        )
    return AngularityResult(
        angularity_mean=float(per_face.mean()),
        vertices=len(surface.vertices),
        faces=len(faces),
        vertex_slope=vertex_slope,
        face_angularity=per_face,
        mesh=surface.mesh_later(),
    )
