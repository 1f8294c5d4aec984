"""What a release needs from the repository: one version, a changelog entry, every file packaged.

The wheel itself is built, checked with twine, installed alone into a fresh
environment and run by CI (``.ci/run``); these tests catch the same mistakes
earlier, from the source tree.
"""

from __future__ import annotations

import fnmatch
import re
import subprocess
from pathlib import Path

import pytest

from dentopo import __version__

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "src" / "dentopo"


def _load_toml(path: Path) -> dict:
    try:
        import tomllib
    except ImportError:  # Python 3.10
        tomllib = pytest.importorskip("tomli", reason="reading pyproject.toml needs tomllib")
    return tomllib.loads(path.read_text(encoding="utf-8"))


def _tracked(under: Path) -> list[Path]:
    """Files git tracks below `under` (skips outside a git checkout, e.g. an unpacked sdist)."""
    try:
        listed = subprocess.run(
            ["git", "ls-files", "-z", "--", str(under)],
            cwd=ROOT,
            capture_output=True,
            check=True,
        ).stdout
    except (OSError, subprocess.CalledProcessError):
        pytest.skip("needs a git checkout of dentopo")
    return [ROOT / name for name in listed.decode().split("\0") if name]


def test_the_version_is_read_from_one_place():
    project = _load_toml(ROOT / "pyproject.toml")
    assert "version" not in project["project"]
    assert "version" in project["project"]["dynamic"]
    attr = project["tool"]["setuptools"]["dynamic"]["version"]["attr"]
    assert attr == "dentopo._version.__version__"
    assert re.fullmatch(r"\d+\.\d+\.\d+", __version__), __version__


def test_the_r_package_carries_the_same_version():
    description = (ROOT / "bridges" / "R" / "dentopo" / "DESCRIPTION").read_text(encoding="utf-8")
    [version] = re.findall(r"^Version:\s*(\S+)\s*$", description, flags=re.MULTILINE)
    assert version == __version__


def test_no_other_file_of_the_package_or_bridges_hard_codes_the_version():
    allowed = {PACKAGE / "_version.py", ROOT / "bridges" / "R" / "dentopo" / "DESCRIPTION"}
    pattern = re.compile(r"(?<![\d.])" + re.escape(__version__) + r"(?![\d.])")
    found = [
        path.relative_to(ROOT)
        for path in _tracked(PACKAGE) + _tracked(ROOT / "bridges")
        if path not in allowed
        and path.suffix not in (".ply", ".png")
        and pattern.search(path.read_text(encoding="utf-8", errors="replace"))
    ]
    assert found == []


def test_the_changelog_has_an_entry_for_this_version_and_an_unreleased_section():
    text = (ROOT / "CHANGELOG.md").read_text(encoding="utf-8")
    headings = re.findall(r"^## \[([^\]]+)\](?: - (\d{4}-\d{2}-\d{2}))?\s*$", text, re.MULTILINE)
    names = [name for name, _ in headings]
    assert names[0] == "Unreleased"
    assert __version__ in names
    assert all(date for name, date in headings if name != "Unreleased"), headings


def test_every_data_file_of_the_package_is_in_its_package_data():
    """A file the code loads at run time (samples, py.typed, ...) must be shipped in the wheel."""
    setuptools = _load_toml(ROOT / "pyproject.toml")["tool"]["setuptools"]
    patterns = setuptools["package-data"]["dentopo"]
    data = [
        path.relative_to(PACKAGE).as_posix() for path in _tracked(PACKAGE) if path.suffix != ".py"
    ]
    assert "py.typed" in data and any(name.startswith("samples/") for name in data)
    unshipped = [name for name in data if not any(fnmatch.fnmatch(name, p) for p in patterns)]
    assert unshipped == []


def test_every_subpackage_is_a_package():
    """setuptools' find only ships folders with an ``__init__.py``."""
    folders = {path.parent for path in _tracked(PACKAGE) if path.suffix == ".py"}
    assert [f for f in folders if not (f / "__init__.py").is_file()] == []
