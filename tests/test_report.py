"""The collection report: a results table to one self-contained HTML page.

A small collection (eight generated crowns in two folders, and one file that
is not a mesh) is computed by the command with ``--report``, and again through
``dentopo report`` and :func:`dentopo.write_report`.  The page is checked as
text (one row per specimen, thumbnails that decode, the payloads unpacking to
the meshes, nothing to fetch) and in headless Chromium (Debian's
``chromium``; skipped with a reason where it is absent): the scripts run
without an error on the console, every thumbnail decodes, each metric's group
plot and the scatter matrix are drawn, the failed specimen is listed with its
error, and a click opens a specimen's 3D view.
"""

from __future__ import annotations

import base64
import html
import io
import os
import re
import shutil

import numpy as np
import pytest
import trimesh

from dentopo import color_scale, read_table, write_report, write_table
from dentopo.cli import main
from dentopo.report._collect import UNGROUPED, folder_groups
from dentopo.report._payload import COLOR_STEPS, color_indices, pack_mesh, unpack_mesh
from dentopo.report._thumbnails import report_camera
from dentopo.samples import tooth

pytest.importorskip("plotly", reason="the report needs the report extra (plotly)")
pytest.importorskip("pyvista", reason="the report's thumbnails need the viz extra (pyvista)")
Image = pytest.importorskip("PIL.Image", reason="Pillow is needed to decode thumbnails")

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
needs_chromium = pytest.mark.skipif(
    CHROMIUM is None, reason="headless Chromium (Debian package 'chromium') is not installed"
)
CORRUPT = "broken.ply"


def _collection(root):
    """Eight crowns in folders ``apes`` and ``monkeys`` and one corrupt PLY; their paths."""
    rng = np.random.default_rng(1)
    base = tooth(rings=12)
    paths = []
    for i in range(8):
        vertices = np.array(base.vertices)
        group = "apes" if i % 2 else "monkeys"
        vertices[:, 2] *= rng.uniform(0.7, 1.0) * (1.4 if group == "apes" else 1.0)
        vertices += rng.normal(scale=0.002, size=vertices.shape)
        path = root / group / f"crown{i}.ply"
        path.parent.mkdir(parents=True, exist_ok=True)
        trimesh.Trimesh(vertices, base.faces, process=False).export(path)
        paths.append(path)
    corrupt = root / "apes" / CORRUPT
    corrupt.write_text("ply\nformat ascii 1.0\nelement vertex 3\nend_header\n1 2\n")
    return [*paths, corrupt]


@pytest.fixture(scope="module")
def collection(tmp_path_factory):
    """The collection computed by the command with --report: (root, table, page)."""
    root = tmp_path_factory.mktemp("report")
    _collection(root / "scans")
    table, page = root / "results.csv", root / "report.html"
    code = main(
        [str(root / "scans"), "-o", str(table), "--metrics", "ariadne,slope", "--report", str(page)]
    )
    assert code == 1  # the corrupt file failed; the table and the report are written
    return root, table, page


def _rows(text: str) -> list[str]:
    return re.findall(r'<tr data-index="(\d+)"', text)


def _thumbnails(text: str) -> list[bytes]:
    found = re.findall(
        r'<img class="thumb" alt="[^"]*" src="data:image/(\w+);base64,([^"]+)"', text
    )
    assert all(kind in ("webp", "png") for kind, _ in found)
    return [base64.b64decode(data) for _, data in found]


def test_the_command_writes_one_row_per_specimen(collection):
    _, table, page = collection
    text = page.read_text()
    records = read_table(table)
    assert len(records) == 9
    assert sorted(map(int, _rows(text))) == list(range(9))
    assert len(_thumbnails(text)) == 8  # not the corrupt file
    assert 'data-group="apes"' in text and 'data-group="monkeys"' in text


def test_every_thumbnail_decodes_and_shows_the_signed_map(collection):
    _, _, page = collection
    for data in _thumbnails(page.read_text()):
        with Image.open(io.BytesIO(data)) as picture:
            pixels = np.asarray(picture.convert("RGB")).astype(int)
        red = (pixels[..., 0] - pixels[..., 2] > 60).sum()
        blue = (pixels[..., 2] - pixels[..., 0] > 60).sum()
        assert red > 20 and blue > 5, (red, blue)  # convex cusps red, the central basin blue


