"""A plain ``pip install dentopo``: each optional feature fails with one line naming its extra.

The tests run in a real virtual environment that holds only dentopo's core
dependencies, as ``pip install dentopo`` would give (built cheaply: a venv
without pip whose ``.pth`` file points at symbolic links to the core
distributions of the interpreter running the tests, and at the dentopo source
the tests run from).  Which distributions are core is read from
``pyproject.toml`` and their own requirements, never listed by hand.  In it the
command must print exactly one line naming the extra and exit with 2, without a
traceback, and the library must raise ``MissingExtraError`` (an
``ImportError``) with the same words.
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import textwrap
from importlib import metadata
from pathlib import Path

import pytest

import dentopo
from dentopo._optional import FEATURES, MissingExtraError, check, missing_extra_message

SOURCE = Path(dentopo.__file__).resolve().parent.parent  # the src directory the tests run from
PYPROJECT = SOURCE.parent / "pyproject.toml"

#: The modules of every extra: none of them may be importable in the bare environment.
OPTIONAL_MODULES = sorted({feature.module for feature in FEATURES} | {"vtk"})


def _normal(name: str) -> str:
    """A distribution name in its normal form (PEP 503)."""
    return re.sub(r"[-_.]+", "-", name).lower()


def _load_toml(path: Path) -> dict:
    try:
        import tomllib
    except ImportError:  # Python 3.10
        tomllib = pytest.importorskip("tomli", reason="reading pyproject.toml needs tomllib")
    return tomllib.loads(path.read_text(encoding="utf-8"))


def _core_distributions() -> list[metadata.Distribution]:
    """dentopo's core dependencies and everything they need, as installed here."""
    requirements = pytest.importorskip(
        "packaging.requirements", reason="evaluating requirement markers needs packaging"
    )
    if not PYPROJECT.is_file():
        pytest.skip(f"no pyproject.toml next to the source {SOURCE}")
    pending = list(_load_toml(PYPROJECT)["project"]["dependencies"])
    found: dict[str, metadata.Distribution] = {}
    while pending:
        requirement = requirements.Requirement(pending.pop())
        if requirement.marker is not None and not requirement.marker.evaluate({"extra": ""}):
            continue  # an extra's requirement, or not for this platform
        key = _normal(requirement.name)
        if key in found:
            continue
        try:
            distribution = metadata.distribution(requirement.name)
        except metadata.PackageNotFoundError:
            pytest.skip(f"core dependency {requirement.name} is not installed here")
        found[key] = distribution
        pending.extend(distribution.requires or [])
    return list(found.values())


def _link_distributions(distributions, directory: Path) -> None:
    """Symbolic links in `directory` to each distribution's top-level files and folders."""
    for distribution in distributions:
        tops = {Path(str(file)).parts[0] for file in distribution.files or ()}
        for top in sorted(tops):
            if top in ("..", "__pycache__") or top.endswith(".pth"):
                continue
            target = Path(distribution.locate_file(top))
            link = directory / top
            if target.exists() and not link.exists():
                link.symlink_to(target, target_is_directory=target.is_dir())


def _base_python() -> str:
    base = getattr(sys, "_base_executable", None)
    if base and os.path.realpath(base) != os.path.realpath(sys.executable):
        return base
    config = Path(sys.prefix) / "pyvenv.cfg"
    if sys.prefix != sys.base_prefix and config.is_file():
        for line in config.read_text().splitlines():
            key, _, value = line.partition("=")
            if key.strip() == "home":
                name = f"python{sys.version_info.major}.{sys.version_info.minor}"
                candidate = Path(value.strip()) / name
                if candidate.exists():
                    return str(candidate)
    return base or sys.executable


def _environment() -> dict:
    env = {k: v for k, v in os.environ.items() if not k.startswith("PYTHON")}
    env.pop("DENTOPO_SCHEDULER", None)
    env["PYTHONNOUSERSITE"] = "1"  # nothing from ~/.local either
    env["NO_COLOR"] = "1"
    return env


