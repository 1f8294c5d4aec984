"""The fault suite's harness: each bad input or fault runs in a subprocess with a time limit.

A crash (a signal such as SIGSEGV), a hang or a traceback then shows as a failed
test with what the process printed, instead of taking the test run down with it.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

#: Seconds a case may take before it counts as hung.
TIME_LIMIT = 120.0


@dataclass
class Ran:
    """What a case's process did."""

    returncode: int
    stdout: str
    stderr: str

    def describe(self) -> str:
        return f"exit {self.returncode}\n--- stdout\n{self.stdout}\n--- stderr\n{self.stderr}"


def _environment() -> dict:
    env = dict(os.environ)
    src = str(Path(__import__("dentopo").__file__).resolve().parents[1])
    env["PYTHONPATH"] = os.pathsep.join([src, *filter(None, [env.get("PYTHONPATH")])])
    env.pop("DENTOPO_SCHEDULER", None)
    return env


def run_case(
    args: list[str], *, cwd=None, timeout: float = TIME_LIMIT, crash_ok: bool = False, **popen
) -> Ran:
    """Run ``python ARGS`` (e.g. ``["-m", "dentopo", ...]``) and return what it did.

    Fails the test if the process hangs past `timeout` or dies of a signal
    (unless `crash_ok`, for cases that kill it on purpose).
    """
    try:
        done = subprocess.run(
            [sys.executable, *args],
            cwd=cwd,
            env=_environment(),
            capture_output=True,
            text=True,
            timeout=timeout,
            **popen,
        )
    except subprocess.TimeoutExpired as exc:
        pytest.fail(f"hung for more than {timeout} s: {args}\n{exc.stderr}")
    ran = Ran(done.returncode, done.stdout, done.stderr)
    if done.returncode < 0 and not crash_ok:
        name = signal.Signals(-done.returncode).name
        pytest.fail(f"crashed with {name}: {args}\n{ran.describe()}")
    return ran


def dentopo(*argv: str, **kwargs) -> Ran:
    """Run the ``dentopo`` command in a subprocess (see :func:`run_case`)."""
    return run_case(["-m", "dentopo", *argv], **kwargs)


def python(code: str, **kwargs) -> Ran:
    """Run Python `code` in a subprocess (see :func:`run_case`)."""
    return run_case(["-c", code], **kwargs)
