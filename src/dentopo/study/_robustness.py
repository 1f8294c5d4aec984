"""The robustness study: one surface meshed differently, every sign method compared.

The paper's central claim (Section 4, Figures 2, 4 and 5) is that its sign
stays put when the same surface is re-meshed, roughened or smoothed, where the
convex/concave split of classic DNE (as molaR computes it) does not.  This
module makes that study runnable on any specimen:

1. `perturb` builds, with a fixed seed, the paper's perturbations of one mesh:

   * ``low``: about 2,000 triangles, by quadric edge-collapse decimation
     (fast-simplification, Garland-Heckbert quadrics, ``agg=7``);
   * ``high``: about 20,000 triangles, by longest-edge bisection (each split
     puts a vertex at an edge's midpoint and splits both faces that share it,
     so the surface is exactly the same piecewise-linear surface and the mesh
     stays conforming); a target below the face count decimates instead;
   * ``noise1``, ``noise2``: independent Gaussian noise with standard deviation
     1e-3 and 2e-3 on the unit-area scale (``sd * sqrt(area)`` in mesh units)
     added to every coordinate, both drawn from one ``numpy.random.default_rng(seed)``;
   * ``smooth``: Taubin smoothing (trimesh ``filter_taubin``, umbrella
     Laplacian, ``lamb=0.5``, ``nu=0.53``, 10 iterations), which smooths
     without the shrinkage of plain Laplacian smoothing.

2. `robustness_study` computes ariaDNE with every sign method, and classic DNE,
   on the original and on each perturbation, and tabulates:

   * totals (DNE, positive, negative; for classic DNE convex and concave)
     normalised by the same method's totals on the original mesh;
   * sign agreement: the fraction of the perturbed surface's area whose sign
     agrees with the original's at the nearest point.  Both meshes are put in
     a common frame first (area-weighted centroid at the origin, area-weighted
     RMS radius 1: unlike unit area, this is not inflated by noise).  For
     ariaDNE each perturbed vertex, weighted by its vertex area, takes the
     sign of the nearest original vertex; for classic DNE, whose sign lives on
     faces, each perturbed face, weighted by its area, takes the class of the
     original face with the nearest centroid.

3. `bandwidth_sweep` computes the totals for a list of bandwidths (the paper's
   Figure 6: our sign, Gaussian, mean).

`write_study` and `write_sweep` write the CSV tables first and the PNG figures
second, each file atomically.
"""

from __future__ import annotations

import csv
import io
import os
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from numbers import Real
from pathlib import Path

import numpy as np
import trimesh

from .._html_repr import rows_html
from .._optional import STUDY_FIGURES
from ..ariadne import AriaDNEResult, ariaDNE, check_bandwidth
from ..formats import atomic_write
from ..mesh import as_arrays, clean, vertex_areas
from ..sign import SIGN_METHODS
from ..topography import ClassicDNEResult, classic_dne

#: The unperturbed mesh's name in tables.
BASE = "normal"
#: Perturbation names, in the paper's order.
PERTURBATIONS = ("low", "high", "noise1", "noise2", "smooth")
#: Rows of the study: every ariaDNE sign method, then classic DNE.
METHODS = (*SIGN_METHODS, "classic")
#: The paper's Figure 6 rows.
SWEEP_METHODS = ("centroid", "gaussian_curvature", "mean_curvature")

#: Taubin smoothing parameters (Taubin 1995: pass-band about 0.1).
TAUBIN = {"lamb": 0.5, "nu": 0.53, "iterations": 10}

STUDY_COLUMNS = (
    "perturbation",
    "method",
    "vertices",
    "faces",
    "dne",
    "positive",
    "negative",
    "dne_normalised",
    "positive_normalised",
    "negative_normalised",
    "sign_agreement",
)
SWEEP_COLUMNS = (
    "bandwidth",
    "method",
    "dne",
    "positive",
    "negative",
    "positive_fraction",
)


# ---------------------------------------------------------------------------
# perturbations


def _check_count(name: str, value) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name} must be an integer; got {type(value).__name__}")
    if value < 4:
        raise ValueError(f"{name} must be at least 4; got {value}")
    return int(value)


