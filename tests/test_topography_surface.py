"""A prepared Surface shared by the topography metrics, and the compiled passes behind them.

Every metric given a :class:`Surface` returns what it returns given the mesh,
bit for bit; the compiled per-face passes equal the numpy formulas they
replace, bit for bit; the compiled Delaunay triangulation is qhull's; a batch
row prepares its surface once.
"""

from __future__ import annotations

import dataclasses
import math
from fractions import Fraction

import numpy as np
import pytest
import trimesh
from scipy.spatial import Delaunay

import dentopo.batch._measure as measure_module
from conftest import shared_mesh
from dentopo import load_mesh
from dentopo.batch._measure import TopographyOptions, measure_mesh
from dentopo.mesh import boundary_edges
from dentopo.topography import (
    Surface,
    classic_dne,
    molar_scale,
    opc,
    opcr,
    prepare_surface,
    rfi,
    slope,
)
from dentopo.topography.footprint._delaunay import delaunay
from dentopo.topography.relief._molar import first_occurrence
from dentopo.topography.surface import _kernels

pytestmark = pytest.mark.filterwarnings("ignore:the crown points to -z:UserWarning")

CALLS = {
    "slope": lambda m, o: slope(m, orient=o),
    "opc": lambda m, o: opc(m, rotation=10.0, orient=o),
    "opcr": lambda m, o: opcr(m, orient=o),
    "rfi": lambda m, o: rfi(m, find_alpha=True, orient=o),
    "classic": lambda m, o: classic_dne(m, boundary="leg"),
}


def _fields(result) -> dict:
    """Every field of a result, arrays and the mesh's arrays included."""
    out = {}
    for name in vars(result):
        value = getattr(result, name)  # a result's mesh is built when first read
        if isinstance(value, trimesh.Trimesh):
            out[name] = (np.asarray(value.vertices), np.asarray(value.faces))
        elif dataclasses.is_dataclass(value) and not isinstance(value, type):
            out.update({f"{name}.{k}": v for k, v in _fields(value).items()})
        else:
            out[name] = value
    return out


def _assert_identical(a, b):
    fa, fb = _fields(a), _fields(b)
    assert fa.keys() == fb.keys()
    for name in fa:
        x, y = fa[name], fb[name]
        if isinstance(x, tuple) and x and isinstance(x[0], np.ndarray):
            for u, v in zip(x, y, strict=True):
                assert np.array_equal(u, v), name
        elif isinstance(x, np.ndarray):
            assert x.dtype == y.dtype and np.array_equal(x, y), name
        else:
            assert str(x) == str(y), name


@pytest.fixture(params=["tooth", "normal"])
def crown(request, tooth):
    if request.param == "tooth":
        # the sample tooth turned upside down: "auto" turns it back
        return trimesh.Trimesh(tooth.vertices * [1, -1, -1], tooth.faces, process=False)
    return load_mesh(shared_mesh(request.param))


@pytest.mark.parametrize("orient", ["as-is", "auto"])
@pytest.mark.parametrize("metric", sorted(CALLS))
def test_a_surface_gives_what_the_mesh_gives(crown, metric, orient):
    surface = prepare_surface(crown)
    call = CALLS[metric]
    _assert_identical(call(surface, orient), call(crown, orient))
    # and the surface as turned (what the oriented metrics measure) gives the same again
    _assert_identical(call(surface.oriented("auto"), orient), call(crown, orient))


def test_the_orientation_is_found_once_and_kept(crown):
    surface = prepare_surface(crown)
    turned = surface.oriented("auto")
    assert turned.orientation.turned and turned.cleaned is surface
    assert surface.oriented("auto") is turned
    assert surface.oriented("as-is") is turned.oriented("as-is")
    assert prepare_surface(turned) is surface
    assert surface.orientation is None and not surface.oriented("as-is").orientation.turned


