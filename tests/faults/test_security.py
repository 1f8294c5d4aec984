"""Hostile names and planted files (issue 22, items 4, 5, 6 and the journal of item 12).

Before the fix a mesh named ``=HYPERLINK(...)`` or ``@SUM(A1).ply`` was a live
formula in the CSV and TSV tables; a name that is not UTF-8 crashed the run
with a traceback; a symbolic link planted at ``.NAME.lock`` or at the journal's
path was followed (its target truncated, a pid or rows written into it, a
dangling link's target created); a temporary file swapped for a link had the
link's target chmod-ed and renamed over the table; a file at the journal's
path that was not a journal was read as a killed run's rows and deleted; and a
mesh named ``<!--<script>x.ply`` left the HTML view and the report with scripts
that never ran, while a group named ``<a href=...>`` became a live link in the
report's plots.
"""

from __future__ import annotations

import csv
import json
import os
import re
import shutil
import stat

import pytest

from faults.harness import dentopo
from faults.live import write_tooth

#: Names a spreadsheet would run as a formula (OWASP), and names that begin with the
#: apostrophe that neutralises them: every one must read back as it was.
FORMULAS = (
    "=1+2.ply",
    "@SUM(A1).ply",
    "+cmd.ply",
    "-2+3.ply",
    "\tTAB.ply",
    "\rCR.ply",
    "'quoted.ply",
    "''twice.ply",
)
BAD = "=bad(1).ply"  # not a mesh: an error row, whose message quotes the name
STARTS = ("=", "+", "-", "@", "\t", "\r")
PRECIOUS = b"precious: must stay byte-identical\n"


def cells(path, delimiter):
    """Every data cell of a CSV or TSV file, as stored."""
    with open(path, newline="", encoding="utf-8", errors="surrogateescape") as stream:
        return [cell for row in list(csv.reader(stream, delimiter=delimiter))[1:] for cell in row]


def assert_no_live_formula(path, delimiter):
    live = [cell for cell in cells(path, delimiter) if cell.startswith(STARTS)]
    assert live == [], live


@pytest.fixture(scope="module")
def named(tmp_path_factory):
    """A folder of meshes with formula names, one ``=HYPERLINK`` path, and a corrupt file."""
    root = tmp_path_factory.mktemp("names")
    for name in FORMULAS:
        write_tooth(root / name, 8)
    # a path that is the formula, read relative to `root`: the folder is
    # '=HYPERLINK("http:' and the '//' an empty part of the path
    (root / '=HYPERLINK("http:').mkdir()
    write_tooth(root / '=HYPERLINK("http:' / 'x","y").ply', 8)
    (root / BAD).write_text("not a mesh\n")
    return root


NAMES = (*FORMULAS, '=HYPERLINK("http://x","y").ply', BAD)


# --- item 4: formula injection -----------------------------------------------------------


@pytest.mark.parametrize("suffix", [".csv", ".tsv"])
@pytest.mark.parametrize("columns", ["dentopo", "molar", "signdne"])
def test_a_name_a_spreadsheet_would_run_is_text_and_reads_back(named, tmp_path, suffix, columns):
    from dentopo import read_table

    out = tmp_path / f"t{suffix}"
    ran = dentopo("-o", str(out), "--columns", columns, "-q", "--", *NAMES, cwd=named)
    assert ran.returncode == 1, ran.describe()  # the corrupt file failed
    assert "Traceback" not in ran.stderr, ran.describe()
    assert_no_live_formula(out, "," if suffix == ".csv" else "\t")
    records = read_table(out)
    expected = [os.path.basename(n) if columns == "molar" else n for n in NAMES]
    if columns == "signdne":  # ok rows only
        expected = expected[:-1]
    assert sorted(r["file"] for r in records) == sorted(expected)
    if columns != "signdne":
        [failed] = [r for r in records if r["status"] == "error"]
        assert failed["error"] and failed["file"] == BAD


