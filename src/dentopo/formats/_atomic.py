"""Atomic file writes: a temporary file in the same directory, renamed over the target.

The temporary file is made by :func:`tempfile.mkstemp`: a new name, created
with ``O_CREAT | O_EXCL | O_NOFOLLOW``, so that a file or a symbolic link
planted where it goes is never opened, let alone written (another name is
drawn).  Its mode is set through the open file (``fchmod``), never through the
name, and it is renamed only if its name still leads to the file written (not
to something put in its place meanwhile).  The rename replaces the target's
name: a symbolic link at the target is replaced by the new file, its own
target is left alone.
"""

from __future__ import annotations

import errno
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
    Text mode is UTF-8 with untranslated newlines; the surrogates by which
    Python holds the bytes of a file name that is not UTF-8 are written as
    those bytes (``errors="surrogateescape"``), so that such a name is kept.
    """
    path = os.fspath(path)
    directory = os.path.dirname(os.path.abspath(path))
    handle, temporary = tempfile.mkstemp(
        dir=directory, prefix=f".{os.path.basename(path)}.", suffix=".tmp"
    )
    try:
        mode = {"mode": "wb"} if binary else {"mode": "w", "encoding": "utf-8", "newline": ""}
        if not binary:  # a file name that is not UTF-8 (os.fsdecode's surrogates) as its bytes
            mode["errors"] = "surrogateescape"
        with os.fdopen(handle, **mode) as stream:
            write(stream)
            stream.flush()
            mode = 0o666 & ~_umask()  # mkstemp creates 0600
            if hasattr(os, "fchmod"):
                os.fchmod(stream.fileno(), mode)
            else:  # pragma: no cover -- Windows before Python 3.13
                os.chmod(temporary, mode)
            os.fsync(stream.fileno())
            mine = os.fstat(stream.fileno())
        there = os.lstat(temporary)
        if (there.st_dev, there.st_ino) != (mine.st_dev, mine.st_ino):  # not renamed: the target
            raise FileExistsError(  # would become whatever was put there
                errno.EEXIST, "the temporary file was replaced while it was written", temporary
            )
        os.replace(temporary, path)
    except BaseException:
        if os.path.lexists(temporary):
            os.unlink(temporary)
        raise
