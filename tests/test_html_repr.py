"""Results in notebooks: every public result has ``_repr_html_``, a compact escaped table.

The result classes are discovered (every public class of dentopo that is a
dataclass with ``to_dict``, or whose name says it is a result, study, sweep or
summary), so that a new result without ``_repr_html_`` fails here, and one
without a factory below fails too.
"""

from __future__ import annotations

import dataclasses
import importlib
import inspect
import pkgutil
from html.parser import HTMLParser

import numpy as np
import pytest

import dentopo
from dentopo import topography
from dentopo._html_repr import array_summary, format_value, histogram_svg, result_html, rows_html
from dentopo.samples import sample_paths, tooth

SCRIPT = "<script>alert(1)</script>"
IMAGE = '<img src=x onerror="alert(1)">'  # a file name may hold markup (but no slash)

RESULT_SUFFIXES = ("Result", "Study", "Sweep", "Summary")


def _public_classes() -> dict[str, type]:
    found = {}
    for info in pkgutil.walk_packages(dentopo.__path__, "dentopo."):
        if info.name.endswith("__main__"):
            continue
        module = importlib.import_module(info.name)
        for name, value in vars(module).items():
            if not inspect.isclass(value) or name.startswith("_"):
                continue
            if not value.__module__.startswith("dentopo."):
                continue
            is_result = dataclasses.is_dataclass(value) and hasattr(value, "to_dict")
            if is_result or name.endswith(RESULT_SUFFIXES):
                found[f"{value.__module__}.{value.__qualname__}"] = value
    return found


CLASSES = _public_classes()


@pytest.fixture(scope="module")
def crown():
    return tooth(rings=8)


def _study():
    from dentopo.study import RobustnessStudy

    row = {"perturbation": "normal", "method": "centroid", "dne": 0.05, "sign_agreement": 1.0}
    return RobustnessStudy(rows=[row], meshes={"normal": None}, results={}, bandwidth=0.08)


def _summary():
    from dentopo.report import ReportSummary

    return ReportSummary(
        path="r.html", specimens=12, pictured=11, failed=1, problems={"a.ply": "gone"},
        groups=("a",), size=1000, seconds=1.5,
    )  # fmt: skip


#: Class name -> (a way to make one from the sample crown, the attribute holding its main value).
FACTORIES = {
    "AriaDNEResult": (lambda m: dentopo.ariaDNE(m), "dne"),
    "SlopeResult": (lambda m: dentopo.slope(m), "slope"),
    "OPCResult": (lambda m: dentopo.opc(m), "opc"),
    "OPCRResult": (lambda m: dentopo.opcr(m), "opcr"),
    "RFIResult": (lambda m: dentopo.rfi(m, find_alpha=True), "rfi"),
    "ClassicDNEResult": (lambda m: dentopo.classic_dne(m), "dne"),
    "ARCResult": (lambda m: topography.arc(m), "arc"),
    "DoolkitARCResult": (lambda m: topography.doolkit_arc(m), "arc_mean"),
    "DoolkitDNEResult": (lambda m: topography.doolkit_dne(m), "dne_total"),
    "AngularityResult": (lambda m: topography.angularity(m), "angularity_mean"),
    "DoolkitSlopeResult": (lambda m: topography.doolkit_slope(m), "slope_mean"),
    "InclinationResult": (lambda m: topography.inclination(m), "inclination_mean"),
    "DoolkitOPCResult": (lambda m: topography.doolkit_opc(m), "opc"),
    "DoolkitOPCRResult": (lambda m: topography.doolkit_opcr(m), "opcr"),
    "ElevationResult": (lambda m: topography.elevation(m), "elevation_mean"),
    "ReliefIndexResult": (lambda m: topography.relief_index(m), "rfi_ungar"),
    "ReliefRateResult": (lambda m: topography.relief_rate_below_median(m), "rrate"),
    "ShapeIndexResult": (lambda m: topography.shape_index(m), "formfactor"),
    "HypsodontyResult": (lambda m: topography.hypsodonty(m), "hypsodonty"),
    "FootprintResult": (lambda m: topography.footprint_area(m), "area"),
    "MorphoTesterDNEResult": (lambda m: topography.morphotester_dne(m), "dne"),
    "MorphoTesterRFIResult": (lambda m: topography.morphotester_rfi(m), "rfi"),
    "MorphoTesterOPCRResult": (lambda m: topography.morphotester_opcr(m), "opcr"),
    "ProjectedFootprintResult": (lambda m: topography.projected_footprint(m), "area"),
    "ProjectedRFIResult": (lambda m: topography.projected_rfi(m), "rfi"),
    "PCVResult": (lambda m: topography.pcv(m, rays=16), "pcv"),
    "BandwidthSweep": (
        lambda m: dentopo.bandwidth_sweep(m, bandwidths=[0.08], sign_methods=["centroid"]),
        None,
    ),
    "RobustnessStudy": (lambda m: _study(), None),
    "Protocol": (lambda m: dentopo.Protocol(faces=2000), "name"),
    "ProtocolStudy": (
        lambda m: dentopo.protocol_study(m, faces=(100,), smoothing=(), noise=(), metrics="slope"),
        "base",
    ),
    "PreparedCrown": (lambda m: dentopo.prepare(m, faces=100), "protocol"),
    "Step": (lambda m: dentopo.prepare(m, faces=100).step("decimate"), "name"),
    "ReportSummary": (lambda m: _summary(), "specimens"),
}


