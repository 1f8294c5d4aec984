// dentopo app: the page of `dentopo app FOLDER`.
//
// Plain JavaScript, no build step.  Every name that comes from the folder (files, groups, errors,
// warnings, log lines) is put into the page as text (textContent), never as HTML.  Every request
// is relative (/api/...); every POST sends JSON with the page's token in X-Dentopo-Token.
"use strict";

const statusBox = document.getElementById("app-status");
const pageErrors = [];
function noteError(text) {
  pageErrors.push(String(text));
  statusBox.dataset.errors = pageErrors.join(" | ");
}
window.addEventListener("error", (e) => noteError(e.message || e));
window.addEventListener("unhandledrejection", (e) => {
  const reason = e.reason;
  noteError(reason && reason.message ? reason.message : reason);
});
(function () {
  const original = console.error;
  console.error = function (...args) {
    noteError(args.map(String).join(" "));
    original.apply(console, args);
  };
})();

const TOKEN = document.querySelector('meta[name="dentopo-token"]').content;
const TOOTH = "#e8dcc4";
const REMOVED = "#d62728";
const MAP_METRICS = [
  ["curvature", "local curvature (ariaDNE)"],
  ["slope", "slope"],
  ["opc", "orientation (OPC)"],
  ["arc", "relief (ARC)"],
];
const PLOT_CONFIG = { displaylogo: false, responsive: true };

const $ = (id) => document.getElementById(id);

// ---------------------------------------------------------------------------------------------
// small helpers

/** An element with attributes/properties and children (strings become text nodes). */
function el(tag, props, ...children) {
  const node = document.createElement(tag);
  for (const [key, value] of Object.entries(props || {})) {
    if (value === undefined || value === null || value === false) continue;
    if (key === "className") node.className = value;
    else if (key === "text") node.textContent = value;
    else if (key.startsWith("data-")) node.setAttribute(key, String(value));
    else if (key in node) node[key] = value;
    else node.setAttribute(key, String(value));
  }
  for (const child of children) {
    if (child === null || child === undefined || child === false) continue;
    node.append(typeof child === "string" ? document.createTextNode(child) : child);
  }
  return node;
}

class ApiError extends Error {}

async function errorOf(response) {
  let text = "";
  try {
    const body = await response.json();
    text = body && body.error ? String(body.error) : JSON.stringify(body);
  } catch (_) {
    text = response.statusText || "";
  }
  return new ApiError(text || "the server answered " + response.status);
}

async function getJSON(path) {
  const response = await fetch(path, { credentials: "same-origin", cache: "no-store" });
  if (!response.ok) throw await errorOf(response);
  return response.json();
}

async function postJSON(path, body) {
  const response = await fetch(path, {
    method: "POST",
    credentials: "same-origin",
    cache: "no-store",
    headers: { "Content-Type": "application/json", "X-Dentopo-Token": TOKEN },
    body: JSON.stringify(body === undefined ? {} : body),
  });
  if (!response.ok) throw await errorOf(response);
  return response.json();
}

const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));
/** Resolves once the page is visible (at once if it is). */
const visible = () => new Promise((resolve) => {
  if (!document.hidden) { resolve(); return; }
  const seen = () => {
    if (document.hidden) return;
    document.removeEventListener("visibilitychange", seen);
    resolve();
  };
  document.addEventListener("visibilitychange", seen);
});

/** Show a message to the reader (an API error, or an error of the page). */
let messageTimer = 0;
function showMessage(text, info) {
  $("message-text").textContent = String(text);
  $("message").classList.toggle("info", Boolean(info));
  $("message").hidden = false;
  clearTimeout(messageTimer);
  if (info) messageTimer = setTimeout(() => { $("message").hidden = true; }, 5000);
}
$("message-close").addEventListener("click", () => { $("message").hidden = true; });

/** Run an action from a button: API errors are shown, other errors noted as page errors. */
function guarded(action) {
  return async (...args) => {
    try {
      await action(...args);
    } catch (error) {
      if (error instanceof ApiError) {
        showMessage(error.message);
      } else {
        showMessage(String(error && error.message ? error.message : error));
        noteError(error && error.stack ? error.stack : error);
      }
    }
  };
}

function humanBytes(bytes) {
  if (bytes === null || bytes === undefined) return "";
  if (bytes < 1024) return bytes + " B";
  if (bytes < 1024 * 1024) return (bytes / 1024).toFixed(1) + " KB";
  return (bytes / 1024 / 1024).toFixed(1) + " MB";
}

function count(n) {
  return n === null || n === undefined ? "?" : Number(n).toLocaleString("en");
}

function fixed3(v) {
  const x = Number(v);
  return (Math.abs(x) < 5e-4 ? 0 : x).toFixed(3);
}

/** Seconds to 2 significant digits ("0.012 s", "1.5 s", "12 s", "140 s"), never "0.0 s". */
function seconds(value) {
  const x = Number(value);
  if (!Number.isFinite(x)) return "";
  if (x <= 0) return "0 s";
  if (x < 0.001) return "< 0.001 s";
  return String(Number(x.toPrecision(2))) + " s";
}

/** The status as shown: "ok, warned" for a row measured with warnings. */
function statusWords(status, warnings) {
  return status === "ok" && warnings ? "ok, warned" : String(status);
}

/** The warnings, as text clamped to 3 lines (all of it in the title). */
function warningsBlock(warnings) {
  return el("div", { className: "cell-warnings", text: String(warnings), title: String(warnings) });
}

function formatNumber(value) {
  if (typeof value !== "number" || !Number.isFinite(value)) return String(value);
  if (Number.isInteger(value)) return String(value);
  const magnitude = Math.abs(value);
  if (magnitude !== 0 && (magnitude < 1e-3 || magnitude >= 1e6)) return value.toExponential(4);
  return String(Number(value.toPrecision(6)));
}

function fillSelect(select, values, labels) {
  const current = select.value;
  select.replaceChildren(...values.map((value) => el("option", {
    value: value === null ? "" : String(value), text: labels ? labels(value) : String(value),
  })));
  if (values.map((v) => (v === null ? "" : String(v))).includes(current)) select.value = current;
}

// ---------------------------------------------------------------------------------------------
// state

const app = {
  state: null,
  meshesKey: "",
  selected: null,        // the selected mesh's path
  base: null,            // the protocol the form started from
  cropTouched: false,    // the reader moved the crop slider (the crop is then crop_below)
  preview: null,         // the last preview answer
  oriented: null,        // its oriented mesh, unpacked
  prepared: null,        // its prepared mesh, unpacked
  showing: "",           // "oriented" | "prepared"
  cameras: { oriented: "occlusal", prepared: "occlusal" },  // each view's camera (CAMERAS)
  sideShown: false,      // the oriented view turned to the side once for this mesh's crop
  previewSerial: 0,
  run: null,
  runTimer: null,
  resultsKey: "",
  results: null,
  sort: null,            // {column, dir}
};

