"""The orient step: a rigid motion that puts the crown occlusal side up (+z).

The rules (the orientation rules the metrics use, :mod:`dentopo.topography.surface._orientation`,
carried from "which way along z" to "which way in space"):

* **Flat.** A surface whose volume, closed over its open boundary, is at most
  ``FLAT_TOLERANCE * area**1.5`` has no up or down: it is left as it is, with a
  warning (the metrics' rule, the same tolerance).
* **An open crown** (a surface with a boundary: the usual crown cut at the
  cervix).  Its boundary edges form loops; the longest loop (by length) is its
  open base, the others are holes (their count is reported; a base loop
  shorter than ``SMALL_BASE`` times the crown's size is warned about: it may
  be a hole in a closed surface).  The base plane is the least-squares plane
  of the base loop taken as a polyline (every edge weighted by its length,
  its exact second moment as a segment): its normal is the direction of
  least spread.  The normal's sign is the one the crown
  lies on: the side of the plane where the surface's area-weighted centroid
  lies (the metrics' "open base" rule, measured along the normal instead of
  along z).  The crown is turned by the *smallest* rotation taking that normal
  to +z (Rodrigues' formula; when the normal is -z exactly, 180 degrees about
  x, as the metrics' turn).
* **A closed surface** (no boundary: a crown closed under its cervix, a whole
  tooth, a specimen).  Its "up" axis is its *shortest* principal axis (of the
  area-weighted second moments of the surface): dentopo measures crowns, and a
  crown is lower than it is long or wide, so that its occlusal direction is
  its least extent (a whole tooth with its roots is the exception: its long
  axis is up; give ``up=`` for it).  The sign is the metrics' area rule: with
  the faces wound outward, the side that at least ``CLOSED_MARGIN`` more of the
  area faces is up.  When the side is undetermined, or the shortest axis is
  not distinct (its second moment within ``AXIS_MARGIN`` of the next), the
  surface is left as it is, with a warning suggesting ``up=(x, y, z)``
  (the command shows it as ``--up X,Y,Z``).  A closed surface that *is*
  turned is also warned about: the rule is a guess from its shape, not from an open base; check it.
* **up=(x, y, z)** names the occlusal direction by hand: the smallest rotation
  taking it to +z, nothing found.

The translation: after the rotation the crown is moved so that its *centre* is
at the origin: the base loop's centroid for an open crown (so that the base
plane is z = 0 and the crown stands above it, and a crop plane ``z = h`` is
at height h above the base), the surface's area-weighted centroid for a closed
surface or with ``up=``.  A surface left as it is is not moved at all (the
identity).  No metric depends on the translation.

``spin="footprint"`` then turns the crown about the z axis (through the
origin) so that the long axis of its footprint (the principal axis of the
surface projected onto x-y, each face weighted by its projected area) lies
along +y (doolkit's mesio-distal convention).  The sign is fixed by the third
moment of the footprint along that axis: the side its skew points to (the
longer tail, a positive third moment) goes to +y; when the skew is below
``SKEW_TOLERANCE`` (a symmetric footprint) the sign that turns least is taken
(the rule used is reported).  A footprint whose two second moments
differ by less than ``ROUND_MARGIN`` is round: it has no long axis and is not
spun (warned).  Everything is computed from the geometry only, so that neither
the pose nor the vertex order changes the result.

The transform is returned as a 4x4 matrix ``[[R, t], [0, 1]]`` (``R`` a proper
rotation, det +1) acting on column vectors: ``new = R @ old + t``.  The plane
reported is the base plane found, ``(point, normal)`` in the coordinates of
the mesh given (before the motion); None if there was no open base.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from ..mesh import boundary_edges, orient_consistently
from ..topography.surface._orientation import CLOSED_MARGIN, FLAT_TOLERANCE, closed_volume
from ._protocol import ProtocolError, scaled_direction
from ._result import Outcome

#: A closed surface's shortest principal axis is distinct when its second moment is at
#: most ``1 - AXIS_MARGIN`` times the next one's.
AXIS_MARGIN = 0.1

#: A footprint is round (no long axis) when its two second moments differ by less than
#: this fraction of the larger.
ROUND_MARGIN = 0.02

#: The footprint's skew along its long axis fixes the axis' sign when its third moment is
#: at least this times the cube of its spread (else: the smallest turn).
SKEW_TOLERANCE = 1e-3

#: The open crown's side is undetermined when its centroid lies within this fraction of
#: its size from the base plane.
SIDE_TOLERANCE = 1e-6

#: An open base whose loop is shorter than this times the crown's size (its bounding box's
#: diagonal) is warned about: a hole, perhaps, in a closed surface (a hemisphere's is 2.1,
#: a crown cut at the cervix about 1.8).
SMALL_BASE = 1.0

_SUGGEST = "give the occlusal direction by hand with up=(x, y, z)"


def rotation_to_z(direction) -> np.ndarray:
    """The smallest rotation (3x3, det +1) taking `direction` to +z.

    Rodrigues' formula about the axis ``direction x z`` by the angle between
    them (taken with ``atan2``, accurate at every angle).  When `direction` is
    -z (to 1e-12), any half-turn about a horizontal axis is smallest: the one
    about the horizontal axis nearest x is taken (about x itself for -z).
    """
    a = np.asarray(scaled_direction("direction", np.ravel(direction)), dtype=np.float64)
    a = a / np.linalg.norm(a)  # scaled first: no overflow nor underflow (1e308, 5e-324)
    z = np.array([0.0, 0.0, 1.0])
    v = np.cross(a, z)
    s = float(np.linalg.norm(v))
    c = float(a @ z)
    if s < 1e-12:
        if c > 0:
            return np.eye(3)
        x = np.array([1.0, 0.0, 0.0])
        u = x - (x @ a) * a
        if np.linalg.norm(u) < 0.5:  # pragma: no cover - a is -z to 1e-12, never near x
            u = np.array([0.0, 1.0, 0.0]) - a[1] * a
        u = u / np.linalg.norm(u)
        return 2.0 * np.outer(u, u) - np.eye(3)
    k = v / s
    cross = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    theta = math.atan2(s, c)
    return np.eye(3) + math.sin(theta) * cross + (1.0 - math.cos(theta)) * (cross @ cross)


def rotation_angle(rotation: np.ndarray) -> float:
    """The angle (degrees) of a rotation matrix."""
    cosine = (float(np.trace(rotation)) - 1.0) / 2.0
    return math.degrees(math.acos(min(1.0, max(-1.0, cosine))))


def _about_z(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _triangles(vertices: np.ndarray, faces: np.ndarray):
    tri = vertices[faces]
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    return tri, cross


def surface_moments(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The surface's area-weighted centroid (3,) and second moments about it (3, 3), per area.

    Exact for the triangulated surface: ``int x x^T dA`` over a triangle is
    ``A / 12 (sum v_i v_i^T + 9 g g^T)`` (``g`` its centroid).
    """
    tri, cross = _triangles(vertices, faces)
    area = 0.5 * np.linalg.norm(cross, axis=1)
    total = float(area.sum())
    centroid = (area[:, None] * tri.mean(axis=1)).sum(axis=0) / total
    t = tri - centroid
    g = t.mean(axis=1)
    second = np.einsum("f,fij,fik->jk", area, t, t) + 9.0 * np.einsum("f,fj,fk->jk", area, g, g)
    return centroid, second / (12.0 * total)


