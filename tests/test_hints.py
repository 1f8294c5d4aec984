"""Hints in the command's words (issue 21): options on the command line, keywords in Python."""

from __future__ import annotations

import argparse
import re
from pathlib import Path

import pytest

from dentopo.cli import main
from dentopo.cli._arguments import build_parser
from dentopo.cli._hints import CommandLineHints
from dentopo.formats import read_table

SRC = Path(__file__).resolve().parents[1] / "src" / "dentopo"


@pytest.fixture(scope="module")
def hints():
    return CommandLineHints(build_parser())


@pytest.mark.parametrize(
    ("library", "command"),
    [
        ("use find_alpha=True to search", "use --find-alpha to search"),
        ("turn it with orient='auto'", "turn it with --orient auto"),
        ("duplicates='keep' measures", "--duplicates keep measures"),
        (
            "read one with load_mesh(path, geometry='crown'), or",
            "read one with --geometry crown, or",
        ),
        ("geometry='all'", "--geometry all"),
        ("at alpha = 0.075", "at alpha = 0.075"),  # prose, not a keyword
        ("x, y = -3.6, 2.9", "x, y = -3.6, 2.9"),
        ("no_such_option=3", "no_such_option=3"),  # the command has no such option: unchanged
    ],
)
def test_keywords_become_options(hints, library, command):
    assert hints(library) == command


def test_every_keyword_hint_in_the_library_names_an_option(hints):
    """Each ``name=value`` the library's messages advise has an option the command knows."""
    advised = set()
    pattern = re.compile(r"(?:with|use|try|read one with) (?:load_mesh\(path, )?([a-z_]+)=")
    for path in SRC.rglob("*.py"):
        if {"cli", "study", "prepare"} & set(path.parts):  # these have their own commands
            continue
        advised.update(pattern.findall(path.read_text()))
    assert {"orient", "find_alpha", "geometry"} <= advised
    for name in advised:
        assert name in hints.options, f"the library advises {name}=, which the command lacks"


def test_a_partial_row_names_the_option(tmp_path, capsys):
    from conftest import shared_mesh

    out = tmp_path / "t.csv"
    mesh = shared_mesh("low")  # alpha 0.075 needs adjusting there (molaR's reference)
    assert main([str(mesh), "--metrics", "slope,rfi", "-o", str(out)]) == 1
    (row,) = read_table(out)
    assert row["status"] == "partial"
    assert "use --find-alpha to search" in row["error"] and "find_alpha" not in row["error"]
    assert "--find-alpha" in capsys.readouterr().err


def test_the_library_batch_keeps_keyword_arguments():
    from conftest import shared_mesh
    from dentopo import compute_batch

    (row,) = compute_batch([shared_mesh("low")], metrics="rfi")
    assert "use find_alpha=True to search" in row["error"]


def test_a_tuple_keyword_becomes_one_comma_separated_value():
    parser = argparse.ArgumentParser()
    parser.add_argument("--up")
    hints = CommandLineHints(parser)
    assert hints("by hand with up=(x, y, z)") == "by hand with --up X,Y,Z"
    assert hints("say up=(0, 0.5, 1).") == "say --up 0,0.5,1."
    assert hints("spin=(1, 2)") == "spin=(1, 2)"  # no such option: left as it is


def test_every_keyword_hint_of_the_preparation_names_an_option_of_its_command():
    """``dentopo prepare`` shows the prepare steps' advice (``up=(x, y, z)``) as its options."""
    from dentopo.cli._prepare import build_parser as prepare_parser

    prepare_hints = CommandLineHints(prepare_parser())
    advised = set()
    pattern = re.compile(r"(?:with|use|try|give [^.;]* with) ([a-z_]+)=")
    for path in (SRC / "prepare").rglob("*.py"):
        advised.update(pattern.findall(path.read_text()))
    assert "up" in advised
    for name in advised:
        assert name in prepare_hints.options, f"prepare advises {name}=, which its command lacks"
