"""The crown's footprint area as doolkit 1.42.2's ``area2d`` computes it: concave or convex.

The footprint is the outline of the vertices' x-y positions, the crown seen
from above along z.  doolkit draws it two ways:

- **concave** (``area2d(mesh, method = "concave")``, doolkit's default and the
  one its relief indices use): mapbox's concaveman hull (concavity 2, no
  length threshold) of the unique x-y points, shifted so that both minima are
  0 and **rounded to 4 decimals**, because doolkit hands them to the R package
  concaveman, which writes them to the JavaScript library with
  ``jsonlite::toJSON`` at its default ``digits = 4``;
- **convex** (``method = "convex"``): the convex hull of the unique x-y points
  as they are (``grDevices::chull``).

The area is the shoelace area of the hull's ring.  The concave hull is this
package's port of the JavaScript (:mod:`._concaveman`), which returns the same
ring point for point, so the area is doolkit's to rounding in the last bits.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..._html_repr import result_html
from ..._jit import njit
from .. import _units
from ..surface._molar import prepare_surface
from ..surface._orientation import Orientation, check_orient
from . import _concaveman, _jsmath

#: The hulls :func:`footprint_area` draws.
HULLS = ("concave", "convex")

#: The table field of each hull (doolkit's reference column names).
FOOTPRINT_FIELDS = {"concave": "area2d", "convex": "area2d_convex"}

#: jsonlite's default ``digits`` in ``toJSON``, which R's concaveman uses.
JSON_DIGITS = 4


@dataclass(frozen=True)
class FootprintResult:
    """The footprint area of one mesh, as doolkit's ``area2d`` computes it.

    Attributes
    ----------
    area : float
        Footprint area, mesh units squared: the shoelace area of the hull's
        ring (for the concave hull, of the ring on the shifted, 4-decimal
        coordinates the hull was drawn on).
    hull : {"concave", "convex"}
        Which outline.
    vertices, faces : int
        Vertex and face counts of the cleaned mesh.
    points : int
        Distinct x-y positions among the vertices (the points the hull is
        drawn around).
    ring : (k, 2) float64
        The ring's points in the mesh's own units and position (x, y of the
        vertices, not shifted, not rounded), in the hull's order, not closed
        (the first point is not repeated), clockwise seen from +z (x to the
        right, y up).  Concave: concaveman's order, starting where concaveman
        starts.
    ring_vertices : (k,) int64
        For each ring point, the first vertex of the cleaned mesh at that x-y
        position.
    orientation : Orientation or None
        What was found of the crown's orientation and whether it was turned
        (``orient="auto"``); None with ``orient="as-is"``, which does not look.
    rounding : float
        How much doolkit's rounding of the coordinates (4 decimals, concave
        hull) can move `area`, relative: the ring's length times the largest
        distance a point moved, over the area (first order; 0 for the convex
        hull, infinite for a footprint of no area).  Large where the crown is
        small in its unit: doolkit assumes millimetres.
    """

    area: float
    hull: str
    vertices: int
    faces: int
    points: int
    ring: np.ndarray = field(repr=False, compare=False)
    ring_vertices: np.ndarray = field(repr=False, compare=False)
    orientation: Orientation | None = field(default=None, compare=False)
    rounding: float = field(default=0.0, compare=False)

    def to_dict(self) -> dict:
        """The table field: ``{"area2d": area}`` (concave) or ``{"area2d_convex": area}``."""
        return {FOOTPRINT_FIELDS[self.hull]: self.area}

    def _repr_html_(self) -> str:
        """A compact table for notebooks: values, settings, arrays summarised."""
        return result_html(self)


def check_hull(hull) -> str:
    """The footprint's hull: ``"concave"`` or ``"convex"``."""
    if not isinstance(hull, str):
        raise TypeError(f"hull must be a string; got {type(hull).__name__}")
    if hull not in HULLS:
        raise ValueError(f"hull must be one of {HULLS}; got {hull!r}")
    return hull


