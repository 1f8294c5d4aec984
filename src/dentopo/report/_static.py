"""The report page's static text: its head (styles, the error hook), the viewer, its scripts.

``HEAD`` (with ``%CSP%``, ``%GRADIENT%`` and ``%TITLE%`` to fill), ``VIEWER`` (the 3D
view's dialog and the status element the checks read), ``UNPACK_JS`` (the unpacking of
:func:`._payload.pack_mesh` payloads, shared with the app) and ``SCRIPT`` (the table's
sorting, filtering and column views, the plots, the viewer, the layout checks; ``%UNPACK%``
to fill).  :mod:`._page` puts them together with the content.
"""

HEAD = """<!DOCTYPE html>
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
.controls { flex-wrap: wrap; }
.controls input[type="search"] { width: 320px; padding: 4px; }
.table-wrap { overflow: auto; max-height: 85vh; border: 1px solid #e4e4e4; }
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
td.status-cell .warn { color: #7a5200; font-size: 12px; display: -webkit-box;
  -webkit-line-clamp: 2; -webkit-box-orient: vertical; overflow: hidden; }
th.metric { white-space: normal; min-width: 48px; vertical-align: bottom; }
th .fam { display: block; font-weight: normal; font-size: 11px; color: #777; }
td.asis { background: #fbe6c6; }
td.name, th.name { position: sticky; left: 0; }  /* the name stays while the columns scroll */
td.name { background: #fff; z-index: 1; } th.name { z-index: 2; }
.mark { font-size: 11px; padding: 0 4px; border-radius: 3px; white-space: nowrap; }
.mark.closed { background: #fbe6c6; color: #6b3a00; border: 1px solid #d9a05b; }
.mark.turned { background: #e1eaf5; color: #1d4a80; border: 1px solid #a4bbd8; }
ul.marks { margin: 4px 0; padding-left: 20px; } ul.marks li { margin: 2px 0; }
details summary { cursor: pointer; } details.settings p { font-size: 13px; color: #333; }
.chooser { margin-bottom: 8px; } .chooser div { margin: 2px 0; }
.chooser label { white-space: nowrap; margin-right: 8px; }
p.legend, p.empty, p.families { color: #555; font-size: 12px; }
p.families a { margin: 0 2px; } h3 { margin: 18px 0 4px; }
.plots { display: grid; grid-template-columns: repeat(auto-fill, minmax(330px, 1fr)); gap: 8px; }
.group-figure { margin: 0; } .group-plot { height: 260px; }
.group-figure figcaption { font-weight: 600; font-size: 13px; padding-left: 8px;
  overflow-wrap: anywhere; } .splom { min-height: 300px; }
#problem-list .path { color: #666; font-size: 12px; }
#problem-list .error { color: #b00020; }
#warning-list li { margin: 3px 0; } #warning-list .warn { color: #7a5200; }
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

VIEWER = """<div id="viewer" hidden><div class="viewer-box" role="dialog" aria-modal="true">
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