@pytest.mark.parametrize("suffix", [".csv", ".tsv"])
def test_resume_reads_the_names_back_and_computes_nothing_again(named, tmp_path, suffix):
    out = tmp_path / f"t{suffix}"
    names = NAMES[:-1]
    assert dentopo("-o", str(out), "-q", "--", *names, cwd=named).returncode == 0
    again = dentopo("-o", str(out), "--resume", "--", *names, cwd=named)
    assert again.returncode == 0, again.describe()
    assert f"resuming: {len(names)} of {len(names)} files already done" in again.stderr


def record(file, **fields):
    from dentopo.formats import COLUMNS

    row = dict.fromkeys(COLUMNS)
    row.update({"file": file, "status": "ok", "dne": 0.5, "seconds": 0.25, **fields})
    return row


@pytest.mark.parametrize("suffix", [".csv", ".tsv", ".json", ".xlsx"])
@pytest.mark.parametrize("columns", ["dentopo", "molar"])
def test_every_text_column_round_trips_in_every_format(tmp_path, suffix, columns):
    from dentopo.formats import read_table, write_table

    if suffix == ".xlsx":
        pytest.importorskip("openpyxl")
    texts = [*FORMULAS, "-", "'", "=", "plain.ply", "a'b.ply", "x=1.ply"]
    records = [record(f"dir/{t}", method=t, error=t, status="error") for t in texts]
    records.append(record("@ok.ply", distance_type="-geodesic", sign_method="=x"))
    out = tmp_path / f"t{suffix}"
    write_table(out, records, columns=columns)
    back = read_table(out)
    for written, read in zip(records, back, strict=True):
        file = os.path.basename(written["file"]) if columns == "molar" else written["file"]
        assert read["file"] == file
        assert read["error"] == written["error"] and read["status"] == written["status"]
        if columns == "dentopo":
            for key in ("method", "distance_type", "sign_method"):
                assert read[key] == written[key], key
    if suffix in (".csv", ".tsv"):
        assert_no_live_formula(out, "," if suffix == ".csv" else "\t")
    if suffix == ".json":  # not a spreadsheet: the raw names
        stored = json.loads(out.read_text(encoding="utf-8"))
        assert stored[0]["error"] == FORMULAS[0]


def test_an_excel_table_stores_a_formula_name_as_a_text_cell(tmp_path):
    openpyxl = pytest.importorskip("openpyxl")
    from dentopo.formats import write_table

    out = tmp_path / "t.xlsx"
    names = ['=HYPERLINK("http://x","y").ply', "@SUM(A1).ply", "'quoted.ply"]
    write_table(out, [record(n) for n in names])
    sheet = openpyxl.load_workbook(out).worksheets[0]  # formulas as formulas, not values
    column = [row[0] for row in sheet.iter_rows(min_row=2)]
    assert [c.value for c in column] == names
    assert {c.data_type for c in column} == {"s"}  # strings, not "f" (formula)


def test_a_name_that_is_not_utf8_is_kept_in_the_journal_and_every_table(tmp_path):
    from dentopo.formats import Journal, read_journal, read_table, write_table

    name = os.fsdecode(b"caf\xe9 \xff.ply")  # Latin-1 bytes: surrogates in Python
    with Journal(tmp_path / "t.partial.jsonl") as journal:
        journal.append(record(name))
    [row], skipped = read_journal(tmp_path / "t.partial.jsonl")
    assert row["file"] == name and skipped == 0
    for suffix in (".csv", ".tsv", ".json"):
        write_table(tmp_path / f"t{suffix}", [record(name)])
        assert read_table(tmp_path / f"t{suffix}")[0]["file"] == name, suffix
    assert b"caf\xe9 \xff.ply" in (tmp_path / "t.csv").read_bytes()  # the name's own bytes


def test_the_command_measures_a_mesh_whose_name_is_not_utf8(tmp_path):
    write_tooth(tmp_path / os.fsdecode(b"\xff.ply"), 8)
    out = tmp_path / "t.csv"
    ran = dentopo(str(tmp_path), "-o", str(out), "-q")
    assert ran.returncode == 0, ran.describe()
    again = dentopo(str(tmp_path), "-o", str(out), "--resume")
    assert "resuming: 1 of 1 files already done" in again.stderr, again.describe()


# --- item 5: planted links ---------------------------------------------------------------


