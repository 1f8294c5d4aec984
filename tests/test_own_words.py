"""The package's own words, as a user reads them (issue 32, part 4).

Values the package writes into a table never begin with a character the formula
guard quotes; ``prepare --faces N`` above a mesh's count says so; stderr has one
short line per file and warning, the long explanation once per run; every row is
counted; ``info`` says what it takes; the preview draws no axis it did not find.
"""

from __future__ import annotations

import csv
import dataclasses
import json
import os
import re
import shutil

import numpy as np
import pytest
import trimesh

from dentopo.cli import main
from dentopo.cli._arguments import build_parser
from dentopo.cli._briefs import SEE_BELOW, Briefing
from dentopo.cli._hints import CommandLineHints
from dentopo.cli._prepare import build_parser as build_prepare_parser
from dentopo.formats import read_record, read_table
from dentopo.formats._tables import _FORMULA_STARTS
from dentopo.mesh import boundary_edges
from dentopo.samples import sample_paths, tooth
from dentopo.topography import Orientation

#: What the formula guard quotes at the start of a text cell (the apostrophe it adds aside).
GUARDED = tuple(c for c in _FORMULA_STARTS if c != "'")


def run(capsys, *argv) -> tuple[int, str, str]:
    code = main([os.fspath(a) for a in argv])
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def upside_down(mesh: trimesh.Trimesh) -> trimesh.Trimesh:
    """`mesh` turned by 180 degrees about x (a crown pointing to -z), faces as they were."""
    return trimesh.Trimesh(mesh.vertices * [1.0, -1.0, -1.0], mesh.faces, process=False)


def inside_out(mesh: trimesh.Trimesh) -> trimesh.Trimesh:
    """`mesh` with every face wound the other way."""
    return trimesh.Trimesh(mesh.vertices, mesh.faces[:, ::-1], process=False)


def closed_crown(height: float = 2.0) -> trimesh.Trimesh:
    """The sample crown stretched up by `height` and closed under its rim by a fan."""
    crown = tooth(rings=12)
    vertices, faces = np.asarray(crown.vertices) * [1.0, 1.0, height], np.asarray(crown.faces)
    rim = boundary_edges(faces, len(vertices))
    centre = len(vertices)
    vertices = np.vstack([vertices, vertices[np.unique(rim)].mean(axis=0)])
    fan = np.column_stack([rim[:, 1], rim[:, 0], np.full(len(rim), centre)])
    return trimesh.Trimesh(vertices, np.vstack([faces, fan]), process=False)


# --- 1. words first: no table cell of the package's own begins as a formula


ORIENTATIONS = {
    "points +z": Orientation("+z", "open base"),
    "points -z": Orientation("-z", "open base"),
    "points -z, turned to +z": Orientation("-z", "open base", turned=True),
    "direction undetermined": Orientation("undetermined", "flat", winding="undetermined"),
    "direction undetermined; closed, as it lies": Orientation("undetermined", "area"),
    "points -z; closed, as it lies": Orientation("-z", "area"),
    "points +z; wound inward": Orientation("+z", "open base", winding="inward"),
    "points -z, turned to +z; wound inward, rewound": Orientation(
        "-z", "open base", turned=True, winding="inward", rewound=True
    ),
    "points +z; 12 faces wound inward, rewound": Orientation(
        "+z", "open base", winding="mixed", rewound=True, inward_faces=12, faces=100
    ),
}


@pytest.mark.parametrize("expected", ORIENTATIONS)
def test_the_orientation_column_begins_with_a_word(expected):
    found = ORIENTATIONS[expected]
    assert str(found) == expected
    assert not str(found).startswith(GUARDED)
    assert found.points in ("+z", "-z", "undetermined")  # the API keeps the bare direction


