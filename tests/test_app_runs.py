"""``dentopo app`` at work, against the real server: runs, previews, protocols, exports.

A run from the app is the command: the table it writes must be the one the
command writes when typed by hand, and a killed server must lose no finished row.
"""

from __future__ import annotations

import io
import json
import os
import signal
import subprocess
import sys
import time
import zipfile

import pytest

from app_server import HOSTILE, make_folder, serving, start
from dentopo.formats import read_table

pytest.importorskip("starlette")
pytest.importorskip("uvicorn")

pytestmark = pytest.mark.slow

FILES = [HOSTILE, "bad.ply", "group-a/saddle.ply", "sphere.ply", "tooth.ply"]


def without_seconds(rows):
    return [{k: v for k, v in row.items() if k != "seconds"} for row in rows]


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    return make_folder(tmp_path_factory.mktemp("app-runs"))


@pytest.fixture(scope="module")
def server(folder):
    with serving(folder) as running:
        yield running


def wait_for(check, seconds=180, step=0.3):
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        value = check()
        if value:
            return value
        time.sleep(step)
    raise AssertionError("timed out")


def test_the_folder_is_listed_with_groups_sizes_and_errors(server):
    state = server.json("GET", "/api/state")
    meshes = {m["path"]: m for m in state["meshes"]}
    assert sorted(meshes) == sorted(FILES)
    assert meshes["group-a/saddle.ply"]["group"] == "group-a"
    assert meshes["tooth.ply"]["group"] == ""
    assert meshes["bad.ply"]["error"] and meshes["bad.ply"]["faces"] is None
    assert meshes["tooth.ply"]["faces"] > 0 and meshes["tooth.ply"]["thumbnail"]
    status, _, body = server.request("GET", "/api/thumbnail?path=tooth.ply")
    assert status == 200 and body.startswith(b"\x89PNG")


def test_a_run_writes_the_table_the_command_writes(server, folder):
    run = server.json("POST", "/api/run", {"metrics": ["ariadne", "slope"], "jobs": 1})
    assert run["state"] == "running" and run["total"] == len(FILES)
    run = server.wait_run()
    assert run["state"] == "done" and run["exit_code"] == 1  # bad.ply failed, named
    assert run["files"]["bad.ply"]["status"] == "error" and run["files"]["bad.ply"]["error"]
    assert run["files"]["tooth.ply"]["status"] == "ok"
    state = server.json("GET", "/api/state")
    by_app = read_table(state["table"])
    typed = folder.parent / "typed.csv"
    subprocess.run(
        [sys.executable, "-m", "dentopo", *sorted(FILES), "--metrics=ariadne,slope", f"-o{typed}"],
        cwd=folder,
        check=False,
        capture_output=True,
    )
    assert without_seconds(by_app) == without_seconds(read_table(typed))
    results = server.json("GET", "/api/results")
    assert [r["file"] for r in results["rows"]] == sorted(FILES)
    columns = results["columns"]
    assert columns[:2] == ["file", "status"]  # then the values asked for, settings after
    assert columns.index("slope") < columns.index("vertices") < columns.index("bandwidth")
    assert set(columns) <= set(read_table(state["table"])[0])


def test_the_exports_are_the_table(server):
    state = server.json("GET", "/api/state")
    status, headers, body = server.request("GET", "/api/export/table?format=csv")
    assert status == 200 and "attachment" in headers["content-disposition"]
    with open(state["table"], "rb") as stream:
        assert body == stream.read()  # the command's table, byte for byte
    rows = without_seconds(read_table(state["table"]))
    for kind in ("tsv", "xlsx"):
        status, headers, body = server.request("GET", f"/api/export/table?format={kind}")
        assert status == 200, body
        copy = os.path.join(os.path.dirname(state["table"]), f"copy.{kind}")
        with open(copy, "wb") as stream:
            stream.write(body)
        assert without_seconds(read_table(copy)) == rows
        os.unlink(copy)


def test_a_map_is_drawn_by_the_command(server):
    def drawn():
        status, _, body = server.request("GET", "/api/map?path=tooth.ply&metric=slope")
        assert status in (200, 202), body
        return body if status == 200 else None

    assert wait_for(drawn).startswith(b"\x89PNG")
    status, _, body = server.request("GET", "/api/map?path=tooth.ply&metric=colour")
    assert status == 400 and b"map must be one of" in body


def test_a_preview_shows_the_crop_and_the_prepared_crown(server):
    protocol = {"crop_fraction": 0.5, "faces": 1500}
    result = server.json("POST", "/api/preview", {"path": "tooth.ply", "protocol": protocol})
    assert [s["name"] for s in result["steps"]] == ["clean", "orient", "crop", "decimate"]
    assert result["prepared"]["m"] < result["oriented"]["m"]
    assert result["z_max"] > result["z_min"]
    assert abs(sum(x * x for x in result["found_up"]) - 1) < 1e-5  # given to 6 decimals
    status, _, body = server.request(
        "POST", "/api/preview", body={"path": "bad.ply", "protocol": {}}
    )
    assert status == 400 and b"bad.ply" in body


