"""Every metric a run asks for, on one mesh: one record, one failure per metric at most.

A batch row holds ariaDNE and molaR's topography metrics side by side.  The
mesh is read once, and cleaned once for all of molaR's metrics (one
:class:`dentopo.topography.Surface`, which also keeps the orientation found,
so it is checked once); each metric is then computed on its own, and a metric
that fails (RFI on a pinched footprint, say) leaves its cells empty and names its
error, while the other metrics of the row are kept, as molaR_Batch carries on.
"""

from __future__ import annotations

import importlib
import math
import os
import warnings
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field

import numpy as np

from ..ariadne import ariaDNE
from ..formats import DOOLKIT_NAMES, METRIC_KEYS, SETTING_KEYS
from ..mesh import as_arrays, clean_listed, load_mesh, read_ply
from ..mesh._lazy import unbuilt
from ..topography import (
    CLASSIC_KEYS,
    DOOLKIT_BASE_KEYS,
    DOOLKIT_METRICS,
    MORPHOTESTER_METRICS,
    MORPHOTESTER_ROTATION_KEYS,
    ORIENTED,
    UNIT_DEPENDENT,
    UnitWarning,
    check_alpha,
    check_arc_options,
    check_classic_options,
    check_duplicates,
    check_find_alpha,
    check_int,
    check_metrics,
    check_min_area,
    check_morphotester_options,
    check_opcr_options,
    check_orient,
    check_pcv_options,
    millimetres_per_unit,
    opc,
    opcr,
    prepare_surface,
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
    unit : str, float or None
        The meshes' length unit: a name (``"um"``, ``"mm"``, ``"cm"``, ``"m"``,
        ``"in"``) or millimetres per unit; kept as millimetres per unit.
        doolkit's metrics whose definitions assume millimetres
        (:data:`dentopo.topography.UNIT_DEPENDENT`: angularity, the relief
        indices, ARC, shape index, footprint, hypsodonty) are measured on the
        crown rescaled to millimetres, their lengths and areas given back in
        the mesh's unit.  None (the default): the coordinates are taken as
        millimetres, as doolkit takes them, and the rows say where that matters.
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
    unit: float | None = None
    mt_condition_check: bool = True
    mt_outliers: str = "energy"
    mt_percentile: float = 99.9
    mt_smooth: bool = False
    mt_min_patch: int = 5
    pcv_rays: int = 256
    pcv_hemisphere: bool = True
    pcv_method: str = "cloudcompare"

    def __post_init__(self):
        # the metrics' own checks, made once for the whole batch
        object.__setattr__(self, "alpha", check_alpha(self.alpha))
        object.__setattr__(self, "find_alpha", check_find_alpha(self.find_alpha))
        steps, step = check_opcr_options(self.opcr_steps, self.opcr_step)
        object.__setattr__(self, "opcr_steps", steps)
        object.__setattr__(self, "opcr_step", step)
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
        object.__setattr__(self, "unit", millimetres_per_unit(self.unit))
        check, outliers, percentile, smooth, patch = check_morphotester_options(
            self.mt_condition_check,
            self.mt_outliers,
            self.mt_percentile,
            self.mt_smooth,
            self.mt_min_patch,
        )
        object.__setattr__(self, "mt_condition_check", check)
        object.__setattr__(self, "mt_outliers", "off" if outliers is None else outliers)
        object.__setattr__(self, "mt_percentile", percentile)
        object.__setattr__(self, "mt_smooth", smooth)
        object.__setattr__(self, "mt_min_patch", patch)
        rays, hemisphere, method = check_pcv_options(
            self.pcv_rays, self.pcv_hemisphere, self.pcv_method
        )
        object.__setattr__(self, "pcv_rays", rays)
        object.__setattr__(self, "pcv_hemisphere", hemisphere)
        object.__setattr__(self, "pcv_method", method)

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
            "mm_per_unit": self.unit,
            "mt_condition_check": self.mt_condition_check,
            "mt_outliers": self.mt_outliers,
            "mt_percentile": self.mt_percentile,
            "mt_smooth": self.mt_smooth,
            "mt_min_patch": self.mt_min_patch,
            "pcv_rays": self.pcv_rays,
            "pcv_hemisphere": self.pcv_hemisphere,
            "pcv_method": self.pcv_method,
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
    if metric == "morphotester_dne":
        return {"mt_dne": result.dne}
    if metric == "morphotester_rfi":
        return {
            "mt_rfi": result.rfi,
            "mt_surface_area": result.surface_area,
            "mt_outline_area": result.outline_area,
        }
    if metric == "morphotester_opcr":
        return {
            "mt_opcr": result.opcr,
            **dict(zip(MORPHOTESTER_ROTATION_KEYS, result.opc, strict=True)),
        }
    values = result.to_dict()
    if metric in DOOLKIT_METRICS:
        return {key: values[DOOLKIT_NAMES.get(key, key)] for key in METRIC_KEYS[metric]}
    return values


