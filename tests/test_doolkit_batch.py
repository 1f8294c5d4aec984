"""``dentopo DIR --metrics doolkit --columns doolkit``: doolkit's table, column for column."""

from __future__ import annotations

import csv
import math

import pytest

from conftest import REFERENCE, ROBUSTNESS_SET, shared_mesh
from dentopo.cli import main

#: The crowns point to -z, and doolkit measured them as they lie: so does ``--orient as-is``.
pytestmark = pytest.mark.filterwarnings("ignore:the crown points to -z:UserWarning")

#: What doolkit computes in double precision (Morpho, R): the issue's 1e-9.
DOUBLE = (
    "slope_mean",
    "inclin_mean",
    "opcr",
    "area2d",
    "area2d_convex",
    "hypso_hypsodonty",
    "hypso_height",
    "hypso_length",
    "hypso_width",
)
#: What goes through Rvcg's single precision: 1e-6.
SINGLE = (
    "area3d",
    "angularity_mean",
    "rfi_ungar",
    "rfi_boyer",
    "rfi_guy",
    "arc_mean",
    "arc_pos_mean",
    "arc_neg_mean",
    "dne_total_unrounded",
    "rrate_below_median",
    "shape_formfactor",
    "shape_elongation",
    "shape_k",
)
COUNTS = (
    "n_vertices",
    "n_faces",
    "opc",
    *(f"opc_bin{k}" for k in range(1, 9)),
    *(f"opcr_rot{k}" for k in range(8)),
)


@pytest.fixture(scope="module")
def doolkit_rows():
    path = REFERENCE / "doolkit_1.42.2_topography.csv"
    if not path.exists():
        pytest.skip(f"doolkit's reference values not found at {path}")
    with path.open(newline="") as handle:
        reader = csv.DictReader(handle)
        return reader.fieldnames, {row["file"]: row for row in reader}


@pytest.fixture(scope="module")
def table(doolkit_rows, tmp_path_factory):
    folder = tmp_path_factory.mktemp("crowns")
    for name in ROBUSTNESS_SET:
        (folder / f"{name}.ply").symlink_to(shared_mesh(name))
    out = folder.parent / "d.csv"
    code = main([str(folder), "--metrics", "doolkit", "--columns", "doolkit",
                 "--orient", "as-is", "-o", str(out), "-q"])  # fmt: skip
    with out.open(newline="") as handle:
        reader = csv.DictReader(handle)
        return code, reader.fieldnames, {row["file"]: row for row in reader}, out


def test_the_table_has_doolkits_columns_then_ours(doolkit_rows, table):
    theirs, _ = doolkit_rows
    code, header, rows, _ = table
    assert code == 0
    expected = [name for name in theirs if not name.startswith("s_") and name != "errors"]
    assert header == [*expected, "status", "error", "warnings"]
    assert sorted(rows) == sorted(f"{name}.ply" for name in ROBUSTNESS_SET)
    assert {row["status"] for row in rows.values()} == {"ok"}


@pytest.mark.parametrize("name", ROBUSTNESS_SET)
def test_every_column_is_doolkits_number(name, doolkit_rows, table):
    _, reference = doolkit_rows
    _, _, rows, _ = table
    ours, theirs = rows[f"{name}.ply"], reference[f"{name}.ply"]
    for column in COUNTS:
        assert int(ours[column]) == int(theirs[column]), column
    for column in DOUBLE:
        assert math.isclose(float(ours[column]), float(theirs[column]), rel_tol=1e-9), column
    for column in SINGLE:
        assert math.isclose(float(ours[column]), float(theirs[column]), rel_tol=1e-6), column
    # doolkit rounds its DNE total to 3 decimals
    assert float(ours["dne_total"]) == float(theirs["dne_total"])


def test_the_table_reads_back_as_doolkits_layout(table):
    from dentopo.formats import read_table

    _, _, rows, path = table
    records = {record["file"]: record for record in read_table(path)}
    for name, row in rows.items():
        assert records[name]["dk_opc"] == int(row["opc"])  # doolkit's names, our keys
        assert records[name]["dk_opcr"] == float(row["opcr"])
        assert records[name]["slope_mean"] == float(row["slope_mean"])
        assert records[name]["status"] == "ok"