def test_a_surface_is_never_modified_by_the_metrics(tooth):
    surface = prepare_surface(tooth)
    before = {f.name: np.copy(getattr(surface, f.name)) for f in dataclasses.fields(Surface)
              if isinstance(getattr(surface, f.name), np.ndarray)}  # fmt: skip
    for call in CALLS.values():
        result = call(surface, "auto")
        result.mesh.vertices[:] = 0.0  # a result's mesh and arrays are its own
        for value in vars(result).values():
            if isinstance(value, np.ndarray):
                value[...] = 0
    with pytest.raises(ValueError, match="read-only"):
        surface.vertices[0, 0] = 1.0
    for name, values in before.items():
        assert np.array_equal(getattr(surface, name), values), name


def test_the_boundary_is_the_mesh_layers_boundary(crown):
    surface = prepare_surface(crown)
    assert np.array_equal(
        surface.boundary_edges(), boundary_edges(surface.faces, len(surface.vertices))
    )


def test_edges_used_by_three_faces_are_grouped_together():
    # a fin: three triangles on the edge (0, 1), one of them with the edge reversed
    vertices = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1.0]])
    faces = np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4]])
    surface = prepare_surface((vertices, faces))
    uses = surface.edge_uses().reshape(3, 3)  # [k, f]
    assert uses[0].tolist() == [3, 3, 3]  # edge k = 0 of every face is (0, 1)
    assert (uses[1:] == 1).all()


# --- the compiled passes equal the numpy formulas they replace -------------------------------


def _numpy_single_precision_areas(vertices, faces):
    tri = vertices.astype(np.float32)[faces]
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    return np.sqrt((cross * cross).sum(axis=1, dtype=np.float32)).astype(np.float64) / 2


def _numpy_energy(vertices, faces, normals):
    x, n = vertices[faces], normals[faces]
    a, b = x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]
    c, d = n[:, 1] - n[:, 0], n[:, 2] - n[:, 0]
    gaa, gab, gbb = (a * a).sum(1), (a * b).sum(1), (b * b).sum(1)
    hcc, hcd, hdd = (c * c).sum(1), (c * d).sum(1), (d * d).sum(1)
    det = gaa * gbb - gab * gab
    norm1 = np.maximum(np.abs(gaa) + np.abs(gab), np.abs(gab) + np.abs(gbb))
    rcond = np.divide(np.abs(det), norm1**2, out=np.zeros_like(det), where=norm1 > 0)
    ok = rcond >= 1e-5
    energy = np.zeros(len(faces))
    energy[ok] = (gbb * hcc - 2.0 * gab * hcd + gaa * hdd)[ok] / det[ok]
    return energy, 0.5 * np.sqrt(np.maximum(det, 0.0))


def _numpy_vertex_normals(vertices, faces, unit):
    tri = vertices[faces]
    normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    if unit:
        length = np.linalg.norm(normal, axis=1, keepdims=True)
        normal = np.divide(normal, length, out=np.zeros_like(normal), where=length > 0)
    total = np.zeros_like(vertices)
    for k in range(3):
        np.add.at(total, faces[:, k], normal)
    length = np.linalg.norm(total, axis=1, keepdims=True)
    return np.divide(total, length, out=np.zeros_like(total), where=length > 0)


def test_compiled_passes_equal_the_numpy_formulas_bit_for_bit(crown):
    surface = prepare_surface(crown)
    vertices, faces = surface.vertices * molar_scale(surface.vertices), surface.faces
    tri = vertices[faces]
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    ours_cross, ours_norm = np.empty_like(cross), np.empty(len(faces))
    _kernels.face_cross_norm(vertices, faces, ours_cross, ours_norm)
    assert np.array_equal(ours_cross, cross)
    assert np.array_equal(ours_norm, np.linalg.norm(cross, axis=1))

    areas = np.empty(len(faces))
    _kernels.single_precision_areas(vertices.astype(np.float32), faces, areas)
    assert np.array_equal(areas, _numpy_single_precision_areas(vertices, faces))

    for unit in (True, False):
        normals = np.empty_like(vertices)
        _kernels.unit_vertex_sums(vertices, faces, unit, normals)
        assert np.array_equal(normals, _numpy_vertex_normals(vertices, faces, unit))

    energy, area = np.empty(len(faces)), np.empty(len(faces))
    _kernels.energy_density(vertices, faces, normals, 1e-5, energy, area)
    expected_energy, expected_area = _numpy_energy(vertices, faces, normals)
    assert np.array_equal(energy, expected_energy) and np.array_equal(area, expected_area)

    heights = np.empty(len(faces))
    _kernels.face_mean_z(vertices, faces, heights)
    assert np.array_equal(heights, vertices[faces, 2].mean(axis=1))


