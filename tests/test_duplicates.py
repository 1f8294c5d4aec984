"""Faces listed twice: every metric of a row measures the same surface, each triangle once.

A mesh whose faces are listed twice (or some of them) used to get classic DNE, RFI, OPC/OPCR
and slope from the raw faces (classic DNE doubled, OPC fell to 0) while the row's ``faces``
column, from ariaDNE's cleaning, showed the cleaned count (issue 22, item 1).  By default the
repeats are dropped and named in a warning; ``duplicates="keep"`` measures the faces as listed,
as molaR does.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import trimesh

from conftest import hemisphere, shared_mesh
from dentopo.batch._measure import TopographyOptions, measure_mesh
from dentopo.mesh import load_mesh
from dentopo.topography import classic_dne, opc, opcr, prepare_surface, rfi, slope

pytestmark = pytest.mark.filterwarnings("ignore:the crown points to -z:UserWarning")

REPEATED = "repeat an earlier face"


def dome() -> trimesh.Trimesh:
    """A low dome, open at its base, faces outward, none of zero area, none repeated."""
    mesh = hemisphere(rings=24, segments=48)
    mesh.vertices[:, 2] *= 0.6
    return prepare_surface(mesh).trimesh()  # the pole's faces of zero area dropped


def crowns():
    yield "dome", dome()
    try:
        yield "normal", load_mesh(shared_mesh("normal"))
    except pytest.skip.Exception:
        pass


def values(mesh) -> dict:
    """Every topography metric's scalar values on `mesh` (its warnings left to the caller)."""
    found = {}
    found.update({f"classic_{k}": v for k, v in classic_dne(mesh).to_dict().items()})
    found.update(rfi(mesh, find_alpha=True).to_dict())
    found.update(opc(mesh).to_dict())
    found["opcr"] = opcr(mesh).opcr
    found.update(slope(mesh).to_dict())
    return found


def _quiet(function, *args, **kwargs):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = function(*args, **kwargs)
    return result, [str(w.message) for w in caught if issubclass(w.category, UserWarning)]


def _listed_again(mesh, which, reverse=False) -> tuple[np.ndarray, np.ndarray]:
    faces = np.asarray(mesh.faces)
    extra = faces[which][:, ::-1] if reverse else faces[which]
    return np.asarray(mesh.vertices), np.vstack([faces, extra])


@pytest.mark.parametrize("share", [1.0, 0.01])
def test_faces_listed_again_change_no_metric_and_are_named(share):
    for name, mesh in crowns():
        clean = _quiet(values, mesh)[0]
        rng = np.random.default_rng(7)
        count = max(1, round(share * len(mesh.faces)))
        which = rng.choice(len(mesh.faces), count, replace=False)
        doubled, caught = _quiet(values, _listed_again(mesh, which))
        assert doubled == clean, name  # bit for bit: the same faces in the same order
        named = [m for m in caught if REPEATED in m]
        assert named and all(f"{count} of the mesh's" in m for m in named), (name, caught)


def test_the_repeat_may_be_listed_first_and_in_any_vertex_order():
    mesh = dome()
    faces = np.asarray(mesh.faces)
    rotated = np.roll(faces[:50], 1, axis=1)  # the same winding, another first vertex
    listed = (np.asarray(mesh.vertices), np.vstack([rotated, faces]))
    surface, caught = _quiet(prepare_surface, listed)
    assert len(surface.faces) == len(faces) and surface.duplicate_faces == 50
    assert any("50 of the mesh's" in m for m in caught)
    assert np.array_equal(surface.faces[:50], rotated)  # the first listing is kept


def test_a_face_listed_again_wound_the_other_way_keeps_the_first_listing():
    mesh = dome()
    which = np.arange(0, len(mesh.faces), 10)
    surface, caught = _quiet(prepare_surface, _listed_again(mesh, which, reverse=True))
    assert np.array_equal(surface.faces, mesh.faces)  # the first, outward, listing kept
    assert any(f"{len(which)} of them wound the other way round" in m for m in caught)
    # the orientation check then finds nothing wrong
    assert surface.oriented("as-is").orientation.winding == "outward"


def test_keep_measures_the_raw_faces_as_molar_does():
    mesh = dome()
    listed = _listed_again(mesh, np.arange(len(mesh.faces)))
    clean = _quiet(classic_dne, mesh)[0]
    raw, caught = _quiet(prepare_surface, listed, duplicates="keep")
    assert len(raw.faces) == 2 * len(mesh.faces) and raw.duplicates == "keep"
    assert any(REPEATED in m and "kept" in m for m in caught)
    assert _quiet(classic_dne, raw)[0].dne > 1.9 * clean.dne  # each triangle counted twice
    assert _quiet(opc, raw)[0].opc == 0  # no edge joins exactly two faces
    # a triangle and its copy are not neighbours that disagree on their winding
    assert raw.oriented("as-is").orientation.winding == "outward"


def test_the_batch_row_counts_the_faces_its_metrics_measured():
    mesh = dome()
    listed = _listed_again(mesh, np.arange(len(mesh.faces)))
    metrics = ("ariadne", "classic", "slope", "opc")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        clean = measure_mesh(mesh, metrics)
        doubled = measure_mesh(listed, metrics)
    assert doubled.status == "ok"
    assert doubled.record == clean.record
    assert doubled.record["faces"] == len(doubled.results["classic"].mesh.faces)
    assert sum(REPEATED in str(w.message) for w in caught) == 1  # once per mesh, not per metric
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        kept = measure_mesh(listed, ("classic",), options=TopographyOptions(duplicates="keep"))
    assert kept.results["classic"].faces == 2 * len(mesh.faces)


def test_the_callers_faces_are_not_modified_and_a_bad_mode_is_refused():
    mesh = dome()
    vertices, faces = _listed_again(mesh, np.arange(10))
    before = faces.copy()
    _quiet(prepare_surface, (vertices, faces))
    assert np.array_equal(faces, before)
    with pytest.raises(ValueError, match="duplicates must be one of"):
        prepare_surface(mesh, duplicates="merge")
    with pytest.raises(ValueError, match="duplicates must be one of"):
        TopographyOptions(duplicates=True)