def _check_positive(name: str, value) -> float:
    if isinstance(value, bool) or not isinstance(value, Real):
        raise TypeError(f"{name} must be a real number; got {type(value).__name__}")
    if not (np.isfinite(value) and value > 0):
        raise ValueError(f"{name} must be positive and finite; got {value!r}")
    return float(value)


def decimate(vertices: np.ndarray, faces: np.ndarray, target_faces: int) -> tuple:
    """Quadric edge-collapse decimation to about `target_faces` (fast-simplification).

    fast-simplification is a dependency of dentopo (the prepare step's
    decimation too); it is imported here, when a mesh is decimated.
    """
    import fast_simplification

    v, f = fast_simplification.simplify(
        np.ascontiguousarray(vertices, dtype=np.float64),
        np.ascontiguousarray(faces, dtype=np.int64),
        target_count=int(target_faces),
    )
    mesh = trimesh.Trimesh(v, f, process=False)
    mesh.remove_unreferenced_vertices()
    return np.asarray(mesh.vertices), np.asarray(mesh.faces)


def refine(vertices: np.ndarray, faces: np.ndarray, target_faces: int) -> tuple:
    """Longest-edge bisection until the mesh has `target_faces` faces (or one more).

    Each pass splits the longest edges first, at their midpoints, choosing
    edges that share no face, and splits every face on a chosen edge in two
    (orientation kept).  The surface is unchanged; the mesh stays conforming.
    Edges of non-manifold fans (more than two faces) are never split.
    """
    vertices = np.asarray(vertices, dtype=np.float64)
    faces = np.asarray(faces, dtype=np.int64)
    while len(faces) < target_faces:
        n, m = len(vertices), len(faces)
        directed = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
        undirected = np.sort(directed, axis=1)
        keys, inverse = np.unique(undirected[:, 0] * n + undirected[:, 1], return_inverse=True)
        edge_ends = np.column_stack([keys // n, keys % n])
        length = np.linalg.norm(vertices[edge_ends[:, 0]] - vertices[edge_ends[:, 1]], axis=1)
        owner = np.tile(np.arange(m), 3)
        by_edge = np.argsort(inverse, kind="stable")
        starts = np.searchsorted(inverse[by_edge], np.arange(len(keys)))
        counts = np.bincount(inverse, minlength=len(keys))
        needed = target_faces - m
        taken = np.zeros(m, dtype=bool)
        chosen = []
        for e in np.argsort(-length, kind="stable"):
            if needed <= 0:
                break
            if counts[e] > 2:
                continue
            around = owner[by_edge[starts[e] : starts[e] + counts[e]]]
            if taken[around].any():
                continue
            taken[around] = True
            chosen.append(e)
            needed -= len(around)
        if not chosen:
            break
        chosen = np.asarray(chosen)
        midpoint = np.full(len(keys), -1, dtype=np.int64)
        midpoint[chosen] = n + np.arange(len(chosen))
        new_vertices = vertices[edge_ends[chosen]].mean(axis=1)
        # which local edge (k: faces[:, k] -> faces[:, k + 1]) of each face is split
        split_at = midpoint[inverse].reshape(3, m).T
        has = (split_at >= 0).any(axis=1)
        k = np.argmax(split_at >= 0, axis=1)[has]
        rows = np.flatnonzero(has)
        a = faces[rows, k]
        b = faces[rows, (k + 1) % 3]
        c = faces[rows, (k + 2) % 3]
        mid = split_at[rows, k]
        faces = np.vstack([faces[~has], np.column_stack([a, mid, c]), np.column_stack([mid, b, c])])
        vertices = np.vstack([vertices, new_vertices])
    return vertices, faces


def retessellate(vertices: np.ndarray, faces: np.ndarray, target_faces: int) -> tuple:
    """About `target_faces` faces: `decimate` when fewer, `refine` when more."""
    if target_faces < len(faces):
        return decimate(vertices, faces, target_faces)
    if target_faces > len(faces):
        return refine(vertices, faces, target_faces)
    return np.array(vertices, dtype=np.float64), np.array(faces, dtype=np.int64)


def perturb(
    mesh,
    *,
    seed: int = 0,
    low_faces: int = 2000,
    high_faces: int = 20000,
    noise: Sequence[float] = (1e-3, 2e-3),
    smooth_iterations: int = TAUBIN["iterations"],
) -> dict[str, trimesh.Trimesh]:
    """The paper's perturbations of one mesh (see the module docstring).

    Parameters
    ----------
    mesh : trimesh.Trimesh, str, path-like, or (vertices, faces)
        The original surface; cleaned as ``ariaDNE`` cleans it first.  Never modified.
    seed : int, default 0
        Seed of the noise.
    low_faces, high_faces : int, default 2000 and 20000
        Face counts of ``low`` and ``high``.
    noise : sequence of float, default (1e-3, 2e-3)
        Noise standard deviations on the unit-area scale; named ``noise1``, ``noise2``, ...
    smooth_iterations : int, default 10
        Taubin iterations of ``smooth`` (``lamb=0.5``, ``nu=0.53``).

    Returns
    -------
    dict of str to trimesh.Trimesh
        ``"normal"`` (the cleaned original), then ``"low"``, ``"high"``,
        ``"noise1"``, ..., ``"smooth"``, in mesh units.
    """
    low_faces = _check_count("low_faces", low_faces)
    high_faces = _check_count("high_faces", high_faces)
    smooth_iterations = _check_count("smooth_iterations", smooth_iterations + 4) - 4
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)):
        raise TypeError(f"seed must be an integer; got {type(seed).__name__}")
    noise = [_check_positive("noise", sd) for sd in noise]

    base = clean(*as_arrays(mesh))
    v, f = np.asarray(base.vertices), np.asarray(base.faces)
    out = {BASE: base}
    out["low"] = trimesh.Trimesh(*retessellate(v, f, low_faces), process=False)
    out["high"] = trimesh.Trimesh(*retessellate(v, f, high_faces), process=False)
    rng = np.random.default_rng(seed)
    unit = float(np.sqrt(base.area))
    for i, sd in enumerate(noise, start=1):
        noisy = v + rng.normal(0.0, sd * unit, size=v.shape)
        out[f"noise{i}"] = trimesh.Trimesh(noisy, f.copy(), process=False)
    smooth = trimesh.Trimesh(v.copy(), f.copy(), process=False)
    trimesh.smoothing.filter_taubin(
        smooth, lamb=TAUBIN["lamb"], nu=TAUBIN["nu"], iterations=smooth_iterations
    )
    out["smooth"] = smooth
    return out