def unique_xy(vertices: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The distinct x-y positions of the vertices, in order of first appearance.

    Returns ``(xy, first)``: the (p, 2) positions and the index of the first
    vertex at each.  Positions are equal when both coordinates are equal
    (``-0.0`` equals ``0.0``), as R's ``unique`` on the coordinate rows.
    """
    xy = np.ascontiguousarray(vertices[:, :2], dtype=np.float64) + 0.0  # -0.0 -> 0.0
    bits = xy.view(np.int64)  # equal bits <=> equal values (finite, no -0.0)
    keep = np.empty(len(xy), dtype=np.int64)
    kept = _first_of_each(np.ascontiguousarray(bits[:, 0]), np.ascontiguousarray(bits[:, 1]), keep)
    first = keep[:kept].copy()
    return xy[first], first


@njit(cache=True)
def _first_of_each(xb, yb, keep):
    """Indices of the first occurrence of each (xb, yb) pair, in order, into `keep` (a hash
    table): their count."""
    n = xb.shape[0]
    size = 1
    while size < 2 * n:
        size *= 2
    table = np.full(size, -1, dtype=np.int64)
    kept = 0
    for i in range(n):
        h = (xb[i] * -7046029254386353131) ^ (yb[i] * -4417276706812531889)
        slot = (h ^ (h >> 29)) & (size - 1)
        while True:
            j = table[slot]
            if j < 0:
                table[slot] = i
                keep[kept] = i
                kept += 1
                break
            if xb[j] == xb[i] and yb[j] == yb[i]:
                break
            slot = (slot + 1) & (size - 1)
    return kept


def json_digits(values: np.ndarray, digits: int = JSON_DIGITS) -> np.ndarray:
    """The numbers ``jsonlite::toJSON(values, digits = 4)`` writes, as JavaScript reads them back.

    jsonlite (1.8) writes a double ``v`` with ``1e-5 < |v| < 2**31 - 1`` with
    ``modp_dtoa2``: ``whole = trunc(|v|)``, ``t = (|v| - whole) * 10**digits``
    in double precision, ``frac = trunc(t)``, one more when ``t - frac > 0.5``
    (carrying into ``whole`` at ``10**digits``) or when ``t - frac == 0.5`` and
    ``frac`` is odd or 0, then ``whole.frac`` with trailing zeros dropped.  This
    equals ``sprintf("%.4f")`` except where the product ``t`` lands on a half
    (``sprintf`` rounds the exact binary value).  Quirks kept:

    - a half-way ``frac = 9999`` becomes 10000 without the carry and is written
      ``whole.1`` (0.99995... can come back as ``whole + 0.1``);
    - ``|v| <= 1e-5``, and ``|v| >= 2**31 - 1``, are written by
      ``sprintf("%.*g")`` with ``ceil(min(17, max(1, log10|v|) + digits))``
      significant digits: ``1e-05`` stays ``1e-05`` and ``2.5e-06`` stays
      ``2.5e-06`` (five significant digits), while ``3e-05`` (above ``1e-5``)
      is written ``0``;
    - 0 is written ``0``.

    The decimal text is then parsed as the nearest double (JavaScript's
    ``JSON.parse``), which is ``(whole * 10**digits + frac) / 10**digits``
    computed in double precision (both exact, the quotient correctly rounded).
    """
    if isinstance(digits, bool) or not isinstance(digits, int) or not 0 < digits < 10:
        raise ValueError(f"digits must be an integer from 1 to 9; got {digits!r}")
    v = np.ascontiguousarray(values, dtype=np.float64)
    out = np.empty_like(v)
    special = np.zeros(v.size, dtype=np.bool_)
    _json_digits(v.ravel(), float(10**digits), out.ravel(), special)
    for i in np.flatnonzero(special).tolist():  # sprintf("%.*g"): tiny, huge or zero
        x = float(v.flat[i])
        if not math.isfinite(x):
            raise ValueError("coordinates must be finite")
        if x == 0.0:
            out.flat[i] = x
            continue
        width = math.ceil(min(17.0, max(1.0, math.log10(abs(x))) + digits))
        out.flat[i] = float(f"{x:.{width}g}")
    return out


@njit(cache=True)
def _json_digits(v, scale, out, special):
    """modp_dtoa2's rounding of v into out (see json_digits); `special` True where sprintf
    writes instead."""
    for i in range(v.shape[0]):
        x = v[i]
        a = abs(x)
        if not (a > 1e-5 and a < 2147483647.0):
            if x == 0.0:
                out[i] = x  # written "0" (or "-0")
            else:
                special[i] = True
            continue
        whole = float(int(a))  # a < 2**31
        t = (a - whole) * scale
        frac = math.floor(t)
        diff = t - frac
        if diff > 0.5:
            frac += 1.0
            if frac >= scale:
                frac = 0.0
                whole += 1.0
        elif diff == 0.5 and (frac == 0.0 or int(frac) & 1 == 1):
            frac += 1.0
        if frac >= scale:  # a half-way 9...9 plus 1, not carried: written "whole.1"
            value = (whole * 10.0 + 1.0) / 10.0
        else:
            value = (whole * scale + frac) / scale
        out[i] = -value if x < 0.0 else value


def shoelace(ring: np.ndarray) -> float:
    """Unsigned area of the polygon `ring` ((k, 2), not closed), fanned from its first point."""
    if len(ring) < 3:
        return 0.0
    d = ring[1:] - ring[0]
    return abs(float(np.sum(d[:-1, 0] * d[1:, 1] - d[1:, 0] * d[:-1, 1]))) / 2.0


def _check_points(points) -> np.ndarray:
    try:
        p = np.array(points, dtype=np.float64, copy=True)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"points must be numeric: {exc}") from exc
    if p.ndim != 2 or p.shape[1] != 2:
        raise ValueError(f"points must have shape (n, 2); got {p.shape}")
    if len(p) == 0:
        raise ValueError("points is empty")
    if not np.all(np.isfinite(p)):
        raise ValueError("points must be finite")
    return np.ascontiguousarray(p + 0.0)


def _check_nonnegative(name: str, value) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise TypeError(f"{name} must be a real number; got {type(value).__name__}")
    value = float(value)
    if not value >= 0:  # NaN too
        raise ValueError(f"{name} must be at least 0; got {value!r}")
    return value


def concave_hull(points, *, concavity: float = 2.0, length_threshold: float = 0.0) -> np.ndarray:
    """mapbox concaveman's concave hull of 2D points, as indices into `points`.

    The JavaScript library concaveman 1.1 (Agafonkin, Mapbox), ported so that
    it returns the same ring, point for point, ties included
    (:mod:`dentopo.topography.footprint._concaveman`).  From the convex hull, each edge
    in turn, first in first out, is bent inward through the point left
    inside that is nearest to it, when that point is nearer to this edge than
    to the two neighbouring edges, joining it crosses no edge of the outline,
    and its distance to the nearer end is at most the edge's length divided
    by `concavity`.  The points are used as given (no rounding): doolkit's
    rounding is :func:`json_digits`, applied by :func:`footprint_area`.

    Parameters
    ----------
    points : (n, 2) array_like
        Finite x-y positions, n >= 1.  Equal positions are distinct points, as
        in the JavaScript.  Never modified.
    concavity : float, default 2
        At least 0; larger gives a simpler outline, ``inf`` the convex hull,
        values below 1 wild ones (concaveman's convention).
    length_threshold : float, default 0
        At least 0: edges shorter than this are not bent.

    Returns
    -------
    (k,) int64
        The ring's point indices, in concaveman's order (clockwise with x to
        the right and y up, starting at the last point of its convex hull), without
        repeating the first at the end (concaveman's JavaScript returns the
        ring closed).  ``points[concave_hull(points)]`` is the ring.

    Raises
    ------
    TypeError, ValueError
        For unusable points or parameters.

    References
    ----------
    Agafonkin V. concaveman: a very fast 2D concave hull algorithm in
    JavaScript. https://github.com/mapbox/concaveman (ISC licence).
    Park J.-S., Oh S.-J. (2012). A new concave hull algorithm and concaveness
    measure for n-dimensional datasets. J Inf Sci Eng 28, 587-600.

    Examples
    --------
    >>> square = [(0, 0), (1, 0), (1, 1), (0, 1), (0.5, 0.5)]
    >>> sorted(concave_hull(square).tolist())
    [0, 1, 2, 3]
    """
    p = _check_points(points)
    concavity = _check_nonnegative("concavity", concavity)
    length_threshold = _check_nonnegative("length_threshold", length_threshold)
    return _concave_ring(p, concavity, length_threshold)


def convex_hull(points) -> np.ndarray:
    """Convex hull of 2D points as indices into `points`, clockwise (x right, y up), not closed.

    Points on the hull's edges between its corners are left out; orientation
    tests are exact.  Fewer than three distinct corners give one or two
    indices.
    """
    return _convex_ring(_check_points(points))


def _concave_ring(p: np.ndarray, concavity: float, length_threshold: float) -> np.ndarray:
    """concaveman's ring as indices into `p`, not closed (the JavaScript repeats its first)."""
    out = np.empty(2 * len(p) + 3, dtype=np.int64)  # room for the repeats of tiny inputs
    size = _concaveman.concaveman_ring(p, concavity, length_threshold, out)
    return out[: size - 1].copy()


def _convex_ring(p: np.ndarray) -> np.ndarray:
    out = np.empty(2 * len(p) + 3, dtype=np.int64)  # coincident points may come twice
    ring = out[: _jsmath.fast_convex_hull(p, out)]
    # a point can come twice only when all points coincide: keep it once
    keep = ring != np.roll(ring, 1)
    keep[0] = True
    return ring[keep]


def footprint_area(mesh, *, hull: str = "concave", orient: str = "auto") -> FootprintResult:
    """Footprint area as doolkit 1.42.2's ``area2d`` computes it.

    1. **Points.** The x-y positions of the cleaned mesh's vertices (molaR's
       cleaning, as every metric here: faces of zero area dropped, then
       unused vertices; doolkit's reader keeps a vertex whose faces all have
       zero area, which only matters if it sticks out of the outline), each
       distinct position once, in order of first appearance
       (:func:`unique_xy`).
    2. **Concave** (doolkit's default): the points shifted so that the least x
       and the least y are 0, rounded as ``jsonlite::toJSON(digits = 4)``
       writes them (:func:`json_digits`: ``sprintf("%.4f")`` on every shared
       mesh), then concaveman's hull with concavity 2 and no length threshold
       (:func:`concave_hull`), the JavaScript library doolkit runs; the area
       is the shoelace area of that ring on those rounded coordinates.
    3. **Convex**: the convex hull of the points as they are (not shifted,
       not rounded; ``grDevices::chull``), shoelace area.

    The concave area depends on where the mesh lies only through the rounding
    (the shift removes translation) and on the order of the vertices only
    where concaveman meets exactly equal distances; the convex area on
    neither.  Both depend on which axis is z: doolkit assumes the occlusal
    plane is x-y.  Turning a crown upside down (``orient="auto"``) mirrors
    the footprint, which changes the concave outline slightly.

    Parameters
    ----------
    mesh : trimesh.Trimesh, str, path-like, (vertices, faces), or Surface
        The crown, or one prepared once for several metrics
        (:func:`dentopo.topography.prepare_surface`).  Never modified.
    hull : {"concave", "convex"}, default "concave"
        Which outline (doolkit's ``method``).
    orient : {"auto", "as-is"}, default "auto"
        ``"as-is"`` (doolkit's behaviour) projects the mesh as it lies, without
        looking at its orientation; ``"auto"`` (the default) first turns a crown pointing to
        -z (see :func:`dentopo.topography.find_orientation`).

    Returns
    -------
    FootprintResult

    Raises
    ------
    TypeError, ValueError
        For an unusable mesh or parameter.

    Warns
    -----
    UnitWarning
        When doolkit's rounding can move the concave area by more than 0.5 %
        (``rounding``): a crown small in its unit (doolkit assumes millimetres).

    References
    ----------
    Thiery G., Gillet G., Lazzari V., Merceron G., Guy F. (2017). Was
    Mesopithecus a seasonal eater? Insight from dental topography. Am J Phys
    Anthropol 163, 702-712 (doolkit's relief indices on this footprint).

    Examples
    --------
    >>> import trimesh
    >>> from dentopo.topography import footprint_area
    >>> box = trimesh.creation.box(extents=(2.0, 3.0, 1.0))
    >>> footprint_area(box).area, footprint_area(box, hull="convex").area
    (6.0, 6.0)
    """
    result = footprint_result(mesh, hull, orient)
    if result.rounding > _units.MATERIAL:
        _units.warn("footprint", rounding_text(result, "area2d"))
    return result


def footprint_result(mesh, hull: str, orient: str) -> FootprintResult:
    """:func:`footprint_area` without its warning (for the relief indices, which say their own)."""
    hull = check_hull(hull)
    orient = check_orient(orient)
    surface = prepare_surface(mesh, orient=None if orient == "as-is" else orient)
    key = ("footprint", hull)
    return surface._cached(key, lambda: _footprint(surface, hull))


def rounding_text(result: FootprintResult, what: str) -> str:
    """What doolkit's 4-decimal rounding does to `what` on this footprint, for a warning."""
    size = float(np.ptp(result.ring, axis=0).max()) if len(result.ring) else 0.0
    if math.isinf(result.rounding):
        moved = "gives it no area"
    else:
        moved = f"can move {what} by up to {result.rounding:.2%}"
    return (
        f"doolkit draws the footprint on coordinates rounded to {JSON_DIGITS} decimals, which "
        f"{moved} on this crown ({size:.3g} units across)"
    )


def _rounding(shifted: np.ndarray, rounded: np.ndarray, ring: np.ndarray, area: float) -> float:
    """First-order bound of the relative change of the ring's area due to the rounding."""
    moved = np.abs(rounded - shifted).max(axis=0) if len(shifted) else np.zeros(2)
    step = float(math.hypot(moved[0], moved[1]))
    if step == 0.0:
        return 0.0
    if not area > 0.0:
        return math.inf
    points = shifted[ring]
    length = float(np.hypot(*(np.roll(points, -1, axis=0) - points).T).sum())
    return length * step / area


def _footprint(surface, hull: str) -> FootprintResult:
    xy, first = surface._cached(("footprint", "xy"), lambda: unique_xy(surface.vertices))
    rounding = 0.0
    if hull == "concave":
        shifted = xy - xy.min(axis=0)
        rounded = json_digits(shifted)
        ring = _concave_ring(rounded, 2.0, 0.0)
        area = shoelace(rounded[ring])
        rounding = _rounding(shifted, rounded, ring, area)
    else:
        ring = _convex_ring(xy)
        area = shoelace(xy[ring])
    ring_xy = xy[ring]
    ring_vertices = first[ring]
    ring_xy.flags.writeable = False
    ring_vertices.flags.writeable = False
    return FootprintResult(
        area=area,
        hull=hull,
        vertices=len(surface.vertices),
        faces=len(surface.faces),
        points=len(xy),
        ring=ring_xy,
        ring_vertices=ring_vertices,
        orientation=surface.orientation,
        rounding=rounding,
    )
