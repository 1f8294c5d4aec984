"""Optional dependencies: imported only when their feature is used, with one clear error.

A plain ``pip install dentopo`` computes every metric; pictures, the fast
method, Dask, data frames and Excel output need an extra.  Asking for one
without it raises :class:`MissingExtraError` (an ``ImportError``) whose message
is one line naming the extra and the command that installs it both from a
clone of the repository and from PyPI, e.g. ``pictures need the viz extra:
pip install '.[viz]' in a clone of dentopo, pip install 'dentopo[viz]' from
PyPI``; the command line prints that line and exits with 2.

May import: nothing of dentopo (every subpackage may import it).
"""

from __future__ import annotations

import importlib
import importlib.util
from dataclasses import dataclass
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
    """One line: what needs `extra` and how to install it, from a clone and from PyPI.

    ``"<purpose> need the <extra> extra: pip install '.[<extra>]' in a clone
    of dentopo, pip install 'dentopo[<extra>]' from PyPI"``.
    """
    return (
        f"{purpose} need the {extra} extra: {install_command(extra, clone=True)} in a clone "
        f"of dentopo, {install_command(extra)} from PyPI"
    )


def install_command(extra: str, *, clone: bool = False) -> str:
    """``pip install 'dentopo[<extra>]'``, or ``pip install '.[<extra>]'`` in a clone."""
    return f"pip install '{'.' if clone else 'dentopo'}[{extra}]'"


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


def check(module: str, *, extra: str, purpose: str) -> None:
    """Raise :class:`MissingExtraError` if `module` is not installed, without importing it.

    A cheap test (``importlib.util.find_spec``) for checking up front, before
    any work is done, that a later :func:`require` can succeed.  It does not
    import `module`, so a broken installation shows only when :func:`require`
    runs.

    Parameters
    ----------
    module, extra, purpose : str
        As for :func:`require`.

    Raises
    ------
    MissingExtraError
        If `module` cannot be found.
    """
    try:
        found = importlib.util.find_spec(module) is not None
    except ImportError:  # a dotted name whose parent package is missing
        found = False
    except ValueError:  # a module in sys.modules without a spec (set up by hand)
        found = True
    if not found:
        raise MissingExtraError(purpose, extra, name=module)


@dataclass(frozen=True)
class Feature:
    """A feature behind an extra: what it is called, the module it imports, the extra.

    Attributes
    ----------
    purpose : str
        The feature, plural, as the subject of the message (``"pictures"``).
    module : str
        The module it imports (``"pyvista"``).
    extra : str
        The extra of ``pyproject.toml`` that installs it (``"viz"``).
    """

    purpose: str
    module: str
    extra: str

    def require(self) -> ModuleType:
        """Import the module, or raise :class:`MissingExtraError` (see :func:`require`)."""
        return require(self.module, extra=self.extra, purpose=self.purpose)

    def check(self) -> None:
        """Raise :class:`MissingExtraError` if the module is not installed (see :func:`check`)."""
        check(self.module, extra=self.extra, purpose=self.purpose)


#: PNG screenshots and interactive windows (HTML pages need no extra).
PICTURES = Feature("pictures", "pyvista", "viz")
#: ``method="fast"``: kernel sums by a non-uniform FFT.
FAST_METHOD = Feature("fast kernel sums (method 'fast')", "finufft", "fast")
#: Batches on a Dask scheduler.
DASK = Feature("Dask clusters", "distributed", "cluster")
#: ``to_dataframe``.
DATA_FRAMES = Feature("data frames", "pandas", "table")
#: The robustness study's and the bandwidth sweep's figures.
STUDY_FIGURES = Feature("study figures", "matplotlib", "study")
#: MorphoTester's outline area (its RFI), counted in a picture drawn by matplotlib's Agg.
MORPHOTESTER_OUTLINE = Feature(
    "MorphoTester's outline areas (morphotester_rfi)", "matplotlib", "viz"
)
#: PCV's exact method: a ray per vertex and direction, cast by Embree (embreex).
EXACT_OCCLUSION = Feature("exact ambient occlusion (PCV method 'exact')", "embreex", "rays")
#: ``.xlsx`` tables.
EXCEL = Feature("Excel tables", "openpyxl", "excel")
#: The collection report's plots and 3D views (plotly.js, inlined into the page).
REPORT = Feature("collection reports", "plotly", "report")

#: ``dentopo app``: its web framework and its server.
APP = Feature("web pages served by dentopo app", "starlette", "app")
APP_SERVER = Feature("web pages served by dentopo app", "uvicorn", "app")

#: Every feature above, for checks and tests.
FEATURES = (
    PICTURES,
    FAST_METHOD,
    DASK,
    DATA_FRAMES,
    STUDY_FIGURES,
    MORPHOTESTER_OUTLINE,
    EXACT_OCCLUSION,
    EXCEL,
    REPORT,
    APP,
    APP_SERVER,
)

#: ``prepare``'s ``decimate="meshlab"``: MeshLab's quadric edge collapse (pymeshlab, GPL).
#: Not in FEATURES: the ``meshlab`` extra is in neither ``all`` nor ``test`` (a 100 MB GPL
#: wheel), so the tests that every feature's module is installed do not hold for it.
MESHLAB = Feature("MeshLab's filters (decimate='meshlab')", "pymeshlab", "meshlab")
