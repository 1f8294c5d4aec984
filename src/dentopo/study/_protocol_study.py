"""The protocol study: how much each preparation parameter moves each metric.

Spradley et al. (2017, "Smooth operator") asked how much simplification and
smoothing move DNE, RFI and OPCR.  `protocol_study` answers that on the user's
own crowns, for every metric the batch computes:

1. A **base** mesh: the crown as given (cleaned as ariaDNE cleans it), or, with
   ``base_faces=N``, the crown decimated to N faces.
2. **Axes**, each varying one parameter of the protocol away from the base:

   * ``faces``: the crown re-meshed to each face count.  Below the crown's own
     count it is decimated by the protocol's decimate step
     (``dentopo.prepare(mesh, Protocol(orient="none", clean=False, faces=N))``,
     quadric edge collapse by fast-simplification); above it, refined by
     longest-edge bisection (`dentopo.study.refine`: the same surface, more
     triangles); at its own count it is the crown itself.  Always made from
     the crown as given, not from the base.
   * ``smoothing``: the base smoothed by the protocol's smooth step with
     ``K`` iterations (``Protocol(orient="none", clean=False, smooth=method,
     smooth_iterations=K)``); ``K = 0`` is the base itself.
   * ``noise``: Gaussian noise of standard deviation ``sd * sqrt(area)`` added
     to every coordinate of the base, drawn in order from one
     ``numpy.random.default_rng(seed)`` (as `dentopo.study.perturb` draws
     it); ``sd = 0`` is the base itself.

3. Every metric asked for, measured on each mesh by the batch's own measuring
   of one mesh (:func:`dentopo.batch._measure.measure_mesh`, the same code as
   a row of ``dentopo``'s table, with its options), and each metric's headline
   quantities (`QUANTITIES`) compared with the base: ``relative_change =
   value / base - 1``.  A metric that fails on a mesh (RFI's alpha search on a
   rough surface, say) leaves its cells empty and names its reason in
   ``error``; so does a perturbation that could not be made.

`write_protocol_study` writes ``sensitivity.csv`` (every row),
``sensitivity_summary.csv`` (per axis level and quantity: the median, minimum
and maximum relative change across crowns) and one figure per metric,
``sensitivity_METRIC.png``, each file atomically.
"""

from __future__ import annotations

import math
import os
import warnings
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from numbers import Real
from pathlib import Path

import numpy as np
import trimesh

from .._html_repr import rows_html
from .._optional import STUDY_FIGURES
from ..ariadne import check_bandwidth
from ..batch._measure import TopographyOptions, measure_mesh
from ..mesh import as_arrays, clean
from ..prepare import SMOOTHERS, Protocol
from ..prepare import prepare as run_protocol
from ..topography import check_metrics
from ._robustness import _atomic_write_bytes, _csv_bytes, _figure_bytes, refine

#: The axes, in table order.
AXES = ("faces", "smoothing", "noise")
#: Default levels of each axis.
DEFAULT_FACES = (2000, 5000, 10000, 20000, 40000)
DEFAULT_SMOOTHING = (0, 3, 10, 30, 100)
DEFAULT_NOISE = (0.0, 1e-3, 2e-3)
#: The smoothing methods (the protocol's).
SMOOTH_METHODS = tuple(SMOOTHERS)

#: Each metric's quantities compared with the base (its headline values; record keys).
QUANTITIES = {
    "ariadne": ("dne", "positive_dne", "negative_dne"),
    "classic": ("classic_dne", "classic_convex_dne", "classic_concave_dne"),
    "rfi": ("rfi",),
    "opcr": ("opcr",),
    "opc": ("opc",),
    "slope": ("slope",),
    "arc": ("arc",),
    "doolkit_slope": ("slope_mean",),
    "angularity": ("angularity_mean",),
    "relief_index": ("rfi_ungar", "rfi_boyer", "rfi_guy"),
    "inclination": ("inclin_mean",),
    "doolkit_opc": ("dk_opc",),
    "doolkit_opcr": ("dk_opcr",),
    "doolkit_arc": ("arc_mean",),
    "doolkit_dne": ("dne_total_unrounded",),
    "relief_rate": ("rrate_below_median",),
    "shape_index": ("shape_formfactor", "shape_elongation"),
    "footprint": ("area2d",),
    "hypsodonty": ("hypso_hypsodonty",),
    "morphotester_dne": ("mt_dne",),
    "morphotester_rfi": ("mt_rfi",),
    "morphotester_opcr": ("mt_opcr",),
    "rfi_projected": ("rfi_projected", "rfi_projected_ungar"),
    "pcv": ("pcv",),
}