def test_the_failed_specimen_is_listed_with_its_error(collection):
    _, table, page = collection
    text = page.read_text()
    error = next(r["error"] for r in read_table(table) if r["file"].endswith(CORRUPT))
    problems = re.search(r'<ul id="problem-list">(.*?)</ul>', text, flags=re.S).group(1)
    assert CORRUPT in problems
    assert error.split("'")[0] in problems  # its reason, as the table says it


def test_the_page_fetches_nothing(collection):
    _, _, page = collection
    text = page.read_text()
    assert "default-src 'none'" in text
    markup = re.sub(r"<script\b[^>]*>.*?</script>", "", text, flags=re.S)
    for attribute in re.findall(r'\b(?:src|href)="([^"]*)"', markup):
        assert attribute.startswith(("data:", "#")), attribute
    assert not re.search(r"https?://", markup)
    assert text.count("<script>") == 3  # the error hook, plotly.js once, the page's own


def test_the_subcommand_and_the_api_write_the_same_page(collection, tmp_path):
    _, table, page = collection
    again = tmp_path / "again.html"
    assert main(["report", str(table), "-o", str(again), "-q"]) == 0
    summary = write_report(table, tmp_path / "api.html", jobs=1)
    assert summary.specimens == 9 and summary.pictured == 8 and summary.failed >= 1
    assert summary.groups == ("apes", "monkeys")
    assert summary.size == (tmp_path / "api.html").stat().st_size
    assert _rows(again.read_text()) == _rows(page.read_text())
    assert _thumbnails(again.read_text()) == _thumbnails((tmp_path / "api.html").read_text())


def test_worker_processes_write_the_same_page(collection, tmp_path, monkeypatch):
    from dentopo.report import _fields

    _, table, _ = collection
    serial = write_report(table, tmp_path / "serial.html", jobs=1)
    monkeypatch.setattr(_fields, "POOL_FROM", 2)  # start workers even for a few files
    parallel = write_report(table, tmp_path / "parallel.html", jobs=2)
    assert parallel.pictured == serial.pictured == 8
    assert (tmp_path / "serial.html").read_bytes() == (tmp_path / "parallel.html").read_bytes()


def test_payloads_unpack_to_the_meshes(collection):
    root, _, page = collection
    text = page.read_text()
    data = re.search(r'<script type="application/json" id="report-data">(.*?)</script>', text)
    import json

    meta = json.loads(data.group(1))
    specimens = {s["index"]: s for s in meta["specimens"]}
    for index, mesh_meta in meta["meshes"].items():
        packed = re.search(
            rf'<script type="application/octet-stream" id="mesh-{index}">([^<]*)</script>', text
        ).group(1)
        vertices, faces, _ = unpack_mesh({**mesh_meta, "data": packed})
        name = specimens[int(index)]["name"]
        original = trimesh.load(next(root.glob(f"scans/*/{name}")), process=False)
        assert np.array_equal(faces, original.faces)
        # stored turned into the occlusal camera's axes (a rotation), so the page starts there
        rotation = report_camera(original.vertices, original.faces)
        assert np.allclose(rotation @ rotation.T, np.eye(3)) and np.linalg.det(rotation) > 0
        turned = original.vertices @ rotation.T
        extent = np.ptp(turned, axis=0).max()
        assert np.abs(vertices - turned).max() <= extent / 65535


def test_payload_round_trip_with_wide_indices():
    rng = np.random.default_rng(0)
    vertices = rng.normal(size=(70_000, 3)) * [1.0, 2.0, 0.5]
    faces = rng.integers(0, len(vertices), size=(5_000, 3))
    values = rng.normal(size=len(vertices))
    before = (vertices.copy(), faces.copy(), values.copy())
    scale = color_scale(values)
    payload = pack_mesh(vertices, faces, values, scale)
    assert payload["wide"]
    got_vertices, got_faces, colors = unpack_mesh(payload)
    assert np.array_equal(got_faces, faces)
    assert np.abs(got_vertices - vertices).max() <= np.ptp(vertices, axis=0).max() / 65535
    assert np.array_equal(colors, color_indices(values, scale))
    for a, b in zip(before, (vertices, faces, values), strict=True):
        assert np.array_equal(a, b)  # the caller's arrays are untouched


