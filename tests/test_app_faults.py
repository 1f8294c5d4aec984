"""``dentopo app`` under bad requests and bad files, against the real server.

Every bad request gets a 4xx with a reason the page shows (JSON ``{"error": ...}``),
never a 500; nothing saved through the page, and no file found in the output
folder (written by an older version, edited by hand, corrupt), can stop the
page's state from loading.
"""

from __future__ import annotations

import asyncio
import json
import os
import shutil
from dataclasses import fields

import pytest

from app_server import make_folder, serving
from dentopo.app import RunOptions
from dentopo.prepare import Protocol
from dentopo.samples import sample_paths

try:  # Python 3.11+
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - Python 3.10 (tomli: a dependency there)
    import tomli as tomllib

pytest.importorskip("starlette")
pytest.importorskip("uvicorn")

#: The POST addresses: every one reads a JSON body.
POSTS = [
    "/api/preview",
    "/api/protocol",
    "/api/run",
    "/api/run/cancel",
    "/api/report",
    "/api/export/prepared",
    "/api/output",
]
DEEP = 100_000
#: Bodies refused before any address looks at them (what is not JSON the page could send).
NOT_JSON = {
    "nested arrays": b"[" * DEEP + b"]" * DEEP,
    "nested objects": b'{"a":' * DEEP + b"0" + b"}" * DEEP,
    "nested 200 deep": b'{"protocol":' + b"[" * 200 + b"]" * 200 + b"}",
    "NaN": b'{"protocol": {"crop_below": NaN}, "bandwidth": NaN}',
    "Infinity": b'{"protocol": {"crop_below": Infinity}, "bandwidth": Infinity}',
    "-Infinity": b'{"cutoff": -Infinity}',
    "overflowing number": b'{"protocol": {"crop_below": 1e999}, "bandwidth": 1e999}',
    "5000 digits": b'{"jobs": ' + b"9" * 5000 + b"}",
    "not UTF-8": b'{"scope": "all", "protocol": {"name": "caf\xe9"}}',
    "lone surrogate": b'{"scope": "all", "protocol": {"name": "\\udc80"}}',
    "lone surrogate key": b'{"\\ud800": 1}',
    "raw control character": b'{"scope": "all", "protocol": {"name": "a\x01b"}}',
    "truncated": b'{"scope": "all"',
    "two values": b"{}{}",
    "NUL": b"\x00",
}
#: Values of every wrong kind, for every field.
HOSTILE = [
    None,
    True,
    -1,
    0,
    2**63,
    10**30,
    -1e308,
    1e308,
    "",
    "x" * 100_000,
    "\x00",
    "\x7f",
    "a\u2028b",
    [],
    [[]],
    {},
    {"a": 1},
    ["a"] * 1000,
    [1e308, 1e308, 1e308],
    [1e308] * 6,
]


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    return make_folder(tmp_path_factory.mktemp("app-faults"))


@pytest.fixture(scope="module")
def server(folder):
    with serving(folder) as running:
        yield running


def refused(answer) -> str:
    """The reason of a refusal: a 4xx whose JSON names the problem."""
    status, headers, data = answer
    assert 400 <= status < 500, (status, data[:300])
    assert headers["content-type"].startswith("application/json"), headers
    reason = json.loads(data)["error"]
    assert isinstance(reason, str) and reason.strip(), data[:300]
    return reason


def never_broken(answer) -> None:
    """Any answer but a 5xx; a refusal says why."""
    status, _, data = answer
    assert status < 500, (status, data[:300])
    if status >= 400:
        refused(answer)


def page_state(server) -> dict:
    status, _, data = server.request("GET", "/api/state")
    assert status == 200, (status, data[:300])
    return json.loads(data)


def post_raw(server, path, data: bytes):
    return server.request("POST", path, body=data, headers={"Content-Type": "application/json"})


