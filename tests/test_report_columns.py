"""The report shows what its table holds: every metric column, the warnings, the marks.

The bundled sample crown and sphere are measured by the command with
``--metrics all`` (every metric column there is) and reported: the page names
every metric column of the table, by family and with its unit, charts none of
the settings columns, shows each row's warnings (escaped: they name files),
and marks the sphere, a closed surface measured as it lies, explaining what
the mark means.  A column the package does not know (a future metric's) is
shown and charted under "other", never dropped.  The grouping is the
package's own lists' (:mod:`dentopo.report._columns`): every record key of
every metric has a family and a unit.
"""

from __future__ import annotations

import html
import json
import re

import pytest

from dentopo import read_table, write_report
from dentopo.cli import main
from dentopo.formats import METRIC_KEYS, SETTING_KEYS, record_keys
from dentopo.report._columns import (
    ARIADNE_SETTINGS,
    COUNTS,
    MESH,
    OTHER,
    ROW_COLUMNS,
    SETTINGS,
    UNITS,
    orientation_mark,
    report_columns,
)
from dentopo.samples import write_samples
from dentopo.topography import METRICS

pytest.importorskip("plotly", reason="the report needs the report extra (plotly)")
pytest.importorskip("pyvista", reason="the report's thumbnails need the viz extra (pyvista)")

#: Every column a metric fills but ariaDNE's settings and counts (OPCR's rotations are checked
#: apart: their names follow its settings).
METRIC_COLUMNS = [
    key
    for keys in METRIC_KEYS.values()
    for key in keys
    if key not in ARIADNE_SETTINGS and key not in COUNTS
]


@pytest.fixture(scope="module")
def samples(tmp_path_factory):
    """tooth.ply (open, points to +z) and sphere.ply (closed) with --metrics all: table, page."""
    root = tmp_path_factory.mktemp("samples")
    write_samples(root)
    table, page = root / "all.csv", root / "all.html"
    argv = [str(root / "tooth.ply"), str(root / "sphere.ply"), "--metrics", "all", "-o", str(table)]
    code = main([*argv, "--report", str(page), "-q"])
    assert code == 1  # molaR's RFI fails on both (partial rows); the table and page are written
    return table, page


def _headers(text: str) -> dict[str, str]:
    """Each metric header's column key -> its text (label and unit), in order."""
    head = re.search(r"<thead><tr>(.*?)</tr></thead>", text).group(1)
    found = {}
    for title, inner in re.findall(r'<th[^>]*class="metric[^"]*" title="([^"]*)">(.*?)</th>', head):
        key = html.unescape(title).split(": ")[0]
        label = re.sub(r"<span class=\"fam\">.*?</span>", "", inner)
        found[key] = html.unescape(re.sub(r"<[^>]+>", "", label))
    return found


def _data(text: str) -> dict:
    found = re.search(r'<script type="application/json" id="report-data">(.*?)</script>', text)
    return json.loads(found.group(1))


def _row(text: str, name: str) -> str:
    rows = (r.split("</tr>")[0] for r in text.split("<tr ")[1:])
    return next(r for r in rows if f">{name}</button>" in r)


def test_the_page_names_every_metric_column_with_its_unit(samples):
    table, page = samples
    text = page.read_text()
    records = read_table(table)
    held = list(records[0])
    assert set(METRIC_COLUMNS) <= set(held)  # the command wrote every metric column
    headers = _headers(text)
    rotations = [key for key in held if re.fullmatch(r"opc_[0-9.]+", key)]
    assert len(rotations) == 8
    for key in (*METRIC_COLUMNS, *rotations):
        assert key in headers, key
    assert headers["slope"] == "slope (\u00b0)"
    assert headers["inclin_mean"] == "inclin_mean (\u00b0)"
    assert headers["surface_area"] == "surface_area (unit\u00b2)"
    assert headers["hypso_height"] == "hypso_height (unit)"
    assert headers["opcr"] == "OPCR (patches)" and headers["opc_5.625"] == "opc_5.625 (patches)"
    assert headers["pcv"] == "PCV" and headers["rfi_ungar"] == "rfi_ungar"  # no unit
    # settings and the row's own columns are not shown as metrics, nor charted
    settings = {k for keys in SETTING_KEYS.values() for k in keys} | set(ARIADNE_SETTINGS)
    assert "pcv_rays" in settings and "bandwidth" in settings
    for key in settings | {"file", "seconds", "status", "error", "warnings", "orientation"}:
        assert key not in headers, key
    plotted = {metric["key"] for metric in _data(text)["metrics"]}
    assert not plotted & (settings | set(COUNTS) | {"seconds"})
    # every metric with a number is plotted, each in its family's section
    numeric = {
        key for key in (*METRIC_COLUMNS, *rotations) if any(r[key] is not None for r in records)
    }
    assert numeric <= plotted
    for key in ("arc", "slope_mean", "mt_opcr", "rfi_projected", "pcv", "pcv_area"):
        assert f'id="box-{key}"' in text, key
    sections = re.findall(r'<h3 id="family-([^"]+)">', text)
    assert sections == ["ariadne", "molar", "doolkit", "morphotester", "rfi_projected", "pcv"]
    doolkit = text[text.index('id="family-doolkit"') : text.index('id="family-morphotester"')]
    assert 'id="box-slope_mean"' in doolkit and 'id="box-dk_opcr_rot0"' in doolkit
    # molaR's RFI failed on both: named, not left out
    assert all(r["rfi"] is None for r in records)
    empty = re.search(r'<p class="empty">No value in any row: ([^<]*)</p>', text).group(1)
    assert "RFI" in empty and "area_3d (unit\u00b2)" in empty
    # the settings are stated once, with their values
    assert "<b>pcv_rays</b> 256" in text and "<b>bandwidth</b> 0.08" in text