def test_a_metrics_all_table_quotes_no_cell_but_the_names_chosen_so(tmp_path, capsys, monkeypatch):
    folder = tmp_path / "meshes"
    folder.mkdir()
    monkeypatch.chdir(folder)  # the file column holds the names as given: "=sum(a1).ply"
    samples = sample_paths()
    shutil.copy(samples["tooth"], folder / "=sum(a1).ply")  # names a spreadsheet would run
    upside_down(tooth(rings=12)).export(folder / "+tilted.ply")
    shutil.copy(samples["sphere"], folder / "sphere.ply")  # closed
    shutil.copy(samples["saddle"], folder / "saddle.ply")  # flat
    inside_out(tooth(rings=12)).export(folder / "inward.ply")
    orientations = set()
    for orient in ("auto", "as-is"):
        table = tmp_path / f"{orient}.csv"
        names = sorted(os.listdir(folder))
        code, _, err = run(
            capsys, *names, "--metrics", "all", "--orient", orient, "-o", table, "-q"
        )
        assert code in (0, 1), err  # 1: some metric failed on a closed or flat surface
        with open(table, newline="", encoding="utf-8") as stream:
            rows = list(csv.reader(stream))
        header, rows = rows[0], rows[1:]
        assert len(rows) == 5 and "orientation" in header and "warnings" in header
        quoted = {
            (header[i], cell) for row in rows for i, cell in enumerate(row) if cell[:1] == "'"
        }
        chosen = {("file", "'=sum(a1).ply"), ("file", "'+tilted.ply")}
        assert quoted == chosen  # the guard still quotes the names, and nothing of ours
        orientations |= {row["orientation"] for row in read_table(table)}
    assert {
        "points -z, turned to +z",
        "points -z",
        "direction undetermined; closed, as it lies",
        "direction undetermined",
        "points +z; wound inward, rewound",
        "points +z; wound inward",
    } <= orientations


def test_a_prepare_record_says_nothing_of_its_own_that_begins_as_a_formula(tmp_path, capsys):
    raw = tmp_path / "raw"
    raw.mkdir()
    upside_down(tooth(rings=12)).export(raw / "down.ply")
    shutil.copy(sample_paths()["sphere"], raw / "sphere.ply")
    closed_crown().export(raw / "closed.ply")
    out = tmp_path / "out"
    code = main(["prepare", str(raw), "-o", str(out), "--spin", "footprint", "--faces", "400"])
    capsys.readouterr()
    assert code == 0

    def texts(value, key=""):
        if isinstance(value, dict):
            for name, item in value.items():
                yield from texts(item, name)
        elif isinstance(value, list):
            for item in value:
                yield from texts(item, key)
        elif isinstance(value, str) and key not in ("path", "file", "name"):
            yield key, value

    found = [text for path in out.glob("*.prepare.json") for text in texts(read_record(path))]
    assert len(found) > 20 and any(key == "spin" for key, _ in found)
    assert [text for text in found if text[1].startswith(GUARDED)] == []


# --- 2. prepare --faces N above the mesh's count: a warning, everywhere it is written


def test_faces_above_the_count_is_a_warning_in_the_record_on_stderr(tmp_path, capsys):
    raw = tmp_path / "sphere.ply"
    shutil.copy(sample_paths()["sphere"], raw)  # 1,280 faces
    out = tmp_path / "out"
    code = main(["prepare", str(raw), "-o", str(out), "--orient", "none", "--faces", "5000"])
    err = capsys.readouterr().err
    assert code == 0, err
    said = "decimate: 1280 faces, no more than the 5000 asked: not decimated"
    assert f"sphere.ply: warning: {said}" in err
    record = read_record(out / "sphere.prepare.json")
    assert record["warnings"] == [said]
    decimate = next(step for step in record["steps"] if step["step"] == "decimate")
    assert decimate["faces"] == [1280, 1280] and decimate["warnings"] == [said.split(": ", 1)[1]]
    code = main(["prepare", str(raw), "-o", str(tmp_path / "o2"), "--orient", "none"])
    assert code == 0 and "warning" not in capsys.readouterr().err  # no target: nothing to say
    code = main(["prepare", str(raw), "-o", str(tmp_path / "o3"), "--faces", "600", "-q"])
    assert code == 0 and "not decimated" not in capsys.readouterr().err  # decimated: no word


