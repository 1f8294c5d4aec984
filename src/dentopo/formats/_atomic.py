"""Atomic file writes: a temporary file in the same directory, renamed over the target."""

from __future__ import annotations

import functools
import io
import os
import tempfile
from collections.abc import Callable


@functools.cache
def _umask() -> int:
    """The process umask (read once: reading it means setting it briefly)."""
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def atomic_write(
    path: str | os.PathLike, write: Callable[[io.IOBase], None], *, binary: bool = False
) -> None:
    """Write a file atomically: `write` fills a temporary file, which is then renamed.

    The temporary file lives in the target's directory (so that the rename is
    atomic) and is removed if `write` raises; the target is then untouched.
    Text mode is UTF-8 with untranslated newlines.
    """
    path = os.fspath(path)
    directory = os.path.dirname(os.path.abspath(path))
    handle, temporary = tempfile.mkstemp(
        dir=directory, prefix=f".{os.path.basename(path)}.", suffix=".tmp"
    )
    try:
        mode = {"mode": "wb"} if binary else {"mode": "w", "encoding": "utf-8", "newline": ""}
        with os.fdopen(handle, **mode) as stream:
            write(stream)
            stream.flush()
            os.fsync(stream.fileno())
        os.chmod(temporary, 0o666 & ~_umask())  # mkstemp creates 0600
        os.replace(temporary, path)
    except BaseException:
        if os.path.exists(temporary):
            os.unlink(temporary)
        raise