def test_each_rows_warnings_are_on_the_page(samples):
    table, page = samples
    text = page.read_text()
    records = read_table(table)
    assert all(r["warnings"] for r in records)
    listed = re.search(r'<ul id="warning-list">(.*?)</ul>', text, flags=re.S).group(1)
    for record in records:
        escaped = html.escape(record["warnings"])
        assert escaped in listed  # in full, under "Warnings"
        name = record["file"].rsplit("/", 1)[-1]
        cell = re.search(r'<td class="status-cell".*?</td>', _row(text, name), flags=re.S).group(0)
        assert f'<div class="warn" title="{escaped}">' in cell  # and beside the name


def test_the_closed_specimen_is_marked_and_the_mark_explained(samples):
    table, page = samples
    text = page.read_text()
    by_name = {r["file"].rsplit("/", 1)[-1]: r for r in read_table(table)}
    assert "closed" in by_name["sphere.ply"]["orientation"]
    assert "closed" not in by_name["tooth.ply"]["orientation"]
    sphere, tooth = _row(text, "sphere.ply"), _row(text, "tooth.ply")
    assert 'data-mark="closed"' in sphere and '<span class="mark closed"' in sphere
    assert "data-mark" not in tooth and 'class="mark' not in tooth
    # its slope (about 90 degrees, the sphere measured as it lies) is shaded, its DNE not
    assert by_name["sphere.ply"]["slope"] == pytest.approx(90, abs=0.01)
    keys = list(_headers(text))
    cells = re.findall(r"<td[^>]*>", sphere)[5:]  # after #, map, name, group, status
    assert len(cells) == len(keys)
    slope, dne = cells[keys.index("slope")], cells[keys.index("dne")]
    assert "asis" in slope and float(re.search(r'data-v="([^"]+)"', slope).group(1)) > 89.9
    assert "asis" not in dne  # ariaDNE does not assume the crown points up
    assert "asis" not in tooth
    # the summary says what the mark means
    marks = re.search(r'<ul class="marks">(.*?)</ul>', text).group(1)
    assert "closed</span> (1 specimen)" in marks and "as it lies" in marks
    assert "turned" not in marks  # no specimen was turned: no mark to explain
    closed = [s["name"] for s in _data(text)["specimens"] if s["mark"] == "closed"]
    assert closed == ["sphere.ply"]


@pytest.mark.parametrize(
    ("cell", "mark"),
    [
        ("+z", None),
        ("-z, turned to +z", "turned"),
        ("-z; closed, as it lies", "closed"),
        ("undetermined; closed, as it lies", "closed"),
        ("points +z", None),
        ("points -z, turned to +z", "turned"),
        ("points -z; closed, as it lies", "closed"),
        ("direction undetermined; closed, as it lies", "closed"),
        ("points -z, not turned", None),
        ("", None),
        (None, None),
    ],
)
def test_the_mark_is_read_from_words_in_the_orientation_cell(cell, mark):
    assert orientation_mark(cell) == mark


def test_every_metric_column_has_a_family_and_a_unit():
    keys = record_keys(METRICS, rotations=(0.0, 5.625))
    columns = {c.key: c for c in report_columns([dict.fromkeys(keys, 1.0)])}
    for key in METRIC_COLUMNS:
        assert key in UNITS, f"{key}: give it a unit in report/_columns.py UNITS"
        assert columns[key].metric and columns[key].family not in (OTHER, MESH), key
    assert columns["opc_5.625"].family == "molar" and columns["opc_5.625"].unit == "patches"
    assert not set(columns) & (set(SETTINGS) | set(ROW_COLUMNS))
    assert {c.key for c in columns.values() if c.family == MESH} == set(COUNTS)
    assert set(COUNTS) <= set(keys)  # the counts named are the table's
    assert "pcv_rays" in SETTINGS and "orient" in SETTINGS and "seconds" in ROW_COLUMNS
    # the families in the order of the metrics, none unknown
    families = list(dict.fromkeys(c.family for c in columns.values()))
    assert families == ["ariadne", "molar", "doolkit", "morphotester", "rfi_projected", "pcv", MESH]


