"""``write_report``: a results table to one self-contained HTML page."""

from __future__ import annotations

import os
import time
from dataclasses import dataclass, field

from .._html_repr import result_html
from .._optional import PICTURES, REPORT
from ..batch import available_cores
from ..figures import DEFAULT_PERCENTILE, color_scale
from ..formats import atomic_write
from ._collect import collect, row_protocols
from ._fields import Field, measure_fields, run_calls, worker_count
from ._page import PageContent, render_page
from ._thumbnails import THUMBNAIL_SIZE, draw


@dataclass(frozen=True)
class ReportSummary:
    """What a report holds.

    Attributes
    ----------
    path : str
        The page written.
    specimens : int
        Rows of the table (one per specimen).
    pictured : int
        Specimens with a thumbnail and a 3D view.
    failed : int
        Rows whose status is not ``ok`` (failed or partial).
    problems : dict
        Specimen file -> why it has no picture (file not found, unreadable, ...).
    groups : tuple of str
        The groups, in the order shown.
    size : int
        The page's size in bytes.
    seconds : float
        Wall-clock time taken.
    unpictured : dict
        Specimen file -> why it has no picture, for the rows measured ``ok``
        only: what the page lacks although the table has it (a file moved or
        unreadable since, a worker that failed).  ``dentopo report`` exits 1
        when it is not empty.
    """

    path: str
    specimens: int
    pictured: int
    failed: int
    problems: dict
    groups: tuple[str, ...]
    size: int
    seconds: float
    unpictured: dict = field(default_factory=dict)

    def _repr_html_(self) -> str:
        """A compact table for notebooks."""
        return result_html(self)


def check_report_extras() -> None:
    """Raise :class:`~dentopo._optional.MissingExtraError` unless plotly and pyvista are there."""
    REPORT.check()
    PICTURES.check()


