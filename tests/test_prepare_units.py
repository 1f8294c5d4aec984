"""A change of unit changes nothing but the unit: every step of ``prepare``, and every shipped
protocol, gives the same crown scaled, and the same dimensionless metrics after it.

The same crown in millimetres, in micrometres (x1000), in metres (x0.001), in inches' reciprocal
(x25.4) and at an odd factor (x3.7): the prepared mesh is the prepared mesh in millimetres
scaled, to 1e-9 of the crown's size, with the same faces in the same order; ariaDNE, classic
DNE and OPCR are the same (to 1e-9 relative, exactly for OPCR); slope and RFI, which compute
per-face quantities in single precision as molaR does, to 1e-5.  A length in a protocol (a crop
height, a crop plane's point) is in the file's unit: it is scaled with the mesh here.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import dentopo
from conftest import shared_mesh
from dentopo.mesh import as_arrays
from dentopo.prepare import _clean, _crop, _decimate, _orient, _smooth, named_protocols
from dentopo.samples import sample_paths

SCALES = (1000.0, 0.001, 25.4, 3.7)

#: How far (a fraction of the crown's bounding-box diagonal) a vertex of the prepared scaled
#: crown, scaled back, may lie from the prepared crown's.
RELATIVE = 1e-9


def _crown(name: str):
    path = sample_paths()[name] if name == "tooth" else shared_mesh(name)
    vertices, faces = as_arrays(dentopo.load_mesh(path))
    return np.asarray(vertices, dtype=np.float64), np.asarray(faces, dtype=np.int64)


@pytest.fixture(scope="module", params=["tooth", "normal"])
def crown(request):
    """The bundled sample tooth (5,400 faces) and the shared ``normal`` crown (8,000)."""
    return _crown(request.param)


def _size(vertices) -> float:
    return float(np.linalg.norm(np.ptp(vertices, axis=0)))


def assert_scaled(base_v, base_f, v, f, scale, size):
    """(v, f) is (base_v * scale, base_f): same faces in the same order, vertices to RELATIVE."""
    assert f.shape == base_f.shape, f"{len(f)} faces at x{scale:g}, {len(base_f)} at x1"
    np.testing.assert_array_equal(f, base_f)
    worst = float(np.abs(v / scale - base_v).max()) / size
    assert worst <= RELATIVE, f"x{scale:g}: vertices differ by {worst:.2e} of the size"


def _plane(vertices):
    """A slanted plane through the crown's upper half (a point, a unit normal)."""
    low, high = vertices.min(axis=0), vertices.max(axis=0)
    point = low + 0.6 * (high - low)
    return [*point, 0.2, -0.1, 1.0]


#: Each step alone: (its run function, its options, the options that are lengths in the unit).
STEPS = {
    "clean": (_clean.run, {"keep": "largest"}),
    "orient": (_orient.run, {"mode": "occlusal", "up": None, "spin": "none"}),
    "orient-footprint": (_orient.run, {"mode": "occlusal", "up": None, "spin": "footprint"}),
    "crop-fraction": (_crop.run, {"fraction": 0.6}),
    "crop-below": (_crop.run, {"below": "height"}),
    "crop-plane": (_crop.run, {"plane": "plane"}),
    "decimate-1000": (_decimate.run, {"faces_target": 1000}),
    "decimate-3000": (_decimate.run, {"faces_target": 3000}),
    "laplacian": (_smooth.run, {"method": "laplacian", "iterations": 10, "step": 0.5}),
    "taubin": (_smooth.run, {"method": "taubin", "iterations": 10, "step": 0.5}),
    "hc": (_smooth.run, {"method": "hc", "iterations": 10, "step": 0.1}),
    "implicit": (_smooth.run, {"method": "implicit", "iterations": 3, "step": 0.1}),
    "implicit-unpinned": (
        _smooth.run,
        {"method": "implicit", "iterations": 3, "step": 0.1, "pin_boundary": False},
    ),
}


def _options(options: dict, vertices, scale: float) -> dict:
    """The step's options for the crown in millimetres scaled by `scale` (lengths scaled)."""
    out = dict(options)
    if out.get("below") == "height":
        out["below"] = 0.3 * float(np.ptp(vertices[:, 2])) * scale
    if out.get("plane") == "plane":
        plane = _plane(vertices)
        out["plane"] = [*(np.array(plane[:3]) * scale), *plane[3:]]
    return out


