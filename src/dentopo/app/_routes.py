"""The app's addresses: the page, its assets, the JSON API, the output folder's files.

Starlette (a small, well-kept ASGI toolkit: routing, requests, responses and
file serving, nothing more) under :class:`._security.Guard`.  Every handler is a
few lines over :class:`._workspace.Workspace`; slow work (reading a mesh for a
preview, writing an export) runs in a worker thread so the server keeps
answering.  Errors are JSON ``{"error": message}`` with a 4xx status.
"""

from __future__ import annotations

import html
import json
import os
from importlib import resources

from starlette.applications import Starlette
from starlette.concurrency import run_in_threadpool
from starlette.requests import Request
from starlette.responses import FileResponse, JSONResponse, Response
from starlette.routing import Route

from ._jobs import Job
from ._security import Guard, PathRefusedError, inside
from ._workspace import AppError, Workspace

#: Largest request body accepted (the page sends small JSON; nothing is uploaded).
MAX_BODY = 1 << 20

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


def _error(message: str, status: int = 400) -> JSONResponse:
    return JSONResponse({"error": message}, status_code=status)


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
        return json.loads(body or b"{}")
    except ValueError:
        raise AppError("the request is not valid JSON") from None


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
        return JSONResponse(await run_in_threadpool(workspace.state))

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
        return JSONResponse(result)

    async def protocol(request: Request):
        body = await _json_body(request)
        if not isinstance(body, dict):
            raise AppError("send an object: {scope, path, protocol}")
        await run_in_threadpool(
            workspace.save_protocol, body.get("scope"), body.get("path"), body.get("protocol")
        )
        if "prepare" in body:
            if not isinstance(body["prepare"], bool):
                raise AppError("prepare must be true or false")
            workspace.set_prepares(body["prepare"])
        return JSONResponse(await run_in_threadpool(workspace.state))

    async def protocol_file(request: Request):
        relative = request.query_params.get("path")
        if relative is None:
            path, name = workspace.protocol_file, "protocol.toml"
        else:
            workspace.mesh(relative)
            path = workspace.protocol_for(relative)[1]
            name = os.path.basename(relative) + ".toml"
        if path is None or not os.path.exists(path):
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
            return JSONResponse(await run_in_threadpool(workspace.start_run, body))
        return JSONResponse(await run_in_threadpool(workspace.run_state))

    async def cancel(request: Request):
        await _json_body(request)
        return JSONResponse(await run_in_threadpool(workspace.cancel_run))

    async def results(request: Request):
        return JSONResponse(await run_in_threadpool(workspace.results))

    async def map_picture(request: Request):
        found = await run_in_threadpool(
            workspace.map_picture,
            request.query_params.get("path"),
            request.query_params.get("metric"),
        )
        if isinstance(found, Job):
            if found.state == "failed":
                lines = [line for line in found.log if line.strip()]
                reason = lines[-1] if lines else "the picture could not be drawn"
                return _error(reason, 422)
            return JSONResponse({"state": "drawing"}, status_code=202)
        return FileResponse(found, media_type="image/png")

    def started(start, state):
        """An endpoint whose POST starts a job (`start`) and whose GET says how it goes."""

        async def endpoint(request: Request):
            if request.method == "POST":
                await _json_body(request)  # unused, but checked like every body (JSON, small)
                return JSONResponse(await run_in_threadpool(start))
            return JSONResponse(state())

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
