"""Outputs that land on inputs or on each other, and an all-partial run (issue 22, items 7-8).

Before the fix ``--report normal.ply``, ``--html normal.ply`` and ``dentopo report
t.csv -o other.ply`` replaced the mesh with HTML and exited 0; ``-o
pv/NAME.dentopo.csv --per-vertex pv`` replaced a per-vertex file with the table;
two runs into one ``--per-vertex`` folder silently replaced each other's files;
and a run whose every row was ``partial`` kept the old table, said "no mesh was
computed" and dropped its rows.
"""

from __future__ import annotations

import csv
import os

import pytest

from faults.harness import dentopo
from faults.live import write_tooth


def rows(path):
    with open(path, newline="", encoding="utf-8") as stream:
        return {os.path.basename(r["file"]): r for r in csv.DictReader(stream)}


def assert_refused(ran, path: str, why: str):
    """Exit 2 before any mesh was computed, one line naming `path` and saying `why`."""
    assert ran.returncode == 2, ran.describe()
    assert "ok (" not in ran.stderr and "Traceback" not in ran.stderr, ran.describe()
    lines = ran.stderr.strip().splitlines()
    assert len(lines) == 1, ran.describe()
    assert repr(path) in lines[0] and why in lines[0], ran.describe()


@pytest.fixture
def mesh(tmp_path):
    return write_tooth(tmp_path / "normal.ply", 12)


@pytest.fixture
def table(tmp_path, mesh):
    out = tmp_path / "t.csv"
    ran = dentopo(str(mesh), "-o", str(out), "-q")
    assert ran.returncode == 0, ran.describe()
    return out


# --- item 7: an output that is an input ------------------------------------------------------


def test_report_onto_the_input_mesh_is_refused_and_the_mesh_kept(mesh, tmp_path):
    before = mesh.read_bytes()
    ran = dentopo(str(mesh), "-o", str(tmp_path / "t.csv"), "--report", str(mesh))
    assert_refused(ran, str(mesh), "is the input mesh")
    assert mesh.read_bytes() == before
    assert not (tmp_path / "t.csv").exists()


def test_html_onto_the_input_mesh_is_refused_and_the_mesh_kept(mesh):
    before = mesh.read_bytes()
    ran = dentopo(str(mesh), "--html", str(mesh))
    assert_refused(ran, str(mesh), "is the input mesh")
    assert mesh.read_bytes() == before


def test_an_output_reached_through_a_symbolic_link_or_a_relative_path_is_the_input(mesh, tmp_path):
    before = mesh.read_bytes()
    (tmp_path / "link.html").symlink_to(mesh)
    ran = dentopo(str(mesh), "--html", str(tmp_path / "link.html"))
    assert_refused(ran, str(tmp_path / "link.html"), "is the input mesh")
    (tmp_path / "sub").mkdir()
    ran = dentopo("normal.ply", "--html", "sub/../normal.ply", cwd=tmp_path)
    assert_refused(ran, "sub/../normal.ply", "is the input mesh")
    assert mesh.read_bytes() == before


def test_a_table_reached_through_a_hard_link_is_the_input(tmp_path):
    source = write_tooth(tmp_path / "mesh.ply", 12)
    os.link(source, tmp_path / "same.csv")
    before = source.read_bytes()
    ran = dentopo(str(source), "-o", str(tmp_path / "same.csv"))
    assert_refused(ran, str(tmp_path / "same.csv"), "is the input mesh")
    assert source.read_bytes() == before


def test_report_subcommand_onto_a_mesh_or_the_table_is_refused(table, mesh, tmp_path):
    before = mesh.read_bytes()
    ran = dentopo("report", str(table), "-o", str(tmp_path / "other.ply"))
    assert_refused(ran, str(tmp_path / "other.ply"), "must end in .html or .htm")
    ran = dentopo("report", str(table), "-o", str(mesh))
    assert_refused(ran, str(mesh), "must end in .html or .htm")
    (tmp_path / "t.html").symlink_to(table)
    ran = dentopo("report", str(table), "-o", str(tmp_path / "t.html"))
    assert_refused(ran, str(tmp_path / "t.html"), "is the table")
    assert mesh.read_bytes() == before
    assert not (tmp_path / "other.ply").exists()


def test_report_and_html_need_an_html_suffix(mesh, tmp_path):
    ran = dentopo(str(mesh), "-o", str(tmp_path / "t.csv"), "--report", str(tmp_path / "r.pdf"))
    assert_refused(ran, str(tmp_path / "r.pdf"), "must end in .html or .htm")
    ran = dentopo(str(mesh), "--html", str(tmp_path / "view.png"))
    assert_refused(ran, str(tmp_path / "view.png"), "must end in .html or .htm")


# --- item 7: an output that is another output of the same run --------------------------------


def test_a_table_that_is_one_of_the_per_vertex_files_is_refused(mesh, tmp_path):
    pv = tmp_path / "pv"
    pv.mkdir()
    (pv / "normal.dentopo.csv").write_text("precious\n")
    ran = dentopo(str(mesh), "-o", str(pv / "normal.dentopo.csv"), "--per-vertex", str(pv))
    assert_refused(ran, str(pv / "normal.dentopo.csv"), "per-vertex file of")
    assert (pv / "normal.dentopo.csv").read_text() == "precious\n"