def test_colour_index_of_zero_is_the_middle_entry():
    scale = color_scale(limits=2.0)
    indices = color_indices(np.array([-5.0, -2.0, 0.0, 2.0, 5.0]), scale)
    assert indices.tolist() == [0, 0, (COLOR_STEPS - 1) // 2, COLOR_STEPS - 1, COLOR_STEPS - 1]


def test_folder_groups(tmp_path):
    files = [tmp_path / "a" / "x.ply", tmp_path / "b" / "c" / "y.ply", tmp_path / "z.ply"]
    assert folder_groups([str(f) for f in files]) == ["a", "b/c", tmp_path.name]


def test_groups_file_by_path_or_base_name(collection, tmp_path):
    root, table, _ = collection
    groups = tmp_path / "groups.csv"
    first = next(root.glob("scans/monkeys/crown0.ply"))
    groups.write_text(f"group,file\nfirst,{first}\nsecond,crown1.ply\n")
    summary = write_report(table, tmp_path / "g.html", groups=groups, jobs=1)
    assert summary.groups == ("(ungrouped)", "first", "second")
    text = (tmp_path / "g.html").read_text()
    assert text.count('data-group="first"') == 1 and text.count('data-group="second"') == 1
    assert text.count(f'data-group="{UNGROUPED}"') == 7


def test_a_bad_groups_file_is_one_line_and_exit_2(collection, tmp_path, capsys):
    _, table, _ = collection
    bad = tmp_path / "bad.csv"
    bad.write_text("name,kind\na,b\n")
    assert main(["report", str(table), "-o", str(tmp_path / "r.html"), "--groups", str(bad)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "needs columns 'file' and 'group'" in err[0]
    assert not (tmp_path / "r.html").exists()


def test_a_file_gone_since_is_listed_without_a_crash(collection, tmp_path):
    _, table, _ = collection
    records = read_table(table)
    copy = [dict(r) for r in records]
    ok = [r for r in records if r["status"] == "ok"]
    gone = dict(ok[1], file=str(tmp_path / "gone.ply"))
    summary = write_report([ok[0], gone], tmp_path / "gone.html", jobs=1)
    assert summary.pictured == 1 and summary.problems == {gone["file"]: "file not found"}
    assert "no picture: file not found" in (tmp_path / "gone.html").read_text()
    assert records == copy  # the caller's records are untouched
    assert summary.unpictured == {gone["file"]: "file not found"}


def test_the_command_exits_1_naming_a_row_measured_ok_left_without_a_picture(
    collection, tmp_path, capsys
):
    _, table, _ = collection
    records = read_table(table)
    ok = [r for r in records if r["status"] == "ok"]
    failed = [r for r in records if r["status"] != "ok"]
    gone = dict(ok[1], file=str(tmp_path / "gone.ply"))
    partial = tmp_path / "partial.csv"
    write_table(partial, [ok[0], gone, *failed])
    capsys.readouterr()
    assert main(["report", str(partial), "-o", str(tmp_path / "partial.html"), "-q"]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [
        f"dentopo: 1 specimen measured ok but without a picture: {gone['file']}: file not found"
    ]
    assert (tmp_path / "partial.html").exists()  # the page is written all the same
    whole = tmp_path / "whole.csv"
    write_table(whole, [ok[0], *failed])  # a failed row has no picture to miss
    assert main(["report", str(whole), "-o", str(tmp_path / "whole.html"), "-q"]) == 0


def test_a_molar_table_of_base_names_finds_its_files_below_it(collection, tmp_path):
    root, _, _ = collection
    table = root / "molar.csv"
    assert main([str(root / "scans"), "--columns", "molar", "-o", str(table), "-q"]) == 1
    assert all("/" not in r["file"] for r in read_table(table))  # base names only
    summary = write_report(table, tmp_path / "molar.html", jobs=1)
    assert summary.specimens == 9 and summary.pictured == 8
    assert summary.groups == ("apes", "monkeys") and summary.problems == {}


def test_an_empty_table_gives_an_empty_page(tmp_path):
    summary = write_report([], tmp_path / "empty.html")
    assert (summary.specimens, summary.pictured, summary.groups) == (0, 0, ())
    assert _rows((tmp_path / "empty.html").read_text()) == []


def test_bad_arguments_raise_before_any_work(collection, tmp_path):
    _, table, _ = collection
    with pytest.raises(ValueError, match="no results table"):
        write_report(tmp_path / "none.csv", tmp_path / "x.html")
    with pytest.raises(TypeError, match="table must be"):
        write_report(42, tmp_path / "x.html")
    with pytest.raises(ValueError, match="symmetric"):
        write_report(table, tmp_path / "x.html", limits=(-1, 2))
    assert not (tmp_path / "x.html").exists()


def test_report_needs_the_table_file(tmp_path, capsys):
    _collection(tmp_path / "scans")
    assert main([str(tmp_path / "scans"), "--report", str(tmp_path / "r.html")]) == 2
    assert "give -o FILE" in capsys.readouterr().err
    assert not (tmp_path / "r.html").exists()


# --- in headless Chromium


def _dom(tmp_path, url: str, *extra: str) -> tuple[str, str]:
    from test_html import chromium

    result = chromium(
        tmp_path,
        url,
        *extra,
        "--use-gl=swiftshader",
        "--enable-unsafe-swiftshader",
        "--enable-logging=stderr",
        "--v=0",
        "--virtual-time-budget=15000",
        "--dump-dom",
    )
    return result.stdout, result.stderr


def _status(dom: str) -> dict:
    tag = re.search(r'<div id="report-status"[^>]*>', dom).group(0)
    return dict(re.findall(r'data-([a-z]+)="([^"]*)"', tag))


@needs_chromium
def test_the_page_in_chromium(collection, tmp_path):
    from test_html import page_requests

    _, _, page = collection
    net_log = tmp_path / "net.json"
    dom, log = _dom(tmp_path, page.as_uri(), f"--log-net-log={net_log}")
    assert page_requests(net_log) == []  # nothing fetched
    status = _status(dom)
    assert status["ready"] == "yes"
    assert status["errors"] == ""
    assert not re.search(r"CONSOLE.*(Uncaught|Error|Refused)", log), log  # CSP refusals too
    assert status["thumbnails"] == "8/8"  # every thumbnail decoded
    assert len(re.findall(r'<tr data-index="\d+"', dom)) == 9
    for metric in ("dne", "positive_dne", "negative_dne", "slope"):
        plot = re.search(rf'<div class="group-plot[^"]*" id="box-{metric}"[^>]*>(.*?)</svg>', dom)
        assert plot and "js-plotly-plot" in plot.group(0), metric
        assert "apes" in plot.group(1) and "monkeys" in plot.group(1)
    splom = dom[dom.index('<div id="splom"') : dom.index('<section id="problems"')]
    assert "js-plotly-plot" in splom[:200] and "<canvas" in splom
    assert 'class="no-webgl"' not in splom  # drawn, not plotly's "WebGL is not supported"
    assert re.search(r'<li data-index="\d+"><b>broken\.ply</b>', dom)
    assert re.search(r'<div id="viewer" hidden=""', dom)  # no 3D view until asked


@needs_chromium
def test_a_click_opens_the_3d_view(collection, tmp_path):
    _, table, page = collection
    dom, _ = _dom(tmp_path, page.as_uri() + "#view=4")  # the page clicks specimen 4's picture
    status = _status(dom)
    assert status["ready"] == "yes" and status["errors"] == ""
    viewer = re.search(r'<div id="viewer"[^>]*>', dom).group(0)
    assert "hidden" not in viewer and 'data-shown="4"' in viewer
    # numbered from 1, as the table's "#" column: the fourth row of the table
    fourth = os.path.basename(read_table(table)[3]["file"])
    assert re.search(r'<td class="num" data-v="4">4</td>.*?' + re.escape(fourth), dom)
    title = re.search(r'<b id="viewer-title">([^<]*)</b>', dom).group(1)
    assert title.startswith(fourth)
    plot = re.search(r'<div id="viewer-plot"[^>]*>', dom).group(0)
    assert "js-plotly-plot" in plot
    viewer_plot = dom.split('id="viewer-plot"')[1].split('id="report-status"')[0]
    assert "<canvas" in viewer_plot and 'class="no-webgl"' not in viewer_plot


@needs_chromium
def test_the_checks_see_a_broken_thumbnail_and_a_broken_payload(collection, tmp_path):
    _, _, page = collection
    text = page.read_text()
    text = re.sub(
        r'(<img class="thumb" alt="[^"]*" src="data:image/\w+;base64,)[^"]+',
        r"\1AAAA",
        text,
        count=1,
    )
    text = re.sub(r'(id="mesh-3">)[^<]+', r"\1AAAA", text)
    broken = tmp_path / "broken.html"
    broken.write_text(text)
    status = _status(_dom(tmp_path, broken.as_uri() + "#view=4")[0])  # row 4 is mesh-3
    assert status["thumbnails"] == "7/8"
    assert status["errors"] != ""


def _square_or_die(value: int) -> int:
    """Squares `value`; kills its own process for a negative one (a worker that dies)."""
    if value < 0:
        os._exit(3)
    return value * value


def test_a_worker_that_dies_costs_only_its_own_call():
    from dentopo.report._fields import run_calls

    calls = [(2,), (-1,), (3,), (4,)]
    results = run_calls(_square_or_die, calls, 2, lambda call, why: f"{why} on {call[0]}")
    assert results == [4, "worker process exited unexpectedly (exit code 3) on -1", 9, 16]
    assert run_calls(_square_or_die, calls[2:], 1, None) == [9, 16]  # one worker: this process


@needs_chromium
def test_a_view_past_the_table_says_so(collection, tmp_path):
    _, _, page = collection
    for wanted in ("10", "0", "x"):  # the table has 9 rows
        dom, _ = _dom(tmp_path, page.as_uri() + "#view=" + wanted)
        status = _status(dom)
        assert status["ready"] == "yes" and status["errors"] == ""
        viewer = re.search(r'<div id="viewer"[^>]*>', dom).group(0)
        assert "hidden" not in viewer and "data-shown" not in viewer
        message = re.search(r'<div id="viewer-message"[^>]*>([^<]*)</div>', dom).group(1)
        assert f"No specimen {wanted}: the table has 9" in message
        assert "#view=1 to #view=9" in message


# --- every metric, at 1400 x 900


@pytest.fixture(scope="module")
def wide(collection):
    """The collection computed with --metrics all (every metric column) and its report."""
    root, _, _ = collection
    table, page = root / "all.csv", root / "all.html"
    code = main(
        [str(root / "scans"), "-o", str(table), "--metrics", "all", "--report", str(page), "-q"]
    )
    assert code == 1  # the corrupt file
    return table, page


def test_every_metric_is_a_column_and_the_status_comes_before_them(wide):
    table, page = wide
    text = page.read_text()
    head = re.search(r"<thead><tr>(.*?)</tr></thead>", text).group(1)
    names = [
        re.sub(r"<[^>]+>", "", cell)
        for cell in re.findall(r"<th[^>]*>(.*?)(?:<span class=\"fam\">.*?</span>)?</th>", head)
    ]
    assert names[:5] == ["#", "map", "specimen", "group", "status, error, warnings"]
    metrics = names[5:]
    assert {
        "ariaDNE",
        "classic DNE convex",
        "OPCR (patches)",
        "OPC (patches)",
        "slope (\u00b0)",
    } <= set(metrics)
    # RFI fails on these small crowns: a long error each, in the status cell next to the name
    records = read_table(table)
    partial = next(r for r in records if r["status"] == "partial")
    assert len(partial["error"]) > 200
    row = next(r for r in text.split("<tr ") if os.path.basename(partial["file"]) + "<" in r)
    cell = re.search(r'<td class="status-cell"[^>]*>(.*?)</td>', row, flags=re.S).group(1)
    assert "partial" in cell and 'class="error" title="' in cell
    assert html.escape(partial["error"], quote=True) in cell  # all of it, cut only on screen
    # the scatter matrix's chooser, one box per metric plotted (not OPC's bins and rotations),
    # on short names explained; the first ten key metrics ticked
    chooser = re.search(r'<div id="splom-metrics".*?</div></div>', text).group(0)
    boxes = re.findall(
        r'<label><input type="checkbox" value="\d+"( checked)?> ([^<]*)</label>', chooser
    )
    ticked = [name for checked, name in boxes if checked]
    assert len(boxes) > 40 and 9 <= len(ticked) <= 10
    assert ticked[:3] == ["aDNE", "aDNE+", "aDNE\u2212"]
    assert "opc_bin1" not in chooser and "dk_opcr_rot0" not in chooser
    assert "cDNE\u2212: classic DNE concave" in text


@needs_chromium
def test_at_1400_by_900_nothing_is_hidden(wide, tmp_path):
    """The status column in view, no page wider than the window, the scatter matrix's
    axis titles apart, and the 3D view's toolbar clear of its colour bar."""
    _, page = wide
    for address in ("", "#view=2"):
        dom, _ = _dom(tmp_path, page.as_uri() + address, "--window-size=1400,900")
        status = _status(dom)
        assert status["ready"] == "yes" and status["errors"] == ""
        assert status["layout"] == "", (address, status["layout"])
        splom = dom[dom.index('<div id="splom"') : dom.index('<section id="problems"')]
        chosen = len(re.findall(r'<input type="checkbox" value="\d+" checked', dom))
        assert chosen >= 9 and f'data-metrics="{chosen}"' in splom[:300] and "<canvas" in splom
        if address:
            assert 'data-shown="2"' in re.search(r'<div id="viewer"[^>]*>', dom).group(0)
            shown = dom.split('id="viewer-plot"')[1].split('id="report-status"')[0]
            assert 'class="modebar' in shown and re.search(r'class="[^"]*\bcolorbar"', shown)


@needs_chromium
def test_the_layout_check_sees_what_it_checks(wide, tmp_path):
    """The same page with the fixes undone (long axis titles, the viewer's toolbar on its
    colour bar, a wide status column, the table not scrolled in its own box): the checks
    name each problem."""
    _, page = wide
    text = page.read_text()
    text = re.sub(r'"short":"[^"]*"', '"short":"classic DNE concave"', text)
    text = text.replace("margin: { l: 0, r: 0, t: 36, b: 0 }", "margin: { l: 0, r: 0, t: 0, b: 0 }")
    text = text.replace("len: 0.9, y: 0.45", "len: 1")
    text = text.replace("max-width: 260px;", "min-width: 1400px;")
    text = text.replace(".table-wrap { overflow: auto;", ".table-wrap { overflow: visible;")
    broken = tmp_path / "undone.html"
    broken.write_text(text)
    dom, _ = _dom(tmp_path, broken.as_uri() + "#view=2", "--window-size=1400,900")
    layout = _status(dom)["layout"]
    assert "scatter matrix titles overlap" in layout
    assert "toolbar over the colour bar" in layout
    assert "status column out of view" in layout
    assert "page wider than the window" in layout


def test_the_summary_says_1_group_not_1_groups(collection, tmp_path, capsys):
    _, table, _ = collection
    records = read_table(table)
    groups = {r["file"]: "all" for r in records}
    summary = write_report(table, tmp_path / "one.html", groups=groups, jobs=1)
    assert summary.groups == ("all",)
    text = (tmp_path / "one.html").read_text()
    assert "9 specimens in 1 group (" in text and "1 groups" not in text
    groups_file = tmp_path / "groups.csv"
    groups_file.write_text("file,group\n" + "".join(f"{r['file']},all\n" for r in records))
    argv = ["report", str(table), "-o", str(tmp_path / "cli.html"), "--groups", str(groups_file)]
    assert main(argv) == 0
    err = capsys.readouterr().err
    assert "9 specimens in 1 group," in err and "1 groups" not in err
