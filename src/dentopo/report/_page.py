"""The report's HTML: one self-contained page, plotly's JavaScript inlined once.

Sections: a summary with the colour scale, the marks, the units and the
table's settings; the table of specimens (one row each: thumbnail, name with
its mark, group, status, error and warnings, then every column the table holds
but its settings, by family: :mod:`._columns`), sorted by clicking a header,
filtered by text, group and status, its columns shown a family at a time, the
key metrics or all of them, in a few lines of plain JavaScript; each metric's
distribution per group, family by family (box plots with every point; OPC's
bins and rotations folded away, drawn when opened) and a scatter matrix of the
metrics ticked, coloured by group (plotly); each row's warnings; the specimens
that failed or have no picture, with why.  A click on a thumbnail, a name or a
plotted point opens that specimen's 3D view, unpacked from its payload only
then (``_payload``; the browser's ``DecompressionStream``); ``#view=N`` in the
address opens specimen N, numbered from 1 as in the table's ``#`` column (a
number past the table's end says so in the viewer).

Specimens measured closed or turned (their ``orientation`` cell) carry a mark
by their name, explained in the summary; a closed one's values of the metrics
that assume the crown points to +z are shaded in the table and drawn as
crosses in the plots.

The page fetches nothing: a Content-Security-Policy forbids every request
(images are ``data:`` URLs).  It allows inline scripts and ``eval``: plotly's
WebGL plots (the scatter matrix) compile their drawing code at run time, and
without it they show "WebGL is not supported" instead.  A small status
element records for checks that the scripts ran (``data-ready``), how many
thumbnails decoded, any error reported to the console or left uncaught, and
what a reader could not see (``data-layout``: the status column past the
window's edge, a page wider than the window, the scatter matrix's axis titles
over each other, the 3D view's toolbar over its colour bar).

Names are text wherever they appear: HTML-escaped in the table and lists, in
the JSON block with ``<``, ``>`` and ``&`` escaped
(:func:`dentopo.figures._provenance.html_json`: a mesh named
``<!--<script>x.ply`` cannot keep the block open), and given to plotly (which
reads some HTML in its texts: links, bold, line breaks) with ``&``, ``<`` and
``>`` as entities, so that a group named ``<a href=...>`` is drawn as those
characters, not as a link.  Warnings and errors (which name files) are
escaped too.
"""

from __future__ import annotations

import html
import json
import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from ..figures import ColorScale, diverging_rgb
from ..figures._provenance import html_json
from ._collect import Specimen
from ._columns import (
    FAMILY_LABELS,
    OTHER,
    SETTINGS,
    SPLOM_TICKED,
    ReportColumn,
    family_label,
)
from ._payload import COLOR_STEPS
from ._static import HEAD, SCRIPT, UNPACK_JS, VIEWER

#: A table of at most this many columns shows all of them at first; a wider one its key metrics.
ALL_COLUMNS_UP_TO = 14

#: Between the links to the families.
SEPARATOR = " \u00b7 "

#: What each mark means, for the summary and the marks' hover text.
MARK_MEANINGS = {
    "closed": (
        "the surface is closed (no open base), so which way the crown points cannot be told: "
        "the metrics that assume it points to +z measured it as it lies, its underside "
        "included (a closed surface's mean slope is near 90\u00b0); such values are shaded in "
        "the table and drawn as \u00d7 in the plots"
    ),
    "turned": (
        "the crown pointed to \u2212z and was turned to +z before the metrics that assume it "
        "points up (the file is unchanged)"
    ),
}

#: Group colours, in the order groups are listed (Tableau 10), repeated past ten groups.
GROUP_COLORS = (
    "#4e79a7",
    "#f28e2b",
    "#59a14f",
    "#e15759",
    "#76b7b2",
    "#edc948",
    "#b07aa1",
    "#ff9da7",
    "#9c755f",
    "#bab0ac",
)

_CSP = (
    "default-src 'none'; script-src 'unsafe-inline' 'unsafe-eval'; "
    "style-src 'unsafe-inline'; img-src data: blob:; font-src data:"
)