#: Why a value can be undefined, by record key: what the row's warning (or error) says.
_UNDEFINED = {
    "arc_positive": "a mean over no faces: no face has an ARC of 0 or more",
    "arc_pos_mean": "a mean over no faces: no face has an ARC of 0 or more",
    "arc_negative": "a mean over no faces: no face has a negative ARC (nothing concave)",
    "arc_neg_mean": "a mean over no faces: no face has a negative ARC (nothing concave)",
    "rfi_guy": "no face is steeper than 45 degrees (gamma divides by their summed elevation)",
    "rrate_below_median": "the crown has no relief (all its faces at one elevation)",
}

#: Record keys of the unit-dependent metrics (doolkit's, MorphoTester's RFI): lengths, areas.
_LENGTH_POWER = {
    "mt_surface_area": 2,
    "mt_outline_area": 2,
    "area2d": 2,
    "area2d_convex": 2,
    "hypso_height": 1,
    "hypso_length": 1,
    "hypso_width": 1,
}

#: What a row says of angularity measured without the mesh's unit.
_ANGULARITY_UNIT = (
    "angularity: doolkit's angularity depends on the mesh's unit; measured as if in millimetres "
    "(give the unit: unit='mm' if it is)"
)


def _finite(metric: str, values: dict) -> tuple[dict, str | None]:
    """`values` with each value that is not a finite number emptied and named in a warning.

    Returns the values, and None; or, when the metric's first (headline)
    value is not a finite number, all of them emptied and the reason (the
    metric's error).
    """
    headline = METRIC_KEYS[metric][0] if metric in METRIC_KEYS else None
    for key, value in values.items():
        if isinstance(value, (float, np.floating)) and not math.isfinite(value):
            why = _UNDEFINED.get(key)
            if key == headline:
                what = f"{float(value)!r} on this mesh" if why is None else f"undefined: {why}"
                return dict.fromkeys(values), f"{key} is {what}"
            why = f"it is {float(value)!r} on this mesh" if why is None else why
            values[key] = None
            warnings.warn(f"{metric}: {key} is empty: {why}", UserWarning, stacklevel=3)
    return values, None


def _in_millimetres(surface, options: TopographyOptions):
    """The surface rescaled to millimetres for doolkit's unit-dependent metrics (or as it is)."""
    if options.unit is None or options.unit == 1.0 or isinstance(surface, BaseException):
        return surface
    try:
        return prepare_surface(
            (surface.vertices * options.unit, surface.faces), duplicates=options.duplicates
        )
    except OSError:
        raise
    except Exception as exc:  # each metric names it
        return exc


#: What a row says of MorphoTester's RFI measured without the mesh's unit.
_MORPHOTESTER_UNIT = (
    "morphotester_rfi: MorphoTester's outline area depends on the mesh's unit (it draws the "
    "crown with half a unit of margin, and rounds both areas to 3 decimals); measured on the "
    "crown as given, as MorphoTester measures it (give the unit to measure it in millimetres, "
    "as MorphoTester's own sample crowns are: unit='mm' if it is)"
)


def _in_mesh_units(values: dict, unit: float) -> dict:
    """Lengths and areas measured in millimetres given back in the mesh's unit."""
    for key, power in _LENGTH_POWER.items():
        if values.get(key) is not None:
            values[key] = values[key] / unit**power
    return values