def test_the_compensated_dot_is_the_exact_sum_rounded():
    rng = np.random.default_rng(7)
    values = rng.integers(0, 181, 20_000)
    weights = rng.random(20_000) * 1e-3
    exact = sum(Fraction(int(v)) * Fraction(float(w)) for v, w in zip(values, weights, strict=True))
    ours = _kernels.compensated_dot(values, weights)
    assert abs(Fraction(ours) - exact) <= Fraction(math.ulp(float(exact)))


# --- Delaunay ---------------------------------------------------------------------------------


def _triangles(simplices) -> set:
    return {tuple(t) for t in np.sort(simplices, axis=1).tolist()}


def _check_neighbors(simplices, neighbors):
    for t, row in enumerate(simplices):
        for k in range(3):
            side = set(row.tolist()) - {int(row[k])}
            other = neighbors[t, k]
            if other >= 0:
                assert side <= set(simplices[other].tolist())
                assert t in neighbors[other].tolist()


def _footprint(mesh):
    surface = prepare_surface(mesh)
    vertices = surface.vertices
    points = np.vstack([vertices - vertices.mean(axis=0), np.zeros((1, 3))])[:, :2]
    points = points * molar_scale(vertices)
    return points[first_occurrence(points)]


@pytest.mark.parametrize("name", ["normal", "high", "low", "noise1", "smooth", "random"])
def test_the_compiled_delaunay_is_qhulls(name):
    if name == "random":
        points = np.random.default_rng(3).random((3000, 2))
    else:
        points = _footprint(load_mesh(shared_mesh(name)))
    simplices, neighbors = delaunay(points)
    assert _triangles(simplices) == _triangles(Delaunay(points).simplices)
    _check_neighbors(simplices, neighbors)
    # counter-clockwise, as qhull's are not necessarily: the alpha shape does not depend on it
    a, b, c = (points[simplices[:, k]] for k in range(3))
    u, v = b - a, c - a
    assert (u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0] > 0).all()


def test_cocircular_points_fall_back_to_qhull():
    grid = np.stack(np.meshgrid(np.arange(12.0), np.arange(9.0)), axis=-1).reshape(-1, 2)
    simplices, neighbors = delaunay(grid)
    tri = Delaunay(grid)
    assert np.array_equal(simplices, tri.simplices) and np.array_equal(neighbors, tri.neighbors)


@pytest.mark.parametrize("name", ["normal", "noise1", "random"])
def test_the_sweep_in_slices_is_the_sweep_in_one_call(name, monkeypatch):
    # the sweep and its certification run in bounded compiled calls (so that Ctrl-C and
    # SIGTERM are raised between them): any slicing gives the same triangles, bit for bit
    from dentopo.topography.footprint import _delaunay

    if name == "random":
        points = np.random.default_rng(5).random((20_000, 2))
    else:
        points = _footprint(load_mesh(shared_mesh(name)))
    most = 3 * (2 * len(points) - 5)
    outputs = []
    for per_call in (len(points), 1, 7, 1000):
        triangles = np.full(most, -9, np.int64)
        halfedges = np.full(most, -9, np.int64)
        count = _delaunay._sweep(points, triangles, halfedges, per_call=per_call)
        assert count > 0
        certified = _delaunay._certified(points, triangles, halfedges, count, per_call=per_call)
        outputs.append((count, certified, triangles, halfedges))
    for count, certified, triangles, halfedges in outputs[1:]:
        assert count == outputs[0][0] and certified is outputs[0][1] is True
        assert np.array_equal(triangles, outputs[0][2])
        assert np.array_equal(halfedges, outputs[0][3])
    monkeypatch.setattr(_delaunay, "INSERTIONS_PER_CALL", 3)
    monkeypatch.setattr(_delaunay, "CHECKS_PER_CALL", 5)
    small = delaunay(points)
    monkeypatch.undo()
    whole = delaunay(points)
    assert all(np.array_equal(a, b) for a, b in zip(small, whole, strict=True))


