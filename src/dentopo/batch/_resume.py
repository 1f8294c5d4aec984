"""Resuming a batch: which rows of a previous table can be kept, and merging them.

A previous ``ok`` row is reused when it holds every metric asked for, computed
with the same settings and the same preparation protocol digest
(:func:`resumable_files`); such rows are relabelled with this run's protocol
name (:func:`relabel_resumed`) and merged with the new rows, one per file,
sorted by file (:func:`merge_records`).
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable

from ..formats import METRIC_KEYS, PROTOCOL_KEY
from ..topography import rotation_key
from ._settings import ARIADNE_OPTIONS, Settings


def resumable_files(previous: Iterable[dict], settings: Settings) -> set[str]:
    """Files (as absolute paths) with an ``ok`` row holding what `settings` computes.

    The row must hold a value for every metric asked for (a row of more
    metrics serves a run of fewer), computed with the same settings: those
    of ariaDNE (with ``method="auto"`` a row computed by either method
    counts, as auto may pick either; otherwise the recorded method must
    match) and of the topography metrics.  With a ``geometry`` no row counts:
    the table does not record which mesh was read.  The row's ``protocol``
    must name the same protocol digest as `settings.prepare` (the first 12
    hex digits the label holds), or both none: a row measured as read is
    not reused for a prepared run, nor the other way round.
    """
    reusable = _reusable(settings)
    return {os.path.abspath(r["file"]) for r in previous if reusable(r) and r.get("file")}


def relabel_resumed(previous: Iterable[dict], settings: Settings) -> list[dict]:
    """`previous`, each row `settings` could reuse labelled with this run's protocol.

    Rows are reused for the same protocol digest (:func:`resumable_files`): the
    digest covers every step, the name nothing that is computed.  A protocol
    renamed since keeps its rows, under its new name, so that a table never
    names one protocol two ways (the report groups and finds protocols by the
    label).  Changed rows are copies; those passed in are untouched.
    """
    label = settings.protocol
    reusable = _reusable(settings)
    return [
        {**r, PROTOCOL_KEY: label}
        if label is not None and r.get(PROTOCOL_KEY) != label and reusable(r)
        else r
        for r in previous
    ]


def _reusable(settings: Settings) -> Callable[[dict], bool]:
    """Whether a row holds what `settings` computes (see :func:`resumable_files`)."""
    if settings.geometry is not None:
        return lambda record: False
    digest = None if settings.prepare is None else settings.prepare.digest[:12]
    wanted = dict(settings.topography.settings(settings.metrics))
    if "ariadne" in settings.metrics:
        wanted.update(settings.options())
        if wanted["method"] == "auto":
            del wanted["method"]
    values = [
        key
        for metric in settings.metrics
        for key in METRIC_KEYS[metric]
        if key not in ARIADNE_OPTIONS
    ]
    values += [rotation_key(degrees) for degrees in settings.rotations()]

    def reusable(record: dict) -> bool:
        return (
            record.get("status") == "ok"
            and all(record.get(name) == value for name, value in wanted.items())
            and all(record.get(key) is not None for key in values)
            and protocol_digest(record.get(PROTOCOL_KEY)) == digest
        )

    return reusable


def protocol_digest(label) -> str | None:
    """The short digest in a ``protocol`` cell (``"crown-10k 3f2a9c1e0b7d"``), or None if empty.

    A cell that is not a label (no digest after the name) gives itself, which
    matches no protocol.
    """
    if label is None or (isinstance(label, float) and label != label) or str(label) == "":
        return None
    return str(label).rsplit(" ", 1)[-1]


def merge_records(previous: Iterable[dict], new: Iterable[dict]) -> list[dict]:
    """Previous rows overridden by new rows for the same file, sorted by file."""
    merged = {os.path.abspath(r["file"]): r for r in previous if r.get("file")}
    merged.update({os.path.abspath(r["file"]): r for r in new})
    return sorted(merged.values(), key=lambda r: r["file"])