@pytest.fixture
def precious(tmp_path):
    path = tmp_path / "precious.txt"
    path.write_bytes(PRECIOUS)
    path.chmod(0o600)
    return path


def assert_untouched(precious):
    assert precious.read_bytes() == PRECIOUS
    assert stat.S_IMODE(precious.stat().st_mode) == 0o600


def test_a_link_planted_at_the_lock_is_refused_and_its_target_untouched(tmp_path, precious):
    mesh = write_tooth(tmp_path / "a.ply", 8)
    lock = tmp_path / ".out.csv.lock"
    lock.symlink_to(precious)
    ran = dentopo(str(mesh), "-o", str(tmp_path / "out.csv"))
    assert ran.returncode == 2, ran.describe()
    assert f"{str(lock)!r} is a symbolic link, not a dentopo lock file" in ran.stderr
    assert "Traceback" not in ran.stderr
    assert_untouched(precious)
    assert lock.is_symlink() and not (tmp_path / "out.csv").exists()


def test_a_dangling_link_at_the_lock_creates_nothing(tmp_path):
    from dentopo.formats import OutputLock

    lock = tmp_path / ".out.csv.lock"
    lock.symlink_to(tmp_path / "created-through-the-link")
    with pytest.raises(OSError, match="symbolic link"):  # ForeignLockError
        OutputLock(tmp_path / "out.csv").acquire()
    assert not (tmp_path / "created-through-the-link").exists()


@pytest.mark.parametrize(
    "kind, what",
    [("hard link", "a file with 2 names"), ("other content", "a file holding something else")],
)
def test_a_file_at_the_lock_that_is_not_a_lock_is_refused(tmp_path, precious, kind, what):
    mesh = write_tooth(tmp_path / "a.ply", 8)
    lock = tmp_path / ".out.csv.lock"
    if kind == "hard link":
        os.link(precious, lock)
    else:
        shutil.copy(precious, lock)
    ran = dentopo(str(mesh), "-o", str(tmp_path / "out.csv"))
    assert ran.returncode == 2, ran.describe()
    assert f"{str(lock)!r} is {what}" in ran.stderr and "not a dentopo lock file" in ran.stderr
    assert_untouched(precious)
    assert lock.read_bytes() == PRECIOUS


def test_a_lock_left_by_a_killed_run_is_taken_over(tmp_path):
    from dentopo.formats import OutputLock

    lock = tmp_path / ".out.csv.lock"
    lock.write_text("12345\n")  # its holder died: the lock is free, the file ours
    with OutputLock(tmp_path / "out.csv"):
        assert lock.read_text() == f"{os.getpid()}\n"
    assert not lock.exists()


@pytest.mark.parametrize("dangling", [False, True])
def test_a_link_planted_at_the_journal_is_refused_and_its_target_untouched(
    tmp_path, precious, dangling
):
    mesh = write_tooth(tmp_path / "a.ply", 8)
    journal = tmp_path / "out.csv.partial.jsonl"
    target = tmp_path / "created-through-the-link" if dangling else precious
    journal.symlink_to(target)
    ran = dentopo(str(mesh), "-o", str(tmp_path / "out.csv"))
    assert ran.returncode == 2, ran.describe()
    assert f"{str(journal)!r} is a symbolic link, not a dentopo journal" in ran.stderr
    assert "move it away" in ran.stderr and "Traceback" not in ran.stderr
    assert_untouched(precious)
    assert journal.is_symlink() and not (tmp_path / "created-through-the-link").exists()


def test_a_link_planted_at_a_temporary_name_is_skipped(tmp_path, precious, monkeypatch):
    import tempfile

    from dentopo.formats import read_table, write_table

    names = iter(["planted", "fresh"])
    monkeypatch.setattr(tempfile, "_get_candidate_names", lambda: names)
    planted = tmp_path / ".out.csv.planted.tmp"
    planted.symlink_to(precious)
    write_table(tmp_path / "out.csv", [record("a.ply")])
    assert [r["file"] for r in read_table(tmp_path / "out.csv")] == ["a.ply"]
    assert_untouched(precious)
    assert planted.is_symlink()


