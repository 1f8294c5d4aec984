"""Every metric a run asks for, on one mesh: one record, one failure per metric at most.

A batch row holds ariaDNE and molaR's topography metrics side by side.  The
mesh is read once, and cleaned once for all of molaR's metrics (one
:class:`dentopo.topography.Surface`, which also keeps the orientation found,
so it is checked once); each metric is then computed on its own, and a metric
that fails (RFI on a pinched footprint, say) leaves its cells empty and names its
error, while the other metrics of the row are kept, as molaR_Batch carries on.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field

from ..ariadne import ariaDNE
from ..formats import METRIC_KEYS, SETTING_KEYS
from ..mesh import load_mesh
from ..topography import (
    CLASSIC_KEYS,
    ORIENTED,
    check_alpha,
    check_find_alpha,
    check_finite,
    check_int,
    check_metrics,
    check_orient,
    classic_dne,
    opc,
    opcr,
    prepare_surface,
    rfi,
    rotation_key,
    rotations,
    slope,
)
from ._errors import failure_reason, names_step


@dataclass(frozen=True)
class TopographyOptions:
    """The options of molaR's topography metrics in a batch (molaR's defaults).

    Attributes
    ----------
    alpha : float
        RFI's alpha (the starting alpha with `find_alpha`).
    find_alpha : bool
        Search for molaR's smallest valid alpha.
    opcr_steps : int
        OPCR's number of rotations.
    opcr_step : float
        OPCR's rotation step, degrees.
    min_faces : int
        OPC's smallest counted patch, in faces.
    orient : str
        ``"as-is"`` (molaR's behaviour) or ``"auto"`` (a crown pointing to -z
        is turned before the metrics that assume +z).
    """

    alpha: float = 0.075
    find_alpha: bool = False
    opcr_steps: int = 8
    opcr_step: float = 5.625
    min_faces: int = 3
    orient: str = "as-is"

    def __post_init__(self):
        # the metrics' own checks, made once for the whole batch
        object.__setattr__(self, "alpha", check_alpha(self.alpha))
        object.__setattr__(self, "find_alpha", check_find_alpha(self.find_alpha))
        object.__setattr__(self, "opcr_steps", check_int("opcr_steps", self.opcr_steps, low=1))
        object.__setattr__(self, "opcr_step", check_finite("opcr_step", self.opcr_step))
        object.__setattr__(self, "min_faces", check_int("min_faces", self.min_faces, low=0))
        object.__setattr__(self, "orient", check_orient(self.orient))

    def rotations(self) -> tuple[float, ...]:
        """OPCR's rotations, degrees."""
        return rotations(self.opcr_steps, self.opcr_step)

    def settings(self, metrics: Iterable[str]) -> dict:
        """The settings columns of `metrics` (:data:`dentopo.formats.SETTING_KEYS`)."""
        values = {
            "rfi_alpha": self.alpha,
            "find_alpha": self.find_alpha,
            "opcr_steps": self.opcr_steps,
            "opcr_step": self.opcr_step,
            "min_faces": self.min_faces,
        }
        record = {}
        for metric in metrics:
            record.update({key: values[key] for key in SETTING_KEYS.get(metric, ())})
        if ORIENTED.intersection(metrics):
            record["orient"] = self.orient
        return record


@dataclass(frozen=True)
class Measurement:
    """What the metrics of one mesh gave.

    Attributes
    ----------
    record : dict
        The values of every metric asked for (None where it failed), the
        orientation found, and the settings columns; no ``file``,
        ``seconds``, ``status`` or ``error``.
    results : dict
        Each metric's result object, by metric name (failed metrics absent).
    errors : dict
        Each failed metric's reason, by metric name.
    metrics : tuple of str
        The metrics asked for.
    """

    record: dict
    results: dict = field(default_factory=dict)
    errors: dict = field(default_factory=dict)
    metrics: tuple[str, ...] = ()

    @property
    def status(self) -> str:
        """``"ok"``, ``"partial"`` (some metric failed) or ``"error"`` (every one did)."""
        if not self.errors:
            return "ok"
        return "error" if not self.results else "partial"

    @property
    def error(self) -> str | None:
        """The reasons of the failed metrics, ``"metric: reason; ..."``, or None.

        With one metric asked for, its reason alone.
        """
        if not self.errors:
            return None
        if len(self.metrics) == 1:
            return next(iter(self.errors.values()))
        return "; ".join(
            reason if names_step(reason, metric) else f"{metric}: {reason}"
            for metric, reason in self.errors.items()
        )


