"""Result tables: formats read back exactly, column layouts, ``-o -``, old tables kept."""

from __future__ import annotations

import csv
import io
import json
import math
import re
import sys

import openpyxl
import pytest
import trimesh

from dentopo import COLUMNS, ariaDNE, compute_batch, read_table, write_table
from dentopo._optional import MissingExtraError
from dentopo.cli import main
from dentopo.formats import FORMATS, LAYOUTS, output_format, table_format
from dentopo.samples import tooth

#: The published signDNE 0.1.4 command line's header, in its order.
SIGNDNE_HEADER = (
    "File",
    "DNE",
    "positive_DNE",
    "negative_DNE",
    "surface_area",
    "positive_surface_area",
    "negative_surface_area",
)
SIGNDNE_NUMBER = re.compile(r"^-?\d+\.\d{16}$")


@pytest.fixture(scope="module")
def meshes(tmp_path_factory):
    """Two small meshes and a file that is not a mesh."""
    folder = tmp_path_factory.mktemp("meshes")
    tooth(rings=8).export(folder / "a_tooth.ply")
    trimesh.creation.icosphere(subdivisions=2).export(folder / "b_sphere.ply")
    (folder / "c_bad.ply").write_text("not a mesh")
    return folder


@pytest.fixture(scope="module")
def records(meshes):
    """A batch's records (two ok, one failed) and a row with awkward values."""
    batch = compute_batch(meshes)
    awkward = dict(batch[0])
    awkward.update(
        file='=cmd|" ,\tname\u00e9.ply',  # a formula-like, quoted, comma, tab, non-ASCII name
        dne=0.1 + 0.2,  # needs 17 significant digits
        positive_dne=1 / 3,
        negative_dne=5e-324,
        surface_area=123456789.12345679,
        positive_surface_area=math.inf,
        negative_surface_area=math.nan,
        seconds=None,
    )
    return [*batch, awkward]


def same(a, b) -> bool:
    """Records equal, NaN equal to NaN."""
    if a.keys() != b.keys():
        return False
    for key in a:
        x, y = a[key], b[key]
        if isinstance(x, float) and isinstance(y, float) and math.isnan(x) and math.isnan(y):
            continue
        if x != y or type(x) is not type(y):
            return False
    return True


def test_the_registry_maps_each_suffix_to_a_format():
    assert set(FORMATS) == {".csv", ".tsv", ".json", ".xlsx"}
    for suffix, fmt in FORMATS.items():
        assert fmt.suffix == suffix and output_format(f"t{suffix.upper()}") == fmt.name
    with pytest.raises(ValueError, match="use one of the extensions"):
        table_format("table.parquet")


@pytest.mark.parametrize("suffix", sorted(FORMATS))
def test_every_format_reads_back_exactly(tmp_path, records, suffix):
    path = tmp_path / f"table{suffix}"
    assert write_table(path, records) == len(records)
    back = read_table(path)
    finite = records[:-1]
    assert back[: len(finite)] == finite  # types too: int, float, str, None
    for name in ("vertices", "faces"):
        assert all(type(r[name]) is int for r in back if r["status"] == "ok")
    last, expected = back[-1], records[-1]
    if suffix == ".json":  # JSON has no inf or nan: they are null
        expected = {**expected, "positive_surface_area": None, "negative_surface_area": None}
    assert same(last, expected)


def test_text_tables_hold_the_shortest_exact_numbers(tmp_path, records):
    path = tmp_path / "t.tsv"
    write_table(path, records)
    lines = path.read_text(encoding="utf-8").splitlines()
    assert lines[0].split("\t") == list(COLUMNS)
    awkward = next(csv.reader(io.StringIO(lines[-1]), delimiter="\t"))
    assert awkward[1:4] == ["0.30000000000000004", "0.3333333333333333", "5e-324"]
    failed = dict(
        zip(COLUMNS, next(csv.reader(io.StringIO(lines[3]), delimiter="\t")), strict=True)
    )
    assert failed["status"] == "error" and failed["dne"] == "" and failed["vertices"] == ""


