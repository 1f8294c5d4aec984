"""The app's addresses: the page, its assets, the JSON API, the output folder's files.

Starlette (a small, well-kept ASGI toolkit: routing, requests, responses and
file serving, nothing more) under :class:`._security.Guard`.  Every handler is a
few lines over :class:`._workspace.Workspace`; slow work (reading a mesh for a
preview, writing an export) runs in a worker thread so the server keeps
answering.  Errors are JSON ``{"error": message}`` (the page shows the message):
a 4xx for every bad request (the app's own refusals, the library's errors,
which are ``ValueError`` subclasses, and a body that is not plain JSON: too
deep, not UTF-8, a lone surrogate, NaN, Infinity or a number out of range), and
as a last resort a 500 whose message is one line, never a traceback (that goes
to the server's log).  JSON answers are gzipped when large and the browser
takes gzip (the state of a 5,000-mesh folder: 700 kB, 60 kB gzipped).
"""

from __future__ import annotations

import gzip
import html
import json
import logging
import math
import os
from importlib import resources

from starlette.applications import Starlette
from starlette.concurrency import run_in_threadpool
from starlette.requests import Request
from starlette.responses import FileResponse, JSONResponse, Response
from starlette.routing import Route

from ._pictures import Drawing
from ._security import Guard, PathRefusedError, inside
from ._workspace import AppError, Workspace

#: Largest request body accepted (the page sends small JSON; nothing is uploaded).
MAX_BODY = 1 << 20
#: Deepest nesting of a request's JSON (the page's is 3 deep).
MAX_DEPTH = 32
#: JSON answers larger than this are gzipped (when the browser takes gzip).
GZIP_BYTES = 16 << 10
#: Longest message of an unexpected error (one line; the traceback goes to the log).
MAX_REASON = 300

log = logging.getLogger(__name__)

#: The page's assets: name -> (package file, MIME type).
ASSETS = {
    "app.js": ("app.js", "text/javascript; charset=utf-8"),
    "app.css": ("app.css", "text/css; charset=utf-8"),
}


JS = "text/javascript; charset=utf-8"
#: The page's assets may be kept by the browser for a while (plotly.js is 4.8 MB); the rest of
#: the app's answers are never stored (Guard's ``no-store``).
CACHED = {"cache-control": "private, max-age=600"}


def _static(name: str) -> bytes:
    return resources.files("dentopo.app").joinpath("static", name).read_bytes()


class JSON(JSONResponse):
    """A JSON answer in ASCII: a name that is not valid UTF-8 (a lone surrogate) is escaped."""

    def render(self, content) -> bytes:
        return json.dumps(content, allow_nan=False, separators=(",", ":")).encode("ascii")


def _json(request: Request, content, status: int = 200) -> Response:
    """`content` as JSON, gzipped if large and the browser takes gzip."""
    answer = JSON(content, status_code=status)
    accepted = request.headers.get("accept-encoding", "")
    if len(answer.body) > GZIP_BYTES and "gzip" in accepted.lower():
        body = gzip.compress(answer.body, compresslevel=5, mtime=0)
        headers = {"content-encoding": "gzip", "vary": "Accept-Encoding"}
        return Response(body, status, headers=headers, media_type="application/json")
    return answer


def _error(message: str, status: int = 400) -> JSONResponse:
    return JSON({"error": message}, status_code=status)


def _no_constant(name: str):
    raise ValueError(f"{name} is not a number (send numbers only)")


def _finite(text: str) -> float:
    value = float(text)
    if not math.isfinite(value):
        raise ValueError(f"the number {text[:40]} is too large")
    return value


def _check_plain(data) -> None:
    """That `data` (a request's JSON) is at most :data:`MAX_DEPTH` deep and its texts Unicode."""
    waiting = [(data, 1)]
    while waiting:
        item, depth = waiting.pop()
        if isinstance(item, str):
            items = (item,)
        elif isinstance(item, (list, dict)):
            if depth > MAX_DEPTH:
                raise AppError(f"the request is nested too deeply (more than {MAX_DEPTH} levels)")
            items = (*item, *item.values()) if isinstance(item, dict) else item
            waiting.extend((x, depth + 1) for x in items if isinstance(x, (list, dict)))
            items = [x for x in items if isinstance(x, str)]
        else:
            continue
        for text in items:
            try:
                text.encode("utf-8")
            except UnicodeEncodeError as exc:
                bad = repr(text[exc.start])  # '\\udc80'
                raise AppError(
                    f"the request holds a lone surrogate ({bad[1:-1]}): texts must be Unicode"
                ) from None


