"""delta_f of Eq. 1 as its ratio to f_max inside the fits (`identification.bearing_fit._ratio`),
mu = f_max - delta_f exp(-a v) (Constantinou, Mokha & Reinhorn 1990): the names and values go
to the optimiser's ratios and back, and the Jacobian in the ratios becomes the one in delta_f
and f_max (checked against central differences of a residual written in delta_f)."""

import numpy as np
import pytest

from identification.bearing_fit._ratio import (
    from_ratios,
    jacobian_from_ratios,
    ratio_bounds,
    series_ratio_pairs,
    to_ratios,
)

PAIRS = series_ratio_pairs(("bottom", "top"))
SPEEDS = np.linspace(0.0, 0.5, 7)  # [m/s]


def _residual(values):
    """Eq. 1 of both surfaces at SPEEDS (rate 20 s/m), in delta_f and f_max."""
    return np.concatenate([values[f"{s}_f_max"] - values[f"{s}_delta_f"] * np.exp(-20.0 * SPEEDS)
                           for s in ("bottom", "top")])


def test_values_go_to_ratios_in_place_and_back():
    values = {"bottom_radius": 2.0, "bottom_f_max": 0.06, "bottom_delta_f": 0.03, "top_delta_f": 0.02}
    held = {"top_f_max": 0.08}
    ratios = to_ratios(values, PAIRS, held)
    assert list(ratios) == ["bottom_radius", "bottom_f_max", "bottom_delta_ratio", "top_delta_ratio"]
    assert ratios["bottom_delta_ratio"] == pytest.approx(0.5) and ratios["top_delta_ratio"] == pytest.approx(0.25)
    assert from_ratios(ratios, PAIRS, held) == pytest.approx(values)
    assert list(ratio_bounds({"bottom_f_max": (0.0, 1.0), "bottom_delta_f": (0.0, 1.0)}, PAIRS).items()) == [
        ("bottom_f_max", (0.0, 1.0)), ("bottom_delta_ratio", (0.0, 1.0))]


def test_the_jacobian_in_the_ratios_becomes_the_one_in_delta_f():
    """Top's f_max held: its delta_f column is the ratio's over f_max alone."""
    held = {"top_f_max": 0.08}
    params = {"bottom_f_max": 0.06, "bottom_delta_ratio": 0.4, "top_delta_ratio": 0.7}
    names = tuple(params)

    def in_ratios(x):
        return _residual(from_ratios(dict(zip(names, x)), PAIRS, held) | held)

    x0, h = np.array(list(params.values())), 1e-6
    jac = np.stack([(in_ratios(x0 + h * e) - in_ratios(x0 - h * e)) / (2 * h) for e in np.eye(len(x0))], axis=1)
    physical, converted = jacobian_from_ratios(names, jac, params, PAIRS, held)
    assert physical == ("bottom_f_max", "bottom_delta_f", "top_delta_f")
    point = from_ratios(params, PAIRS, held) | held
    for i, name in enumerate(physical):
        up, down = dict(point), dict(point)
        up[name] += h
        down[name] -= h
        np.testing.assert_allclose(converted[:, i], (_residual(up) - _residual(down)) / (2 * h), atol=1e-8)
