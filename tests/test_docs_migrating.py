"""The examples on docs/coming-from/signdne.md, and what the page promises of them.

Its ```python blocks run as scripts, each in a fresh interpreter as a reader runs
them, in tests/test_examples.py (with every page's): not again here, in this
process, where a script's problems (worker processes that re-run it) do not show.
Each ```bash block's ``dentopo`` commands are run through the CLI's ``main`` and
must succeed, and the published CLI's columns are checked.  A block directly
preceded by ``<!-- not run: REASON -->`` is skipped (those need the published
package itself).
"""

from __future__ import annotations

import csv
import re
import shlex
from pathlib import Path

import pytest

from dentopo.cli import main
from dentopo.cli._arguments import build_parser
from dentopo.samples import tooth

PAGE = Path(__file__).resolve().parents[1] / "docs" / "coming-from" / "signdne.md"

#: The published CLI's columns, in its order (signDNE 0.1.4, ``create_dataframe``).
SIGNDNE_COLUMNS = [
    "File",
    "DNE",
    "positive_DNE",
    "negative_DNE",
    "surface_area",
    "positive_surface_area",
    "negative_surface_area",
]

_BLOCK = re.compile(
    r"(?:<!-- not run: (?P<reason>[^>]*?) -->\n)?```(?P<lang>\w+)\n(?P<code>.*?)```", re.S
)


def blocks(lang: str) -> list[tuple[int, str, str | None]]:
    """``(line, code, reason-not-run)`` of each block of `lang` on the page."""
    text = PAGE.read_text(encoding="utf-8")
    return [
        (text.count("\n", 0, m.start("code")), m["code"], m["reason"])
        for m in _BLOCK.finditer(text)
        if m["lang"] == lang
    ]


@pytest.fixture
def workdir(tmp_path, monkeypatch):
    tooth().export(tmp_path / "tooth.ply")
    monkeypatch.chdir(tmp_path)
    return tmp_path


def test_the_page_has_examples_and_few_are_skipped():
    python, bash = blocks("python"), blocks("bash")
    assert len([b for b in python if b[2] is None]) >= 4
    assert len([b for b in bash if b[2] is None]) >= 1
    skipped = [b for b in python + bash if b[2] is not None]
    assert len(skipped) <= 2 and all("signDNE 0.1.4" in reason for _, _, reason in skipped)


def _ids(lang: str) -> list[str]:
    return [f"line {line}" for line, _, _ in blocks(lang)]


def _cli_has(option: str) -> bool:
    return option in build_parser().format_help()


@pytest.mark.parametrize(("line", "code", "reason"), blocks("bash"), ids=_ids("bash"))
def test_bash_example_runs(workdir, line, code, reason):
    if reason is not None:
        pytest.skip(f"line {line}: {reason}")
    commands = [c for c in code.splitlines() if c.strip() and not c.lstrip().startswith("#")]
    for command in commands:
        words = shlex.split(command, comments=True)
        assert words[0] == "dentopo", f"line {line}: only dentopo commands run here: {command}"
        if "--columns" in words and not _cli_has("--columns"):
            pytest.skip("--columns (the published CLI's columns) is not in this version yet")
        assert main(words[1:]) == 0, f"line {line}: {command}"
    if "--columns" in code:  # what the page promises about the published columns
        out = workdir / "signdne.csv"
        with open(out, newline="", encoding="utf-8") as stream:
            assert next(csv.reader(stream)) == SIGNDNE_COLUMNS