def test_a_column_the_package_does_not_know_is_shown_under_other(samples, tmp_path):
    table, _ = samples
    records = read_table(table)
    for value, record in enumerate(records):
        record["future_metric"] = 1.5 + value  # a metric added later, numbers
        record["note"] = "<b>scan & check</b>"  # text a user added
        record["warnings"] = "read <script>alert(1)</script>.ply; " + record["warnings"]
    page = tmp_path / "future.html"
    write_report(records, page, jobs=1)
    text = page.read_text()
    headers = _headers(text)
    assert headers["future_metric"] == "future_metric" and "note" in headers
    assert 'id="box-future_metric"' in text  # charted, in its own family
    other = text[text.index('id="family-other"') :]
    assert 'id="box-future_metric"' in other
    assert [m["key"] for m in _data(text)["metrics"]][-1] == "future_metric"
    assert 'id="box-note"' not in text  # text: shown, not charted
    assert "&lt;b&gt;scan &amp; check&lt;/b&gt;" in text
    # warnings naming files are text, not markup
    assert "<script>alert(1)</script>" not in text
    assert "read &lt;script&gt;alert(1)&lt;/script&gt;.ply" in text


# --- in headless Chromium


def _browser():
    from test_report import CHROMIUM

    if CHROMIUM is None:
        pytest.skip("headless Chromium (Debian package 'chromium') is not installed")


def test_the_page_of_every_metric_in_chromium(samples, tmp_path):
    """At 1400 x 900: drawn without an error, nothing out of sight; each family's plots drawn,
    OPC's bins and rotations when their fold opens; the columns chooser shows every column, the
    marks' filter the closed specimen alone."""
    _browser()
    from test_report import _dom, _status

    _, page = samples
    dom, _ = _dom(tmp_path, page.as_uri(), "--window-size=1400,900")
    status = _status(dom)
    assert status["ready"] == "yes" and status["errors"] == "" and status["layout"] == ""
    for key in ("dne", "slope", "slope_mean", "mt_opcr", "rfi_projected", "pcv"):
        plot = re.search(rf'<div class="group-plot[^"]*" id="box-{key}"[^>]*>', dom).group(0)
        assert "js-plotly-plot" in plot, key
    folded = re.search(r'<div class="group-plot[^"]*" id="box-opc_bin1"[^>]*>', dom).group(0)
    assert "js-plotly-plot" not in folded  # drawn only when opened
    style = re.search(r'<style id="column-view-style">([^<]*)</style>', dom).group(1)
    assert ".m:not(.k)" in style  # a wide table shows its key metrics first
    # the folds opened and "every column" chosen, as a reader would
    text = page.read_text().replace(
        '<details class="detail-plots">', '<details class="detail-plots" open>'
    )
    chosen = (
        '<script>window.addEventListener("load", () => { for (const [id, value] of '
        '[["column-view", "all"], ["mark-filter", "closed"]]) { const s = '
        "document.getElementById(id); s.value = value; "
        's.dispatchEvent(new Event("change")); } });</script></body>'
    )
    opened = tmp_path / "opened.html"
    opened.write_text(text.replace("</body>", chosen))
    dom, _ = _dom(tmp_path, opened.as_uri(), "--window-size=1400,900")
    status = _status(dom)
    assert status["ready"] == "yes" and status["errors"] == "" and status["layout"] == ""
    for key in ("opc_bin1", "dk_opcr_rot7", "mt_opc_rot0", "opc_5.625"):
        plot = re.search(rf'<div class="group-plot[^"]*" id="box-{re.escape(key)}"[^>]*>', dom)
        assert "js-plotly-plot" in plot.group(0), key
    assert re.search(r'<style id="column-view-style"></style>', dom)
    assert '<span id="shown">1 of 2 shown</span>' in dom  # the closed sphere alone
    assert re.search(r'<tr data-index="\d+"[^>]*hidden=""[^>]*>(?:(?!</tr>).)*tooth\.ply', dom)


def test_a_family_empty_throughout_is_left_out_and_an_empty_metric_beside_others_kept(samples):
    """A table of another layout, read with the library's columns, holds no ariaDNE (read_table
    gives its columns as None): no ariaDNE on the page.  molaR's RFI, empty where its footprint
    failed on every crown, is kept beside molaR's other metrics, and said to be empty."""
    table, _ = samples
    records = read_table(table)
    for record in records:
        for key in (*METRIC_KEYS["ariadne"], "n_vertices", "mt_n_faces"):
            record[key] = None
    columns = {c.key: c for c in report_columns(records)}
    assert not any(c.family == "ariadne" for c in columns.values())
    assert "rfi" in columns and not columns["rfi"].numeric and not columns["rfi"].charted
    assert "n_faces" in columns and "n_vertices" not in columns  # an empty count: left out
