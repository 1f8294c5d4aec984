"""The report's HTML: one self-contained page, plotly's JavaScript inlined once.

Sections: a summary with the colour scale; the table of specimens (one row
each: thumbnail, group, metrics, status, error), sorted by clicking a header
and filtered by text, group and status in a few lines of plain JavaScript; the
per-group distributions of each metric (box plots with every point) and a
scatter matrix of the metrics coloured by group (plotly); the specimens that
failed or have no picture, with why.  A click on a thumbnail, a name or a
plotted point opens that specimen's 3D view, unpacked from its payload only
then (``_payload``; the browser's ``DecompressionStream``); ``#view=N`` in the
address opens specimen N, numbered from 1 as in the table's ``#`` column (a
number past the table's end says so in the viewer).

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
characters, not as a link.
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
from ._collect import METRIC_LABELS, Specimen
from ._payload import COLOR_STEPS

#: Short names of the metrics for the scatter matrix's axes, where ten of them share the width.
SHORT_LABELS = {
    "dne": "aDNE",
    "positive_dne": "aDNE+",
    "negative_dne": "aDNE\u2212",
    "classic_dne": "cDNE",
    "classic_convex_dne": "cDNE+",
    "classic_concave_dne": "cDNE\u2212",
    "rfi": "RFI",
    "opcr": "OPCR",
    "opc": "OPC",
    "slope": "slope",
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
    metrics : list of str
        The metric columns shown and plotted.
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
    metrics: Sequence[str]
    groups: Sequence[str]
    scale: ColorScale
    thumbnails: dict
    payloads: dict
    plotly_js: str
    notes: list = field(default_factory=list)
    protocols: list = field(default_factory=list)


def plural(count: int, noun: str) -> str:
    """``"1 group"``, ``"2 groups"``."""
    return f"{count} {noun}{'' if count == 1 else 's'}"


def _number(value) -> float | None:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    return float(value) if math.isfinite(value) else None


def _cell(value) -> str:
    """A table cell of a number: short text, the full value to sort by."""
    number = _number(value)
    if number is None:
        return '<td class="num" data-v=""></td>'
    text = str(int(number)) if isinstance(value, int) else f"{number:.4g}"
    return f'<td class="num" data-v="{number!r}">{text}</td>'


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


def _data(content: PageContent) -> dict:
    group_index = {name: i for i, name in enumerate(content.groups)}
    specimens = []
    for s in content.specimens:
        specimens.append(
            {
                "index": s.index,
                "name": s.name,
                "group": group_index[s.group],
                "status": s.status,
                "values": [_number(s.record.get(key)) for key in content.metrics],
                "problem": s.problem,
            }
        )
    meshes = {
        str(i): {k: v for k, v in payload.items() if k != "data"}
        for i, payload in content.payloads.items()
    }
    return {
        "metrics": [
            {"key": k, "label": METRIC_LABELS.get(k, k), "short": SHORT_LABELS.get(k, k)}
            for k in content.metrics
        ],
        "groups": list(content.groups),
        "colors": [GROUP_COLORS[i % len(GROUP_COLORS)] for i in range(len(content.groups))],
        "specimens": specimens,
        "meshes": meshes,
        "limit": content.scale.limit,
        "steps": COLOR_STEPS,
        "colorscale": colorscale(),
        "rule": content.scale.rule,
    }


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
    # status and error next to the name, where a wide table cannot scroll them out of sight;
    # a long error is cut to three lines here (all of it on hover and under "Failed specimens")
    error = f'<div class="error" title="{errors}">{errors}</div>' if errors else ""
    cells = [
        f'<td class="num" data-v="{s.index + 1}">{s.index + 1}</td>',
        f'<td class="pic">{picture}</td>',
        f'<td data-v="{esc(s.name.lower())}">{label}</td>',
        f"<td>{esc(s.group)}</td>",
        f'<td class="status-cell" data-v="{esc(s.status)}"><span class="status '
        f'{esc(s.status)}">{esc(s.status)}</span>{error}</td>',
        *(_cell(s.record.get(key)) for key in content.metrics),
        _cell(s.record.get("vertices")),
    ]
    return (
        f'<tr data-index="{s.index}" data-group="{esc(s.group)}" data-status="{esc(s.status)}">'
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


def _summary(content: PageContent) -> str:
    counts = {}
    for s in content.specimens:
        counts[s.status] = counts.get(s.status, 0) + 1
    statuses = ", ".join(f"{n} {status}" for status, n in sorted(counts.items()))
    specimens = plural(len(content.specimens), "specimen")
    lines = [
        f"{specimens} in {plural(len(content.groups), 'group')} "
        f"({statuses}), from {html.escape(content.source)}.",
        "Pictures: signed local curvature (ariaDNE, each row's settings), one colour scale "
        f"for the whole collection, {html.escape(content.scale.rule)}: "
        "blue \u2212 concave, red + convex. Click a picture, a name or a plotted point "
        "for the specimen's 3D view.",
        *(html.escape(note) for note in content.notes),
    ]
    return "".join(f"<p>{line}</p>" for line in lines) + _protocols(content)


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


def render_page(content: PageContent) -> str:
    """The whole page as text."""
    esc = html.escape
    headers = [
        '<th data-sort="num">#</th>',
        '<th class="pic">map</th>',
        '<th data-sort="text">specimen</th>',
        '<th data-sort="text">group</th>',
        '<th data-sort="text" class="status-cell">status, error</th>',
        *(
            f'<th data-sort="num" class="metric" title="{esc(key)}">'
            f"{esc(METRIC_LABELS.get(key, key))}</th>"
            for key in content.metrics
        ),
        '<th data-sort="num">vertices</th>',
    ]
    rows = "\n".join(_row(s, content) for s in content.specimens)
    statuses = sorted({s.status for s in content.specimens})
    plots = "".join(
        f'<div class="group-plot" id="box-{esc(key)}" data-metric="{esc(key)}"></div>'
        for key in content.metrics
    )
    if len(content.metrics) >= 2:
        boxes = "".join(
            f'<label><input type="checkbox" value="{m}" checked> '
            f"{esc(SHORT_LABELS.get(key, key))}</label>"
            for m, key in enumerate(content.metrics)
        )
        names = "; ".join(
            f"{esc(SHORT_LABELS[key])}: {esc(METRIC_LABELS.get(key, key))}"
            for key in content.metrics
            if key in SHORT_LABELS and SHORT_LABELS[key] != METRIC_LABELS.get(key, key)
        )
        splom = (
            f'<div id="splom-metrics" class="controls">plotted: {boxes}</div>'
            + (f'<p class="legend">{names}.</p>' if names else "")
            + '<div id="splom" class="splom"></div>'
        )
    else:
        splom = "<p>A scatter matrix needs two metric columns or more.</p>"
    meshes = "\n".join(
        f'<script type="application/octet-stream" id="mesh-{i}">{payload["data"]}</script>'
        for i, payload in content.payloads.items()
    )
    return (
        _HEAD.replace("%CSP%", _CSP)
        .replace("%GRADIENT%", _gradient())
        .replace("%TITLE%", esc(content.title))  # last: a title's "%CSP%" stays as it is
        + "<script>"
        + content.plotly_js
        + "</script>\n</head>\n<body>\n"
        + f"<header><h1>{esc(content.title)}</h1>{_summary(content)}"
        + f'<div class="bar"><span>\u2212{content.scale.limit:.4g}</span><span class="gradient">'
        + f"</span><span>+{content.scale.limit:.4g}</span></div></header>\n"
        + '<nav><a href="#specimens">specimens</a> <a href="#groups">groups</a> '
        + '<a href="#problems">failed</a></nav>\n'
        + '<section id="specimens"><h2>Specimens</h2><div class="controls">'
        + '<input id="filter" type="search" placeholder="filter: name, group, status, error">'
        + '<select id="group-filter"><option value="">all groups</option>'
        + f"{_options(content.groups)}</select>"
        + '<select id="status-filter"><option value="">any status</option>'
        + f'{_options(statuses)}</select><span id="shown"></span></div>\n'
        + f'<table id="specimen-table"><thead><tr>{"".join(headers)}</tr></thead>\n<tbody>\n'
        + rows
        + "\n</tbody></table></section>\n"
        + '<section id="groups"><h2>Groups</h2>'
        + "<p>Each metric by group: a box (quartiles, median, whiskers to 1.5 IQR) over every "
        + "specimen's point.</p>"
        + f'<div class="plots">{plots}</div><h3>Scatter matrix</h3>{splom}</section>\n'
        + f'<section id="problems"><h2>Failed specimens</h2>{_problems(content)}</section>\n'
        + _VIEWER
        + _json_script("report-data", _data(content))
        + "\n"
        + meshes
        + "\n<script>"
        + _SCRIPT.replace("%UNPACK%", UNPACK_JS)
        + "</script>\n</body>\n</html>\n"
    )


_HEAD = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta http-equiv="Content-Security-Policy" content="%CSP%">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>%TITLE%</title>
<style>
body { margin: 0 auto; max-width: 1500px; padding: 0 16px 40px; color: #111; background: #fff;
  font: 14px system-ui, sans-serif; }
h1 { font-size: 22px; margin: 16px 0 4px; } h2 { margin-top: 28px; } p { margin: 4px 0; }
nav a { margin-right: 12px; }
.bar { display: flex; align-items: center; gap: 6px; margin: 6px 0 10px; font-size: 12px; }
.bar .gradient { display: inline-block; width: 240px; height: 12px; background: %GRADIENT%; }
.controls { display: flex; gap: 8px; align-items: center; margin-bottom: 8px; }
.controls input[type="search"] { width: 320px; padding: 4px; }
table { border-collapse: collapse; width: 100%; }
th, td { border-bottom: 1px solid #ddd; padding: 2px 6px; text-align: left; }
th { position: sticky; top: 0; background: #f4f4f4; z-index: 1; }
th[data-sort] { cursor: pointer; user-select: none; white-space: nowrap; }
th[data-dir="asc"]::after { content: " \\25B2"; } th[data-dir="desc"]::after { content: " \\25BC"; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
td.pic { padding: 1px; width: 84px; }
img.thumb { width: 80px; height: 80px; display: block; }
button.open { border: 0; padding: 0; background: none; cursor: pointer; }
button.link { color: #1a55b0; text-decoration: underline; font: inherit; text-align: left; }
.nothumb { color: #888; font-size: 12px; }
.status.error { color: #b00020; font-weight: 600; }
.status.partial { color: #a06000; font-weight: 600; }
td.status-cell { min-width: 60px; max-width: 260px; }
td.status-cell .error { color: #b00020; font-size: 12px; display: -webkit-box;
  -webkit-line-clamp: 3; -webkit-box-orient: vertical; overflow: hidden; }
th.metric { white-space: normal; min-width: 48px; }
#splom-metrics { flex-wrap: wrap; } #splom-metrics label { white-space: nowrap; }
p.legend { color: #555; font-size: 12px; }
.plots { display: grid; grid-template-columns: repeat(auto-fill, minmax(420px, 1fr)); gap: 8px; }
.group-plot { height: 340px; } .splom { min-height: 300px; }
#problem-list .path { color: #666; font-size: 12px; }
#problem-list .error { color: #b00020; }
#viewer { position: fixed; inset: 0; background: rgba(0,0,0,0.45); z-index: 10;
  display: flex; align-items: center; justify-content: center; }
#viewer[hidden] { display: none; }
.viewer-box { background: #fff; width: min(1100px, 94vw); height: min(820px, 90vh);
  display: flex; flex-direction: column; border-radius: 6px; overflow: hidden; }
.viewer-head { display: flex; justify-content: space-between; align-items: center;
  padding: 6px 10px; border-bottom: 1px solid #ddd; }
#viewer-plot { flex: 1; min-height: 0; }
#viewer-message { padding: 20px; color: #b00020; }
</style>
<script>
window.reportErrors = [];
window.addEventListener("error", (e) => window.reportErrors.push(String(e.message || e)));
window.addEventListener("unhandledrejection", (e) => window.reportErrors.push(String(e.reason)));
(function () {
  const original = console.error;
  console.error = function (...args) {
    window.reportErrors.push(args.map(String).join(" "));
    original.apply(console, args);
  };
})();
</script>
"""