async def _json_body(request: Request):
    length = request.headers.get("content-length")
    if length is not None and (not length.isdigit() or int(length) > MAX_BODY):
        raise AppError("the request is too large", 413)
    body = b""
    async for chunk in request.stream():
        body += chunk
        if len(body) > MAX_BODY:
            raise AppError("the request is too large", 413)
    if request.headers.get("content-type", "").split(";")[0].strip() != "application/json":
        raise AppError("send JSON (Content-Type: application/json)", 415)
    try:
        text = (body or b"{}").decode("utf-8")
    except UnicodeDecodeError as exc:
        raise AppError(f"the request is not UTF-8 text (byte {exc.start})") from None
    try:
        data = json.loads(text, parse_constant=_no_constant, parse_float=_finite)
    except RecursionError:
        raise AppError(f"the request is nested too deeply (more than {MAX_DEPTH} levels)") from None
    except ValueError as exc:  # not JSON, NaN or Infinity, a number out of range
        raise AppError(f"the request is not valid JSON: {exc}") from None
    _check_plain(data)
    return data


def _reason(exc: BaseException) -> str:
    """An exception's message on one short line (its type if it has none)."""
    text = " ".join(str(exc).split()) or type(exc).__name__
    return text if len(text) <= MAX_REASON else text[: MAX_REASON - 1] + "\u2026"