PROTOCOL_STUDY_COLUMNS = (
    "crown",
    "axis",
    "level",
    "vertices",
    "faces",
    "metric",
    "quantity",
    "value",
    "base_value",
    "relative_change",
    "error",
)
SUMMARY_COLUMNS = (
    "axis",
    "level",
    "metric",
    "quantity",
    "crowns",
    "missing",
    "median_relative_change",
    "min_relative_change",
    "max_relative_change",
)
#: The tables `write_protocol_study` writes, before the figures.
PROTOCOL_STUDY_TABLES = ("sensitivity.csv", "sensitivity_summary.csv")


def protocol_study_files(metrics: Iterable[str], *, figures: bool = True) -> tuple[str, ...]:
    """The names `write_protocol_study` writes for these metrics: the tables, then the figures."""
    names = PROTOCOL_STUDY_TABLES
    if figures:
        names += tuple(f"sensitivity_{metric}.png" for metric in check_metrics(metrics))
    return names


# ---------------------------------------------------------------------------
# checks


def _levels(name: str, values, check) -> tuple:
    if values is None:
        return ()
    if isinstance(values, (str, bytes)) or not isinstance(values, Iterable):
        raise TypeError(f"{name} must be a sequence of levels; got {values!r}")
    out = []
    for value in values:
        value = check(name, value)
        if value not in out:
            out.append(value)
    return tuple(sorted(out))


def _face_count(name: str, value) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name} must hold integers; got {value!r}")
    if value < 4:
        raise ValueError(f"{name} must be at least 4 faces; got {value}")
    return int(value)


def _iterations(name: str, value) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name} must hold integers; got {value!r}")
    if value < 0:
        raise ValueError(f"{name} must be 0 or more iterations; got {value}")
    return int(value)


def _noise(name: str, value) -> float:
    if isinstance(value, bool) or not isinstance(value, Real):
        raise TypeError(f"{name} must hold real numbers; got {value!r}")
    if not (math.isfinite(value) and value >= 0):
        raise ValueError(f"{name} must be 0 or more and finite; got {value!r}")
    return float(value)


def _crowns(meshes) -> dict:
    """``{name: mesh}`` from one mesh or a mapping of names to meshes."""
    if isinstance(meshes, Mapping):
        if not meshes:
            raise ValueError("no crowns: the mapping of crowns is empty")
        return {str(name): mesh for name, mesh in meshes.items()}
    if isinstance(meshes, (str, os.PathLike)):
        return {Path(meshes).stem: meshes}
    return {"crown": meshes}


# ---------------------------------------------------------------------------
# the meshes of the axes


def _arrays(mesh) -> tuple[np.ndarray, np.ndarray]:
    return np.asarray(mesh.vertices, dtype=np.float64), np.asarray(mesh.faces, dtype=np.int64)


def _with_faces(vertices, faces, target: int) -> tuple[np.ndarray, np.ndarray]:
    if target < len(faces):
        prepared = run_protocol(
            (vertices, faces), Protocol(orient="none", clean=False, faces=target)
        )
        return np.array(prepared.vertices), np.array(prepared.faces)
    if target > len(faces):
        return refine(vertices, faces, target)
    return vertices.copy(), faces.copy()


def _smoothed(vertices, faces, method: str, iterations: int, step, mu):
    if iterations == 0:
        return vertices.copy(), faces.copy()
    protocol = Protocol(
        orient="none",
        clean=False,
        smooth=method,
        smooth_iterations=iterations,
        smooth_step=step,
        smooth_mu=mu,
    )
    prepared = run_protocol((vertices, faces), protocol)
    return np.array(prepared.vertices), np.array(prepared.faces)


