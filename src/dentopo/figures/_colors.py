"""Colour scale for signed fields: a diverging map centred exactly at zero.

Signed curvature is shown red where positive (convex: cusps, ridges), blue
where negative (concave: valleys, basins) and a light neutral grey at zero,
with intensity growing with magnitude.  The neutral colour means zero and
nothing else:

* by default the limits are ``±L`` with ``L`` a high percentile (98 by
  default) of ``|value|``, so that a few extreme vertices (one sharp tip) do
  not wash out the picture; values beyond ``L`` are drawn in the end colours;
* or limits fixed by the caller, ``L`` for ``±L`` or a pair ``(LO, HI)`` with
  ``LO < 0 < HI``, so that several specimens share one scale.  An asymmetric
  pair keeps zero neutral: negative values run from neutral at 0 to the blue
  end at ``LO``, positive ones to the red end at ``HI`` (two linear halves).

The map is Moreland's "cool to warm": under simulated protanopia,
deuteranopia and tritanopia its two sides stay far apart and its lightness
falls from the middle to both ends (tests/test_colors.py measures it).

numpy only; the renderers (pyvista, the HTML viewer) use these colours.
"""

from __future__ import annotations

from dataclasses import dataclass
from numbers import Real

import numpy as np

#: The colour of zero (light grey, so that shading stays visible).
NEUTRAL = (0.866, 0.866, 0.866)

#: Control points of the map, position in [-1, 1] -> RGB in [0, 1].  The ends
#: and the middle follow Moreland's "cool to warm" map (doi:10.1007/978-3-642-10520-3_9).
_STOPS = np.array([-1.0, -0.5, 0.0, 0.5, 1.0])
_STOP_RGB = np.array(
    [
        [0.230, 0.299, 0.754],  # deep blue: most concave
        [0.552, 0.690, 0.996],
        NEUTRAL,
        [0.957, 0.604, 0.482],
        [0.706, 0.016, 0.150],  # deep red: most convex
    ]
)

DEFAULT_PERCENTILE = 98.0


def diverging_rgb(t) -> np.ndarray:
    """Colours of positions on the diverging map.

    Parameters
    ----------
    t : array_like of float
        Positions; -1 is the blue end, 0 the neutral grey, +1 the red end.
        Values beyond [-1, 1] are clipped; NaN is drawn neutral.

    Returns
    -------
    (..., 3) float
        RGB in [0, 1].  ``diverging_rgb(0)`` is exactly ``NEUTRAL``.

    Examples
    --------
    >>> from dentopo import diverging_rgb
    >>> diverging_rgb([-1.0, 0.0, 1.0]).round(3).tolist()
    [[0.23, 0.299, 0.754], [0.866, 0.866, 0.866], [0.706, 0.016, 0.15]]
    """
    t = np.clip(np.nan_to_num(np.asarray(t, dtype=np.float64), nan=0.0), -1.0, 1.0)
    return np.stack([np.interp(t, _STOPS, _STOP_RGB[:, c]) for c in range(3)], axis=-1)


@dataclass(frozen=True)
class ColorScale:
    """Limits ``(low, limit)`` of a signed colour scale, zero neutral; symmetric by default.

    Attributes
    ----------
    limit : float
        Values at or beyond ``limit`` get the red end colour; positive.
    rule : str
        How the limits were chosen, for the colour bar, e.g.
        ``"±0.0123 (98th percentile of the magnitude)"`` or ``"±0.05 (fixed)"``.
    low : float, optional
        Values at or below ``low`` get the blue end colour; negative.
        Default ``-limit``.
    """

    limit: float
    rule: str
    low: float | None = None

    @property
    def limits(self) -> tuple[float, float]:
        """The limits as a ``(low, high)`` pair (``low == -high`` unless set apart)."""
        return (-self.limit if self.low is None else self.low, self.limit)

    def normalize(self, values) -> np.ndarray:
        """Map values to positions on the map, clipped to [-1, 1]: ``0`` stays ``0``.

        Positive values are divided by ``high``, negative ones by ``|low|``.
        """
        values = np.asarray(values, dtype=np.float64)
        low, high = self.limits
        with np.errstate(invalid="ignore"):
            scaled = np.where(values < 0, values / -low, values / high)
        return np.clip(scaled, -1.0, 1.0)

    def position(self, values) -> np.ndarray:
        """Where values lie along a colour bar running linearly from low (0) to high (1)."""
        low, high = self.limits
        return (np.asarray(values, dtype=np.float64) - low) / (high - low)

    def bar_rgb(self, t) -> np.ndarray:
        """(..., 3) float colours along that bar, at positions ``t`` in [0, 1]."""
        low, high = self.limits
        return diverging_rgb(self.normalize(low + np.asarray(t, dtype=np.float64) * (high - low)))

    def rgb(self, values) -> np.ndarray:
        """(n, 3) uint8 colours of ``values`` on this scale."""
        return np.round(255 * diverging_rgb(self.normalize(values))).astype(np.uint8)


