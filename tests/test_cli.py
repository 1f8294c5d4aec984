"""The dentopo command, called as ``main([...])`` on small generated meshes in tmp_path."""

from __future__ import annotations

import csv
import json
import os
import sys
import types

import numpy as np
import pytest
import trimesh

from dentopo import COLUMNS, __version__, ariaDNE
from dentopo.cli import SUBCOMMANDS, _progress, main
from dentopo.cli import _compute as _cli
from dentopo.formats import Journal, read_journal, read_table
from dentopo.samples import tooth


def small_tooth(path, *, rings=10):
    tooth(rings=rings).export(path)
    return path


def small_sphere(path):
    trimesh.creation.icosphere(subdivisions=2).export(path)
    return path


def read_csv(path):
    with open(path, newline="", encoding="utf-8") as stream:
        reader = csv.DictReader(stream)
        return reader.fieldnames, list(reader)


def test_version(capsys):
    assert main(["--version"]) == 0
    fast = capsys.readouterr().out
    assert __version__ in fast
    # the same line as the main command's own parser prints for it
    assert _cli.compute_main(["--version"], tuple(SUBCOMMANDS)) == 0
    assert capsys.readouterr().out == fast


def test_version_and_import_load_no_numerics():
    import subprocess

    code = (
        "import sys; from dentopo.cli import main; main(['--version']); import dentopo; "
        "print(sorted(m for m in ('numba', 'scipy', 'trimesh', 'numpy') if m in sys.modules)); "
        "print(callable(dentopo.ariaDNE), set(dentopo.__all__) <= set(dir(dentopo)))"
    )
    ran = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    lines = ran.stdout.splitlines()
    assert lines[0] == f"dentopo {__version__}"
    assert lines[1] == "[]"
    assert lines[2] == "True True"


def test_help_shows_the_papers_examples(capsys):
    assert main(["--help"]) == 0
    out = capsys.readouterr().out
    assert "dentopo path/to/mesh1.obj path/to/mesh2.ply -o DNEs.csv" in out
    assert "dentopo path/to/mesh/directory -b 0.1" in out
    assert "dentopo path/to/mesh.ply -v" in out


def test_help_names_every_format_searched_in_folders(capsys):
    from dentopo.batch import FORMAT_PACKAGES, MESH_EXTENSIONS

    assert main(["--help"]) == 0
    paragraph = capsys.readouterr().out.split("inputs are files")[1].split("\n\n")[0]
    words = " ".join(paragraph.split())  # wrapped: join the lines
    assert "3mf" in MESH_EXTENSIONS and "dae" in MESH_EXTENSIONS
    assert ", ".join(MESH_EXTENSIONS) in words
    for ext, package in FORMAT_PACKAGES.items():
        assert f"{ext} needs {package}" in words


def test_samples_print_a_table_on_stdout_and_progress_on_stderr(capsys):
    assert main(["--samples"]) == 0
    out, err = capsys.readouterr()
    lines = out.strip().splitlines()
    assert lines[0].split()[:4] == ["file", "dne", "positive_dne", "negative_dne"]
    assert len(lines) == 4 and all(line.split()[-1] == "ok" for line in lines[1:])
    assert "[3/3]" in err  # not a terminal: plain lines
    assert "[" not in out


def test_two_files_to_csv_as_in_the_paper(tmp_path, capsys):
    obj = small_tooth(tmp_path / "mesh1.obj")
    ply = small_sphere(tmp_path / "mesh2.ply")
    out = tmp_path / "DNEs.csv"
    assert main([str(obj), str(ply), "-o", str(out)]) == 0
    assert capsys.readouterr().out == ""  # machine output went to the file only
    header, rows = read_csv(out)
    assert tuple(header) == COLUMNS
    assert [row["file"] for row in rows] == [str(obj), str(ply)]
    for row, path in zip(rows, (obj, ply), strict=True):
        expected = ariaDNE(str(path)).to_dict()
        for name, value in expected.items():
            cell = row[name]
            assert (float(cell) if isinstance(value, (int, float)) else cell) == value
        assert row["status"] == "ok" and row["error"] == ""
        assert float(row["seconds"]) >= 0


