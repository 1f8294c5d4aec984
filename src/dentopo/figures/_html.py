"""Self-contained HTML pages: coloured meshes to rotate in a browser, offline.

One file holds everything: the meshes (base64 binary arrays in a JSON block),
a small viewer (inline JavaScript drawing with WebGL, or with a 2D canvas
where WebGL is unavailable), the colour bar and the captions.  The page loads
nothing: no scripts, styles, fonts or data from elsewhere, and its Content
Security Policy (``default-src 'none'``) makes the browser refuse any request
it might try.  Drag to rotate (all panels turn together), wheel to zoom,
double-click to reset.  Opening the page with ``#canvas2d`` appended to
its address forces the 2D-canvas fallback.  numpy only.

Names and captions are text: the JSON blocks escape ``<``, ``>`` and ``&``
(:func:`._provenance.html_json`), the viewer sets them as ``textContent``, and
the page is filled in one pass (:func:`fill`), so that a name holding
``%DATA%`` stays as it is.
"""

from __future__ import annotations

import base64
import html as html_escape
import json
import os
import re

import numpy as np

from . import _provenance
from ._camera import DEFAULT_VIEW, camera_for
from ._colors import ColorScale
from ._layout import write_bytes


def _b64(array: np.ndarray, dtype) -> str:
    return base64.b64encode(np.ascontiguousarray(array, dtype=dtype).tobytes()).decode("ascii")


def _mesh_payload(camera, vertices, faces, rgb, label, caption, options=None) -> dict:
    """The JSON record of one mesh (see :func:`write_html` for the arguments).

    Positions, normals and lines are given in the camera's frame (right, up,
    towards the viewer), around its focal point: the viewer starts unturned.
    """
    options = options or {}
    rotation = camera.rotation()
    centre = np.asarray(camera.focal_point, dtype=np.float64)
    vertices = (np.asarray(vertices, dtype=np.float64) - centre) @ rotation.T
    centre = np.zeros(3)
    faces = np.asarray(faces, dtype=np.int64)
    rgb = np.asarray(rgb, dtype=np.uint8)
    centred = vertices
    radius = float(np.linalg.norm(centred, axis=1).max()) or 1.0
    tri = centred[faces]
    face_normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])  # area-weighted
    if options.get("face_colors"):
        # flat: three corners of their own per face, sharing its normal and colour
        length = np.linalg.norm(face_normal, axis=1, keepdims=True)
        unit = np.divide(face_normal, length, out=np.zeros_like(face_normal), where=length > 0)
        centred = tri.reshape(-1, 3)
        normals = np.repeat(unit, 3, axis=0)
        rgb = np.repeat(rgb, 3, axis=0)
        faces = np.arange(3 * len(faces)).reshape(-1, 3)
    else:
        normals = np.zeros_like(centred)
        for corner in range(3):
            np.add.at(normals, faces[:, corner], face_normal)
        length = np.linalg.norm(normals, axis=1, keepdims=True)
        normals = np.divide(normals, length, out=np.zeros_like(normals), where=length > 0)
    record = {
        "label": label,
        "caption": caption,
        "nv": len(centred),
        "nf": len(faces),
        "positions": _b64(centred / radius, "<f4"),
        "normals": _b64(normals, "<f4"),
        "colors": _b64(rgb, np.uint8),
        "faces": _b64(faces, "<u4"),
    }
    lines = options.get("lines")
    if lines is not None and len(lines):
        lines = np.asarray(lines, dtype=np.float64).reshape(-1, 2, 3)
        lines = ((lines - np.asarray(camera.focal_point)) @ rotation.T - centre) / radius
        record["lines"] = _b64(lines, "<f4")
        record["lineColor"] = [int(c) for c in options.get("line_rgb", (0, 0, 0))]
        record["lineWidth"] = float(options.get("line_width", 2.0))
    return record