def test_a_temporary_file_swapped_for_a_link_is_not_renamed_over_the_table(tmp_path, precious):
    from dentopo.formats import atomic_write

    table = tmp_path / "out.csv"
    table.write_text("old rows\n")

    def swap(stream):  # another user replaces the temporary name with a link meanwhile
        [temporary] = tmp_path.glob(".out.csv.*.tmp")
        temporary.unlink()
        temporary.symlink_to(precious)
        stream.write("new rows\n")

    with pytest.raises(FileExistsError, match="replaced while it was written"):
        atomic_write(table, swap)
    assert_untouched(precious)
    assert not table.is_symlink() and table.read_text() == "old rows\n"
    assert list(tmp_path.glob(".out.csv.*")) == []


# --- item 12: a foreign file at the journal's path ---------------------------------------


@pytest.mark.parametrize(
    "content, what",
    [
        (b"hello, world\nsecond line\n", "a file of other content"),
        (b'{"a": 1}\n{"file": "x.ply", "status": "ok"}\n', "a file of JSON"),
        (b"\xff\xfe binary \x00\n", "a file of other content"),
    ],
)
def test_a_foreign_file_at_the_journal_is_named_and_left_alone(tmp_path, content, what):
    mesh = write_tooth(tmp_path / "a.ply", 8)
    out = tmp_path / "out.csv"
    out.write_text("file,status\nold.ply,ok\n")
    journal = tmp_path / "out.csv.partial.jsonl"
    journal.write_bytes(content)
    ran = dentopo(str(mesh), "-o", str(out), "--resume")
    assert ran.returncode == 2, ran.describe()
    assert f"{str(journal)!r} is {what}" in ran.stderr and "not a dentopo journal" in ran.stderr
    assert "move it away" in ran.stderr
    assert "killed" not in ran.stderr and "earlier run" not in ran.stderr
    assert journal.read_bytes() == content  # never deleted, read as rows or appended to
    assert out.read_text() == "file,status\nold.ply,ok\n"


def test_a_fifo_at_the_journal_is_named_and_does_not_hang(tmp_path):
    mesh = write_tooth(tmp_path / "a.ply", 8)
    journal = tmp_path / "out.csv.partial.jsonl"
    os.mkfifo(journal)
    ran = dentopo(str(mesh), "-o", str(tmp_path / "out.csv"), timeout=60)
    assert ran.returncode == 2, ran.describe()
    assert f"{str(journal)!r} is not a regular file, not a dentopo journal" in ran.stderr
    assert stat.S_ISFIFO(journal.lstat().st_mode)


def test_a_journal_says_what_it_is_and_one_of_the_earlier_version_still_reads(tmp_path):
    from dentopo.formats import JOURNAL_HEADER, Journal, read_journal

    mesh = write_tooth(tmp_path / "a.ply", 8)
    out = tmp_path / "out.csv"
    with Journal(tmp_path / "new.partial.jsonl") as journal:
        journal.append(record("a.ply"))
    first = (tmp_path / "new.partial.jsonl").read_text().splitlines()[0]
    assert json.loads(first) == JOURNAL_HEADER
    # the earlier version's journal: rows from the first line on, the last cut short
    row = json.dumps(record(str(mesh), seconds=0.125))
    (tmp_path / "out.csv.partial.jsonl").write_text(row + "\n" + row[:20])
    assert len(read_journal(tmp_path / "out.csv.partial.jsonl")[0]) == 1
    ran = dentopo(str(mesh), "-o", str(out), "--resume")
    assert ran.returncode == 0, ran.describe()
    assert "added 1 row of an earlier run" in ran.stderr
    assert "1 unreadable line skipped (cut short by a kill)" in ran.stderr
    assert not (tmp_path / "out.csv.partial.jsonl").exists()


# --- item 6: markup in a name ------------------------------------------------------------

MARKUP = "<!--<script>x.ply"
LINK = '<a href="http://x">g</a>'


def json_blocks(page: str) -> list[str]:
    return re.findall(r'<script type="application/json"[^>]*>(.*?)</script>', page, re.S)


def assert_blocks_are_inert(page: str) -> None:
    blocks = json_blocks(page)
    assert blocks
    for block in blocks:
        assert not set("<>&") & set(block), block[:200]
        json.loads(block)


