"""``prepare``: run a protocol's steps in order on a private copy, recording each."""

from __future__ import annotations

import hashlib
import os
import warnings

import numpy as np

from ..mesh import as_arrays, load_mesh, vertex_areas
from ..mesh._validate import check_finite
from . import _clean, _crop, _decimate, _orient, _smooth
from ._protocol import Protocol, load_protocol
from ._result import Outcome, PreparedCrown, Step, frozen_array


class PrepareWarning(UserWarning):
    """Something a preparation step did or could not do that the user should know."""


def _sha256(path: str | os.PathLike) -> str:
    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        for block in iter(lambda: handle.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def _area(vertices: np.ndarray, faces: np.ndarray) -> float:
    return float(vertex_areas(vertices, faces).sum()) if len(faces) else 0.0


def _parameters(parameters: dict) -> str:
    """A step's parameters in a message: ``method=laplacian, iterations=10, step=0.5``."""
    return ", ".join(f"{key}={value}" for key, value in parameters.items() if value is not None)


def _check_output(name: str, parameters: dict, vertices: np.ndarray, area: float) -> None:
    """The safety net under every step: its mesh is finite and measurable, else a ValueError.

    Each step checks what it can; whatever a step (or a library it calls) lets
    through, a NaN or infinite coordinate, a mesh beyond double precision's
    range (:func:`dentopo.mesh.check_finite`), or an area that overflows, stops
    the preparation here, naming the step and its parameters, so that no such
    mesh is ever returned or written.
    """
    where = f"the {name} step ({_parameters(parameters)}) gave an unusable mesh: "
    check_finite(vertices, where=where)
    if not np.isfinite(area):
        raise ValueError(f"{where}its area overflows")


def _runs(protocol: Protocol):
    """(name, parameters as recorded, the step function's keyword arguments) for each step run."""
    steps = protocol.steps()
    for name, parameters in steps.items():
        if name == "clean":
            yield name, parameters, _clean.run, {"keep": protocol.keep}
        elif name == "orient":
            yield (
                name,
                parameters,
                _orient.run,
                {"mode": protocol.orient, "up": protocol.up, "spin": protocol.spin},
            )
        elif name == "crop":
            yield (
                name,
                parameters,
                _crop.run,
                {
                    "below": protocol.crop_below,
                    "fraction": protocol.crop_fraction,
                    "plane": protocol.crop_plane,
                },
            )
        elif name == "decimate":
            yield (
                name,
                parameters,
                _decimate.run,
                {"faces_target": protocol.faces, "method": protocol.decimate},
            )
        elif name == "smooth":
            options = dict(parameters)
            options.pop("method")
            yield name, parameters, _smooth.run, {"method": protocol.smooth, **options}


def run(mesh, protocol=None, *, geometry: str | None = None, **changes) -> PreparedCrown:
    """Run `protocol`, changed by `changes`, on `mesh` (documented at :func:`dentopo.prepare`)."""
    protocol = load_protocol(protocol)
    if changes:
        protocol = protocol.replace(**changes)
    source = sha = None
    if isinstance(mesh, (str, os.PathLike)):
        source = os.fspath(mesh)
        sha = _sha256(mesh)
        mesh = load_mesh(mesh, geometry=geometry)
    vertices, faces = as_arrays(mesh)
    transform = np.eye(4)
    steps: list[Step] = []
    found_warnings: list[str] = []
    area = _area(vertices, faces)
    for name, parameters, function, options in _runs(protocol):
        outcome: Outcome = function(vertices, faces, **options)
        v = np.asarray(outcome.vertices, dtype=np.float64)
        f = np.asarray(outcome.faces, dtype=np.int64)
        if len(f) == 0:
            raise ValueError(f"the {name} step left no faces")
        with np.errstate(over="ignore", invalid="ignore"):
            area_after = _area(v, f)
        _check_output(name, parameters, v, area_after)
        step_transform = None
        if outcome.transform is not None:
            step_transform = frozen_array(outcome.transform, np.float64)
            transform = step_transform @ transform
        plane = None
        if outcome.plane is not None:
            point, normal = outcome.plane
            plane = {"point": [float(x) for x in point], "normal": [float(x) for x in normal]}
        steps.append(
            Step(
                name=name,
                parameters=parameters,
                vertices_before=len(vertices),
                vertices_after=len(v),
                faces_before=len(faces),
                faces_after=len(f),
                area_before=area,
                area_after=area_after,
                transform=step_transform,
                plane=plane,
                pieces_removed=int(outcome.pieces_removed),
                details=dict(outcome.details),
                warnings=tuple(outcome.warnings),
            )
        )
        found_warnings.extend(f"{name}: {text}" for text in outcome.warnings)
        vertices, faces, area = v, f, area_after
    for text in found_warnings:
        warnings.warn(text, PrepareWarning, stacklevel=2)
    return PreparedCrown(
        vertices=frozen_array(vertices, np.float64),
        faces=frozen_array(faces, np.int64),
        protocol=protocol,
        steps=tuple(steps),
        transform=frozen_array(transform, np.float64),
        warnings=tuple(found_warnings),
        source=source,
        source_sha256=sha,
    )