def write_html(
    path,
    meshes,
    *,
    scale: ColorScale | None = None,
    title: str,
    legend: str = "blue \u2212 concave, red + convex",
    view=DEFAULT_VIEW,
    bar: str | None = None,
    cameras=None,
    provenance: dict | None = None,
) -> None:
    """Write a self-contained interactive page of coloured meshes.

    Parameters
    ----------
    path : str or path-like
        The HTML file to write.
    meshes : sequence of (vertices, faces, rgb, label, caption[, options])
        ``vertices`` (n, 3) float, ``faces`` (m, 3) int, ``rgb`` (n, 3) uint8
        per-vertex colours, and the texts shown above each mesh.  The
        optional ``options`` dict may hold ``face_colors`` (True: ``rgb`` is
        (m, 3), one colour per face, drawn flat), ``lines`` ((k, 2, 3) float
        segments in mesh coordinates, drawn over the mesh with depth),
        ``line_rgb`` (their colour, 3 ints) and ``line_width`` (pixels).
    scale : ColorScale, optional
        The diverging colour scale used, for the colour bar; needed unless
        `bar` is given.
    title : str
        Name of the coloured quantity.
    legend : str
        What the colours mean, shown by the colour bar.
    view : str or (3, 3), default "occlusal"
        The initial view of each mesh (see :func:`~._camera.camera_for`),
        when `cameras` is not given; None means "occlusal".
    bar : str, optional
        The legend block's HTML (from :func:`sequential_bar` or
        :func:`swatch_bar`) in place of the diverging colour bar.
    cameras : sequence of Camera, optional
        The initial camera of each mesh.
    provenance : dict, optional
        The JSON record kept in the page (``<script type="application/json"
        id="dentopo-provenance">``).
    """
    meshes = list(meshes)
    if cameras is None:
        cameras = [camera_for(m[0], m[1], view or DEFAULT_VIEW) for m in meshes]
    payload = {
        "meshes": [_mesh_payload(c, *m) for c, m in zip(cameras, meshes, strict=True)],
        "rotation": np.eye(3).tolist(),
    }
    if bar is None:
        if scale is None:
            raise ValueError("write_html needs the colour scale or a legend block (bar=)")
        bar = _diverging_bar(scale, title, legend)
    parts = {
        "TITLE": html_escape.escape(title),
        "BAR": bar,
        "SCRIPT": _SCRIPT,
        "PROVENANCE": _provenance.html_block(provenance) if provenance else "",
        "DATA": _provenance.html_json(json.dumps(payload, separators=(",", ":"))),
    }
    write_bytes(os.fspath(path), fill(_TEMPLATE, parts).encode("utf-8"))


def fill(template: str, parts: dict[str, str]) -> str:
    """`template` with each ``%NAME%`` replaced by ``parts[NAME]``, in one pass.

    One pass: a part that itself holds ``%DATA%`` or ``%SCRIPT%`` (a title or a
    file name, say) is kept as it is, not filled in turn.
    """
    return re.sub(r"%([A-Z]+)%", lambda m: parts.get(m.group(1), m.group(0)), template)


def _gradient(stops) -> str:
    return ", ".join(f"rgb({r},{g},{b}) {100 * t:.1f}%" for t, (r, g, b) in stops)


def _diverging_bar(scale: ColorScale, title: str, legend: str) -> str:
    """The colour bar of a signed field, as in the pictures: title, bar, ticks, the rule."""
    t = np.linspace(0, 1, 41)
    rgb = np.round(255 * scale.bar_rgb(t)).astype(int)
    low, high = scale.limits
    heading = f"{title} ({legend})" if legend else title
    spans = "".join(
        f'<span style="left: {100 * float(scale.position(v)):.2f}%">'
        f"{html_escape.escape('0' if v == 0 else f'{v:.3g}'.replace('-', chr(0x2212)))}</span>"
        for v in (low, low / 2, 0.0, high / 2, high)
    )
    return (
        f'<div id="rule">{html_escape.escape(heading)}</div>\n'
        f'<div id="gradient" style="background: linear-gradient(to right, '
        f'{_gradient(zip(t, rgb, strict=True))})"></div>\n'
        f'<div id="ticks" class="placed">{spans}</div>\n'
        f'<div id="note">limits {html_escape.escape(scale.rule)}</div>'
    )


