"""Ctrl-C while numba compiles or loads a kernel: held until numba's compiler lock is released.

Python runs a signal's handler in the first Python code it reaches.  While
LLVM compiles, that is llvmlite's object-cache callback, a ctypes callback,
where an exception is printed as "Exception ignored" and dropped: a Ctrl-C
during a kernel's first compilation was lost and the computation ran on.  The
test below makes that moment deterministic: a compile listener calls a ctypes
callback that sends SIGINT, as LLVM's callback does when a Ctrl-C arrives
while it compiles.  Without the hold that importing ``dentopo._jit``
registers, the interrupt is lost and the call returns; with it, it is raised
once the kernel is compiled.

The hold covers the whole of numba's compiler lock: loading a kernel from the
cache (llvmlite hands modules to the execution engine in two steps, which an
interrupt between them leaves freed twice) and saving it to the cache too.
"""

from __future__ import annotations

import ctypes
import os
import signal
import subprocess
import sys
import threading

import numba
import pytest
from numba.core import event

from dentopo import _jit

pytestmark = pytest.mark.skipif(
    threading.current_thread() is not threading.main_thread(), reason="signals need the main thread"
)


class _InterruptInACallback(event.Listener):
    """Sends SIGINT from inside a ctypes callback when a compilation starts."""

    def __init__(self):
        self.callback = ctypes.CFUNCTYPE(None)(self._interrupt)
        self.sent = 0

    def _interrupt(self):
        self.sent += 1
        os.kill(os.getpid(), signal.SIGINT)
        sum(range(1000))  # Python code after the signal: where its handler runs

    def on_start(self, event_):
        if not self.sent:
            self.callback()

    def on_end(self, event_):
        pass


def _compile_with_an_interrupt(njit, function, *args):
    """Call a fresh kernel of `function` while a Ctrl-C is sent inside a callback of its compile."""
    kernel = njit(function)
    listener = _InterruptInACallback()
    with event.install_listener("numba:compile", listener):
        result = kernel(*args)
    return kernel, listener, result


def _add_one(x):
    return x + 1


def _twice(x):
    return 2 * x


def test_a_ctrl_c_during_a_compilation_is_raised_when_it_ends():
    before = signal.getsignal(signal.SIGINT)
    kernel = _jit.njit(_add_one)
    listener = _InterruptInACallback()
    with event.install_listener("numba:compile", listener), pytest.raises(KeyboardInterrupt):
        kernel(1)
    assert listener.sent == 1
    assert len(kernel.signatures) == 1  # compiled before the interrupt was raised
    assert kernel(1) == 2  # and usable after it
    assert signal.getsignal(signal.SIGINT) is before  # the handler is back


def test_a_callee_compiled_inside_a_kernel_holds_until_the_outer_compilation_ends():
    inner = _jit.njit(_twice)

    def outer(x):
        return inner(x) + 1

    kernel = _jit.njit(outer)
    listener = _InterruptInACallback()
    with event.install_listener("numba:compile", listener), pytest.raises(KeyboardInterrupt):
        kernel(3)
    assert len(kernel.signatures) == 1 and len(inner.signatures) == 1
    assert _jit._HOLD.depth == 0 and not _jit._HOLD.caught


def test_the_control_without_the_hold_the_ctrl_c_is_lost(monkeypatch):
    """The failure the hold prevents: without it the call returns as if no Ctrl-C came."""
    ignored = []
    monkeypatch.setattr(sys, "unraisablehook", ignored.append)  # "Exception ignored ..."
    kernel = numba.njit(_add_one)
    event.unregister(_jit.HELD_DURING, _jit._HOLD)  # the hold listens to every compilation
    try:
        listener = _InterruptInACallback()
        with event.install_listener("numba:compile", listener):
            assert kernel(1) == 2
    finally:
        event.register(_jit.HELD_DURING, _jit._HOLD)
    assert listener.sent == 1
    assert [type(u.exc_value) for u in ignored] == [KeyboardInterrupt]


