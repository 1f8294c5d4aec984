"""From raw scans to measurable crowns: ``dentopo prepare raw/ -o prepared/ --faces 10000``.

Raw scans are made from the paper's crowns: refined (the same surface, more
faces), turned to random poses, and given loose specks.  Prepared, each must
come back as one piece, occlusal side up with its base level, at the face
count asked for, and with the ariaDNE of the crown it was made from.
"""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from conftest import shared_mesh
from dentopo import ariaDNE
from dentopo.cli import main
from dentopo.mesh import boundary_edges, load_mesh
from dentopo.prepare._clean import face_pieces
from dentopo.study import refine
from dentopo.topography import find_orientation

#: The crowns the scans are made from, and the face count of their refined copies.
CROWNS = {"normal": 30_000, "high": 20_000}


def _random_rotation(rng) -> np.ndarray:
    q = rng.normal(size=4)
    q /= np.linalg.norm(q)
    w, x, y, z = q
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def _raw_scan(crown: trimesh.Trimesh, faces: int, rng) -> trimesh.Trimesh:
    """The crown refined to `faces`, turned and moved at random, with three loose specks."""
    v, f = np.asarray(crown.vertices), np.asarray(crown.faces)
    if faces > len(f):
        v, f = refine(v, f, faces)
    size = float(np.ptp(v, axis=0).max())
    parts = [trimesh.Trimesh(v, f, process=False)]
    for _ in range(3):
        speck = trimesh.creation.icosphere(subdivisions=1, radius=0.01 * size)
        speck.apply_translation(v.mean(axis=0) + (0.8 + rng.random(3)) * size)
        parts.append(speck)
    scan = trimesh.util.concatenate(parts)
    turned = scan.vertices @ _random_rotation(rng).T + rng.normal(size=3) * 10 * size
    return trimesh.Trimesh(turned, scan.faces, process=False)


def _base_normal(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """The unit normal of the least-squares plane through the boundary vertices."""
    ends = np.unique(boundary_edges(faces, len(vertices)))
    points = vertices[ends] - vertices[ends].mean(axis=0)
    return np.linalg.svd(points, full_matrices=False)[2][-1]


@pytest.fixture(scope="module")
def prepared(tmp_path_factory):
    rng = np.random.default_rng(20)
    root = tmp_path_factory.mktemp("scans")
    raw = root / "raw"
    raw.mkdir()
    originals = {}
    for name, faces in CROWNS.items():
        crown = load_mesh(shared_mesh(name))
        originals[name] = crown
        _raw_scan(crown, faces, rng).export(raw / f"{name}.ply")
    code = main(["prepare", str(raw), "-o", str(root / "prepared"), "--faces", "10000", "-q"])
    return code, root / "prepared", originals


def test_every_scan_is_prepared(prepared):
    code, folder, originals = prepared
    assert code == 0
    assert sorted(p.stem for p in folder.glob("*.ply")) == sorted(originals)
    assert sorted(p.name for p in folder.glob("*.prepare.json")) == sorted(
        f"{name}.prepare.json" for name in originals
    )


@pytest.mark.parametrize("name", sorted(CROWNS))
def test_one_piece_occlusal_side_up_at_the_face_count(prepared, name):
    _, folder, _ = prepared
    crown = load_mesh(folder / f"{name}.ply")
    v, f = np.asarray(crown.vertices), np.asarray(crown.faces)
    assert face_pieces(f, len(v))[0] == 1  # the specks are gone
    assert len(f) == pytest.approx(10_000, rel=0.01)
    assert find_orientation(v, f).points == "+z"
    tilt = np.degrees(np.arccos(abs(_base_normal(v, f)[2])))
    assert tilt < 1.0  # the base lies level


@pytest.mark.parametrize("name", sorted(CROWNS))
def test_ariadne_stays_within_a_few_percent(prepared, name):
    _, folder, originals = prepared
    before = ariaDNE(originals[name]).dne
    after = ariaDNE(folder / f"{name}.ply").dne
    assert after == pytest.approx(before, rel=0.03)
