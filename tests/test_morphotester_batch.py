"""``dentopo DIR --metrics morphotester --columns morphotester``: MorphoTester's results file.

MorphoTester 1.1.1 writes ``morphoresults.txt``: tab-separated, its columns (Filename, Mesh Face
Number, DNE, RFI, Surface Area, Outline Area, OPCR), numbers as Python 2's ``str`` prints them.
The two sample crowns it ships with its own results are in ``../shared/data/morphotester``.
"""

from __future__ import annotations

import csv
import shutil
import warnings

import numpy as np
import pytest
import trimesh

from conftest import SHARED
from dentopo.batch._measure import TopographyOptions, measure_mesh
from dentopo.cli import main
from dentopo.formats import read_table
from dentopo.formats._layouts import python2_str
from dentopo.mesh import read_ply

#: Without --unit every row says that MorphoTester's outline depends on the unit (tested below).
pytestmark = pytest.mark.filterwarnings("ignore::dentopo.topography.UnitWarning")

SAMPLES = SHARED / "data" / "morphotester"
EXPECTED = SAMPLES / "expected_morphoresults.txt"
THEROPITHECUS = SAMPLES / "Theropithecus_gelada_1963-58.ply"


@pytest.fixture(scope="module")
def expected():
    if not EXPECTED.exists():
        pytest.skip(f"MorphoTester's sample crowns and results not found at {SAMPLES}")
    return EXPECTED.read_text().splitlines()


def _tsv(path):
    with open(path, newline="") as handle:
        return list(csv.reader(handle, delimiter="\t"))


def test_the_morphotester_table_is_morphotesters_results_file_digit_for_digit(expected, tmp_path):
    out = tmp_path / "m.tsv"
    code = main(
        [str(SAMPLES), "--metrics", "morphotester", "--columns", "morphotester", "-o", str(out)]
    )
    assert code == 0
    rows = _tsv(out)
    assert rows[0] == [
        "Filename",
        "Mesh Face Number",
        "DNE",
        "RFI",
        "Surface Area",
        "Outline Area",
        "OPCR",
        "status",
        "error",
        "warnings",
    ]
    # MorphoTester's own columns, as text, equal; then status ok with no error, and a warning
    # that its outline depends on the unit (no --unit given)
    assert ["\t".join(row[:7]) for row in rows] == expected
    assert all(row[7:9] == ["ok", ""] for row in rows[1:])
    assert all(row[9].startswith("morphotester_rfi: MorphoTester's outline") for row in rows[1:])


def test_given_the_unit_morphotesters_rfi_is_the_crowns_in_millimetres(expected, tmp_path):
    """The same crown in micrometres with --unit um: MorphoTester's digits, areas in um^2."""
    in_mm = measure_mesh(str(THEROPITHECUS), "morphotester", options=TopographyOptions(unit="mm"))
    assert in_mm.record["mt_rfi"] == 2.178 and in_mm.record["mt_outline_area"] == 98.056
    vertices, faces = read_ply(THEROPITHECUS, exact_text=True)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no unit warning: the unit is given
        in_um = measure_mesh(
            (vertices * 1000.0, faces), "morphotester", options=TopographyOptions(unit="um")
        )
    assert in_um.record["mt_rfi"] == 2.178
    assert in_um.record["mt_outline_area"] == pytest.approx(98.056e6, rel=1e-12)
    assert in_um.record["mm_per_unit"] == 1e-3
    with pytest.warns(UserWarning, match="morphotester_rfi: MorphoTester's outline area depends"):
        unitless = measure_mesh((vertices * 1000.0, faces), "morphotester")
    assert unitless.record["mt_rfi"] != 2.178  # MorphoTester on the crown as given


def test_a_morphotester_table_reads_back_with_its_types(expected, tmp_path):
    out = tmp_path / "m.tsv"
    main([str(SAMPLES), "--metrics", "morphotester", "--columns", "morphotester", "-o", str(out)])
    records = {r["file"]: r for r in read_table(out)}
    row = records["Theropithecus_gelada_1963-58.ply"]
    assert row["mt_n_faces"] == 10040 and isinstance(row["mt_n_faces"], int)
    assert row["mt_dne"] == 249.806
    assert row["mt_opcr"] == 76.5


