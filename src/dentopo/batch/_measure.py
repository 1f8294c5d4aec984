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
from ..formats import DOOLKIT_NAMES, METRIC_KEYS, SETTING_KEYS
from ..mesh import load_mesh
from ..topography import (
    CLASSIC_KEYS,
    DOOLKIT_BASE_KEYS,
    DOOLKIT_METRICS,
    ORIENTED,
    angularity,
    arc,
    check_alpha,
    check_arc_options,
    check_classic_options,
    check_duplicates,
    check_find_alpha,
    check_finite,
    check_int,
    check_metrics,
    check_min_area,
    check_orient,
    classic_dne,
    doolkit_arc,
    doolkit_dne,
    doolkit_opc,
    doolkit_opcr,
    doolkit_slope,
    footprint_area,
    hypsodonty,
    inclination,
    opc,
    opcr,
    prepare_surface,
    relief_index,
    relief_rate_below_median,
    rfi,
    rotation_key,
    rotations,
    shape_index,
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
    min_area : float
        OPC's smallest counted patch as a fraction of the surface area
        (molaR's ``minimum_area``; 0: count by `min_faces`).
    dne_outliers : float
        Classic DNE's outlier percentage (molaR's ``outliers``).
    dne_boundary : str
        Classic DNE's boundary rule (molaR's ``BoundaryDiscard``: ``"vertex"``,
        ``"leg"`` or ``"none"``).
    dne_kappa : float
        Classic DNE's convex/concave threshold (molaR's ``kappa``).
    arc_boundary : str
        ARC's boundary rule (``"vertex"``, ``"leg"`` or ``"none"``).
    arc_range : (float, float)
        ARC's quantiles beyond which faces are zeroed (molaR's ``Range``).
    orient : str
        ``"as-is"`` (molaR's behaviour) or ``"auto"`` (a crown pointing to -z
        is turned before the metrics that assume +z, and faces wound inward
        are rewound before those and classic DNE).
    duplicates : str
        ``"drop"`` (faces listed twice measured once) or ``"keep"`` (molaR's:
        as listed); see :func:`dentopo.topography.prepare_surface`.
    """

    alpha: float = 0.075
    find_alpha: bool = False
    opcr_steps: int = 8
    opcr_step: float = 5.625
    min_faces: int = 3
    min_area: float = 0.0
    dne_outliers: float = 0.1
    dne_boundary: str = "vertex"
    dne_kappa: float = 0.0
    arc_boundary: str = "vertex"
    arc_range: tuple[float, float] = (0.01, 0.99)
    orient: str = "auto"
    duplicates: str = "drop"

    def __post_init__(self):
        # the metrics' own checks, made once for the whole batch
        object.__setattr__(self, "alpha", check_alpha(self.alpha))
        object.__setattr__(self, "find_alpha", check_find_alpha(self.find_alpha))
        object.__setattr__(self, "opcr_steps", check_int("opcr_steps", self.opcr_steps, low=1))
        object.__setattr__(self, "opcr_step", check_finite("opcr_step", self.opcr_step))
        object.__setattr__(self, "min_faces", check_int("min_faces", self.min_faces, low=0))
        object.__setattr__(self, "min_area", check_min_area(self.min_area))
        outliers, boundary, kappa = check_classic_options(
            self.dne_outliers, self.dne_boundary, self.dne_kappa
        )
        object.__setattr__(self, "dne_outliers", outliers)
        object.__setattr__(self, "dne_boundary", boundary)
        object.__setattr__(self, "dne_kappa", kappa)
        boundary, quantiles = check_arc_options(self.arc_boundary, self.arc_range)
        object.__setattr__(self, "arc_boundary", boundary)
        object.__setattr__(self, "arc_range", quantiles)
        object.__setattr__(self, "orient", check_orient(self.orient))
        object.__setattr__(self, "duplicates", check_duplicates(self.duplicates))

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
            "min_area": self.min_area,
            "dne_outliers": self.dne_outliers,
            "dne_boundary": self.dne_boundary,
            "dne_kappa": self.dne_kappa,
            "arc_boundary": self.arc_boundary,
            "arc_range_low": self.arc_range[0],
            "arc_range_high": self.arc_range[1],
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
    """The record values of one metric's result (classic DNE's under its prefixed keys).

    doolkit's metrics give their values under the names of doolkit's table,
    which are the record keys except where molaR has the name (OPC, OPCR:
    ``dk_`` keys, see :data:`dentopo.formats.DOOLKIT_NAMES`).
    """
    if metric == "classic":
        return {key: getattr(result, name) for name, key in CLASSIC_KEYS.items()}
    if metric == "footprint":
        concave, convex = result
        return {"area2d": concave.area, "area2d_convex": convex.area}
    values = result.to_dict()
    if metric in DOOLKIT_METRICS:
        return {key: values[DOOLKIT_NAMES.get(key, key)] for key in METRIC_KEYS[metric]}
    return values


def _prepared(mesh, options: TopographyOptions):
    """The surface molaR's metrics share, or the reason it could not be prepared."""
    try:
        return prepare_surface(mesh, duplicates=options.duplicates)
    except OSError:
        raise
    except Exception as exc:  # each metric names it (see _errors: ours, or an internal error)
        return exc


