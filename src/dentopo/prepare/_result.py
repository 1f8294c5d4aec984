"""What preparation did: a :class:`Step` per step run, and the frozen :class:`PreparedCrown`."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
import trimesh

from .._html_repr import array_summary, result_html, rows_html
from ._protocol import Protocol


def frozen_array(values, dtype) -> np.ndarray:
    """A private, read-only copy of `values`."""
    array = np.array(values, dtype=dtype, copy=True)
    array.setflags(write=False)
    return array


def _plain(value):
    """`value` made JSON-ready: arrays and tuples as lists, numpy scalars as Python numbers."""
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, (np.integer, np.floating, np.bool_)):
        return value.item()
    if isinstance(value, Mapping):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    return value


@dataclass(frozen=True)
class Outcome:
    """What one step function returns: the new mesh and what it did (see ``Step``)."""

    vertices: np.ndarray
    faces: np.ndarray
    transform: np.ndarray | None = None
    plane: tuple | None = None
    pieces_removed: int = 0
    details: Mapping = field(default_factory=dict)
    warnings: tuple[str, ...] = ()


@dataclass(frozen=True)
class Step:
    """One preparation step as run: its parameters and its effects.

    Attributes
    ----------
    name : str
        ``"clean"``, ``"orient"``, ``"crop"``, ``"decimate"`` or ``"smooth"``.
    parameters : mapping
        The step's parameters, defaults filled in (the protocol's ``steps()`` entry).
    vertices_before, vertices_after, faces_before, faces_after : int
        The mesh's size before and after the step.
    area_before, area_after : float
        Its surface area before and after (mesh units squared).
    transform : (4, 4) float or None
        The rigid motion the step applied to the vertices (orient), else None.
    plane : mapping or None
        ``{"point": [x, y, z], "normal": [nx, ny, nz]}``: the plane used (the
        base plane found by orient, the cutting plane of crop), else None.
    pieces_removed : int
        Connected pieces removed (clean with ``keep="largest"``; crop).
    details : mapping
        What else the step reports (e.g. the face count reached, the rule that
        found the occlusal direction).
    warnings : tuple of str
    """

    name: str
    parameters: Mapping
    vertices_before: int
    vertices_after: int
    faces_before: int
    faces_after: int
    area_before: float
    area_after: float
    transform: np.ndarray | None = None
    plane: Mapping | None = None
    pieces_removed: int = 0
    details: Mapping = field(default_factory=dict)
    warnings: tuple[str, ...] = ()

    @property
    def area_change(self) -> float:
        """The relative change of area, ``area_after / area_before - 1``."""
        return self.area_after / self.area_before - 1.0 if self.area_before > 0 else float("nan")

    def to_dict(self) -> dict:
        """The step as a JSON-ready record (the ``.prepare.json`` file's ``steps`` entries)."""
        return {
            "step": self.name,
            "parameters": _plain(self.parameters),
            "vertices": [self.vertices_before, self.vertices_after],
            "faces": [self.faces_before, self.faces_after],
            "area": [self.area_before, self.area_after],
            "area_change": self.area_change,
            "transform": None if self.transform is None else _plain(self.transform),
            "plane": None if self.plane is None else _plain(self.plane),
            "pieces_removed": self.pieces_removed,
            "details": _plain(self.details),
            "warnings": list(self.warnings),
        }

    def _repr_html_(self) -> str:
        return result_html(self)


@dataclass(frozen=True)
class PreparedCrown:
    """A prepared mesh and the record of how it was prepared (returned by :func:`prepare`).

    Attributes
    ----------
    vertices : (n, 3) float, read-only
    faces : (m, 3) int, read-only
    protocol : Protocol
        The protocol run.
    steps : tuple of Step
        Each step run, in order.
    transform : (4, 4) float, read-only
        The rigid motion from the input's coordinates to the prepared mesh's
        (the product of the steps' transforms; the identity if none moved it).
    warnings : tuple of str
        Every step's warnings.
    source : str or None
        The input file's path, if a path was given.
    source_sha256 : str or None
        The SHA-256 (hex) of the input file's bytes, if a path was given.
    """

    vertices: np.ndarray
    faces: np.ndarray
    protocol: Protocol
    steps: tuple[Step, ...]
    transform: np.ndarray
    warnings: tuple[str, ...] = ()
    source: str | None = None
    source_sha256: str | None = None

    @property
    def mesh(self) -> trimesh.Trimesh:
        """The prepared mesh as a new ``trimesh.Trimesh`` (a copy each time)."""
        return trimesh.Trimesh(
            vertices=self.vertices.copy(), faces=self.faces.copy(), process=False
        )

    @property
    def step_names(self) -> tuple[str, ...]:
        return tuple(step.name for step in self.steps)

    def step(self, name: str) -> Step:
        """The step called `name` (KeyError if it did not run)."""
        for step in self.steps:
            if step.name == name:
                return step
        raise KeyError(f"no {name!r} step ran (steps: {', '.join(self.step_names) or 'none'})")

    def to_dict(self) -> dict:
        """The record of the ``.prepare.json`` file (without dentopo's version; see ``formats``)."""
        return {
            "input": {"path": self.source, "sha256": self.source_sha256},
            "protocol": {
                "name": self.protocol.name,
                "digest": self.protocol.digest,
                **self.protocol.to_dict(),
            },
            "steps": [step.to_dict() for step in self.steps],
            "transform": _plain(self.transform),
            "result": {"vertices": len(self.vertices), "faces": len(self.faces)},
            "warnings": list(self.warnings),
        }

    def step_rows(self) -> list[dict]:
        """One row per step: name, parameters, faces and vertices before and after, area change."""
        return [
            {
                "step": step.name,
                "parameters": ", ".join(
                    f"{k}={v}" for k, v in step.parameters.items() if v is not None
                ),
                "faces": f"{step.faces_before} -> {step.faces_after}",
                "vertices": f"{step.vertices_before} -> {step.vertices_after}",
                "area_change": step.area_change,
                "pieces_removed": step.pieces_removed,
                "warnings": "; ".join(step.warnings),
            }
            for step in self.steps
        ]

    def _repr_html_(self) -> str:
        summary = {
            "protocol": self.protocol.label,
            "vertices": array_summary(self.vertices),
            "faces": array_summary(self.faces),
            "transform": array_summary(self.transform),
        }
        if self.source is not None:
            summary["source"] = self.source
        if self.warnings:
            summary["warnings"] = " ".join(self.warnings)
        return rows_html(self.step_rows(), title="PreparedCrown", summary=summary)