def test_morphotesters_options_reach_its_metrics_and_the_settings_columns(expected, tmp_path):
    """The unit-test values of its other settings: energy x area DNE 247.938, OPCR 92.625 at 3."""
    folder = tmp_path / "in"
    folder.mkdir()
    shutil.copy(THEROPITHECUS, folder)
    out = tmp_path / "m.csv"
    options = ["--mt-outliers", "energy-area", "--mt-min-patch", "3"]
    code = main([str(folder), "--metrics", "morphotester", *options, "-o", str(out)])
    assert code == 0
    (row,) = read_table(out)
    assert row["mt_dne"] == 247.938
    assert row["mt_opcr"] == 92.625
    assert row["mt_outliers"] == "energy_area"
    assert row["mt_min_patch"] == 3
    assert row["mt_condition_check"] is True and row["mt_smooth"] is False
    assert row["mt_percentile"] == 99.9
    assert [row[f"mt_opc_rot{k}"] for k in range(8)] != [None] * 8


@pytest.mark.parametrize(
    "option",
    [
        ["--mt-percentile", "101"],
        ["--mt-percentile", "0"],
        ["--mt-percentile", "nan"],
        ["--mt-min-patch", "-1"],
    ],
)
def test_morphotester_options_out_of_range_are_a_usage_error(option, tmp_path, capsys):
    out = tmp_path / "m.csv"
    code = main([str(tmp_path), "--metrics", "morphotester", *option, "-o", str(out)])
    assert code == 2
    err = capsys.readouterr().err
    assert ("percentile" in err or "min_patch" in err) and len(err.strip().splitlines()) == 1
    assert not out.exists()


def test_a_ply_file_is_measured_as_morphotester_reads_it_not_as_cleaned(expected):
    """From a file, the ASCII text in float64, nothing merged; from a mesh, that mesh as given.

    The sample's coordinates are declared float32: read as dentopo reads them for the other
    metrics (rounded to float32), MorphoTester's outline area and DNE move at the third decimal.
    """
    from_file = measure_mesh(str(THEROPITHECUS), "morphotester")
    assert from_file.record["mt_dne"] == 249.806
    assert from_file.record["mt_outline_area"] == 98.056
    loaded = trimesh.load(THEROPITHECUS, process=False)
    as_float32 = measure_mesh(loaded, "morphotester")
    assert as_float32.record["mt_n_faces"] == from_file.record["mt_n_faces"]
    assert np.asarray(loaded.vertices).dtype == np.float64
    assert (
        as_float32.record["mt_dne"] != from_file.record["mt_dne"]
        or as_float32.record["mt_outline_area"] != from_file.record["mt_outline_area"]
    )


def test_a_row_with_other_metrics_keeps_morphotesters_reading(expected):
    alone = measure_mesh(str(THEROPITHECUS), "morphotester").record
    beside = measure_mesh(str(THEROPITHECUS), ["ariadne", "morphotester", "slope"]).record
    assert {k: beside[k] for k in alone} == alone


def test_morphotester_metrics_are_in_all_and_named_each_on_its_own():
    from dentopo.topography import check_metrics

    assert {"morphotester_dne", "morphotester_rfi", "morphotester_opcr"} <= set(
        check_metrics("all")
    )
    assert check_metrics("morphotester_opcr") == ("morphotester_opcr",)


@pytest.mark.parametrize(
    ("value", "text"),
    [
        (68.0, "68.0"),
        (67.125, "67.125"),
        (209.485, "209.485"),
        (0.1 + 0.2, "0.3"),
        (1e16, "1e+16"),
        (123456789012345.0, "1.23456789012e+14"),
        (-0.0, "-0.0"),
    ],
)
def test_numbers_are_printed_as_python_2_prints_them(value, text):
    assert python2_str(value) == text


def test_morphotesters_rfi_without_matplotlib_is_one_line_before_any_file(
    tmp_path, monkeypatch, capsys
):
    import sys

    from dentopo._optional import missing_extra_message
    from dentopo.samples import sample_paths

    monkeypatch.setitem(sys.modules, "matplotlib", None)  # as if not installed
    out = tmp_path / "m.csv"
    code = main([str(sample_paths()["tooth"]), "--metrics", "morphotester", "-o", str(out)])
    assert code == 2
    err = capsys.readouterr().err
    assert (
        err
        == "dentopo: "
        + missing_extra_message("MorphoTester's outline areas (morphotester_rfi)", "viz")
        + "\n"
    )
    assert not out.exists()


def test_morphotesters_metrics_alone_read_a_ply_file_once(expected, monkeypatch):
    """The file as MorphoTester reads it is all they need: dentopo's own reading is skipped."""
    from dentopo.batch import _measure

    def no_second_reading(*args, **kwargs):
        raise AssertionError("load_mesh called for MorphoTester's metrics alone")

    monkeypatch.setattr(_measure, "load_mesh", no_second_reading)
    record = measure_mesh(str(THEROPITHECUS), "morphotester").record
    assert record["mt_dne"] == 249.806 and record["mt_opcr"] == 76.5