@dataclass
class PageContent:
    """Everything the page shows.

    Attributes
    ----------
    title : str
        The page's title.
    source : str
        Where the table came from (shown in the summary).
    specimens : list of Specimen
        The rows, in table order.
    columns : list of ReportColumn
        The columns shown (:func:`._columns.report_columns`), by family; the
        metrics among them with a number in some row are plotted.
    groups : list of str
        The groups, in the order listed.
    scale : ColorScale
        The collection's colour limits.
    thumbnails : dict
        Specimen index -> data URL of its picture.
    payloads : dict
        Specimen index -> its 3D payload (``_payload.pack_mesh``).
    plotly_js : str
        plotly.js, inlined once.
    notes : list of str
        Lines added to the summary.
    protocols : list of (str, Protocol)
        The preparation protocols of the rows (by their ``protocol`` label):
        stated with their steps, and the pictures are of the prepared crowns.
    """

    title: str
    source: str
    specimens: Sequence[Specimen]
    columns: Sequence[ReportColumn]
    groups: Sequence[str]
    scale: ColorScale
    thumbnails: dict
    payloads: dict
    plotly_js: str
    notes: list = field(default_factory=list)
    protocols: list = field(default_factory=list)

    @property
    def families(self) -> list[str]:
        """The families of the columns shown, in order."""
        return list(dict.fromkeys(column.family for column in self.columns))

    @property
    def charted(self) -> list[ReportColumn]:
        """The columns plotted: the metrics with a number in some row."""
        return [column for column in self.columns if column.charted]


def plural(count: int, noun: str) -> str:
    """``"1 group"``, ``"2 groups"``; ``"2 families"``."""
    if count == 1:
        return f"{count} {noun}"
    return f"{count} {noun[:-1]}ies" if noun.endswith("y") else f"{count} {noun}s"


def _number(value) -> float | None:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    return float(value) if math.isfinite(value) else None


def _text(value) -> str:
    """A setting's or a text cell's value as text (``"empty"`` for none)."""
    if value is None or (isinstance(value, float) and math.isnan(value)) or value == "":
        return "empty"
    if isinstance(value, float):
        return f"{value:.6g}"
    return str(value)


def _cell(value, classes: str = "", title: str = "") -> str:
    """A table cell of a number (short text, the full value to sort by), or of text."""
    esc = html.escape
    hover = f' title="{esc(title)}"' if title else ""
    number = _number(value)
    if number is None and isinstance(value, str) and value:
        return f'<td class="{classes}" data-v="{esc(value.lower())}"{hover}>{esc(value)}</td>'
    kind = f"num {classes}".strip()
    if number is None:
        return f'<td class="{kind}" data-v=""></td>'
    text = str(int(number)) if isinstance(value, int) else f"{number:.4g}"
    return f'<td class="{kind}" data-v="{number!r}"{hover}>{text}</td>'


def _rgb(row) -> str:
    r, g, b = (round(255 * float(c)) for c in row)
    return f"rgb({r},{g},{b})"


def colorscale(steps: int = 11) -> list:
    """The diverging scale as plotly's ``[[position, colour], ...]`` (position 0..1)."""
    t = np.linspace(-1.0, 1.0, steps)
    return [[float((x + 1) / 2), _rgb(c)] for x, c in zip(t, diverging_rgb(t), strict=True)]


def _gradient() -> str:
    stops = ", ".join(f"{color} {100 * at:.0f}%" for at, color in colorscale())
    return f"linear-gradient(to right, {stops})"


def _json_script(element_id: str, data) -> str:
    text = html_json(json.dumps(data, separators=(",", ":"), allow_nan=False))
    return f'<script type="application/json" id="{element_id}">{text}</script>'


def _ticked(content: PageContent) -> set[str]:
    """The metrics ticked for the scatter matrix at first: the first key metrics plotted."""
    key = [c.key for c in content.charted if c.headline and not c.detail]
    return set(key[:SPLOM_TICKED])


def _data(content: PageContent) -> dict:
    group_index = {name: i for i, name in enumerate(content.groups)}
    family_index = {name: i for i, name in enumerate(content.families)}
    charted = content.charted
    specimens = []
    for s in content.specimens:
        specimens.append(
            {
                "index": s.index,
                "name": s.name,
                "group": group_index[s.group],
                "status": s.status,
                "values": [_number(s.record.get(c.key)) for c in charted],
                "problem": s.problem,
                "mark": s.mark,
            }
        )
    meshes = {
        str(i): {k: v for k, v in payload.items() if k != "data"}
        for i, payload in content.payloads.items()
    }
    return {
        "metrics": [
            {
                "key": c.key,
                "label": c.title,
                "short": c.short,
                "family": family_index[c.family],
                "detail": c.detail,
                "oriented": c.oriented,
            }
            for c in charted
        ],
        "families": [family_label(f) for f in content.families],
        "groups": list(content.groups),
        "colors": [GROUP_COLORS[i % len(GROUP_COLORS)] for i in range(len(content.groups))],
        "specimens": specimens,
        "meshes": meshes,
        "limit": content.scale.limit,
        "steps": COLOR_STEPS,
        "colorscale": colorscale(),
        "rule": content.scale.rule,
    }