const DEFAULT_PROTOCOL = {
  name: "custom", clean: true, keep: "largest", orient: "occlusal", up: null, spin: "none",
  crop_below: null, crop_fraction: null, crop_plane: null, faces: null, decimate: "quadric",
  smooth: null, smooth_iterations: null, smooth_step: null, smooth_mu: null,
  smooth_pin_boundary: true,
};
const PROTOCOL_FIELDS = Object.keys(DEFAULT_PROTOCOL);

function choices(name, fallback) {
  const c = app.state && app.state.choices && app.state.choices[name];
  return Array.isArray(c) && c.length ? c : fallback;
}

// ---------------------------------------------------------------------------------------------
// header and meshes

function drawHeader(state) {
  $("folder").textContent = state.folder || "";
  $("output").textContent = state.output || "";
  $("version").textContent = state.version || "";
  $("table-path").textContent = state.table || "";
  const label = state.protocol_label || (state.protocol ? state.protocol.name : null);
  $("protocol-summary").textContent = state.protocol_error
    ? "The folder protocol cannot be used: " + state.protocol_error
    : state.protocol
      ? protocolWords(label || "custom", "Folder protocol") + " (used for every mesh without its own)."
      : "No folder protocol: the meshes are measured as read (unless a mesh has its own).";
  $("protocol-summary").classList.toggle("error", Boolean(state.protocol_error));
}

function meshByPath(path) {
  return app.state ? app.state.meshes.find((m) => m.path === path) : undefined;
}

const cards = new Map();  // path -> {card, key}: cards are kept (and updated) across polls

function drawMeshes(state) {
  $("meshes-pending").hidden = !state.pending;
  $("mesh-count").textContent = "(" + state.meshes.length + ")";
  const groups = new Map();
  for (const mesh of state.meshes) {
    if (!groups.has(mesh.group)) groups.set(mesh.group, []);
    groups.get(mesh.group).push(mesh);
  }
  const names = Array.from(groups.keys()).sort((a, b) => (a === "" ? -1 : b === "" ? 1 : a < b ? -1 : 1));
  for (const mesh of state.meshes) {
    const key = JSON.stringify(mesh);
    let entry = cards.get(mesh.path);
    if (!entry) {
      entry = { card: newCard(mesh.path), key: "" };
      cards.set(mesh.path, entry);
    }
    if (entry.key !== key) {
      fillCard(entry.card, mesh);
      entry.key = key;
    }
    entry.card.classList.toggle("selected", mesh.path === app.selected);
  }
  const layout = JSON.stringify(names.map((name) => [name, groups.get(name).map((m) => m.path)]));
  if (layout === app.meshesKey) return;
  app.meshesKey = layout;
  const present = new Set(state.meshes.map((m) => m.path));
  for (const path of Array.from(cards.keys())) if (!present.has(path)) cards.delete(path);
  const parts = [];
  if (!state.meshes.length) parts.push(el("p", { className: "muted", text: "No meshes in this folder." }));
  for (const name of names) {
    if (names.length > 1 || name !== "") {
      parts.push(el("h3", { className: "group-title", text: name === "" ? "(top folder)" : name }));
    }
    parts.push(el("div", { className: "cards" }, ...groups.get(name).map((m) => cards.get(m.path).card)));
  }
  $("meshes").replaceChildren(...parts);
  // the groups for the results' group filter ("\u0000top": the meshes at the top)
  const options = [""].concat(names.filter((n) => n !== ""));
  if (names.includes("") && names.length > 1) options.push("\u0000top");
  fillSelect($("group-filter"), options,
    (v) => (v === "" ? "all groups" : v === "\u0000top" ? "(top folder)" : v));
}

function newCard(path) {
  const card = el("div", { className: "card", tabIndex: 0, "data-path": path, title: path, role: "button" });
  card.addEventListener("click", () => selectMesh(path));
  card.addEventListener("keydown", (e) => {
    if (e.key === "Enter" || e.key === " ") { e.preventDefault(); selectMesh(path); }
  });
  return card;
}

function thumbnail(path) {
  const img = el("img", {
    className: "thumb", alt: "", loading: "lazy",
    src: "/api/thumbnail?path=" + encodeURIComponent(path),
  });
  img.addEventListener("error", () => {
    img.replaceWith(el("div", { className: "thumb", text: "no picture" }));
  }, { once: true });
  return img;
}

function fillCard(card, mesh) {
  const old = card.querySelector("img.thumb");
  const thumb = mesh.thumbnail
    ? old || thumbnail(mesh.path)
    : el("div", { className: "thumb", text: mesh.error ? "no picture" : "\u2026" });
  const size = [humanBytes(mesh.bytes)];
  if (mesh.vertices !== null && mesh.vertices !== undefined) size.push(count(mesh.vertices) + " vertices");
  if (mesh.faces !== null && mesh.faces !== undefined) size.push(count(mesh.faces) + " faces");
  // each part whole on its line ("· 5,000 faces" never split), the line may break between them
  const sizeParts = size.filter(Boolean).map((text, i) => el("span", { text: (i ? "\u00b7 " : "") + text }));
  const sizeLine = el("div", { className: "size" });
  sizeParts.forEach((part, i) => { if (i) sizeLine.append(" "); sizeLine.append(part); });
  const name = mesh.group && mesh.path.startsWith(mesh.group + "/") ? mesh.path.slice(mesh.group.length + 1) : mesh.path;
  card.replaceChildren(
    thumb,
    el("div", { className: "name", text: name }),
    sizeLine,
    ...(mesh.error ? [el("div", { className: "error", text: mesh.error })] : []),
    ...(mesh.protocol === "own" ? [el("span", { className: "badge", text: "own protocol" })] : []),
    ...(mesh.protocol_error ? [el("div", { className: "error", text: mesh.protocol_error })] : []));
  card.classList.toggle("unreadable", Boolean(mesh.error));
  if (mesh.path === app.selected) drawSelectedHeader();
}

// ---------------------------------------------------------------------------------------------
// prepare

function drawSelectedHeader() {
  const mesh = meshByPath(app.selected);
  if (!mesh) return;
  const own = mesh.protocol === "own";
  $("prepare-name").textContent = "\u2014 " + mesh.path + (own ? " (own protocol)" : "");
  $("remove-own").hidden = !own;
  $("download-own-protocol").hidden = !own;
  $("download-own-protocol").href = "/api/protocol.toml?path=" + encodeURIComponent(mesh.path);
  $("download-protocol").hidden = !(app.state && app.state.protocol);
}