def sequential_bar(title: str, ticks, rgb_at, note: str = "") -> str:
    """A colour bar's HTML for a sequential scale.

    Parameters
    ----------
    title : str
        The text above the bar.
    ticks : sequence of str
        Labels spread evenly from the left end to the right end.
    rgb_at : callable
        Maps positions in [0, 1] to (..., 3) uint8 colours.
    note : str
        A further line under the ticks (e.g. how out-of-range values are drawn).
    """
    t = np.linspace(0, 1, 21)
    rgb = np.asarray(rgb_at(t), dtype=int)
    spans = "".join(f"<span>{html_escape.escape(str(tick))}</span>" for tick in ticks)
    text = (
        f'<div id="rule">{html_escape.escape(title)}</div>\n'
        f'<div id="gradient" style="background: linear-gradient(to right, '
        f'{_gradient(zip(t, rgb, strict=True))})"></div>\n'
        f'<div id="ticks">{spans}</div>'
    )
    if note:
        text += f'\n<div id="note">{html_escape.escape(note)}</div>'
    return text


def swatch_bar(title: str, entries) -> str:
    """A categorical legend's HTML: a coloured square and a label per entry.

    Parameters
    ----------
    title : str
        The text above the entries.
    entries : sequence of (str, (r, g, b))
        Labels and their colours (0 to 255).
    """
    items = "".join(
        f'<span class="entry"><span class="swatch" style="background: rgb({int(r)},{int(g)},'
        f'{int(b)})"></span>{html_escape.escape(label)}</span>'
        for label, (r, g, b) in entries
    )
    return f'<div id="rule">{html_escape.escape(title)}</div>\n<div id="swatches">{items}</div>'


_TEMPLATE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta http-equiv="Content-Security-Policy"
 content="default-src 'none'; script-src 'unsafe-inline'; style-src 'unsafe-inline'">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>dentopo: %TITLE%</title>
<style>
html, body { margin: 0; height: 100%; background: #fff; color: #111;
  font: 14px system-ui, sans-serif; }
body { display: flex; flex-direction: column; }
#panels { flex: 1; display: grid; gap: 4px; padding: 4px; min-height: 0; }
.cell { position: relative; min-height: 0; min-width: 0; overflow: hidden;
  display: flex; flex-direction: column; }
.cell canvas { flex: 1; width: 100%; min-height: 0; display: block; touch-action: none;
  cursor: grab; }
.text { padding: 2px 6px; box-sizing: border-box; white-space: pre-wrap; overflow-wrap: anywhere;
  font-size: clamp(10px, 1.6vw, 14px); line-height: 1.3; pointer-events: none; }
#bar { padding: 6px 4% 10px; max-width: 900px; width: 92%; margin: 0 auto;
  box-sizing: border-box; }
