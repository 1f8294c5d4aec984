"""Shared fixtures: generated meshes and the optional shared reference data."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import trimesh

#: The project's shared data lives beside the checkout (../shared), never inside it.
SHARED = Path(__file__).resolve().parents[2] / "shared"
MESHES = SHARED / "data" / "meshes"
REFERENCE = SHARED / "data" / "reference"
ROBUSTNESS_SET = ("normal", "low", "high", "noise1", "noise2", "smooth")


def shared_mesh(name: str) -> Path:
    """Path of a shared mesh; skips the test with the reason when it is absent."""
    path = MESHES / f"{name}.ply"
    if not path.exists():
        pytest.skip(f"shared data not found at {path} (expected beside the checkout)")
    return path


@pytest.fixture(scope="session")
def reference():
    path = REFERENCE / "signdne_0.1.4.json"
    if not path.exists():
        pytest.skip(f"published reference values not found at {path}")
    return json.loads(path.read_text())["meshes"]


@pytest.fixture(scope="session")
def reference_curvature():
    path = REFERENCE / "signdne_0.1.4_local_curvature.npz"
    if not path.exists():
        pytest.skip(f"published per-vertex curvature not found at {path}")
    with np.load(path) as data:
        return {name: data[name] for name in data.files}


@pytest.fixture
def sphere():
    return trimesh.creation.icosphere(subdivisions=3)


@pytest.fixture
def tooth():
    from dentopo.samples import tooth

    return tooth(rings=16)


def plane_patch(n: int = 21) -> trimesh.Trimesh:
    """A flat, regularly triangulated square in the z = 0 plane."""
    x, y = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n))
    vertices = np.column_stack([x.ravel(), y.ravel(), np.zeros(n * n)])
    idx = np.arange(n * n).reshape(n, n)
    a, b, c, d = (
        idx[:-1, :-1].ravel(),
        idx[:-1, 1:].ravel(),
        idx[1:, :-1].ravel(),
        idx[1:, 1:].ravel(),
    )
    faces = np.concatenate([np.column_stack([a, b, d]), np.column_stack([a, d, c])])
    return trimesh.Trimesh(vertices, faces, process=False)


@pytest.fixture
def plane():
    return plane_patch()