def test_excel_cells_are_numbers_and_text_stays_text(tmp_path, records):
    path = tmp_path / "t.xlsx"
    write_table(path, records)
    workbook = openpyxl.load_workbook(path)
    sheet = workbook.worksheets[0]
    rows = list(sheet.iter_rows())
    assert [cell.value for cell in rows[0]] == list(COLUMNS)
    index = {name: i for i, name in enumerate(COLUMNS)}
    ok = rows[1]
    assert ok[index["dne"]].data_type == "n" and isinstance(ok[index["dne"]].value, float)
    assert ok[index["vertices"]].data_type == "n" and type(ok[index["vertices"]].value) is int
    assert ok[index["error"]].value is None  # missing: an empty cell
    failed = rows[3]
    assert failed[index["dne"]].value is None and failed[index["status"]].value == "error"
    awkward = rows[4]
    assert awkward[index["file"]].data_type == "s"  # not a formula
    assert awkward[index["file"]].value == records[-1]["file"]
    assert awkward[index["dne"]].value == 0.1 + 0.2  # all 17 digits
    workbook.close()


def test_excel_without_openpyxl_names_the_extra(tmp_path, records, monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "openpyxl", None)  # import openpyxl now fails
    path = tmp_path / "t.xlsx"
    with pytest.raises(MissingExtraError, match=r"pip install 'dentopo\[excel\]'"):
        write_table(path, records)
    assert list(tmp_path.iterdir()) == []  # no temporary file left
    mesh = tmp_path / "m.ply"
    tooth(rings=6).export(mesh)
    assert main([str(mesh), "-o", str(path)]) == 2
    assert "Excel tables need the excel extra" in capsys.readouterr().err


def test_a_text_stream_gets_csv(records):
    stream = io.StringIO()
    write_table(stream, records[:3])
    rows = list(csv.DictReader(io.StringIO(stream.getvalue())))
    assert [row["file"] for row in rows] == [r["file"] for r in records[:3]]
    with pytest.raises(ValueError, match="not to a text stream"):
        write_table(io.StringIO(), records, format="xlsx")


def test_signdne_columns_as_the_published_cli_writes_them(tmp_path, records):
    ok = [r for r in records[:3] if r["status"] == "ok"]
    path = tmp_path / "published.csv"
    assert write_table(path, records[:3], columns="signdne") == len(ok)  # failed rows left out
    with open(path, newline="", encoding="utf-8") as stream:
        rows = list(csv.reader(stream))
    assert tuple(rows[0]) == SIGNDNE_HEADER
    assert [row[0] for row in rows[1:]] == [r["file"] for r in ok]
    for row, record in zip(rows[1:], ok, strict=True):
        assert all(SIGNDNE_NUMBER.match(cell) for cell in row[1:])
        assert row[1:] == [
            f"{record[key]:.16f}"
            for key in (
                "dne",
                "positive_dne",
                "negative_dne",
                "surface_area",
                "positive_surface_area",
                "negative_surface_area",
            )
        ]
        assert float(row[3]) >= 0  # negative_DNE: a magnitude
    # read back (a table of the published CLI reads too): ok rows, numbers to 1e-16
    back = read_table(path)
    assert [r["file"] for r in back] == [r["file"] for r in ok]
    assert all(r["status"] == "ok" and r["bandwidth"] is None for r in back)
    assert all(abs(b["dne"] - r["dne"]) <= 1e-16 for b, r in zip(back, ok, strict=True))


@pytest.mark.parametrize("suffix", [".json", ".xlsx"])
def test_signdne_columns_keep_numbers_in_typed_formats(tmp_path, records, suffix):
    path = tmp_path / f"published{suffix}"
    write_table(path, records[:3], columns="signdne")
    back = read_table(path)
    ok = [r for r in records[:3] if r["status"] == "ok"]
    assert [(r["file"], r["dne"], r["negative_surface_area"]) for r in back] == [
        (r["file"], r["dne"], r["negative_surface_area"]) for r in ok
    ]
    if suffix == ".json":
        assert tuple(json.loads(path.read_text())[0]) == SIGNDNE_HEADER


def test_unknown_layouts_and_other_tables_are_refused(tmp_path, records):
    assert set(LAYOUTS) == {"dentopo", "signdne", "molar", "doolkit", "morphotester"}
    with pytest.raises(ValueError, match="unknown columns"):
        write_table(tmp_path / "t.csv", records, columns="morphosource")
    other = tmp_path / "other.tsv"
    other.write_text("a\tb\n1\t2\n")
    with pytest.raises(ValueError, match="not a dentopo results table"):
        read_table(other)
    broken = tmp_path / "broken.xlsx"
    broken.write_text("not a zip")
    with pytest.raises(ValueError, match="not an Excel workbook"):
        read_table(broken)
    empty = tmp_path / "empty.csv"
    empty.write_text("")
    assert read_table(empty) == []