def _pixels(path):
    image = pytest.importorskip("PIL.Image", reason="Pillow reads the PNGs")
    with image.open(path) as picture:
        pixels = np.asarray(picture.convert("RGB")).astype(int)
    return pixels[:, : pixels.shape[1] // 2]  # the raw scan's half


def _red(pixels) -> int:
    return int(((pixels[..., 0] > 120) & (pixels[..., 1] < 60) & (pixels[..., 2] < 60)).sum())


def _blue(pixels) -> int:
    return int(((pixels[..., 2] > 150) & (pixels[..., 0] < 90)).sum())


def test_faces_above_the_count_is_written_on_the_preview(tmp_path):
    pytest.importorskip("pyvista", reason="pyvista (the viz extra) draws the previews")
    import dentopo
    from dentopo.figures import render_preparation
    from dentopo.figures._preparation import _warning_lines

    mesh = tooth(rings=12)
    with pytest.warns(dentopo.PrepareWarning, match="not decimated"):
        said = dentopo.prepare(mesh, orient="none", faces=100_000)
    silent = dentopo.prepare(mesh, orient="none")
    assert said.warnings == (
        f"decimate: {len(mesh.faces)} faces, no more than the 100000 asked: not decimated",
    )
    assert _warning_lines(said.warnings) == ["warnings:", said.warnings[0]]  # whole: it fits
    for crown, name in ((said, "said.png"), (silent, "silent.png")):
        render_preparation(mesh.vertices, mesh.faces, crown, tmp_path / name, title="t.ply")
    assert _red(_pixels(tmp_path / "said.png")) > 100  # the warning, in red
    assert _red(_pixels(tmp_path / "silent.png")) == 0


def test_the_preview_writes_each_warning_on_a_line_of_its_own():
    from dentopo.figures._preparation import PREVIEW_WARNINGS, WARNING_CHARACTERS, _warning_lines

    warnings = [f"step {i}: " + "x" * 200 for i in range(PREVIEW_WARNINGS + 2)]
    lines = _warning_lines(warnings)
    assert lines[0] == "warnings:" and len(lines) == PREVIEW_WARNINGS + 2
    assert all(len(line) <= WARNING_CHARACTERS for line in lines[1:])
    assert [line[:7] for line in lines[1:-1]] == ["step 0:", "step 1:", "step 2:"]
    assert lines[-1] == "(and 2 more: see the .prepare.json)"
    assert _warning_lines(()) == []


# --- 4. the preview draws no found axis on a crown left as it lies


def test_the_preview_draws_an_axis_only_where_one_was_found(tmp_path):
    pytest.importorskip("pyvista", reason="pyvista (the viz extra) draws the previews")
    import dentopo
    from dentopo.figures import render_preparation
    from dentopo.figures._preparation import _raw_label

    crown = tooth(rings=12)
    turn = np.radians(40.0)
    tilt = np.array([[1, 0, 0], [0, np.cos(turn), -np.sin(turn)], [0, np.sin(turn), np.cos(turn)]])
    tilted = trimesh.Trimesh(crown.vertices @ tilt.T, crown.faces, process=False)
    sphere = trimesh.load(sample_paths()["sphere"], process=False)
    with pytest.warns(dentopo.PrepareWarning, match="left as it is"):
        left = dentopo.prepare(sphere)  # closed, no axis distinct: left as it is
    cases = {
        "found": (tilted, dentopo.prepare(tilted)),  # orient finds the open base
        "left": (sphere, left),
        "none": (tilted, dentopo.prepare(tilted, orient="none")),  # no orient step
    }
    assert cases["found"][1].step("orient").details["turned"]
    assert not cases["left"][1].step("orient").details["turned"]
    blue = {}
    for name, (mesh, prepared) in cases.items():
        path = tmp_path / f"{name}.png"
        render_preparation(mesh.vertices, mesh.faces, prepared, path)
        blue[name] = _blue(_pixels(path))
    assert blue["found"] > 200  # the arrow and the base plane
    assert blue["left"] == 0 and blue["none"] == 0  # no arrow where nothing was found
    orient = cases["left"][1].step("orient")
    assert _raw_label(orient, None) == "raw scan as it lies, +z up (no axis found), no crop"
    assert _raw_label(None, None) == "raw scan as it lies, +z up (no orient step), no crop"
    found = cases["found"][1].step("orient")
    assert _raw_label(found, None) == "raw scan: found axis (blue), no crop"


# --- 3. one short line per file and warning; the explanation once per run


def test_two_closed_meshes_give_one_short_line_each_and_one_explanation(tmp_path, capsys):
    for name in ("a.ply", "b.ply"):
        shutil.copy(sample_paths()["sphere"], tmp_path / name)
    table = tmp_path / "out.csv"
    code, _, err = run(
        capsys, tmp_path / "a.ply", tmp_path / "b.ply", "--metrics", "slope", "-o", table
    )
    assert code == 0, err
    lines = err.splitlines()
    short = [
        line for line in lines if line.endswith("closed surface, measured as it lies" + SEE_BELOW)
    ]
    assert [line.split(": warning: ")[0] for line in short] == [
        f"dentopo: {tmp_path / 'a.ply'}",
        f"dentopo: {tmp_path / 'b.ply'}",
    ]
    long = "crop it to the crown above the cervix, or turn it by hand"
    [explained] = [line for line in lines if long in line]  # once per run
    assert explained.startswith("dentopo: closed surface, measured as it lies (2 files): ")
    assert "neither side" not in explained  # a file's own detail stays in its row
    assert lines.index(explained) > max(lines.index(line) for line in short)
    assert lines[-1] == f"dentopo: wrote 2 rows to {table} (0 failed)"
    for name in ("a.ply", "b.ply"):  # its warning's line and its counted line, no more
        about = [line for line in lines if line.startswith(f"dentopo: {tmp_path / name}: ")]
        counted = [line for line in lines if f"] {tmp_path / name}: ok (" in line]
        assert len(about) == 1 and len(counted) == 1
    assert all(len(line.replace(str(tmp_path), "")) <= 80 for line in lines if line != explained)
    for row in read_table(table):  # the record keeps every word
        assert long in row["warnings"] and "neither side of it faces up" in row["warnings"]


def test_a_partial_row_says_its_long_reason_short(tmp_path, capsys):
    shutil.copy(sample_paths()["sphere"], tmp_path / "s.ply")
    table = tmp_path / "out.csv"
    code, _, err = run(
        capsys, tmp_path / "s.ply", "--metrics", "ariadne,rfi,angularity", "-o", table
    )
    assert code == 1
    [line] = [line for line in err.splitlines() if ": partial" in line]
    assert re.fullmatch(
        rf"dentopo: \[1/1\] {re.escape(str(tmp_path / 's.ply'))}: partial \(\d+\.\d\d s\): "
        r"rfi: alpha adjustment required at alpha = 0\.075 \(see below\); angularity: "
        r"angularity is undefined: 24 of 1280 faces have no area \(see below\)",
        line,
    ), line
    assert "dentopo: alpha adjustment required at alpha = 0.075 (1 file): the relief" in err
    assert "dentopo: angularity undefined (1 file): faces have no area on doolkit's" in err
    [row] = read_table(table)
    assert "the point at x, y = " in row["error"] and "(a vertical wall)" in row["error"]


def _prepare_messages(monkeypatch) -> list[str]:
    from dentopo.prepare import _orient
    from dentopo.samples import saddle

    def found(mesh):
        out = _orient.run(
            np.asarray(mesh.vertices), np.asarray(mesh.faces), mode="occlusal", up=None, spin="none"
        )
        return list(out.warnings)

    messages = []
    messages += found(trimesh.load(sample_paths()["sphere"], process=False))  # axes alike
    messages += found(trimesh.creation.box(extents=(1.0, 2.0, 4.0)))  # sides alike
    messages += found(closed_crown())  # turned by its shape
    messages += found(saddle())  # flat
    with monkeypatch.context() as patch:
        patch.setattr(_orient, "SIDE_TOLERANCE", 1e9)  # every centroid "on" its base plane
        messages += found(tooth(rings=12))
    return messages


def _library_messages() -> list[str]:
    import dentopo.topography as topography
    from dentopo.batch import _measure

    sphere = trimesh.load(sample_paths()["sphere"], process=False)
    messages = []
    for found in ORIENTATIONS.values():
        messages += found.messages()
    messages += dataclasses.replace(ORIENTATIONS["points -z"], asked="as-is").messages()
    messages += Orientation("+z", "open base", winding="mixed", inward_faces=3, faces=9).messages()
    messages += [_measure._ANGULARITY_UNIT, _measure._MORPHOTESTER_UNIT]
    for find_alpha in (False, True):
        with pytest.raises(ValueError) as failed:
            topography.rfi(sphere, find_alpha=find_alpha)
        messages.append(f"rfi: {failed.value}")
    with pytest.raises(ValueError) as failed:
        topography.angularity(sphere)
    messages.append(f"angularity: {failed.value}")
    return messages


@pytest.mark.filterwarnings("ignore::UserWarning")
def test_every_long_message_of_the_library_is_written_short(monkeypatch):
    prepare = _prepare_messages(monkeypatch)
    assert len(prepare) == 5 and len(set(prepare)) == 5
    library = _library_messages()
    long = [m for m in library if len(m) > 100]
    assert len(long) >= 12
    main_words, prepare_words = (
        CommandLineHints(build_parser()),
        CommandLineHints(build_prepare_parser()),
    )
    for message in long + prepare:
        for words in (message, main_words(message), prepare_words(f"orient: {message}")):
            briefing = Briefing()
            short = briefing("f.ply", words)
            assert short.endswith(SEE_BELOW) or f"{SEE_BELOW}; " in short, words
            assert len(short) <= 100, short
            [explanation] = briefing.explanations()
            said = set(re.findall(r"[\w'.=-]+", explanation.split(" (1 file): ")[1]))
            assert said <= set(re.findall(r"[\w'.=-]+", words))  # in the library's own words
            assert len(said) > 8  # an explanation, not a word or two


def test_the_explanation_of_a_warning_leaves_out_what_differs_between_files():
    briefing = Briefing()
    one = Orientation("undetermined", "area", asked="auto").messages()[0]
    two = Orientation("-z", "area", asked="auto").messages()[0]
    assert one != two
    assert (
        briefing("a.ply", one)
        == briefing("b.ply", two)
        == ("closed surface, measured as it lies" + SEE_BELOW)
    )
    [line] = briefing.explanations()
    assert line.startswith("closed surface, measured as it lies (2 files): the surface is closed")
    assert "-z" not in line and "neither side" not in line
    assert briefing("c.ply", "3 vertices have few neighbours") == "3 vertices have few neighbours"


def test_a_row_measured_by_molar_and_doolkit_says_each_orientation_warning_once(tmp_path, capsys):
    inside_out(trimesh.load(sample_paths()["sphere"], process=False)).export(tmp_path / "in.ply")
    table = tmp_path / "out.csv"
    code, _, err = run(capsys, tmp_path / "in.ply", "--metrics", "slope,relief_index", "-o", table)
    assert code == 0, err
    [row] = read_table(table)
    assert row["warnings"].count("the surface is closed") == 1
    assert row["warnings"].count("every face is wound inward") == 1
    assert err.count("closed surface, measured as it lies") == 2  # the file's line, the end's
    assert err.count("every face wound inward, rewound") == 1


# --- 4. every row counted; one row, one "row"; info says what it takes


def test_progress_counts_partial_rows_and_one_row_is_a_row(tmp_path, capsys):
    shutil.copy(sample_paths()["tooth"], tmp_path / "a.ply")
    shutil.copy(sample_paths()["sphere"], tmp_path / "b.ply")  # angularity fails: partial
    table = tmp_path / "out.csv"
    code, _, err = run(capsys, tmp_path, "--metrics", "ariadne,angularity", "-o", table)
    assert code == 1
    counted = re.findall(r"^dentopo: \[(\d)/2\] (\S+): (ok|partial) \(", err, re.M)
    assert [(n, os.path.basename(f), s) for n, f, s in counted] == [
        ("1", "a.ply", "ok"),
        ("2", "b.ply", "partial"),  # counted, not left out of the count
    ]
    assert "wrote 2 rows to" in err and "(0 failed, 1 partial)" in err
    code, _, err = run(capsys, tmp_path / "a.ply", "-o", tmp_path / "one.csv")
    assert code == 0 and f"dentopo: wrote 1 row to {tmp_path / 'one.csv'} (0 failed)" in err


def test_the_counter_counts_a_partial_and_an_error_row(capsys):
    from dentopo.cli._progress import Progress, counted

    progress = Progress(3, quiet=False)
    base = {"seconds": 0.5, "error": None}
    progress.update({**base, "file": "a.ply", "status": "ok"})
    progress.update({**base, "file": "b.ply", "status": "partial", "error": "rfi: no"})
    progress.update({**base, "file": "c.ply", "status": "error", "error": "not a mesh"})
    progress.close()
    assert capsys.readouterr().err.splitlines() == [
        "dentopo: [1/3] a.ply: ok (0.50 s)",
        "dentopo: [2/3] b.ply: partial (0.50 s): rfi: no",
        "dentopo: [3/3] c.ply: error (0.50 s): not a mesh",
    ]
    assert (counted(1, "row"), counted(0, "row"), counted(2, "row")) == (
        "1 row",
        "0 rows",
        "2 rows",
    )


def test_info_on_a_mesh_says_what_it_takes_and_how_to_measure_it(tmp_path, capsys):
    scan = tmp_path / "my scan.ply"
    shutil.copy(sample_paths()["tooth"], scan)
    code, out, err = run(capsys, "info", scan)
    assert code == 1 and out == ""
    [line] = err.splitlines()
    assert line == (
        f"dentopo: {str(scan)!r} is a mesh, not a picture: dentopo info reads the record dentopo "
        f"keeps in the PNG pictures and HTML pages it writes; to measure the mesh, run dentopo "
        f"'{scan}' (see dentopo --help)"
    )
    notes = tmp_path / "notes.csv"
    notes.write_text("file,dne\n")
    code, _, err = run(capsys, "info", notes)
    assert code == 1 and "PNG pictures and HTML pages" in err and "measure" not in err
    code, out, _ = run(capsys, "info", "--help")
    assert code == 0 and "not meshes" in out


def test_info_reads_only_the_start_of_a_file_that_is_not_a_page(tmp_path, monkeypatch):
    import builtins

    from dentopo.figures import read_provenance

    scan = tmp_path / "big.stl"
    scan.write_bytes(b"solid x\n" + b"facet normal 0 0 1\n" * 100_000)
    read = []
    original = builtins.open

    def counting(*args, **kwargs):
        handle = original(*args, **kwargs)
        if "b" not in (args[1] if len(args) > 1 else kwargs.get("mode", "r")):
            real = handle.read

            def spy(size=-1):
                text = real(size)
                read.append(len(text))
                return text

            handle.read = spy
        return handle

    monkeypatch.setattr(builtins, "open", counting)
    with pytest.raises(ValueError, match="neither a PNG nor an HTML"):
        read_provenance(scan)
    assert read and sum(read) <= 4096


def test_the_briefs_keep_the_json_record_whole(tmp_path, capsys):
    """--output JSON: the warnings column is the record, whole, whatever stderr says."""
    shutil.copy(sample_paths()["sphere"], tmp_path / "s.ply")
    table = tmp_path / "out.json"
    code, _, err = run(capsys, tmp_path / "s.ply", "--metrics", "slope", "-o", table)
    assert code == 0 and SEE_BELOW in err
    [row] = json.loads(table.read_text())
    assert SEE_BELOW not in row["warnings"] and "turn it by hand" in row["warnings"]
