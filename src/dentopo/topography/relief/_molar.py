"""Relief index (RFI) as molaR 6.0 computes it, with its alpha-convex-hull footprint.

RFI compares a crown's 3D surface area with the area of its footprint, the
outline of the crown seen from above (+z): ``RFI = ln(sqrt(area_3d) /
sqrt(area_2d))`` (Boyer 2008).  molaR draws the footprint as the R package
``alphahull``'s alpha-convex hull (``ahull``) of the vertices' x-y positions,
a list of circular arcs (:mod:`._alphahull`), tests that list for two faults
(S, structural; F, a fan from the vertices' mean that is not star-shaped) and
sums triangles fanned from the mean over the arcs.  Every convention below is
molaR's, the odd ones included, because matching its numbers requires them.

molaR's search for an alpha (``findAlpha``) is a walk of at most 99 steps
whose floating-point arithmetic shows in the alpha it reports; it is walked
here step by step (:func:`walk`), one hull per step.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import trimesh

from ..._html_repr import result_html
from .._lazy import LazyMesh
from .._parameters import check_alpha, check_find_alpha
from ..footprint._alphahull import FAN_INSIDE, FAN_UNDEFINED, AlphaHull, Arcs, chain
from ..surface._molar import molar_face_areas, molar_scale, prepare_surface
from ..surface._orientation import Orientation, check_orient

#: Scalar fields, in the order of output tables.
RFI_FIELDS = ("rfi", "area_3d", "area_2d", "alpha")

#: molaR's search (:func:`walk`): the steps up after S and F, back down after an
#: S that overshoots the last success, down after OK; and its budget of hulls.
UP_STEP = 0.01
BACK_STEP = 0.009
FINE_STEP = 0.001
DOWN_STEP = 0.005
MAX_EVALUATIONS = 99

#: What molaR's failures add: the relief index that needs no alpha.
PROJECTED_HINT = (
    "the relief index on the exact projected footprint needs no alpha and exists for every "
    "open crown: use metrics='rfi_projected' (dentopo.topography.projected_rfi)"
)

#: The verdicts on a hull (see :func:`rfi`).
STRUCTURAL, FAN, OK = "S", "F", "OK"


class AlphaAdjustmentError(ValueError):
    """The alpha-convex hull's arcs do not make a usable outline at this alpha (molaR's S).

    molaR's "alpha adjustment required": some point starts two arcs (the hull
    pinches there) or some point of the hull's edge is on no arc (an isolated
    point, a point joined only by dangling edges, or a pinch cut off on both
    sides).  Try ``find_alpha=True`` (molaR's ``findAlpha``) or another
    ``alpha``; or the relief index on the exact projected footprint
    (:func:`dentopo.topography.projected_rfi`, batch metric ``rfi_projected``),
    which needs no alpha and exists for every open crown.
    """


class FootprintWarning(UserWarning):
    """RFI's 2D area may be over-estimated, or molaR's search for an alpha failed.

    The 2D area is a fan of triangles from the vertices' mean over the hull's
    arcs; when some arc end lies inside another arc's triangle (molaR's F) the
    footprint is not star-shaped from the mean and the fan covers more than
    the footprint.  molaR warns and keeps the number; so does :func:`rfi`, and
    the result's ``warning`` says so.
    """


class FootprintError(ValueError):
    """molaR stops while measuring the footprint at this alpha, so RFI has no value (NA).

    Either the fan test meets a missing value (the vertices' mean lies on the
    line through an arc's two ends, so the barycentric formula divides 0 by
    0), or the hull's boundary has points of its own (arcs trimmed at a
    pinch), whose indices are past the list of footprint points that the 2D
    area reads ("subscript out of bounds").
    """


@dataclass(frozen=True)
class RFIResult:
    """Relief index and its parts for one mesh, as molaR's ``RFI`` reports them.

    Attributes
    ----------
    rfi : float
        ``ln(sqrt(area_3d) / sqrt(area_2d))``.  Invariant to uniform scale.
    area_3d : float
        Total face area, mesh units squared, computed as molaR's reader
        computes it (single precision per face, see :func:`rfi`).
    area_2d : float
        Footprint area, mesh units squared: the sum of the triangles fanned
        from the vertices' mean over the hull's arcs (each by the Gram form
        of its two end points).
    alpha : float
        The alpha used: the radius of the empty discs of the alpha-convex
        hull, in molaR's rescaled units (centroid size 100).  With
        ``find_alpha`` it is the alpha molaR's search ends on, bit for bit (or
        the start alpha when the search fails, as in molaR).
    find_alpha : bool
        Whether ``alpha`` was searched for.
    vertices, faces : int
        Vertex and face counts of the cleaned mesh.
    footprint : (k, 2, 2) float
        The hull's arcs as x-y coordinates of their two end points, in the
        mesh's own units and position, chained head to tail around each loop
        (clockwise around the footprint; for drawing the outline over a top
        view, the arcs drawn as chords).
    mesh : trimesh.Trimesh
        The cleaned mesh (a private copy; turned to +z if ``orient="auto"``
        turned it, and the footprint with it).
    orientation : Orientation
        Which way the crown points (``+z``, ``-z`` or ``undetermined``) and
        whether it was turned before measuring (``orient="auto"``).
    warning : str or None
        What was warned (:class:`FootprintWarning`): the 2D area may be
        over-estimated, or the search for an alpha failed; None if nothing.
    """

    rfi: float
    area_3d: float
    area_2d: float
    alpha: float
    find_alpha: bool
    vertices: int
    faces: int
    footprint: np.ndarray = field(repr=False, compare=False)
    mesh: trimesh.Trimesh = field(default=LazyMesh(), repr=False, compare=False)
    orientation: Orientation | None = field(default=None, compare=False)
    warning: str | None = field(default=None, compare=False)

    def to_dict(self) -> dict:
        """The table fields (:data:`RFI_FIELDS`) as a plain dict."""
        return {name: getattr(self, name) for name in RFI_FIELDS}

    def _repr_html_(self) -> str:
        """A compact table for notebooks: values, settings, arrays summarised."""
        return result_html(self)


def molar_area_3d(vertices: np.ndarray, faces: np.ndarray) -> float:
    """molaR's 3D area: per-face areas in single precision (:func:`molar_face_areas`), summed."""
    return float(molar_face_areas(vertices, faces).sum())


