"""Shortcuts that keep cleaning and orientation linear on large meshes behave as before.

The compiled passes are checked against the numpy and trimesh forms they replace, bit for
bit, on meshes holding everything cleaning removes.
"""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from conftest import plane_patch
from dentopo.mesh import (
    boundary_edges,
    clean,
    orient_consistently,
    vertex_areas,
    vertex_normals,
)
from dentopo.mesh._prepare import _may_have_small_holes
from dentopo.mesh._topology import edge_uses


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
    # a 3-edge hole is the open sphere's only boundary, its base: left open, and said so
    cleaned = clean(np.asarray(open_sphere.vertices), np.asarray(open_sphere.faces))
    assert len(cleaned.faces) == len(open_sphere.faces)
    assert cleaned.metadata["cleaning"].bases_kept == (3,)
    # beside the crown's open base, the same hole is a defect: filled
    holed = np.delete(np.asarray(tooth.faces), 700, axis=0)
    cleaned = clean(np.asarray(tooth.vertices), holed)
    assert len(cleaned.faces) == len(tooth.faces)
    assert cleaned.metadata["cleaning"].holes_filled == 1


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


# --- compiled passes against the numpy and trimesh forms they replace ----------------------


def _dirty_meshes():
    """Meshes with what cleaning removes: slivers, repeated indices, duplicates, holes, soups."""
    from dentopo.samples import tooth

    rng = np.random.default_rng(5)
    base = tooth(rings=24)
    v, f = np.asarray(base.vertices), np.asarray(base.faces)
    yield "crown", v, f
    sliver = v.copy()
    sliver[f[40, 1]] = sliver[f[40, 0]] + 1e-13  # a face (and its neighbours) of no height
    extra = np.vstack([f[:9][:, [1, 2, 0]], f[30:36, ::-1], f[50:52], [[0, 0, 1], [7, 8, 7]]])
    dirty = np.vstack([f, extra])[rng.permutation(len(f) + len(extra))]
    yield "dirty", np.vstack([sliver, rng.normal(size=(4, 3))]), dirty
    yield "holes", v, np.delete(f, [100, 400, 401, 900], axis=0)
    yield "soup", rng.normal(size=(50, 3)), rng.integers(0, 50, size=(250, 3))
    grid = np.round(rng.normal(size=(30, 3)) * 2)  # coincident and collinear points
    yield "grid", grid, rng.integers(0, 30, size=(150, 3))


DIRTY = list(_dirty_meshes())


def _numpy_high_faces(vertices, faces, height):
    tri = vertices[faces]
    a, b = tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
    area = np.sqrt((np.cross(a, tri[:, 2] - tri[:, 1]) ** 2).sum(axis=1)) / 2.0
    keep = np.ones(len(faces), dtype=bool)
    for edge in (a, b):
        length = (edge**2).sum(axis=1) ** 0.5
        box = np.zeros(len(faces))
        long = length > height
        box[long] = (area[long] * 2) / length[long]
        keep &= box > height
    return keep


def _numpy_vertex_areas(vertices, faces):
    tri = vertices[faces]
    face_area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
    weights = np.repeat(face_area / 3.0, 3)
    return np.bincount(faces.ravel(), weights=weights, minlength=len(vertices))


def _numpy_vertex_normals(vertices, faces):
    tri = vertices[faces]
    normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    length = np.linalg.norm(normal, axis=1, keepdims=True)
    normal = np.divide(normal, length, out=np.zeros_like(normal), where=length > 0)
    corner = faces.T.ravel()
    summed = np.column_stack(
        [np.bincount(corner, np.tile(normal[:, a], 3), len(vertices)) for a in range(3)]
    )
    length = np.linalg.norm(summed, axis=1, keepdims=True)
    return np.divide(summed, length, out=np.zeros_like(summed), where=length > 0)


@pytest.mark.parametrize(("name", "vertices", "faces"), DIRTY, ids=[d[0] for d in DIRTY])
def test_compiled_face_passes_give_the_numpy_forms_bits(name, vertices, faces):
    from dentopo.mesh import _faces, length_scale

    for height in (0.0, 1e-7 * length_scale(vertices, faces), 1e-2):
        expected = _numpy_high_faces(vertices, faces, height)
        assert np.array_equal(_faces.high_faces(vertices, faces, height), expected)
    # bit for bit: the same operations in the same order
    assert np.array_equal(vertex_areas(vertices, faces), _numpy_vertex_areas(vertices, faces))
    assert np.array_equal(vertex_normals(vertices, faces), _numpy_vertex_normals(vertices, faces))


