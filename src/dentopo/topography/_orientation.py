"""Which way a crown points, and turning it to molaR's convention (+z).

Slope, OPC/OPCR and RFI assume that the occlusal plane is the x-y plane and
that the crown points to +z; molaR never checks.  A crown pointing to -z gets
a meaningless slope (about 106 degrees on the paper's crowns), mirrored OPC
aspects and a footprint of the wrong side.  This module finds the direction
along z a crown points to, by a stated rule, and turns it if asked.

The rule
--------
* **An open crown** (a surface with a boundary: the usual cut-off crown)
  points away from its open base: it points to +z when the boundary edges'
  length-weighted mean height lies below the surface's area-weighted mean
  height, else to -z.  This does not depend on how the faces are oriented.
* **A closed surface** points to the side its area faces: with its faces
  oriented outward, the area of the faces whose normal has a positive z
  component is compared with that of the faces whose normal has a negative
  one (a crown's worn, cusped occlusal side has more area than its base).
  When neither side has at least 60 % of the area (a whole tooth, a bone),
  the direction is ``"undetermined"``: nothing is turned and nothing warned.

Turning a crown that points to -z is the rotation by 180 degrees about the
x axis, ``(x, y, z) -> (x, -y, -z)``: a proper rotation, so faces keep their
vertex order and every orientation-free quantity (areas, DNE) is unchanged.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..mesh import boundary_edges, outward_faces
from . import _kernels

#: ``orient``: ``"as-is"`` (molaR's behaviour: never turn) or ``"auto"``.
ORIENT_MODES = ("as-is", "auto")

#: The rotation that turns a crown pointing to -z to +z (180 degrees about x).
TURN = np.diag([1.0, -1.0, -1.0])


#: A closed surface points to a side only if that side has this much more of its area.
CLOSED_MARGIN = 0.2


@dataclass(frozen=True)
class Orientation:
    """Which way a crown points along z, by which rule, and whether it was turned.

    Attributes
    ----------
    points : str
        ``"+z"``, ``"-z"`` or ``"undetermined"``, as found on the mesh given.
    rule : str
        ``"open base"`` (an open surface: away from its boundary) or
        ``"area"`` (a closed surface: the side its area faces).
    turned : bool
        Whether the metrics measured the crown turned to +z.
    """

    points: str
    rule: str
    turned: bool = False

    @property
    def wrong_way(self) -> bool:
        """Whether the crown, as measured, points to -z (against molaR's convention)."""
        return self.points == "-z" and not self.turned

    def __str__(self) -> str:
        """The ``orientation`` column: ``+z``, ``-z`` or ``-z, turned to +z``."""
        return f"{self.points}, turned to +z" if self.turned else self.points

    def warning(self) -> str | None:
        """The warning for a crown measured pointing the wrong way, or None."""
        if not self.wrong_way:
            return None
        why = "its open base lies above it" if self.rule == "open base" else "its area faces -z"
        return (
            f"the crown points to -z ({why}); slope, OPC and RFI assume it points to +z, "
            "as molaR does: turn it with orient='auto' (command line: --orient auto)"
        )


def check_orient(orient) -> str:
    """Validate ``orient`` (``"as-is"`` or ``"auto"``, any case)."""
    if not isinstance(orient, str) or orient.lower() not in ORIENT_MODES:
        raise ValueError(f"orient must be one of {ORIENT_MODES}; got {orient!r}")
    return orient.lower()


def find_orientation(
    vertices: np.ndarray,
    faces: np.ndarray,
    area: np.ndarray | None = None,
    boundary: np.ndarray | None = None,
) -> Orientation:
    """Which way along z the crown ``(vertices, faces)`` points (see the module's rule).

    `area`: the faces' areas, and `boundary`: the mesh's boundary edges
    (:func:`dentopo.mesh.boundary_edges`), if the caller has them already.
    """
    vertices, faces = np.asarray(vertices, dtype=np.float64), np.asarray(faces)
    if area is None:
        tri = vertices[faces]
        area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
    edges = boundary_edges(faces, len(vertices)) if boundary is None else boundary
    if len(edges):
        ends = vertices[edges]
        length = np.linalg.norm(ends[:, 1] - ends[:, 0], axis=1)
        base = np.sum(length * ends[:, :, 2].mean(axis=1)) / length.sum()
        height = np.empty(len(faces))
        _kernels.face_mean_z(vertices, np.asarray(faces, dtype=np.int64), height)
        centre = np.sum(area * height) / area.sum()
        return Orientation("+z" if base < centre else "-z", "open base")
    out = vertices[outward_faces(vertices, faces)]
    nz = np.cross(out[:, 1] - out[:, 0], out[:, 2] - out[:, 0])[:, 2]
    up, down = area[nz > 0].sum(), area[nz < 0].sum()
    if abs(up - down) < CLOSED_MARGIN * (up + down):
        return Orientation("undetermined", "area")
    return Orientation("+z" if up > down else "-z", "area")


def orient_vertices(
    vertices: np.ndarray, faces: np.ndarray, orient: str, area: np.ndarray | None = None
) -> tuple[np.ndarray, Orientation]:
    """The vertices to measure (turned to +z if ``orient="auto"`` and needed), and what was done.

    `area`: the faces' areas, if the caller has them already.  Never modifies `vertices`.
    """
    orient = check_orient(orient)
    found = find_orientation(vertices, faces, area)
    if orient == "auto" and found.points == "-z":
        return vertices @ TURN.T, Orientation(found.points, found.rule, turned=True)
    return vertices, found
