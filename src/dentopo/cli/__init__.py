"""The ``dentopo`` command (also ``python -m dentopo``): a thin shell over the public API.

``_main`` dispatches to a subcommand or the main command; ``_compute`` is the
main command (a table with one row per mesh), with its parser in ``_arguments``,
its checks before any file is read in ``_checks`` and its pictures in
``_pictures``, drawing its progress with ``_progress`` and its table with
``_table`` (both with rich on a terminal, plain text otherwise), and keeping its
table file with ``_output`` (checked before any work, locked, each finished row
journalled as it finishes);
``_study`` the ``robustness`` and ``sweep`` subcommands; ``_compiling`` prints
one line while numba compiles kernels (a fresh install's first run).  Only this
subpackage prints or exits.  A missing extra ends as one line naming it, with
exit code 2; an interrupt as one line, with exit code 130.

May import: every other subpackage of dentopo; nothing imports it.
"""

from ._main import SUBCOMMANDS, main, run

__all__ = ["SUBCOMMANDS", "main", "run"]
