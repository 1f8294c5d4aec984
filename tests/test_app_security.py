"""``dentopo app``'s door, tested against the real server: the secret, Host, origin, paths.

Each test sends raw requests (``http.client``: the path and the headers as
given, nothing normalised) to a server started as a user starts it.
"""

from __future__ import annotations

import json
import os
import socket
import time
import urllib.parse

import pytest

from app_server import HOSTILE, make_folder, serving
from dentopo.app import PathRefusedError, inside

pytest.importorskip("starlette")
pytest.importorskip("uvicorn")

SECRET_TEXT = "the contents of a file outside the folder"


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    root = tmp_path_factory.mktemp("app-security")
    folder = make_folder(root)
    outside = root / "outside"
    outside.mkdir()
    (outside / "secret.ply").write_text(SECRET_TEXT)
    (outside / "secret.txt").write_text(SECRET_TEXT)
    os.symlink(outside / "secret.ply", folder / "link-out.ply")  # a mesh that leads out
    os.symlink(outside, folder / "dir-out")  # a folder that leads out
    return folder, outside


@pytest.fixture(scope="module")
def server(study):
    folder, _ = study
    with serving(folder) as running:
        yield running


def test_the_address_is_the_loopback_with_a_long_secret(server):
    assert server.url.startswith("http://127.0.0.1:")
    assert len(server.token) >= 32
    assert sum("token=" in line for line in server.lines) == 1  # one line carries it


def test_listens_on_the_loopback_only(server):
    probe = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    try:
        probe.connect(("10.255.255.255", 1))  # no packet is sent: it picks the outward address
        address = probe.getsockname()[0]
    except OSError:
        address = None
    finally:
        probe.close()
    if address is None or address.startswith("127."):
        pytest.skip("this machine has no address but the loopback to try")
    with pytest.raises(OSError):
        socket.create_connection((address, server.port), timeout=5).close()
    socket.create_connection(("127.0.0.1", server.port), timeout=5).close()


@pytest.mark.parametrize(
    "path", ["/", "/api/state", "/static/app.js", "/api/results", "/output/results.csv"]
)
def test_no_secret_is_401_and_a_wrong_one_403(server, path):
    status, _, body = server.request("GET", path, token=False)
    assert status == 401, body
    assert b"secret" in body
    wrong = server.token[:-1] + ("A" if server.token[-1] != "A" else "B")
    status, _, _ = server.request("GET", path, token=False, headers={"X-Dentopo-Token": wrong})
    assert status == 403
    joiner = "&" if "?" in path else "?"
    status, _, _ = server.request("GET", f"{path}{joiner}token={wrong}", token=False)
    assert status == 403
    cookie = f"dentopo-app-{server.port}={wrong}"
    status, _, _ = server.request("GET", path, token=False, headers={"Cookie": cookie})
    assert status == 403


def test_the_first_visit_keeps_the_secret_in_a_strict_cookie(server):
    status, headers, _ = server.request("GET", f"/?token={server.token}", token=False)
    assert status == 303 and headers["location"] == "/"
    cookie = headers["set-cookie"]
    assert "HttpOnly" in cookie and "SameSite=Strict" in cookie
    name_value = cookie.split(";")[0]
    status, headers, body = server.request("GET", "/", token=False, headers={"Cookie": name_value})
    assert status == 200 and b"<html" in body.lower()
    assert server.token.encode() in body  # in the page's meta, for its own requests


@pytest.mark.parametrize(
    "host",
    [
        "evil.example:{port}",  # DNS rebinding: the attacker's name pointed at 127.0.0.1
        "127.0.0.1.evil.example:{port}",
        "127.0.0.1:{other}",  # another port: another app
        "localhost.:{port}",
        "",
    ],
)
def test_a_foreign_host_is_refused_even_with_the_secret(server, host):
    host = host.format(port=server.port, other=server.port + 1)
    status, _, body = server.request("GET", "/api/state", host=host)
    assert status in (400, 403), body
    assert b'"meshes"' not in body


@pytest.mark.parametrize("host", ["127.0.0.1:{port}", "localhost:{port}"])
def test_the_loopback_names_are_accepted(server, host):
    status, _, _ = server.request("GET", "/api/state", host=host.format(port=server.port))
    assert status == 200


