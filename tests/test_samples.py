"""The shipped sample meshes are what our generator makes."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from dentopo.samples import NAMES, generate, sample_paths


@pytest.mark.parametrize("name", NAMES)
def test_shipped_sample_equals_generated(name):
    shipped = trimesh.load(sample_paths()[name])
    made = generate(name)
    np.testing.assert_array_equal(shipped.faces, made.faces)
    np.testing.assert_allclose(shipped.vertices, made.vertices, atol=1e-6)  # PLY float32


def test_generated_tooth_is_an_open_clean_crown():
    mesh = generate("tooth")
    assert not mesh.is_watertight and mesh.is_winding_consistent
    assert len(mesh.nondegenerate_faces()) == len(mesh.faces) == mesh.nondegenerate_faces().sum()


def test_unknown_sample():
    with pytest.raises(ValueError, match="unknown sample"):
        generate("molar")