def _interrupting(function, calls):
    """`function`, which first sends SIGINT and runs Python code (where the handler runs)."""

    def wrapped(*args, **kwargs):
        os.kill(os.getpid(), signal.SIGINT)
        sum(range(1000))
        calls.append(function.__name__)
        return function(*args, **kwargs)

    return wrapped


def test_a_ctrl_c_while_a_kernel_is_looked_up_in_the_cache_is_raised_once_it_is_ready():
    # numba looks in its cache before compiling and loads from it there: a Ctrl-C then used to
    # be raised inside numba's (and llvmlite's) Python code
    kernel = _jit.njit(_add_one)
    calls = []
    kernel._cache.load_overload = _interrupting(kernel._cache.load_overload, calls)
    with pytest.raises(KeyboardInterrupt):
        kernel(1)
    assert calls == ["load_overload"]
    assert len(kernel.signatures) == 1 and kernel(1) == 2
    assert _jit._HOLD.depth == 0 and not _jit._HOLD.caught


def test_an_interrupted_compilation_is_still_saved_to_the_cache():
    # held to the lock's release, not to the compilation's end: the next run loads the kernel
    kernel = _jit.njit(_add_one)
    saved = []
    real_save = kernel._cache.save_overload
    kernel._cache.save_overload = lambda sig, cres: (saved.append(sig), real_save(sig, cres))
    listener = _InterruptInACallback()
    with event.install_listener("numba:compile", listener), pytest.raises(KeyboardInterrupt):
        kernel(1)
    assert listener.sent == 1 and len(saved) == 1


@pytest.mark.parametrize(("given", "expected"), [(None, "PASSIVE"), ("ACTIVE", "ACTIVE")])
def test_openmp_threads_sleep_between_kernels_unless_told_otherwise(given, expected):
    # a spinning OpenMP thread takes a core from the serial work between dentopo's
    # short kernels on a busy machine; a value the user set is kept
    env = {k: v for k, v in os.environ.items() if k != "OMP_WAIT_POLICY"}
    if given:
        env["OMP_WAIT_POLICY"] = given
    code = "import os, dentopo._jit; print(os.environ['OMP_WAIT_POLICY'])"
    done = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == expected


_LEAN = """
import sys
from dentopo._jit import lean_numba_typing, njit
loaded = lean_numba_typing()
print(loaded)
print("cffi" in sys.modules, "scipy.linalg" in sys.modules)
from numba.core.typing import cffi_utils
print(cffi_utils.SUPPORTED)

@njit
def total(a):
    s = 0.0
    for x in a:
        s += x
    return s

import numpy as np
print(total(np.arange(4.0)))
import scipy.linalg  # both stay importable for every other use
print(scipy.linalg.det(np.eye(2)))
print(lean_numba_typing())  # a second call: nothing left to do
"""


