"""A drop-in for the published signDNE 0.1.4: change one import line, keep the script.

The published package (PyPI ``signDNE==0.1.4``) exposes one function,
``from signDNE import signDNE``, which returns an 8-tuple.  :func:`signDNE`
here has its signature (the same parameter names, order and defaults) and
returns the same tuple in the same order, computed by :func:`dentopo.ariaDNE`::

    from signDNE import signDNE          # before
    from dentopo.compat import signDNE   # after

    (local_dne, local_curvature, dne, positive_dne, negative_dne,
     surface_area, positive_surface_area, negative_surface_area) = signDNE(mesh)

What differs, and why (docs/coming-from/signdne.md has the whole story):

* **Your mesh is not modified.**  The published function cleans, centres and
  rescales the mesh it is given, in place, so that afterwards its vertices are
  those the per-vertex arrays refer to.  Here the arrays refer to the cleaned
  copy (``dentopo.ariaDNE(mesh).mesh``), in the same vertex order as the
  published package's; when cleaning removes no vertex (the usual case) that is
  your mesh's order.  When it does remove some, a ``UserWarning`` says so.
* **The sign is exact**: the weighted centroid is tested against the capped
  surface by a generalised winding number, not by a ray (the published ray test
  errs where a centroid lies within ~3e-7 of the surface, e.g. vertex 791 of the
  ``noise1`` mesh, and varies between runs there).
* **Errors**: bad input raises ``TypeError``/``ValueError`` naming the problem
  (the published raises ``NameError`` for an unknown ``distance_type`` and
  ``TypeError`` for a misshapen ``precomputed_dist``); ``distance_type`` is
  case-insensitive; ``cutoff`` must lie in [0, 1) and ``bandwidth`` in
  [1e-50, 1e50]; ``precomputed_dist`` must also be symmetric and non-negative.
* **Few neighbours**: one ``UserWarning`` with a count instead of one printed
  line per vertex.
* **More inputs**: besides a ``trimesh.Trimesh``, a path or ``(vertices,
  faces)`` is accepted, as by :func:`dentopo.ariaDNE`.

May import: :mod:`dentopo.ariadne`, :mod:`dentopo.mesh`.
"""

from __future__ import annotations

import warnings

import numpy as np
import trimesh

from .ariadne import ariaDNE

__all__ = ["PUBLISHED_RETURNS", "signDNE"]

#: The published function's return values, position by position, as our field names.
PUBLISHED_RETURNS = (
    "local_dne",
    "local_curvature",
    "dne",
    "positive_dne",
    "negative_dne",
    "surface_area",
    "positive_surface_area",
    "negative_surface_area",
)


def signDNE(  # noqa: N802 -- the published name
    mesh,
    bandwidth=0.08,
    cutoff=0,
    distance_type="Euclidean",
    precomputed_dist=None,
):
    """ariaDNE and its sign-oriented split, called and returned as signDNE 0.1.4 does.

    Parameters
    ----------
    mesh : trimesh.Trimesh, str, path-like, or (vertices, faces)
        The mesh (the published function takes a ``trimesh.Trimesh`` only).
        Never modified.
    bandwidth : float, default 0.08
        Gaussian kernel bandwidth on the unit-area scale.
    cutoff : float, default 0
        Neighbours whose kernel weight is ``<= cutoff`` are ignored; in [0, 1).
    distance_type : {"Euclidean", "Geodesic"}, default "Euclidean"
        Any case is accepted.
    precomputed_dist : (n, n) ndarray, optional
        Distances between the cleaned mesh's vertices on the unit-area scale;
        ``distance_type`` is then ignored.

    Returns
    -------
    tuple of 8
        ``local_dne`` ((n,) float64), ``local_curvature`` ((n,) float64),
        ``dne``, ``positive_dne``, ``negative_dne`` (a non-negative magnitude,
        so that ``positive_dne + negative_dne == dne``), ``surface_area``,
        ``positive_surface_area``, ``negative_surface_area`` (numpy float64;
        areas in the mesh's units squared), in this order (``PUBLISHED_RETURNS``).
        The per-vertex arrays follow the vertices of the cleaned mesh.

    Raises
    ------
    TypeError, ValueError
        For unusable meshes or parameters.

    Warns
    -----
    UserWarning
        If cleaning removed vertices of a ``trimesh.Trimesh`` input (the arrays
        are then shorter than ``mesh.vertices``), and as :func:`dentopo.ariaDNE`
        warns.

    Examples
    --------
    >>> import trimesh
    >>> from dentopo.compat import signDNE
    >>> out = signDNE(trimesh.creation.icosphere(subdivisions=3))
    >>> len(out), float(out[4])
    (8, 0.0)
    """
    result = ariaDNE(
        mesh,
        bandwidth=bandwidth,
        cutoff=cutoff,
        distance_type=distance_type,
        precomputed_dist=precomputed_dist,
    )
    if isinstance(mesh, trimesh.Trimesh) and len(mesh.vertices) != result.vertices:
        warnings.warn(
            f"cleaning the mesh left {result.vertices} of its {len(mesh.vertices)} vertices: "
            "the per-vertex arrays follow the cleaned mesh, dentopo.ariaDNE(mesh).mesh (the "
            "published signDNE wrote it back into your mesh; dentopo leaves your mesh as it was)",
            UserWarning,
            stacklevel=2,
        )
    return tuple(
        getattr(result, name) if name.startswith("local_") else np.float64(getattr(result, name))
        for name in PUBLISHED_RETURNS
    )