def footprint_axis(vertices: np.ndarray, faces: np.ndarray) -> dict:
    """The footprint's long axis in x-y: ``{"axis", "moments", "skew", "sign_rule", "round"}``.

    The surface projected onto x-y, each triangle weighted by its projected
    area, its exact second moments in the plane; the axis is the eigenvector
    of the larger moment, signed by the third moment of the projected faces'
    centroids along it (positive to +axis), or, for a symmetric footprint, so
    that it makes an acute angle with +y (the smallest turn).
    """
    tri = vertices[faces][:, :, :2]
    e1, e2 = tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
    weight = 0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
    total = float(weight.sum())
    if not total > 0:
        return {"axis": None, "moments": (0.0, 0.0), "skew": 0.0, "sign_rule": None, "round": True}
    centroid = (weight[:, None] * tri.mean(axis=1)).sum(axis=0) / total
    t = tri - centroid
    g = t.mean(axis=1)
    second = np.einsum("f,fij,fik->jk", weight, t, t) + 9.0 * np.einsum("f,fj,fk->jk", weight, g, g)
    second /= 12.0 * total
    values, vectors = np.linalg.eigh(second)
    small, large = float(values[0]), float(values[1])
    axis = vectors[:, 1]
    along = g @ axis
    skew = float(np.sum(weight * along**3) / total)
    spread = math.sqrt(max(large, 0.0))
    if abs(skew) >= SKEW_TOLERANCE * spread**3:
        rule = "skew"
        if skew < 0:
            axis, skew = -axis, -skew
    else:
        rule = "smallest turn"
        if axis[1] < 0 or (axis[1] == 0 and axis[0] > 0):
            axis, skew = -axis, -skew
    is_round = not (large - small) >= ROUND_MARGIN * large
    return {
        "axis": axis,
        "moments": (large, small),
        "skew": skew,
        "sign_rule": rule,
        "round": is_round,
    }


