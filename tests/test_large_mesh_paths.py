"""Shortcuts that keep cleaning and orientation linear on large meshes behave as before."""

from __future__ import annotations

import numpy as np
import trimesh

from conftest import plane_patch
from dentopo.mesh import clean, orient_consistently
from dentopo.mesh._prepare import _may_have_small_holes


def _trimesh_fill_holes(mesh):
    copy = trimesh.Trimesh(mesh.vertices, mesh.faces, process=False)
    copy.fill_holes()
    return copy


def test_fill_holes_is_skipped_only_where_it_adds_nothing(sphere, tooth):
    open_sphere = trimesh.Trimesh(sphere.vertices, sphere.faces[1:], process=False)
    square_hole = trimesh.Trimesh(sphere.vertices, sphere.faces[2:], process=False)
    cases = [(sphere, False), (tooth, False), (plane_patch(), False)]
    cases += [(open_sphere, True), (square_hole, True)]
    for mesh, expected in cases:
        faces = np.asarray(mesh.faces)
        assert _may_have_small_holes(faces, len(mesh.vertices)) == expected
        added = len(_trimesh_fill_holes(mesh).faces) - len(faces)
        assert (added > 0) == expected  # the check agrees with what trimesh does
    cleaned = clean(np.asarray(open_sphere.vertices), np.asarray(open_sphere.faces))
    assert len(cleaned.faces) == len(sphere.faces)  # the 3-edge hole was filled


def test_orientation_walk_restores_a_scrambled_mesh(tooth):
    faces = np.asarray(tooth.faces)
    rng = np.random.default_rng(0)
    scrambled = faces.copy()
    flip = rng.random(len(faces)) < 0.3
    scrambled[flip] = scrambled[flip][:, ::-1]
    fixed = orient_consistently(scrambled, len(tooth.vertices))
    agrees = (fixed == faces).all(axis=1)
    assert agrees.all() or (~agrees).all()  # consistent, up to one global flip
    assert orient_consistently(faces, len(tooth.vertices)) is faces  # consistent: untouched
