"""What a batch returns: its records, a list of dicts that becomes a DataFrame in one call."""

from __future__ import annotations

from collections.abc import Iterable

from .._html_repr import rows_html
from .._optional import DATA_FRAMES
from ..formats import COLUMNS

#: Columns a batch's notebook table shows first.
_FIRST = ("file", "status", "dne", "positive_dne", "negative_dne")

#: Columns shown once above a batch's notebook table when every row has the same value.
_SETTINGS = ("bandwidth", "cutoff")


def to_dataframe(records: Iterable[dict]):
    """The records of :func:`compute_batch` as a pandas DataFrame (columns in order).

    Raises
    ------
    dentopo._optional.MissingExtraError
        An ``ImportError``: pandas is not installed (``pip install 'dentopo[table]'``, in a
        clone ``pip install '.[table]'``).
    """
    pd = DATA_FRAMES.require()
    records = list(records)
    keys = list(dict.fromkeys(key for record in records for key in record)) or list(COLUMNS)
    return pd.DataFrame(records, columns=keys)


class BatchResult(list):
    """The records of :func:`compute_batch`: a ``list`` of dicts, one per file, sorted by file.

    Everything a list does works (indexing, ``len``, ``json.dump``,
    ``pandas.DataFrame(result)``, equality with a plain list); on top of that
    :meth:`to_dataframe` gives the table with its columns in order, and a
    notebook shows the batch as a compact table (``_repr_html_``).

    Examples
    --------
    >>> from dentopo import compute_batch
    >>> table = compute_batch("scans/", metrics=["ariadne", "rfi"]).to_dataframe()  # doctest: +SKIP
    >>> table.set_index("file")["rfi"]  # doctest: +SKIP
    """

    __slots__ = ()

    def to_dataframe(self):
        """These records as a pandas DataFrame: one row per file, columns in table order.

        Raises
        ------
        dentopo._optional.MissingExtraError
            An ``ImportError``: pandas is not installed (``pip install 'dentopo[table]'``, in a
        clone ``pip install '.[table]'``).
        """
        return to_dataframe(self)

    @property
    def failed(self) -> list[dict]:
        """The records whose status is not ``"ok"`` (errors and partial rows)."""
        return [record for record in self if record.get("status") != "ok"]

    def _repr_html_(self) -> str:
        statuses: dict[str, int] = {}
        for record in self:
            status = str(record.get("status"))
            statuses[status] = statuses.get(status, 0) + 1
        summary: dict[str, object] = {"files": len(self)}
        summary.update(statuses)
        return rows_html(
            self, title=type(self).__name__, summary=summary, first=_FIRST, settings=_SETTINGS
        )
