"""Metric names in the batch: molaR's and doolkit's names, sets, and the tools' table layouts."""

from __future__ import annotations

import csv

import pytest

from conftest import REFERENCE
from dentopo.formats import layout
from dentopo.topography import (
    DOOLKIT_METRICS,
    GROUPS,
    METRICS,
    MOLAR_METRICS,
    MORPHOTESTER_METRICS,
    check_metrics,
)


@pytest.mark.parametrize(
    ("given", "expected"),
    [
        ("DNE", ("classic",)),
        ("RFI", ("rfi",)),
        ("OPCr", ("opcr",)),
        ("OPC", ("opc",)),
        ("Slope", ("slope",)),
        ("ARC", ("arc",)),
        ("inclin", ("inclination",)),
        ("rrate", ("relief_rate",)),
        ("shape.index", ("shape_index",)),
        ("Hypso", ("hypsodonty",)),
        ("area2d", ("footprint",)),
        ("Angularity", ("angularity",)),
        ("doolkit_SLOPE", ("doolkit_slope",)),
    ],
)
def test_molar_and_doolkit_names_are_aliases_in_any_case(given, expected):
    assert check_metrics(given) == expected


def test_sets_name_each_tools_metrics_and_all_names_every_metric():
    assert check_metrics("molar") == MOLAR_METRICS
    assert check_metrics("doolkit") == DOOLKIT_METRICS
    assert check_metrics("morphotester") == MORPHOTESTER_METRICS
    assert check_metrics("all") == METRICS
    assert set(GROUPS) == {"all", "molar", "doolkit", "morphotester"}
    # a set and names together, in table order, each once
    assert check_metrics("slope,molar,DNE") == MOLAR_METRICS


def test_an_unknown_name_is_named_as_given():
    with pytest.raises(ValueError, match="unknown metric 'curvy'"):
        check_metrics("slope,curvy")


def test_the_doolkit_layout_has_doolkits_columns_in_its_order():
    path = REFERENCE / "doolkit_1.42.2_topography.csv"
    if not path.exists():
        pytest.skip(f"doolkit's reference values not found at {path}")
    with path.open(newline="") as handle:
        header = next(csv.reader(handle))
    theirs = [name for name in header if not name.startswith("s_") and name != "errors"]
    ours = layout("doolkit", "doolkit").header
    assert list(ours[: len(theirs)]) == theirs
    assert ours[len(theirs) :] == ("status", "error", "warnings")


def test_the_molar_layout_puts_arc_after_molars_own_columns():
    header = layout("molar", "all").header
    assert header[header.index("Slope") + 1 : header.index("Slope") + 4] == (
        "ARC",
        "ARC_positive",
        "ARC_negative",
    )
    assert header.index("ARC_negative") < header.index("ariaDNE")


@pytest.mark.parametrize("given", [[[]], [1], [None], [["slope"]], 3.5])
def test_metrics_that_are_not_names_are_a_type_error_naming_them(given):
    # a list of lists (a JSON body) raised AttributeError: 'list' has no attribute 'strip'
    with pytest.raises(TypeError, match="metrics must be names"):
        check_metrics(given)