def _classes(column: ReportColumn, family: int) -> str:
    return f"m f{family}" + (" k" if column.headline else "")


def _mark(s: Specimen) -> str:
    """The mark by a specimen's name (closed, turned), its meaning and orientation on hover."""
    if s.mark is None:
        return ""
    title = f"orientation: {s.orientation}. {s.mark.capitalize()}: {MARK_MEANINGS[s.mark]}."
    return f' <span class="mark {s.mark}" title="{html.escape(title)}">{s.mark}</span>'


def _row(s: Specimen, content: PageContent) -> str:
    esc = html.escape
    thumb = content.thumbnails.get(s.index)
    name = esc(s.name)
    if thumb is not None:
        picture = (
            f'<button class="open" type="button" data-index="{s.index}" '
            f'title="open the 3D view of {name}"><img class="thumb" alt="{name}" '
            f'src="{thumb}"></button>'
        )
    else:
        picture = '<span class="nothumb">no picture</span>'
    if s.index in content.payloads:
        label = (
            f'<button class="open link" type="button" data-index="{s.index}" '
            f'title="{esc(s.path or s.file)}">{name}</button>'
        )
    else:
        label = f'<span title="{esc(s.file)}">{name}</span>'
    errors = esc(
        "; ".join(e for e in (s.error, f"no picture: {s.problem}" if s.problem else "") if e)
    )
    # status, error and warnings next to the name, where a wide table cannot scroll them out
    # of sight; each cut to a few lines here (all of it on hover, and under "Warnings" and
    # "Failed specimens")
    error = f'<div class="error" title="{errors}">{errors}</div>' if errors else ""
    warned = esc(s.warnings)
    warning = f'<div class="warn" title="{warned}">\u26a0 {warned}</div>' if warned else ""
    family = {name: i for i, name in enumerate(content.families)}
    cells = [
        f'<td class="num" data-v="{s.index + 1}">{s.index + 1}</td>',
        f'<td class="pic">{picture}</td>',
        f'<td class="name" data-v="{esc(s.name.lower())}">{label}{_mark(s)}</td>',
        f"<td>{esc(s.group)}</td>",
        f'<td class="status-cell" data-v="{esc(s.status)}"><span class="status '
        f'{esc(s.status)}">{esc(s.status)}</span>{error}{warning}</td>',
    ]
    for column in content.columns:
        classes = _classes(column, family[column.family])
        value = s.record.get(column.key)
        title = ""
        if s.mark == "closed" and column.oriented and _number(value) is not None:
            classes += " asis"
            title = "closed surface: measured as it lies, its underside included"
        cells.append(_cell(value, classes, title))
    return (
        f'<tr data-index="{s.index}" data-group="{esc(s.group)}" data-status="{esc(s.status)}"'
        + (f' data-mark="{s.mark}"' if s.mark else "")
        + ">"
        + "".join(cells)
        + "</tr>"
    )


def _problems(content: PageContent) -> str:
    items = []
    for s in content.specimens:
        if s.status == "ok" and not s.problem:
            continue
        why = [e for e in (s.error, f"no picture: {s.problem}" if s.problem else "") if e]
        items.append(
            f'<li data-index="{s.index}"><b>{html.escape(s.name)}</b> '
            f'<span class="status {html.escape(s.status)}">{html.escape(s.status)}</span> '
            f'<span class="error">{html.escape("; ".join(why) or "no error recorded")}</span>'
            f' <span class="path">{html.escape(s.file)}</span></li>'
        )
    if not items:
        return "<p>None: every specimen was measured and drawn.</p>"
    return f'<ul id="problem-list">{"".join(items)}</ul>'


def _warnings(content: PageContent) -> str:
    """Each row's warnings in full, with its mark."""
    items = [
        f'<li data-index="{s.index}"><b>{html.escape(s.name)}</b>{_mark(s)} '
        f'<span class="warn">{html.escape(s.warnings)}</span></li>'
        for s in content.specimens
        if s.warnings
    ]
    if not items:
        held = any("warnings" in s.record for s in content.specimens)
        return "<p>None.</p>" if held else "<p>The table has no warnings column.</p>"
    return f'<ul id="warning-list">{"".join(items)}</ul>'