_VIEWER = """<div id="viewer" hidden><div class="viewer-box" role="dialog" aria-modal="true">
<div class="viewer-head"><b id="viewer-title"></b><button type="button" id="viewer-close">
close (Esc)</button></div><div id="viewer-message" hidden></div><div id="viewer-plot"></div>
</div></div>
<div id="report-status" hidden data-ready="no" data-thumbnails="" data-errors="" data-layout="">
</div>
"""

#: The page's unpacking of :func:`._payload.pack_mesh` payloads (``unpackPayload(meta, text)``):
#: the report inlines it, the app serves it as ``/static/viewer.js``.
UNPACK_JS = r"""
async function inflate(text) {
  const binary = atob(text.trim());
  const bytes = new Uint8Array(binary.length);
  for (let i = 0; i < binary.length; i++) bytes[i] = binary.charCodeAt(i);
  const stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream("deflate"));
  return new Uint8Array(await new Response(stream).arrayBuffer());
}

function words(bytes, offset, count, size) {
  const out = new Uint32Array(count);
  for (let b = 0; b < size; b++) {
    const base = offset + b * count, factor = 2 ** (8 * b);
    for (let i = 0; i < count; i++) out[i] += bytes[base + i] * factor;
  }
  return out;
}

function undo(codes, start, count, bits) {  // zigzag deltas -> values, wrapping at 2**bits
  const out = new Float64Array(count);
  const modulus = 2 ** bits;
  let value = 0;
  for (let i = 0; i < count; i++) {
    const z = codes[start + i];
    const delta = z % 2 ? -(z + 1) / 2 : z / 2;
    value = (value + delta) % modulus;
    if (value < 0) value += modulus;
    out[i] = value;
  }
  return out;
}

// A payload of _payload.pack_mesh (its "data" text given apart): coordinates, faces, colours.
async function unpackPayload(meta, text) {
  const bytes = await inflate(text === undefined ? meta.data : text);
  const n = meta.n, m = meta.m, size = meta.wide ? 4 : 2;
  const coords = words(bytes, 0, 3 * n, 2);
  const xyz = [0, 1, 2].map((c) => {
    const q = undo(coords, c * n, n, 16);
    return Array.from(q, (v) => meta.low[c] + (v / 65535) * meta.extent);
  });
  const faces = undo(words(bytes, 6 * n, 3 * m, size), 0, 3 * m, 8 * size);
  const ijk = [0, 1, 2].map((c) => Array.from({ length: m }, (_, f) => faces[3 * f + c]));
  return { xyz, ijk, colors: bytes.subarray(6 * n + 3 * m * size) };
}
"""

