"""Warnings on stderr: one short line per file and warning, the long explanation once per run.

The library's warnings explain themselves in full (why it matters, what to do):
the closed-surface warning is 300 characters, and a run of a hundred closed
specimens wrote it a hundred times.  The table's ``warnings`` column keeps
every word (it is the record); on stderr each long warning a run knows is
written short, ``sphere.ply: warning: closed surface, measured as it lies (see
below)``, and its explanation once, at the end of the run, under the same
words: ``closed surface, measured as it lies (2 files): the surface is closed
(...)``.

Each :class:`Brief` finds one of those texts by its wording (anywhere in a
message: a row's warnings may run several together, a partial row's error
names each metric) and gives its short words and the explanation, with what
differs from file to file (a count, a side, a coordinate) left in the short
words only.  A message no brief knows is written as it is.  The tests build
each message from the library and check that its brief finds it.

May import: nothing of dentopo.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass
from functools import partial


@dataclass(frozen=True)
class Brief:
    """One long warning the command writes short.

    Attributes
    ----------
    pattern : re.Pattern
        Finds the long text (in the command's words: ``--orient auto``).
    short : callable
        ``short(match)``: the words written in its place on each file's line.
    title : callable
        ``title(match)``: the words the explanation is written under (the same for
        every file the explanation fits).
    explanation : callable
        ``explanation(match)``: the long text, once per run.
    """

    pattern: re.Pattern
    short: Callable[[re.Match], str]
    title: Callable[[re.Match], str]
    explanation: Callable[[re.Match], str]


def _text(match: re.Match) -> str:
    return match.group(0)


def _without(*groups: str) -> Callable[[re.Match], str]:
    """The matched text with the named groups (what differs between files) cut out."""

    def explanation(match: re.Match) -> str:
        text, start = [], match.start()
        cuts = sorted(match.span(g) for g in groups if match.group(g) is not None)
        for begin, end in cuts:
            text.append(match.string[start:begin])
            start = end
        text.append(match.string[start : match.end()])
        return "".join(text)

    return explanation


def _fixed(words: str) -> Callable[[re.Match], str]:
    return lambda match: words


def _wound(match: re.Match) -> str:
    fix = "rewound" if match.group("fix").startswith("they were rewound") else "measured as wound"
    return f"faces wound inward, {fix}"


def _wound_explanation(match: re.Match) -> str:
    return f"{match.group('effect')}; {match.group('fix')}"


def _wound_short(match: re.Match) -> str:
    which = (
        "every face"
        if match.group("count") is None
        else f"{match.group('count')} of {match.group('faces')} faces"
    )
    return f"{which} wound inward, " + _wound(match).rpartition(", ")[2]


#: ``--orient auto`` in the command's words, ``orient='auto'`` in the library's.
_AUTO = r"(?:--orient auto|orient='auto')"
_UP = r"(?:--up X,Y,Z|up=\(x, y, z\))"
_UNIT = r"(?:--unit mm|unit='mm')"

#: The long warnings the command writes short, in the library's wording.
BRIEFS: tuple[Brief, ...] = (
    # the orientation check of the metrics that assume +z (topography's Orientation.messages)
    Brief(
        re.compile(
            r"the surface is closed \(it has no open base to tell up from down"
            r"(?P<side>; [^()]*)\): it was not turned, and slope, OPC and RFI measure it as it "
            r"lies, its underside included; crop it to the crown above the cervix, or turn it by "
            r"hand"
        ),
        _fixed("closed surface, measured as it lies"),
        _fixed("closed surface, measured as it lies"),
        _without("side"),
    ),
    Brief(
        re.compile(
            r"the surface is flat \(it encloses no volume over its open base\): it has no up or "
            r"down, so its direction is undetermined and it was not turned; slope, OPC and RFI "
            r"measure it as it lies"
        ),
        _fixed("flat surface, direction undetermined, measured as it lies"),
        _fixed("flat surface, direction undetermined, measured as it lies"),
        _text,
    ),
    Brief(
        re.compile(
            r"the crown points to -z \(its open base lies above it\); slope, OPC and RFI assume "
            rf"it points to \+z, as molaR does: turn it with {_AUTO}"
        ),
        _fixed("points -z, measured as it lies"),
        _fixed("points -z, measured as it lies"),
        _text,
    ),
    Brief(
        re.compile(
            r"(?P<which>every face is wound inward|(?P<count>\d+) of (?P<faces>\d+) faces are "
            r"wound inward, against the rest) \((?P<effect>normals into the tooth: slope reads "
            r"180 degrees minus itself, OPC's aspects turn by 180 degrees and classic DNE's "
            r"convex and concave parts swap)\); (?P<fix>they were rewound outward before "
            rf"measuring \({_AUTO}\)|measured as wound, as molaR does: rewind them with {_AUTO})"
        ),
        _wound_short,
        _wound,
        _wound_explanation,
    ),
    # the unit-dependent metrics measured without --unit (batch)
    Brief(
        re.compile(
            r"doolkit's angularity depends on the mesh's unit; measured as if in millimetres "
            rf"\(give the unit: {_UNIT} if it is\)"
        ),
        _fixed("measured as if in millimetres"),
        _fixed("angularity measured as if in millimetres"),
        _text,
    ),
    Brief(
        re.compile(
            r"MorphoTester's outline area depends on the mesh's unit \(it draws the crown with "
            r"half a unit of margin, and rounds both areas to 3 decimals\); measured on the "
            r"crown as given, as MorphoTester measures it \(give the unit to measure it in "
            rf"millimetres, as MorphoTester's own sample crowns are: {_UNIT} if it is\)"
        ),
        _fixed("measured in the mesh's own unit"),
        _fixed("morphotester_rfi measured in the mesh's own unit"),
        _text,
    ),
    # molaR's RFI at an alpha whose hull it stops on (a partial row's error)
    Brief(
        re.compile(
            r"(?P<head>alpha adjustment required at alpha = [^:]+): (?P<where>[^;]*); "
            r"(?P<advice>(?:molaR's search from there failed too; )?the relief index on the "
            r"exact projected footprint needs no alpha and exists for every open crown: use "
            r"[^;]*?(?:; for molaR's own number, use [^;]*? to search for an alpha \(the "
            r"search can fail too\), or choose another alpha)?)(?=;|$)"
        ),
        lambda match: match.group("head"),  # where it stops: in the row's error
        lambda match: match.group("head"),
        lambda match: match.group("advice"),
    ),
    Brief(
        re.compile(
            r"angularity is undefined: (?P<count>\d+ of \d+) faces have no area on doolkit's "
            r"slope surface (?P<why>\(x, y and each vertex's slope as z\), where doolkit gives "
            r"NaN: their x-y footprint is a line and their vertices' slopes are equal \(a "
            r"vertical wall\))"
        ),
        lambda match: f"angularity is undefined: {match.group('count')} faces have no area",
        _fixed("angularity undefined"),
        lambda match: f"faces have no area on doolkit's slope surface {match.group('why')}",
    ),
    # the orient step of a preparation (prepare's orient)
    Brief(
        re.compile(
            r"the surface is closed \(it has no open base to tell up from down\)(?P<why> and "
            rf"[^:]*): it was left as it is; give the occlusal direction by hand with {_UP}"
        ),
        _fixed("closed surface, no axis found, left as it lies"),
        _fixed("closed surface, no axis found, left as it lies"),
        _without("why"),
    ),
    Brief(
        re.compile(
            r"the surface is closed \(it has no open base\): it was turned so that its shortest "
            r"principal axis points up, to the side most of its area faces; a guess from its "
            rf"shape \(a whole tooth's long axis is its up\): check it, or give the occlusal "
            rf"direction by hand with {_UP}"
        ),
        _fixed("closed surface, turned by its shape (a guess)"),
        _fixed("closed surface, turned by its shape (a guess)"),
        _text,
    ),
    Brief(
        re.compile(
            r"the surface is flat \(it encloses no volume over its open base\): it has no up or "
            rf"down, so it was left as it is; give the occlusal direction by hand with {_UP}"
        ),
        _fixed("flat surface, no axis found, left as it lies"),
        _fixed("flat surface, no axis found, left as it lies"),
        _text,
    ),
    Brief(
        re.compile(
            r"the crown's centroid lies on the plane of its open base: which side is up is "
            r"undetermined, so it was left as it is; give the occlusal direction by hand with "
            rf"{_UP}"
        ),
        _fixed("no side of the open base is up, left as it lies"),
        _fixed("no side of the open base is up, left as it lies"),
        _text,
    ),
)

#: What a short line adds, pointing at the explanation.
SEE_BELOW = " (see below)"


class Briefing:
    """The warnings of one run: each written short, each explanation kept for the end.

    Parameters
    ----------
    briefs : sequence of Brief
        The long texts known (default :data:`BRIEFS`).
    """

    def __init__(self, briefs: tuple[Brief, ...] = BRIEFS):
        self.briefs = briefs
        self._explained: dict[str, tuple[str, set[str]]] = {}  # title -> (explanation, files)

    def __call__(self, file: str, message: str) -> str:
        """`message` about `file` with each long text it holds in short words."""
        for brief in self.briefs:
            message = brief.pattern.sub(partial(self._short, brief, file), message)
        return message

    def _short(self, brief: Brief, file: str, match: re.Match) -> str:
        title = brief.title(match)
        self._explained.setdefault(title, (brief.explanation(match), set()))[1].add(file)
        return brief.short(match) + SEE_BELOW

    def explanations(self) -> list[str]:
        """One line per long text met, in the order met: ``title (N files): explanation``."""
        lines = []
        for title, (explanation, files) in self._explained.items():
            count = f"{len(files)} file" + ("" if len(files) == 1 else "s")
            lines.append(f"{title} ({count}): {explanation}")
        return lines