def first_occurrence(points: np.ndarray) -> np.ndarray:
    """molaR's duplicate check on 2D points: True for the points it keeps.

    A point is dropped when its x value equals the x value of some earlier
    point **and** its y value equals the y value of some earlier point, not
    necessarily the same one (so distinct points on a grid are dropped too).
    """

    def seen_before(values: np.ndarray) -> np.ndarray:
        order = np.argsort(values)  # equal values in any order: their first is found below
        ordered = values[order]
        starts = np.flatnonzero(np.r_[True, ordered[1:] != ordered[:-1]])
        repeat = np.ones(len(values), dtype=bool)
        repeat[np.minimum.reduceat(order, starts)] = False
        return repeat

    return ~(seen_before(points[:, 0]) & seen_before(points[:, 1]))


def walk(
    start: float,
    verdict: Callable[[float], str],
    max_evaluations: int = MAX_EVALUATIONS,
) -> tuple[float | None, list[tuple[float, str]]]:
    """molaR's ``findAlpha`` walk from `start`: the alpha it accepts, or None, and its steps.

    `verdict` gives the hull's verdict at an alpha: :data:`STRUCTURAL` ("S"),
    :data:`FAN` ("F") or :data:`OK`, or raises :class:`FootprintError` (R
    stops inside the search).  Every step is one IEEE double operation, as
    in molaR, so the alpha accepted has the bits molaR's has:

    - ``a = start``; last failure ``L = 0``; last success ``H = a + 1``;
    - S: ``L = a; a = a + 0.01``, then ``a = a - 0.009`` if ``a > H``;
    - F: ``L = a; a = a + 0.001``;
    - OK: accept ``a`` if ``L == a - 0.001``; else ``H = a; a = a - 0.005``,
      then ``a = L + 0.001`` if ``a <= L``, and accept ``a`` if now ``a == H``.

    At most `max_evaluations` hulls are evaluated; needing one more, or an
    error from `verdict`, is a failure (None).  The steps are ``(alpha,
    verdict)`` pairs, ``"error"`` for an error.
    """
    a, low = start, 0.0
    high = a + 1.0
    steps: list[tuple[float, str]] = []
    while len(steps) < max_evaluations:
        try:
            seen = verdict(a)
        except FootprintError:
            steps.append((a, "error"))
            return None, steps
        steps.append((a, seen))
        if seen == STRUCTURAL:
            low = a
            a = a + UP_STEP
            if a > high:
                a = a - BACK_STEP
        elif seen == FAN:
            low = a
            a = a + FINE_STEP
        else:
            if low == a - FINE_STEP:
                return a, steps
            high = a
            a = a - DOWN_STEP
            if a <= low:
                a = low + FINE_STEP
            if a == high:
                return a, steps
    return None, steps


