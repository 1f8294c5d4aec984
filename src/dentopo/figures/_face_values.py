"""Pictures of any per-face value (ARC, angularity, inclination, elevation), one renderer.

:func:`render_face_values` colours each face flat by a value of its own: on
the diverging map centred on 0 (signed values: ARC) or on the sequential one
(ordered values: angularity, inclination, elevation), with a colour bar in the
metric's units; faces without a value are drawn in :data:`MISSING_RGB`.
:data:`FACE_METRICS` says how each of those four is drawn (its array, name,
units, map and scale; :class:`FaceMetric`).  The sequential scale's limits,
round ticks and the HTML page's placed colour bar are built here too; the
window and the output are those of :mod:`._face_drawing`, as for the slope
and OPC pictures (:mod:`._topography`).
"""

from __future__ import annotations

import html as html_escape
import math
from dataclasses import dataclass
from numbers import Real

import numpy as np

from ._camera import DEFAULT_VIEW
from ._colors import (
    DEFAULT_PERCENTILE,
    ColorScale,
    color_scale,
    lookup_table,
    sequential_rgb,
    sequential_table,
)
from ._face_drawing import (
    MISSING_RGB,
    _check_outputs,
    _heading,
    _mesh_arrays,
    _options,
    _plotter,
    _record,
    _show,
)
from ._layout import ColorBar, Panel


@dataclass(frozen=True)
class FaceMetric:
    """How :func:`render_face_values` draws one metric's per-face values.

    Attributes
    ----------
    field : str
        The result's per-face array (``face_arc``, ...), which follows the
        faces of the result's ``mesh``.
    label : str
        The quantity's name, on the colour bar and above the mesh.
    units : str
        Its units, on the colour bar: ``"degrees"``, ``"mesh units"``, or
        ``"dimensionless"``.
    meaning : str
        What the ends of the scale mean, on the colour bar.
    diverging : bool
        Signed values on the diverging map centred on 0 (True), or ordered
        ones on the sequential map (False).
    limits : (float, float), optional
        The sequential scale, fixed; None: from 0 to the largest value (or,
        diverging, symmetric limits from the values' magnitude).
    """

    field: str
    label: str
    units: str
    meaning: str
    diverging: bool = False
    limits: tuple[float, float] | None = None

    def keywords(self) -> dict:
        """The keywords of :func:`render_face_values` for this metric (``limits`` included)."""
        return {
            "metric": self.label.lower(),
            "label": self.label,
            "units": self.units,
            "meaning": self.meaning,
            "diverging": self.diverging,
            "limits": self.limits,
        }


#: The per-face pictures of ARC (molaR), angularity, inclination and elevation (doolkit), and
#: PCV (ambient occlusion: the share of the light directions each face's corners see).
FACE_METRICS = {
    "arc": FaceMetric(
        "face_arc",
        "ARC",
        "dimensionless",
        "blue \u2212 concave, red + convex, zeroed faces neutral",
        diverging=True,
    ),
    "angularity": FaceMetric(
        "face_angularity",
        "angularity",
        "degrees",
        "the slope of the slope: 0 = even, 90 = abrupt",
        limits=(0.0, 90.0),
    ),
    "inclination": FaceMetric(
        "face_inclination",
        "inclination",
        "degrees",
        "0 = facing down, 90 = vertical, 180 = facing up",
        limits=(0.0, 180.0),
    ),
    "elevation": FaceMetric(
        "face_elevation",
        "elevation",
        "mesh units",
        "height above the lowest vertex",
    ),
    "pcv": FaceMetric(
        "face_pcv",
        "PCV",
        "share of the sky",
        "0 = no light reaches it, 1 = lit from every direction",
        limits=(0.0, 1.0),
    ),
}