_SCRIPT = r"""
"use strict";
const D = JSON.parse(document.getElementById("report-data").textContent);
const table = document.getElementById("specimen-table");
const tbody = table.tBodies[0];
const status = document.getElementById("report-status");
const PLOT_CONFIG = { displaylogo: false, responsive: true };

function sortBy(th) {
  const col = th.cellIndex;
  const numeric = th.dataset.sort === "num";
  const dir = th.dataset.dir === "asc" ? "desc" : "asc";
  for (const other of table.tHead.rows[0].cells) delete other.dataset.dir;
  th.dataset.dir = dir;
  const sign = dir === "asc" ? 1 : -1;
  const key = (row) => {
    const cell = row.cells[col];
    const v = cell.dataset.v !== undefined ? cell.dataset.v : cell.textContent.toLowerCase();
    return numeric ? (v === "" ? null : Number(v)) : v;
  };
  const rows = Array.from(tbody.rows, (row) => [key(row), row]);
  rows.sort((a, b) => {
    if (a[0] === b[0]) return 0;
    if (a[0] === null) return 1;  // missing values last, either way
    if (b[0] === null) return -1;
    return a[0] < b[0] ? -sign : sign;
  });
  tbody.append(...rows.map((pair) => pair[1]));
}
for (const th of table.tHead.rows[0].cells) {
  if (th.dataset.sort) th.addEventListener("click", () => sortBy(th));
}

const filter = document.getElementById("filter");
const groupFilter = document.getElementById("group-filter");
const statusFilter = document.getElementById("status-filter");
function applyFilter() {
  const text = filter.value.trim().toLowerCase();
  let shown = 0;
  for (const row of tbody.rows) {
    const keep = (!text || row.textContent.toLowerCase().includes(text))
      && (!groupFilter.value || row.dataset.group === groupFilter.value)
      && (!statusFilter.value || row.dataset.status === statusFilter.value);
    row.hidden = !keep;
    shown += keep;
  }
  document.getElementById("shown").textContent = shown + " of " + tbody.rows.length + " shown";
}
filter.addEventListener("input", applyFilter);
groupFilter.addEventListener("change", applyFilter);
statusFilter.addEventListener("change", applyFilter);
applyFilter();

// plotly reads some HTML in the texts it draws (<a href>, <b>, <br>, &amp; ...): names,
// groups and labels are text, so their &, < and > are given to it as entities.
function plain(text) {
  return String(text).replace(/&/g, "&amp;").replace(/</g, "&lt;").replace(/>/g, "&gt;");
}

function groupRows(g, m) {
  return D.specimens.filter((s) => s.group === g && s.values[m] !== null);
}

function drawGroups() {
  D.metrics.forEach((metric, m) => {
    const div = document.getElementById("box-" + metric.key);
    const traces = D.groups.map((name, g) => {
      const rows = groupRows(g, m);
      return {
        type: "box", name: plain(name), y: rows.map((s) => s.values[m]),
        text: rows.map((s) => plain(s.name)), customdata: rows.map((s) => s.index),
        boxpoints: "all", jitter: 0.45, pointpos: 0,
        marker: { color: D.colors[g], size: 5, opacity: 0.8 },
        line: { color: D.colors[g] }, fillcolor: "rgba(0,0,0,0)",
        // the name through a variable: a "%{...}" in it is text, not part of the template
        hovertemplate: "%{text}<br>%{y:.4g}<extra>%{fullData.name}</extra>",
      };
    });
    Plotly.newPlot(div, traces, {
      title: { text: plain(metric.label), x: 0.01, xanchor: "left" }, showlegend: false,
      height: 340,
      margin: { l: 60, r: 10, t: 40, b: 60 },
    }, PLOT_CONFIG);
    div.on("plotly_click", pickPoint);
  });
  drawSplom();
  const chooser = document.getElementById("splom-metrics");
  if (chooser) chooser.addEventListener("change", drawSplom);
}

// The scatter matrix of the metrics ticked above it, on their short names (ten full names
// would overlap); its height grows with the number of metrics, its cells kept near square.
function drawSplom() {
  const splom = document.getElementById("splom");
  if (!splom) return;
  const chosen = Array.from(
    document.querySelectorAll("#splom-metrics input:checked"), (box) => Number(box.value));
  Plotly.purge(splom);
  splom.dataset.metrics = String(chosen.length);
  if (chosen.length < 2) {
    splom.textContent = "Tick two metrics or more for a scatter matrix.";
    return;
  }
  splom.textContent = "";
  const traces = D.groups.map((name, g) => {
    const rows = D.specimens.filter((s) => s.group === g);
    return {
      type: "splom", name: plain(name),
      dimensions: chosen.map((m) => ({
        label: plain(D.metrics[m].short), values: rows.map((s) => s.values[m]),
      })),
      text: rows.map((s) => plain(s.name)), customdata: rows.map((s) => s.index),
      marker: { color: D.colors[g], size: 5, opacity: 0.8 },
      diagonal: { visible: false }, showupperhalf: false,
      hovertemplate: "%{text}<extra>%{fullData.name}</extra>",
    };
  });
  const height = Math.max(320, Math.min(900, 110 * (chosen.length - 1) + 90));
  Plotly.newPlot(splom, traces, {
    height: height, dragmode: "select", legend: { title: { text: "group" } },
    margin: { l: 70, r: 10, t: 30, b: 70 },
  }, PLOT_CONFIG);
  splom.on("plotly_click", pickPoint);
}

function pickPoint(event) {
  const point = event && event.points && event.points[0];
  if (point && point.customdata !== undefined) openViewer(point.customdata);
}

%UNPACK%
async function unpack(index) {
  const text = document.getElementById("mesh-" + index).textContent;
  const mesh = await unpackPayload(D.meshes[index], text);
  const half = (D.steps - 1) / 2;
  const intensity = Array.from(mesh.colors, (k) => ((k - half) / half) * D.limit);
  return { xyz: mesh.xyz, ijk: mesh.ijk, intensity };
}

const viewer = document.getElementById("viewer");
const viewerPlot = document.getElementById("viewer-plot");
const viewerMessage = document.getElementById("viewer-message");
function showMessage(title, text) {
  document.getElementById("viewer-title").textContent = title;
  viewer.hidden = false;
  Plotly.purge(viewerPlot);
  viewerMessage.hidden = false;
  viewerMessage.textContent = text;
  delete viewer.dataset.shown;
}
async function openViewer(index) {
  const specimen = D.specimens.find((s) => s.index === Number(index));
  if (!specimen) return;
  document.getElementById("viewer-title").textContent = specimen.name + " ("
    + D.groups[specimen.group] + "); colours " + D.rule + ", blue \u2212 concave, red + convex";
  viewer.hidden = false;
  Plotly.purge(viewerPlot);
  if (!D.meshes[specimen.index]) {
    viewerMessage.hidden = false;
    viewerMessage.textContent = "No 3D view: " + (specimen.problem || specimen.status);
    return;
  }
  viewerMessage.hidden = true;
  const mesh = await unpack(specimen.index);
  await Plotly.newPlot(viewerPlot, [{
    type: "mesh3d", x: mesh.xyz[0], y: mesh.xyz[1], z: mesh.xyz[2],
    i: mesh.ijk[0], j: mesh.ijk[1], k: mesh.ijk[2],
    intensity: mesh.intensity, intensitymode: "vertex", colorscale: D.colorscale,
    cmin: -D.limit, cmax: D.limit, hoverinfo: "skip",
    colorbar: { title: { text: "local curvature", side: "right" }, len: 0.9, y: 0.45 },
    lighting: { ambient: 0.45, diffuse: 0.7, specular: 0.05, roughness: 0.9, fresnel: 0 },
  }], {
    margin: { l: 0, r: 0, t: 36, b: 0 },  // the toolbar sits in the top margin, not on the bar
    scene: {
      aspectmode: "data",
      xaxis: { visible: false }, yaxis: { visible: false }, zaxis: { visible: false },
      camera: { eye: { x: 0, y: 0, z: 1.8 }, up: { x: 0, y: 1, z: 0 } },
    },
  }, PLOT_CONFIG);
  viewer.dataset.shown = String(specimen.index + 1);  // its number in the table
}

// #view=N opens specimen N, numbered as in the table's "#" column (from 1).
async function openFromAddress() {
  const wanted = /^#view=(.*)$/.exec(location.hash);
  if (!wanted) return;
  const count = D.specimens.length;
  const number = /^\d+$/.test(wanted[1]) ? Number(wanted[1]) : NaN;
  if (!(number >= 1 && number <= count)) {
    const range = count ? "#view=1 to #view=" + count : "no specimens";
    showMessage("#view=" + wanted[1], "No specimen " + wanted[1] + ": the table has "
      + count + " (" + range + ", numbered as in its # column).");
    return;
  }
  const button = tbody.querySelector('button.open[data-index="' + (number - 1) + '"]');
  if (button) button.click(); else await openViewer(number - 1);
}
window.addEventListener("hashchange", () => {
  openFromAddress().catch((error) => window.reportErrors.push(String(error)));
});
function closeViewer() {
  viewer.hidden = true;
  Plotly.purge(viewerPlot);
  delete viewer.dataset.shown;
}
document.getElementById("viewer-close").addEventListener("click", closeViewer);
viewer.addEventListener("click", (e) => { if (e.target === viewer) closeViewer(); });
document.addEventListener("keydown", (e) => { if (e.key === "Escape") closeViewer(); });
tbody.addEventListener("click", (e) => {
  const button = e.target.closest("button.open");
  if (button) openViewer(button.dataset.index);
});

function report() {
  const images = Array.from(document.querySelectorAll("img.thumb"));
  const decoded = images.filter((img) => img.complete && img.naturalWidth > 0).length;
  status.dataset.thumbnails = decoded + "/" + images.length;
  status.dataset.errors = window.reportErrors.join(" | ");
  status.dataset.layout = layoutProblems().join(" | ");
}

// What a reader could not see: a status or error column past the window's right edge, axis
// titles of the scatter matrix over each other, the 3D view's toolbar over its colour bar.
function overlap(a, b) {
  return a.left < b.right && b.left < a.right && a.top < b.bottom && b.top < a.bottom;
}
function layoutProblems() {
  const problems = [];
  const width = document.documentElement.clientWidth;
  const head = table.tHead.rows[0].querySelector("th.status-cell");
  if (head && head.getBoundingClientRect().right > width) {
    problems.push("status column out of view");
  }
  if (document.documentElement.scrollWidth > width + 1) problems.push("page wider than the window");
  const titles = Array.from(
    document.querySelectorAll('#splom g[class^="g-x"][class$="title"] text, '
      + '#splom g[class^="g-y"][class$="title"] text'),
    (text) => text.getBoundingClientRect()).filter((box) => box.width > 0);
  if (titles.some((a, i) => titles.some((b, j) => j > i && overlap(a, b)))) {
    problems.push("scatter matrix titles overlap");
  }
  const bar = viewerPlot.querySelector(".colorbar");
  const tools = viewerPlot.querySelector(".modebar");
  if (bar && tools && overlap(bar.getBoundingClientRect(), tools.getBoundingClientRect())) {
    problems.push("toolbar over the colour bar");
  }
  return problems;
}
window.addEventListener("load", async () => {
  try {
    drawGroups();
    await openFromAddress();
  } catch (error) {
    window.reportErrors.push(String(error));
  }
  status.dataset.ready = "yes";
  report();
  setInterval(report, 250);
});
"""