def write_report(
    table,
    path: str | os.PathLike,
    *,
    groups=None,
    title: str | None = None,
    limits=None,
    percentile: float = DEFAULT_PERCENTILE,
    jobs: int | None = None,
    thumbnail_size: int = THUMBNAIL_SIZE,
    prepare=None,
) -> ReportSummary:
    """Write one self-contained HTML page about a collection of measured meshes.

    The page holds a sortable, filterable table with one row per specimen
    (a thumbnail of its signed curvature map, its status, error and
    warnings, and every column the table holds but its settings: the metrics
    by family, ariaDNE, molaR, doolkit, MorphoTester, the projected
    footprint's RFI, PCV, with their units, then any column the package does
    not know, under "other", and the mesh counts), each metric's distribution
    per group (box plots over every point, family by family), a scatter
    matrix of the metrics ticked, coloured by group, a 3D view of any
    specimen on click (unpacked only then), each row's warnings, and the
    specimens that failed with their errors.  Specimens measured closed (as
    they lie) or turned, as their ``orientation`` cell says, are marked, and
    the marks explained.  It works offline: plotly.js is inlined once, and
    nothing is fetched.

    Parameters
    ----------
    table : str, path-like or sequence of dict
        A results table (any format and layout :func:`dentopo.read_table`
        reads) or its records.  Each row's file is looked for as written, then
        relative to the table's directory; ariaDNE's local curvature is
        recomputed with the row's settings for the pictures.
    path : str or path-like
        The HTML file to write (atomically).
    groups : str, path-like or mapping, optional
        A CSV with columns ``file`` and ``group``, or a ``{file: group}``
        mapping: a file matches by path (relative paths from the CSV's
        directory), else by base name; unmatched specimens are
        ``"(ungrouped)"``.  By default each file's folder relative to the
        files' common root (files in the root itself: the root's name).
    title : str, optional
        The page's title (default: from the table's name).
    limits, percentile
        The colour scale, one for the whole collection, symmetric about zero:
        fixed ``limits`` (``L`` or ``(-L, L)``), else ``percentile`` of the
        magnitude over every specimen's vertices (see :func:`dentopo.color_scale`).
    jobs : int, optional
        Worker processes recomputing the curvature and drawing the
        thumbnails (default: every core; 1, or fewer than a dozen files: in
        this process).  The page does not depend on it.
    thumbnail_size : int
        Thumbnail width and height, pixels.
    prepare : Protocol, str or path-like, or a list of them, optional
        The preparation protocol of rows whose ``protocol`` column names one
        (tables of ``compute_batch(prepare=...)``, ``dentopo --prepare``):
        their pictures are of the crown prepared again with it, as measured,
        and the page states the protocol and its steps.  A row holds only its
        protocol's label, so a protocol that is not shipped must be given
        (its digest must be the row's; a list when rows were prepared with
        several); shipped ones are found by digest.

    Returns
    -------
    ReportSummary
        What the page holds, its size and the time taken.

    Raises
    ------
    TypeError, ValueError
        For a table that cannot be read, a bad groups file, bad limits.
    dentopo._optional.MissingExtraError
        Without plotly (``pip install 'dentopo[report]'``, in a clone ``pip install '.[report]'``)
        or pyvista.

    Examples
    --------
    >>> from dentopo import write_report
    >>> write_report("results.csv", "report.html")  # doctest: +SKIP
    """
    start = time.perf_counter()
    plotly = REPORT.require()
    PICTURES.require()
    if jobs is not None and (isinstance(jobs, bool) or not isinstance(jobs, int) or jobs < 0):
        raise ValueError(f"jobs must be 0 (every core) or a positive integer; got {jobs!r}")
    if isinstance(thumbnail_size, bool) or not isinstance(thumbnail_size, int):
        raise TypeError(f"thumbnail_size must be an integer; got {thumbnail_size!r}")
    if not 16 <= thumbnail_size <= 1024:
        raise ValueError(f"thumbnail_size must lie in [16, 1024]; got {thumbnail_size}")
    fixed = None if limits is None else color_scale(limits=limits)  # checked before any work
    if fixed is not None and fixed.low not in (None, -fixed.limit):
        raise ValueError(
            "the report's colour limits are symmetric, one scale (-L, L) for the whole "
            f"collection so that its pictures compare; got limits={limits!r}"
        )
    path = os.fspath(path)
    specimens, columns = collect(table, groups=groups)
    charted = {column.key for column in columns if column.charted}
    protocols = row_protocols(specimens, prepare)  # before any work: a missing one is named

    for specimen in specimens:  # its ariaDNE failed when the table was computed: so would ours
        if "dne" in charted and specimen.status == "partial" and specimen.record.get("dne") is None:
            specimen.problem = specimen.problem or "ariaDNE failed (see the error)"
    todo = [s for s in specimens if s.path is not None and s.status != "error" and not s.problem]
    jobs = jobs or available_cores()
    workers = worker_count(jobs, len(todo))
    fields = measure_fields(
        [(s.path, s.ariadne_options(), protocols.get(s.protocol_label)) for s in todo], workers
    )
    drawn: dict[int, Field] = {}
    for specimen, result in zip(todo, fields, strict=True):
        if isinstance(result, Field):
            drawn[specimen.index] = result
        else:
            specimen.problem = result
    if limits is not None:
        scale = color_scale(limits=limits)
    elif drawn:
        scale = color_scale([f.values for f in drawn.values()], percentile=percentile)
    else:
        scale = color_scale(limits=1.0)
    indices = list(drawn)
    chunks = [indices[k::workers] for k in range(workers)]  # one plotter per worker
    chunks = [chunk for chunk in chunks if chunk]
    pictures = run_calls(
        draw,
        [([drawn[i] for i in chunk], scale, thumbnail_size) for chunk in chunks],
        workers,
        lambda call, reason: draw(*call),  # a worker died: draw its share here
    )
    thumbnails, payloads = {}, {}
    for chunk, results in zip(chunks, pictures, strict=True):
        for index, (thumbnail, payload) in zip(chunk, results, strict=True):
            thumbnails[index], payloads[index] = thumbnail, payload
    thumbnails = dict(sorted(thumbnails.items()))
    payloads = dict(sorted(payloads.items()))

    order = list(dict.fromkeys(sorted(s.group for s in specimens)))
    source = os.fspath(table) if isinstance(table, (str, os.PathLike)) else "records"
    if title is None:
        base = os.path.splitext(os.path.basename(source))[0] if source != "records" else ""
        title = f"dentopo report: {base}" if base else "dentopo report"
    notes = []
    if "dne" not in charted:
        notes.append("The table holds no ariaDNE column: pictures use ariaDNE's default settings.")
    content = PageContent(
        title=title,
        source=source,
        specimens=specimens,
        columns=columns,
        groups=order,
        scale=scale,
        thumbnails=thumbnails,
        payloads=payloads,
        plotly_js=plotly.offline.get_plotlyjs(),
        notes=notes,
        protocols=[(label, protocols[label]) for label in sorted(protocols)],
    )
    page = render_page(content).encode("utf-8")
    atomic_write(path, lambda stream: stream.write(page), binary=True)
    return ReportSummary(
        path=path,
        specimens=len(specimens),
        pictured=len(drawn),
        failed=sum(s.status != "ok" for s in specimens),
        problems={s.file: s.problem for s in specimens if s.problem},
        groups=tuple(order),
        size=len(page),
        seconds=time.perf_counter() - start,
        unpictured={s.file: s.problem for s in specimens if s.problem and s.status == "ok"},
    )
