"""Figures of the robustness study and the bandwidth sweep (matplotlib only).

* `sign_grid`: rows of coloured meshes, one row per method, one column per mesh
  or bandwidth (the paper's Figures 2 and 6).  Every cell is drawn from the
  same viewpoint: looking down the outward mean normal of the first mesh (the
  occlusal view of an open crown), orthographic, faces painted back to front
  and shaded by the cosine to the view.  Colours: a diverging map centred on
  zero (red convex, blue concave), symmetric limits at the 98th percentile of
  |value| over the row, so colours compare along a row.  ariaDNE cells show
  ``local_curvature`` (per vertex, averaged per face); classic DNE cells show
  the face energy density signed by molaR's convex/concave class (excluded
  faces at zero), each cell scaled by its own percentile, because the density
  itself grows with the resolution.
* `totals_bars`: one bar chart per method of DNE, positive and negative
  totals normalised by the original mesh, and the sign agreement (the
  paper's Figure 5).

Drawn with ``matplotlib.figure.Figure`` (no pyplot state, no display needed);
matplotlib comes with the ``study`` extra and is imported only here, through
:data:`dentopo._optional.STUDY_FIGURES`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from .._optional import STUDY_FIGURES, require
from ..figures import diverging_rgb
from ..mesh import outward_faces
from ..topography import ClassicDNEResult

PERCENTILE = 98.0
METHOD_LABELS = {
    "centroid": "signDNE (centroid)",
    "winding": "winding number",
    "mean_curvature": "mean curvature",
    "gaussian_curvature": "Gaussian curvature",
    "classic": "classic DNE (molaR)",
}


def _mpl(module: str):
    """A matplotlib module, or :class:`~dentopo._optional.MissingExtraError` (study extra)."""
    return require(module, extra=STUDY_FIGURES.extra, purpose=STUDY_FIGURES.purpose)


def face_values(result) -> np.ndarray:
    """The signed value drawn on each face of ``result.mesh``."""
    if isinstance(result, ClassicDNEResult):
        signed = np.where(result.convex, result.face_energy, -result.face_energy)
        return np.where(result.excluded, 0.0, signed)
    faces = np.asarray(result.mesh.faces)
    return result.local_curvature[faces].mean(axis=1)


def view_basis(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Rows: right, up, toward the viewer; the viewer looks down the outward mean normal."""
    oriented = outward_faces(vertices, faces)
    tri = vertices[oriented]
    total = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]).sum(axis=0)
    area2 = np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1).sum()
    toward = total / np.linalg.norm(total) if np.linalg.norm(total) > 0.1 * area2 else np.eye(3)[2]
    helper = np.eye(3)[np.argmin(np.abs(toward))]
    right = np.cross(helper, toward)
    right /= np.linalg.norm(right)
    return np.vstack([right, np.cross(toward, right), toward])


def colour_map():
    """The package's diverging map (:func:`dentopo.figures.diverging_rgb`) for matplotlib.

    The one map of every other picture (Moreland's cool to warm, zero neutral),
    as a matplotlib colormap for the figures' colour bars.
    """
    colors = _mpl("matplotlib.colors")
    return colors.ListedColormap(
        diverging_rgb(np.linspace(-1.0, 1.0, 255)), name="dentopo_diverging"
    )


def draw_mesh(ax, vertices, faces, values, *, basis, limit) -> None:
    """Paint a mesh on a 2-D axes, orthographic along ``basis[2]``, back to front.

    Faces are coloured by :func:`dentopo.figures.diverging_rgb` at ``values /
    limit`` (clipped to [-1, 1]), the package's one diverging map.
    """
    collections = _mpl("matplotlib.collections")

    projected = (vertices - vertices.mean(axis=0)) @ basis.T
    tri = projected[faces]
    normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    length = np.linalg.norm(normal, axis=1)
    shade = np.divide(np.abs(normal[:, 2]), length, out=np.zeros(len(faces)), where=length > 0)
    order = np.argsort(tri[:, :, 2].mean(axis=1))
    rgb = diverging_rgb(np.clip(values / limit, -1.0, 1.0))
    colour = np.column_stack([rgb, np.ones(len(rgb))])
    colour[:, :3] *= (0.35 + 0.65 * shade)[:, None]
    ax.add_collection(
        collections.PolyCollection(
            tri[order, :, :2], facecolors=colour[order], edgecolors="none", antialiased=False
        )
    )
    ax.set_xlim(projected[:, 0].min(), projected[:, 0].max())
    ax.set_ylim(projected[:, 1].min(), projected[:, 1].max())
    ax.set_aspect("equal")
    ax.set_axis_off()