def test_directory_with_bandwidth_recursive_skipping_hidden_and_own_outputs(tmp_path, capsys):
    scans = tmp_path / "scans"
    (scans / "upper").mkdir(parents=True)
    (scans / ".cache").mkdir()
    small_tooth(scans / "a.ply")
    small_sphere(scans / "upper" / "b.stl")
    small_sphere(scans / ".hidden.ply")
    small_sphere(scans / ".cache" / "c.ply")
    small_sphere(scans / "a.dentopo.ply")  # looks like our own per-vertex output
    (scans / "notes.txt").write_text("not a mesh")
    out = tmp_path / "out.json"
    assert main([str(scans), "-b", "0.1", "-o", str(out), "-q"]) == 0
    rows = json.loads(out.read_text())
    assert [row["file"] for row in rows] == [str(scans / "a.ply"), str(scans / "upper" / "b.stl")]
    assert all(row["bandwidth"] == 0.1 and row["status"] == "ok" for row in rows)
    assert list(rows[0]) == list(COLUMNS)
    assert rows[0]["dne"] == ariaDNE(str(scans / "a.ply"), bandwidth=0.1).dne
    assert capsys.readouterr().err == ""  # --quiet, nothing went wrong


def test_glob_and_a_path_given_twice(tmp_path, capsys):
    small_tooth(tmp_path / "a.ply")
    small_sphere(tmp_path / "b.ply")
    pattern = str(tmp_path / "*.ply")
    assert main([pattern, str(tmp_path / "a.ply"), os.path.join(str(tmp_path), ".", "a.ply")]) == 0
    rows = capsys.readouterr().out.strip().splitlines()[1:]
    assert [row.split()[0] for row in rows] == [str(tmp_path / "a.ply"), str(tmp_path / "b.ply")]