@pytest.fixture(scope="module")
def bare(tmp_path_factory):
    """A Python with dentopo and its core dependencies only (no extra)."""
    if sys.platform.startswith("win"):
        pytest.skip("the bare environment is built with symbolic links (POSIX)")
    distributions = _core_distributions()
    root = tmp_path_factory.mktemp("bare")
    venv = root / "venv"
    made = subprocess.run(
        [_base_python(), "-m", "venv", "--without-pip", str(venv)],
        capture_output=True,
        text=True,
    )
    python = venv / "bin" / "python"
    if made.returncode or not python.exists():
        pytest.skip(f"cannot build a virtual environment: {made.stderr.strip()[-300:]}")
    site = subprocess.run(
        [str(python), "-c", "import sysconfig; print(sysconfig.get_path('purelib'))"],
        capture_output=True,
        text=True,
        env=_environment(),
    ).stdout.strip()
    links = root / "core"
    links.mkdir()
    _link_distributions(distributions, links)
    Path(site, "dentopo_core.pth").write_text(f"{links}\n{SOURCE}\n", encoding="utf-8")
    names = [d.metadata["Name"] for d in distributions]
    probe = subprocess.run(
        [str(python), "-c", "import dentopo, numpy, scipy, trimesh, numba, networkx"],
        capture_output=True,
        text=True,
        env=_environment(),
    )
    if probe.returncode:
        pytest.skip(f"the core-only environment ({names}) cannot import dentopo: {probe.stderr}")
    return python


def run_bare(python, *args, cwd, env=None):
    return subprocess.run(
        [str(python), *args],
        capture_output=True,
        text=True,
        cwd=cwd,
        env={**_environment(), **(env or {})},
        timeout=300,
    )


def assert_one_line_naming(result, extra: str) -> None:
    """Exit 2; stderr exactly one line naming `extra` and its pip command; no traceback."""
    assert "Traceback" not in result.stderr, result.stderr
    assert result.returncode == 2, result.stderr
    lines = result.stderr.splitlines()
    assert len(lines) == 1, result.stderr
    assert f"the {extra} extra" in lines[0]
    assert f"pip install 'dentopo[{extra}]' from PyPI" in lines[0]
    assert f"pip install '.[{extra}]' in a clone" in lines[0]
    assert lines[0].startswith("dentopo")


