"""The diverging colour scale: neutral exactly at zero, symmetric, robust limits."""

from __future__ import annotations

import numpy as np
import pytest

from dentopo import ColorScale, color_scale, diverging_rgb
from dentopo.figures._colors import NEUTRAL, lookup_table


def test_zero_is_exactly_neutral_and_the_ends_are_red_and_blue():
    neutral, red, blue = diverging_rgb([0.0, 1.0, -1.0])
    np.testing.assert_array_equal(neutral, NEUTRAL)
    assert red[0] > 0.6 and red[2] < 0.2  # red end: positive, convex
    assert blue[2] > 0.6 and blue[0] < 0.3  # blue end: negative, concave


def test_positive_is_reddish_and_negative_bluish_at_every_magnitude():
    t = np.linspace(0.01, 1.0, 50)
    positive, negative = diverging_rgb(t), diverging_rgb(-t)
    assert (positive[:, 0] > positive[:, 2]).all()
    assert (negative[:, 2] > negative[:, 0]).all()
    # intensity grows with magnitude: the distance from neutral increases
    distance = np.linalg.norm(positive - np.asarray(NEUTRAL), axis=1)
    assert (np.diff(distance) > 0).all()


def test_percentile_limit_ignores_a_few_extreme_vertices():
    rng = np.random.default_rng(0)
    values = rng.uniform(-1, 1, 1000)
    values[:3] = [40.0, -55.0, 70.0]  # a few sharp tips
    scale = color_scale(values, percentile=98)
    assert scale.limit == pytest.approx(np.percentile(np.abs(values), 98))
    assert scale.limit < 1.0
    assert scale.limits == (-scale.limit, scale.limit)
    assert "98th percentile" in scale.rule and f"{scale.limit:.4g}" in scale.rule


def test_pooled_values_share_one_scale():
    a, b = np.linspace(-1, 1, 101), np.linspace(-3, 3, 101)
    pooled = color_scale([a, b], percentile=100)
    assert pooled.limit == pytest.approx(3.0)


def test_fixed_limits_accept_a_number_or_a_symmetric_pair():
    assert color_scale(limits=0.2).limits == (-0.2, 0.2)
    assert color_scale(np.ones(5), limits=(-0.2, 0.2)).limit == 0.2
    assert "fixed" in color_scale(limits=0.2).rule


@pytest.mark.parametrize("limits", [(0.1, 0.3), (-0.3, -0.1), (-0.1, 0.0), 0.0, -1.0, float("nan")])
def test_limits_without_zero_inside_or_bad_are_refused(limits):
    with pytest.raises(ValueError, match="limit"):
        color_scale(limits=limits)


def test_asymmetric_limits_keep_zero_neutral_and_reach_both_ends():
    scale = color_scale(limits=(-0.1, 0.3))
    assert scale.limits == (-0.1, 0.3) and "fixed" in scale.rule
    np.testing.assert_array_equal(scale.rgb([-0.1, 0.3]), color_scale(limits=1).rgb([-1, 1]))
    np.testing.assert_array_equal(scale.rgb([0.0]), color_scale(limits=1).rgb([0.0]))
    np.testing.assert_allclose(scale.normalize([-0.05, 0.15, -1.0, 1.0]), [-0.5, 0.5, -1, 1])
    # the bar runs linearly in value: zero sits a quarter of the way along
    assert scale.position(0.0) == pytest.approx(0.25)
    np.testing.assert_allclose(scale.bar_rgb(0.25), np.asarray(NEUTRAL))
    assert color_scale(limits=(-0.2, 0.2)).low is None  # a symmetric pair is symmetric


def test_zero_field_gets_a_unit_scale_and_renders_neutral():
    scale = color_scale(np.zeros(10))
    assert scale.limit == 1.0
    assert (scale.rgb(np.zeros(10)) == np.round(255 * np.asarray(NEUTRAL))).all()


def test_values_beyond_the_limit_take_the_end_colours():
    scale = ColorScale(1.0, "test")
    np.testing.assert_array_equal(scale.rgb([5.0, -5.0]), scale.rgb([1.0, -1.0]))


def test_lookup_table_puts_zero_in_a_neutral_middle_entry():
    table = lookup_table(255)
    assert table.shape == (255, 4)
    np.testing.assert_array_equal(table[127, :3], np.round(255 * np.asarray(NEUTRAL)))
    with pytest.raises(ValueError, match="odd"):
        lookup_table(256)


@pytest.mark.parametrize("percentile", [0, 101])
def test_percentile_outside_range_is_refused(percentile):
    with pytest.raises(ValueError, match="percentile"):
        color_scale(np.ones(3), percentile=percentile)


# ---------------------------------------------------------------------------
# colour-vision deficiency: the two sides stay apart, lightness falls from the middle

#: Machado, Oliveira and Fernandes (2009), severity 1.0, on linear RGB.
CVD = {
    "protanopia": [
        [0.152286, 1.052583, -0.204868],
        [0.114503, 0.786281, 0.099216],
        [-0.003882, -0.048116, 1.051998],
    ],
    "deuteranopia": [
        [0.367322, 0.860646, -0.227968],
        [0.280085, 0.672501, 0.047413],
        [-0.011820, 0.042940, 0.968881],
    ],
    "tritanopia": [
        [1.255528, -0.076749, -0.178779],
        [-0.078411, 0.930809, 0.147602],
        [0.004733, 0.691367, 0.303900],
    ],
}


def cielab(srgb: np.ndarray, matrix) -> np.ndarray:
    linear = np.where(srgb <= 0.04045, srgb / 12.92, ((srgb + 0.055) / 1.055) ** 2.4)
    linear = np.clip(linear @ np.asarray(matrix).T, 0, 1)
    xyz = (
        linear
        @ np.array([[0.4124, 0.3576, 0.1805], [0.2126, 0.7152, 0.0722], [0.0193, 0.1192, 0.9505]]).T
    )
    xyz = xyz / np.array([0.95047, 1.0, 1.08883])
    f = np.where(xyz > 0.008856, np.cbrt(xyz), 7.787 * xyz + 16 / 116)
    return np.stack(
        [116 * f[:, 1] - 16, 500 * (f[:, 0] - f[:, 1]), 200 * (f[:, 1] - f[:, 2])], axis=1
    )


@pytest.mark.parametrize("vision", ["normal", *CVD])
def test_diverging_map_is_safe_for_colour_blind_readers(vision):
    matrix = np.eye(3) if vision == "normal" else CVD[vision]
    t = np.linspace(0.0, 1.0, 21)
    negative = cielab(diverging_rgb(-t), matrix)
    positive = cielab(diverging_rgb(t), matrix)
    apart = np.linalg.norm(negative - positive, axis=1)
    assert (apart[t >= 0.2] > 20).all(), apart  # concave and convex never look alike
    assert (apart[t >= 0.5] > 50).all(), apart
    for side in (negative, positive):  # darker away from zero, on both sides
        assert (np.diff(side[:, 0]) < 0).all()