#gradient { height: 16px; border: 1px solid #444; margin: 0 2em; }
#ticks { display: flex; justify-content: space-between; gap: 4px; margin: 0 2em; }
#ticks span { min-width: 0; overflow-wrap: anywhere; }
#ticks.placed { position: relative; display: block; height: 1.4em; margin: 0 2em; }
#ticks.placed span { position: absolute; transform: translateX(-50%); white-space: nowrap; }
#rule, #note { text-align: center; overflow-wrap: anywhere; }
#swatches { display: flex; flex-wrap: wrap; justify-content: center; gap: 4px 16px; }
.entry { max-width: 100%; overflow-wrap: anywhere; }
.swatch { display: inline-block; width: 14px; height: 14px; margin-right: 5px;
  vertical-align: -2px; border: 1px solid #444; }
</style>
</head>
<body>
<div id="panels"></div>
<div id="bar">
%BAR%
</div>
<div id="status" hidden></div>
%PROVENANCE%
<script type="application/json" id="dentopo-data">%DATA%</script>
<script>%SCRIPT%</script>
</body>
</html>
"""

_SCRIPT = r"""
"use strict";
(function () {
  const data = JSON.parse(document.getElementById("dentopo-data").textContent);
  const status = document.getElementById("status");
  const force2d = window.location.hash === "#canvas2d";  // the fallback, on request
  function bytes(b64) {
    const s = atob(b64), out = new Uint8Array(s.length);
    for (let i = 0; i < s.length; i++) out[i] = s.charCodeAt(i);
    return out.buffer;
  }
  const start = data.rotation.map(function (r) { return r.slice(); });
  const state = { rot: start.map(function (r) { return r.slice(); }), zoom: 0.9, views: [] };
  function mul(a, b) {
    const c = [[0, 0, 0], [0, 0, 0], [0, 0, 0]];
    for (let i = 0; i < 3; i++) for (let j = 0; j < 3; j++)
      for (let k = 0; k < 3; k++) c[i][j] += a[i][k] * b[k][j];
    return c;
  }
  function turn(ax, ay) {  // rotate about the screen's y (ax) and x (ay) axes
    const cy = Math.cos(ax), sy = Math.sin(ax), cx = Math.cos(ay), sx = Math.sin(ay);
    const ry = [[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]];
    const rx = [[1, 0, 0], [0, cx, -sx], [0, sx, cx]];
    state.rot = mul(rx, mul(ry, state.rot));
  }
  function drawAll() { state.views.forEach(function (v) { v.draw(); }); }

  function webglView(canvas, m) {
    let gl = canvas.getContext("webgl2", { antialias: true, preserveDrawingBuffer: true });
    let kind = "webgl2";
    if (!gl) {
      gl = canvas.getContext("webgl", { antialias: true, preserveDrawingBuffer: true });
      kind = "webgl";
      if (!gl || !gl.getExtension("OES_element_index_uint")) return null;
    }
    const vs = "attribute vec3 p; attribute vec3 n; attribute vec3 c;" +
      "uniform mat3 r; uniform vec2 s; varying vec3 vc; varying vec3 vn;" +
      "void main() { vec3 q = r * p; vn = r * n; vc = c;" +
      " gl_Position = vec4(q.x * s.x, q.y * s.y, -q.z * 0.5, 1.0); }";
    const fs = "precision mediump float; varying vec3 vc; varying vec3 vn;" +
      "void main() { vec3 l = normalize(vec3(0.3, 0.4, 1.0));" +
      " float d = abs(dot(normalize(vn), l));" +
      " gl_FragColor = vec4(vc * (0.35 + 0.65 * d), 1.0); }";
    function shader(type, src) {
      const sh = gl.createShader(type);
      gl.shaderSource(sh, src); gl.compileShader(sh);
      return sh;
    }
    const prog = gl.createProgram();
    gl.attachShader(prog, shader(gl.VERTEX_SHADER, vs));
    gl.attachShader(prog, shader(gl.FRAGMENT_SHADER, fs));
    gl.linkProgram(prog);
    if (!gl.getProgramParameter(prog, gl.LINK_STATUS)) return null;
    gl.useProgram(prog);
    const bound = [];
    function attribute(name, array, size, type, normalized) {
      const loc = gl.getAttribLocation(prog, name), buf = gl.createBuffer();
      gl.bindBuffer(gl.ARRAY_BUFFER, buf);
      gl.bufferData(gl.ARRAY_BUFFER, array, gl.STATIC_DRAW);
      bound.push([loc, buf, size, type, normalized]);
    }
    function bind() {
      for (let i = 0; i < 8; i++) gl.disableVertexAttribArray(i);
      bound.forEach(function (a) {
        gl.bindBuffer(gl.ARRAY_BUFFER, a[1]);
        gl.enableVertexAttribArray(a[0]);
        gl.vertexAttribPointer(a[0], a[2], a[3], a[4], 0, 0);
      });
    }
    attribute("p", m.positions, 3, gl.FLOAT, false);
    attribute("n", m.normals, 3, gl.FLOAT, false);
    attribute("c", m.colors, 3, gl.UNSIGNED_BYTE, true);
    const ibuf = gl.createBuffer();
    gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, ibuf);
    gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, m.faces, gl.STATIC_DRAW);
    const ur = gl.getUniformLocation(prog, "r"), us = gl.getUniformLocation(prog, "s");
    const lines = m.lines ? lineLayer(gl, shader, m) : null;
    gl.enable(gl.DEPTH_TEST);
    return { kind: kind, draw: function () {
      const w = canvas.width, h = canvas.height, k = state.zoom * Math.min(w, h);
      gl.viewport(0, 0, w, h);
      gl.clearColor(1, 1, 1, 1);
      gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
      const r = state.rot;  // column-major: the transpose of the row list
      gl.useProgram(prog);
      bind();
      gl.uniformMatrix3fv(ur, false, [r[0][0], r[1][0], r[2][0], r[0][1], r[1][1], r[2][1],
        r[0][2], r[1][2], r[2][2]]);
      gl.uniform2f(us, k / w, k / h);
      gl.drawElements(gl.TRIANGLES, m.faces.length, gl.UNSIGNED_INT, 0);
      if (lines) lines.draw(r, k / w, k / h, w, h);
    } };
  }

  // segments as screen-space quads of a fixed width in pixels, depth-tested, drawn
  // slightly towards the viewer so that lines lying on the surface stay visible
  function lineLayer(gl, shader, m) {
    const vs = "attribute vec3 p; attribute vec3 q; attribute float side;" +
      "uniform mat3 r; uniform vec2 s; uniform vec2 vp; uniform float width;" +
      "void main() { vec3 a = r * p; vec3 b = r * q; vec2 sa = a.xy * s; vec2 sb = b.xy * s;" +
      " vec2 d = (sb - sa) * vp; if (length(d) < 1e-6) d = vec2(1.0, 0.0);" +
      " vec2 n = normalize(vec2(-d.y, d.x)) * side * width / vp;" +
      " gl_Position = vec4(sa + n, -a.z * 0.5 - 0.002, 1.0); }";
    const fs = "precision mediump float; uniform vec3 color;" +
      "void main() { gl_FragColor = vec4(color, 1.0); }";
    const prog = gl.createProgram();
    gl.attachShader(prog, shader(gl.VERTEX_SHADER, vs));
    gl.attachShader(prog, shader(gl.FRAGMENT_SHADER, fs));
    gl.linkProgram(prog);
    if (!gl.getProgramParameter(prog, gl.LINK_STATUS)) return null;
    const seg = m.lines, ns = seg.length / 6;
    const P = new Float32Array(ns * 18), Q = new Float32Array(ns * 18);
    const S = new Float32Array(ns * 6);
    // corners: (a, b, +1) (a, b, -1) (b, a, -1) (b, a, +1); triangles 0 1 3 and 0 3 2
    const ends = [0, 0, 1, 0, 1, 1], sides = [1, -1, 1, 1, 1, -1];
    for (let i = 0; i < ns; i++) for (let j = 0; j < 6; j++) {
      const e = ends[j], here = 6 * i + 3 * e, there = 6 * i + 3 * (1 - e), o = 18 * i + 3 * j;
      for (let c = 0; c < 3; c++) { P[o + c] = seg[here + c]; Q[o + c] = seg[there + c]; }
      S[6 * i + j] = sides[j];
    }
    function buffer(array) {
      const b = gl.createBuffer();
      gl.bindBuffer(gl.ARRAY_BUFFER, b);
      gl.bufferData(gl.ARRAY_BUFFER, array, gl.STATIC_DRAW);
      return b;
    }
    const bp = buffer(P), bq = buffer(Q), bs = buffer(S);
    const lp = gl.getAttribLocation(prog, "p"), lq = gl.getAttribLocation(prog, "q");
    const ls = gl.getAttribLocation(prog, "side");
    const u = {};
    ["r", "s", "vp", "width", "color"].forEach(function (n) {
      u[n] = gl.getUniformLocation(prog, n);
    });
    return { draw: function (r, sx, sy, w, h) {
      gl.useProgram(prog);
      for (let i = 0; i < 8; i++) gl.disableVertexAttribArray(i);
      [[lp, bp, 3], [lq, bq, 3], [ls, bs, 1]].forEach(function (a) {
        gl.bindBuffer(gl.ARRAY_BUFFER, a[1]);
        gl.enableVertexAttribArray(a[0]);
        gl.vertexAttribPointer(a[0], a[2], gl.FLOAT, false, 0, 0);
      });
      gl.uniformMatrix3fv(u.r, false, [r[0][0], r[1][0], r[2][0], r[0][1], r[1][1], r[2][1],
        r[0][2], r[1][2], r[2][2]]);
      gl.uniform2f(u.s, sx, sy);
      gl.uniform2f(u.vp, w, h);
      gl.uniform1f(u.width, m.lineWidth * (window.devicePixelRatio || 1));
      gl.uniform3f(u.color, m.lineColor[0] / 255, m.lineColor[1] / 255, m.lineColor[2] / 255);
      gl.drawArrays(gl.TRIANGLES, 0, ns * 6);
    } };
  }

  function canvasView(canvas, m) {  // painter's algorithm, flat shading per face
    const ctx = canvas.getContext("2d");
    const nf = m.faces.length / 3, ns = m.lines ? m.lines.length / 6 : 0;
    const order = new Uint32Array(nf + ns), depth = new Float32Array(nf + ns);
    const sx = new Float32Array(m.nv), sy = new Float32Array(m.nv), sz = new Float32Array(m.nv);
    return { kind: "canvas2d", draw: function () {
      const w = canvas.width, h = canvas.height, k = state.zoom * Math.min(w, h) / 2;
      const r = state.rot, p = m.positions, f = m.faces, c = m.colors;
      ctx.fillStyle = "#fff"; ctx.fillRect(0, 0, w, h);
      for (let i = 0; i < m.nv; i++) {
        const x = p[3 * i], y = p[3 * i + 1], z = p[3 * i + 2];
        sx[i] = w / 2 + k * (r[0][0] * x + r[0][1] * y + r[0][2] * z);
        sy[i] = h / 2 - k * (r[1][0] * x + r[1][1] * y + r[1][2] * z);
        sz[i] = r[2][0] * x + r[2][1] * y + r[2][2] * z;
      }
      for (let t = 0; t < nf; t++) {
        order[t] = t; depth[t] = sz[f[3 * t]] + sz[f[3 * t + 1]] + sz[f[3 * t + 2]];
      }
      const L = m.lines, lw = ns ? m.lineWidth * (window.devicePixelRatio || 1) : 0;
      function project(i, row) {
        return r[row][0] * L[i] + r[row][1] * L[i + 1] + r[row][2] * L[i + 2];
      }
      for (let t = 0; t < ns; t++) {  // depth on the faces' scale (a sum of three), a bit nearer
        order[nf + t] = nf + t;
        depth[nf + t] = 1.5 * (project(6 * t, 2) + project(6 * t + 3, 2)) + 0.01;
      }
      order.sort(function (a, b) { return depth[a] - depth[b]; });
      const lx = 0.3 / 1.1180, ly = 0.4 / 1.1180, lz = 1.0 / 1.1180;
      for (let o = 0; o < nf + ns; o++) {
        if (order[o] >= nf) {
          const i = 6 * (order[o] - nf);
          ctx.strokeStyle = "rgb(" + m.lineColor.join(",") + ")";
          ctx.lineWidth = lw; ctx.lineCap = "round";
          ctx.beginPath();
          ctx.moveTo(w / 2 + k * project(i, 0), h / 2 - k * project(i, 1));
          ctx.lineTo(w / 2 + k * project(i + 3, 0), h / 2 - k * project(i + 3, 1));
          ctx.stroke(); ctx.lineWidth = 1;
          continue;
        }
        const t = order[o], a = f[3 * t], b = f[3 * t + 1], d = f[3 * t + 2];
        const ux = (sx[b] - sx[a]) / k, uy = (sy[a] - sy[b]) / k, uz = sz[b] - sz[a];
        const vx = (sx[d] - sx[a]) / k, vy = (sy[a] - sy[d]) / k, vz = sz[d] - sz[a];
        let nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
        const len = Math.hypot(nx, ny, nz) || 1;
        const s = 0.35 + 0.65 * Math.abs((nx * lx + ny * ly + nz * lz) / len);
        const cr = (c[3 * a] + c[3 * b] + c[3 * d]) / 3 * s;
        const cg = (c[3 * a + 1] + c[3 * b + 1] + c[3 * d + 1]) / 3 * s;
        const cb = (c[3 * a + 2] + c[3 * b + 2] + c[3 * d + 2]) / 3 * s;
        ctx.fillStyle = "rgb(" + (cr | 0) + "," + (cg | 0) + "," + (cb | 0) + ")";
        ctx.strokeStyle = ctx.fillStyle;
        ctx.beginPath(); ctx.moveTo(sx[a], sy[a]); ctx.lineTo(sx[b], sy[b]);
        ctx.lineTo(sx[d], sy[d]); ctx.closePath(); ctx.fill(); ctx.stroke();
      }
    } };
  }

  const panels = document.getElementById("panels");
  const n = data.meshes.length, cols = n <= 4 ? n : Math.ceil(Math.sqrt(n));
  panels.style.gridTemplateColumns = "repeat(" + cols + ", 1fr)";
  panels.style.gridTemplateRows = "repeat(" + Math.ceil(n / cols) + ", 1fr)";
  const kinds = [];
  data.meshes.forEach(function (raw) {
    const m = { nv: raw.nv, positions: new Float32Array(bytes(raw.positions)),
      normals: new Float32Array(bytes(raw.normals)), colors: new Uint8Array(bytes(raw.colors)),
      faces: new Uint32Array(bytes(raw.faces)),
      lines: raw.lines ? new Float32Array(bytes(raw.lines)) : null,
      lineColor: raw.lineColor || [0, 0, 0], lineWidth: raw.lineWidth || 2 };
    const cell = document.createElement("div"), canvas = document.createElement("canvas");
    const text = document.createElement("div");
    cell.className = "cell"; text.className = "text";
    text.textContent = [raw.label, raw.caption].filter(Boolean).join("\n");
    if (data.meshes.some(function (r) { return r.label || r.caption; })) cell.appendChild(text);
    cell.appendChild(canvas); panels.appendChild(cell);
    const view = (force2d ? null : webglView(canvas, m)) || canvasView(canvas, m);
    view.canvas = canvas;
    kinds.push(view.kind);
    state.views.push(view);
    let last = null;
    canvas.addEventListener("pointerdown", function (e) {
      last = [e.clientX, e.clientY]; canvas.setPointerCapture(e.pointerId);
    });
    canvas.addEventListener("pointermove", function (e) {
      if (!last) return;
      turn((e.clientX - last[0]) * 0.01, (e.clientY - last[1]) * 0.01);
      last = [e.clientX, e.clientY]; drawAll();
    });
    canvas.addEventListener("pointerup", function () { last = null; });
    canvas.addEventListener("wheel", function (e) {
      e.preventDefault(); state.zoom *= Math.exp(-e.deltaY * 0.001); drawAll();
    }, { passive: false });
    canvas.addEventListener("dblclick", function () {
      state.rot = start.map(function (r) { return r.slice(); }); state.zoom = 0.9; drawAll();
    });
  });
  function resize() {
    const ratio = window.devicePixelRatio || 1;
    const texts = panels.querySelectorAll(".text");  // one height: the meshes line up
    texts.forEach(function (t) { t.style.minHeight = ""; });
    let tallest = 0;
    texts.forEach(function (t) { tallest = Math.max(tallest, t.offsetHeight); });
    texts.forEach(function (t) { t.style.minHeight = tallest + "px"; });
    state.views.forEach(function (v) {
      v.canvas.width = Math.max(1, Math.round(v.canvas.clientWidth * ratio));
      v.canvas.height = Math.max(1, Math.round(v.canvas.clientHeight * ratio));
    });
    drawAll();
  }
  window.addEventListener("resize", resize);
  resize();
  status.setAttribute("data-renderer", kinds.join(" "));
  status.setAttribute("data-ready", "yes");
})();
"""