def test_a_failed_certificate_in_slices_is_still_a_failure():
    from dentopo.topography.footprint import _delaunay

    points = np.random.default_rng(6).random((500, 2))
    most = 3 * (2 * len(points) - 5)
    triangles, halfedges = np.empty(most, np.int64), np.empty(most, np.int64)
    count = _delaunay._sweep(points, triangles, halfedges)
    triangles[3 * count - 3 : 3 * count] = triangles[3 * count - 3 : 3 * count][::-1].copy()
    for per_call in (None, 1, 7):
        assert not _delaunay._certified(points, triangles, halfedges, count, per_call=per_call)


# --- a batch row ------------------------------------------------------------------------------


def test_a_batch_row_prepares_the_surface_once(tooth, monkeypatch):
    calls = []
    original = measure_module.prepare_surface

    def counting(mesh, *args, **kwargs):
        calls.append(type(mesh).__name__)
        return original(mesh, *args, **kwargs)

    monkeypatch.setattr(measure_module, "prepare_surface", counting)
    options = TopographyOptions(find_alpha=True)
    measurement = measure_mesh(tooth, ["classic", "rfi", "opcr", "opc", "slope"], options=options)
    assert calls == ["Trimesh"]
    assert measurement.status == "ok"
    assert measurement.record["rfi"] == rfi(tooth, find_alpha=True).rfi
    assert measurement.record["slope"] == slope(tooth).slope
    assert measurement.record["opcr"] == opcr(tooth).opcr
    assert measurement.record["classic_dne"] == classic_dne(tooth).dne


def test_a_batch_row_names_the_preparation_error_for_every_metric():
    flat = (np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0.0]]), np.array([[0, 1, 2]]))
    measurement = measure_mesh(flat, ["classic", "slope"])
    assert measurement.status == "error"
    assert set(measurement.errors) == {"classic", "slope"}
    assert all("no face of non-zero area" in reason for reason in measurement.errors.values())


@pytest.mark.parametrize(("factor", "why"), [(1e-10, "too small"), (1e12, "too large")])
def test_coordinates_out_of_single_precisions_range_are_an_error_naming_the_scale(
    tooth, factor, why
):
    # before: a crown scaled by 1e-10 gave a slope of 48 (42 at any sane scale), an RFI of
    # 0.55 (1.38) and doolkit's DNE 19 (55), all as ok; by 1e12, NaN and inf; doolkit's
    # inclination turned a crown scaled by 1e-12 upside down (float32 volumes of zero)
    from dentopo.topography import doolkit_dne, inclination, relief_index

    scaled = trimesh.Trimesh(np.asarray(tooth.vertices) * factor, tooth.faces, process=False)
    for metric in (slope, relief_index, inclination, doolkit_dne):
        with pytest.raises(ValueError, match=f"{why} for single-precision.*rescale"):
            metric(scaled)


@pytest.mark.parametrize("factor", [1e-7, 1e8])  # metres to kilometres, millimetres to nm
def test_coordinates_near_single_precisions_limits_still_measure_the_crown(tooth, factor):
    scaled = trimesh.Trimesh(np.asarray(tooth.vertices) * factor, tooth.faces, process=False)
    assert slope(scaled).slope == pytest.approx(slope(tooth).slope, rel=1e-6)