def _limit(values: np.ndarray) -> float:
    return float(np.percentile(np.abs(values), PERCENTILE)) or 1.0


def sign_grid(grid: Mapping[str, Sequence], column_labels: Sequence[str]):
    """Rows of coloured meshes: ``grid[method]`` is one result per column.

    Returns
    -------
    matplotlib.figure.Figure
    """
    cm, colors = _mpl("matplotlib.cm"), _mpl("matplotlib.colors")

    methods = list(grid)
    ncols = len(column_labels)
    figure = _mpl("matplotlib.figure").Figure(
        figsize=(1.9 * ncols + 1.2, 1.9 * len(methods) + 0.4), layout="constrained"
    )
    axes = figure.subplots(len(methods), ncols, squeeze=False)
    first = grid[methods[0]][0].mesh
    basis = view_basis(np.asarray(first.vertices, float), np.asarray(first.faces, np.int64))
    for r, method in enumerate(methods):
        values = [face_values(result) for result in grid[method]]
        per_cell = all(isinstance(result, ClassicDNEResult) for result in grid[method])
        limit = _limit(np.concatenate(values))
        for c, (result, value) in enumerate(zip(grid[method], values, strict=True)):
            mesh = result.mesh
            if per_cell:
                limit = _limit(value)
            draw_mesh(
                axes[r, c],
                np.asarray(mesh.vertices, float),
                np.asarray(mesh.faces, np.int64),
                value,
                basis=basis,
                limit=limit,
            )
            if r == 0:
                axes[r, c].set_title(column_labels[c], fontsize=9)
        axes[r, 0].text(
            -0.08,
            0.5,
            METHOD_LABELS.get(method, method),
            transform=axes[r, 0].transAxes,
            rotation=90,
            ha="right",
            va="center",
            fontsize=9,
        )
        bar = figure.colorbar(
            cm.ScalarMappable(
                colors.Normalize(-1 if per_cell else -limit, 1 if per_cell else limit),
                colour_map(),
            ),
            ax=axes[r, -1],
            shrink=0.8,
        )
        bar.ax.tick_params(labelsize=7)
        if per_cell:
            bar.set_label("per mesh, / 98th pct.", fontsize=7)
    return figure


def totals_bars(rows: Sequence[Mapping], columns: Sequence[str], methods: Sequence[str]):
    """Bar charts of normalised totals and sign agreement, one panel per method.

    Returns
    -------
    matplotlib.figure.Figure
    """
    series = (
        ("dne_normalised", "DNE", "0.55"),
        ("positive_normalised", "positive / convex", "#c0392b"),
        ("negative_normalised", "negative / concave", "#2e6db4"),
        ("sign_agreement", "sign agreement (area)", "#e0b040"),
    )
    figure = _mpl("matplotlib.figure").Figure(
        figsize=(1.3 * len(columns) + 2.5, 2.1 * len(methods)), layout="constrained"
    )
    axes = figure.subplots(len(methods), 1, squeeze=False, sharex=True)[:, 0]
    table = {(row["perturbation"], row["method"]): row for row in rows}
    x = np.arange(len(columns))
    width = 0.8 / len(series)
    top = 1.2
    for ax, method in zip(axes, methods, strict=True):
        for k, (key, label, colour) in enumerate(series):
            heights = [table[name, method][key] for name in columns]
            top = max(top, *(h for h in heights if np.isfinite(h)))
            ax.bar(x + (k - 1.5) * width, heights, width, label=label, color=colour)
        ax.axhline(1.0, color="k", linewidth=0.8, linestyle="--")
        ax.set_title(METHOD_LABELS.get(method, method), fontsize=9, loc="left")
        ax.tick_params(labelsize=8)
    for ax in axes:
        ax.set_ylim(0, 1.05 * top)
    axes[-1].set_xticks(x, columns)
    axes[0].legend(fontsize=7, ncols=len(series), loc="lower left")
    return figure


#: Axis titles of `sensitivity_figure`.
AXIS_LABELS = {
    "faces": "faces",
    "smoothing": "smoothing iterations",
    "noise": "noise sd (unit-area scale)",
}
_QUANTITY_COLOURS = ("0.2", "#c0392b", "#2e6db4", "#e0b040")