@pytest.mark.parametrize(
    "name",
    [
        "\x7f",
        "a\x01b",
        "tab\there\nnext line",
        "\x00",
        "\x1b[31mred",
        "a\u2028b",
        "\udc80",
        "x\ud800",
    ],
)
@pytest.mark.parametrize("scope", ["all", "mesh"])
def test_a_protocol_named_with_a_control_character_is_never_a_500_nor_breaks_the_page(
    server, name, scope
):
    body = {"scope": scope, "path": "tooth.ply", "protocol": {"name": name}}
    try:
        status, _, data = answer = server.request("POST", "/api/protocol", body=body)
        assert status < 500, (status, data[:300])
        if status == 200:  # saved: then it reads back as it was given
            if scope == "all":
                assert page_state(server)["protocol"]["name"] == name
            query = "?path=tooth.ply" if scope == "mesh" else ""
            status, _, saved = server.request("GET", "/api/protocol.toml" + query)
            assert status == 200 and tomllib.loads(saved.decode("utf-8"))["name"] == name
        else:
            reason = refused(answer)
            if "\udc80" in name or "\ud800" in name:
                assert "surrogate" in reason, reason
        state = page_state(server)
        tooth = next(m for m in state["meshes"] if m["path"] == "tooth.ply")
        assert not tooth.get("protocol_error") and not state.get("protocol_error")
    finally:
        server.request("POST", "/api/protocol", body={**body, "protocol": None})
    page_state(server)


@pytest.mark.parametrize("path", POSTS)
@pytest.mark.parametrize("kind", list(NOT_JSON))
def test_a_body_that_is_not_plain_json_is_refused_naming_the_problem(server, path, kind):
    reason = refused(post_raw(server, path, NOT_JSON[kind])).lower()
    expected = {
        "nested arrays": "nested",
        "nested objects": "nested",
        "nested 200 deep": "nested",
        "NaN": "nan",
        "Infinity": "infinity",
        "-Infinity": "infinity",
        "overflowing number": "large",
        "not UTF-8": "utf-8",
        "lone surrogate": "surrogate",
        "lone surrogate key": "surrogate",
    }
    assert expected.get(kind, "json") in reason, reason
    page_state(server)


def test_the_preview_of_a_diverging_protocol_is_refused_with_the_reason(server):
    protocol = {"smooth": "laplacian", "smooth_iterations": 200, "smooth_step": 1e9}
    body = {"path": "tooth.ply", "protocol": protocol}
    reason = refused(server.request("POST", "/api/preview", body=body)).lower()
    assert "finite" in reason or "diverg" in reason, reason
    assert "smooth" in reason, reason
    page_state(server)


def _bodies():
    """(address, body): wrong bodies for the addresses that read their fields."""
    protocol_fields = [f.name for f in fields(Protocol)]
    for value in HOSTILE:
        for path in ("/api/preview", "/api/protocol", "/api/run"):
            if not isinstance(value, dict):
                yield path, value  # not an object
        yield "/api/preview", {"path": value, "protocol": {}}
        yield "/api/protocol", {"scope": value, "protocol": {}}
        yield "/api/protocol", {"scope": "mesh", "path": value, "protocol": {}}
        yield "/api/protocol", {"scope": "all", "protocol": None, "prepare": value}
        for name in protocol_fields:
            yield "/api/preview", {"path": "tooth.ply", "protocol": {name: value}}
            yield "/api/protocol", {"scope": "all", "protocol": {name: value}}
            smoothing = {"smooth": "taubin", name: value}
            yield "/api/protocol", {"scope": "mesh", "path": "sphere.ply", "protocol": smoothing}
        for option in (f.name for f in fields(RunOptions)):
            if option == "prepare":
                if not isinstance(value, bool):
                    yield "/api/run", {"prepare": value}
            elif option == "jobs":
                yield "/api/run", {"jobs": value, "prepare": "no"}  # never a run
            else:
                yield "/api/run", {option: value, "jobs": 0}  # never a run


