"""Optional dependencies: imported only when their feature is used, with one clear error.

A plain ``pip install dentopo`` computes every metric; pictures, the fast
method, Dask, data frames and Excel output need an extra.  Asking for one
without it raises :class:`MissingExtraError` (an ``ImportError``) whose message
is one line naming the extra to install, e.g.
``pictures need the viz extra: pip install 'dentopo[viz]'``; the command line
prints that line and exits with 2.

May import: nothing of dentopo (every subpackage may import it).
"""

from __future__ import annotations

import importlib
from types import ModuleType


class MissingExtraError(ImportError):
    """An optional dependency is not installed; the message names the extra to install.

    Attributes
    ----------
    extra : str
        The extra that provides it (``viz``, ``fast``, ``table``, ...).
    purpose : str
        What needs it, as the start of the message (``"pictures"``).
    """

    def __init__(self, purpose: str, extra: str, *, name: str | None = None):
        self.purpose = purpose
        self.extra = extra
        super().__init__(missing_extra_message(purpose, extra), name=name)


def missing_extra_message(purpose: str, extra: str) -> str:
    """``"<purpose> need the <extra> extra: pip install 'dentopo[<extra>]'"``."""
    return f"{purpose} need the {extra} extra: pip install 'dentopo[{extra}]'"


def require(module: str, *, extra: str, purpose: str) -> ModuleType:
    """Import `module`, or raise :class:`MissingExtraError` naming `extra`.

    Parameters
    ----------
    module : str
        The module to import (``"pyvista"``, ``"distributed"``).
    extra : str
        The dentopo extra that installs it.
    purpose : str
        What needs it, plural, as the message's subject (``"pictures"``).

    Raises
    ------
    MissingExtraError
        If `module` (or a package it needs) is not installed.  Any other
        ``ImportError`` (installed but broken, e.g. a missing system library)
        propagates unchanged, since installing the extra would not help.
    """
    try:
        return importlib.import_module(module)
    except ModuleNotFoundError as exc:
        raise MissingExtraError(purpose, extra, name=exc.name) from exc