def test_changes_need_the_header_not_just_the_cookie(server):
    cookie = f"dentopo-app-{server.port}={server.token}"
    status, _, body = server.request(
        "POST", "/api/run/cancel", body={}, token=False, headers={"Cookie": cookie}
    )
    assert status == 403 and b"page" in body  # a form on another site can send the cookie


@pytest.mark.parametrize(
    "headers",
    [
        {"Origin": "http://evil.example"},
        {"Origin": "null"},
        {"Origin": "http://127.0.0.1:1"},
        {"Sec-Fetch-Site": "cross-site"},
        {"Sec-Fetch-Site": "same-site"},
    ],
)
def test_changes_from_another_origin_are_refused(server, headers):
    status, _, body = server.request("POST", "/api/run/cancel", body={}, headers=headers)
    assert status == 403, body


def test_changes_from_the_page_itself_are_accepted(server):
    origin = {"Origin": f"http://127.0.0.1:{server.port}", "Sec-Fetch-Site": "same-origin"}
    status, _, body = server.request("POST", "/api/run/cancel", body={}, headers=origin)
    assert status == 200, body


def test_every_response_has_the_policy_and_no_sniffing(server):
    for path, token in (("/", True), ("/api/state", True), ("/api/state", False)):
        _, headers, _ = server.request("GET", path, token=token)
        policy = headers["content-security-policy"]
        assert "default-src 'none'" in policy and "connect-src 'self'" in policy
        assert "frame-ancestors 'none'" in policy
        assert headers["x-content-type-options"] == "nosniff"
        assert headers["referrer-policy"] == "no-referrer"


def test_only_the_assets_may_be_kept_by_the_browser(server):
    for path in ("/", "/api/state", "/api/results"):
        assert server.request("GET", path)[1]["cache-control"] == "no-store"
    _, headers, _ = server.request("GET", "/static/app.js")
    assert headers["cache-control"].startswith("private")
    _, headers, _ = server.request("GET", "/static/app.js", token=False)
    assert headers["cache-control"] == "no-store"  # a refusal is never kept


def test_the_page_and_its_scripts_name_no_other_site(server):
    for path in ("/", "/static/app.js", "/static/app.css", "/static/viewer.js"):
        status, _, body = server.request("GET", path)
        assert status == 200, path
        text = body.decode()
        assert "http://" not in text and "https://" not in text, path
        assert "innerHTML" not in text or path != "/static/app.js"


TRAVERSALS = [
    "../outside/secret.ply",
    "%2e%2e/outside/secret.ply",
    "%2E%2E%2Foutside%2Fsecret.ply",
    "..%2foutside%2fsecret.ply",
    "/etc/passwd",
    "group-a/../../outside/secret.ply",
    "./bad.ply",
    "link-out.ply",  # a symlink out of the folder
    "dir-out/secret.ply",  # through a symlinked folder
    "bad.ply%00.png",
    "..\\outside\\secret.ply",
]


@pytest.mark.parametrize("path", TRAVERSALS)
def test_no_path_leads_out_of_the_folder(server, path):
    for address in (
        f"/api/thumbnail?path={path}",
        f"/api/map?path={path}&metric=slope",
        f"/api/protocol.toml?path={path}",
    ):
        status, _, body = server.request("GET", address)
        assert status in (403, 404), (address, status, body)
        assert SECRET_TEXT.encode() not in body
    status, _, body = server.request(
        "POST", "/api/preview", body={"path": urllib.parse.unquote(path), "protocol": {}}
    )
    assert status in (403, 404), (path, status, body)
    status, _, body = server.request(
        "POST",
        "/api/protocol",
        body={"scope": "mesh", "path": urllib.parse.unquote(path), "protocol": {}},
    )
    assert status in (403, 404), (path, status, body)


@pytest.mark.parametrize("path", [*TRAVERSALS, "/tmp/elsewhere", "", "group-a", "tooth.ply"])
def test_the_output_folder_chosen_on_the_page_stays_in_the_folder(server, study, path):
    before = server.json("GET", "/api/state")["output"]
    answer = server.request("POST", "/api/output", body={"output": urllib.parse.unquote(path)})
    assert answer[0] in (400, 403), (path, answer)  # out, a file, or the folder's meshes
    assert server.json("GET", "/api/state")["output"] == before
    assert sorted(os.listdir(study[1])) == ["secret.ply", "secret.txt"]  # nothing written there