def test_two_options_naming_one_file_are_refused(mesh, tmp_path):
    page = str(tmp_path / "v.html")
    ran = dentopo(str(mesh), "--html", page, "--panel", os.path.join(str(tmp_path), ".", "v.html"))
    assert_refused(ran, page, "is also --html")
    ran = dentopo(str(mesh), "-o", str(tmp_path / "t.csv"), "--report", page, "--html", page)
    assert_refused(ran, page, "is also --report")
    assert not os.path.exists(page)


# --- item 7: two runs into one per-vertex folder ---------------------------------------------


def test_a_run_replacing_another_meshs_per_vertex_files_says_so(tmp_path):
    for folder in ("a", "b"):
        (tmp_path / folder).mkdir()
        write_tooth(tmp_path / folder / "tooth.ply", 8 if folder == "a" else 9)
    pv = str(tmp_path / "pv")
    first = dentopo(str(tmp_path / "a"), "--per-vertex", pv, "-q")
    assert first.returncode == 0 and "warning" not in first.stderr, first.describe()
    again = dentopo(str(tmp_path / "a"), "--per-vertex", pv, "-q")  # the same mesh: no warning
    assert again.returncode == 0 and "warning" not in again.stderr, again.describe()
    second = dentopo(str(tmp_path / "b"), "--per-vertex", pv, "-q")
    assert second.returncode == 0, second.describe()
    [line] = [line for line in second.stderr.splitlines() if "warning" in line]
    assert "tooth.dentopo.*" in line and "replaced" in line, second.describe()
    assert str(tmp_path / "a" / "tooth.ply") in line and str(tmp_path / "b" / "tooth.ply") in line


# --- item 8: an all-partial run is written ---------------------------------------------------


def test_an_all_partial_run_replaces_the_old_table_with_its_rows(tmp_path, table, mesh):
    before = rows(table)["normal.ply"]
    assert before["status"] == "ok"
    # RFI fails on every mesh at this alpha ("alpha adjustment required"): every row is partial
    ran = dentopo(str(mesh), "--metrics", "ariadne,rfi", "--alpha", "0.01", "-o", str(table))
    assert ran.returncode == 1, ran.describe()
    assert "no mesh was computed" not in ran.stderr, ran.describe()
    assert "wrote 1 row to" in ran.stderr and "1 partial" in ran.stderr, ran.describe()
    after = rows(table)["normal.ply"]
    assert after["status"] == "partial" and "alpha adjustment required" in after["error"]
    assert after["dne"] == before["dne"]  # the metric that succeeded is kept
    assert not (tmp_path / "t.csv.partial.jsonl").exists()


def test_every_file_failing_keeps_the_old_table_and_says_so(tmp_path, table):
    before = table.read_bytes()
    ran = dentopo(str(tmp_path / "missing.ply"), "-o", str(table))
    assert ran.returncode == 1, ran.describe()
    assert "no mesh was computed (every file failed)" in ran.stderr, ran.describe()
    assert table.read_bytes() == before


# --- the study commands' output folder ---------------------------------------------------------
# Before the fix ``dentopo sweep normal.ply -o normal.ply`` computed every bandwidth and then
# failed to create the folder (exit 1); a folder holding an input under a name the study
# writes was not checked at all.


@pytest.mark.parametrize("command", ["sweep", "robustness"])
def test_a_study_folder_that_is_the_input_mesh_is_refused_before_computing(mesh, command):
    before = mesh.read_bytes()
    ran = dentopo(command, str(mesh), "-o", str(mesh), "--no-figures", "--sign-method", "centroid")
    assert_refused(ran, str(mesh), "is the input mesh")
    assert "dentopo " + command in ran.stderr, ran.describe()
    assert mesh.read_bytes() == before


def test_a_study_folder_holding_a_perturbation_under_the_tables_name_is_refused(mesh, tmp_path):
    folder = tmp_path / "study"
    folder.mkdir()
    kept = folder / "robustness.csv"  # a perturbation where the table would go
    kept.write_bytes(mesh.read_bytes())
    ran = dentopo(
        "robustness",
        str(mesh),
        "--perturbation",
        f"same={kept}",
        "-o",
        str(folder),
        "--no-figures",
    )
    assert_refused(ran, str(kept), "is the perturbation 'same'")
    assert kept.read_bytes() == mesh.read_bytes()


def test_a_study_figure_that_is_the_input_reached_through_a_link_is_refused(mesh, tmp_path):
    folder = tmp_path / "sweep"
    folder.mkdir()
    (folder / "sweep.png").symlink_to(mesh)
    before = mesh.read_bytes()
    ran = dentopo("sweep", str(mesh), "-o", str(folder), "-b", "0.08")
    assert ran.returncode == 2, ran.describe()
    assert "is the input mesh" in ran.stderr and "sweep.png" in ran.stderr, ran.describe()
    assert mesh.read_bytes() == before
    assert not (folder / "sweep.csv").exists()


def test_a_study_folder_that_is_a_file_is_refused_before_computing(mesh, tmp_path):
    other = tmp_path / "notes.txt"
    other.write_text("mine\n")
    ran = dentopo("sweep", str(mesh), "-o", str(other), "--no-figures", "-b", "0.08")
    assert_refused(ran, str(other), "is not a directory")
    assert other.read_text() == "mine\n"
