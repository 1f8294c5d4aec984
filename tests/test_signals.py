"""Ctrl-C inside a finalizer (a ``__del__``): sent again a moment later, not dropped.

Python drops an exception raised in a ``__del__`` ("Exception ignored in ..."),
and the garbage collector runs finalizers at any moment (llvmlite frees its
LLVM objects in one).  Each test makes the moment certain: an object whose
``__del__`` sends SIGINT to the process and goes on for a while, as when a
Ctrl-C arrives while the collector runs one.
"""

from __future__ import annotations

import os
import signal
import sys
import threading
import time

import pytest

from dentopo import _signals
from dentopo.batch._interrupts import Interrupted, guard_interrupts

pytestmark = pytest.mark.skipif(
    threading.current_thread() is not threading.main_thread()
    or not hasattr(signal, "pthread_kill"),
    reason="signals to the main thread (POSIX)",
)


class _CtrlCInFinalizer:
    """Its ``__del__`` sends SIGINT, then runs Python code (where the handler runs) for a while."""

    finished = 0

    def __del__(self):
        os.kill(os.getpid(), signal.SIGINT)
        deadline = time.monotonic() + 0.05  # longer than REDELIVERY_SECONDS: sent again, twice
        while time.monotonic() < deadline:
            sum(range(100))
        type(self).finished += 1


def _finalize_and_wait() -> float:
    """Finalize one object, then wait in Python code; the seconds waited (raises if interrupted)."""
    _CtrlCInFinalizer.finished = 0
    started = time.monotonic()
    _CtrlCInFinalizer()  # dropped at once: __del__ runs here
    while time.monotonic() - started < 2.0:
        time.sleep(0.01)
    return time.monotonic() - started


@pytest.fixture
def dropped(monkeypatch):
    """The exceptions Python dropped ("Exception ignored in ...")."""
    found = []
    monkeypatch.setattr(sys, "unraisablehook", found.append)
    return found


@pytest.fixture
def handler():
    before = signal.getsignal(signal.SIGINT)
    yield lambda h: signal.signal(signal.SIGINT, h)
    signal.signal(signal.SIGINT, before)


def test_the_control_python_s_own_handler_drops_a_ctrl_c_in_a_finalizer(dropped, handler):
    handler(signal.default_int_handler)
    assert _finalize_and_wait() >= 2.0  # ran on as if no Ctrl-C came
    assert [type(u.exc_value) for u in dropped] == [KeyboardInterrupt]


def test_interrupt_raises_a_ctrl_c_in_a_finalizer_once_it_has_returned(dropped, handler):
    handler(_signals.interrupt)
    started = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        _finalize_and_wait()
    assert _CtrlCInFinalizer.finished == 1  # the finalizer ran to its end
    assert time.monotonic() - started < 1.0
    assert dropped == []
    time.sleep(3 * _signals.REDELIVERY_SECONDS)  # no second KeyboardInterrupt comes


def test_interrupt_is_python_s_keyboard_interrupt_elsewhere(handler):
    handler(_signals.interrupt)
    with pytest.raises(KeyboardInterrupt):
        os.kill(os.getpid(), signal.SIGINT)
        time.sleep(1.0)


def test_the_batch_guard_raises_a_ctrl_c_in_a_finalizer_once_it_has_returned(dropped, handler):
    handler(signal.default_int_handler)
    started = time.monotonic()
    with pytest.raises(Interrupted), guard_interrupts() as guard:
        _finalize_and_wait()
    assert _CtrlCInFinalizer.finished == 1 and guard.raised == signal.SIGINT
    assert time.monotonic() - started < 1.0
    assert dropped == []
    assert guard._later == 0  # every signal sent again has arrived


def test_the_guard_drops_a_signal_sent_again_after_a_safe_point_raised_it(dropped, handler):
    handler(signal.default_int_handler)
    with guard_interrupts() as guard:
        guard._later = 1  # as if a finalizer's Ctrl-C is to come again ...
        guard.pending = signal.SIGINT
        with pytest.raises(Interrupted):
            guard.check()  # ... and was raised at a safe point first
        os.kill(os.getpid(), signal.SIGINT)  # the second sending: no second Interrupted
        time.sleep(0.2)
        assert guard._later == 0 and guard.pending is None


def _sigint_handler_while_the_command_runs():
    """The SIGINT handler that a subcommand of the command line sees as it runs."""
    from dentopo.cli import _main

    seen = []
    _main.SUBCOMMANDS["_probe"] = lambda argv: seen.append(signal.getsignal(signal.SIGINT)) or 0
    try:
        assert _main.main(["_probe"]) == 0
    finally:
        del _main.SUBCOMMANDS["_probe"]
    return seen[0]


def test_the_command_line_installs_interrupt_while_it_runs_and_restores_the_handler(handler):
    handler(signal.default_int_handler)
    assert _sigint_handler_while_the_command_runs() is _signals.interrupt
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def test_the_command_line_leaves_an_ignored_sigint_ignored(handler):
    handler(signal.SIG_IGN)  # started under nohup, or in the background
    assert _sigint_handler_while_the_command_runs() is signal.SIG_IGN
