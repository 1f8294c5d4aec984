"""The app's maps, drawn by its warm picture worker: the command's pictures, and a worker that
survives a failing picture, is replaced when it dies, and never outlives the server."""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import time

import pytest

pytest.importorskip("starlette")

from dentopo.app import Workspace
from dentopo.app._pictures import MAPS, WORKER_CODE
from dentopo.samples import sample_paths

pytestmark = pytest.mark.slow


def picture(workspace: Workspace, relative: str, name: str, seconds: float = 300):
    """The map's file, or the failed drawing (waited for)."""
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        found = workspace.map_picture(relative, name)
        if isinstance(found, str) or found.state == "failed":
            return found
        found.wait(1.0)
    raise AssertionError(f"the {name} map of {relative} was not drawn in {seconds} s")


def command_picture(folder, relative, name, target, *extra) -> bytes:
    """The map as ``dentopo`` draws it, with the arguments the app used to run it with."""
    metric, color_by = MAPS[name]
    arguments = ["--metrics", metric, "--bandwidth", "0.08", "--cutoff", "0.0"]
    arguments += ["--distance-type", "euclidean", "--sign-method", "centroid", "--method", "auto"]
    arguments += ["--quiet", "--color-by", color_by, "--screenshot", str(target)]
    arguments += ["--size", "900,760", *extra, "--", relative]
    done = subprocess.run(
        [sys.executable, "-m", "dentopo", *arguments],
        cwd=folder,
        capture_output=True,
        text=True,
        env={**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)},  # this dentopo
    )
    assert done.returncode == 0, done.stderr
    return target.read_bytes()


@pytest.fixture()
def folder(tmp_path):
    folder = tmp_path / "study"
    (folder / "sub").mkdir(parents=True)
    shutil.copy(sample_paths()["tooth"], folder / "sub" / "tooth.ply")
    (folder / "bad.ply").write_bytes(b"ply\nformat ascii 1.0\nelement vertex 3\nnonsense\n")
    return folder


def test_the_four_maps_are_the_command_s_pictures_byte_for_byte(folder, tmp_path):
    workspace = Workspace(str(folder))
    try:
        for name in MAPS:
            drawn = picture(workspace, "sub/tooth.ply", name)
            assert isinstance(drawn, str), drawn
            typed = command_picture(folder, "sub/tooth.ply", name, tmp_path / f"{name}.png")
            with open(drawn, "rb") as stream:
                assert stream.read() == typed, name
        assert workspace.drawer.started == 1  # one worker drew the four
        # a prepared mesh: the picture names the protocol it was drawn with, as the command's
        workspace.save_protocol("mesh", "sub/tooth.ply", {"faces": 600, "name": "small"})
        workspace.set_prepares(True)
        with open(os.path.join(workspace.output, ".app", "run.json"), "w") as stream:
            stream.write('{"prepare": true}')
        drawn = picture(workspace, "sub/tooth.ply", "slope")
        assert isinstance(drawn, str), drawn
        protocol = workspace.own_protocol_file("sub/tooth.ply")
        typed = command_picture(
            folder, "sub/tooth.ply", "slope", tmp_path / "prepared.png", "--prepare", protocol
        )
        with open(drawn, "rb") as stream:
            assert stream.read() == typed
    finally:
        workspace.close()


def test_a_failing_picture_is_one_line_and_the_worker_goes_on(folder):
    workspace = Workspace(str(folder))
    try:
        workspace.drawer.warm()
        assert workspace.drawer.wait_warm(300)
        pid = workspace.drawer.pid
        failed = picture(workspace, "bad.ply", "slope")
        assert not isinstance(failed, str) and failed.state == "failed"
        assert failed.error and "\n" not in failed.error and not failed.retry
        assert "bad.ply" in failed.error or "ply" in failed.error.lower(), failed.error
        again = workspace.map_picture("bad.ply", "slope")  # a failure is kept, not redrawn
        assert again is failed
        assert isinstance(picture(workspace, "sub/tooth.ply", "opc"), str)
        assert workspace.drawer.pid == pid and workspace.drawer.started == 1
    finally:
        workspace.close()


def test_a_killed_worker_costs_that_picture_only(folder):
    from dentopo.samples import tooth

    tooth(rings=250).export(folder / "large.ply")  # about 190,000 vertices: seconds to draw
    workspace = Workspace(str(folder))
    try:
        workspace.drawer.warm()
        assert workspace.drawer.wait_warm(300)
        first = workspace.drawer.pid
        drawing = workspace.map_picture("large.ply", "curvature")
        deadline = time.monotonic() + 60
        while drawing.state == "waiting" and time.monotonic() < deadline:
            time.sleep(0.05)
        assert drawing.state == "drawing"
        os.kill(first, signal.SIGKILL)
        assert drawing.wait(60)
        assert drawing.state == "failed" and drawing.retry
        assert "killed by signal 9" in drawing.error and "\n" not in drawing.error
        assert not [n for n in os.listdir(os.path.dirname(drawing.target)) if n.endswith(".png")]
        # the next picture starts a new worker; asking again for the lost one draws it
        assert isinstance(picture(workspace, "sub/tooth.ply", "slope"), str)
        second = workspace.drawer.pid
        assert second not in (None, first) and workspace.drawer.started == 2
        again = workspace.map_picture("large.ply", "curvature")
        assert again is drawing  # said once, as the page asks while it waits
        assert isinstance(picture(workspace, "large.ply", "curvature"), str)
        # killed while it waits between pictures: replaced as well
        os.kill(second, signal.SIGKILL)
        time.sleep(0.5)
        assert isinstance(picture(workspace, "sub/tooth.ply", "arc"), str)
        assert workspace.drawer.started == 3
    finally:
        workspace.close()
    assert workspace.drawer.pid is None


def workers_of(pid: int) -> list[int]:
    """The picture workers whose parent is `pid` (Linux /proc)."""
    found = []
    for name in os.listdir("/proc"):
        if not name.isdigit():
            continue
        try:
            with open(f"/proc/{name}/stat") as stream:
                fields = stream.read().rpartition(")")[2].split()
            with open(f"/proc/{name}/cmdline", "rb") as stream:
                command = stream.read().replace(b"\0", b" ").decode(errors="replace")
        except OSError:
            continue
        if int(fields[1]) == pid and WORKER_CODE in command:
            found.append(int(name))
    return found


def alive(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat") as stream:
            return stream.read().rpartition(")")[2].split()[0] != "Z"  # a zombie has ended
    except OSError:
        return False


def wait_until(check, seconds: float) -> bool:
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        if check():
            return True
        time.sleep(0.1)
    return False


@pytest.mark.skipif(not os.path.isdir("/proc/self"), reason="finds the worker in /proc")
@pytest.mark.parametrize("stop", [signal.SIGINT, signal.SIGTERM, signal.SIGKILL])
def test_the_worker_is_warmed_at_start_and_never_outlives_the_server(folder, stop):
    from app_server import start

    server = start(folder)
    try:
        assert wait_until(lambda: workers_of(server.process.pid), 60), "no worker started"
        (worker,) = workers_of(server.process.pid)
        server.wait_idle()
        status, _, body = server.request("GET", "/api/map?path=sub/tooth.ply&metric=slope")
        assert status in (200, 202), body
    finally:
        code = server.stop(stop)
    assert code is not None
    assert wait_until(lambda: not alive(worker), 30), f"the worker {worker} outlived the server"