def _ordinal(p: float) -> str:
    text = f"{p:g}"
    if not float(p).is_integer():
        return f"{text}th"
    n = int(p)
    suffix = "th" if 10 <= n % 100 <= 20 else {1: "st", 2: "nd", 3: "rd"}.get(n % 10, "th")
    return f"{text}{suffix}"


def color_scale(values=None, *, limits=None, percentile: float = DEFAULT_PERCENTILE) -> ColorScale:
    """Choose symmetric limits for a signed field.

    Parameters
    ----------
    values : array_like of float, or a sequence of them, optional
        The field(s) to be drawn; several arrays (one per specimen) are pooled,
        so that a panel shares one scale.  Not needed when `limits` is given.
    limits : float or (float, float), optional
        Fixed limits: ``L`` for ``(-L, L)``, or a pair ``(LO, HI)`` with
        ``LO < 0 < HI`` (the neutral colour means zero; an asymmetric pair
        stretches the two sides apart).  Use the same limits for several
        specimens to compare them on one scale.
    percentile : float, default 98.0
        When `limits` is None, ``L`` is this percentile of ``|value|`` over the
        finite values, in (0, 100].  100 gives the largest magnitude.

    Returns
    -------
    ColorScale
        The limit and a description of the rule, for the colour bar.  A field
        that is zero everywhere gets ``L = 1`` so that it is drawn neutral.

    Raises
    ------
    ValueError
        For limits that do not hold zero strictly inside, or are not finite,
        a percentile outside (0, 100], or no values and no limits.

    Examples
    --------
    >>> import numpy as np
    >>> from dentopo import color_scale
    >>> color_scale(np.r_[np.linspace(-1, 1, 99), 50.0], percentile=98).rule
    '±0.9596 (98th percentile of the magnitude)'
    >>> color_scale(limits=0.05).limits
    (-0.05, 0.05)
    """
    if limits is not None:
        low, high = _check_limits(limits)
        if low == -high:
            return ColorScale(high, f"±{high:.4g} (fixed)")
        return ColorScale(high, f"{low:.4g} to {high:.4g} (fixed)", low=low)
    if isinstance(percentile, bool) or not isinstance(percentile, Real):
        raise TypeError(f"percentile must be a number; got {type(percentile).__name__}")
    if not 0 < percentile <= 100:
        raise ValueError(f"percentile must lie in (0, 100]; got {percentile!r}")
    if values is None:
        raise ValueError("color_scale needs values or fixed limits")
    if isinstance(values, (list, tuple)) and values and np.ndim(values[0]) == 1:
        values = np.concatenate([np.ravel(np.asarray(v, dtype=np.float64)) for v in values])
    magnitude = np.abs(np.ravel(np.asarray(values, dtype=np.float64)))
    magnitude = magnitude[np.isfinite(magnitude)]
    limit = float(np.percentile(magnitude, percentile)) if magnitude.size else 0.0
    if limit <= 0.0:
        limit = float(magnitude.max()) if magnitude.size else 0.0
    if limit <= 0.0:
        return ColorScale(1.0, "±1 (the field is zero everywhere)")
    return ColorScale(limit, f"±{limit:.4g} ({_ordinal(percentile)} percentile of the magnitude)")


def _check_limits(limits) -> tuple[float, float]:
    """``(low, high)`` with ``low < 0 < high``, from ``L`` or a pair."""
    if isinstance(limits, Real) and not isinstance(limits, bool):
        low, high = -float(limits), float(limits)
    else:
        try:
            low, high = (float(v) for v in limits)
        except (TypeError, ValueError) as exc:
            raise TypeError(
                f"limits must be a number L or a pair (LO, HI); got {limits!r}"
            ) from exc
    if not (np.isfinite(low) and np.isfinite(high)):
        raise ValueError(f"the limits must be finite; got ({low!r}, {high!r})")
    if not low < 0 < high:
        raise ValueError(
            f"the limits must hold zero strictly inside, LO < 0 < HI (the neutral colour means "
            f"zero); a single limit L must be positive; got ({low!r}, {high!r})"
        )
    if np.isclose(low, -high, rtol=1e-12, atol=0.0):
        low = -high
    return low, high


def lookup_table(n: int = 255, scale: ColorScale | None = None) -> np.ndarray:
    """A colour table for renderers that map values linearly onto ``n`` entries.

    Parameters
    ----------
    n : int, default 255
        Number of entries; odd, so that the middle entry, which zero falls
        into when the range is symmetric, is exactly the neutral colour.
    scale : ColorScale, optional
        For asymmetric limits: the table then runs linearly from its low to
        its high limit, zero neutral.

    Returns
    -------
    (n, 4) uint8
        RGBA rows, entry ``k`` coloured at the centre of its bin.
    """
    if n < 3 or n % 2 == 0:
        raise ValueError(f"the table needs an odd number (>= 3) of entries; got {n}")
    centres = -1.0 + (2.0 * np.arange(n) + 1.0) / n
    if scale is not None:
        rgb = np.round(255 * scale.bar_rgb((centres + 1.0) / 2.0)).astype(np.uint8)
    else:
        rgb = np.round(255 * diverging_rgb(centres)).astype(np.uint8)
    return np.column_stack([rgb, np.full(n, 255, dtype=np.uint8)])


