"""Running ``dentopo`` in the background to signal it, kill it, or race it against another run.

:func:`start` runs the command in a subprocess whose stderr is read line by
line as it comes, so that a test can wait for a moment (a progress line, a
phase) and then act: send a signal, kill a worker, start a second run.  Test
hooks (``hooks/sitecustomize.py``, imported by every Python process the test
starts, workers included) are switched on by environment variables:

``DENTOPO_TEST_PHASES=1``
    every phase of every mesh is reported on stderr (``FILE: kernel (0.0 s)``);
``DENTOPO_TEST_KILL_WORKER_ON=NAME``
    a worker process SIGKILLs itself as it starts the file called NAME;
``DENTOPO_TEST_SLOW_WRITE=SECONDS``
    writing a table file first says ``dentopo-test: writing TABLE`` and waits;
``DENTOPO_TEST_KERNEL=1``
    each exact ariaDNE kernel says ``dentopo-test: kernel N points`` as it starts;
``DENTOPO_TEST_DELAUNAY=1``
    RFI's Delaunay triangulation says ``dentopo-test: delaunay N points`` as it
    starts and ``dentopo-test: delaunay done`` as it ends.

:func:`start_python` runs Python code the same way (a script that calls the
library).
"""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from faults.harness import Ran, _environment

HOOKS = Path(__file__).resolve().parent / "hooks"

#: Seconds a background run may take in all before it counts as hung.
TIME_LIMIT = 60.0


def environment(**variables: str) -> dict:
    """The harness's environment, with the test hooks importable and `variables` set."""
    env = _environment()
    env["PYTHONPATH"] = os.pathsep.join([str(HOOKS), env["PYTHONPATH"]])
    env["PYTHONFAULTHANDLER"] = "1"  # a crash prints every thread's Python stack in the report
    # no sample crown computed before the run's meshes: the hooks report the meshes' own
    # kernels and sweeps, which the tests time their signals by
    env["DENTOPO_WARMUP"] = "0"
    env.update(variables)
    return env


class Live:
    """A ``dentopo`` process running in the background (see :func:`start`)."""

    def __init__(self, args: list[str], *, cwd=None, env=None, module: bool = True, **popen):
        self.args = args
        self.process = subprocess.Popen(
            [sys.executable, *(["-m", "dentopo"] if module else []), *args],
            cwd=cwd,
            env=env if env is not None else environment(),
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            **popen,
        )
        self.pid = self.process.pid
        self.lines: list[str] = []
        self._changed = threading.Condition()
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()
        self._stdout = ""
        self._out_reader = threading.Thread(target=self._read_stdout, daemon=True)
        self._out_reader.start()

    def _read(self) -> None:
        with self.process.stderr:
            for line in self.process.stderr:
                with self._changed:
                    self.lines.append(line)
                    self._changed.notify_all()
        with self._changed:
            self._changed.notify_all()

    def _read_stdout(self) -> None:
        with self.process.stdout:
            self._stdout = self.process.stdout.read()

    @property
    def stderr(self) -> str:
        with self._changed:
            return "".join(self.lines)

    def wait_for(self, pattern: str, timeout: float = 30.0) -> str:
        """Wait for a stderr line matching the regular expression `pattern`; the line."""
        regex = re.compile(pattern)
        deadline = time.monotonic() + timeout
        seen = 0
        with self._changed:
            while True:
                for line in self.lines[seen:]:
                    if regex.search(line):
                        return line
                seen = len(self.lines)
                if self.process.poll() is not None and not self._reader.is_alive():
                    pytest.fail(f"ended before {pattern!r}:\n{self.describe()}")
                left = deadline - time.monotonic()
                if left <= 0:
                    self.kill()
                    pytest.fail(f"no line matching {pattern!r} in {timeout} s:\n{self.describe()}")
                self._changed.wait(min(left, 0.1))

    def send(self, signum: int) -> None:
        """Send `signum` to the process."""
        self.process.send_signal(signum)

    def kill(self) -> None:
        """SIGKILL the process and the processes it started, and wait for it."""
        started = children_of(self.pid) if Path("/proc").is_dir() else []
        if self.process.poll() is None:
            self.process.kill()
        for pid in started:
            try:
                os.kill(pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
        self.process.wait()

    def workers(self) -> list[int]:
        """Pids of its live worker processes (not multiprocessing's resource tracker)."""
        found = []
        for pid in children_of(self.pid):
            try:
                command = Path(f"/proc/{pid}/cmdline").read_bytes()
            except OSError:
                continue
            if b"spawn_main" in command:
                found.append(pid)
        return found

    def finish(self, timeout: float = TIME_LIMIT) -> Ran:
        """Wait for the process to end; what it did."""
        try:
            self.process.wait(timeout)
        except subprocess.TimeoutExpired:
            self.kill()
            self.process.wait()
            self._reader.join(5)
            pytest.fail(f"hung for more than {timeout} s: {self.args}\n{self.describe()}")
        self._reader.join(5)
        self._out_reader.join(5)
        return Ran(self.process.returncode, self._stdout, self.stderr)

    def describe(self) -> str:
        return f"exit {self.process.poll()}\n--- stderr\n{self.stderr}"


def start(*argv: str, cwd=None, env=None, **popen) -> Live:
    """Start ``python -m dentopo ARGV`` in the background (see :class:`Live`)."""
    return Live(list(argv), cwd=cwd, env=env, **popen)


def start_python(code: str, *, cwd=None, env=None, **popen) -> Live:
    """Start ``python -c CODE`` in the background (see :class:`Live`)."""
    return Live(["-c", code], cwd=cwd, env=env, module=False, **popen)


def children_of(pid: int) -> list[int]:
    """Live processes whose parent is `pid` (Linux: read from /proc)."""
    found = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            stat = (entry / "stat").read_text()
        except OSError:
            continue
        fields = stat[stat.rindex(")") + 2 :].split()
        if int(fields[1]) == pid and fields[0] != "Z":
            found.append(int(entry.name))
    return found


def alive(pid: int) -> bool:
    """Whether process `pid` exists and is not a zombie."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return False
    return stat[stat.rindex(")") + 2] != "Z"


def needs_proc() -> None:
    """Skip the test where /proc does not list processes (not Linux)."""
    if not sys.platform.startswith("linux") or not Path("/proc/self/stat").exists():
        pytest.skip("finding worker processes reads /proc (Linux)")


def write_tooth(path: Path, rings: int) -> Path:
    """A tooth-like crown of ``3 * rings * (rings + 1) + 1`` vertices, written to `path`.

    About 0.1 s to compute with 20 rings, 3 s with 100 and 13 s with 150
    (``--method exact``, two cores).
    """
    from dentopo.samples import tooth

    tooth(rings=rings).export(path)
    return path