@pytest.mark.parametrize(
    "address",
    [
        "/output/../../outside/secret.txt",
        "/output/%2e%2e/%2e%2e/outside/secret.txt",
        "/output/%2e%2e%2f%2e%2e%2foutside%2fsecret.txt",
        "/output/..%2f..%2foutside%2fsecret.txt",
        "/static/..%2f..%2f..%2fetc%2fpasswd",
        "/static/../../../etc/passwd",
        "/output/.app/run.json",
    ],
)
def test_the_output_folder_serves_nothing_else(server, study, address):
    status, _, body = server.request("GET", address)
    assert status in (403, 404), (address, status)
    assert SECRET_TEXT.encode() not in body and b"root:" not in body


def test_a_symlink_out_is_not_listed(server):
    paths = [m["path"] for m in server.json("GET", "/api/state")["meshes"]]
    assert "link-out.ply" not in paths and not any(p.startswith("dir-out") for p in paths)
    assert "bad.ply" in paths and HOSTILE in paths


def test_names_are_data_in_json_never_markup_in_the_page(server):
    state = server.json("GET", "/api/state")
    bad = next(m for m in state["meshes"] if m["path"] == "bad.ply")
    assert bad["error"]  # the corrupt file shows why
    _, _, page = server.request("GET", "/")
    assert b"onerror" not in page  # the page is static: names come as JSON, set as text


def test_a_large_body_is_refused(server):
    status, _, _ = server.request(
        "POST",
        "/api/preview",
        body=b"{" + b" " * (2 << 20) + b"}",
        headers={"Content-Type": "application/json"},
    )
    assert status == 413


def test_a_body_that_is_not_json_is_refused(server):
    status, _, body = server.request(
        "POST", "/api/run", body=b"metrics=ariadne", headers={"Content-Type": "text/plain"}
    )
    assert status == 415, body  # a form post cannot pass for the page's JSON


@pytest.mark.parametrize(
    "options, named",
    [
        ({"metrics": ["nonsense"]}, "nonsense"),
        ({"metrics": []}, "metric"),
        ({"bandwidth": -1}, "bandwidth"),
        ({"bandwidth": "0.1; rm -rf /"}, "bandwidth"),
        ({"jobs": 0}, "jobs"),
        ({"method": "--output=/etc/x"}, "method"),
        ({"colour": "red"}, "colour"),
    ],
)
def test_wrong_run_options_are_refused_naming_them(server, options, named):
    status, _, body = server.request("POST", "/api/run", body=options)
    assert status == 400 and named in json.loads(body)["error"], body


def test_protocol_values_are_checked(server):
    status, _, body = server.request(
        "POST", "/api/protocol", body={"scope": "all", "protocol": {"crop_fraction": 7}}
    )
    assert status == 400 and "crop_fraction" in json.loads(body)["error"]


@pytest.mark.parametrize(
    "relative",
    ["", "/etc", "../x", "a/../b", "a/./b", "a//b", "a\\b", "x\x00y"],
)
def test_inside_refuses_paths_that_are_not_plain(tmp_path, relative):
    with pytest.raises(PathRefusedError):
        inside(str(tmp_path), relative)


def test_inside_follows_symlinks(tmp_path):
    (tmp_path / "in").mkdir()
    (tmp_path / "in" / "a.ply").write_text("x")
    os.symlink(tmp_path / "in" / "a.ply", tmp_path / "in" / "b.ply")
    os.symlink(tmp_path, tmp_path / "in" / "up")
    (tmp_path / "outside.ply").write_text("x")
    assert inside(str(tmp_path / "in"), "b.ply") == str((tmp_path / "in" / "a.ply").resolve())
    with pytest.raises(PathRefusedError):
        inside(str(tmp_path / "in"), "up/outside.ply")


def test_every_interface_warns_and_still_refuses_foreign_names(study):
    folder, _ = study
    with serving(folder, "--host", "0.0.0.0") as running:
        for host in ("127.0.0.1", "192.0.2.7", "[2001:db8::1]", socket.gethostname()):
            status, _, _ = running.request("GET", "/api/state", host=f"{host}:{running.port}")
            assert status == 200, host  # any address of this computer's, or its name
        status, _, _ = running.request("GET", "/api/state", host=f"evil.example:{running.port}")
        assert status == 403  # a name that is not this computer's: still refused
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline and not running.errors:
            time.sleep(0.1)
        assert any("warning" in line and "0.0.0.0" in line for line in running.errors)