@pytest.mark.parametrize("step", list(STEPS))
def test_each_step_alone_gives_the_scaled_mesh_in_every_unit(crown, step):
    v, f = crown
    run, options = STEPS[step]
    base = run(v, f, **_options(options, v, 1.0))
    assert len(base.faces) > 0
    for scale in SCALES:
        out = run(v * scale, f, **_options(options, v, scale))
        assert_scaled(base.vertices, base.faces, out.vertices, out.faces, scale, _size(v))
        if base.transform is not None:  # orient: the same rotation, the translation scaled
            np.testing.assert_allclose(out.transform[:3, :3], base.transform[:3, :3], atol=1e-12)
            np.testing.assert_allclose(
                out.transform[:3, 3] / scale, base.transform[:3, 3], atol=RELATIVE * _size(v)
            )


def _metrics(vertices, faces) -> dict:
    """The dimensionless metrics of a prepared crown (an error's type where one raises)."""
    mesh = (vertices, faces)
    out = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for name, metric in (
            ("ariadne", lambda: dentopo.ariaDNE(mesh).dne),
            ("classic", lambda: dentopo.classic_dne(mesh).dne),
            ("opcr", lambda: dentopo.opcr(mesh).opcr),
            ("slope", lambda: dentopo.slope(mesh).slope),
            ("rfi", lambda: dentopo.rfi(mesh).rfi),
        ):
            try:
                out[name] = metric()
            except ValueError as exc:  # molaR's RFI can stop; it must stop in every unit
                out[name] = type(exc).__name__
    return out


#: The relative tolerance of each metric across units (slope and RFI: single precision).
METRIC_TOLERANCE = {"ariadne": 1e-9, "classic": 1e-9, "opcr": 0.0, "slope": 1e-5, "rfi": 1e-5}


def assert_same_metrics(base: dict, other: dict, scale: float):
    for name, value in base.items():
        if isinstance(value, str):
            assert other[name] == value, f"{name} at x{scale:g}: {other[name]!r}, not {value}"
            continue
        assert isinstance(other[name], float), f"{name} at x{scale:g}: {other[name]!r}"
        change = abs(other[name] - value) / abs(value)
        assert change <= METRIC_TOLERANCE[name], f"{name} at x{scale:g} changed by {change:.1e}"


def _prepare(vertices, faces, protocol, /, **changes):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", dentopo.PrepareWarning)
        return dentopo.prepare((vertices, faces), protocol, **changes)


def assert_protocol_is_unit_free(v, f, protocol, /, lengths=(), **changes):
    """`protocol` with `changes` prepares (v * s, f) into the prepared (v, f) scaled, for every
    scale; `lengths` name the changes that are lengths (scaled with the mesh)."""
    base = _prepare(v, f, protocol, **changes)
    base_metrics = _metrics(base.vertices, base.faces)
    assert isinstance(base_metrics["ariadne"], float)
    for scale in SCALES:
        scaled = {k: (x * scale if k in lengths else x) for k, x in changes.items()}
        out = _prepare(v * scale, f, protocol, **scaled)
        assert_scaled(base.vertices, base.faces, out.vertices, out.faces, scale, _size(v))
        assert [(s.name, s.faces_after, s.vertices_after) for s in out.steps] == [
            (s.name, s.faces_after, s.vertices_after) for s in base.steps
        ]
        assert_same_metrics(base_metrics, _metrics(out.vertices, out.faces), scale)
    return base


@pytest.fixture(scope="module", params=["tooth", "normal", "high"])
def any_crown(request):
    """The sample tooth and the shared ``normal`` crown (below 10,000 faces: the shipped
    protocols do not decimate them) and ``high`` (20,000 faces: they do)."""
    return _crown(request.param)


@pytest.mark.parametrize("protocol", sorted(named_protocols()))
def test_every_shipped_protocol_prepares_the_same_crown_in_every_unit(any_crown, protocol):
    v, f = any_crown
    assert_protocol_is_unit_free(v, f, protocol)


@pytest.mark.parametrize("protocol", sorted(named_protocols()))
def test_every_shipped_protocol_decimating_further_is_the_same_in_every_unit(crown, protocol):
    # the crowns below 10,000 faces, decimated to 2,000 by the protocol changed
    v, f = crown
    base = assert_protocol_is_unit_free(v, f, protocol, faces=2000)
    assert abs(len(base.faces) - 2000) <= 20


def test_a_crop_height_is_a_length_in_the_unit_of_the_file(crown):
    v, f = crown
    height = 0.25 * float(np.ptp(v[:, 2]))
    base = assert_protocol_is_unit_free(
        v, f, "crown-10k", lengths=("crop_below",), crop_below=height, faces=1500
    )
    # not scaled, the same number is another height: the crop, so the crown, differs
    unscaled = _prepare(v * 1000.0, f, "crown-10k", crop_below=height, faces=1500)
    assert unscaled.step("crop").faces_after != base.step("crop").faces_after


def test_a_crop_fraction_has_no_unit(crown):
    v, f = crown
    assert_protocol_is_unit_free(v, f, "crown-10k-smooth100", crop_fraction=0.7, faces=2500)
