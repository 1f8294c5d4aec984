"""Files that hold a scene (GLB, OBJ objects, 3MF): one mesh in world coordinates, or a choice.

A file with several meshes is never measured by picking one silently, nor by
measuring them together unasked: ``load_mesh`` (and everything that reads a
path) raises, naming the meshes, unless ``geometry`` says which, or ``"all"``.
"""

from __future__ import annotations

import csv

import numpy as np
import pytest
import trimesh

from dentopo import ariaDNE, compute_batch, load_mesh
from dentopo.cli import main
from dentopo.mesh import check_geometry
from dentopo.mesh._read import _obj_options
from dentopo.samples import tooth

#: Where the crown sits in the scenes below: rotated, scaled by 2 and moved.
PLACE = trimesh.transformations.concatenate_matrices(
    trimesh.transformations.translation_matrix([10.0, -3.0, 2.0]),
    trimesh.transformations.rotation_matrix(0.7, [1.0, 2.0, 0.5]),
    trimesh.transformations.scale_matrix(2.0),
)


def crown():
    return tooth(rings=8)


def root():
    return trimesh.creation.icosphere(subdivisions=2).apply_translation([0.0, 0.0, -3.0])


def scene_file(path, parts):
    """Write a scene of ``{name: (mesh, transform)}`` to `path`; return the path."""
    scene = trimesh.Scene()
    for name, (mesh, transform) in parts.items():
        scene.add_geometry(mesh, geom_name=name, node_name=name, transform=transform)
    scene.export(path)
    return path


def stored(path, name):
    """The mesh as the file stores it (GLB keeps float32), before its transform."""
    return trimesh.load(path, force="scene").geometry[name]


def obj_text(objects, *, materials=None):
    """OBJ text with one ``o`` per mesh; `materials` splits each object's faces in two."""
    lines, offset = [], 0
    if materials:
        lines.append("mtllib parts.mtl")
    for name, mesh in objects.items():
        lines.append(f"o {name}")
        lines += [f"v {x:.17g} {y:.17g} {z:.17g}" for x, y, z in mesh.vertices]
        faces = [f"f {a + 1 + offset} {b + 1 + offset} {c + 1 + offset}" for a, b, c in mesh.faces]
        if materials:
            half = len(faces) // 2
            faces = [
                f"usemtl {materials[0]}",
                *faces[:half],
                f"usemtl {materials[1]}",
                *faces[half:],
            ]
        lines += faces
        offset += len(mesh.vertices)
    return "\n".join(lines) + "\n"


def same_totals(a, b, *, rtol=1e-9):
    for name in ("dne", "positive_dne", "negative_dne", "surface_area"):
        assert getattr(a, name) == pytest.approx(getattr(b, name), rel=rtol, abs=1e-12), name


def sorted_rows(points):
    points = np.asarray(points)
    return points[np.lexsort(points.T[::-1])]


# --------------------------------------------------------------------------------------------
# one mesh in the file: used, in world coordinates
# --------------------------------------------------------------------------------------------


def test_one_placed_mesh_is_read_in_world_coordinates(tmp_path):
    path = scene_file(tmp_path / "one.glb", {"crown": (crown(), PLACE)})
    local = stored(path, "crown")
    mesh = load_mesh(path)
    assert np.allclose(mesh.vertices, trimesh.transform_points(local.vertices, PLACE), atol=1e-12)
    # DNE does not depend on position, orientation or scale; the area does (scale 2: 4x)
    placed, unplaced = ariaDNE(path), ariaDNE(local)
    assert placed.dne == pytest.approx(unplaced.dne, rel=1e-9)
    assert placed.positive_dne == pytest.approx(unplaced.positive_dne, rel=1e-9)
    assert placed.surface_area == pytest.approx(4 * unplaced.surface_area, rel=1e-9)


def test_a_mirrored_placement_keeps_the_signs(tmp_path):
    mirror = np.diag([-1.0, 1.0, 1.0, 1.0])
    path = scene_file(tmp_path / "mirrored.glb", {"crown": (crown(), mirror)})
    direct = stored(path, "crown").copy()
    direct.vertices[:, 0] *= -1  # the mirror image, built directly, faces turned back outward
    direct.invert()
    same_totals(ariaDNE(path), ariaDNE(direct))


def test_a_single_mesh_file_is_unchanged(tmp_path):
    path = tmp_path / "crown.ply"
    crown().export(path)
    assert np.array_equal(load_mesh(path).vertices, trimesh.load(path).vertices)
    assert np.array_equal(load_mesh(path, geometry="all").faces, trimesh.load(path).faces)


# --------------------------------------------------------------------------------------------
# several meshes: an error unless the caller chooses
# --------------------------------------------------------------------------------------------


@pytest.fixture
def two_glb(tmp_path):
    return scene_file(tmp_path / "two.glb", {"crown": (crown(), PLACE), "root": (root(), None)})