function fillProtocolChoices() {
  fillSelect($("p-keep"), choices("keep", ["largest", "all"]));
  fillSelect($("p-orient"), choices("orient", ["occlusal", "none"]));
  fillSelect($("p-spin"), choices("spin", ["none", "footprint"]));
  fillSelect($("p-decimate"), choices("decimate", ["quadric"]));
  const smooth = choices("smooth", ["laplacian", "taubin", "hc", "implicit"]).filter((s) => s !== "none" && s !== null);
  fillSelect($("p-smooth"), [""].concat(smooth), (v) => (v === "" ? "none" : v));
}

function setForm(protocol) {
  const p = Object.assign({}, DEFAULT_PROTOCOL, protocol || {});
  app.base = p;
  app.cropTouched = false;
  $("p-clean").checked = Boolean(p.clean);
  $("p-keep").value = p.keep;
  $("p-orient").value = p.orient;
  $("p-spin").value = p.spin;
  const up = Array.isArray(p.up) ? p.up : [null, null, null];
  ["up-x", "up-y", "up-z"].forEach((id, i) => { $(id).value = up[i] === null ? "" : String(up[i]); });
  $("p-faces").value = p.faces === null ? "" : String(p.faces);
  $("p-decimate").value = p.decimate;
  $("p-smooth").value = p.smooth || "";
  $("p-smooth-iterations").value = p.smooth_iterations === null ? "" : String(p.smooth_iterations);
  $("crop").value = "0";
}

function readUp() {
  const values = ["up-x", "up-y", "up-z"].map((id) => $(id).value.trim());
  if (values.every((v) => v === "")) return null;
  const numbers = values.map((v) => (v === "" ? 0 : Number(v)));
  if (numbers.some((v) => !Number.isFinite(v))) throw new ApiError("up must be three numbers");
  if (numbers.every((v) => v === 0)) throw new ApiError("up must not be the zero vector");
  return numbers;
}

function optionalInt(id, name) {
  const text = $(id).value.trim();
  if (text === "") return null;
  const value = Number(text);
  if (!Number.isInteger(value)) throw new ApiError(name + " must be a whole number");
  return value;
}

/** The protocol the form describes (the base protocol with the form's fields). */
function readForm() {
  const p = {};
  for (const field of PROTOCOL_FIELDS) p[field] = app.base ? app.base[field] : DEFAULT_PROTOCOL[field];
  p.clean = $("p-clean").checked;
  p.keep = $("p-keep").value;
  p.orient = $("p-orient").value;
  p.spin = $("p-spin").value;
  p.up = readUp();
  if (p.orient === "none") { p.up = null; p.spin = "none"; }
  const height = cropHeight();
  if (app.cropTouched) {  // untouched, the protocol's own crop stays exactly as it was
    const range = Number($("crop").max) || 0;
    const share = $("crop-as-share").checked && height > 0 && range > 0;
    // as a share: keep the top (1 - H / height) of each crown (crop_fraction), whatever its size
    p.crop_below = height > 0 && !share ? height : null;
    p.crop_fraction = share ? Math.min(1, Math.max(1e-6, 1 - height / range)) : null;
    p.crop_plane = null;
  }
  p.faces = optionalInt("p-faces", "target faces");
  p.decimate = $("p-decimate").value || p.decimate;
  const smooth = $("p-smooth").value || null;
  if (smooth !== (app.base ? app.base.smooth : null)) { p.smooth_step = null; p.smooth_mu = null; }
  p.smooth = smooth;
  p.smooth_iterations = optionalInt("p-smooth-iterations", "iterations");
  if (smooth === null) {
    p.smooth_iterations = null; p.smooth_step = null; p.smooth_mu = null; p.smooth_pin_boundary = true;
  }
  if (app.base && app.base.name && app.base.name !== "custom" && changed(p, app.base)) p.name = "custom";
  return p;
}

function changed(a, b) {
  return PROTOCOL_FIELDS.some((f) => f !== "name" && JSON.stringify(a[f]) !== JSON.stringify(b[f]));
}

function cropHeight() {
  return Number($("crop").value) || 0;
}

// A protocol file as the app writes it (Protocol.to_toml): a table per step, `key = value` lines
// whose values are strings, numbers, booleans or arrays of numbers.  Its tables' keys -> fields.
const TOML_TABLES = {
  clean: { enabled: "clean", keep: "keep" },
  orient: { mode: "orient", up: "up", spin: "spin" },
  crop: { below: "crop_below", fraction: "crop_fraction", plane: "crop_plane" },
  decimate: { faces: "faces", method: "decimate" },
  smooth: {
    method: "smooth", iterations: "smooth_iterations", step: "smooth_step", mu: "smooth_mu",
    pin_boundary: "smooth_pin_boundary",
  },
};

function tomlValue(text) {
  let inString = false;
  for (let i = 0; i < text.length; i++) {  // cut a trailing comment (not a # inside a string)
    const ch = text[i];
    if (ch === "\\" && inString) { i++; continue; }
    if (ch === '"') inString = !inString;
    if (ch === "#" && !inString) { text = text.slice(0, i); break; }
  }
  return JSON.parse(text.trim());
}

/** The fields of a protocol file, or null if it is not in the form the app writes. */
function parseProtocol(text) {
  const protocol = Object.assign({}, DEFAULT_PROTOCOL);
  let table = "";
  for (const raw of text.split(/\r?\n/)) {
    const line = raw.trim();
    if (!line || line.startsWith("#")) continue;
    const header = /^\[([A-Za-z_]+)\]$/.exec(line);
    if (header) {
      if (!(header[1] in TOML_TABLES)) return null;
      table = header[1];
      continue;
    }
    const pair = /^([A-Za-z_]+)\s*=\s*(.+)$/.exec(line);
    if (!pair) return null;
    const value = tomlValue(pair[2]);
    if (!table) {
      if (pair[1] === "name") protocol.name = String(value);
      continue;  // description, source: not edited here
    }
    const field = TOML_TABLES[table][pair[1]];
    if (!field) return null;
    protocol[field] = value;
  }
  return protocol;
}

async function ownProtocol(path) {
  try {
    const response = await fetch("/api/protocol.toml?path=" + encodeURIComponent(path),
      { credentials: "same-origin", cache: "no-store" });
    if (!response.ok) return null;
    return parseProtocol(await response.text());
  } catch (_) {
    return null;  // the form then starts from the folder's protocol, and says so
  }
}

async function selectMesh(path) {
  const mesh = meshByPath(path);
  if (!mesh) return;
  app.selected = path;
  for (const card of document.querySelectorAll("#meshes .card")) {
    card.classList.toggle("selected", card.dataset.path === path);
  }
  $("prepare-hint").hidden = true;
  $("prepare-body").hidden = false;
  drawSelectedHeader();
  setForm(app.state.protocol);
  $("view-message").textContent = "";
  if (mesh.protocol === "own") {
    const own = await ownProtocol(path);
    if (path !== app.selected) return;
    if (own && !mesh.protocol_error) {
      setForm(own);
    } else {
      $("view-message").textContent = (mesh.protocol_error ? mesh.protocol_error + " " : "")
        + "This mesh has its own protocol (download it below); the form starts from the "
        + "folder's protocol.";
    }
  }
  app.preview = null; app.oriented = null; app.prepared = null;
  app.cameras = { oriented: "occlusal", prepared: "occlusal" };
  app.sideShown = false;
  $("steps").hidden = true;
  $("steps-stale").hidden = true;
  $("preview-label").textContent = "";
  $("preview-warnings").replaceChildren();
  $("found-up").textContent = "";
  $("found-up-note").hidden = true;
  if (mesh.error) {
    clearView("This mesh could not be read: " + mesh.error);
    return;
  }
  $("prepare-section").scrollIntoView({ block: "start" });
  await refreshPreview("oriented");
}