def _marks(content: PageContent) -> str:
    """What the marks by the names mean, for the marks the page shows."""
    lines = []
    for mark, meaning in MARK_MEANINGS.items():
        count = sum(s.mark == mark for s in content.specimens)
        if count:
            lines.append(
                f'<li><span class="mark {mark}">{mark}</span> '
                f"({plural(count, 'specimen')}): {html.escape(meaning)}.</li>"
            )
    if not lines:
        return ""
    return f'<ul class="marks">{"".join(lines)}</ul>'


def _units(content: PageContent) -> str:
    """What the units in the headers mean, for those shown."""
    units = {column.unit for column in content.columns if column.metric}
    parts = []
    if "\u00b0" in units:
        parts.append("\u00b0 degrees")
    if units & {"unit", "unit\u00b2"}:
        scale = {
            _number(s.record.get("mm_per_unit"))
            for s in content.specimens
            if "mm_per_unit" in s.record
        }
        given = ""
        if len(scale) == 1 and None not in scale:
            given = f" (the table's mm_per_unit: 1 unit = {next(iter(scale)):g} mm)"
        parts.append(
            "unit, unit\u00b2: lengths and areas in the meshes' own unit, that of their "
            "coordinates" + given
        )
    if "patches" in units:
        parts.append("patches: OPC's counts")
    if "" in units:
        parts.append("no unit: ratios, energies, mean curvatures, fractions")
    return f"<p>Units: {html.escape('; '.join(parts))}.</p>" if parts else ""


def _settings(content: PageContent) -> str:
    """The table's settings columns, each with its values (and how many rows hold each)."""
    parts = []
    rows = len(content.specimens)
    for key in SETTINGS:
        values = [s.record[key] for s in content.specimens if key in s.record]
        if all(_text(value) == "empty" for value in values):
            continue  # not held (a table of another layout), or empty throughout
        counts: dict[str, int] = {}
        for value in values:
            counts[_text(value)] = counts.get(_text(value), 0) + 1
        if len(counts) == 1 and len(values) == rows:
            text = next(iter(counts))
        else:
            text = ", ".join(f"{v} ({plural(n, 'row')})" for v, n in counts.items())
        parts.append(f"<b>{html.escape(key)}</b> {html.escape(text)}")
    if not parts:
        return ""
    return (
        f'<details class="settings"><summary>Settings the table records '
        f"({plural(len(parts), 'column')})</summary><p>{'; '.join(parts)}.</p></details>"
    )


def _summary(content: PageContent) -> str:
    counts = {}
    for s in content.specimens:
        counts[s.status] = counts.get(s.status, 0) + 1
    statuses = ", ".join(f"{n} {status}" for status, n in sorted(counts.items()))
    specimens = plural(len(content.specimens), "specimen")
    metrics = [c for c in content.columns if c.metric]
    families = [f for f in content.families if any(c.family == f for c in metrics)]
    lines = [
        f"{specimens} in {plural(len(content.groups), 'group')} "
        f"({statuses}), from {html.escape(content.source)}.",
        "Pictures: signed local curvature (ariaDNE, each row's settings), one colour scale "
        f"for the whole collection, {html.escape(content.scale.rule)}: "
        "blue \u2212 concave, red + convex. Click a picture, a name or a plotted point "
        "for the specimen's 3D view.",
        f"{plural(len(metrics), 'metric column')} in {plural(len(families), 'family')}: "
        + html.escape(", ".join(family_label(f) for f in families) or "none")
        + ".",
        *(html.escape(note) for note in content.notes),
    ]
    return (
        "".join(f"<p>{line}</p>" for line in lines)
        + _marks(content)
        + _units(content)
        + _settings(content)
        + _protocols(content)
    )


def _step_text(parameters: dict) -> str:
    return ", ".join(
        f"{key}={'none' if value is None else value}" for key, value in parameters.items()
    )


def _protocols(content: PageContent) -> str:
    """The preparation protocols of the rows: name, digest, each step with its parameters."""
    if not content.protocols:
        return ""
    esc = html.escape
    parts = []
    for label, protocol in content.protocols:
        rows = sum(s.protocol_label == label for s in content.specimens)
        steps = "".join(
            f"<li><b>{esc(name)}</b> {esc(_step_text(parameters))}</li>"
            for name, parameters in protocol.steps().items()
        )
        about = " ".join(x for x in (protocol.description, protocol.source) if x)
        parts.append(
            f'<div class="protocol"><p>Prepared before measuring ({plural(rows, "row")}): '
            f"protocol <b>{esc(protocol.name)}</b>, digest <code>{esc(protocol.digest)}</code>"
            + (f" ({esc(about)})" if about else "")
            + ". The pictures show the prepared crowns (prepared again with it from the "
            f"files).</p><ol>{steps}</ol></div>"
        )
    return "".join(parts)