def test_the_command_loads_numbas_typing_without_cffi_and_scipy():
    # what the main command does first: numba's cffi support and its BLAS probe loaded as
    # where cffi and scipy are missing (0.14 s of a warm start), both still importable
    done = subprocess.run([sys.executable, "-c", _LEAN], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    lines = done.stdout.splitlines()
    assert lines[0] == "['numba.core.typing.cffi_utils', 'numba.np.arraymath']"
    assert lines[1] == "False False"  # neither was imported on the way
    assert lines[2] == "False"  # numba types no cffi object in that process
    assert lines[3] == "6.0"  # kernels compile and run
    assert lines[4] == "1.0"
    assert lines[5] == "[]"


def test_the_main_command_calls_it_before_its_first_kernel(monkeypatch):
    from dentopo.cli import _compute

    calls = []
    monkeypatch.setattr(_compute, "lean_numba_typing", lambda: calls.append(1) or [])
    assert _compute.compute_main(["--version"]) == 0
    assert calls == [1]


def _recorder():
    """A list and a call(a, b) that records each slice and whether the calling thread ran it."""
    seen = []
    lock = threading.Lock()

    def call(a, b):
        with lock:
            seen.append((a, b, threading.current_thread() is threading.main_thread()))

    return seen, call


def test_in_threads_cuts_the_rows_once_each_and_raises_the_first_error(monkeypatch):
    seen, call = _recorder()
    monkeypatch.setattr(numba, "get_num_threads", lambda: 3)
    _jit.in_threads(5, 15, call)
    assert sorted((a, b) for a, b, _ in seen) == [(5, 8), (8, 11), (11, 15)]
    seen.clear()
    _jit.in_threads(5, 15, call, threads_from=11)  # too few rows: one slice, this thread
    assert seen == [(5, 15, True)]
    seen.clear()
    _jit.in_threads(0, 2, call)  # never more slices than rows
    assert sorted((a, b) for a, b, _ in seen) == [(0, 1), (1, 2)]

    def failing(a, b):
        if a == 8:
            raise ValueError("slice 8:11")

    with pytest.raises(ValueError, match="slice 8:11"):
        _jit.in_threads(5, 15, failing)


def test_in_threads_chunks_are_each_taken_once_and_the_caller_takes_a_share(monkeypatch):
    seen, call = _recorder()
    monkeypatch.setattr(numba, "get_num_threads", lambda: 2)
    _jit.in_threads(0, 100, call, chunks=8)
    chunks = [(100 * k // 8, 100 * (k + 1) // 8) for k in range(8)]
    assert sorted((a, b) for a, b, _ in seen) == chunks
    seen.clear()
    _jit.in_threads(0, 100, call)
    assert sorted((a, b) for a, b, _ in seen) == [(0, 50), (50, 100)]
    assert [own for a, b, own in seen if a == 0] == [True]  # the caller's own share
    seen.clear()
    _jit.in_threads(0, 3, call, chunks=8)  # never more chunks than rows
    assert sorted((a, b) for a, b, _ in seen) == [(0, 1), (1, 2), (2, 3)]

    def failing(a, b):
        if a == 50:
            raise ValueError("chunk 50")

    with pytest.raises(ValueError, match="chunk 50"):
        _jit.in_threads(0, 100, failing, chunks=8)


def _numbas_values(config) -> dict:
    """``TargetConfig.values`` as numba writes it: each option read through its property."""
    return {name: getattr(config, name) for name in config.options}


def test_the_quick_compile_flags_give_numbas_own_values_and_hash():
    from numba.core.compiler import Flags

    assert _jit.quick_compile_flags()  # in since dentopo._jit was imported
    plain, changed, same = Flags(), Flags(), Flags()
    changed.nrt = True
    changed.fastmath = True
    changed.error_model = "numpy"
    same.nrt = False  # set, but to the default
    for flags in (plain, changed, same):
        assert flags.values() == _numbas_values(flags)
        assert hash(flags) == hash(tuple(sorted(_numbas_values(flags))))
    assert plain == same and plain != changed
    assert hash(plain) == hash(changed)  # numba's hash: the option names only
    # setting an option afterwards is seen (nothing is cached per instance)
    same.boundscheck = True
    assert same.values() == _numbas_values(same) and same != plain


def test_a_kernel_compiles_and_caches_with_the_quick_compile_flags(tmp_path):
    code = """
import numpy as np
from dentopo._jit import njit

@njit(cache=True)
def total(a):
    return np.full(3, a.sum()).sum() + min(a[0], a[1])

print(total(np.arange(4.0)))
"""
    script = tmp_path / "kernel.py"
    script.write_text(code)
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "cache"))
    for _ in range(2):  # compiled, then loaded from the cache
        out = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, env=env)
        assert out.returncode == 0, out.stderr
        assert out.stdout.strip() == "18.0"