function clearView(text) {
  if (window.Plotly) Plotly.purge($("view"));
  app.showing = "";
  $("view-label").textContent = "";
  $("view-message").textContent = text || "";
  updateSwitch();
}

/** POST /api/preview with the form's protocol; then draw `show` ("oriented" or "prepared"). */
async function refreshPreview(show) {
  const path = app.selected;
  const serial = ++app.previewSerial;
  const protocol = readForm();
  $("preview").disabled = true;
  $("view-label").textContent = "preparing\u2026";
  let answer;
  try {
    answer = await postJSON("/api/preview", { path: path, protocol: protocol });
  } catch (error) {
    if (serial === app.previewSerial) {
      $("view-label").textContent = "";
      $("preview").disabled = false;
    }
    throw error;
  }
  if (serial !== app.previewSerial || path !== app.selected) return;  // a newer one is coming
  const [oriented, prepared] = await Promise.all([
    unpackPayload(answer.oriented), unpackPayload(answer.prepared),
  ]);
  if (serial !== app.previewSerial || path !== app.selected) return;
  $("preview").disabled = false;
  app.preview = answer; app.oriented = oriented; app.prepared = prepared;
  const up = answer.found_up;
  $("found-up").textContent = Array.isArray(up) ? up.map(fixed3).join(", ") : "\u2014";
  $("found-up-note").hidden = !Array.isArray(up) || Boolean(protocol.up);
  $("found-up-flipped").hidden = !(Array.isArray(up) && Number(up[2]) < -0.5);
  $("found-up-label").textContent = protocol.up ? "up used" : "found up";
  setupCrop(answer);
  drawSteps(answer);
  $("steps-stale").hidden = true;
  $("preview-label").textContent = answer.label
    ? protocolWords(answer.label) + " (names its parameters exactly)" : "";
  const warnings = (answer.warnings || []).map((w) => el("li", { text: String(w) }));
  $("preview-warnings").replaceChildren(...warnings);
  await drawView(show);
}

function setupCrop(answer) {
  const range = Math.max(0, Number(answer.z_max) - Number(answer.z_min));
  const slider = $("crop");
  const keep = cropHeight();
  slider.max = String(range);
  slider.step = range > 0 ? String(range / 500) : "any";
  let height = keep;
  const base = app.base || DEFAULT_PROTOCOL;
  if (!app.cropTouched && keep === 0) {
    if (base.crop_below !== null && base.crop_below !== undefined) height = Number(base.crop_below);
    const fraction = base.crop_fraction;
    if (fraction !== null && fraction !== undefined) height = (1 - Number(fraction)) * range;
    $("crop-as-share").checked = fraction !== null && fraction !== undefined;
  }
  slider.value = String(Math.min(height, range));
  const note = $("crop-note");
  if (!app.cropTouched && base.crop_fraction !== null && base.crop_fraction !== undefined) {
    note.hidden = false;
    note.textContent = "The protocol keeps the top " + Math.round(base.crop_fraction * 100)
      + "% of each crown's height.";
  } else if (!app.cropTouched && base.crop_plane) {
    note.hidden = false;
    note.textContent = "The protocol crops by a plane; moving the slider replaces it by a height.";
  } else {
    note.hidden = true;
  }
  updateCropText();
}

function cropColors() {
  const mesh = app.oriented;
  if (!mesh) return [];
  const limit = Number(app.preview.z_min) + cropHeight();
  const height = cropHeight();
  const zs = mesh.xyz[2];
  const colors = new Array(zs.length);
  let removed = 0;
  for (let i = 0; i < zs.length; i++) {
    const cut = height > 0 && zs[i] < limit;
    colors[i] = cut ? REMOVED : TOOTH;
    removed += cut;
  }
  return { colors, removed, total: zs.length };
}

function updateCropText() {
  const height = cropHeight();
  const range = Number($("crop").max) || 0;
  $("crop-all").hidden = height <= 0 || $("crop-as-share").checked;
  if (height <= 0) {
    $("crop-value").textContent = "no crop";
  } else if ($("crop-as-share").checked && range > 0) {
    $("crop-value").textContent = "remove the bottom " + formatNumber(Number((100 * height / range).toPrecision(3)))
      + "% of each crown's height (here " + formatNumber(Number(height.toPrecision(4))) + " of "
      + formatNumber(Number(range.toPrecision(4))) + ")";
  } else {
    $("crop-value").textContent = "remove below " + formatNumber(Number(height.toPrecision(4)))
      + " (of " + formatNumber(Number(range.toPrecision(4))) + ") above the lowest point";
  }
  $("crop").setAttribute("aria-valuetext", $("crop-value").textContent);
  if (app.oriented) {
    const { removed, total } = cropColors();
    const share = total ? (100 * removed) / total : 0;
    $("crop-share").textContent = share.toFixed(1) + "% of the vertices removed";
  } else {
    $("crop-share").textContent = "";
  }
}

function meshTrace(mesh, colors) {
  const trace = {
    type: "mesh3d", x: mesh.xyz[0], y: mesh.xyz[1], z: mesh.xyz[2],
    i: mesh.ijk[0], j: mesh.ijk[1], k: mesh.ijk[2], hoverinfo: "skip", flatshading: false,
    lighting: { ambient: 0.45, diffuse: 0.75, specular: 0.08, roughness: 0.85, fresnel: 0.1 },
    lightposition: { x: 0, y: 0, z: 1e5 },
  };
  if (colors) trace.vertexcolor = colors; else trace.color = TOOTH;
  return trace;
}

/** The view's cameras: from above the crown, and obliquely from the side (to see a crop). */
const CAMERAS = {
  occlusal: { eye: { x: 0, y: 0, z: 1.8 }, up: { x: 0, y: 1, z: 0 } },
  side: { eye: { x: 1.3, y: -1.3, z: 0.7 }, up: { x: 0, y: 0, z: 1 } },
};

function camera(name) {
  return JSON.parse(JSON.stringify(CAMERAS[name] || CAMERAS.occlusal));
}

