"""One writer per output table, and a table that can be written, checked before any work.

:class:`OutputLock` holds ``fcntl.flock`` on a lock file ``.NAME.lock`` beside
the table ``NAME`` for a whole run: a second run on the same table waits until
the first has finished (and then reads what it wrote), so that neither
overwrites the other's rows.  The operating system releases the lock when its
process dies, however it dies, so a killed run never leaves a stale lock.  The
lock file holds the owner's pid (for the message of a run that waits) and is
removed when the lock is released.  Where ``fcntl`` does not exist (Windows)
the lock does nothing.

The lock file is created new (``O_CREAT | O_EXCL``) or opened as it is, never
through a symbolic link (``O_NOFOLLOW``), and written only if it is one of
ours: a regular file with one name, empty or holding a process id.  Anything
else planted at ``.NAME.lock`` (a link to a file the run must not touch, a
second name of such a file, a device, a file with other content) is refused
with :class:`ForeignLockError`, naming the path, and left exactly as it was.

:func:`check_writable` creates and removes a temporary file where the table
will be written, so that a table that cannot be written is found before the
first mesh is computed rather than after the last.
"""

from __future__ import annotations

import errno
import os
import re
import stat
import tempfile
from collections.abc import Callable

try:
    import fcntl
except ImportError:  # pragma: no cover -- Windows
    fcntl = None


def lock_path(output: str | os.PathLike) -> str:
    """The lock file of the table `output`: ``.<name>.lock`` beside it."""
    directory, name = os.path.split(os.path.abspath(os.fspath(output)))
    return os.path.join(directory, f".{name}.lock")


class ForeignLockError(OSError):
    """Something that is not a dentopo lock file is where the lock file goes (left untouched)."""

    def __str__(self) -> str:
        return f"{self.filename!r} is {self.strerror}"


#: Flags that never follow a link and never wait on a FIFO (0 where the system lacks them).
_SAFE = getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0)
_PID = re.compile(rb"[0-9]*\n?")


def _foreign(path: str, what: str) -> ForeignLockError:
    return ForeignLockError(
        errno.EEXIST,
        f"{what}, not a dentopo lock file: it was left as it is; move it away (dentopo "
        "creates and removes this file itself)",
        path,
    )


def _open_lock(path: str) -> int:
    """Open or create the lock file at `path`, refusing anything that is not one of ours."""
    while True:
        try:
            return os.open(path, os.O_RDWR | os.O_CREAT | os.O_EXCL | _SAFE, 0o666)
        except FileExistsError:
            pass
        try:
            fd = os.open(path, os.O_RDWR | _SAFE)
        except FileNotFoundError:  # its holder removed it meanwhile: create it
            continue
        except OSError as exc:
            if exc.errno == errno.ELOOP or os.path.islink(path):
                raise _foreign(path, "a symbolic link") from None
            raise
        try:
            info = os.fstat(fd)
            if not stat.S_ISREG(info.st_mode):
                raise _foreign(path, "not a regular file")
            if info.st_nlink != 1:
                raise _foreign(path, f"a file with {info.st_nlink} names (a hard link)")
            if info.st_size > 32 or not _PID.fullmatch(os.pread(fd, 33, 0)):
                raise _foreign(path, "a file holding something else than a process id")
        except BaseException:
            os.close(fd)
            raise
        return fd


def _owner(fd: int) -> int | None:
    try:
        text = os.pread(fd, 32, 0).decode("ascii", "replace").strip()
        return int(text) if text else None
    except (OSError, ValueError):
        return None


class OutputLock:
    """An exclusive lock on the table `output` (see the module docstring).

    Parameters
    ----------
    output : str or path-like
        The table.
    on_wait : callable, optional
        ``on_wait(pid)`` is called once if another process holds the lock,
        before waiting for it (`pid` is that process, or None if unknown).
    """

    def __init__(
        self, output: str | os.PathLike, *, on_wait: Callable[[int | None], None] | None = None
    ):
        self.path = lock_path(output)
        self.on_wait = on_wait
        self._fd: int | None = None

    def acquire(self) -> None:
        """Take the lock, waiting for another holder to finish.

        Raises
        ------
        ForeignLockError
            If something that is not a dentopo lock file is at its path.
        OSError
            If the lock file cannot be created.
        """
        if fcntl is None:
            return
        told = False
        while True:
            fd = _open_lock(self.path)
            try:
                try:
                    fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
                except OSError as exc:
                    if exc.errno not in (errno.EWOULDBLOCK, errno.EAGAIN, errno.EACCES):
                        raise
                    if not told and self.on_wait is not None:
                        self.on_wait(_owner(fd))
                    told = True
                    fcntl.flock(fd, fcntl.LOCK_EX)  # an interrupt raises out of the wait
                # the holder removes the file as it releases it: lock the file that is there
                mine = os.fstat(fd)
                try:
                    there = os.lstat(self.path)
                except FileNotFoundError:
                    there = None
                if there is not None and (there.st_dev, there.st_ino) == (mine.st_dev, mine.st_ino):
                    os.ftruncate(fd, 0)
                    os.pwrite(fd, f"{os.getpid()}\n".encode("ascii"), 0)
                    self._fd = fd
                    return
            except BaseException:
                os.close(fd)
                raise
            os.close(fd)

    def release(self) -> None:
        """Release the lock and remove the lock file (safe to call more than once)."""
        if self._fd is None:
            return
        try:
            os.unlink(self.path)
        except OSError:
            pass
        os.close(self._fd)  # closing releases the lock
        self._fd = None

    def __enter__(self) -> OutputLock:
        self.acquire()
        return self

    def __exit__(self, *exc) -> None:
        self.release()


def check_writable(path: str | os.PathLike) -> None:
    """Check that a table can be written at `path`, leaving nothing behind.

    Creates and removes a temporary file in its directory (the way the table
    itself is written), and refuses an existing file without write permission.

    Raises
    ------
    OSError
        Naming the problem: a missing directory or one that is a file
        (``NotADirectoryError``), no permission (``PermissionError``), a
        read-only file system, ...
    """
    path = os.fspath(path)
    directory = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(directory):
        error = errno.ENOTDIR if os.path.exists(directory) else errno.ENOENT
        raise OSError(error, os.strerror(error), directory)
    if os.path.isdir(path):
        raise IsADirectoryError(errno.EISDIR, os.strerror(errno.EISDIR), path)
    handle, probe = tempfile.mkstemp(dir=directory, prefix=f".{os.path.basename(path)}.")
    os.close(handle)
    os.unlink(probe)
    if os.path.exists(path) and not os.access(path, os.W_OK):
        raise PermissionError(errno.EACCES, "the file is read-only", path)