def _values(metric: str, result) -> dict:
    """The record values of one metric's result (classic DNE's under its prefixed keys)."""
    if metric == "classic":
        return {key: getattr(result, name) for name, key in CLASSIC_KEYS.items()}
    return result.to_dict()


def _prepared(mesh):
    """The surface molaR's metrics share, or the reason it could not be prepared."""
    try:
        return prepare_surface(mesh)
    except OSError:
        raise
    except Exception as exc:  # each metric names it (see _errors: ours, or an internal error)
        return exc


def _compute(metric: str, mesh, ariadne_options: dict, options: TopographyOptions, progress):
    if metric == "ariadne":
        return ariaDNE(mesh, progress=progress, **ariadne_options)
    if isinstance(mesh, BaseException):  # every topography metric fails as it would alone
        raise mesh
    if metric == "classic":
        return classic_dne(mesh)
    if metric == "rfi":
        return rfi(mesh, alpha=options.alpha, find_alpha=options.find_alpha, orient=options.orient)
    if metric == "opcr":
        return opcr(
            mesh,
            steps=options.opcr_steps,
            step=options.opcr_step,
            min_faces=options.min_faces,
            orient=options.orient,
        )
    if metric == "opc":
        return opc(mesh, min_faces=options.min_faces, orient=options.orient)
    return slope(mesh, orient=options.orient)


def measure_mesh(
    mesh,
    metrics: str | Iterable[str] = ("ariadne",),
    *,
    ariadne_options: dict | None = None,
    options: TopographyOptions | None = None,
    reason: Callable[[BaseException], str] = str,
    progress: Callable[[str], None] | None = None,
) -> Measurement:
    """Compute `metrics` on one mesh; a metric that fails is named, not raised.

    Parameters
    ----------
    mesh : trimesh.Trimesh, str, path-like or (vertices, faces)
        A path is read once (:func:`dentopo.load_mesh`) for all metrics.
        Reading errors are raised: without a mesh there is no row.
    metrics : str or iterable of str
        Names of :data:`dentopo.topography.METRICS`, or ``"all"``.
    ariadne_options : dict, optional
        Keywords of :func:`dentopo.ariaDNE`.
    options : TopographyOptions, optional
        The options of the topography metrics.
    reason : callable
        Turns a metric's exception into its reason text.
    progress : callable, optional
        ariaDNE's phase callback; each other metric's name is reported as it
        starts.
    """
    metrics = check_metrics(metrics)
    options = TopographyOptions() if options is None else options
    ariadne_options = {} if ariadne_options is None else ariadne_options
    if isinstance(mesh, (str, os.PathLike)) and metrics != ("ariadne",):
        mesh = load_mesh(mesh)  # once for all the metrics (ariaDNE alone reads it itself)
    surface = _prepared(mesh) if metrics != ("ariadne",) else None
    record: dict = {}
    results: dict = {}
    errors: dict = {}
    for metric in metrics:
        keys = METRIC_KEYS[metric]
        if metric != "ariadne" and progress is not None:
            progress(metric)
        given = mesh if metric == "ariadne" else surface
        try:
            result = _compute(metric, given, ariadne_options, options, progress)
        except OSError:
            raise  # reading the file (ariaDNE alone reads it): the row's error
        except Exception as exc:  # this metric, on this mesh; not ours: an internal error
            errors[metric] = failure_reason(metric, exc, reason)
            record.update(dict.fromkeys(keys))
            if metric == "opcr":
                record.update(dict.fromkeys(rotation_key(d) for d in options.rotations()))
            if metric == "ariadne":  # its settings columns are still the settings
                record.update(ariadne_options)
            continue
        results[metric] = result
        record.update(_values(metric, result))
        if metric in ORIENTED and "orientation" not in record:
            record["orientation"] = str(result.orientation)
    if ORIENTED.intersection(metrics):
        record.setdefault("orientation", None)
    record.update(options.settings(metrics))
    return Measurement(record, results, errors, metrics)