const VIEW_LAYOUT = (cameraName) => ({
  margin: { l: 0, r: 0, t: 0, b: 0 },
  paper_bgcolor: "#ffffff",
  scene: {
    aspectmode: "data",
    xaxis: { visible: false }, yaxis: { visible: false }, zaxis: { visible: false },
    camera: camera(cameraName),
  },
});

/** Turn the view shown to camera `name` (a relayout: the mesh is not drawn again). */
async function setCamera(name) {
  if (!CAMERAS[name]) return;
  if (app.showing) app.cameras[app.showing] = name;
  updateSwitch();
  if (app.showing && $("view").data) await Plotly.relayout($("view"), { "scene.camera": camera(name) });
}

async function drawView(show) {
  const which = show === "prepared" ? "prepared" : "oriented";
  const mesh = which === "prepared" ? app.prepared : app.oriented;
  if (!mesh) return;
  const trace = which === "prepared" ? meshTrace(mesh, null) : meshTrace(mesh, cropColors().colors);
  await Plotly.newPlot($("view"), [trace], VIEW_LAYOUT(app.cameras[which]), PLOT_CONFIG);
  app.showing = which;
  const n = mesh.xyz[0].length, m = mesh.ijk[0].length;
  const real = realFaces(which);
  $("view-label").textContent = (which === "prepared" ? "prepared: " : "cleaned and oriented: ")
    + (real !== null && real > m
      ? count(real) + " faces (" + count(m) + " drawn)"
      : count(n) + " vertices, " + count(m) + " faces");
  updateSwitch();
}

/** The faces of the mesh shown, as the preview's steps count them (the view may draw fewer). */
function realFaces(which) {
  const steps = (app.preview && app.preview.steps) || [];
  if (!steps.length) return null;
  if (which === "prepared") return Number(steps[steps.length - 1].faces_after);
  const placed = steps.filter((step) => step.name === "clean" || step.name === "orient");
  return placed.length ? Number(placed[placed.length - 1].faces_after) : Number(steps[0].faces_before);
}

function updateSwitch() {
  $("show-oriented").classList.toggle("on", app.showing === "oriented");
  $("show-prepared").classList.toggle("on", app.showing === "prepared");
  $("show-oriented").disabled = !app.oriented;
  $("show-prepared").disabled = !app.prepared;
  const current = app.showing ? app.cameras[app.showing] : "";
  for (const name of Object.keys(CAMERAS)) {
    const button = $("camera-" + name);
    button.classList.toggle("on", current === name);
    button.setAttribute("aria-pressed", String(current === name));
    button.disabled = !app.showing;
  }
}

function drawSteps(answer) {
  const rows = (answer.steps || []).map((step) => el("tr", {},
    el("td", { text: String(step.name) }),
    el("td", { text: count(step.vertices_before) + " \u2192 " + count(step.vertices_after) }),
    el("td", { text: count(step.faces_before) + " \u2192 " + count(step.faces_after) }),
    el("td", { className: "warn", text: (step.warnings || []).map(String).join("; ") })));
  $("steps").tBodies[0].replaceChildren(...rows);
  $("steps").hidden = rows.length === 0;
}

$("crop-as-share").addEventListener("change", () => {
  app.cropTouched = true;
  $("crop-note").hidden = true;
  $("steps-stale").hidden = !app.preview;
  updateCropText();
});

let cropFrame = 0;
let cropTurn = false;  // the next frame turns the oriented view to the side
$("crop").addEventListener("input", () => {
  app.cropTouched = true;
  $("crop-note").hidden = true;
  $("steps-stale").hidden = !app.preview;
  updateCropText();
  if (!app.oriented) return;
  // the first crop of a mesh turns the oriented view to the side, once (the reader may turn it back)
  if (!app.sideShown && cropHeight() > 0) {
    app.sideShown = true;
    app.cameras.oriented = "side";
    cropTurn = true;
  }
  if (cropFrame) return;
  cropFrame = requestAnimationFrame(() => {
    cropFrame = 0;
    let done;
    if (app.showing === "oriented") {
      done = Plotly.restyle($("view"), { vertexcolor: [cropColors().colors] }, [0]);
      if (cropTurn) done = Promise.resolve(done).then(() => setCamera("side"));
    } else {
      done = drawView("oriented");
    }
    cropTurn = false;
    Promise.resolve(done).catch((error) => noteError(error));
  });
});

let previewTimer = 0;
function previewSoon() {
  if (!app.selected) return;
  clearTimeout(previewTimer);
  previewTimer = setTimeout(guarded(() => refreshPreview("oriented")), 400);
}
for (const id of ["p-clean", "p-keep", "p-orient", "p-spin", "up-x", "up-y", "up-z"]) {
  $(id).addEventListener("change", previewSoon);
}

$("up-flip").addEventListener("click", guarded(async () => {
  let up = readUp();
  if (up === null) up = app.preview && Array.isArray(app.preview.found_up) ? app.preview.found_up : [0, 0, 1];
  ["up-x", "up-y", "up-z"].forEach((id, i) => { $(id).value = String(Number((-up[i]).toFixed(4)) || 0); });
  if ($("p-orient").value === "none") $("p-orient").value = "occlusal";
  await refreshPreview("oriented");
}));
$("up-found").addEventListener("click", guarded(async () => {
  ["up-x", "up-y", "up-z"].forEach((id) => { $(id).value = ""; });
  await refreshPreview("oriented");
}));
$("preview").addEventListener("click", guarded(() => {
  app.cameras.prepared = "occlusal";  // the prepared mesh opens seen from above
  return refreshPreview("prepared");
}));
$("show-oriented").addEventListener("click", guarded(() => drawView("oriented")));
$("show-prepared").addEventListener("click", guarded(() => drawView("prepared")));
for (const name of Object.keys(CAMERAS)) {
  $("camera-" + name).addEventListener("click", guarded(() => setCamera(name)));
}

async function saveProtocol(scope, protocol) {
  const body = { scope: scope, protocol: protocol };
  if (scope === "mesh") body.path = app.selected;
  if (protocol !== null) body.prepare = true;  // a protocol just made is one to measure with
  const state = await postJSON("/api/protocol", body);
  if (protocol !== null) $("prepare-before").checked = true;
  drawState(state);
  const where = scope === "all" ? "the folder (every mesh without its own)" : app.selected;
  showMessage(protocol === null ? "Removed the protocol of " + where + "." : "Saved the protocol for " + where + ".", true);
  if (protocol !== null) {
    app.base = Object.assign({}, protocol);
    app.cropTouched = false;
  }
}
$("apply-mesh").addEventListener("click", guarded(() => saveProtocol("mesh", readForm())));
$("apply-all").addEventListener("click", guarded(() => saveProtocol("all", readForm())));
$("remove-own").addEventListener("click", guarded(() => saveProtocol("mesh", null)));

// ---------------------------------------------------------------------------------------------
// measure