def sensitivity_figure(
    rows: Sequence[Mapping],
    metric: str,
    quantities: Sequence[str],
    axes: Mapping[str, Sequence],
    *,
    crowns: int = 1,
    base: str = "as given",
):
    """One metric's relative change (%) against each axis of a protocol study.

    One panel per axis; one line per quantity of the metric.  With one crown
    the line is that crown's; with several it is the median over the crowns,
    with the band from the smallest to the largest change.  Missing values
    (a metric that failed) are left out of the line; the panel says how many.

    Returns
    -------
    matplotlib.figure.Figure
    """
    figure = _mpl("matplotlib.figure").Figure(
        figsize=(3.3 * len(axes) + 0.6, 3.0), layout="constrained"
    )
    panels = figure.subplots(1, len(axes), squeeze=False)[0]
    for ax, (axis, levels) in zip(panels, axes.items(), strict=True):
        missing = counted = 0
        for k, quantity in enumerate(quantities):
            colour = _QUANTITY_COLOURS[k % len(_QUANTITY_COLOURS)]
            x, middle, low, high = [], [], [], []
            for level in levels:
                changes = [
                    row["relative_change"]
                    for row in rows
                    if row["axis"] == axis
                    and row["level"] == level
                    and row["metric"] == metric
                    and row["quantity"] == quantity
                ]
                finite = [100.0 * c for c in changes if c is not None and np.isfinite(c)]
                missing += len(changes) - len(finite)
                counted += len(changes)
                if finite:
                    x.append(level)
                    middle.append(float(np.median(finite)))
                    low.append(min(finite))
                    high.append(max(finite))
            if not x:
                continue
            ax.plot(x, middle, marker="o", markersize=3, color=colour, label=quantity)
            if crowns > 1:
                ax.fill_between(x, low, high, color=colour, alpha=0.15, linewidth=0)
        ax.axhline(0.0, color="k", linewidth=0.8, linestyle="--")
        if axis == "faces":
            ax.set_xscale("log")
            ax.set_xticks(list(levels), [f"{n / 1000:g}k" for n in levels])
            ax.minorticks_off()
        elif axis == "smoothing" and max(levels) >= 10:
            ax.set_xscale("symlog", linthresh=1.0)
            ax.set_xticks(list(levels), [f"{n:g}" for n in levels])
            ax.minorticks_off()
        elif axis == "noise":
            ax.set_xticks(list(levels), [f"{sd:g}" for sd in levels])
        ax.set_xlabel(AXIS_LABELS.get(axis, axis), fontsize=8)
        ax.tick_params(labelsize=7)
        if missing:
            ax.set_title(
                f"{missing} of {counted} values missing", fontsize=7, loc="right", color="#a00"
            )
    panels[0].set_ylabel(f"change from base ({base}), %", fontsize=8)
    if panels[0].get_legend_handles_labels()[0]:
        panels[0].legend(fontsize=7, loc="best")
    spread = "median and range of " if crowns > 1 else ""
    figure.suptitle(
        f"{METRIC_TITLES.get(metric, metric)}: {spread}{crowns} crown{'s' * (crowns != 1)}",
        fontsize=9,
    )
    return figure


#: Titles of the metrics in `sensitivity_figure`.
METRIC_TITLES = {
    "ariadne": "ariaDNE (signDNE split)",
    "classic": "classic DNE (molaR)",
    "rfi": "RFI (molaR)",
    "opcr": "OPCR (molaR)",
    "opc": "OPC (molaR)",
    "slope": "slope (molaR)",
    "arc": "ARC (molaR)",
    "doolkit_slope": "slope (doolkit)",
    "angularity": "angularity (doolkit)",
    "relief_index": "relief index (doolkit)",
    "inclination": "inclination (doolkit)",
    "doolkit_opc": "OPC (doolkit)",
    "doolkit_opcr": "OPCR (doolkit)",
    "doolkit_arc": "ARC (doolkit)",
    "doolkit_dne": "DNE (doolkit)",
    "relief_rate": "relief rate below median (doolkit)",
    "shape_index": "shape indices (doolkit)",
    "footprint": "footprint area (doolkit)",
    "hypsodonty": "hypsodonty (doolkit)",
}