# --- the command line ------------------------------------------------------------------------


def test_dash_writes_csv_on_stdout_and_nothing_else(meshes, capsys):
    good = [str(meshes / "a_tooth.ply"), str(meshes / "b_sphere.ply")]
    assert main([*good, "-o", "-"]) == 0
    out, err = capsys.readouterr()
    rows = list(csv.reader(io.StringIO(out)))
    assert tuple(rows[0]) == COLUMNS
    assert len(rows) == 1 + len(good)  # exactly the rows
    assert [row[0] for row in rows[1:]] == good
    for row, file in zip(rows[1:], good, strict=True):
        assert float(row[1]) == ariaDNE(file).dne  # full precision
        assert row[COLUMNS.index("status")] == "ok"
    assert "[2/2]" in err and "[" not in out  # progress on stderr only


def test_dash_with_signdne_columns_and_a_failed_file(meshes, capsys):
    files = [str(meshes / "a_tooth.ply"), str(meshes / "c_bad.ply")]
    assert main([*files, "-o", "-", "--columns", "signdne", "-q"]) == 1
    out, err = capsys.readouterr()
    rows = list(csv.reader(io.StringIO(out)))
    assert tuple(rows[0]) == SIGNDNE_HEADER and [row[0] for row in rows[1:]] == files[:1]
    assert "c_bad.ply: error" in err and "1 failed file left out" in err


def test_signdne_columns_printed_without_output(meshes, capsys):
    assert main([str(meshes / "a_tooth.ply"), "--columns", "SignDNE", "-q"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].split() == list(SIGNDNE_HEADER) and len(lines) == 2
    assert all(SIGNDNE_NUMBER.match(cell) for cell in lines[1].split()[1:])


@pytest.mark.parametrize(
    ("options", "message"),
    [
        (["-o", "-", "--resume"], "not '-'"),
        (["-o", "t.csv", "--resume", "--columns", "signdne"], "resume without --columns"),
        (["--columns", "morphosource"], "invalid choice"),
    ],
)
def test_output_usage_errors(meshes, tmp_path, monkeypatch, capsys, options, message):
    monkeypatch.chdir(tmp_path)
    assert main([str(meshes / "a_tooth.ply"), *options]) == 2
    out, err = capsys.readouterr()
    assert message in err and out == ""
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("suffix", sorted(FORMATS))
def test_resume_works_from_every_format(meshes, tmp_path, capsys, suffix):
    out = tmp_path / f"results{suffix}"
    assert main([str(meshes), "-o", str(out), "-q"]) == 1  # c_bad fails
    before = read_table(out)
    written = out.read_bytes()
    assert [r["status"] for r in before] == ["ok", "ok", "error"]
    capsys.readouterr()
    good = [str(meshes / "a_tooth.ply"), str(meshes / "b_sphere.ply")]
    assert main([*good, "-o", str(out), "--resume"]) == 0
    err = capsys.readouterr().err
    assert "resuming: 2 of 2 files already done" in err and "left as it was" in err
    assert out.read_bytes() == written


def test_a_run_where_nothing_computes_keeps_the_old_table(tmp_path, capsys):
    keep = tmp_path / "keep.csv"
    keep.write_text("precious results\n")
    missing = tmp_path / "missing.ply"
    bad = tmp_path / "bad.ply"
    bad.write_text("not a mesh")
    assert main([str(missing), str(bad), "-o", str(keep)]) == 1
    err = capsys.readouterr().err
    assert "no mesh was computed" in err and "keep.csv left as it was" in err
    assert keep.read_text() == "precious results\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.ply", "keep.csv"]


def test_a_run_where_some_compute_writes_every_row(tmp_path, capsys):
    keep = tmp_path / "keep.csv"
    keep.write_text("old results\n")
    good = tmp_path / "good.ply"
    tooth(rings=6).export(good)
    assert main([str(good), str(tmp_path / "missing.ply"), "-o", str(keep), "-q"]) == 1
    rows = read_table(keep)
    assert [(r["file"], r["status"]) for r in rows] == [
        (str(good), "ok"),
        (str(tmp_path / "missing.ply"), "error"),
    ]
    assert rows[1]["error"] == "file not found"


def test_a_run_where_nothing_computes_writes_a_new_table(tmp_path, capsys):
    out = tmp_path / "new.csv"
    assert main([str(tmp_path / "missing.ply"), "-o", str(out), "-q"]) == 1
    assert [r["status"] for r in read_table(out)] == ["error"]  # nothing to keep: the reasons