function drawMeasureChoices(state) {
  const metrics = choices("metrics", []);
  const box = $("metrics");
  if (box.dataset.built !== metrics.join(",")) {
    const checked = new Set(Array.from(box.querySelectorAll("input:checked"), (i) => i.value));
    const first = !box.dataset.built;
    box.replaceChildren(...metrics.map((name) => el("label", { className: "check" },
      el("input", { type: "checkbox", value: name, checked: first ? name === "ariadne" : checked.has(name), name: "metric" }),
      String(name))));
    box.dataset.built = metrics.join(",");
    if (first && !box.querySelector("input:checked") && box.querySelector("input")) {
      box.querySelector("input").checked = true;
    }
    const groups = (state.choices && state.choices.metric_groups) || {};
    const buttons = Object.entries(groups).map(([name, members]) => {
      const b = el("button", { type: "button", text: name, "data-group": name });
      b.addEventListener("click", () => {
        const wanted = new Set(members);
        for (const input of box.querySelectorAll("input")) input.checked = wanted.has(input.value);
      });
      return b;
    });
    const none = el("button", { type: "button", text: "none" });
    none.addEventListener("click", () => {
      for (const input of box.querySelectorAll("input")) input.checked = false;
    });
    $("metric-groups").replaceChildren(...buttons, none);
  }
  fillSelect($("distance_type"), choices("distance_type", ["euclidean", "geodesic"]));
  fillSelect($("sign_method"), choices("sign_method", ["centroid"]));
  fillSelect($("method"), choices("method", ["auto"]));
  if (!$("bandwidth").dataset.set) {
    // the last run's settings if there was one, else the defaults
    const d = Object.assign({}, state.defaults || {}, state.last_run || {});
    $("bandwidth").value = d.bandwidth !== undefined ? String(d.bandwidth) : "0.08";
    $("cutoff").value = d.cutoff !== undefined ? String(d.cutoff) : "0";
    if (d.distance_type) $("distance_type").value = d.distance_type;
    if (d.sign_method) $("sign_method").value = d.sign_method;
    if (d.method) $("method").value = d.method;
    $("jobs").value = d.jobs !== undefined ? String(d.jobs) : "1";
    if (Array.isArray(d.metrics) && d.metrics.length) {
      const wanted = new Set(d.metrics);
      for (const input of box.querySelectorAll("input")) input.checked = wanted.has(input.value);
    }
    if (typeof state.prepare === "boolean") $("prepare-before").checked = state.prepare;
    $("bandwidth").dataset.set = "1";
  }
}

/** Split a protocol label ("NAME DIGEST") into its name and digest. */
function labelParts(label) {
  const text = String(label || "");
  const cut = text.lastIndexOf(" ");
  if (cut < 0) return { name: text, digest: "" };
  return { name: text.slice(0, cut), digest: text.slice(cut + 1) };
}

/** 'Protocol “NAME” · digest DIGEST': the name and the digest that names its parameters. */
function protocolWords(label, lead) {
  const { name, digest } = labelParts(label);
  return (lead || "Protocol") + " \u201c" + name + "\u201d" + (digest ? " \u00b7 digest " + digest : "");
}

/** The line above Run: what a run will do with the meshes (as read, or prepared with what). */
function drawRunPlan() {
  const state = app.state;
  const line = $("run-plan");
  if (!state) { line.textContent = ""; return; }
  if (!$("prepare-before").checked) {
    line.textContent = "Meshes are measured as read.";
    line.dataset.plan = "as-read";
    return;
  }
  const meshes = state.meshes || [];
  const folder = meshes.filter((m) => m.protocol === "folder").length;
  const own = meshes.filter((m) => m.protocol === "own").length;
  const none = meshes.length - folder - own;
  if (!folder && !own) {
    line.textContent = "Meshes are measured as read: no mesh has a protocol yet (Apply one above).";
    line.dataset.plan = "as-read";
    return;
  }
  const name = state.protocol ? labelParts(state.protocol_label || state.protocol.name).name : "";
  const parts = [];
  if (folder) parts.push("the folder\u2019s (" + (name || "custom") + ") for " + folder);
  if (own) parts.push("their own for " + own);
  let text = "Each mesh is prepared with its protocol first: " + parts.join(", ");
  if (none) text += "; " + none + " without one " + (none === 1 ? "is" : "are") + " measured as read";
  line.textContent = text + ".";
  line.dataset.plan = "prepare";
}
$("prepare-before").addEventListener("change", drawRunPlan);

function readNumber(id, name) {
  const value = Number($(id).value);
  if ($(id).value.trim() === "" || !Number.isFinite(value)) throw new ApiError(name + " must be a number");
  return value;
}

$("run").addEventListener("click", guarded(async () => {
  const metrics = Array.from($("metrics").querySelectorAll("input:checked"), (i) => i.value);
  if (!metrics.length) throw new ApiError("Tick at least one metric.");
  const jobs = readNumber("jobs", "jobs");
  if (!Number.isInteger(jobs) || jobs < 1) throw new ApiError("jobs must be a whole number, 1 or more");
  const body = {
    metrics: metrics,
    bandwidth: readNumber("bandwidth", "bandwidth"),
    cutoff: readNumber("cutoff", "cutoff"),
    distance_type: $("distance_type").value,
    sign_method: $("sign_method").value,
    method: $("method").value,
    jobs: jobs,
    prepare: $("prepare-before").checked,
  };
  $("run").disabled = true;
  $("progress").dataset.state = "starting";
  try {
    drawRun(await postJSON("/api/run", body));
  } catch (error) {
    $("run").disabled = false;
    if (app.run) $("progress").dataset.state = app.run.state;
    throw error;
  }
  pollRun();
}));
$("cancel").addEventListener("click", guarded(async () => {
  $("cancel").disabled = true;
  drawRun(await postJSON("/api/run/cancel", {}));
}));

const ACTIVE = new Set(["running", "cancelling"]);

/** Whether `run` is older than the run state drawn (two answers can cross on the way). */
function olderRun(run, was) {
  if (!was || run.run !== was.run) return false;
  return (Number(run.serial) || 0) < (Number(was.serial) || 0);
}

