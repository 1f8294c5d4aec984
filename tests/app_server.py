"""Starting ``dentopo app`` for real, as a user does, and talking to it (for the app's tests)."""

from __future__ import annotations

import http.client
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import threading
import time
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

from dentopo.samples import sample_paths

#: A mesh file named as markup (a page that sets it as HTML would run it).
HOSTILE = "<img src=x onerror=alert(1)>.ply"
#: Seconds to wait for the server's address line.
START_SECONDS = 90


def make_folder(root: Path) -> Path:
    """A study folder: the samples (one in a subfolder), a corrupt file, a hostile name."""
    folder = root / "study"
    (folder / "group-a").mkdir(parents=True)
    paths = sorted(sample_paths().values())
    for path in paths[1:]:
        shutil.copy(path, folder / Path(path).name)
    shutil.copy(paths[0], folder / "group-a" / Path(paths[0]).name)
    shutil.copy(paths[-1], folder / HOSTILE)
    (folder / "bad.ply").write_bytes(b"ply\nformat ascii 1.0\nelement vertex 3\nnonsense\n")
    return folder


@dataclass
class Server:
    """A running ``dentopo app`` (its process, address and secret)."""

    process: subprocess.Popen
    port: int
    token: str
    lines: list[str] = field(default_factory=list)
    errors: list[str] = field(default_factory=list)
    _readers: list = field(default_factory=list)

    @property
    def url(self) -> str:
        return f"http://127.0.0.1:{self.port}/?token={self.token}"

    def request(self, method, path, *, body=None, headers=None, token=True, host=None):
        """(status, headers, body bytes) of one raw request (the path sent as given)."""
        connection = http.client.HTTPConnection("127.0.0.1", self.port, timeout=60)
        sent = {"Host": f"127.0.0.1:{self.port}" if host is None else host}
        if token:
            sent["X-Dentopo-Token"] = self.token
        if body is not None and not isinstance(body, bytes):
            body = json.dumps(body).encode()
            sent["Content-Type"] = "application/json"
        if body is not None:
            sent["Content-Length"] = str(len(body))
        sent.update(headers or {})
        connection.putrequest(method, path, skip_host=True, skip_accept_encoding=True)
        for name, value in sent.items():
            connection.putheader(name, value)
        connection.endheaders(body)
        response = connection.getresponse()
        data = response.read()
        connection.close()
        return response.status, {k.lower(): v for k, v in response.getheaders()}, data

    def json(self, method, path, body=None):
        status, _, data = self.request(method, path, body=body)
        assert status == 200, (status, data)
        return json.loads(data)

    def wait_run(self, seconds=300) -> dict:
        """The run's state once it has ended."""
        deadline = time.monotonic() + seconds
        while time.monotonic() < deadline:
            run = self.json("GET", "/api/run")
            if run["state"] not in ("running", "cancelling"):
                return run
            time.sleep(0.3)
        raise AssertionError(f"the run did not end in {seconds} s: {run}")

    def wait_idle(self, seconds=120) -> dict:
        """The state once every mesh of the folder is read."""
        deadline = time.monotonic() + seconds
        while time.monotonic() < deadline:
            state = self.json("GET", "/api/state")
            if not state["pending"]:
                return state
            time.sleep(0.3)
        raise AssertionError("the folder was not read in time")

    def stop(self, sig=signal.SIGINT) -> int:
        if self.process.poll() is None:
            self.process.send_signal(sig)
            try:
                self.process.wait(60)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        for thread in self._readers:
            thread.join(10)
        for stream in (self.process.stdout, self.process.stderr):
            stream.close()
        return self.process.returncode


@contextmanager
def serving(folder, *arguments: str):
    """A started server whose folder is read (:func:`start`), stopped at the end."""
    running = start(folder, *arguments)
    try:
        running.wait_idle()
        yield running
    finally:
        running.stop()


def start(folder, *arguments: str) -> Server:
    """Start ``dentopo app FOLDER --no-browser --port 0 ARGUMENTS`` and read its address."""
    process = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "dentopo",
            "app",
            str(folder),
            "--no-browser",
            "--port",
            "0",
            *arguments,
        ],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "PYTHONUNBUFFERED": "1"},
    )
    server = Server(process, 0, "")
    server._readers.append(
        threading.Thread(target=lambda: server.errors.extend(process.stderr), daemon=True)
    )
    found = threading.Event()

    def read():
        for line in process.stdout:
            server.lines.append(line)
            match = re.search(r"http://127\.0\.0\.1:(\d+)/\?token=(\S+)", line)
            if match:
                server.port, server.token = int(match.group(1)), match.group(2)
                found.set()

    server._readers.append(threading.Thread(target=read, daemon=True))
    for thread in server._readers:
        thread.start()
    if not found.wait(START_SECONDS):
        process.kill()
        raise AssertionError(f"no address from dentopo app: {server.lines} {server.errors}")
    return server