class _Footprint:
    """A mesh's footprint points (both copies) and their alpha-convex hulls."""

    def __init__(self, vertices: np.ndarray):
        self.mean = vertices.mean(axis=0)
        points = np.vstack([vertices - self.mean, np.zeros((1, 3))])[:, :2]
        self.flat = points[first_occurrence(points)]
        self.scale = molar_scale(vertices)
        scaled = points * self.scale
        scaled = scaled[first_occurrence(scaled)]
        if len(scaled) < 3:
            raise ValueError("the footprint has fewer than three distinct points")
        self.hull = AlphaHull(scaled)
        self._arcs: dict[float, Arcs] = {}

    def arcs(self, alpha: float) -> Arcs:
        if alpha not in self._arcs:
            self._arcs[alpha] = self.hull.arcs(alpha)
        return self._arcs[alpha]

    def where(self, xy) -> str:
        x, y = np.asarray(xy) / self.scale + self.mean[:2]
        return f"{x:.6g}, {y:.6g}"

    def structural(self, arcs: Arcs) -> str | None:
        """Why molaR's S holds for `arcs`, or None."""
        if arcs.pinch >= 0:
            return (
                f"the hull pinches: the point at x, y = {self.where(arcs.xy[arcs.pinch])} "
                "starts two arcs"
            )
        if arcs.isolated >= 0:
            return (
                f"the point at x, y = {self.where(arcs.xy[arcs.isolated])} is on the hull's "
                "edge but ends no arc (an isolated point, a point joined only by dangling "
                "edges, or a pinch cut off on both sides)"
            )
        return None

    def fan(self, arcs: Arcs) -> bool:
        """molaR's F for `arcs` (not S); raises FootprintError where R stops."""
        answer = self.hull.fan(arcs)
        if answer == FAN_UNDEFINED:
            raise FootprintError(
                f"at alpha = {arcs.alpha!r} the vertices' mean lies on the line through the "
                "two ends of a hull arc: molaR's fan test divides 0 by 0 and R stops on the "
                f"missing value (RFI is NA); {PROJECTED_HINT}"
            )
        return answer == FAN_INSIDE

    def verdict(self, alpha: float) -> str:
        arcs = self.arcs(alpha)
        if arcs.structural:
            return STRUCTURAL
        return FAN if self.fan(arcs) else OK

    def area(self, arcs: Arcs) -> tuple[float, np.ndarray]:
        """The 2D area over `arcs` on the flat copy, and the arcs' ends there, loop by loop."""
        order = _chained(arcs.start, arcs.end)
        ends = np.column_stack([arcs.start[order], arcs.end[order]])
        if ends.size and ends.max() >= len(self.flat):
            raise FootprintError(
                f"at alpha = {arcs.alpha!r} the hull's boundary pinches and is cut at "
                f"{arcs.new} point(s) of its own, which are not footprint points: molaR's 2D "
                "area stops on 'subscript out of bounds' (RFI is NA); try another alpha, or "
                + PROJECTED_HINT
            )
        b1, b2 = self.flat[ends[:, 0]], self.flat[ends[:, 1]]
        b11 = b1[:, 0] * b1[:, 0] + b1[:, 1] * b1[:, 1]
        b22 = b2[:, 0] * b2[:, 0] + b2[:, 1] * b2[:, 1]
        b12 = b1[:, 0] * b2[:, 0] + b1[:, 1] * b2[:, 1]
        triangles = 0.5 * np.sqrt(np.abs(b11 * b22 - b12 * b12))
        return math.fsum(triangles.tolist()), self.flat[ends]


