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


@pytest.mark.parametrize("limits", [(-0.1, 0.3), 0.0, -1.0, float("nan")])
def test_asymmetric_or_bad_limits_are_refused(limits):
    with pytest.raises(ValueError, match="limit"):
        color_scale(limits=limits)


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
