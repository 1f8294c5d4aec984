"""Which way a crown points, which way its faces are wound, and turning it to molaR's convention.

Slope, OPC/OPCR and RFI assume that the occlusal plane is the x-y plane and
that the crown points to +z; molaR never checks.  A crown pointing to -z gets
a meaningless slope (about 106 degrees on the paper's crowns), mirrored OPC
aspects and a footprint of the wrong side.  Slope, OPC and classic DNE's
convex/concave split also assume the faces are wound outward (counter-clockwise
seen from outside, so that ``(v2 - v1) x (v3 - v1)`` points out of the tooth):
with every face wound inward, slope becomes 180 degrees minus itself, every
OPC aspect turns by 180 degrees and classic DNE's convex and concave parts
swap.  This module finds both, by stated rules, and puts them right if asked.

The rules
---------
* **Winding.** The surface is closed over each loop of its open boundary by
  a fan of triangles around the loop's mean vertex (running each boundary edge
  backwards, so that the fan is wound as its neighbours), and the signed
  volume of the closed surface is taken.  Faces wound outward enclose a
  positive volume, faces wound inward a negative one; this is a property of
  the surface, not of its pose.  Faces wound against their neighbours (a
  shared edge run the same way by both) are first made to agree, patch by
  patch (:func:`dentopo.mesh.orient_consistently`); the faces whose winding
  then differs from the outward one are the ones wound inward.
* **Flat.** A surface whose closed volume ``|V|`` is at most
  ``FLAT_TOLERANCE * A**1.5`` (``A`` its area; the ratio does not depend on
  units or pose: a hemisphere gives 0.13, the paper's crowns 0.08, a dome of
  height h over radius R about ``0.28 h / R``) encloses nothing: it has no
  inside and no outside, no up and no down.  Its direction and its winding are
  ``"undetermined"``: it is warned about and never turned or rewound.  This
  is the rule for a plane in any pose, noise or not.
* **An open crown** (a surface with a boundary: the usual cut-off crown)
  points away from its open base: it points to +z when the boundary edges'
  length-weighted mean height lies below the surface's area-weighted mean
  height, else to -z.  This does not depend on how the faces are wound.
* **A closed surface** (no boundary: a whole tooth, a bone, a crown closed
  under its cervix) has no open base to say where up is.  The side its area
  faces is reported: with its faces wound outward, the area of the faces
  whose normal has a positive z component is compared with that of the
  faces whose normal has a negative one; when neither side has at least
  60 % of the area the direction is ``"undetermined"``.  Either way a closed
  surface is never turned, even with ``orient="auto"`` (the area rule is a
  hint, not a base), and the metrics that assume +z warn that they measure
  it as it lies, its underside included.  Its faces are still rewound
  outward when they enclose a negative volume: that rule is certain.

Turning a crown that points to -z is the rotation by 180 degrees about the
x axis, ``(x, y, z) -> (x, -y, -z)``: a proper rotation, so faces keep their
vertex order and every orientation-free quantity (areas, DNE) is unchanged.
Rewinding a face reverses its vertex order, ``(a, b, c) -> (c, b, a)``: it
undoes exactly the usual flip (``faces[:, ::-1]``, trimesh's ``invert``).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from ...mesh import boundary_edges, orient_consistently
from . import _kernels

#: ``orient``: ``"auto"`` (the default: turn a crown pointing to -z, rewind faces wound
#: inward) or ``"as-is"`` (molaR's and doolkit's behaviour: never turn, never rewind).
ORIENT_MODES = ("auto", "as-is")

#: The default ``orient`` of every metric that assumes the crown points to +z.
DEFAULT_ORIENT = "auto"

#: The rotation that turns a crown pointing to -z to +z (180 degrees about x).
TURN = np.diag([1.0, -1.0, -1.0])

#: A closed surface points to a side only if that side has this much more of its area.
CLOSED_MARGIN = 0.2

#: A surface is flat when the volume it encloses (closed over its open boundary) is at most
#: this times its area to the power 3/2 (a scale-free ratio: 0.13 for a hemisphere).
FLAT_TOLERANCE = 1e-3

#: ``Orientation.winding``: how the faces are wound.
WINDINGS = ("outward", "inward", "mixed", "undetermined")


@dataclass(frozen=True)
class Orientation:
    """Which way a crown points along z and its faces are wound, and what was done about it.

    Attributes
    ----------
    points : str
        ``"+z"``, ``"-z"`` or ``"undetermined"``, as found on the mesh given.
    rule : str
        ``"open base"`` (an open surface: away from its boundary), ``"area"``
        (a closed surface: the side its area faces) or ``"flat"`` (the surface
        encloses no volume: no up or down).
    turned : bool
        Whether the metrics measured the crown turned to +z.
    winding : str
        ``"outward"``, ``"inward"`` (every face), ``"mixed"`` (`inward_faces`
        of them, against the rest) or ``"undetermined"`` (a flat surface).
    rewound : bool
        Whether the metrics measured the faces wound outward (``orient="auto"``).
    inward_faces : int
        How many faces were found wound inward.
    faces : int
        How many faces the surface has.
    asked : str or None
        The ``orient`` it was measured with (None: only found, not measured).
        A closed surface is warned about unless ``"as-is"`` was asked for
        (measuring it as it lies is then what was asked).
    """

    points: str
    rule: str
    turned: bool = False
    winding: str = "outward"
    rewound: bool = False
    inward_faces: int = 0
    faces: int = 0
    asked: str | None = field(default=None, compare=False)

    @property
    def closed(self) -> bool:
        """Whether the surface has no open base (its direction, if any, is by area)."""
        return self.rule == "area"

    def turns(self, orient: str) -> bool:
        """Whether `orient` turns this crown: ``"auto"``, pointing to -z, with an open base."""
        return orient == "auto" and self.points == "-z" and self.rule == "open base"

    @property
    def wrong_way(self) -> bool:
        """Whether the crown, as measured, points to -z (against molaR's convention)."""
        return self.points == "-z" and not self.turned

    @property
    def wound_inward(self) -> bool:
        """Whether some faces were found wound inward (rewound or not)."""
        return self.winding in ("inward", "mixed")

    def __str__(self) -> str:
        """The ``orientation`` column: ``points -z, turned to +z; wound inward, rewound``.

        Words first (``points +z``, ``direction undetermined``): a table cell that
        began with ``+`` or ``-`` would be quoted against spreadsheet formulas.
        """
        if self.points == "undetermined":
            text = "direction undetermined"
        elif self.turned:
            text = f"points {self.points}, turned to +z"
        else:
            text = f"points {self.points}"
        if self.closed:
            text += "; closed, as it lies"
        if self.winding == "inward":
            text += "; wound inward"
        elif self.winding == "mixed":
            text += f"; {self.inward_faces} faces wound inward"
        if self.wound_inward and self.rewound:
            text += ", rewound"
        return text

    def messages(self, *, winding_only: bool = False) -> tuple[str, ...]:
        """The warnings for what was found, one per problem (``winding_only``: classic DNE's)."""
        found = []
        if self.wrong_way and not winding_only and not self.closed:
            found.append(
                "the crown points to -z (its open base lies above it); slope, OPC and RFI "
                "assume it points to +z, as molaR does: turn it with orient='auto'"
            )
        if self.closed and not winding_only and self.asked != "as-is":
            side = (
                "neither side of it faces up more than the other"
                if self.points == "undetermined"
                else f"most of its area faces {self.points}"
            )
            found.append(
                f"the surface is closed (it has no open base to tell up from down; {side}): "
                "it was not turned, and slope, OPC and RFI measure it as it lies, its underside "
                "included; crop it to the crown above the cervix, or turn it by hand"
            )
        if self.rule == "flat" and not winding_only:
            found.append(
                "the surface is flat (it encloses no volume over its open base): it has no up or "
                "down, so its direction is undetermined and it was not turned; slope, OPC and RFI "
                "measure it as it lies"
            )
        if self.wound_inward:
            which = (
                "every face is wound inward"
                if self.winding == "inward"
                else f"{self.inward_faces} of {self.faces} faces are wound inward, against the rest"
            )
            effect = (
                "(normals into the tooth: slope reads 180 degrees minus itself, OPC's aspects "
                "turn by 180 degrees and classic DNE's convex and concave parts swap)"
            )
            fix = (
                "they were rewound outward before measuring (orient='auto')"
                if self.rewound
                else "measured as wound, as molaR does: rewind them with orient='auto'"
            )
            found.append(f"{which} {effect}; {fix}")
        return tuple(found)

    def warning(self) -> str | None:
        """The warnings of :meth:`messages` in one text, or None if there is nothing to say."""
        found = self.messages()
        return " ".join(found) if found else None


def check_orient(orient) -> str:
    """Validate ``orient`` (``"as-is"`` or ``"auto"``, any case)."""
    if not isinstance(orient, str) or orient.lower() not in ORIENT_MODES:
        raise ValueError(f"orient must be one of {ORIENT_MODES}; got {orient!r}")
    return orient.lower()


def _face_areas(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    tri = vertices[faces]
    return 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)


def closed_volume(
    vertices: np.ndarray, faces: np.ndarray, boundary: np.ndarray, cross: np.ndarray | None = None
) -> float:
    """Signed volume of the surface closed by a fan over each loop of its `boundary` edges.

    Each connected set of boundary edges gets a fan around its mean vertex,
    each edge run backwards (so that the fan is wound as the faces next to it);
    coordinates are taken about the mean vertex, so that the sum is well
    conditioned far from the origin.  Positive for faces wound outward.
    `cross`: the faces' ``(v2 - v1) x (v3 - v1)``, if the caller has them
    (``det(x1, x2, x3) = x1 . ((x2 - x1) x (x3 - x1))``).
    """
    origin = vertices.mean(axis=0)
    points = np.ascontiguousarray(vertices - origin)
    if cross is None:
        tri = points[faces]
        cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    # writeable arrays: a read-only one (a result's frozen faces) is a second compilation
    six = _kernels.closed_volume(
        points,
        np.require(faces, dtype=np.int64, requirements="CW"),
        np.require(cross, dtype=np.float64, requirements="CW"),
        np.require(boundary, dtype=np.int64, requirements="CW").reshape(-1, 2),
    )
    return float(six / 6.0)


def survey(
    vertices: np.ndarray,
    faces: np.ndarray,
    area: np.ndarray | None = None,
    boundary: np.ndarray | None = None,
    consistent: bool | None = None,
    cross: np.ndarray | None = None,
) -> tuple[Orientation, np.ndarray]:
    """:func:`find_orientation`, and which faces are wound inward ((m,) bool).

    `consistent`: whether the caller knows that no shared edge is run the same
    way by both its faces (None: found here); `cross`: the faces' cross
    products, if the caller has them.
    """
    vertices = np.asarray(vertices, dtype=np.float64)
    faces = np.asarray(faces, dtype=np.int64)
    m = len(faces)
    area = _face_areas(vertices, faces) if area is None else area
    edges = boundary_edges(faces, len(vertices)) if boundary is None else boundary
    agreeing = faces if consistent else orient_consistently(faces, len(vertices))
    if agreeing is not faces:  # some faces were flipped to agree with their neighbours
        volume = closed_volume(vertices, agreeing, boundary_edges(agreeing, len(vertices)))
    else:
        volume = closed_volume(vertices, faces, edges, cross)
    total = float(area.sum())
    if not abs(volume) > FLAT_TOLERANCE * total**1.5:
        found = Orientation("undetermined", "flat", winding="undetermined", faces=m)
        return found, np.zeros(m, dtype=bool)
    outward = agreeing if volume > 0 else agreeing[:, ::-1]
    if agreeing is faces:
        inward = np.full(m, volume < 0)
    else:
        inward = np.any(outward != faces, axis=1)
    count = int(np.count_nonzero(inward))
    winding = "outward" if count == 0 else "inward" if count == m else "mixed"
    details = {"winding": winding, "inward_faces": count, "faces": m}
    if len(edges):
        ends = vertices[edges]
        length = np.linalg.norm(ends[:, 1] - ends[:, 0], axis=1)
        base = np.sum(length * ends[:, :, 2].mean(axis=1)) / length.sum()
        height = np.empty(m)
        _kernels.face_mean_z(_kernels.readonly(vertices), _kernels.readonly(faces), height)
        centre = np.sum(area * height) / total
        return Orientation("+z" if base < centre else "-z", "open base", **details), inward
    tri = vertices[outward]
    nz = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])[:, 2]
    up, down = area[nz > 0].sum(), area[nz < 0].sum()
    if abs(up - down) < CLOSED_MARGIN * (up + down):
        return Orientation("undetermined", "area", **details), inward
    return Orientation("+z" if up > down else "-z", "area", **details), inward


def find_orientation(
    vertices: np.ndarray,
    faces: np.ndarray,
    area: np.ndarray | None = None,
    boundary: np.ndarray | None = None,
) -> Orientation:
    """Which way along z the crown ``(vertices, faces)`` points, and how its faces are wound.

    See the module's rules.  `area`: the faces' areas, and `boundary`: the
    mesh's boundary edges (:func:`dentopo.mesh.boundary_edges`), if the
    caller has them already.
    """
    return survey(vertices, faces, area, boundary)[0]


def orient_vertices(
    vertices: np.ndarray, faces: np.ndarray, orient: str, area: np.ndarray | None = None
) -> tuple[np.ndarray, Orientation]:
    """The vertices to measure (turned to +z if ``orient="auto"`` and needed), and what was found.

    Turns only: the faces are not rewound here (see
    :func:`dentopo.topography.prepare_surface`, which does both).  `area`: the
    faces' areas, if the caller has them already.  Never modifies `vertices`.
    """
    orient = check_orient(orient)
    found = find_orientation(vertices, faces, area)
    if found.turns(orient):
        return vertices @ TURN.T, replace(found, turned=True, asked=orient)
    return vertices, replace(found, asked=orient)