@dataclass(frozen=True)
class _SequentialScale:
    """Linear limits ``(low, high)`` on the sequential map, and how they were chosen."""

    low: float
    high: float
    rule: str

    @property
    def limits(self) -> tuple[float, float]:
        return (self.low, self.high)

    def position(self, values) -> np.ndarray:
        return (np.asarray(values, dtype=np.float64) - self.low) / (self.high - self.low)

    def bar_rgb(self, t) -> np.ndarray:
        return sequential_rgb(t)

    def rgb(self, values) -> np.ndarray:
        return np.round(255 * sequential_rgb(self.position(values))).astype(np.uint8)


def _number(value: float, digits: int = 4) -> str:
    """A tick or limit as text: `digits` significant digits, a true minus sign, never ``-0``."""
    return f"{value + 0.0:.{digits}g}".replace("-", "\u2212")


def _sequential_scale(values: np.ndarray, limits, unit: str) -> _SequentialScale:
    """The sequential scale: `limits` (``HI`` for ``(0, HI)``, or ``(LO, HI)``) or 0 to the max."""
    if limits is None:
        finite = values[np.isfinite(values)]
        low = min(0.0, float(finite.min())) if finite.size else 0.0
        high = float(finite.max()) if finite.size else 1.0
        if high <= low:
            return _SequentialScale(low, low + 1.0, f"{_number(low)} to {_number(low + 1)}")
        return _SequentialScale(
            low, high, f"{_number(low)} to {_number(high)}{unit} (the largest value)"
        )
    if isinstance(limits, Real) and not isinstance(limits, bool):
        low, high = 0.0, float(limits)
    else:
        try:
            low, high = (float(v) for v in limits)
        except (TypeError, ValueError) as exc:
            raise TypeError(
                f"limits must be a number HI (for 0 to HI) or a pair (LO, HI); got {limits!r}"
            ) from exc
    if not (math.isfinite(low) and math.isfinite(high)) or not low < high:
        raise ValueError(f"the limits must be finite with LO < HI; got ({low!r}, {high!r})")
    return _SequentialScale(low, high, f"{_number(low)} to {_number(high)}{unit} (fixed)")


def _nice_ticks(low: float, high: float, most: int = 7) -> list[float]:
    """Round values from `low` to `high` (both ends when they are round), at most `most`."""
    span = high - low
    raw = span / (most - 1)
    magnitude = 10.0 ** math.floor(math.log10(raw))
    for multiple in (1.0, 1.5, 2.0, 2.5, 3.0, 5.0, 10.0):
        step = multiple * magnitude
        if span / step <= most - 1 + 1e-9:
            break
    first = math.ceil(low / step - 1e-9)
    last = math.floor(high / step + 1e-9)
    return [k * step for k in range(first, last + 1)]


def _tick_text(value: float, degrees: bool, digits: int = 4) -> str:
    return _number(value, digits) + ("\u00b0" if degrees else "")


def _placed_bar_html(title: str, scale, ticks, note: str) -> str:
    """A colour bar's HTML block with ticks placed at their values (as the pictures do)."""
    t = np.linspace(0, 1, 41)
    rgb = np.round(255 * np.asarray(scale.bar_rgb(t))).astype(int)
    stops = zip(t, rgb, strict=True)
    gradient = ", ".join(f"rgb({r},{g},{b}) {100 * p:.1f}%" for p, (r, g, b) in stops)
    spans = "".join(
        f'<span style="left: {100 * p:.2f}%">{html_escape.escape(text)}</span>' for p, text in ticks
    )
    block = (
        f'<div id="rule">{html_escape.escape(title)}</div>\n'
        f'<div id="gradient" style="background: linear-gradient(to right, {gradient})"></div>\n'
        f'<div id="ticks" class="placed">{spans}</div>'
    )
    if note:
        lines = "<br>".join(html_escape.escape(line) for line in note.splitlines())
        block += f'\n<div id="note">{lines}</div>'
    return block