def test_several_meshes_are_an_error_naming_them(two_glb):
    with pytest.raises(ValueError, match="holds 2 meshes") as caught:
        load_mesh(two_glb)
    message = str(caught.value)
    assert repr(str(two_glb)) in message
    assert f"'crown' ({len(crown().faces)} faces)" in message
    assert f"'root' ({len(root().faces)} faces)" in message
    # the library names its keyword arguments; the command, its options (below)
    assert "geometry='crown'" in message and "geometry='all'" in message
    assert "--geometry" not in message
    with pytest.raises(ValueError, match="holds 2 meshes"):
        ariaDNE(two_glb)  # every path goes through load_mesh


def test_a_named_mesh_is_read_in_world_coordinates(two_glb):
    mesh = load_mesh(two_glb, geometry="crown")
    expected = trimesh.transform_points(stored(two_glb, "crown").vertices, PLACE)
    assert np.allclose(mesh.vertices, expected, atol=1e-12)
    assert len(load_mesh(two_glb, geometry="root").faces) == len(root().faces)


def test_all_joins_the_meshes_in_world_coordinates(two_glb):
    joined = load_mesh(two_glb, geometry="all")
    placed = stored(two_glb, "crown").copy().apply_transform(PLACE)
    expected = trimesh.util.concatenate([placed, stored(two_glb, "root")])
    assert len(joined.faces) == len(expected.faces)
    assert np.allclose(sorted_rows(joined.vertices), sorted_rows(expected.vertices), atol=1e-12)
    same_totals(ariaDNE(joined), ariaDNE(expected))


def test_all_rejoins_a_surface_stored_in_pieces(tmp_path):
    whole = crown()
    left = whole.vertices[whole.faces].mean(axis=1)[:, 0] < 0
    halves = whole.submesh([np.flatnonzero(left), np.flatnonzero(~left)], append=False)
    path = scene_file(tmp_path / "halves.glb", {"a": (halves[0], None), "b": (halves[1], None)})
    assert sum(len(h.vertices) for h in halves) > len(whole.vertices)  # the seam, twice
    joined = load_mesh(path, geometry="all")
    assert len(joined.vertices) == len(whole.vertices)  # the seam merged again
    same_totals(ariaDNE(joined), ariaDNE(whole), rtol=1e-6)  # GLB stores float32


def test_a_missing_name_is_an_error_listing_the_names(two_glb):
    with pytest.raises(ValueError, match="no geometry named 'crwn'") as caught:
        load_mesh(two_glb, geometry="crwn")
    assert "'crown'" in str(caught.value) and "'root'" in str(caught.value)


def test_each_placement_of_a_geometry_counts(tmp_path):
    scene = trimesh.Scene()
    scene.add_geometry(crown(), geom_name="molar", node_name="left")
    scene.graph.update(frame_to="right", geometry="molar", matrix=PLACE)
    path = tmp_path / "pair.glb"
    scene.export(path)
    with pytest.raises(ValueError, match="holds 2 meshes") as caught:
        load_mesh(path)
    assert "node 'left' of 'molar'" in str(caught.value)
    with pytest.raises(ValueError, match="placed 2 times"):
        load_mesh(path, geometry="molar")
    right = load_mesh(path, geometry="right")
    local = stored(path, "molar")
    assert np.allclose(right.vertices, trimesh.transform_points(local.vertices, PLACE), atol=1e-12)
    assert np.allclose(load_mesh(path, geometry="left").vertices, local.vertices)
    assert len(load_mesh(path, geometry="all").faces) == 2 * len(local.faces)


def test_the_option_is_checked():
    assert check_geometry(None) is None and check_geometry("crown") == "crown"
    with pytest.raises(TypeError, match="geometry must be"):
        check_geometry(3)
    with pytest.raises(ValueError, match="non-empty"):
        check_geometry("  ")


def test_a_point_cloud_is_not_a_mesh(tmp_path):
    path = tmp_path / "points.ply"
    trimesh.PointCloud(np.random.default_rng(0).random((20, 3))).export(path)
    with pytest.raises(ValueError, match="no triangle mesh, only PointCloud"):
        load_mesh(path)


# --------------------------------------------------------------------------------------------
# OBJ: one geometry per object, whatever its materials
# --------------------------------------------------------------------------------------------


def test_obj_objects_are_separate_meshes(tmp_path):
    path = tmp_path / "two.obj"
    path.write_text(obj_text({"crown": crown(), "root": root()}))
    # trimesh's own default merges objects without materials into one mesh
    assert len(trimesh.load(path).faces) == len(crown().faces) + len(root().faces)
    with pytest.raises(ValueError, match="holds 2 meshes: 'crown'"):
        load_mesh(path)
    same_totals(ariaDNE(load_mesh(path, geometry="crown")), ariaDNE(crown()))
    assert len(load_mesh(path, geometry="all").vertices) == len(crown().vertices) + len(
        root().vertices
    )