def _options(values: Sequence[str]) -> str:
    return "".join(f'<option value="{html.escape(v)}">{html.escape(v)}</option>' for v in values)


def _view_rule(view: str) -> str:
    """The CSS that hides the columns outside `view` (``key``, ``all``, ``f<N>``)."""
    if view == "all":
        return ""
    shown = "k" if view == "key" else view
    return f"#specimen-table .m:not(.{shown}) {{ display: none; }}"


def _column_views(content: PageContent) -> tuple[str, str]:
    """The column chooser (key metrics, each family, every column) and the view shown first."""
    columns = content.columns
    first = "all" if len(columns) <= ALL_COLUMNS_UP_TO else "key"
    options = [("key", f"key metrics ({sum(c.headline for c in columns)})")]
    for i, family in enumerate(content.families):
        count = sum(c.family == family for c in columns)
        options.append((f"f{i}", f"{family_label(family)} ({count})"))
    options.append(("all", f"every column ({len(columns)})"))
    chooser = "".join(
        f'<option value="{value}"{" selected" if value == first else ""}>'
        f"{html.escape(text)}</option>"
        for value, text in options
    )
    return f'<label>columns <select id="column-view">{chooser}</select></label>', first


def _header(column: ReportColumn, family: int) -> str:
    esc = html.escape
    kind = "num" if column.numeric or column.family != OTHER else "text"
    about = f"{column.key}: {family_label(column.family)}" + (
        f", {column.unit}" if column.unit else ""
    )
    if column.oriented:
        about += "; assumes the crown points to +z"
    return (
        f'<th data-sort="{kind}" class="metric {_classes(column, family)}" '
        f'title="{esc(about)}">{_breakable(column.title)}'
        f'<span class="fam">{esc(_short_family(column.family))}</span></th>'
    )


def _breakable(text: str) -> str:
    """`text` escaped, with a place to break the line after each ``_`` (long column keys)."""
    return html.escape(text).replace("_", "_<wbr>")


def _short_family(family: str) -> str:
    """The family's name without the tool's version (``molaR 6.0`` -> ``molaR``)."""
    label = family_label(family)
    return label.split(" ")[0] if family in FAMILY_LABELS else label


def _group_plots(content: PageContent) -> str:
    """Each family's heading and its metrics' box plots; OPC's bins and rotations folded away."""
    esc = html.escape
    parts = []
    index = []
    charted = {c.key: m for m, c in enumerate(content.charted)}
    for family in content.families:
        columns = [c for c in content.columns if c.family == family and c.metric]
        if not columns:
            continue
        label = family_label(family)
        index.append(f'<a href="#family-{esc(family)}">{esc(label)}</a>')

        def boxes(chosen):
            return "".join(
                f'<figure class="group-figure"><figcaption title="{esc(c.key)}">'
                f"{esc(c.title)}</figcaption>"
                f'<div class="group-plot" id="box-{esc(c.key)}" data-metric="{charted[c.key]}">'
                "</div></figure>"
                for c in chosen
            )

        main = [c for c in columns if c.charted and not c.detail]
        folded = [c for c in columns if c.charted and c.detail]
        empty = [c for c in columns if not c.charted]
        part = f'<h3 id="family-{esc(family)}">{esc(label)}</h3>'
        if main:
            part += f'<div class="plots">{boxes(main)}</div>'
        if empty:
            part += (
                '<p class="empty">No value in any row: '
                + esc(", ".join(c.title for c in empty))
                + ".</p>"
            )
        if folded:
            part += (
                f'<details class="detail-plots"><summary>OPC\'s bins and rotations '
                f"({plural(len(folded), 'column')}): "
                + esc(", ".join(c.key for c in folded[:2]))
                + (", \u2026" if len(folded) > 2 else "")
                + f'</summary><div class="plots">{boxes(folded)}</div></details>'
            )
        parts.append(part)
    if not parts:
        return "<p>The table holds no metric with a number.</p>"
    return f'<p class="families">{SEPARATOR.join(index)}</p>' + "".join(parts)