def _levels_meshes(crown, faces, smoothing, noise, base_faces, method, step, mu, seed):
    """The base and ``{(axis, level): (vertices, faces) or exception}`` of one crown."""
    original = clean(*as_arrays(crown))
    v0, f0 = _arrays(original)
    if base_faces is None:
        base = (v0, f0)
    else:
        base = _with_faces(v0, f0, base_faces)
    made: dict = {}
    for level in faces:
        try:
            made["faces", level] = _with_faces(v0, f0, level)
        except Exception as exc:  # this level, named in its rows
            made["faces", level] = exc
    for level in smoothing:
        try:
            made["smoothing", level] = _smoothed(*base, method, level, step, mu)
        except NotImplementedError:
            raise  # the method itself is missing: every level would fail
        except Exception as exc:
            made["smoothing", level] = exc
    rng = np.random.default_rng(seed)
    v, f = base
    unit = float(np.sqrt(trimesh.Trimesh(v, f, process=False).area))
    for level in noise:
        if level == 0:
            made["noise", level] = (v.copy(), f.copy())
        else:
            made["noise", level] = (v + rng.normal(0.0, level * unit, size=v.shape), f.copy())
    return base, made


# ---------------------------------------------------------------------------
# the study


@dataclass(frozen=True)
class ProtocolStudy:
    """The outcome of `protocol_study`.

    Attributes
    ----------
    rows : list of dict
        One row per (crown, axis level, metric quantity) with the columns
        ``PROTOCOL_STUDY_COLUMNS``; the base's rows have axis ``"base"``.
        ``value`` and ``relative_change`` are None where the metric failed or
        gave no finite number (``error`` says why; ``base_value`` is None where
        it failed on the base); ``relative_change`` is NaN where the base value
        is 0 and the value is not.
    crowns : tuple of str
        The crowns' names, in the order given.
    axes : dict of str to tuple
        Each axis's levels (an axis not studied is absent).
    metrics : tuple of str
    base : str
        What the base is (``"as given"`` or ``"N faces"``).
    meshes : dict
        ``(crown, axis, level)`` to the trimesh measured (``(crown, "base", "")``: the base).
    warnings : tuple of str
        The distinct warnings the metrics gave (an undetermined orientation, say).
    """

    rows: list
    crowns: tuple
    axes: dict
    metrics: tuple
    base: str = "as given"
    meshes: dict = field(default_factory=dict, repr=False)
    warnings: tuple = ()

    def row(self, crown: str, axis: str, level, quantity: str) -> dict:
        """The row of one crown, axis level and quantity (level ``""`` for the base)."""
        for row in self.rows:
            if (
                row["crown"] == crown
                and row["axis"] == axis
                and row["level"] == level
                and row["quantity"] == quantity
            ):
                return row
        raise KeyError((crown, axis, level, quantity))

    def summary(self) -> list[dict]:
        """Per axis level and quantity: median, minimum and maximum relative change over crowns.

        Rows with the columns ``SUMMARY_COLUMNS``; ``crowns`` counts the crowns
        with a finite relative change, ``missing`` the others.
        """
        groups: dict = {}
        for row in self.rows:
            if row["axis"] == "base":
                continue
            key = (row["axis"], row["level"], row["metric"], row["quantity"])
            groups.setdefault(key, []).append(row["relative_change"])
        out = []
        for (axis, level, metric, quantity), changes in groups.items():
            finite = [c for c in changes if c is not None and math.isfinite(c)]
            out.append(
                {
                    "axis": axis,
                    "level": level,
                    "metric": metric,
                    "quantity": quantity,
                    "crowns": len(finite),
                    "missing": len(changes) - len(finite),
                    "median_relative_change": float(np.median(finite)) if finite else None,
                    "min_relative_change": min(finite) if finite else None,
                    "max_relative_change": max(finite) if finite else None,
                }
            )
        return out

    def _repr_html_(self) -> str:
        """Its summary as a compact table for notebooks."""
        summary = {"crowns": len(self.crowns), "metrics": len(self.metrics), "base": self.base}
        return rows_html(self.summary(), title=type(self).__name__, summary=summary)