def _chained(start: np.ndarray, end: np.ndarray) -> np.ndarray:
    """The arcs' order head to tail around each loop (:func:`._alphahull.chain`)."""
    order = np.empty(len(start), dtype=np.int64)
    if len(start):
        chain(start, end, int(max(start.max(), end.max())) + 1, order)
    return order


def rfi(mesh, *, alpha: float = 0.075, find_alpha: bool = False, orient: str = "auto") -> RFIResult:
    """Relief index (Boyer 2008) as molaR 6.0's ``RFI`` computes it.

    molaR's conventions, all kept:

    1. ``area_3d``: the total face area of the mesh after molaR's cleaning
       (faces of zero area dropped, then unused vertices), per face in single
       precision as molaR's mesh reader computes it (:func:`molar_area_3d`).
    2. Footprint points: the vertices translated so that their mean is the
       origin, with the origin appended as one more point, in two copies: in
       mesh units ("flat") and multiplied by molaR's ``100 / size`` (centroid
       size with its per-vertex centring quirk, computed on the mesh as given;
       "scaled").  Each copy drops the points molaR's duplicate check drops
       (:func:`first_occurrence`: a repeated x value **and** a repeated y
       value, from any earlier points; on a regular grid this drops most of
       the points).  The scaled copy is the flat copy times a constant, so
       equal flat values stay equal and it drops at least the flat copy's
       points; it can drop more only where rounding makes two close values
       equal, and then its point indices, which the 2D area uses on the flat
       copy, are shifted, as in molaR.
    3. The hull: ``alphahull``'s alpha-convex hull (``ahull``; `alpha` is the
       radius of the empty discs) of the scaled copy's x-y points, a list of
       arcs clockwise around the region, trimmed where two empty discs
       overlap over a pinch, with a degenerate arc (a point to itself) for
       each point of the hull's edge on no arc (see :mod:`._alphahull`).
    4. molaR's tests on the list: **S** if some arc has equal ends or some
       point starts two arcs (:class:`AlphaAdjustmentError`, molaR's "alpha
       adjustment required"); **F** if some arc end lies strictly inside the
       triangle fanned from the last scaled point (the mean) over some arc,
       by molaR's barycentric formula in double precision.  F means that the
       footprint is not star-shaped from the mean, so the 2D area may be
       over-estimated: molaR warns and keeps the number, and so does this
       function (:class:`FootprintWarning`, and the result's ``warning``).
    5. ``area_2d``: over every arc (all loops), the unsigned area of the
       triangle (mean, end 1, end 2) on the flat copy's x-y coordinates, by
       the Gram form ``0.5 sqrt(|(b1.b1)(b2.b2) - (b1.b2)^2|)``, summed.  A
       boundary trimmed at points of its own has no flat coordinates there:
       molaR stops ("subscript out of bounds"), and so does this function
       (:class:`FootprintError`).
    6. ``RFI = ln(sqrt(area_3d) / sqrt(area_2d))``.

    With ``find_alpha=True`` the alpha is molaR's walk from `alpha`
    (:func:`walk`): up by 0.01 after S and by 0.001 after F, down by 0.005
    after OK, never below the last failure, until an OK alpha 0.001 above the
    last failure or the last success is met again.  Every step is an IEEE
    double operation as in molaR, so the alpha found has molaR's bits (e.g.
    0.040000000000000008).  It is not a search for the smallest valid alpha.
    If the walk needs more than 99 hulls or R would stop inside it, molaR
    measures at the start alpha instead: so does this function, with a
    :class:`FootprintWarning`.

    Parameters
    ----------
    mesh : trimesh.Trimesh, str, path-like, (vertices, faces), or Surface
        The crown, occlusal plane x-y and crown towards +z (see `orient`),
        or one prepared once for several metrics
        (:func:`dentopo.topography.prepare_surface`).  Never modified.
    alpha : float, default 0.075
        Radius of the hull's empty discs, in molaR's rescaled units; with
        `find_alpha`, where the walk starts.
    find_alpha : bool, default False
        Search for the alpha as molaR's ``findAlpha = TRUE`` does.
    orient : {"auto", "as-is"}, default "auto"
        The metric assumes the crown points to +z.  ``"as-is"`` measures the
        mesh as it lies (molaR's behaviour) and warns if the crown points to
        -z; ``"auto"`` (the default) turns such a crown first (see
        :func:`dentopo.topography.find_orientation`).  Either way the result's
        ``orientation`` says what was found and done.

    Returns
    -------
    RFIResult

    Raises
    ------
    AlphaAdjustmentError
        S at the alpha measured (`alpha`, or the start alpha after a failed
        search).
    FootprintError
        Where molaR stops with no value (RFI is NA): a trimmed boundary, or a
        missing value in the fan test.
    TypeError, ValueError
        For bad parameters or an unusable mesh.

    Warns
    -----
    FootprintWarning
        F at the alpha measured (the 2D area may be over-estimated), or the
        search for an alpha failed.
    UserWarning
        When the crown is measured pointing to -z (``orient="as-is"``), or
        when it is flat or closed (never turned).

    References
    ----------
    Boyer DM (2008). Relief index of second mandibular molars is a correlate
    of diet among prosimian primates and other euarchontan mammals. J Hum Evol
    55:1118-1137. https://doi.org/10.1016/j.jhevol.2008.08.002

    Pateiro-Lopez B, Rodriguez-Casal A (2010). Generalizing the convex hull of
    a sample: the R package alphahull. J Stat Softw 34(5).
    https://doi.org/10.18637/jss.v034.i05

    Examples
    --------
    >>> from dentopo.samples import tooth
    >>> result = rfi(tooth(rings=16), find_alpha=True)
    >>> sorted(result.to_dict())
    ['alpha', 'area_2d', 'area_3d', 'rfi']
    """
    alpha = check_alpha(alpha)
    find_alpha = check_find_alpha(find_alpha)
    surface = prepare_surface(mesh, orient=check_orient(orient))
    surface.warn_orientation()
    vertices = surface.vertices
    area_3d = float(surface.single_precision_areas().sum())
    footprint = _Footprint(vertices)

    warned: list[str] = []
    found = None
    if find_alpha:
        found, steps = walk(alpha, footprint.verdict)
        if found is None:
            why = (
                "R stops inside the hull test"
                if steps[-1][1] == "error"
                else f"no alpha within {MAX_EVALUATIONS} hulls"
            )
            warned.append(
                f"find_alpha failed ({why}, from alpha = {alpha!r}); measured at that "
                "alpha instead, as molaR does"
            )
    arcs = footprint.arcs(alpha if found is None else found)
    if found is None:  # a fixed alpha, or the search's fallback: S stops, F warns
        problem = footprint.structural(arcs)
        if problem is not None:
            raise AlphaAdjustmentError(
                f"alpha adjustment required at alpha = {alpha!r}: {problem}; "
                + (
                    f"molaR's search from there failed too; {PROJECTED_HINT}"
                    if find_alpha
                    else f"{PROJECTED_HINT}; for molaR's own number, use find_alpha=True to "
                    "search for an alpha (the search can fail too), or choose another alpha"
                )
            )
        if footprint.fan(arcs):
            warned.append(
                f"2D area may be over-estimated at alpha = {alpha!r}: the footprint is not "
                "star-shaped from the vertices' mean (an end of a hull arc lies inside the "
                "triangle fanned from the mean over another arc), so the fan of triangles "
                "covers more than the footprint"
            )
    area_2d, ends = footprint.area(arcs)
    warning = "; ".join(warned) if warned else None
    if warning is not None:
        warnings.warn(warning, FootprintWarning, stacklevel=2)
    return RFIResult(
        rfi=float(np.log(np.sqrt(area_3d) / np.sqrt(area_2d))),
        area_3d=area_3d,
        area_2d=area_2d,
        alpha=alpha if found is None else found,
        find_alpha=find_alpha,
        vertices=len(vertices),
        faces=len(surface.faces),
        footprint=ends + footprint.mean[:2],
        mesh=surface.mesh_later(),
        orientation=surface.orientation,
        warning=warning,
    )