function drawRun(run) {
  if (!run || olderRun(run, app.run)) return;  // the progress never runs backwards
  const was = app.run;
  app.run = run;
  const active = ACTIVE.has(run.state);
  $("run").disabled = active;
  $("cancel").disabled = run.state !== "running";
  $("output-change").disabled = active;
  const total = Number(run.total) || 0, done = Number(run.done) || 0;
  const progress = $("progress");
  progress.dataset.state = run.state;
  progress.setAttribute("aria-valuemax", String(total));
  progress.setAttribute("aria-valuenow", String(done));
  progress.querySelector(".fill").style.width = (total ? (100 * done) / total : 0) + "%";
  progress.querySelector(".progress-text").textContent = done + " / " + total;
  // a fresh install's first run compiles the kernels first: said here, not only in the log
  const compiling = active && run.compiling ? run.compiling : null;
  const note = progress.querySelector(".progress-note");
  note.hidden = !compiling;
  note.textContent = compiling
    ? compiling.message + " \u00b7 " + (Number(compiling.seconds) || 0) + " s so far"
    : "";
  progress.dataset.phase = compiling ? "compiling" : "";
  const words = {
    idle: "", running: "running\u2026", cancelling: "cancelling\u2026", done: "done",
    cancelled: "cancelled", failed: "failed",
  };
  let text = words[run.state] !== undefined ? words[run.state] : String(run.state);
  if (!active && run.exit_code !== null && run.exit_code !== undefined && run.state !== "idle") {
    text += " (exit code " + run.exit_code + ")";
  }
  $("run-state").textContent = text;
  $("run-command").textContent = run.command || "";
  const files = Object.entries(run.files || {});
  $("run-files").replaceChildren(...files.map(([path, info]) => {
    const warned = info.status === "ok" && Boolean(info.warnings);
    return el("li", { "data-path": path, "data-status": warned ? "warned" : info.status },
      el("span", { className: "status status-" + (warned ? "warned" : info.status), text: statusWords(info.status, info.warnings) }), " ",
      el("span", { text: path }),
      info.seconds !== null && info.seconds !== undefined ? el("span", { className: "muted", text: " " + seconds(info.seconds) }) : null,
      info.error ? el("span", { className: "error " + info.status, text: " \u2014 " + info.error }) : null,
      info.warnings && info.status !== "error" ? warningsBlock(info.warnings) : null);
  }));
  const log = $("log");
  const lines = (run.log || []).map(String).join("\n");
  if (log.textContent !== lines) {
    const atEnd = log.scrollTop + log.clientHeight >= log.scrollHeight - 4;
    log.textContent = lines;
    if (atEnd) log.scrollTop = log.scrollHeight;
  }
  if (run.state === "failed") $("log-box").open = true;
  const finished = was && ACTIVE.has(was.state) && !active;
  if (active || finished || (was && was.done !== run.done)) loadResults().catch(showError);
  if (finished) getJSON("/api/state").then(drawState).catch(showError);
}

function showError(error) {
  showMessage(error && error.message ? error.message : String(error));
}

async function pollRun() {
  if (app.runTimer) return;
  app.runTimer = true;
  try {
    for (;;) {
      await sleep(500);
      const run = await getJSON("/api/run");
      drawRun(run);
      if (!ACTIVE.has(run.state)) break;
    }
  } catch (error) {
    showError(error);
  } finally {
    app.runTimer = null;
  }
}

// ---------------------------------------------------------------------------------------------
// results

async function loadResults() {
  const results = await getJSON("/api/results");
  const key = JSON.stringify(results);
  if (key === app.resultsKey) return;
  app.resultsKey = key;
  app.results = results;
  drawResults();
}

function groupOf(file) {
  const mesh = meshByPath(file);
  if (mesh) return mesh.group;
  const parts = String(file).split("/");
  return parts.length > 1 ? parts[0] : "";
}

function drawResults() {
  const results = app.results || { columns: [], rows: [] };
  const given = results.columns || [];
  // the file, then its status, then the rest in the server's order (warnings, error, headlines...)
  const columns = given.filter((c) => c === "file").concat(given.filter((c) => c === "status"),
    given.filter((c) => c !== "file" && c !== "status"));
  const rows = results.rows || [];
  const table = $("results");
  const numeric = new Set(columns.filter((c) => {
    const values = rows.map((r) => r[c]).filter((v) => v !== null && v !== undefined && v !== "");
    return values.length > 0 && values.every((v) => typeof v === "number");
  }));
  table.tHead.rows[0].replaceChildren(...columns.map((c) => {
    const th = el("th", { text: String(c), "data-column": c, "data-sort": numeric.has(c) ? "num" : "text", scope: "col" });
    if (app.sort && app.sort.column === c) th.dataset.dir = app.sort.dir;
    th.addEventListener("click", () => {
      const dir = app.sort && app.sort.column === c && app.sort.dir === "asc" ? "desc" : "asc";
      app.sort = { column: c, dir: dir };
      drawResults();
    });
    return th;
  }));
  let ordered = rows.slice();
  if (app.sort && columns.includes(app.sort.column)) {
    const c = app.sort.column, sign = app.sort.dir === "asc" ? 1 : -1, isNum = numeric.has(c);
    const key = (row) => {
      const v = row[c];
      if (v === null || v === undefined || v === "") return null;
      return isNum ? Number(v) : String(v).toLowerCase();
    };
    ordered = ordered.map((row) => [key(row), row]).sort((a, b) => {
      if (a[0] === b[0]) return 0;
      if (a[0] === null) return 1;
      if (b[0] === null) return -1;
      return a[0] < b[0] ? -sign : sign;
    }).map((pair) => pair[1]);
  }
  const body = ordered.map((row) => {
    const file = row.file !== undefined ? String(row.file) : "";
    const warned = row.status === "ok" && Boolean(row.warnings);
    const tr = el("tr", { "data-file": file, "data-group": groupOf(file), "data-status": row.status });
    if (row.status === "error") tr.classList.add("row-error");
    if (warned) tr.classList.add("row-warned");
    if (file && file === app.mapsFor) tr.classList.add("picked");
    for (const c of columns) {
      const v = row[c];
      const raw = v === null || v === undefined ? "" : String(v);
      let td;
      if (c === "file" && file && row.status !== "error") {
        const button = el("button", { type: "button", className: "file", text: file, title: "show the maps" });
        button.addEventListener("click", () => showMaps(file));
        td = el("td", { "data-v": raw }, button);
      } else if (c === "status" && warned) {
        // "ok, warned", the warnings below it (data-v keeps the table's own value)
        td = el("td", { "data-v": raw, className: "status status-warned" },
          el("div", { text: statusWords(raw, row.warnings) }), warningsBlock(row.warnings));
      } else if (c === "warnings" && raw) {
        td = el("td", { "data-v": raw, className: "warnings-cell", text: raw, title: raw });
      } else {
        const kind = typeof v === "number" ? "num" : c === "status" ? "status status-" + raw : "";
        td = el("td", { "data-v": raw, className: kind, text: typeof v === "number" ? formatNumber(v) : raw });
        if (c === "status" && row.error) td.title = String(row.error);
      }
      tr.append(td);
    }
    return tr;
  });
  table.tBodies[0].replaceChildren(...body);
  $("results-empty").hidden = rows.length > 0;
  applyFilter();
}