class _Checker(HTMLParser):
    """Counts tags, and fails on a closing tag that does not close the innermost open one."""

    VOID = frozenset({"br", "hr", "img", "meta", "link", "input", "rect", "col"})

    def __init__(self):
        super().__init__()
        self.stack: list[str] = []
        self.tags: list[str] = []
        self.text: list[str] = []

    def handle_starttag(self, tag, attrs):
        self.tags.append(tag)
        if tag not in self.VOID:
            self.stack.append(tag)

    def handle_startendtag(self, tag, attrs):
        self.tags.append(tag)

    def handle_endtag(self, tag):
        if tag in self.VOID:
            return
        assert self.stack and self.stack[-1] == tag, f"</{tag}> closes {self.stack[-1:]}"
        self.stack.pop()

    def handle_data(self, data):
        self.text.append(data)


def _check_html(text: str) -> _Checker:
    checker = _Checker()
    checker.feed(text)
    checker.close()
    assert not checker.stack, f"unclosed tags {checker.stack}"
    assert "table" in checker.tags
    assert "script" not in checker.tags
    return checker


def test_the_discovery_finds_the_results():
    names = {cls.__name__ for cls in CLASSES.values()}
    assert {"AriaDNEResult", "SlopeResult", "OPCRResult", "RFIResult", "BatchResult"} <= names


@pytest.mark.parametrize("name", sorted(CLASSES))
def test_every_public_result_has_a_repr_html(name):
    cls = CLASSES[name]
    assert callable(getattr(cls, "_repr_html_", None)), f"{name} has no _repr_html_"


def test_every_result_class_has_a_factory_here():
    names = {cls.__name__ for cls in CLASSES.values()} - {"BatchResult"}  # tested below
    assert names <= set(FACTORIES), f"add a factory for {sorted(names - set(FACTORIES))}"


@pytest.mark.parametrize("name", sorted(FACTORIES))
def test_repr_html_is_a_table_holding_the_main_value(name, crown):
    make, main = FACTORIES[name]
    result = make(crown)
    assert type(result).__name__ == name
    text = result._repr_html_()
    checker = _check_html(text)
    body = "".join(checker.text)
    assert name in body
    if main is not None:
        assert format_value(getattr(result, main)) in body
    else:
        assert format_value(result.rows[0]["dne"]) in body
    # arrays summarised, never dumped: the page stays small whatever the mesh
    assert len(text) < 12000
    for field in dataclasses.fields(result):
        value = getattr(result, field.name)
        if isinstance(value, np.ndarray) and value.size > 3:
            assert array_summary(value) in body
            assert np.array2string(value[:3]) not in body


def test_the_main_value_comes_first_and_in_bold(crown):
    result = dentopo.ariaDNE(crown)
    text = result._repr_html_()
    assert f"<b>{format_value(result.dne)}</b>" in text
    assert text.index(">dne<") < text.index(">positive_dne<") < text.index(">bandwidth<")


def test_a_per_vertex_array_is_drawn_as_a_small_histogram(crown):
    result = dentopo.ariaDNE(crown)
    text = result._repr_html_()
    assert text.count("<svg") == 1 and text.count("<rect") == 24
    assert "<svg" not in dentopo.opc(crown)._repr_html_()  # no per-vertex values to draw