def _compute(metric: str, mesh, ariadne_options: dict, options: TopographyOptions, progress):
    if metric == "ariadne":
        return ariaDNE(mesh, progress=progress, **ariadne_options)
    if isinstance(mesh, BaseException):  # every topography metric fails as it would alone
        raise mesh
    return _TOPOGRAPHY[metric](mesh, options)


def _opcr(surface, options: TopographyOptions):
    return opcr(
        surface,
        steps=options.opcr_steps,
        step=options.opcr_step,
        min_faces=options.min_faces,
        min_area=options.min_area,
        orient=options.orient,
    )


#: ``compute(surface, options)`` of each topography metric.
_TOPOGRAPHY = {
    "classic": lambda surface, options: classic_dne(
        surface,
        outliers=options.dne_outliers,
        boundary=options.dne_boundary,
        kappa=options.dne_kappa,
        orient=options.orient,
    ),
    "rfi": lambda surface, options: rfi(
        surface, alpha=options.alpha, find_alpha=options.find_alpha, orient=options.orient
    ),
    "opcr": _opcr,
    "opc": lambda surface, options: opc(
        surface, min_faces=options.min_faces, min_area=options.min_area, orient=options.orient
    ),
    "slope": lambda surface, options: slope(surface, orient=options.orient),
    "arc": lambda surface, options: arc(
        surface, boundary=options.arc_boundary, range=options.arc_range
    ),
    "angularity": lambda surface, options: angularity(surface),
    "doolkit_slope": lambda surface, options: doolkit_slope(surface),
    "relief_index": lambda surface, options: relief_index(surface, orient=options.orient),
    "inclination": lambda surface, options: inclination(surface, orient=options.orient),
    "doolkit_opc": lambda surface, options: doolkit_opc(surface, orient=options.orient),
    "doolkit_opcr": lambda surface, options: doolkit_opcr(surface, orient=options.orient),
    "doolkit_arc": lambda surface, options: doolkit_arc(surface),
    "doolkit_dne": lambda surface, options: doolkit_dne(surface),
    "relief_rate": lambda surface, options: relief_rate_below_median(
        surface, orient=options.orient
    ),
    "shape_index": lambda surface, options: shape_index(surface),
    # doolkit's area2d (concave) and its convex counterpart
    "footprint": lambda surface, options: (
        footprint_area(surface, hull="concave", orient=options.orient),
        footprint_area(surface, hull="convex", orient=options.orient),
    ),
    "hypsodonty": lambda surface, options: hypsodonty(surface),
}


def _doolkit_base(surface) -> dict:
    """doolkit's first columns: the counts and 3D area of the mesh its metrics measured."""
    if isinstance(surface, BaseException):
        return dict.fromkeys(DOOLKIT_BASE_KEYS)
    return {
        "n_vertices": len(surface.vertices),
        "n_faces": len(surface.faces),
        "area3d": float(surface.single_precision_areas().sum()),
    }


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
    surface = _prepared(mesh, options) if metrics != ("ariadne",) else None
    record: dict = {}
    results: dict = {}
    errors: dict = {}
    for metric in metrics:
        if metric in DOOLKIT_METRICS and "n_vertices" not in record:
            record.update(_doolkit_base(surface))
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