def _prepared(mesh, options: TopographyOptions):
    """The surface molaR's metrics share, or the reason it could not be prepared.

    It is the surface ariaDNE measures: the mesh cleaned as ariaDNE cleans it
    (small holes beside the open base filled, degenerate faces dropped), so
    that every metric of a row measures the same triangles (with
    ``duplicates="keep"``, and faces listed again, those as listed).  What
    cleaning changed is warned about, for the row to say.
    """
    try:
        listed = clean_listed(mesh)
        if len(listed.faces) == 0:
            if listed.cleaning.zero_area_faces == listed.cleaning.degenerate_faces:
                raise ValueError("the mesh has no face of non-zero area")
            raise ValueError("cleaning left the mesh empty: every face is of no height")
        import trimesh  # only for molaR's and doolkit's metrics, not for ariaDNE alone

        listed_mesh = trimesh.Trimesh(listed.vertices, listed.faces, process=False)
        surface = prepare_surface(listed_mesh, duplicates=options.duplicates)
    except OSError:
        raise
    except Exception as exc:  # each metric names it (see _errors: ours, or an internal error)
        return exc
    for note in listed.cleaning.notes(duplicates=False):  # prepare_surface names repeats
        warnings.warn(note, UserWarning, stacklevel=3)
    return surface


def _compute(metric: str, mesh, ariadne_options: dict, options: TopographyOptions, progress):
    if metric == "ariadne":
        return ariaDNE(mesh, progress=progress, **ariadne_options)
    if isinstance(mesh, BaseException):  # every topography metric fails as it would alone
        raise mesh
    return _TOPOGRAPHY[metric](mesh, options)


def _topography():
    """:mod:`dentopo.topography`: its families are imported on their first metric (PEP 562).

    Not imported by name at the top of this module, so that a run of ariaDNE alone does
    not import them (nor trimesh and scipy, which they import).
    """
    return importlib.import_module("..topography", __package__)


#: The topography metrics this module calls by name, imported on their first use.
_LAZY_METRICS = frozenset(
    (
        "angularity",
        "arc",
        "classic_dne",
        "doolkit_arc",
        "doolkit_dne",
        "doolkit_opc",
        "doolkit_opcr",
        "doolkit_slope",
        "footprint_area",
        "hypsodonty",
        "inclination",
        "morphotester_dne",
        "morphotester_opcr",
        "morphotester_rfi",
        "pcv",
        "projected_rfi",
        "relief_index",
        "relief_rate_below_median",
        "rfi",
        "shape_index",
    )
)