def test_text_fields_are_escaped(crown):
    result = dataclasses.replace(dentopo.ariaDNE(crown), distance_type=SCRIPT)
    text = result._repr_html_()
    assert "<script" not in text
    assert "&lt;script&gt;alert(1)&lt;/script&gt;" in text
    _check_html(text)


def test_a_mesh_name_is_escaped(crown):
    result = dentopo.ariaDNE(crown)
    mesh = result.mesh.copy()
    mesh.metadata["file_name"] = f"{SCRIPT}.ply"
    text = dataclasses.replace(result, mesh=mesh)._repr_html_()
    assert "<script" not in text
    assert "&lt;script&gt;alert(1)&lt;/script&gt;.ply" in text


def test_the_helpers_summarise_and_escape():
    assert array_summary(np.array([1.0, np.nan, 3.0])) == (
        "(3,) float64, min 1, mean 2, max 3, 1 not finite"
    )
    assert array_summary(np.zeros((0, 3))) == "(0, 3) float64, empty"
    assert array_summary(np.array([True, False, True])) == "(3,) bool, 2 true"
    assert histogram_svg(np.array([np.nan])) == ""
    assert format_value(tuple(range(12))).endswith("... 12 in all)")
    text = rows_html([{"file": f"/x/{IMAGE}.ply", "dne": 1.5}], title=SCRIPT)
    assert "<script" not in text and "&lt;script&gt;" in text
    _check_html(text)


def test_other_fields_are_described_not_dumped():
    text = _summary()._repr_html_()
    assert "<b>r.html</b>" in text  # no table fields: the first scalar leads
    assert "<th>problems</th><td>1 entry</td>" in text


def test_result_html_never_modifies_the_result(crown):
    result = dentopo.slope(crown)
    before = result.face_slope.copy()
    result_html(result, histogram="face_slope")
    np.testing.assert_array_equal(result.face_slope, before)


# --- a batch --------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def batch():
    paths = [sample_paths()["tooth"], sample_paths()["saddle"]]
    with pytest.warns(UserWarning, match="flat"):
        return dentopo.compute_batch(paths, metrics=["ariadne", "slope"])


def test_a_batch_is_a_list_of_records(batch):
    assert isinstance(batch, dentopo.BatchResult) and isinstance(batch, list)
    assert [r["file"].rsplit("/", 1)[-1] for r in batch] == ["saddle.ply", "tooth.ply"]
    assert batch == [dict(r) for r in batch]
    assert batch.failed == []


def test_a_batch_becomes_a_dataframe_in_one_call(batch):
    pd = pytest.importorskip("pandas")
    table = batch.to_dataframe()
    assert isinstance(table, pd.DataFrame)
    assert list(table.columns) == list(dict.fromkeys(k for r in batch for k in r))
    assert table.shape == (2, len(batch[0]))
    assert table["dne"].tolist() == [r["dne"] for r in batch]
    assert table["slope"].tolist() == [r["slope"] for r in batch]
    # pandas' own constructor takes it as it is, too
    assert pd.DataFrame(batch)["dne"].tolist() == table["dne"].tolist()


def test_a_batch_repr_html_shows_the_files_and_values(batch):
    text = batch._repr_html_()
    body = "".join(_check_html(text).text)
    assert "saddle.ply" in body and "tooth.ply" in body
    assert "/samples/" not in body  # file names, not paths
    assert format_value(batch[1]["dne"]) in body
    assert format_value(batch[1]["slope"]) in body  # the metric, not hidden behind settings


def test_a_batch_repr_html_escapes_file_names_and_errors():
    records = dentopo.BatchResult(
        [
            {"file": f"/d/{IMAGE}.ply", "status": "error", "error": SCRIPT, "dne": None},
            {"file": "/d/b.ply", "status": "ok", "error": None, "dne": 0.5},
        ]
    )
    text = records._repr_html_()
    assert "<script" not in text and "<img" not in text
    assert "&lt;img src=x onerror=&quot;alert(1)&quot;&gt;.ply" in text
    assert "&lt;script&gt;alert(1)&lt;/script&gt;" in text
    assert records.failed == [records[0]]
    _check_html(text)