def test_hostile_bodies_on_every_post_address_never_get_a_5xx(server):
    for path in POSTS:
        for data in NOT_JSON.values():
            never_broken(post_raw(server, path, data))
    for path, body in _bodies():
        answer = server.request("POST", path, body=body)
        assert answer[0] < 500, (path, repr(body)[:200], answer[2][:300])
        never_broken(answer)
        if path == "/api/run":
            assert answer[0] >= 400, (body, answer)  # no run was started
    server.request("POST", "/api/protocol", body={"scope": "all", "protocol": None})
    server.request(
        "POST", "/api/protocol", body={"scope": "mesh", "path": "sphere.ply", "protocol": None}
    )
    page_state(server)


#: Files an older version, a hand edit or a crash may leave: (file below the output folder, its
#: bytes, or None for a folder in its place).
BAD_FILES = [
    ("protocol.toml", b"name = [unclosed\n"),
    ("protocol.toml", b"\xff\xfe n\x00a\x00"),
    ("protocol.toml", b"smooth_step = 0.5\n"),
    ("protocol.toml", b"colour = 'red'\n"),
    ("protocol.toml", b'name = "\x7f"\n'),
    ("protocol.toml", b"a = " + b"[" * 5000 + b"]" * 5000 + b"\n"),
    ("protocol.toml", None),
    ("protocols/tooth.ply.toml", b"name = [unclosed\n"),
    ("protocols/tooth.ply.toml", b"\xff"),
    ("protocols/tooth.ply.toml", b"[decimate]\nfaces = -4\n"),
    ("protocols/tooth.ply.toml", None),
    (".app/prepare.json", b"[1]"),
    (".app/prepare.json", b'"prepare"'),
    (".app/prepare.json", b"[" * 100_000),
    (".app/prepare.json", b"\xff"),
    (".app/prepare.json", None),
    (".app/run.json", b"[]"),
    (".app/run.json", b'{"metrics": {}}'),
    (".app/run.json", b'{"metrics": [[]], "bandwidth": "wide"}'),
    (".app/run.json", b'{"jobs": 1e999, "bandwidth": NaN}'),
    (".app/run.json", b"[" * 100_000 + b"]" * 100_000),
    (".app/run.json", b"\xff"),
    (".app/run.json", None),
]


@pytest.mark.parametrize(("name", "data"), BAD_FILES, ids=lambda v: repr(v)[:40])
def test_a_bad_file_in_the_output_folder_never_stops_the_page(server, name, data):
    path = os.path.join(page_state(server)["output"], *name.split("/"))
    os.makedirs(os.path.dirname(path), exist_ok=True)
    if data is None:
        os.makedirs(path)
    else:
        with open(path, "wb") as stream:
            stream.write(data)
    try:
        state = page_state(server)
        for address in ("/api/run", "/api/results", "/api/report", "/api/export/prepared"):
            assert server.request("GET", address)[0] == 200, address
        if name == "protocol.toml":  # listed with its error; a run that would use it says why
            assert state["protocol"] is None and state["protocol_error"], state["protocol_error"]
            assert "protocol.toml" in refused(
                server.request("POST", "/api/run", body={"prepare": True})
            )
        elif name.startswith("protocols/"):
            tooth = next(m for m in state["meshes"] if m["path"] == "tooth.ply")
            assert tooth["protocol"] == "own" and tooth["protocol_error"], tooth
            assert "tooth.ply" in refused(
                server.request("POST", "/api/run", body={"prepare": True})
            )
        elif name == ".app/prepare.json":
            assert state["prepare"] is False
        else:
            assert state["last_run"] == RunOptions().to_json()
    finally:
        if os.path.isdir(path):
            shutil.rmtree(path)
        else:
            os.unlink(path)
    page_state(server)