def _splom(content: PageContent) -> str:
    """The scatter matrix's chooser (every metric plotted, by family) and its place."""
    esc = html.escape
    chosen = [(m, c) for m, c in enumerate(content.charted) if not c.detail]
    if len(chosen) < 2:
        return "<p>A scatter matrix needs two metric columns or more.</p>"
    ticked = _ticked(content)
    lines = []
    for family in content.families:
        boxes = "".join(
            f'<label><input type="checkbox" value="{m}"{" checked" if c.key in ticked else ""}>'
            f" {esc(c.short)}</label>"
            for m, c in chosen
            if c.family == family
        )
        if boxes:
            lines.append(f"<div><b>{esc(_short_family(family))}</b> {boxes}</div>")
    names = "; ".join(f"{esc(c.short)}: {esc(c.label)}" for _, c in chosen if c.short != c.label)
    return (
        f'<div id="splom-metrics" class="chooser">{"".join(lines)}</div>'
        + (f'<p class="legend">{names}.</p>' if names else "")
        + '<div id="splom" class="splom"></div>'
    )


def render_page(content: PageContent) -> str:
    """The whole page as text."""
    esc = html.escape
    family = {name: i for i, name in enumerate(content.families)}
    headers = [
        '<th data-sort="num">#</th>',
        '<th class="pic">map</th>',
        '<th data-sort="text" class="name">specimen</th>',
        '<th data-sort="text">group</th>',
        '<th data-sort="text" class="status-cell">status, error, warnings</th>',
        *(_header(column, family[column.family]) for column in content.columns),
    ]
    rows = "\n".join(_row(s, content) for s in content.specimens)
    statuses = sorted({s.status for s in content.specimens})
    marks = [mark for mark in MARK_MEANINGS if any(s.mark == mark for s in content.specimens)]
    chooser, view = _column_views(content)
    meshes = "\n".join(
        f'<script type="application/octet-stream" id="mesh-{i}">{payload["data"]}</script>'
        for i, payload in content.payloads.items()
    )
    return (
        HEAD.replace("%CSP%", _CSP)
        .replace("%GRADIENT%", _gradient())
        .replace("%TITLE%", esc(content.title))  # last: a title's "%CSP%" stays as it is
        + f'<style id="column-view-style">{_view_rule(view)}</style>\n'
        + "<script>"
        + content.plotly_js
        + "</script>\n</head>\n<body>\n"
        + f"<header><h1>{esc(content.title)}</h1>{_summary(content)}"
        + f'<div class="bar"><span>\u2212{content.scale.limit:.4g}</span><span class="gradient">'
        + f"</span><span>+{content.scale.limit:.4g}</span></div></header>\n"
        + '<nav><a href="#specimens">specimens</a> <a href="#groups">groups</a> '
        + '<a href="#warnings">warnings</a> <a href="#problems">failed</a></nav>\n'
        + '<section id="specimens"><h2>Specimens</h2><div class="controls">'
        + '<input id="filter" type="search" placeholder="filter: name, group, status, error">'
        + '<select id="group-filter"><option value="">all groups</option>'
        + f"{_options(content.groups)}</select>"
        + '<select id="status-filter"><option value="">any status</option>'
        + f"{_options(statuses)}</select>"
        + '<select id="mark-filter"><option value="">any mark</option>'
        + f'{_options(marks)}<option value="none">no mark</option></select>'
        + f'{chooser}<span id="shown"></span></div>\n'
        + '<div class="table-wrap">'
        + f'<table id="specimen-table"><thead><tr>{"".join(headers)}</tr></thead>\n<tbody>\n'
        + rows
        + "\n</tbody></table></div></section>\n"
        + '<section id="groups"><h2>Groups</h2>'
        + "<p>Each metric by group, family by family: a box (quartiles, median, whiskers to "
        + "1.5 IQR) over every specimen's point; \u00d7 marks a closed surface.</p>"
        + _group_plots(content)
        + f"<h3>Scatter matrix</h3>{_splom(content)}</section>\n"
        + f'<section id="warnings"><h2>Warnings</h2>{_warnings(content)}</section>\n'
        + f'<section id="problems"><h2>Failed specimens</h2>{_problems(content)}</section>\n'
        + VIEWER
        + _json_script("report-data", _data(content))
        + "\n"
        + meshes
        + "\n<script>"
        + SCRIPT.replace("%UNPACK%", UNPACK_JS)
        + "</script>\n</body>\n</html>\n"
    )