def test_the_environment_is_bare_and_dentopo_works_in_it(bare, tmp_path):
    code = textwrap.dedent(
        f"""
        import importlib.util, json, dentopo
        print(json.dumps({{
            "file": dentopo.__file__,
            "found": [m for m in {OPTIONAL_MODULES!r} if importlib.util.find_spec(m)],
        }}))
        """
    )
    result = run_bare(bare, "-c", code, cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    report = json.loads(result.stdout)
    assert Path(report["file"]).resolve() == Path(dentopo.__file__).resolve()
    assert report["found"] == []  # no extra can be imported: the tests below are not vacuous
    result = run_bare(bare, "-c", "import pyvista", cwd=tmp_path)
    assert result.returncode == 1 and "ModuleNotFoundError" in result.stderr


def test_core_commands_work_without_extras(bare, tmp_path):
    from dentopo.samples import sample_paths

    tooth = str(sample_paths()["tooth"])
    # an HTML page needs no extra; --method auto stays exact silently without finufft
    result = run_bare(
        bare, "-m", "dentopo", tooth, "--method", "auto", "--html", "t.html", "-o", "t.csv",
        cwd=tmp_path,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    assert (tmp_path / "t.html").stat().st_size > 0
    assert ",exact," in (tmp_path / "t.csv").read_text()
    assert "pip install" not in result.stderr and "Traceback" not in result.stderr


@pytest.mark.parametrize(
    ("options", "env", "extra"),
    [
        (["--samples", "--screenshot", "x.png"], {}, "viz"),
        (["TOOTH", "--show"], {}, "viz"),
        (["TOOTH", "-v"], {}, "viz"),
        (["--samples", "--panel", "p.png"], {}, "viz"),
        (["--samples", "--method", "fast"], {}, "fast"),
        (["--samples", "--scheduler", "tcp://x:1"], {}, "cluster"),
        (["--samples"], {"DENTOPO_SCHEDULER": "tcp://x:1"}, "cluster"),
        (["robustness", "TOOTH", "-o", "study"], {}, "study"),
        (["robustness", "TOOTH", "-o", "study", "--faces", "300"], {}, "study"),
        (["sweep", "TOOTH", "-o", "sweep"], {}, "study"),
        (["report", "results.csv", "-o", "x.html"], {}, "report"),
        (["--samples", "-o", "t.csv", "--report", "x.html"], {}, "report"),
        (["app", ".", "--no-browser"], {}, "app"),
    ],
)
def test_a_missing_extra_is_one_line_and_exit_2(bare, tmp_path, options, env, extra):
    from dentopo.samples import sample_paths

    tooth = str(sample_paths()["tooth"])
    options = [tooth if option == "TOOTH" else option for option in options]
    result = run_bare(bare, "-m", "dentopo", *options, cwd=tmp_path, env=env)
    assert_one_line_naming(result, extra)
    assert result.stdout == ""
    assert not (tmp_path / "x.png").exists() and not (tmp_path / "p.png").exists()
    assert not (tmp_path / "x.html").exists() and not (tmp_path / "t.csv").exists()


def test_excel_output_without_its_extra(bare, tmp_path):
    from dentopo.formats import output_format

    try:
        output_format("t.xlsx")
    except ValueError:
        pytest.skip("Excel output (-o FILE.xlsx, the excel extra) is not in this branch yet")
    result = run_bare(bare, "-m", "dentopo", "--samples", "-o", "t.xlsx", cwd=tmp_path)
    assert_one_line_naming(result, "excel")
    assert not (tmp_path / "t.xlsx").exists()


LIBRARY_CALLS = {
    "to_dataframe": "dentopo.to_dataframe([])",
    "ariaDNE fast": "dentopo.ariaDNE(tooth(rings=6), method='fast')",
    "render_curvature": "dentopo.render_curvature(tooth(rings=6), screenshot='x.png')",
    "render_panel": "dentopo.render_panel([(tooth(rings=6), None)], interactive=True)",
    "compute_batch fast": "dentopo.compute_batch(path, method='fast')",
    "compute_batch dask": "dentopo.compute_batch(path, scheduler='tcp://x:1')",
    "write_protocol_study": "dentopo.write_protocol_study(None, 'out')",
    "write_sweep": "dentopo.write_sweep(None, 'out')",
    "write_report": "dentopo.write_report([], 'x.html')",
}
LIBRARY_EXTRAS = {
    "to_dataframe": "table",
    "ariaDNE fast": "fast",
    "render_curvature": "viz",
    "render_panel": "viz",
    "compute_batch fast": "fast",
    "compute_batch dask": "cluster",
    "write_protocol_study": "study",
    "write_sweep": "study",
    "write_report": "report",
}


def test_the_library_raises_missing_extra_error_with_the_same_words(bare, tmp_path):
    code = textwrap.dedent(
        f"""
        import json
        import dentopo
        from dentopo._optional import MissingExtraError
        from dentopo.samples import sample_paths, tooth

        path = str(sample_paths()["tooth"])
        report = {{}}
        for name, call in {LIBRARY_CALLS!r}.items():
            try:
                eval(call)
            except Exception as exc:
                report[name] = [
                    type(exc).__name__,
                    isinstance(exc, MissingExtraError),
                    isinstance(exc, ImportError),
                    getattr(exc, "extra", None),
                    str(exc),
                ]
            else:
                report[name] = None
        print(json.dumps(report))
        """
    )
    result = run_bare(bare, "-c", code, cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    report = json.loads(result.stdout)
    for name, extra in LIBRARY_EXTRAS.items():
        assert report[name] is not None, f"{name} did not raise"
        _, missing, importerror, raised_extra, message = report[name]
        assert (missing, importerror, raised_extra) == (True, True, extra), report[name]
        assert message.endswith(
            f"need the {extra} extra: pip install '.[{extra}]' in a clone of dentopo, "
            f"pip install 'dentopo[{extra}]' from PyPI"
        )
        assert "\n" not in message
    assert not (tmp_path / "x.png").exists() and not (tmp_path / "out").exists()


# --- in this interpreter (every extra installed): the helpers themselves


def test_every_feature_names_an_extra_of_pyproject_that_installs_its_module():
    requirements = pytest.importorskip("packaging.requirements", reason="needs packaging")
    extras = _load_toml(PYPROJECT)["project"]["optional-dependencies"]
    installed_by = metadata.packages_distributions()
    for feature in FEATURES:
        assert feature.extra in extras, feature
        listed = set()
        for text in extras[feature.extra]:
            requirement = requirements.Requirement(text)
            listed |= {_normal(requirement.name)} | {_normal(e) for e in requirement.extras}
        providers = {_normal(name) for name in installed_by.get(feature.module, ())}
        assert providers, f"{feature.module} is not installed here"
        assert providers & listed, (feature, listed)  # dask[distributed] lists distributed


def test_the_message_says_what_to_run_from_a_clone_and_from_pypi():
    message = missing_extra_message("pictures", "viz")
    assert message == (
        "pictures need the viz extra: pip install '.[viz]' in a clone of dentopo, "
        "pip install 'dentopo[viz]' from PyPI"
    )
    assert "\n" not in message


def test_check_finds_a_missing_module_without_importing(monkeypatch):
    check("json", extra="x", purpose="things")  # installed: no error
    monkeypatch.setitem(sys.modules, "json", None)  # as if not installed
    with pytest.raises(MissingExtraError) as caught:
        check("json", extra="viz", purpose="pictures")
    assert str(caught.value) == missing_extra_message("pictures", "viz")
    assert caught.value.extra == "viz" and isinstance(caught.value, ImportError)
    with pytest.raises(MissingExtraError):
        check("no_such_package_here.sub", extra="viz", purpose="pictures")


def test_show_is_the_primary_spelling_and_v_visualize_are_aliases():
    from dentopo.cli._arguments import build_parser

    parser = build_parser()
    for spelling in ("--show", "-v", "--visualize"):
        assert parser.parse_args(["a.ply", spelling]).show is True
    assert parser.parse_args(["a.ply"]).show is False
    assert "--show" in parser.format_help()


@pytest.mark.parametrize(
    ("module", "options", "extra"),
    [
        ("finufft", ["--method", "fast"], "fast"),
        ("pyvista", ["--screenshot", "x.png"], "viz"),
        ("distributed", ["--scheduler", "tcp://x:1"], "cluster"),
    ],
)
def test_the_command_checks_extras_before_computing(
    tmp_path, monkeypatch, capsys, module, options, extra
):
    from dentopo.cli import _checks, _compute, main
    from dentopo.samples import sample_paths

    monkeypatch.setitem(sys.modules, module, None)  # as if not installed

    def no_batch(*args, **kwargs):
        raise AssertionError("a batch was planned before the missing extra was reported")

    monkeypatch.setattr(_compute, "plan_batch", no_batch)
    monkeypatch.setattr(_checks, "plan_batch", no_batch)  # the outputs of --per-vertex
    monkeypatch.chdir(tmp_path)
    assert main([str(sample_paths()["tooth"]), *options]) == 2
    out, err = capsys.readouterr()
    assert out == ""
    [feature] = [f for f in FEATURES if f.module == module]
    assert feature.extra == extra
    assert err == f"dentopo: {missing_extra_message(feature.purpose, extra)}\n"


def test_a_missing_extra_found_late_is_still_one_line(monkeypatch, capsys):
    from dentopo.cli import _compute, main

    def late(*args, **kwargs):
        raise MissingExtraError("pictures", "viz", name="vtkmodules")

    monkeypatch.setattr(_compute, "plan_batch", late)
    assert main(["--samples", "-q"]) == 2
    assert capsys.readouterr().err == "dentopo: " + missing_extra_message("pictures", "viz") + "\n"