def test_every_json_block_of_a_page_escapes_markup(tmp_path):
    pytest.importorskip("pyvista")
    from dentopo.figures import read_provenance

    mesh = write_tooth(tmp_path / MARKUP, 12)
    page = tmp_path / "view.html"
    ran = dentopo(str(mesh), "--html", str(page), "-q")
    assert ran.returncode == 0, ran.describe()
    text = page.read_text()
    assert_blocks_are_inert(text)
    assert "<!--" not in text
    assert read_provenance(page)["input"]["file"] == MARKUP


def test_a_name_holding_a_template_placeholder_stays_text(tmp_path):
    from dentopo.figures._html import write_html
    from dentopo.figures._provenance import html_block

    page = tmp_path / "p.html"
    record = {"input": {"file": "%DATA%%SCRIPT%.ply"}}
    write_html(page, [], title="%SCRIPT% %BAR%", bar="%DATA%", provenance=record)
    text = page.read_text()
    assert text.count('"use strict"') == 1 and html_block(record) in text
    assert "<title>dentopo: %SCRIPT% %BAR%</title>" in text


@pytest.fixture(scope="module")
def hostile_report(tmp_path_factory):
    pytest.importorskip("plotly")
    pytest.importorskip("pyvista")
    root = tmp_path_factory.mktemp("hostile")
    write_tooth(root / MARKUP, 12)
    write_tooth(root / "b.ply", 10)
    write_tooth(root / "c.ply", 14)
    groups = root / "groups.csv"
    with open(groups, "w", newline="", encoding="utf-8") as stream:
        writer = csv.writer(stream)
        writer.writerows([("file", "group"), (MARKUP, LINK), ("b.ply", LINK), ("c.ply", "plain")])
    table, page = root / "t.csv", root / "report.html"
    ran = dentopo(str(root / MARKUP), str(root / "b.ply"), str(root / "c.ply"), "-o", str(table))
    assert ran.returncode == 0, ran.describe()
    ran = dentopo("report", str(table), "-o", str(page), "--groups", str(groups))
    assert ran.returncode == 0, ran.describe()
    return page


def test_the_report_keeps_markup_out_of_its_json(hostile_report):
    text = hostile_report.read_text()
    assert_blocks_are_inert(text)
    assert "<!--" not in text
    assert LINK not in text and MARKUP not in text  # shown only escaped


def test_the_report_and_the_view_show_markup_as_text_in_chromium(hostile_report, tmp_path):
    from test_html import CHROMIUM
    from test_report import _dom, _status

    if CHROMIUM is None:
        pytest.skip("headless Chromium (Debian package 'chromium') is not installed")
    dom, log = _dom(tmp_path, hostile_report.as_uri())
    status = _status(dom)
    assert status["ready"] == "yes", status  # the page's scripts ran
    assert status["errors"] == "" and not re.search(r"CONSOLE.*(Uncaught|Error)", log), log
    assert not re.search(r'<a\b[^>]*href="http://x"', dom)  # no live link, in HTML or SVG
    shown = LINK.replace("<", "&lt;").replace(">", "&gt;")  # a text node, serialised
    plot = re.search(r'<div class="group-plot[^"]*" id="box-dne"[^>]*>(.*?)</svg>', dom, re.S)
    assert plot and shown in plot.group(1)  # the group's name drawn as text
    assert "&lt;!--&lt;script&gt;x" in dom  # the specimen's name shown as text


def test_the_view_of_a_mesh_with_markup_in_its_name_runs_in_chromium(tmp_path):
    pytest.importorskip("pyvista")
    from test_html import CHROMIUM, chromium

    if CHROMIUM is None:
        pytest.skip("headless Chromium (Debian package 'chromium') is not installed")
    mesh = write_tooth(tmp_path / MARKUP, 12)
    page = tmp_path / "view.html"
    assert dentopo(str(mesh), "--html", str(page), "-q").returncode == 0
    dom = chromium(tmp_path, page.as_uri(), "--dump-dom").stdout
    assert re.search(r'<div id="status"[^>]*data-ready="yes"', dom), dom[-2000:]