def test_a_mesh_whose_name_is_not_utf8_is_listed_and_the_page_loads(tmp_path):
    folder = tmp_path / "study"
    folder.mkdir()
    sample = str(sample_paths()["tooth"])
    shutil.copy(sample, folder / "tooth.ply")
    shutil.copy(sample, os.path.join(os.fsencode(folder), b"caf\xe9.ply"))
    with serving(folder) as running:
        state = page_state(running)
        assert len(state["meshes"]) == 2
        odd = next(m for m in state["meshes"] if m["path"] != "tooth.ply")
        assert "UTF-8" in odd["error"], odd
        tooth = next(m for m in state["meshes"] if m["path"] == "tooth.ply")
        assert tooth["error"] is None and tooth["faces"] > 0
        run = running.json("POST", "/api/run", {"metrics": ["slope"], "jobs": 1})
        assert list(run["files"]) == ["tooth.ply"]  # the page could not name the other one
        assert running.wait_run()["state"] == "done"
        page_state(running)


def _asgi_get(app, path: str, token: str, headers=()):
    """(status, headers, body) of one GET sent straight to the ASGI application."""
    sent = []

    async def receive():
        return {"type": "http.request", "body": b"", "more_body": False}

    async def send(message):
        sent.append(message)

    scope = {
        "type": "http",
        "method": "GET",
        "path": path,
        "raw_path": path.encode(),
        "query_string": b"",
        "root_path": "",
        "scheme": "http",
        "server": ("127.0.0.1", 8000),
        "client": ("127.0.0.1", 50000),
        "headers": [
            (b"host", b"127.0.0.1:8000"),
            (b"x-dentopo-token", token.encode()),
            *headers,
        ],
        "http_version": "1.1",
    }
    asyncio.run(app(scope, receive, send))
    start = next(m for m in sent if m["type"] == "http.response.start")
    body = b"".join(m.get("body", b"") for m in sent if m["type"] == "http.response.body")
    return start["status"], {k.decode(): v.decode() for k, v in start["headers"]}, body


def test_an_unexpected_error_is_a_500_with_a_short_reason_and_no_traceback(tmp_path):
    from dentopo.app import Workspace
    from dentopo.app._routes import build_app

    folder = tmp_path / "study"
    folder.mkdir()
    workspace = Workspace(str(folder))
    try:

        def broken():
            raise RuntimeError("something the app did not expect")

        workspace.results = broken
        app = build_app(workspace, "secret", port=8000)
        status, headers, body = _asgi_get(app, "/api/results", "secret")
        assert status == 500
        assert headers["content-type"].startswith("application/json")
        reason = json.loads(body)["error"]
        assert "something the app did not expect" in reason and "Traceback" not in reason
        assert len(reason) < 400
        assert _asgi_get(app, "/api/state", "secret")[0] == 200
    finally:
        workspace.close()


def test_a_large_state_is_gzipped_for_a_browser_that_takes_it(tmp_path):
    import gzip

    from dentopo.app import Workspace
    from dentopo.app._routes import build_app

    folder = tmp_path / "study"
    folder.mkdir()
    mesh = sample_paths()["tooth"].read_bytes()
    for index in range(300):
        (folder / f"specimen-{index:04d}.ply").write_bytes(mesh)
    workspace = Workspace(str(folder))
    workspace.folder.close()  # the listing is enough: the meshes are not read
    try:
        app = build_app(workspace, "secret", port=8000)
        status, headers, plain = _asgi_get(app, "/api/state", "secret")
        assert status == 200 and "content-encoding" not in headers
        status, headers, packed = _asgi_get(
            app, "/api/state", "secret", [(b"accept-encoding", b"gzip, deflate")]
        )
        assert status == 200 and headers["content-encoding"] == "gzip"
        assert headers["vary"] == "Accept-Encoding" and len(packed) < len(plain) / 3
        # the same listing (the meshes' counts may be read in the background between the two)
        listed = [mesh["path"] for mesh in json.loads(gzip.decompress(packed))["meshes"]]
        assert listed == [mesh["path"] for mesh in json.loads(plain)["meshes"]]
        assert len(listed) == 300
    finally:
        workspace.close()