def test_protocols_for_all_and_one_then_a_prepared_run(server, folder):
    state = server.json(
        "POST", "/api/protocol", {"scope": "all", "protocol": {"faces": 2000}, "prepare": True}
    )
    assert state["protocol"]["faces"] == 2000 and state["prepare"] is True
    state = server.json(
        "POST",
        "/api/protocol",
        {"scope": "mesh", "path": "tooth.ply", "protocol": {"crop_fraction": 0.6}},
    )
    own = {m["path"]: m["protocol"] for m in state["meshes"]}
    assert own["tooth.ply"] == "own" and own["sphere.ply"] == "folder"
    status, _, body = server.request("GET", "/api/protocol.toml?path=tooth.ply")
    assert status == 200 and b"fraction = 0.6" in body
    run = server.json("POST", "/api/run", {"metrics": ["ariadne"], "jobs": 1, "prepare": True})
    assert run["command"].count("--prepare") == 2  # one command per protocol, one table
    run = server.wait_run()
    assert run["state"] == "done"
    rows = {r["file"]: r for r in read_table(server.json("GET", "/api/state")["table"])}
    assert rows["tooth.ply"]["protocol"].startswith("app ")
    assert rows["tooth.ply"]["protocol"] != rows["sphere.ply"]["protocol"]
    assert rows["sphere.ply"]["faces"] <= 2020


def test_the_report_and_the_prepared_meshes(server):
    server.json("POST", "/api/report", {})
    report = wait_for(lambda: (r := server.json("GET", "/api/report"))["state"] != "running" and r)
    assert report["state"] == "done", report
    status, headers, body = server.request("GET", report["url"])
    assert status == 200 and b"<html" in body.lower()
    assert "sandbox" in headers["content-security-policy"]  # its scripts cannot call the app
    server.json("POST", "/api/export/prepared", {})
    export = wait_for(
        lambda: (r := server.json("GET", "/api/export/prepared"))["state"] != "running" and r
    )
    assert export["state"] == "done", export
    status, _, body = server.request("GET", export["url"])
    names = zipfile.ZipFile(io.BytesIO(body)).namelist()
    assert "prepared/group-a/saddle.ply" in names and "prepared/tooth.prepare.json" in names
    assert "protocol.toml" in names and "protocols/tooth.ply.toml" in names
    record = json.loads(zipfile.ZipFile(io.BytesIO(body)).read("prepared/tooth.prepare.json"))
    assert record["protocol"]["crop_fraction"] == 0.6  # the mesh's own protocol


def test_a_killed_server_loses_no_row_and_reopening_shows_them(tmp_path):
    folder = make_folder(tmp_path)
    first = start(folder)
    first.wait_idle()
    first.json("POST", "/api/run", {"metrics": ["ariadne"], "jobs": 1})
    first.stop(signal.SIGKILL)  # no chance to clean up
    table = folder / "dentopo-app" / "results.csv"
    wait_for(table.exists, seconds=240)  # the command, in its own session, finishes its rows
    wait_for(lambda: not (folder / "dentopo-app" / ".results.csv.lock").exists(), seconds=60)
    with serving(folder) as again:
        assert again.json("GET", "/api/state")["results"] is True
        rows = again.json("GET", "/api/results")["rows"]
        assert [r["file"] for r in rows] == sorted(FILES)
        assert sum(r["status"] == "ok" for r in rows) == len(FILES) - 1


def test_cancel_stops_the_run_and_leaves_no_half_file(tmp_path):
    folder = make_folder(tmp_path)
    with serving(folder) as running:
        running.json("POST", "/api/run", {"metrics": ["all"], "jobs": 1})
        run = running.json("POST", "/api/run/cancel", {})
        assert run["state"] in ("cancelling", "cancelled")
        run = running.wait_run()
        assert run["state"] == "cancelled"
        output = folder / "dentopo-app"
        assert not [p for p in os.listdir(output) if p.endswith(".tmp")]
        if (output / "results.csv").exists():
            assert all(r["status"] in ("ok", "error") for r in read_table(output / "results.csv"))


def test_a_mesh_copied_into_the_folder_appears_and_a_removed_one_goes(tmp_path):
    folder = make_folder(tmp_path)
    with serving(folder) as running:
        (folder / "group-a" / "copy.ply").write_bytes((folder / "tooth.ply").read_bytes())
        (folder / "sphere.ply").unlink()

        def listed():
            paths = {m["path"] for m in running.json("GET", "/api/state")["meshes"]}
            return paths if "group-a/copy.ply" in paths and "sphere.ply" not in paths else None

        assert wait_for(listed, seconds=30) == (set(FILES) - {"sphere.ply"}) | {"group-a/copy.ply"}