SCRIPT = r"""
"use strict";
const D = JSON.parse(document.getElementById("report-data").textContent);
const table = document.getElementById("specimen-table");
const tbody = table.tBodies[0];
const status = document.getElementById("report-status");
const PLOT_CONFIG = { displaylogo: false, responsive: true };
// the box plots' toolbar: a picture, zoom, pan, reset (dozens of plots: the fewer the better)
const BOX_CONFIG = Object.assign({
  modeBarButtonsToRemove: ["select2d", "lasso2d", "zoomIn2d", "zoomOut2d", "autoScale2d",
    "hoverClosestCartesian", "hoverCompareCartesian", "toggleSpikelines"],
}, PLOT_CONFIG);

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
const markFilter = document.getElementById("mark-filter");
function applyFilter() {
  const text = filter.value.trim().toLowerCase();
  let shown = 0;
  for (const row of tbody.rows) {
    const keep = (!text || row.textContent.toLowerCase().includes(text))
      && (!groupFilter.value || row.dataset.group === groupFilter.value)
      && (!statusFilter.value || row.dataset.status === statusFilter.value)
      && (!markFilter.value || (row.dataset.mark || "none") === markFilter.value);
    row.hidden = !keep;
    shown += keep;
  }
  document.getElementById("shown").textContent = shown + " of " + tbody.rows.length + " shown";
}
filter.addEventListener("input", applyFilter);
groupFilter.addEventListener("change", applyFilter);
statusFilter.addEventListener("change", applyFilter);
markFilter.addEventListener("change", applyFilter);
applyFilter();

// The table's columns: the key metrics, one family, or all (a rule hiding the others).
const columnView = document.getElementById("column-view");
const columnStyle = document.getElementById("column-view-style");
function showColumns() {
  const view = columnView.value;
  const shown = view === "key" ? "k" : view;
  columnStyle.textContent = view === "all" ? ""
    : "#specimen-table .m:not(." + shown + ") { display: none; }";
}
columnView.addEventListener("change", showColumns);

// plotly reads some HTML in the texts it draws (<a href>, <b>, <br>, &amp; ...): names,
// groups and labels are text, so their &, < and > are given to it as entities.
function plain(text) {
  return String(text).replace(/&/g, "&amp;").replace(/</g, "&lt;").replace(/>/g, "&gt;");
}

function groupRows(g, m) {
  return D.specimens.filter((s) => s.group === g && s.values[m] !== null);
}

// A group's points spread across its box, the same way on every plot (golden-ratio steps).
function spread(k, n) {
  return n < 2 ? 0 : (((k * 0.618034) % 1) - 0.5) * 0.5;
}

const CLOSED = "x";  // a closed surface's point: measured as it lies
function drawBox(m) {
  const metric = D.metrics[m];
  const div = document.getElementById("box-" + metric.key);
  if (!div || div.dataset.drawn) return;
  div.dataset.drawn = "yes";
  const traces = [];
  D.groups.forEach((name, g) => {
    const rows = groupRows(g, m);
    const y = rows.map((s) => s.values[m]);
    traces.push({
      type: "box", orientation: "v", name: plain(name), x: rows.map(() => g), y: y,
      boxpoints: false, width: 0.6, line: { color: D.colors[g] }, fillcolor: "rgba(0,0,0,0)",
    });
    traces.push({
      type: "scatter", mode: "markers", name: plain(name), y: y,
      x: rows.map((s, k) => g + spread(k, rows.length)),
      text: rows.map((s) => plain(s.name) + (s.mark === "closed" ? " (closed)" : "")),
      customdata: rows.map((s) => s.index),
      marker: {
        color: D.colors[g], opacity: 0.85,
        size: rows.map((s) => (s.mark === "closed" ? 9 : 6)),
        symbol: rows.map((s) => (s.mark === "closed" ? CLOSED : "circle")),
      },
      // the name through a variable: a "%{...}" in it is text, not part of the template
      hovertemplate: "%{text}<br>%{y:.4g}<extra>%{fullData.name}</extra>",
    });
  });
  Plotly.newPlot(div, traces, {  // its title is the figure's caption, clear of the toolbar
    showlegend: false, height: 260,
    margin: { l: 56, r: 10, t: 26, b: 50 },
    xaxis: {
      tickmode: "array", tickvals: D.groups.map((_, g) => g), ticktext: D.groups.map(plain),
      range: [-0.5, D.groups.length - 0.5], showgrid: false, zeroline: false,
    },
    yaxis: { zeroline: false },
  }, BOX_CONFIG);
  div.on("plotly_click", pickPoint);
}

// Each metric's box plot; OPC's bins and rotations only when their fold is opened.
function drawGroups() {
  D.metrics.forEach((metric, m) => {
    if (!metric.detail) drawBox(m);
  });
  for (const fold of document.querySelectorAll("details.detail-plots")) {
    const draw = () => {
      if (!fold.open) return;
      for (const div of fold.querySelectorAll(".group-plot")) drawBox(Number(div.dataset.metric));
    };
    fold.addEventListener("toggle", draw);
    draw();  // open already (the browser kept it open)
  }
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
      text: rows.map((s) => plain(s.name) + (s.mark === "closed" ? " (closed)" : "")),
      customdata: rows.map((s) => s.index),
      marker: {
        color: D.colors[g], opacity: 0.8,
        size: rows.map((s) => (s.mark === "closed" ? 8 : 5)),
        symbol: rows.map((s) => (s.mark === "closed" ? CLOSED : "circle")),
      },
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
    + D.groups[specimen.group] + (specimen.mark ? "; " + specimen.mark : "") + "); colours "
    + D.rule + ", blue \u2212 concave, red + convex";
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