def write_bad_file(kind, directory):
    """A bad mesh file of the given kind; returns its path (as str)."""
    good = tooth(rings=10).export(file_type="ply")
    path = directory / {"text": "notes.obj"}.get(kind, f"{kind}.ply")
    if kind == "corrupt":
        path.write_bytes(np.random.default_rng(0).bytes(4000))
    elif kind == "truncated":
        path.write_bytes(good[: len(good) // 2])
    elif kind == "empty":
        path.write_bytes(b"")
    elif kind == "text":
        path.write_text("Specimen notes: lower left molar, worn.\nNo mesh here.\n")
    elif kind == "broken-link":  # unreadable: its target is gone
        os.symlink(directory / "gone.ply", path)
    elif kind == "no-permission":
        path.write_bytes(good)
        path.chmod(0)
        if os.access(path, os.R_OK):  # root reads anything
            pytest.skip("running as root: chmod 000 does not make a file unreadable")
    return str(path)


@pytest.mark.parametrize(
    ("kind", "reason"),
    [
        ("corrupt", "could not read"),
        ("truncated", "could not read"),
        ("empty", "empty"),
        ("text", "no triangle mesh"),
        ("broken-link", "unreadable"),
        ("no-permission", "unreadable"),
    ],
)
def test_a_bad_file_gives_an_error_row_and_the_batch_goes_on(tmp_path, capsys, kind, reason):
    bad = write_bad_file(kind, tmp_path)
    good = str(small_sphere(tmp_path / "z_good.ply"))
    out = tmp_path / "out.csv"
    assert main([bad, good, "-o", str(out)]) == 1
    _, rows = read_csv(out)
    by_file = {row["file"]: row for row in rows}
    assert by_file[good]["status"] == "ok"
    row = by_file[bad]
    assert row["status"] == "error"
    assert reason in row["error"]
    assert all(row[name] == "" for name in COLUMNS[1:13])  # numbers empty
    assert reason in capsys.readouterr().err


def test_a_missing_file_is_an_error_row(tmp_path):
    out = tmp_path / "out.json"
    assert main([str(tmp_path / "nope.ply"), "-o", str(out)]) == 1
    [row] = json.loads(out.read_text())
    assert row["status"] == "error" and row["error"] == "file not found" and row["dne"] is None


def test_spaces_and_non_ascii_names(tmp_path):
    folder = tmp_path / "my scans" / "Zähne 歯"
    folder.mkdir(parents=True)
    mesh = small_tooth(folder / "molar ø 1.ply")
    for ext in ("csv", "json"):
        out = tmp_path / "my scans" / f"résultats.{ext}"
        assert main([str(tmp_path / "my scans"), "-o", str(out), "-q"]) == 0
        rows = json.loads(out.read_text("utf-8")) if ext == "json" else read_csv(out)[1]
        assert [row["file"] for row in rows] == [str(mesh)]
        assert float(rows[0]["dne"]) == ariaDNE(str(mesh)).dne


def test_empty_directory_is_a_usage_error(tmp_path, capsys):
    (tmp_path / "empty").mkdir()
    assert main([str(tmp_path / "empty")]) == 2
    assert "no mesh files found" in capsys.readouterr().err


def test_no_inputs_is_a_usage_error(capsys):
    assert main([]) == 2
    assert "no mesh files given" in capsys.readouterr().err


def test_output_in_a_missing_directory_fails_before_computing(tmp_path, capsys, monkeypatch):
    mesh = small_sphere(tmp_path / "a.ply")
    monkeypatch.setattr(_cli, "run_tasks", None)  # would fail if anything were computed
    assert main([str(mesh), "-o", str(tmp_path / "missing" / "out.csv")]) == 2
    assert "does not exist" in capsys.readouterr().err
    assert not (tmp_path / "missing").exists()


@pytest.mark.parametrize(
    "options",
    [
        ["-o", "out.parquet"],
        ["--resume"],
        ["-b", "0"],
        ["-c", "1.5"],
        ["-d", "manhattan"],
        ["-j", "-1"],
        ["--bandwidth", "wide"],
    ],
)
def test_usage_errors_exit_2(tmp_path, capsys, options, monkeypatch):
    monkeypatch.chdir(tmp_path)
    small_sphere(tmp_path / "a.ply")
    assert main(["a.ply", *options]) == 2
    assert capsys.readouterr().err.strip()
    assert not (tmp_path / "out.parquet").exists()


def test_papers_capitalised_distance_type(tmp_path, capsys):
    mesh = small_sphere(tmp_path / "a.ply")
    out = tmp_path / "out.json"
    assert main([str(mesh), "-d", "Geodesic", "-o", str(out)]) == 0
    [row] = json.loads(out.read_text())
    assert row["distance_type"] == "geodesic"
    assert row["dne"] == ariaDNE(str(mesh), distance_type="geodesic").dne


def test_resume_skips_ok_rows_and_recomputes_failed_ones(tmp_path, capsys):
    done = small_sphere(tmp_path / "a.ply")
    broken = tmp_path / "b.ply"
    broken.write_bytes(b"")
    out = tmp_path / "out.csv"
    assert main([str(tmp_path), "-o", str(out), "-q"]) == 1
    first = read_csv(out)[1]
    assert [row["status"] for row in first] == ["ok", "error"]

    # a.ply changes (had it been recomputed its row would change), b.ply is repaired, c is new
    small_tooth(done)
    small_tooth(broken)
    small_tooth(tmp_path / "c.ply", rings=12)
    assert main([str(tmp_path), "-o", str(out), "--resume"]) == 0
    assert "1 of 3 files already done" in capsys.readouterr().err
    rows = read_csv(out)[1]
    assert [row["file"] for row in rows] == [str(tmp_path / n) for n in ("a.ply", "b.ply", "c.ply")]
    assert rows[0] == first[0]  # kept as it was
    assert [row["status"] for row in rows] == ["ok", "ok", "ok"]
    assert float(rows[1]["dne"]) == ariaDNE(str(broken)).dne

    # other settings: nothing is reused
    assert main([str(tmp_path), "-o", str(out), "--resume", "-b", "0.1", "-q"]) == 0
    rows = read_csv(out)[1]
    assert float(rows[0]["dne"]) == ariaDNE(str(done), bandwidth=0.1).dne


def test_resume_without_an_existing_output_computes_everything(tmp_path):
    small_sphere(tmp_path / "a.ply")
    out = tmp_path / "out.json"
    assert main([str(tmp_path / "a.ply"), "-o", str(out), "--resume", "-q"]) == 0
    assert [row["status"] for row in json.loads(out.read_text())] == ["ok"]


def test_a_failed_write_keeps_the_old_output(tmp_path, capsys, monkeypatch):
    mesh = small_sphere(tmp_path / "a.ply")
    out = tmp_path / "out.csv"
    out.write_text("precious results\n")

    def disk_full(layout, value):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr("dentopo.formats._layouts.Layout.text", disk_full)
    assert main([str(mesh), "-o", str(out)]) == 1
    assert "No space left" in capsys.readouterr().err
    assert out.read_text() == "precious results\n"
    # no temporary file; the row computed is kept in the journal for --resume
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "a.ply",
        "out.csv",
        "out.csv.partial.jsonl",
    ]
    [row] = read_journal(tmp_path / "out.csv.partial.jsonl")[0]
    assert row["status"] == "ok" and row["dne"] == ariaDNE(str(mesh)).dne


def test_ctrl_c_keeps_the_rows_already_done(tmp_path, capsys, monkeypatch):
    for name in ("a", "b", "c"):
        small_sphere(tmp_path / f"{name}.ply")
    out = tmp_path / "out.json"
    assert main([str(tmp_path), "-o", str(out), "-q"]) == 0
    before = json.loads(out.read_text())
    small_tooth(tmp_path / "a.ply")
    small_tooth(tmp_path / "b.ply")
    real = _cli.run_tasks

    def interrupted(tasks, settings, **kwargs):
        for i, outcome in enumerate(real(tasks, settings, **kwargs)):
            if i == 1:
                raise KeyboardInterrupt
            yield outcome

    monkeypatch.setattr(_cli, "run_tasks", interrupted)
    assert main([str(tmp_path), "-o", str(out)]) == 130
    assert "interrupted: 1 of 3" in capsys.readouterr().err
    after = json.loads(out.read_text())
    assert after[0]["dne"] == ariaDNE(str(tmp_path / "a.ply")).dne  # done before Ctrl-C
    assert after[1:] == before[1:]  # not reached: the old rows are kept


def test_the_rows_of_a_killed_run_are_added_back_by_the_next_run(tmp_path, capsys):
    a, b = small_sphere(tmp_path / "a.ply"), small_tooth(tmp_path / "b.ply")
    out = tmp_path / "out.csv"
    assert main([str(a), "-o", str(out), "-q"]) == 0
    assert main([str(b), "-o", str(tmp_path / "b.json"), "-q"]) == 0
    [row_b] = read_table(tmp_path / "b.json")
    with Journal(tmp_path / "out.csv.partial.jsonl") as journal:  # as a killed run leaves it
        journal.append(row_b)
    capsys.readouterr()
    assert main([str(a), str(b), "-o", str(out), "--resume"]) == 0
    err = capsys.readouterr().err
    assert "added 1 row of an earlier run" in err
    assert "resuming: 2 of 2 files already done" in err
    assert [r["file"] for r in read_table(out)] == [str(a), str(b)]
    assert read_table(out)[1] == row_b
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.ply", "b.json", "b.ply", "out.csv"]


def test_per_vertex_files(tmp_path):
    (tmp_path / "scans").mkdir()
    mesh = small_tooth(tmp_path / "scans" / "molar.ply")
    out_dir = tmp_path / "per vertex"  # created on demand
    assert main([str(mesh), "--per-vertex", str(out_dir), "-q"]) == 0
    result = ariaDNE(str(mesh))
    ply = trimesh.load(out_dir / "molar.dentopo.ply", process=False)
    assert np.array_equal(ply.vertices, result.mesh.vertices)
    assert np.array_equal(ply.faces, result.mesh.faces)
    data = ply.metadata["_ply_raw"]["vertex"]["data"]
    assert np.array_equal(data["local_curvature"], result.local_curvature)
    assert np.array_equal(data["local_dne"], result.local_dne)
    colors = ply.visual.vertex_colors[:, :3].astype(int)
    convex = result.local_curvature > 0.5 * result.local_curvature.max()
    concave = result.local_curvature < 0.5 * result.local_curvature.min()
    assert (colors[convex, 0] > colors[convex, 2]).all()  # red where convex
    assert (colors[concave, 2] > colors[concave, 0]).all()  # blue where concave
    table = np.genfromtxt(out_dir / "molar.dentopo.csv", delimiter=",", names=True)
    assert table.dtype.names == ("vertex", "x", "y", "z", "local_curvature", "local_dne", "sign")
    assert np.array_equal(table["local_curvature"], result.local_curvature)
    # our own outputs are not taken for inputs the next time round
    assert main([str(tmp_path), "--per-vertex", str(out_dir), "-q"]) == 0


def test_per_vertex_names_stay_unique(tmp_path):
    for folder in ("left", "right"):
        (tmp_path / folder).mkdir()
        small_sphere(tmp_path / folder / "molar.ply")
    out_dir = tmp_path / "pv"
    assert (
        main([str(tmp_path / "left"), str(tmp_path / "right"), "--per-vertex", str(out_dir)]) == 0
    )
    assert len(list(out_dir.glob("molar-*.dentopo.ply"))) == 2


def test_jobs_2_gives_the_same_rows_as_jobs_1(tmp_path):
    for i in range(4):
        small_tooth(tmp_path / f"m{i}.ply", rings=8 + i)
    (tmp_path / "bad.ply").write_text("nonsense")
    tables = []
    for jobs in ("1", "2"):
        out = tmp_path / f"out{jobs}.json"
        assert main([str(tmp_path), "-j", jobs, "-o", str(out), "-q"]) == 1
        tables.append(
            [{k: v for k, v in r.items() if k != "seconds"} for r in json.loads(out.read_text())]
        )
    assert tables[0] == tables[1]
    assert len(tables[0]) == 5


def test_subcommands_are_dispatched_on_the_first_argument(tmp_path, monkeypatch, capsys):
    calls = []
    monkeypatch.setitem(SUBCOMMANDS, "robustness", lambda argv: calls.append(argv) or 7)
    assert main(["robustness", "--flag", "x"]) == 7
    assert calls == [["--flag", "x"]]
    # a lazy "module:function" entry
    module = types.ModuleType("fake_subcommand")
    module.run = lambda argv: len(argv)
    monkeypatch.setitem(sys.modules, "fake_subcommand", module)
    monkeypatch.setitem(SUBCOMMANDS, "sweep", "fake_subcommand:run")
    assert main(["sweep", "a", "b"]) == 2
    # a mesh file called like a subcommand
    monkeypatch.chdir(tmp_path)
    (tmp_path / "robustness").write_bytes(trimesh.creation.icosphere(2).export(file_type="ply"))
    capsys.readouterr()
    assert main(["./robustness"]) == 1  # computed as a file: no extension, so not readable
    assert "./robustness" in capsys.readouterr().out


def test_a_renderer_that_cannot_be_loaded_is_a_usage_error(tmp_path, monkeypatch, capsys):
    mesh = small_sphere(tmp_path / "a.ply")
    monkeypatch.setitem(sys.modules, "dentopo.figures", None)  # import fails
    assert main([str(mesh), "-v"]) == 2
    assert "cannot load the renderer" in capsys.readouterr().err


class _DisplayUnavailableError(RuntimeError):
    pass


def fake_renderer(monkeypatch, *, display=True, window=True):
    """A stand-in for dentopo.figures; `display` is what has_display says, `window` whether
    drawing works (False: it raises DisplayUnavailableError, as a window that fails late)."""
    calls = []
    module = types.ModuleType("dentopo.figures")
    module.DisplayUnavailableError = _DisplayUnavailableError
    module.has_display = lambda: display

    def render_curvature(mesh, result=None, **options):
        if not window:
            raise _DisplayUnavailableError("no display (DISPLAY is not set)")
        calls.append(("curvature", mesh, result, options))

    def render_panel(items, **options):
        calls.append(("panel", items, options))

    module.render_curvature = render_curvature
    module.render_panel = render_panel
    monkeypatch.setitem(sys.modules, "dentopo.figures", module)
    return calls


def test_visualise_one_mesh(tmp_path, monkeypatch):
    calls = fake_renderer(monkeypatch)
    mesh = small_sphere(tmp_path / "a.ply")
    png = tmp_path / "a.png"
    args = [str(mesh), "--screenshot", str(png), "--color-by", "local_dne", "--limits", "-1", "1"]
    assert main([*args, "--window-size", "640", "480", "-q"]) == 0
    [(kind, drawn, result, options)] = calls
    assert kind == "curvature" and result.dne == ariaDNE(str(mesh)).dne
    assert drawn is result.mesh
    assert options["screenshot"] == str(png) and options["interactive"] is False
    assert options["field"] == "local_dne" and options["limits"] == (-1.0, 1.0)
    assert options["window_size"] == (640, 480)


def test_visualise_needs_one_input_and_panel_takes_all(tmp_path, monkeypatch, capsys):
    calls = fake_renderer(monkeypatch)
    a, b = small_sphere(tmp_path / "a.ply"), small_tooth(tmp_path / "b.ply")
    assert main([str(a), str(b), "-v"]) == 2
    assert "--panel" in capsys.readouterr().err
    assert main([str(a), str(b), "--panel", str(tmp_path / "p.html"), "-q"]) == 0
    [(kind, items, options)] = calls
    assert kind == "panel" and len(items) == 2
    assert options["labels"] == ["a.ply", "b.ply"] and options["html"] == str(tmp_path / "p.html")


def test_a_window_that_fails_late_exits_1_and_keeps_the_rows(tmp_path, monkeypatch, capsys):
    fake_renderer(monkeypatch, window=False)
    mesh = small_sphere(tmp_path / "a.ply")
    out = tmp_path / "out.csv"
    assert main([str(mesh), "-v", "-o", str(out), "-q"]) == 1
    assert "no display" in capsys.readouterr().err
    assert read_csv(out)[1][0]["status"] == "ok"


@pytest.mark.parametrize("spelling", ["-v", "--show", "--visualize"])
def test_show_without_a_display_says_so_before_computing(tmp_path, monkeypatch, capsys, spelling):
    calls = fake_renderer(monkeypatch, display=False)
    measured = []
    monkeypatch.setattr("dentopo.cli._compute.run_tasks", lambda *a, **k: measured.append(a))
    mesh = small_sphere(tmp_path / "a.ply")
    out = tmp_path / "out.csv"
    assert main([str(mesh), spelling, "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert "needs a display" in err and "--screenshot" in err and "--html" in err
    assert err.count("\n") == 1  # one line, and no progress: nothing was computed
    assert not out.exists() and calls == [] and measured == []


def test_method_option_is_recorded_and_fast_agrees_with_exact(tmp_path):
    pytest.importorskip("finufft", reason="the fast method needs the optional finufft")
    mesh = small_tooth(tmp_path / "crown.ply", rings=20)
    rows = {}
    for method in ("exact", "fast", "auto"):
        out = tmp_path / f"{method}.csv"
        assert main([str(mesh), "--method", method, "-o", str(out), "-q"]) == 0
        fieldnames, (row,) = read_csv(out)
        assert fieldnames == list(COLUMNS)
        rows[method] = row
    assert rows["exact"]["method"] == "exact" and rows["fast"]["method"] == "fast"
    assert rows["auto"]["method"] == "exact"  # a small mesh: auto keeps the exact sums
    assert float(rows["fast"]["dne"]) == pytest.approx(float(rows["exact"]["dne"]), rel=1e-7)


def test_bad_method_is_a_usage_error(tmp_path, capsys):
    mesh = small_tooth(tmp_path / "crown.ply")
    assert main([str(mesh), "--method", "quick"]) == 2
    assert "--method" in capsys.readouterr().err


def test_resume_with_auto_reuses_rows_of_either_method(tmp_path, capsys):
    mesh = small_tooth(tmp_path / "crown.ply")
    out = tmp_path / "dne.csv"
    assert main([str(mesh), "--method", "exact", "-o", str(out), "-q"]) == 0
    capsys.readouterr()
    assert main([str(mesh), "--resume", "-o", str(out)]) == 0
    assert "1 of 1 files already done" in capsys.readouterr().err
    assert main([str(mesh), "--resume", "--method", "fast", "-o", str(out), "-q"]) == 0
    assert read_csv(out)[1][0]["method"] == "fast"  # an explicit method must match


def test_phases_of_a_slow_mesh_are_reported(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(_progress, "SLOW_MESH_SECONDS", 0.0)
    mesh = small_tooth(tmp_path / "crown.ply")
    assert main([str(mesh)]) == 0
    err = capsys.readouterr().err
    for phase in ("prepare", "kernel", "bending", "sign", "totals"):
        assert f"crown.ply: {phase} (" in err


def test_two_value_options_take_one_comma_separated_word_too(tmp_path):
    """``--arc-range 0.05,0.95`` (as the R and MATLAB bridges pass a vector) is the pair."""
    from dentopo.cli._arguments import split_pairs
    from dentopo.samples import write_samples

    assert split_pairs(["--arc-range", "0.05,0.95", "x.ply"]) == [
        "--arc-range",
        "0.05",
        "0.95",
        "x.ply",
    ]
    assert split_pairs(["--limits=-1,1", "--size", "640", "480"]) == [
        "--limits",
        "-1",
        "1",
        "--size",
        "640",
        "480",
    ]
    assert split_pairs(["--", "--arc-range", "a,b"]) == ["--", "--arc-range", "a,b"]
    tooth = str(write_samples(tmp_path)[0])
    values = {}
    for name, words in {
        "comma": ["--arc-range", "0.2,0.8"],
        "two": ["--arc-range", "0.2", "0.8"],
        "default": [],
    }.items():
        out = tmp_path / f"{name}.csv"
        assert main([tooth, "--metrics", "arc", "-o", str(out), "-q", *words]) == 0
        values[name] = read_table(out)[0]["arc"]
    assert values["comma"] == values["two"] != values["default"]
    assert main([tooth, "--metrics", "arc", "--arc-range", "0.2,0.8,0.9", "-q"]) == 2