def test_obj_surface_split_by_material(tmp_path):
    (tmp_path / "parts.mtl").write_text("newmtl enamel\nKd 1 1 1\nnewmtl dentine\nKd 1 1 0\n")
    path = tmp_path / "coloured.obj"
    path.write_text(obj_text({"tooth": crown()}, materials=("enamel", "dentine")))
    # trimesh's default splits the one surface into a mesh per material, seam vertices doubled
    pieces = trimesh.load(path, force="scene").geometry.values()
    assert len(pieces) == 2
    assert sum(len(p.vertices) for p in pieces) > len(crown().vertices)
    whole = ariaDNE(crown())
    # "all" joins the pieces and merges the seam: the whole surface again
    joined = load_mesh(path, geometry="all")
    assert len(joined.vertices) == len(crown().vertices)
    same_totals(ariaDNE(joined), whole)
    if "split_objects" not in _obj_options():
        pytest.skip("trimesh < 4.10 splits an OBJ object at material changes: 'all' is needed")
    assert len(load_mesh(path).vertices) == len(crown().vertices)  # one object: one mesh
    same_totals(ariaDNE(path), whole)


def test_3mf_scene(tmp_path):
    pytest.importorskip("lxml", reason="trimesh writes and reads 3MF with lxml (not installed)")
    path = scene_file(tmp_path / "two.3mf", {"crown": (crown(), PLACE), "root": (root(), None)})
    with pytest.raises(ValueError, match="holds 2 meshes"):
        load_mesh(path)
    assert len(load_mesh(path, geometry="all").faces) == len(crown().faces) + len(root().faces)
    same_totals(ariaDNE(load_mesh(path, geometry="root")), ariaDNE(root()), rtol=1e-6)


# --------------------------------------------------------------------------------------------
# the batch and the command line
# --------------------------------------------------------------------------------------------


def rows_of(path):
    with open(path, newline="", encoding="utf-8") as stream:
        return {row["file"]: row for row in csv.DictReader(stream)}


@pytest.fixture
def folder(tmp_path, two_glb):
    single = tmp_path / "single.ply"
    crown().export(single)
    return str(two_glb), str(single)


def test_cli_without_geometry_gives_an_error_row(tmp_path, folder, capsys):
    scene, single = folder
    out = tmp_path / "out.csv"
    assert main([scene, single, "-o", str(out), "-q"]) == 1
    rows = rows_of(out)
    assert rows[single]["status"] == "ok"
    assert rows[scene]["status"] == "error" and rows[scene]["dne"] == ""
    assert "holds 2 meshes: 'crown'" in rows[scene]["error"]
    error = rows[scene]["error"]
    assert "read one with --geometry crown" in error and "surface with --geometry all" in error
    assert "geometry=" not in error and "load_mesh" not in error
    assert "--geometry crown" in capsys.readouterr().err


def test_cli_geometry_name(tmp_path, folder, capsys):
    scene, single = folder
    out = tmp_path / "out.csv"
    assert main([scene, single, "--geometry", "crown", "-o", str(out), "-q"]) == 1
    rows = rows_of(out)
    assert rows[scene]["status"] == "ok"
    assert float(rows[scene]["dne"]) == ariaDNE(load_mesh(scene, geometry="crown")).dne
    # the single mesh has another name: its row says which it has
    assert rows[single]["status"] == "error"
    assert "no geometry named 'crown'" in rows[single]["error"]
    assert "'single.ply'" in rows[single]["error"]
    capsys.readouterr()
    assert main([scene, "--geometry", "crown", "-o", str(out), "--resume"]) == 0
    assert "computing every file" in capsys.readouterr().err


def test_cli_geometry_all(tmp_path, folder):
    scene, single = folder
    out = tmp_path / "out.csv"
    assert main([scene, single, "--geometry", "all", "-o", str(out), "-q"]) == 0
    rows = rows_of(out)
    assert float(rows[scene]["dne"]) == ariaDNE(load_mesh(scene, geometry="all")).dne
    assert float(rows[single]["dne"]) == ariaDNE(single).dne


def test_cli_empty_geometry_is_a_usage_error(folder, capsys):
    assert main([folder[0], "--geometry", ""]) == 2
    assert "geometry" in capsys.readouterr().err


def test_compute_batch_geometry(folder):
    scene, single = folder
    records = {r["file"]: r for r in compute_batch([scene, single], geometry="root")}
    assert records[scene]["status"] == "ok"
    assert records[scene]["faces"] == len(root().faces)
    assert records[single]["status"] == "error"
    with pytest.raises(TypeError, match="geometry must be"):
        compute_batch([scene], geometry=["crown"])