@pytest.mark.parametrize(("name", "vertices", "faces"), DIRTY, ids=[d[0] for d in DIRTY])
def test_first_faces_is_trimeshs_unique_faces(name, vertices, faces):
    from dentopo.mesh._faces import first_faces

    rng = np.random.default_rng(len(faces))
    for keep in (np.ones(len(faces), dtype=bool), rng.random(len(faces)) < 0.8):
        mesh = trimesh.Trimesh(vertices, faces[keep], process=False)
        expected = np.zeros(len(faces), dtype=bool)
        expected[np.flatnonzero(keep)[mesh.unique_faces()]] = True
        assert np.array_equal(first_faces(faces, keep, len(vertices)), expected)


def _not_closing_a_base(faces, filled):
    """Which faces of `filled` (`faces`, then the faces trimesh added) are kept: all but those
    closing a boundary loop at least as long as every other loop of its piece (its base)."""
    import networkx as nx

    mesh = trimesh.Trimesh(np.zeros((int(faces.max()) + 1, 3)), faces, process=False)
    boundary = mesh.edges_sorted[trimesh.grouping.group_rows(mesh.edges_sorted, require_count=1)]
    loops = [set(c) for c in nx.connected_components(nx.from_edgelist(boundary.tolist()))]
    length = [sum(1 for a, b in boundary if a in loop) for loop in loops]
    piece = {}
    for k, component in enumerate(nx.connected_components(nx.from_edgelist(mesh.edges.tolist()))):
        piece.update(dict.fromkeys(component, k))
    longest = {}
    for loop, n in zip(loops, length, strict=True):
        longest[piece[min(loop)]] = max(longest.get(piece[min(loop)], 0), n)
    keep = np.ones(len(filled), dtype=bool)
    for k in range(len(faces), len(filled)):
        for loop, n in zip(loops, length, strict=True):
            if set(filled[k].tolist()) <= loop and n >= longest[piece[min(loop)]]:
                keep[k] = False
    return keep


def _trimesh_clean(vertices, faces):
    """The published cleaning, step by step with trimesh (what ``clean`` must equal)."""
    from dentopo.mesh import length_scale, nondegenerate_faces

    scale = length_scale(vertices, faces)
    mesh = trimesh.Trimesh(vertices, faces, process=False)
    mesh.fill_holes()
    mesh.update_faces(_not_closing_a_base(faces, mesh.faces))
    mesh.update_faces(nondegenerate_faces(mesh.vertices, mesh.faces, scale=scale))
    mesh.update_faces(mesh.unique_faces())
    mesh.remove_unreferenced_vertices()
    return mesh


@pytest.mark.parametrize(("name", "vertices", "faces"), DIRTY, ids=[d[0] for d in DIRTY])
def test_clean_equals_trimeshs_steps(name, vertices, faces):
    before = (vertices.copy(), faces.copy())
    ours, theirs = clean(vertices, faces), _trimesh_clean(vertices, faces)
    assert np.array_equal(ours.vertices, theirs.vertices)
    assert np.array_equal(ours.faces, theirs.faces)
    assert np.array_equal(vertices, before[0]) and np.array_equal(faces, before[1])


def _sorting_boundary(faces):
    """Boundary edges by sorting undirected keys (the form ``boundary_edges`` replaced)."""
    directed = np.stack([faces.T.ravel(), np.roll(faces, -1, axis=1).T.ravel()], axis=1)
    _, inverse, counts = np.unique(
        np.sort(directed, axis=1), axis=0, return_inverse=True, return_counts=True
    )
    return directed[counts[inverse.ravel()] == 1]


@pytest.mark.parametrize(("name", "vertices", "faces"), DIRTY, ids=[d[0] for d in DIRTY])
def test_boundary_edges_and_repeated_edges_as_sorting_finds_them(name, vertices, faces):
    assert np.array_equal(boundary_edges(faces, len(vertices)), _sorting_boundary(faces))
    directed = np.stack([faces.T.ravel(), np.roll(faces, -1, axis=1).T.ravel()], axis=1)
    repeated = len(np.unique(directed, axis=0)) < len(directed)
    assert edge_uses(faces, len(vertices))[1] == repeated
    assert (orient_consistently(faces, len(vertices)) is faces) == (not repeated)