def __getattr__(name: str):
    """``rfi``, ``arc``, ...: the topography metric of that name, imported on first use."""
    if name in _LAZY_METRICS:
        return getattr(_topography(), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def _metric(name: str):
    """The metric function `name`: this module's own if one was set (a test replaces
    ``_measure.rfi`` to make it fail), else :mod:`dentopo.topography`'s."""
    own = globals().get(name)
    return own if own is not None else getattr(_topography(), name)


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
    "classic": lambda surface, options: _metric("classic_dne")(
        surface,
        outliers=options.dne_outliers,
        boundary=options.dne_boundary,
        kappa=options.dne_kappa,
        orient=options.orient,
    ),
    "rfi": lambda surface, options: _metric("rfi")(
        surface, alpha=options.alpha, find_alpha=options.find_alpha, orient=options.orient
    ),
    "opcr": _opcr,
    "opc": lambda surface, options: opc(
        surface, min_faces=options.min_faces, min_area=options.min_area, orient=options.orient
    ),
    "slope": lambda surface, options: slope(surface, orient=options.orient),
    "arc": lambda surface, options: _metric("arc")(
        surface, boundary=options.arc_boundary, range=options.arc_range
    ),
    "angularity": lambda surface, options: _metric("angularity")(surface),
    "doolkit_slope": lambda surface, options: _metric("doolkit_slope")(surface),
    "relief_index": lambda surface, options: _metric("relief_index")(
        surface, orient=options.orient
    ),
    "inclination": lambda surface, options: _metric("inclination")(surface, orient=options.orient),
    "doolkit_opc": lambda surface, options: _metric("doolkit_opc")(surface, orient=options.orient),
    "doolkit_opcr": lambda surface, options: _metric("doolkit_opcr")(
        surface, orient=options.orient
    ),
    "doolkit_arc": lambda surface, options: _metric("doolkit_arc")(surface),
    "doolkit_dne": lambda surface, options: _metric("doolkit_dne")(surface),
    "relief_rate": lambda surface, options: _metric("relief_rate_below_median")(
        surface, orient=options.orient
    ),
    "shape_index": lambda surface, options: _metric("shape_index")(surface),
    # doolkit's area2d (concave) and its convex counterpart
    "footprint": lambda surface, options: (
        _metric("footprint_area")(surface, hull="concave", orient=options.orient),
        _metric("footprint_area")(surface, hull="convex", orient=options.orient),
    ),
    "hypsodonty": lambda surface, options: _metric("hypsodonty")(surface),
    # MorphoTester's, on the mesh as MorphoTester reads it (see _as_read)
    "morphotester_dne": lambda mesh, options: _metric("morphotester_dne")(
        mesh,
        condition_check=options.mt_condition_check,
        outliers=None if options.mt_outliers == "off" else options.mt_outliers,
        percentile=options.mt_percentile,
        smooth=options.mt_smooth,
    ),
    "morphotester_rfi": lambda mesh, options: _metric("morphotester_rfi")(mesh),
    "rfi_projected": lambda surface, options: _metric("projected_rfi")(
        surface, orient=options.orient
    ),
    "pcv": lambda surface, options: _metric("pcv")(
        surface,
        rays=options.pcv_rays,
        hemisphere=options.pcv_hemisphere,
        method=options.pcv_method,
        orient=options.orient,
    ),
    "morphotester_opcr": lambda mesh, options: _metric("morphotester_opcr")(
        mesh, min_patch=options.mt_min_patch
    ),
}


def _as_read(mesh, raw):
    """The mesh MorphoTester's metrics measure: as MorphoTester reads it, nothing cleaned.

    `raw` is the file read as MorphoTester reads a PLY (:func:`dentopo.mesh.read_ply`
    with ``exact_text=True``: ASCII coordinates as float64 from their text, no vertex
    merged, no face dropped); without it (a mesh given in memory, a prepared mesh, a
    format MorphoTester does not read) the mesh's own vertices and faces, as given.
    """
    if raw is not None:
        return raw
    if isinstance(mesh, BaseException):
        return mesh
    try:
        return as_arrays(mesh)
    except Exception as exc:  # each metric names it
        return exc


def _scaled(mesh, unit: float):
    """`mesh` (vertices, faces) with its vertices in millimetres (or the exception it is)."""
    if isinstance(mesh, BaseException) or unit == 1.0:
        return mesh
    return (mesh[0] * unit, mesh[1])


def read_as_morphotester(path) -> tuple[np.ndarray, np.ndarray] | None:
    """A PLY file read as MorphoTester reads it; None for another format."""
    if os.fspath(path).lower().endswith(".ply"):
        return read_ply(path, exact_text=True)
    return None


def _doolkit_base(surface) -> dict:
    """doolkit's first columns: the counts and 3D area of the mesh its metrics measured."""
    if isinstance(surface, BaseException):
        return dict.fromkeys(DOOLKIT_BASE_KEYS)
    area = float(surface.single_precision_areas().sum())
    if not math.isfinite(area):
        warnings.warn(f"area3d is empty: the computation gave {area!r}", UserWarning, stacklevel=3)
    return {
        "n_vertices": len(surface.vertices),
        "n_faces": len(surface.faces),
        "area3d": area if math.isfinite(area) else None,
    }


