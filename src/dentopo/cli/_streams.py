"""stdout and stderr that cannot be written: a full disk, ``/dev/full``, a closed pipe.

A failed write to stdout (``dentopo x.ply > /dev/full``) raised an ``OSError``
from wherever the table was being printed, and ended in a traceback; a failed
write to stderr (``2>/dev/full``) did the same at the first progress line, so
that the table of ``-o FILE`` was never written.  Here:

* while the command runs, ``sys.stdout`` is wrapped (:func:`guarded_stdout`):
  a failed write raises :class:`StreamError`, which is not an ``OSError``, so
  that no handler meant for files takes it for one; the entry point says
  ``cannot write to stdout: <reason>`` and exits 1 (a closed pipe, as in
  ``dentopo scans/ | head``, ends quietly with exit 0, as before);
* a message that cannot be written to stderr is dropped
  (:func:`write_stderr`): the run goes on, its files are written, and it
  exits 1 at the end (:func:`stderr_failed`), as GNU tools do;
* :func:`silence` points a failed stream at ``/dev/null``, so that Python's
  final flush at exit does not fail again ("Exception ignored ...").
"""

from __future__ import annotations

import contextlib
import errno
import os
import sys
from collections.abc import Iterator


class StreamError(Exception):
    """A write to ``stdout`` failed; ``error`` is the ``OSError``."""

    def __init__(self, name: str, error: OSError):
        super().__init__(f"cannot write to {name}: {error.strerror or error}")
        self.name = name
        self.error = error

    @property
    def broken_pipe(self) -> bool:
        """The reader went away (``| head``): not worth a message."""
        return isinstance(self.error, BrokenPipeError) or self.error.errno == errno.EPIPE


class _Guarded:
    """A text stream whose failed writes raise :class:`StreamError`; the rest is the stream's."""

    def __init__(self, stream, name: str):
        self._stream = stream
        self._name = name

    def write(self, text):
        try:
            return self._stream.write(text)
        except OSError as exc:
            raise StreamError(self._name, exc) from None

    def writelines(self, lines):
        for line in lines:
            self.write(line)

    def flush(self):
        try:
            return self._stream.flush()
        except OSError as exc:
            raise StreamError(self._name, exc) from None

    def __getattr__(self, name):
        return getattr(self._stream, name)


@contextlib.contextmanager
def guarded_stdout() -> Iterator[None]:
    """Wrap ``sys.stdout`` (see the module docstring) while the command runs."""
    original = sys.stdout
    if original is None or isinstance(original, _Guarded):
        yield
        return
    sys.stdout = _Guarded(original, "stdout")
    try:
        yield
    finally:
        if isinstance(sys.stdout, _Guarded):
            sys.stdout = original


_failed = {"stderr": False}


def write_stderr(text: str) -> None:
    """Write `text` to stderr and flush it; a failed write is dropped, and remembered."""
    stream = sys.stderr
    if stream is None:
        _failed["stderr"] = True
        return
    try:
        stream.write(text)
        stream.flush()
    except OSError:
        _failed["stderr"] = True


def stderr_failed() -> bool:
    """Whether a message could not be written to stderr in this process."""
    return _failed["stderr"]


def forget_stderr_failure() -> None:
    """Start again (each call of the entry point in one process, as tests make)."""
    _failed["stderr"] = False


def silence(stream) -> None:
    """Point a failed standard stream at ``/dev/null`` (its buffered text dropped)."""
    try:
        descriptor = stream.fileno()
    except (AttributeError, OSError, ValueError):
        return
    try:
        null = os.open(os.devnull, os.O_WRONLY)
    except OSError:
        return
    try:
        os.dup2(null, descriptor)
    except OSError:
        pass
    finally:
        os.close(null)
