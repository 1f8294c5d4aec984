"""Hints in the command's words: a library message's keyword arguments as command-line options.

The library's messages name what to change as keyword arguments, the way a
Python caller writes them: ``use find_alpha=True to search for an alpha``,
``turn it with orient='auto'``, ``read one with load_mesh(path,
geometry='crown')``.  On the command line that advice is in the wrong
language: the command shows it as ``use --find-alpha``, ``turn it with
--orient auto``, ``read one with --geometry crown``.  The options are looked up
in the command's own parser, so a hint names an option only if the command
has it; a keyword the command has no option for is left as it is.

May import: nothing of dentopo.
"""

from __future__ import annotations

import argparse
import re
from dataclasses import dataclass

#: ``name=value`` as the library's messages write it (a value quoted, a number or a word).
_KEYWORD = re.compile(
    r"(?<![\w.\-])(?P<name>[a-z][a-z0-9_]*)="
    r"(?P<value>'[^']*'|\"[^\"]*\"|\([^()]*\)|[A-Za-z0-9_.+\-]+)"
)

#: ``load_mesh(path, geometry='x')`` and the like: a call whose only advice is its keyword.
_CALL = re.compile(r"\b[a-z_]+\(path, (?P<keyword>[a-z_]+=(?:'[^']*'|[A-Za-z0-9_.+\-]+))\)")


@dataclass(frozen=True)
class _Option:
    flag: str  # the long option string, e.g. --find-alpha
    switch: bool  # a store_true option: name=True is the bare flag


def _options(parser: argparse.ArgumentParser) -> dict[str, _Option]:
    options = {}
    for action in parser._actions:  # argparse keeps no public list of its actions
        long = [s for s in action.option_strings if s.startswith("--")]
        if not long or action.dest in (argparse.SUPPRESS, "help"):
            continue
        switch = isinstance(action, argparse._StoreTrueAction)
        options[action.dest] = _Option(long[0], switch)
    return options


class CommandLineHints:
    """Rewrites the keyword arguments in a message as the options of `parser`."""

    def __init__(self, parser: argparse.ArgumentParser):
        self.options = _options(parser)

    def __call__(self, text):
        """`text` with each ``name=value`` the command has an option for in its words."""
        if not isinstance(text, str) or "=" not in text:
            return text
        text = _CALL.sub(lambda m: m.group("keyword"), text)
        return _KEYWORD.sub(self._option, text)

    def _option(self, match: re.Match) -> str:
        option = self.options.get(match.group("name"))
        if option is None:
            return match.group(0)
        value = match.group("value")
        if value[:1] in "'\"":
            value = value[1:-1]
        elif value[:1] == "(":  # a tuple, up=(x, y, z): one comma-separated word, --up X,Y,Z
            parts = [part.strip() for part in value[1:-1].split(",") if part.strip()]
            if all(part.isidentifier() for part in parts):
                parts = [part.upper() for part in parts]
            value = ",".join(parts)
        if option.switch:
            if value == "True":
                return option.flag
            if value == "False":
                return f"no {option.flag}"
        return f"{option.flag} {value}"

    def record(self, record: dict) -> dict:
        """A copy of a table row with its ``error`` and ``warnings`` in the command's words."""
        changed = dict(record)
        for key in ("error", "warnings"):
            if key in changed:
                changed[key] = self(changed[key])
        return changed
