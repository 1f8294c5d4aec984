"""How each vertex's sign (convex +, concave -) is decided.

The sign methods of ``ariaDNE`` (``_methods``): the paper's centroid test, which
uses the exact generalised winding number (``_winding``: solid angles, queries and
the public functions; ``_hierarchy``: the bounding-volume hierarchy over the
triangles; ``_strips``: long triangles and needles cut into strips), and the
curvature-measure alternatives built on trimesh's discrete mean and Gaussian
curvature measures (``_measures``).

May import: :mod:`dentopo.mesh`.  Nothing from ariadne, topography, figures,
formats, batch, study or cli.
"""

from ._measures import (
    DEFAULT_RADIUS_FACTOR,
    curvature_measure,
    curvature_measure_sign,
    measure_radius,
)
from ._methods import SIGN_METHODS, check_sign_method, convex_vertices
from ._winding import exact_winding_number, inside, winding_number

__all__ = [
    "DEFAULT_RADIUS_FACTOR",
    "SIGN_METHODS",
    "check_sign_method",
    "convex_vertices",
    "curvature_measure",
    "curvature_measure_sign",
    "exact_winding_number",
    "inside",
    "measure_radius",
    "winding_number",
]