function applyFilter() {
  const text = $("filter").value.trim().toLowerCase();
  const group = $("group-filter").value;
  let shown = 0;
  const rows = $("results").tBodies[0].rows;
  for (const row of rows) {
    const rowGroup = row.dataset.group || "";
    const groupOk = !group || (group === "\u0000top" ? rowGroup === "" : rowGroup === group);
    const keep = groupOk && (!text || row.textContent.toLowerCase().includes(text));
    row.hidden = !keep;
    shown += keep;
  }
  $("results-count").textContent = rows.length ? "(" + shown + " of " + rows.length + " shown)" : "";
}
$("filter").addEventListener("input", applyFilter);
$("group-filter").addEventListener("change", applyFilter);

let mapSerial = 0;
async function showMaps(file) {
  const serial = ++mapSerial;
  app.mapsFor = file;
  for (const row of $("results").tBodies[0].rows) row.classList.toggle("picked", row.dataset.file === file);
  $("maps-box").hidden = false;
  $("maps-name").textContent = file;
  const known = choices("maps", MAP_METRICS.map((pair) => pair[0]));
  const labels = new Map(MAP_METRICS);
  const maps = known.map((metric) => {
    const label = labels.get(metric) || String(metric);
    const img = el("img", { alt: label + " of " + file, hidden: true });
    const placeholder = el("div", { className: "map-wait", text: "\u2026" });
    const caption = el("figcaption", { text: label + ": waiting\u2026" });
    const figure = el("figure", { "data-metric": metric }, placeholder, img, caption);
    return { metric, label, img, placeholder, caption, figure };
  });
  $("maps").replaceChildren(...maps.map((m) => m.figure));
  $("maps-box").scrollIntoView({ block: "nearest" });
  // one after the other, as the picture worker draws them
  for (const m of maps) {
    if (serial !== mapSerial) return;
    m.caption.textContent = m.label + ": drawing\u2026";
    try {
      await loadMap(file, m.metric, m.label, m.img, m.caption, serial);
      m.placeholder.remove();
    } catch (error) {
      m.caption.textContent = m.label + ": " + (error && error.message ? error.message : error);
      m.caption.classList.add("error");
      m.placeholder.remove();
    }
  }
}

async function loadMap(file, metric, label, img, caption, serial) {
  const url = "/api/map?path=" + encodeURIComponent(file) + "&metric=" + encodeURIComponent(metric);
  for (let tries = 0; tries < 600; tries++) {
    if (serial !== mapSerial) return;
    const response = await fetch(url, { credentials: "same-origin", cache: "no-store" });
    if (response.status === 202) { await sleep(1000); continue; }
    if (!response.ok) throw await errorOf(response);
    const blob = await response.blob();
    if (serial !== mapSerial) return;
    img.src = URL.createObjectURL(blob);
    img.hidden = false;
    // the picture's own address: the full-size PNG (drawn already, so it is answered at once)
    const link = el("a", { href: url, target: "_blank", rel: "noopener", title: "open the full-size picture", className: "map-link" });
    img.replaceWith(link);
    link.append(img);
    caption.replaceChildren(label + " \u00b7 ", el("a", { href: url, target: "_blank", rel: "noopener", text: "full size" }));
    return;
  }
  throw new ApiError("gave up waiting for the picture");
}

// ---------------------------------------------------------------------------------------------
// export

async function follow(path, start, stateBox, link, what) {
  let answer = start;
  stateBox.textContent = what + "\u2026";
  link.hidden = true;
  for (let tries = 0; answer.state !== "done"; tries++) {
    if (answer.state === "failed" || answer.error) throw new ApiError(answer.error || what + " failed");
    if (tries > 1800) throw new ApiError(what + ": gave up waiting");
    await sleep(1000);
    answer = await getJSON(path);
  }
  stateBox.textContent = answer.folder ? "written to " + answer.folder : "";
  link.href = answer.url;
  link.hidden = false;
  return answer;
}

$("build-report").addEventListener("click", guarded(async () => {
  $("build-report").disabled = true;
  try {
    await follow("/api/report", await postJSON("/api/report", {}), $("report-state"), $("report-link"), "drawing the report");
    $("report-state").textContent = "";
  } catch (error) {
    $("report-state").textContent = "";
    throw error;
  } finally {
    $("build-report").disabled = false;
  }
}));
$("export-prepared").addEventListener("click", guarded(async () => {
  $("export-prepared").disabled = true;
  try {
    await follow("/api/export/prepared", await postJSON("/api/export/prepared", {}), $("prepared-state"), $("prepared-link"), "preparing the meshes");
  } catch (error) {
    $("prepared-state").textContent = "";
    throw error;
  } finally {
    $("export-prepared").disabled = false;
  }
}));

// ---------------------------------------------------------------------------------------------
// the output folder

function drawOutput(state) {
  $("output-where").textContent = state.output || "";
  $("output-root").textContent = state.folder || "";
  $("output-change").disabled = Boolean(app.run && ACTIVE.has(app.run.state));
  if ($("output-form").hidden) $("output-folder").value = state.output_relative || "";
}
$("output-change").addEventListener("click", () => {
  $("output-form").hidden = false;
  $("output-folder").focus();
});
$("output-cancel").addEventListener("click", () => { $("output-form").hidden = true; });
$("output-form").addEventListener("submit", guarded(async (event) => {
  event.preventDefault();
  $("output-use").disabled = true;
  try {
    const state = await postJSON("/api/output", { output: $("output-folder").value });
    $("output-form").hidden = true;
    drawState(state);
    await loadResults();
    await followPending(state);
  } finally {
    $("output-use").disabled = false;
  }
}));

function drawExport(state) {
  const hasResults = Boolean(state.results);
  for (const id of ["export-csv", "export-tsv", "export-xlsx"]) {
    $(id).classList.toggle("disabled", !hasResults);
    $(id).title = hasResults ? "" : "no results yet";
  }
  if (state.report && $("report-link").hidden) $("report-link").href = "/output/report.html";
  $("report-link").hidden = !state.report;  // (another output folder may have none)
}

// ---------------------------------------------------------------------------------------------
// the state

function drawState(state) {
  app.state = state;
  drawHeader(state);
  fillProtocolChoices();
  drawMeshes(state);
  if (app.selected) drawSelectedHeader();
  drawMeasureChoices(state);
  drawRunPlan();
  drawOutput(state);
  drawExport(state);
  if (state.run) {
    drawRun(state.run);
    if (ACTIVE.has(state.run.state)) pollRun();
  }
}

/** Ask for the state every second while meshes are being read (each drawn). */
async function followPending(state) {
  let current = state;
  while (current.pending) {
    await sleep(1000);
    await visible();  // a hidden tab asks for nothing
    current = await getJSON("/api/state");
    drawState(current);
  }
}

async function start() {
  try {
    const state = await getJSON("/api/state");
    drawState(state);
    statusBox.dataset.ready = "1";
    if (state.results) await loadResults();
    await followPending(state);
  } catch (error) {
    showError(error);
    if (!(error instanceof ApiError)) noteError(error && error.message ? error.message : error);
    statusBox.dataset.ready = statusBox.dataset.ready || "error";
  }
}

updateSwitch();
start();