def boundary_loops(
    vertices: np.ndarray, faces: np.ndarray, edges: np.ndarray | None = None
) -> list[np.ndarray]:
    """The boundary's connected sets of edges (each (k, 2) directed edges), longest first.

    `edges`: the boundary edges (:func:`dentopo.mesh.boundary_edges`), if the caller has them.
    """
    if edges is None:
        edges = boundary_edges(faces, len(vertices))
    if len(edges) == 0:
        return []
    n = len(vertices)
    graph = coo_matrix((np.ones(len(edges), dtype=np.int8), (edges[:, 0], edges[:, 1])), (n, n))
    _, label = connected_components(graph, directed=False)
    loop = label[edges[:, 0]]
    length = np.linalg.norm(vertices[edges[:, 1]] - vertices[edges[:, 0]], axis=1)
    ids, first = np.unique(loop, return_index=True)
    sums = np.bincount(loop, weights=length)[ids]
    # longest first; ties by the first edge's place (deterministic for a given mesh)
    order = sorted(range(len(ids)), key=lambda i: (-sums[i], first[i]))
    return [edges[loop == ids[i]] for i in order]


def fit_base_plane(vertices: np.ndarray, edges: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """The least-squares plane of a loop of edges: (centroid, unit normal, RMS distance).

    Each edge is a segment weighted by its length; a segment from a to b
    about its midpoint m has second moment ``(m m^T + d d^T / 12)`` per length
    (``d = b - a``), so that the fit does not depend on how finely the loop is cut.
    """
    a, b = vertices[edges[:, 0]], vertices[edges[:, 1]]
    d = b - a
    length = np.linalg.norm(d, axis=1)
    total = float(length.sum())
    middle = 0.5 * (a + b)
    centroid = (length[:, None] * middle).sum(axis=0) / total
    m = middle - centroid
    second = (
        np.einsum("e,ej,ek->jk", length, m, m) + np.einsum("e,ej,ek->jk", length, d, d) / 12.0
    ) / total
    values, vectors = np.linalg.eigh(second)
    return centroid, vectors[:, 0], math.sqrt(max(float(values[0]), 0.0))


def _transform(rotation: np.ndarray, centre: np.ndarray) -> np.ndarray:
    """``[[R, -R c], [0, 1]]``: rotate, then move the rotated `centre` to the origin."""
    out = np.eye(4)
    out[:3, :3] = rotation
    out[:3, 3] = -rotation @ centre
    return out


def _as_is(vertices, faces, rule: str, message: str, details: dict) -> Outcome:
    details = {"rule": rule, "tilt_degrees": 0.0, "turned": False, **details}
    return Outcome(
        vertices.copy(), faces.copy(), transform=np.eye(4), details=details, warnings=(message,)
    )


def _closed_volume(vertices, faces, edges, cross) -> tuple[float, np.ndarray]:
    """The volume closed over the boundary (faces made to agree first), and the agreeing faces."""
    agreeing = orient_consistently(faces, len(vertices))
    if agreeing is faces:
        return closed_volume(vertices, faces, edges, cross), faces
    return closed_volume(vertices, agreeing, boundary_edges(agreeing, len(vertices))), agreeing


def _find_up(vertices: np.ndarray, faces: np.ndarray):
    """(direction or None, centre, plane or None, rule, details, warnings) of the occlusal side."""
    tri, cross = _triangles(vertices, faces)
    area = 0.5 * np.linalg.norm(cross, axis=1)
    total = float(area.sum())
    edges = boundary_edges(faces, len(vertices))
    volume, agreeing = _closed_volume(vertices, faces, edges, cross)
    if not abs(volume) > FLAT_TOLERANCE * total**1.5:
        message = (
            "the surface is flat (it encloses no volume over its open base): it has no up or "
            f"down, so it was left as it is; {_SUGGEST}"
        )
        ratio = abs(volume) / total**1.5 if total > 0 else 0.0
        return None, None, None, "flat", {"volume_ratio": ratio}, (message,)
    loops = boundary_loops(vertices, faces, edges)
    size = float(np.linalg.norm(np.ptp(vertices, axis=0)))
    if loops:
        point, normal, rms = fit_base_plane(vertices, loops[0])
        centroid = (area[:, None] * tri.mean(axis=1)).sum(axis=0) / total
        side = float((centroid - point) @ normal)
        ends = vertices[loops[0]]
        base_length = float(np.linalg.norm(ends[:, 1] - ends[:, 0], axis=1).sum())
        details = {
            "boundary_loops": len(loops),
            "holes": len(loops) - 1,
            "base_edges": len(loops[0]),
            "base_length": base_length,
            "base_rms": rms,
        }
        if not abs(side) > SIDE_TOLERANCE * size:
            message = (
                "the crown's centroid lies on the plane of its open base: which side is up is "
                f"undetermined, so it was left as it is; {_SUGGEST}"
            )
            return None, None, None, "open base", details, (message,)
        if side < 0:
            normal = -normal
        found = ()
        if base_length < SMALL_BASE * size:
            found = (
                f"the open base is small (its loop is {base_length:.4g} long, the crown "
                f"{size:.4g} across): if the surface is closed but for a hole, the hole's plane "
                f"was levelled; check it, or {_SUGGEST}",
            )
        return normal, point, (point, normal), "open base", details, found
    # closed: the shortest principal axis, its side by the area rule
    centroid, second = surface_moments(vertices, faces)
    values, vectors = np.linalg.eigh(second)
    axis = vectors[:, 0]
    outward = agreeing if volume > 0 else agreeing[:, ::-1]
    _, out_cross = _triangles(vertices, outward)
    facing = out_cross @ axis
    up, down = float(area[facing > 0].sum()), float(area[facing < 0].sum())
    details = {
        "principal_moments": [float(x) for x in values],
        "area_up": up,
        "area_down": down,
    }
    distinct = values[0] <= (1.0 - AXIS_MARGIN) * values[1]
    if not distinct or abs(up - down) < CLOSED_MARGIN * (up + down):
        why = (
            "its shortest principal axis is not distinct from the next"
            if not distinct
            else "neither side of its shortest principal axis has most of its area facing it"
        )
        message = (
            f"the surface is closed (it has no open base to tell up from down) and {why}: "
            f"it was left as it is; {_SUGGEST}"
        )
        return None, None, None, "area", details, (message,)
    if down > up:
        axis = -axis
    message = (
        "the surface is closed (it has no open base): it was turned so that its shortest "
        "principal axis points up, to the side most of its area faces; a guess from its shape "
        f"(a whole tooth's long axis is its up): check it, or {_SUGGEST}"
    )
    return axis, centroid, None, "area", details, (message,)


def run(vertices: np.ndarray, faces: np.ndarray, *, mode: str, up, spin: str) -> Outcome:
    """Turn the crown occlusal side up (see the module's rules); never modifies its arguments.

    Parameters
    ----------
    vertices : (n, 3) float
    faces : (m, 3) int
    mode : {"occlusal", "none"}
        ``"none"`` returns the mesh as it is (the identity).
    up : (3,) float or None
        The occlusal direction by hand (no base is looked for).
    spin : {"none", "footprint"}
        Also turn about z so that the footprint's long axis lies along +y.

    Returns
    -------
    Outcome
        ``transform`` the 4x4 rigid motion (``new = R @ old + t``), ``plane`` the
        base plane found (open crown) in the input's coordinates, ``details``
        with ``rule`` (``"open base"``, ``"area"``, ``"flat"``, ``"up"`` or
        ``"none"``), ``turned``, ``tilt_degrees`` (the levelling rotation's
        angle), ``up`` (the input's direction that became +z), ``spin_degrees``...
    """
    vertices = np.asarray(vertices, dtype=np.float64)
    faces = np.asarray(faces, dtype=np.int64)
    if mode == "none":
        return Outcome(
            vertices.copy(),
            faces.copy(),
            transform=np.eye(4),
            details={"rule": "none", "tilt_degrees": 0.0, "turned": False},
        )
    if mode != "occlusal":
        raise ValueError(f"orient mode must be 'occlusal' or 'none'; got {mode!r}")
    if spin not in ("none", "footprint"):
        raise ValueError(f"spin must be 'none' or 'footprint'; got {spin!r}")
    plane = None
    warnings: list[str] = []
    if up is not None:
        direction = np.asarray(up, dtype=np.float64).reshape(3)
        try:  # scaled as the protocol checks it: its length neither overflows nor underflows
            direction = np.asarray(scaled_direction("up", direction), dtype=np.float64)
        except ProtocolError:
            raise ValueError(f"up must be a finite, non-zero direction; got {up!r}") from None
        direction = direction / np.linalg.norm(direction)
        centre, _ = surface_moments(vertices, faces)
        rule, details = "up", {}
    else:
        direction, centre, plane, rule, details, found = _find_up(vertices, faces)
        warnings.extend(found)
        if direction is None:
            if spin != "none":
                details["spin"] = "not spun: the crown was not levelled"
            return _as_is(vertices, faces, rule, " ".join(warnings), details)
    rotation = rotation_to_z(direction)
    details.update(
        {
            "rule": rule,
            "turned": True,
            "up": [float(x) for x in direction],
            "tilt_degrees": rotation_angle(rotation),
        }
    )
    if spin == "footprint":
        levelled = vertices @ rotation.T
        found_axis = footprint_axis(levelled, faces)
        if found_axis["round"]:
            warnings.append(
                "the footprint is round (its two principal moments differ by less than "
                f"{ROUND_MARGIN:.0%}): it has no long axis, so it was not spun"
            )
            details.update({"spin_degrees": 0.0, "spin": "round footprint: not spun"})
        else:
            ax, ay = found_axis["axis"]
            angle = math.pi / 2 - math.atan2(ay, ax)
            angle = math.atan2(math.sin(angle), math.cos(angle))  # to (-pi, pi]
            rotation = _about_z(angle) @ rotation
            details.update(
                {
                    "spin_degrees": math.degrees(angle),
                    "spin": f"footprint long axis to +y (sign by {found_axis['sign_rule']})",
                    "footprint_moments": list(found_axis["moments"]),
                }
            )
    transform = _transform(rotation, centre)
    new_vertices = vertices @ rotation.T + transform[:3, 3]
    details["translation"] = [float(x) for x in transform[:3, 3]]
    return Outcome(
        new_vertices,
        faces.copy(),
        transform=transform,
        plane=None if plane is None else (plane[0].copy(), plane[1].copy()),
        details=details,
        warnings=tuple(warnings),
    )
