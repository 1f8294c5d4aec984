"""The preview of a preparation: the mesh cleaned and oriented (the crop slider's), and prepared.

Computed here, in the server's process (a thread of its own), by the library:
:func:`dentopo.prepare` run in two parts, the second part the rest of the
protocol run on the first's mesh, so that nothing is done twice; each mesh is
sent packed as the report packs its meshes, at most :data:`VIEW_FACES` faces
(a larger one decimated for the view only).
"""

from __future__ import annotations

import numpy as np

from ..mesh import load_mesh
from ..prepare import Protocol, ProtocolError
from ..report import pack_mesh
from ._errors import AppError
from ._folder import MeshEntry, simplified

#: Faces the page's 3D view draws at most (a larger mesh is decimated for the view only).
VIEW_FACES = 150_000


def preview(entry: MeshEntry, relative: str, protocol: Protocol) -> dict:
    """The preview of `protocol` on the mesh `entry` (named `relative` on the page)."""
    try:
        mesh = load_mesh(entry.real)
    except Exception as exc:
        raise AppError(f"cannot read {relative}: {exc}") from None
    try:
        oriented, rest = prepared_in_two(mesh, protocol)
    except (ValueError, ProtocolError) as exc:
        raise AppError(str(exc), 422) from None
    for made, steps in ((oriented, "cleaning and orienting"), (rest, "the protocol")):
        if not np.isfinite(np.asarray(made.vertices)).all():  # never drawn, never sent as NaN
            hint = (
                f" (the {protocol.smooth} smoothing diverges: a smaller step or fewer iterations)"
                if protocol.smooth is not None and made is rest
                else ""
            )
            raise AppError(f"{steps} made coordinates that are not finite{hint}", 422)
    rotation = np.asarray(oriented.transform)[:3, :3]
    found_up = rotation.T @ np.array([0.0, 0.0, 1.0])
    z = np.asarray(oriented.vertices)[:, 2]
    return {
        "oriented": _view_payload(oriented.vertices, oriented.faces),
        "prepared": _view_payload(rest.vertices, rest.faces),
        "z_min": float(z.min()),
        "z_max": float(z.max()),
        "found_up": [round(float(x), 6) for x in found_up],
        "steps": [
            {
                "name": s.name,
                "vertices_before": s.vertices_before,
                "vertices_after": s.vertices_after,
                "faces_before": s.faces_before,
                "faces_after": s.faces_after,
                "warnings": list(s.warnings),
            }
            for s in (*oriented.steps, *rest.steps)
        ],
        "warnings": [*oriented.warnings, *rest.warnings],
        "label": protocol.label,
        "display_faces": min(len(rest.faces), VIEW_FACES),
    }


def prepared_in_two(mesh, protocol: Protocol):
    """(the mesh cleaned and oriented, then the rest of `protocol` run on that).

    The first is what the crop slider is drawn on; the second is the mesh
    ``dentopo.prepare(mesh, protocol)`` makes, to the bit (the steps run in a fixed
    order, each on what the one before made; tests/test_app_parts.py checks it),
    without cleaning and orienting twice (1.2 s of a 1M-face scan's 2.8 s).
    """
    from ..prepare import prepare

    placing = {"clean": protocol.clean, "keep": protocol.keep, "orient": protocol.orient}
    placing.update(up=protocol.up, spin=protocol.spin)
    oriented = prepare(mesh, Protocol(**placing))
    rest = prepare(
        oriented.mesh, protocol.replace(clean=False, orient="none", up=None, spin="none")
    )
    return oriented, rest


def _view_payload(vertices, faces) -> dict:
    from ..figures import color_scale

    vertices, faces = simplified(vertices, faces, VIEW_FACES)
    return pack_mesh(vertices, faces, np.zeros(len(vertices)), color_scale(limits=(-1.0, 1.0)))