def measure_mesh(
    mesh,
    metrics: str | Iterable[str] = ("ariadne",),
    *,
    ariadne_options: dict | None = None,
    options: TopographyOptions | None = None,
    reason: Callable[[BaseException], str] = str,
    progress: Callable[[str], None] | None = None,
    raw: tuple[np.ndarray, np.ndarray] | None = None,
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
    raw : (vertices, faces), optional
        The file as MorphoTester reads it, for MorphoTester's metrics
        (:func:`read_as_morphotester`); read here when `mesh` is a PLY file's
        path.  Without it they measure `mesh` as given, nothing cleaned.
    """
    metrics = check_metrics(metrics)
    options = TopographyOptions() if options is None else options
    ariadne_options = {} if ariadne_options is None else ariadne_options
    morphotester = [metric for metric in metrics if metric in MORPHOTESTER_METRICS]
    if morphotester and raw is None and isinstance(mesh, (str, os.PathLike)):
        raw = read_as_morphotester(mesh)
    others = [metric for metric in metrics if metric not in MORPHOTESTER_METRICS]
    # read once for all the metrics; ariaDNE alone reads it itself, and MorphoTester's alone
    # need only the file as MorphoTester reads it
    if isinstance(mesh, (str, os.PathLike)) and metrics != ("ariadne",) and (others or raw is None):
        mesh = load_mesh(mesh)
    surface = _prepared(mesh, options) if others and others != ["ariadne"] else None
    as_read = _as_read(mesh, raw) if morphotester else None
    millimetres = surface
    if set(UNIT_DEPENDENT).intersection(metrics):
        millimetres = _in_millimetres(surface, options)
    record: dict = {}
    results: dict = {}
    errors: dict = {}
    for metric in metrics:
        if metric in DOOLKIT_METRICS and "n_vertices" not in record:
            record.update(_doolkit_base(surface))
        if metric in MORPHOTESTER_METRICS and "mt_n_faces" not in record:
            record["mt_n_faces"] = None if isinstance(as_read, BaseException) else len(as_read[1])
        keys = METRIC_KEYS[metric]
        if metric != "ariadne" and progress is not None:
            progress(metric)
        given = mesh if metric == "ariadne" else surface
        if metric in UNIT_DEPENDENT:
            given = millimetres
        elif metric in MORPHOTESTER_METRICS:
            given = as_read
            if metric == "morphotester_rfi" and options.unit is not None:
                given = _scaled(as_read, options.unit)
        try:
            result = _compute(metric, given, ariadne_options, options, progress)
        except OSError:
            raise  # reading the file (ariaDNE alone reads it): the row's error
        except Exception as exc:  # this metric, on this mesh; not ours: an internal error
            errors[metric] = failure_reason(metric, exc, reason)
            record.update(dict.fromkeys(keys))
            if metric == "opcr":
                record.update(dict.fromkeys(rotation_key(d) for d in options.rotations()))
            if metric == "morphotester_opcr":
                record.update(dict.fromkeys(MORPHOTESTER_ROTATION_KEYS))
            if metric == "ariadne":  # its settings columns are still the settings
                record.update(ariadne_options)
            continue
        values, undefined = _finite(metric, _values(metric, result))
        if undefined is not None:  # the headline value is not a number: the metric failed
            errors[metric] = undefined
            record.update(values)
            continue
        if metric in UNIT_DEPENDENT and options.unit is not None:
            values = _in_mesh_units(values, options.unit)
        elif metric == "morphotester_rfi":
            if options.unit is not None:
                values = _in_mesh_units(values, options.unit)
            else:
                warnings.warn(_MORPHOTESTER_UNIT, UnitWarning, stacklevel=2)
        elif metric == "angularity":
            warnings.warn(_ANGULARITY_UNIT, UnitWarning, stacklevel=2)
        results[metric] = result
        record.update(values)
        if metric in ORIENTED and "orientation" not in record:
            record["orientation"] = str(result.orientation)
    if ORIENTED.intersection(metrics):
        record.setdefault("orientation", None)
    if surface is None and "ariadne" in results:  # ariaDNE alone: what its cleaning changed
        cleaning = unbuilt(results["ariadne"]).metadata.get("cleaning")  # not building it
        for note in cleaning.notes() if cleaning is not None else ():
            warnings.warn(note, UserWarning, stacklevel=2)
    record.update(options.settings(metrics))
    return Measurement(record, results, errors, metrics)