def _measured(vertices, faces, metrics, ariadne_options, options, seen):
    mesh = trimesh.Trimesh(vertices, faces, process=False)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        measurement = measure_mesh(mesh, metrics, ariadne_options=ariadne_options, options=options)
    for warning in caught:
        seen.setdefault(str(warning.message), None)
    return mesh, measurement


def _relative(value, base) -> float | None:
    if value is None or base is None:
        return None
    if base == 0:
        return 0.0 if value == 0 else float("nan")
    return float(value / base - 1.0)


def protocol_study(
    meshes,
    *,
    faces: Sequence[int] | None = DEFAULT_FACES,
    smoothing: Sequence[int] | None = DEFAULT_SMOOTHING,
    noise: Sequence[float] | None = DEFAULT_NOISE,
    method: str = "taubin",
    step: float | None = None,
    mu: float | None = None,
    base_faces: int | None = None,
    metrics: str | Iterable[str] = "all",
    bandwidth: float = 0.08,
    options: TopographyOptions | None = None,
    seed: int = 0,
) -> ProtocolStudy:
    """Every metric on crowns re-meshed, smoothed and roughened, against a base protocol.

    Parameters
    ----------
    meshes : mesh, or mapping of str to mesh
        One crown (a trimesh.Trimesh, a path, or (vertices, faces)) or
        several by name.  Never modified.
    faces : sequence of int, optional
        Face counts (default 2k, 5k, 10k, 20k, 40k); None or () skips the axis.
    smoothing : sequence of int, optional
        Smoothing iterations (default 0, 3, 10, 30, 100); 0 is the base itself.
    noise : sequence of float, optional
        Noise standard deviations on the unit-area scale (default 0, 1e-3,
        2e-3: the robustness study's levels, and 0, the base, to start the line).
    method : str, default "taubin"
        The smooth step's method (``laplacian``, ``taubin``, ``hc``,
        ``implicit``), with its protocol defaults unless `step` and `mu` are given.
    step, mu : float, optional
        The smooth step's ``smooth_step`` and ``smooth_mu``.
    base_faces : int, optional
        Decimate (or refine) the crown to this many faces for the base; default:
        the crown as given.
    metrics : str or iterable of str, default "all"
        Names of :data:`dentopo.topography.METRICS`, or ``"all"``.
    bandwidth : float, default 0.08
        ariaDNE's bandwidth.
    options : TopographyOptions, optional
        The other metrics' options (the batch's defaults).
    seed : int, default 0
        Seed of the noise.

    Returns
    -------
    ProtocolStudy

    Examples
    --------
    >>> from dentopo.samples import tooth
    >>> from dentopo.study import protocol_study
    >>> study = protocol_study(tooth(rings=10), faces=(300, 1200), smoothing=(0, 10),
    ...                        noise=(), metrics=["ariadne", "rfi"])  # doctest: +SKIP
    >>> study.row("crown", "smoothing", 0, "dne")["relative_change"]  # doctest: +SKIP
    0.0
    """
    crowns = _crowns(meshes)
    faces = _levels("faces", faces, _face_count)
    smoothing = _levels("smoothing", smoothing, _iterations)
    noise = _levels("noise", noise, _noise)
    if not (faces or smoothing or noise):
        raise ValueError("no axis to study: give faces, smoothing or noise levels")
    if method not in SMOOTH_METHODS:
        raise ValueError(f"method must be one of {', '.join(SMOOTH_METHODS)}; got {method!r}")
    if smoothing:  # the protocol checks step and mu (and that mu fits the method) now
        Protocol(orient="none", smooth=method, smooth_step=step, smooth_mu=mu)
    if base_faces is not None:
        base_faces = _face_count("base_faces", base_faces)
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)):
        raise TypeError(f"seed must be an integer; got {type(seed).__name__}")
    metrics = check_metrics(metrics)
    ariadne_options = {"bandwidth": check_bandwidth(bandwidth)}
    options = TopographyOptions() if options is None else options
    axes = {
        axis: levels for axis, levels in zip(AXES, (faces, smoothing, noise), strict=True) if levels
    }

    rows: list = []
    kept: dict = {}
    seen: dict = {}
    for name, crown in crowns.items():
        (bv, bf), made = _levels_meshes(
            crown, faces, smoothing, noise, base_faces, method, step, mu, seed
        )
        base_mesh, base = _measured(bv, bf, metrics, ariadne_options, options, seen)
        kept[name, "base", ""] = base_mesh
        levels = [("base", "", (bv, bf))] + [(a, lv, made[a, lv]) for a in axes for lv in axes[a]]
        for axis, level, item in levels:
            if isinstance(item, BaseException):
                mesh, measurement = None, None
                problem = f"{axis}={level}: {item}"
            elif axis != "base" and np.array_equal(item[0], bv) and np.array_equal(item[1], bf):
                mesh, measurement, problem = base_mesh, base, None  # the base itself
            else:
                mesh, measurement = _measured(*item, metrics, ariadne_options, options, seen)
                problem = None
            if mesh is not None:
                kept[name, axis, level] = mesh
            for metric in metrics:
                for quantity in QUANTITIES[metric]:
                    base_value = base.record.get(quantity)
                    if measurement is None:
                        value, error = None, problem
                    else:
                        value = measurement.record.get(quantity)
                        error = measurement.errors.get(metric)
                    if error is None and base_value is None:
                        error = f"base: {base.errors.get(metric, 'no value')}"
                    if error is None and value is not None and not math.isfinite(value):
                        error = f"{quantity} is {value} on this mesh"
                        value = None
                    if error is None and base_value is not None and not math.isfinite(base_value):
                        error = f"base: {quantity} is {base_value} on the base mesh"
                        value = None
                    rows.append(
                        {
                            "crown": name,
                            "axis": axis,
                            "level": level,
                            "vertices": None if mesh is None else len(mesh.vertices),
                            "faces": None if mesh is None else len(mesh.faces),
                            "metric": metric,
                            "quantity": quantity,
                            "value": None if value is None else float(value),
                            "base_value": None if base_value is None else float(base_value),
                            "relative_change": _relative(value, base_value),
                            "error": error,
                        }
                    )
    return ProtocolStudy(
        rows=rows,
        crowns=tuple(crowns),
        axes=axes,
        metrics=metrics,
        base="as given" if base_faces is None else f"{base_faces} faces",
        meshes=kept,
        warnings=tuple(seen),
    )


