"""Relief index (RFI) as molaR 6.0 computes it, with its alpha-shape footprint.

RFI compares a crown's 3D surface area with the area of its footprint, the
outline of the crown seen from above (+z): ``RFI = ln(sqrt(area_3d) /
sqrt(area_2d))`` (Boyer 2008).  molaR draws the footprint as the boundary of
an alpha shape (Edelsbrunner) of the vertices' x-y positions, in the R package
``alphahull``'s convention, and sums triangles fanned from the vertices' mean
over the boundary segments.  Every convention below is molaR's, the odd ones
included, because matching its numbers requires them.

The alpha shape is computed once per mesh as an interval of radii per
Delaunay edge; any alpha is then a cheap filter, and molaR's search for an
alpha (``findAlpha``) is replayed on these intervals instead of recomputing the
shape at every step.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
import trimesh
from scipy.spatial import QhullError

from . import _kernels
from ._delaunay import delaunay
from ._orientation import Orientation, check_orient
from ._parameters import check_alpha, check_find_alpha
from ._surface import molar_face_areas, molar_scale, prepare_surface

#: Scalar fields, in the order of output tables.
RFI_FIELDS = ("rfi", "area_3d", "area_2d", "alpha")

#: molaR's search steps (see AlphaShape.find_alpha): UP_STEP multiples added to
#: the start, DOWN_STEP and FINE_STEP added repeatedly.
UP_STEP = 0.01
DOWN_STEP = 0.005
FINE_STEP = 0.001

#: Candidate alphas generated at a time while walking molaR's search.
_CHUNK = 4096


class AlphaAdjustmentError(ValueError):
    """The alpha-shape boundary is not one simple closed outline at this alpha.

    molaR's "alpha adjustment required": its footprint needs the boundary
    segments to chain into one closed loop.  Try ``find_alpha=True`` (molaR's
    ``findAlpha``) or another ``alpha``.
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
        from the vertices' mean over the boundary segments.
    alpha : float
        The alpha used: the radius of the empty discs of the alpha shape, in
        molaR's rescaled units (centroid size 100).  With ``find_alpha`` it is
        the alpha molaR's search ends on, bit for bit.
    find_alpha : bool
        Whether ``alpha`` was searched for.
    vertices, faces : int
        Vertex and face counts of the cleaned mesh.
    footprint : (k, 2, 2) float
        The boundary segments as x-y coordinates of their two ends, in the
        mesh's own units and position, chained head to tail around the loop
        (for drawing the outline over a top view).
    mesh : trimesh.Trimesh
        The cleaned mesh (a private copy; turned to +z if ``orient="auto"``
        turned it, and the footprint with it).
    orientation : Orientation
        Which way the crown points (``+z``, ``-z`` or ``undetermined``) and
        whether it was turned before measuring (``orient="auto"``).
    """

    rfi: float
    area_3d: float
    area_2d: float
    alpha: float
    find_alpha: bool
    vertices: int
    faces: int
    footprint: np.ndarray = field(repr=False, compare=False)
    mesh: trimesh.Trimesh = field(repr=False, compare=False)
    orientation: Orientation | None = field(default=None, compare=False)

    def to_dict(self) -> dict:
        """The table fields (:data:`RFI_FIELDS`) as a plain dict."""
        return {name: getattr(self, name) for name in RFI_FIELDS}


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


class AlphaShape:
    """The alpha shapes of a 2D point set, for every alpha at once.

    An edge ``(i, j)`` of the Delaunay triangulation is on the boundary of the
    alpha shape (``alphahull``'s ``ashape``) when some disc of radius alpha
    with both points on its circle has no point inside: the disc's centre then
    lies on the edge's dual Voronoi edge, the segment between the circumcentres
    of the two triangles on the edge (a ray outwards for a convex-hull edge).
    So the edge is on the boundary exactly for ``alpha_min <= alpha <=
    alpha_max``: ``alpha_min`` is half the edge length when the edge's midpoint
    lies on the Voronoi edge (both opposite angles at most 90 degrees; the
    triangle's opposite angle for a hull edge) and otherwise the smaller
    circumradius, and ``alpha_max`` is the larger circumradius (infinite for a
    hull edge).

    Parameters
    ----------
    points : (n, 2) float
        Distinct points, not all on one line.
    positions : (n, 2) float, optional
        Where to say the points are in messages (default `points`).
    """

    def __init__(self, points: np.ndarray, positions: np.ndarray | None = None):
        self.n = len(points)
        self.positions = points if positions is None else positions
        try:
            simplices, neighbors = delaunay(points)
        except QhullError as exc:
            raise ValueError(
                "the footprint has no area: the vertices' x-y positions lie on one line"
            ) from exc
        ux, uy = np.empty(len(simplices)), np.empty(len(simplices))
        _kernels.circumcentres(points, simplices, ux, uy)
        radius = np.hypot(ux, uy)

        most = 3 * len(simplices)
        ends = np.empty((most, 2), dtype=np.int64)
        alpha_min, alpha_max = np.empty(most), np.empty(most)
        hull = np.empty(most, dtype=bool)
        count = _kernels.alpha_intervals(
            points, simplices, neighbors, radius, ends, alpha_min, alpha_max, hull
        )
        self.edges = ends[:count]
        self.alpha_min = alpha_min[:count]
        self.alpha_max = alpha_max[:count]
        self._hull = hull[:count]
        self._valid: dict[int, bool] = {}

    @cached_property
    def critical(self) -> np.ndarray:
        """The sorted distinct finite interval ends: where the boundary changes."""
        return np.unique(np.concatenate([self.alpha_min, self.alpha_max[~self._hull]]))

    def boundary(self, alpha: float) -> np.ndarray:
        """(k, 2) int: the boundary segments at `alpha` (point indices)."""
        return self.edges[(self.alpha_min <= alpha) & (alpha <= self.alpha_max)]

    def state(self, alphas) -> np.ndarray:
        """An integer per alpha, equal for alphas whose boundaries are equal.

        The boundary changes only at the critical radii (the finite interval
        ends): alphas strictly between two consecutive ones, or equal to the
        same one, have the same boundary.
        """
        alphas = np.asarray(alphas, dtype=np.float64)
        above = np.searchsorted(self.critical, alphas, side="right")
        on = (above > 0) & (self.critical[np.maximum(above - 1, 0)] == alphas)
        return 2 * above + on

    def problem(self, alpha: float) -> str | None:
        """Why the boundary at `alpha` is not one closed loop, or None if it is."""
        segments = self.boundary(alpha)
        if len(segments) == 0:
            return "there is no boundary segment (alpha is below half the spacing of the points)"
        degree = np.bincount(segments.ravel(), minlength=self.n)
        worst = int(degree.argmax())
        if degree[worst] > 2:
            return (
                f"the boundary pinches: the point at x, y = {self._where(worst)} "
                f"lies on {degree[worst]} boundary segments"
            )
        loose = np.flatnonzero(degree == 1)
        if len(loose):
            return (
                f"the boundary is not closed: the point at x, y = {self._where(loose[0])} "
                "ends a dangling segment"
            )
        loops = _kernels.loops(segments, self.n)
        if loops > 1:
            return f"the boundary segments form {loops} separate loops, not one outline"
        return None

    def _where(self, point: int) -> str:
        x, y = self.positions[point]
        return f"{x:.6g}, {y:.6g}"

    def valid(self, alpha: float) -> bool:
        """Whether the boundary at `alpha` is one simple closed loop (cached per state)."""
        key = int(self.state(alpha))
        if key not in self._valid:
            self._valid[key] = self.problem(alpha) is None
        return self._valid[key]

    def first(self, alphas: np.ndarray, want: bool) -> float | None:
        """The first of `alphas` whose validity is `want` (one test per distinct state)."""
        states = self.state(alphas)
        runs = np.flatnonzero(np.r_[True, states[1:] != states[:-1]])
        for start in runs:
            if self.valid(float(alphas[start])) == want:
                return float(alphas[start])
        return None

    def walk(self, start: float, step: float, want: bool) -> float:
        """``a = start; while valid(a) != want: a = a + step``, in molaR's arithmetic.

        The steps are repeated additions (as a loop adds them), so the alpha
        reached is the same floating-point number molaR reaches.
        """
        if self.valid(start) == want:
            return start
        while True:
            alphas = np.add.accumulate(np.r_[start, np.full(_CHUNK, step)])[1:]
            found = self.first(alphas, want)
            if found is not None:
                return found
            start = float(alphas[-1])

    def climb(self, alpha: float) -> float:
        """The first valid ``alpha + i * 0.01`` for i = 1, 2, ..."""
        i = 1
        while True:
            steps = np.arange(i, i + _CHUNK, dtype=np.float64)
            found = self.first(alpha + steps * UP_STEP, True)
            if found is not None:
                return found
            i += _CHUNK
            # Skip the candidates below the next critical radius: they share
            # the last candidate's (invalid) boundary.  Beyond the last
            # critical radius the boundary is the convex hull, which is valid.
            last = alpha + (i - 1) * UP_STEP
            if self.state(last) % 2 == 0:
                later = self.critical[self.critical > last]
                if len(later):
                    i = max(i, int(np.floor((later[0] - alpha) / UP_STEP)) - 1)

    def find_alpha(self, alpha: float) -> float:
        """molaR's search for an alpha whose boundary is one closed loop.

        - Valid at `alpha`: step down by 0.005 (``a = a - 0.005`` repeated)
          to the first invalid alpha, then up by 0.001 (``a = a + 0.001``
          repeated) to the first valid one.
        - Invalid at `alpha`: take the first valid ``b = alpha + i * 0.01``
          (i = 1, 2, ...), step back to ``b - 0.01``, then up by 0.001 as
          above to the first valid alpha.

        The arithmetic is molaR's to the bit (it shows in the alphas found,
        e.g. 0.020000000000000004); one alpha per distinct boundary is tested.
        """
        if self.valid(alpha):
            start = self.walk(alpha, -DOWN_STEP, False)
        else:
            start = self.climb(alpha) - UP_STEP
        return self.walk(start, FINE_STEP, True)


def _chain(segments: np.ndarray, n: int) -> np.ndarray:
    """The segments of one closed loop, head to tail from its lowest point index.

    The loop runs first towards the lower of that point's two neighbours, so
    the order does not depend on how the triangulation listed its edges.
    """
    order = np.empty(len(segments), dtype=np.int64)
    _kernels.loop_order(segments, n, order)
    return np.column_stack([order, np.roll(order, -1)])


def rfi(
    mesh, *, alpha: float = 0.075, find_alpha: bool = False, orient: str = "as-is"
) -> RFIResult:
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
       value, from any earlier points).  The scaled copy is the flat copy
       times a constant, so equal flat values stay equal and it drops at least
       the flat copy's points; it can drop more only where rounding makes two
       close values equal, and then its point indices, which the footprint
       uses on the flat copy, are shifted, as in molaR.
    3. The alpha shape (``alphahull``'s ``ashape``; `alpha` is the radius of
       the empty discs) of the scaled copy's x-y points.  Its boundary
       segments must form one simple closed loop: a point on more than two
       segments (the boundary pinches), a dangling segment, or several
       separate loops (islands or holes) raise :class:`AlphaAdjustmentError`,
       molaR's "alpha adjustment required".  molaR's reference values show
       the pinch (at the default alpha) and, through its search, that it also
       rejects several loops.
    4. ``area_2d``: for each boundary segment, the unsigned area of the
       triangle (origin, end 1, end 2) on the flat copy's x-y coordinates,
       summed.  (A fan from the vertices' mean: over-estimated when the
       footprint is not star-shaped from there; molaR warns and keeps it.)
    5. ``RFI = ln(sqrt(area_3d) / sqrt(area_2d))``.

    With ``find_alpha=True`` the alpha is molaR's search from `alpha`
    (:meth:`AlphaShape.find_alpha`): from a valid `alpha`, down by 0.005 to
    the first invalid alpha; from an invalid one, up to the first valid
    ``alpha + i * 0.01`` and back by 0.01; then up by 0.001 to the first valid
    alpha.  The arithmetic is molaR's, so the alpha found is the same number.
    Validity need not be monotone in alpha, so this is not always the smallest
    valid alpha.  The search is replayed on the precomputed alpha intervals,
    testing one alpha per distinct boundary.

    Parameters
    ----------
    mesh : trimesh.Trimesh, str, path-like, (vertices, faces), or Surface
        The crown, occlusal plane x-y and crown towards +z (see `orient`),
        or one prepared once for several metrics
        (:func:`dentopo.topography.prepare_surface`).  Never modified.
    alpha : float, default 0.075
        Radius of the alpha shape's discs, in molaR's rescaled units; with
        `find_alpha`, where the search starts.
    find_alpha : bool, default False
        Search for the alpha as molaR's ``findAlpha = TRUE`` does.
    orient : {"as-is", "auto"}, default "as-is"
        The metric assumes the crown points to +z.  ``"as-is"`` measures the
        mesh as it lies (molaR's behaviour) and warns if the crown points to
        -z; ``"auto"`` turns such a crown first (see
        :func:`dentopo.topography.find_orientation`).  Either way the result's
        ``orientation`` says what was found and done.

    Returns
    -------
    RFIResult

    Raises
    ------
    AlphaAdjustmentError
        When the boundary at `alpha` is not one closed loop (not with
        `find_alpha`).
    TypeError, ValueError
        For bad parameters or an unusable mesh.

    Warns
    -----
    UserWarning
        With ``orient="as-is"``, when the crown points to -z.

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

    mean = vertices.mean(axis=0)
    points = np.vstack([vertices - mean, np.zeros((1, 3))])[:, :2]
    flat = points[first_occurrence(points)]
    scale = molar_scale(vertices)
    scaled = points * scale
    scaled = scaled[first_occurrence(scaled)]
    if len(scaled) < 3:
        raise ValueError("the footprint has fewer than three distinct points")

    shape = AlphaShape(scaled, positions=scaled / scale + mean[:2])
    if find_alpha:
        alpha = shape.find_alpha(alpha)
    else:
        problem = shape.problem(alpha)
        if problem is not None:
            raise AlphaAdjustmentError(
                f"alpha adjustment required at alpha = {alpha!r}: {problem}; "
                "use find_alpha=True to search for an alpha, or choose another alpha"
            )
    segments = _chain(shape.boundary(alpha), shape.n)
    ends = flat[segments]
    cross = ends[:, 0, 0] * ends[:, 1, 1] - ends[:, 0, 1] * ends[:, 1, 0]
    area_2d = float(0.5 * np.abs(cross).sum())
    return RFIResult(
        rfi=float(np.log(np.sqrt(area_3d) / np.sqrt(area_2d))),
        area_3d=area_3d,
        area_2d=area_2d,
        alpha=alpha,
        find_alpha=find_alpha,
        vertices=len(vertices),
        faces=len(surface.faces),
        footprint=ends + mean[:2],
        mesh=surface.trimesh(),
        orientation=surface.orientation,
    )