# ---------------------------------------------------------------------------
# slope: a sequential scale in degrees

#: The largest slope on the slope scale, in degrees; steeper faces (overhangs) get its colour.
SLOPE_LIMIT = 90.0

#: Viridis (van der Walt and Smith, matplotlib's default map), sampled at 17 evenly
#: spaced positions in [0, 1]; linear interpolation between them stays within one
#: unit of 255 of the full table.  Dark blue-purple: flat; yellow: steep.
_SEQUENTIAL_RGB = np.array(
    [
        [0.267, 0.005, 0.329],
        [0.282, 0.095, 0.417],
        [0.279, 0.175, 0.483],
        [0.259, 0.252, 0.525],
        [0.230, 0.322, 0.546],
        [0.199, 0.388, 0.555],
        [0.173, 0.449, 0.558],
        [0.149, 0.508, 0.557],
        [0.128, 0.567, 0.551],
        [0.121, 0.626, 0.533],
        [0.158, 0.684, 0.502],
        [0.246, 0.739, 0.452],
        [0.369, 0.789, 0.383],
        [0.516, 0.831, 0.294],
        [0.678, 0.864, 0.190],
        [0.846, 0.887, 0.100],
        [0.993, 0.906, 0.144],
    ]
)
_SEQUENTIAL_STOPS = np.linspace(0.0, 1.0, len(_SEQUENTIAL_RGB))


def sequential_rgb(t) -> np.ndarray:
    """Colours of positions on the sequential map (viridis).

    Parameters
    ----------
    t : array_like of float
        Positions; 0 is the dark blue-purple end, 1 the yellow end.  Values
        beyond [0, 1] are clipped; NaN is drawn at 0.

    Returns
    -------
    (..., 3) float
        RGB in [0, 1].
    """
    t = np.clip(np.nan_to_num(np.asarray(t, dtype=np.float64), nan=0.0), 0.0, 1.0)
    return np.stack(
        [np.interp(t, _SEQUENTIAL_STOPS, _SEQUENTIAL_RGB[:, c]) for c in range(3)], axis=-1
    )


def slope_rgb(degrees) -> np.ndarray:
    """(..., 3) uint8 colours of slopes in degrees on the 0 to 90 degree scale.

    0 (facing straight up) is dark blue-purple, 90 (vertical) yellow; steeper
    slopes (overhangs, over 90) are drawn in the 90 degree colour.
    """
    t = np.asarray(degrees, dtype=np.float64) / SLOPE_LIMIT
    return np.round(255 * sequential_rgb(t)).astype(np.uint8)


def sequential_table(n: int = 256) -> np.ndarray:
    """(n, 4) uint8 RGBA rows of the sequential map, entry ``k`` coloured at its bin's centre."""
    if n < 2:
        raise ValueError(f"the table needs at least 2 entries; got {n}")
    rgb = np.round(255 * sequential_rgb((np.arange(n) + 0.5) / n)).astype(np.uint8)
    return np.column_stack([rgb, np.full(n, 255, dtype=np.uint8)])


# ---------------------------------------------------------------------------
# OPC: eight aspect bins around a colour wheel

#: Number of aspect (orientation) bins of OPC.
OPC_BINS = 8


def _hsv_to_rgb(hue: np.ndarray, saturation: float, value: float) -> np.ndarray:
    """RGB in [0, 1] of hues in degrees at one saturation and value (the HSV hexcone)."""
    h = (np.asarray(hue, dtype=np.float64) % 360.0) / 60.0
    c = value * saturation
    x = c * (1.0 - np.abs(h % 2.0 - 1.0))
    sector = np.floor(h).astype(int) % 6
    zero = np.zeros_like(h)
    r = np.choose(sector, [c, x, zero, zero, x, c])
    g = np.choose(sector, [x, c, c, x, zero, zero])
    b = np.choose(sector, [zero, zero, x, c, c, x])
    return np.stack([r, g, b], axis=-1) + (value - c)


#: Hue (degrees on the HSV colour wheel) of OPC bins 1 to 8: 45 degrees apart, in the
#: order of the bins' aspect directions, so that neighbouring directions (bins 8 and 1
#: included) have neighbouring hues.  Bin 1 is red, then orange, yellow-green, green,
#: cyan, azure, violet, magenta.
OPC_HUES = 45.0 * np.arange(OPC_BINS)

#: (8, 3) uint8 colours of OPC bins 1 to 8 (row ``k - 1`` is bin ``k``).
OPC_COLORS = np.round(255 * _hsv_to_rgb(OPC_HUES, 0.85, 0.92)).astype(np.uint8)
OPC_COLORS.flags.writeable = False


def opc_bin_label(k: int) -> str:
    """``"bin k: -180° to -135°"``: the aspect range of OPC bin ``k`` (1 to 8), in degrees.

    The aspect of a face is ``atan2(n_y, n_x)`` of its normal, in (-180, 180];
    bin ``k`` holds aspects in ``(-180 + 45 (k - 1), -180 + 45 k]``.
    """
    low = -180 + 45 * (k - 1)
    return f"bin {k}: {low}\u00b0 to {low + 45}\u00b0"