# ---------------------------------------------------------------------------
# files


def write_protocol_study(
    study: ProtocolStudy, directory: str | os.PathLike, *, figures: bool = True
) -> list[Path]:
    """Write ``sensitivity.csv``, ``sensitivity_summary.csv``, then one figure per metric.

    Parameters
    ----------
    study : ProtocolStudy
    directory : path-like
        Created if missing.  Each file is written atomically.
    figures : bool, default True
        Also draw ``sensitivity_METRIC.png`` (matplotlib, the ``study`` extra):
        one panel per axis, the relative change (%) of each quantity against
        the axis level; with several crowns the median line and the range.

    Returns
    -------
    list of Path
        The files written.

    Raises
    ------
    dentopo._optional.MissingExtraError
        An ``ImportError``: `figures` without matplotlib, before anything is written.
    """
    if figures:
        STUDY_FIGURES.require()
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    names = protocol_study_files(study.metrics, figures=figures)
    summary = study.summary()
    written = []
    for name, rows, columns in (
        (names[0], study.rows, PROTOCOL_STUDY_COLUMNS),
        (names[1], summary, SUMMARY_COLUMNS),
    ):
        _atomic_write_bytes(directory / name, _csv_bytes(rows, columns))
        written.append(directory / name)
    if figures:
        from ._figures import sensitivity_figure

        for metric, name in zip(study.metrics, names[2:], strict=True):
            figure = sensitivity_figure(
                study.rows,
                metric,
                QUANTITIES[metric],
                study.axes,
                crowns=len(study.crowns),
                base=study.base,
            )
            _atomic_write_bytes(directory / name, _figure_bytes(figure))
            written.append(directory / name)
    return written