def render_face_values(
    mesh,
    values,
    *,
    metric: str,
    label: str,
    units: str = "",
    meaning: str = "",
    diverging: bool = False,
    limits=None,
    percentile: float = DEFAULT_PERCENTILE,
    note: str = "",
    view=DEFAULT_VIEW,
    window_size: tuple[int, int] = (900, 900),
    title: str | None = None,
    screenshot=None,
    html=None,
    interactive: bool = False,
    azimuth: float = 0.0,
    elevation: float = 0.0,
    dpi: float | None = None,
    transparent: bool = False,
    source=None,
    parameters: dict | None = None,
) -> None:
    """Draw a mesh with each face coloured flat by a value of its own, with a colour bar.

    One renderer for every per-face metric: signed values (ARC) on the
    diverging map centred on 0 (Moreland's cool to warm: blue negative, light
    grey exactly 0, red positive; the curvature pictures' map), ordered ones
    (angularity, inclination, elevation) on the sequential map (viridis: dark
    blue-purple low, yellow high; the slope picture's map).  Faces are
    coloured flat, one colour per face.  Values beyond the limits get the end
    colours (counted under the colour bar on the sequential map; on the
    diverging one a few are expected, its default limit being a percentile);
    faces without a value (NaN) are drawn mid grey (:data:`MISSING_RGB`) and
    counted.
    :data:`FACE_METRICS` holds the settings of the four metrics drawn by
    ``dentopo --color-by``: ``render_face_values(r.mesh, r.face_arc,
    **FACE_METRICS["arc"].keywords())``.

    Parameters
    ----------
    mesh : trimesh.Trimesh or (vertices, faces)
        The mesh the values refer to: the result's ``mesh``.  Never modified.
    values : (m,) array_like of float
        One value per face (NaN allowed: drawn grey).  Never modified.
    metric : str
        What the colours show, for the provenance (``"arc"``, ...).
    label : str
        The quantity's name, above the mesh and on the colour bar.
    units : str, default ""
        Its units, on the colour bar (``"degrees"``: ticks get a degree sign).
    meaning : str, default ""
        What the colours mean, on the colour bar after the units.
    diverging : bool, default False
        The diverging map centred on 0 (signed values) instead of the
        sequential one.
    limits : float or (float, float), optional
        Diverging: ``L`` for ``±L`` or ``(LO, HI)`` with ``LO < 0 < HI``
        (:func:`~dentopo.figures.color_scale`); default symmetric, ``±`` the
        `percentile` of ``|value|``.  Sequential: ``HI`` for 0 to ``HI`` or
        ``(LO, HI)`` with ``LO < HI``; default from 0 (or the smallest value,
        if negative) to the largest value.  Fix them to compare specimens.
    percentile : float, default 98
        Diverging, without `limits`: the percentile of ``|value|`` taken as
        the limit.
    note : str, default ""
        A further line under the colour bar (e.g. how many faces were zeroed).
    view, window_size, title, screenshot, html, interactive
        As in :func:`render_slope`.
    azimuth, elevation, dpi, transparent, source, parameters
        As in :func:`render_slope` (`elevation` turns the camera).

    Raises
    ------
    ValueError
        If `values` does not hold one value per face or holds infinities,
        or no finite value; for bad limits or options, or when no output is
        requested.
    DisplayUnavailableError, dentopo._optional.MissingExtraError
        As in :func:`render_slope`.

    Examples
    --------
    >>> from dentopo.figures import FACE_METRICS, render_face_values
    >>> from dentopo.topography import arc
    >>> result = arc("tooth.ply")  # doctest: +SKIP
    >>> render_face_values(result.mesh, result.face_arc, screenshot="arc.png",
    ...                    **FACE_METRICS["arc"].keywords())  # doctest: +SKIP
    """
    view, window_size = _check_outputs(screenshot, html, interactive, view, window_size)
    vertices, faces = _mesh_arrays(mesh)
    name = str(label)
    per_face = _face_values(values, len(faces), name)
    missing = np.isnan(per_face)
    degrees = units == "degrees"
    unit = "\u00b0" if degrees else ""
    if diverging:
        scale: ColorScale | _SequentialScale = color_scale(
            per_face[~missing], limits=limits, percentile=percentile
        )
        low, high = scale.limits
        tick_values = [low, low / 2, 0.0, high / 2, high]
        rule = f"limits {scale.rule}"
    else:
        scale = _sequential_scale(per_face, limits, unit)
        low, high = scale.limits
        tick_values = _nice_ticks(low, high)
        rule = f"scale {scale.rule}"
    digits = 3 if diverging else 4  # the diverging ticks as the curvature pictures' ones
    ticks = [(float(scale.position(v)), _tick_text(v, degrees, digits)) for v in tick_values]
    rgb = scale.rgb(np.where(missing, 0.0, per_face))
    rgb[missing] = MISSING_RGB
    finite = per_face[~missing]
    notes = [rule]
    # beyond the limits: by design on the diverging map (a percentile), so counted on the other
    above, below = int((finite > high).sum()), int((finite < low).sum())
    if diverging:
        above = below = 0
    if above:
        notes.append(f"{above} faces above {_tick_text(high, degrees)} in the top colour")
    if below:
        notes.append(f"{below} faces below {_tick_text(low, degrees)} in the bottom colour")
    if missing.any():
        notes.append(f"{int(missing.sum())} faces without a value in grey")
    full_note = "; ".join(notes) + (f"\n{note}" if note else "")
    inside = "; ".join(part for part in (units, meaning) if part)
    bar_title = f"{name} ({inside})" if inside else name
    options = _options(view, window_size, azimuth, elevation, dpi, transparent, vertices, faces)
    camera = options["camera"]
    heading = _heading(title, name)
    record = _record(
        metric,
        title,
        source,
        camera,
        {
            "scale": [low, high],
            "map": "diverging" if diverging else "sequential",
            "units": units,
            **({"percentile": percentile} if diverging and limits is None else {}),
            **(parameters or {}),
        },
    )
    if html is not None:
        from ._html import write_html

        write_html(
            html,
            [(vertices, faces, rgb, title or "", "", {"face_colors": True})],
            title=heading,
            cameras=[camera],
            bar=_placed_bar_html(_heading(title, bar_title), scale, ticks, full_note),
            provenance=record,
        )
    panel = Panel(vertices, faces, camera, cell_rgb=rgb, label=heading, ambient=0.6)
    legend = ColorBar(scale.bar_rgb, ticks, title=bar_title, note=full_note)

    def window():
        table = lookup_table(255, scale) if diverging else sequential_table()
        return _plotter(
            vertices,
            faces,
            off_screen=False,
            window_size=window_size,
            view=camera,
            heading=heading,
            cell_values=per_face,
            legend="bar",
            bar_title=bar_title,
            note=full_note,
            table=table,
            clim=(low, high),
            fmt="%.3g",
        )

    _show(
        window,
        screenshot=screenshot,
        interactive=interactive,
        title=heading,
        panel=panel,
        legend=legend,
        options=options,
        record=record,
    )


def _face_values(values, m: int, name: str) -> np.ndarray:
    """`values` as an (m,) float array: NaN allowed (no value), infinities not."""
    try:
        array = np.array(values, dtype=np.float64)  # a copy
    except (TypeError, ValueError) as exc:
        raise TypeError(f"the {name} values must be an array of numbers, one per face") from exc
    if array.shape != (m,):
        raise ValueError(
            f"the {name} values must hold one value per face of the mesh, shape ({m},); "
            f"got {array.shape}"
        )
    if np.isinf(array).any():
        raise ValueError(f"the {name} values hold {int(np.isinf(array).sum())} infinite values")
    if np.isnan(array).all():
        raise ValueError(f"the {name} values hold no number (every face is NaN)")
    return array