def build_app(
    workspace: Workspace, token: str, *, port: int = 0, hosts=(), any_address: bool = False
) -> Guard:
    """The ASGI application for `workspace`, behind the guard of secret `token`."""

    def handled(function):
        async def endpoint(request: Request):
            try:
                return await function(request)
            except AppError as exc:
                return _error(str(exc), exc.status)
            except PathRefusedError as exc:
                return _error(f"refused: {exc}", 403)
            except (ValueError, OverflowError) as exc:  # the library's errors: a bad request
                return _error(_reason(exc))
            except Exception as exc:  # a bug: a short reason the page shows, the rest logged
                log.error(
                    "dentopo app: %s %s failed", request.method, request.url.path, exc_info=True
                )
                return _error(f"the app failed ({_reason(exc)}): see the server's messages", 500)

        return endpoint

    async def index(request: Request):
        page = _static("index.html").decode("utf-8")
        page = page.replace("%TOKEN%", html.escape(token, quote=True))
        return Response(page, media_type="text/html; charset=utf-8")

    async def asset(request: Request):
        name = request.path_params["name"]
        if name == "plotly.min.js":
            from plotly.offline import get_plotlyjs

            return Response(get_plotlyjs(), media_type=JS, headers=CACHED)
        if name == "viewer.js":
            from ..report import UNPACK_JS

            return Response(UNPACK_JS, media_type=JS, headers=CACHED)
        if name not in ASSETS:
            return _error("no such file", 404)
        file, mime = ASSETS[name]
        return Response(_static(file), media_type=mime, headers=CACHED)

    async def state(request: Request):
        return _json(request, await run_in_threadpool(workspace.state))

    async def thumbnail(request: Request):
        entry = workspace.mesh(request.query_params.get("path"))
        if entry.thumbnail is None:
            return _error("no thumbnail (yet)", 404)
        return FileResponse(entry.thumbnail, media_type="image/png")

    async def preview(request: Request):
        body = await _json_body(request)
        if not isinstance(body, dict):
            raise AppError("send an object: {path, protocol}")
        result = await run_in_threadpool(workspace.preview, body.get("path"), body.get("protocol"))
        return _json(request, result)

    async def protocol(request: Request):
        body = await _json_body(request)
        if not isinstance(body, dict):
            raise AppError("send an object: {scope, path, protocol}")
        if "prepare" in body and not isinstance(body["prepare"], bool):
            raise AppError("prepare must be true or false")  # checked before anything is saved
        await run_in_threadpool(
            workspace.save_protocol, body.get("scope"), body.get("path"), body.get("protocol")
        )
        if "prepare" in body:
            workspace.set_prepares(body["prepare"])
        return _json(request, await run_in_threadpool(workspace.state))

    async def protocol_file(request: Request):
        relative = request.query_params.get("path")
        if relative is None:
            path, name = workspace.protocol_file, "protocol.toml"
        else:
            workspace.mesh(relative)
            path = workspace.protocol_path(relative)  # as it is, even if it does not read
            name = os.path.basename(relative) + ".toml"
        if path is None or not os.path.isfile(path):
            return _error("no protocol saved yet", 404)
        return FileResponse(
            path,
            media_type="application/toml",
            filename=name,
            content_disposition_type="attachment",
        )

    async def run(request: Request):
        if request.method == "POST":
            body = await _json_body(request)
            return _json(request, await run_in_threadpool(workspace.start_run, body))
        return _json(request, await run_in_threadpool(workspace.run_state))

    async def output(request: Request):
        body = await _json_body(request)
        if not isinstance(body, dict):
            raise AppError("send an object: {output}")
        return _json(request, await run_in_threadpool(workspace.choose_output, body.get("output")))

    async def cancel(request: Request):
        await _json_body(request)
        return _json(request, await run_in_threadpool(workspace.cancel_run))

    async def results(request: Request):
        return _json(request, await run_in_threadpool(workspace.results))

    async def map_picture(request: Request):
        found = await run_in_threadpool(
            workspace.map_picture,
            request.query_params.get("path"),
            request.query_params.get("metric"),
        )
        if isinstance(found, Drawing):
            if found.state == "failed":
                return _error(found.error or "the picture could not be drawn", 422)
            return _json(request, {"state": "drawing"}, 202)
        return FileResponse(found, media_type="image/png")

    def started(start, state):
        """An endpoint whose POST starts a job (`start`) and whose GET says how it goes."""

        async def endpoint(request: Request):
            if request.method == "POST":
                await _json_body(request)  # unused, but checked like every body (JSON, small)
                return _json(request, await run_in_threadpool(start))
            return _json(request, state())

        return endpoint

    report = started(workspace.start_report, workspace.report_state)

    async def export_table(request: Request):
        data, name, mime = await run_in_threadpool(
            workspace.export_table, request.query_params.get("format", "csv")
        )
        return Response(
            data, media_type=mime, headers={"content-disposition": f'attachment; filename="{name}"'}
        )

    export_prepared = started(workspace.start_export, workspace.export_state)

    async def prepared_zip(request: Request):
        data = await run_in_threadpool(workspace.prepared_zip)
        return Response(
            data,
            media_type="application/zip",
            headers={"content-disposition": 'attachment; filename="prepared.zip"'},
        )

    async def output_file(request: Request):
        relative = request.path_params["path"]
        if relative.split("/")[0] == ".app":
            return _error("no such file", 404)
        path = inside(workspace.output, relative)
        if not os.path.isfile(path):
            return _error("no such file", 404)
        return FileResponse(path)

    async def not_found(request: Request, exc):
        return _error("no such address", 404)

    async def not_allowed(request: Request, exc):
        return _error("method not allowed", 405)

    routes = [
        Route("/", handled(index)),
        Route("/static/{name}", handled(asset)),
        Route("/api/state", handled(state)),
        Route("/api/thumbnail", handled(thumbnail)),
        Route("/api/preview", handled(preview), methods=["POST"]),
        Route("/api/protocol", handled(protocol), methods=["POST"]),
        Route("/api/protocol.toml", handled(protocol_file)),
        Route("/api/run", handled(run), methods=["GET", "POST"]),
        Route("/api/run/cancel", handled(cancel), methods=["POST"]),
        Route("/api/output", handled(output), methods=["POST"]),
        Route("/api/results", handled(results)),
        Route("/api/map", handled(map_picture)),
        Route("/api/report", handled(report), methods=["GET", "POST"]),
        Route("/api/export/table", handled(export_table)),
        Route("/api/export/prepared", handled(export_prepared), methods=["GET", "POST"]),
        Route("/api/export/prepared.zip", handled(prepared_zip)),
        Route("/output/{path:path}", handled(output_file)),
    ]
    app = Starlette(routes=routes, exception_handlers={404: not_found, 405: not_allowed})
    return Guard(app, token, port=port, hosts=hosts, any_address=any_address)