# ---------------------------------------------------------------------------
# comparison


def _frame(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, float]:
    """Area-weighted centroid and RMS radius of a surface (tessellation-independent)."""
    tri = vertices[faces]
    area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
    weight = np.repeat(area / (3.0 * area.sum()), 3)
    corners = tri.reshape(-1, 3)
    centre = weight @ corners
    radius = float(np.sqrt(weight @ np.sum((corners - centre) ** 2, axis=1)))
    return centre, radius


def _located_signs(result) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(positions in the common frame, sign >= 0, area weight) per vertex or per face."""
    v = np.asarray(result.mesh.vertices, dtype=np.float64)
    f = np.asarray(result.mesh.faces, dtype=np.int64)
    if isinstance(result, ClassicDNEResult):
        where, positive, weight = v[f].mean(axis=1), result.convex, result.face_area
    else:
        where, positive, weight = v, result.local_dne >= 0, vertex_areas(v, f)
    centre, radius = _frame(v, f)
    return (where - centre) / radius, positive, weight


def sign_agreement(reference, other) -> float:
    """Fraction of `other`'s surface area whose sign agrees with `reference` nearby.

    Both results must be of the same kind: ``AriaDNEResult`` (per vertex,
    weighted by vertex area, sign ``local_dne >= 0``) or ``ClassicDNEResult``
    (per face, weighted by face area, convex or concave).  Each element of
    `other` is matched to the nearest element of `reference` after both
    meshes are put in a common frame: area-weighted centroid at the origin,
    area-weighted RMS radius 1 (tessellation-independent, and not inflated
    by noise as the area is).

    Returns
    -------
    float
        In [0, 1]; 1 when every sign agrees.
    """
    from scipy.spatial import cKDTree

    kinds = (AriaDNEResult, ClassicDNEResult)
    if not (isinstance(reference, kinds) and type(reference) is type(other)):
        raise TypeError(
            "sign_agreement compares two AriaDNEResult or two ClassicDNEResult; got "
            f"{type(reference).__name__} and {type(other).__name__}"
        )
    ref_at, ref_sign, _ = _located_signs(reference)
    at, sign, weight = _located_signs(other)
    _, nearest = cKDTree(ref_at).query(at)
    agree = sign == ref_sign[nearest]
    return float(weight[agree].sum() / weight.sum())


def _totals(result) -> tuple[float, float, float]:
    if isinstance(result, ClassicDNEResult):
        return result.dne, result.convex_dne, result.concave_dne
    return result.dne, result.positive_dne, result.negative_dne


def _ratio(value: float, base: float) -> float:
    return float(value / base) if base != 0 else float("nan")


@dataclass(frozen=True)
class RobustnessStudy:
    """The outcome of `robustness_study`.

    Attributes
    ----------
    rows : list of dict
        One row per (perturbation, method) with the columns ``STUDY_COLUMNS``:
        counts, totals (``positive``/``negative`` are convex/concave DNE for
        ``"classic"``), totals divided by the same method's on the original,
        and ``sign_agreement`` (see `sign_agreement`).
    meshes : dict of str to trimesh.Trimesh
        The original (``"normal"``) and the perturbed meshes.
    results : dict of (str, str) to result
        ``AriaDNEResult`` or ``ClassicDNEResult`` per (perturbation, method).
    bandwidth : float
        Bandwidth of the ariaDNE runs.
    """

    rows: list
    meshes: dict = field(repr=False)
    results: dict = field(repr=False)
    bandwidth: float = 0.08

    @property
    def perturbations(self) -> list[str]:
        """Mesh names, original first."""
        return list(self.meshes)

    @property
    def methods(self) -> list[str]:
        """Methods, in row order."""
        return list(dict.fromkeys(row["method"] for row in self.rows))

    def row(self, perturbation: str, method: str) -> dict:
        """The row for one perturbation and method."""
        for row in self.rows:
            if row["perturbation"] == perturbation and row["method"] == method:
                return row
        raise KeyError((perturbation, method))

    def _repr_html_(self) -> str:
        """Its rows as a compact table for notebooks."""
        summary = {"perturbations": len(self.meshes), "bandwidth": self.bandwidth}
        return rows_html(self.rows, title=type(self).__name__, summary=summary)


def robustness_study(
    mesh,
    *,
    perturbations: Mapping | None = None,
    bandwidth: float = 0.08,
    sign_methods: Iterable[str] = SIGN_METHODS,
    classic: bool = True,
    seed: int = 0,
    **perturb_options,
) -> RobustnessStudy:
    """Every sign method, and classic DNE, on a mesh and its perturbations.

    Parameters
    ----------
    mesh : trimesh.Trimesh, str, path-like, or (vertices, faces)
        The original surface.  Never modified.
    perturbations : mapping of str to mesh, optional
        Perturbed versions to use instead of generating them (for example the
        paper's own robustness set); generated by `perturb` when omitted.
    bandwidth : float, default 0.08
        ariaDNE bandwidth.
    sign_methods : iterable of str, default all of ``SIGN_METHODS``
        The ariaDNE sign methods to compare.
    classic : bool, default True
        Also compute classic DNE (molaR's convex/concave split).
    seed : int, default 0
        Seed of the generated noise.
    **perturb_options
        Passed to `perturb` (``low_faces``, ``high_faces``, ``noise``,
        ``smooth_iterations``).

    Returns
    -------
    RobustnessStudy

    Examples
    --------
    >>> from dentopo import robustness_study
    >>> from dentopo.samples import tooth
    >>> study = robustness_study(tooth(rings=12), low_faces=300, high_faces=1200,
    ...                          sign_methods=["centroid"])  # doctest: +SKIP
    >>> study.row("smooth", "centroid")["sign_agreement"] > 0.9  # doctest: +SKIP
    True
    """
    bandwidth = check_bandwidth(bandwidth)
    sign_methods = list(sign_methods)
    for method in sign_methods:
        if method not in SIGN_METHODS:
            raise ValueError(f"sign_methods must be among {SIGN_METHODS}; got {method!r}")
    if not sign_methods and not classic:
        raise ValueError("nothing to compare: give sign_methods or classic=True")
    if perturbations is None:
        meshes = perturb(mesh, seed=seed, **perturb_options)
    else:
        if perturb_options:
            raise TypeError(
                f"{sorted(perturb_options)} apply to generated perturbations only; "
                "they cannot be combined with perturbations="
            )
        if BASE in perturbations:
            raise ValueError(f"{BASE!r} names the original mesh; rename that perturbation")
        meshes = {BASE: clean(*as_arrays(mesh))}
        for name, other in perturbations.items():
            meshes[str(name)] = clean(*as_arrays(other))

    results: dict = {}
    for name, surface in meshes.items():
        for method in sign_methods:
            results[name, method] = ariaDNE(surface, bandwidth=bandwidth, sign_method=method)
        if classic:
            results[name, "classic"] = classic_dne(surface)

    methods = [*sign_methods, *(["classic"] if classic else [])]
    rows = []
    for name in meshes:
        for method in methods:
            result, base = results[name, method], results[BASE, method]
            total, positive, negative = _totals(result)
            base_total, base_positive, base_negative = _totals(base)
            rows.append(
                {
                    "perturbation": name,
                    "method": method,
                    "vertices": int(result.vertices),
                    "faces": int(result.faces),
                    "dne": total,
                    "positive": positive,
                    "negative": negative,
                    "dne_normalised": _ratio(total, base_total),
                    "positive_normalised": _ratio(positive, base_positive),
                    "negative_normalised": _ratio(negative, base_negative),
                    "sign_agreement": 1.0 if name == BASE else sign_agreement(base, result),
                }
            )
    return RobustnessStudy(rows=rows, meshes=meshes, results=results, bandwidth=bandwidth)


@dataclass(frozen=True)
class BandwidthSweep:
    """The outcome of `bandwidth_sweep`.

    Attributes
    ----------
    rows : list of dict
        One row per (bandwidth, method) with the columns ``SWEEP_COLUMNS``;
        ``positive_fraction`` is ``positive / dne``.
    results : dict of (float, str) to AriaDNEResult
    """

    rows: list
    results: dict = field(repr=False)

    @property
    def bandwidths(self) -> list[float]:
        return list(dict.fromkeys(row["bandwidth"] for row in self.rows))

    @property
    def methods(self) -> list[str]:
        return list(dict.fromkeys(row["method"] for row in self.rows))

    def _repr_html_(self) -> str:
        """Its rows as a compact table for notebooks."""
        summary = {"bandwidths": len(self.bandwidths), "methods": ", ".join(self.methods)}
        return rows_html(self.rows, title=type(self).__name__, summary=summary)


def bandwidth_sweep(
    mesh,
    bandwidths: Iterable[float] = (0.04, 0.06, 0.08, 0.10, 0.12, 0.14),
    *,
    sign_methods: Iterable[str] = SWEEP_METHODS,
) -> BandwidthSweep:
    """ariaDNE totals for each bandwidth and sign method (the paper's Figure 6).

    Parameters
    ----------
    mesh : trimesh.Trimesh, str, path-like, or (vertices, faces)
        Never modified.
    bandwidths : iterable of float
        Bandwidths in [1e-50, 1e50], in the order of the table.
    sign_methods : iterable of str, default ("centroid", "gaussian_curvature", "mean_curvature")
        The curvature methods use a ball of radius equal to the bandwidth.

    Returns
    -------
    BandwidthSweep
    """
    bandwidths = [check_bandwidth(b) for b in bandwidths]
    if not bandwidths:
        raise ValueError("bandwidths is empty: give at least one bandwidth")
    sign_methods = list(sign_methods)
    if not sign_methods:
        raise ValueError("sign_methods is empty")
    for method in sign_methods:
        if method not in SIGN_METHODS:
            raise ValueError(f"sign_methods must be among {SIGN_METHODS}; got {method!r}")
    surface = clean(*as_arrays(mesh))
    results, rows = {}, []
    for h in bandwidths:
        for method in sign_methods:
            result = ariaDNE(surface, bandwidth=h, sign_method=method)
            results[h, method] = result
            rows.append(
                {
                    "bandwidth": h,
                    "method": method,
                    "dne": result.dne,
                    "positive": result.positive_dne,
                    "negative": result.negative_dne,
                    "positive_fraction": _ratio(result.positive_dne, result.dne),
                }
            )
    return BandwidthSweep(rows=rows, results=results)


# ---------------------------------------------------------------------------
# files


def _atomic_write_bytes(path: Path, data: bytes) -> None:
    atomic_write(path, lambda stream: stream.write(data), binary=True)


def _csv_bytes(rows: Sequence[dict], columns: Sequence[str]) -> bytes:
    buffer = io.StringIO()
    writer = csv.DictWriter(buffer, fieldnames=list(columns), lineterminator="\n")
    writer.writeheader()
    for row in rows:
        writer.writerow({key: _cell(row[key]) for key in columns})
    return buffer.getvalue().encode()


def _cell(value):
    if isinstance(value, float):
        return repr(value)
    return value


def _figure_bytes(figure) -> bytes:
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", dpi=120)
    return buffer.getvalue()


#: The files :func:`write_study` writes into its directory: the table, then the figures.
STUDY_FILES = ("robustness.csv", "robustness_signs.png", "robustness_totals.png")
#: ... and :func:`write_sweep`.
SWEEP_FILES = ("sweep.csv", "sweep.png")


def write_study(
    study: RobustnessStudy, directory: str | os.PathLike, *, figures: bool = True
) -> list[Path]:
    """Write ``robustness.csv``, then ``robustness_signs.png`` and ``robustness_totals.png``.

    Parameters
    ----------
    study : RobustnessStudy
    directory : path-like
        Created if missing.  Each file is written atomically.
    figures : bool, default True
        Also draw the figures (matplotlib, the ``study`` extra).

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
    table = directory / STUDY_FILES[0]
    _atomic_write_bytes(table, _csv_bytes(study.rows, STUDY_COLUMNS))
    written = [table]
    if figures:
        from ._figures import sign_grid, totals_bars

        columns = study.perturbations
        grid = {
            method: [study.results[name, method] for name in columns] for method in study.methods
        }
        for filename, figure in (
            (STUDY_FILES[1], sign_grid(grid, columns)),
            (STUDY_FILES[2], totals_bars(study.rows, columns, study.methods)),
        ):
            _atomic_write_bytes(directory / filename, _figure_bytes(figure))
            written.append(directory / filename)
    return written


def write_sweep(
    sweep: BandwidthSweep, directory: str | os.PathLike, *, figures: bool = True
) -> list[Path]:
    """Write ``sweep.csv``, then the panel ``sweep.png`` (rows: methods; columns: bandwidths).

    As :func:`write_study`: `figures` needs matplotlib (the ``study`` extra),
    checked before anything is written.
    """
    if figures:
        STUDY_FIGURES.require()
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    table = directory / SWEEP_FILES[0]
    _atomic_write_bytes(table, _csv_bytes(sweep.rows, SWEEP_COLUMNS))
    written = [table]
    if figures:
        from ._figures import sign_grid

        grid = {
            method: [sweep.results[h, method] for h in sweep.bandwidths] for method in sweep.methods
        }
        labels = [f"h = {h:g}" for h in sweep.bandwidths]
        figure = sign_grid(grid, labels)
        _atomic_write_bytes(directory / SWEEP_FILES[1], _figure_bytes(figure))
        written.append(directory / SWEEP_FILES[1])
    return written
