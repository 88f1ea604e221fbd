"""Figures and summaries say what their numbers are: the Monte Carlo legend's values carry their
units, the residual maps follow `--units`, `fit.png` marks a constant the records do not
determine, Fig. 11's dimensionless axes say [-], and `fit` says what its exit status means."""

import dataclasses
import types

import matplotlib.pyplot as plt
import numpy as np
import pytest

from teflon_jax.cli._isolator_table import fit_status
from teflon_jax.paper._structure_figures import fig11_panels
from teflon_jax.report import fit_figure, montecarlo_figure, residual_maps
from teflon_jax.studies import MonteCarloResult
from teflon_jax.units import INCH, KIP


def _result(n=40):
    rng = np.random.default_rng(0)
    disp, shear = rng.uniform(0.05, 0.2, n), rng.uniform(0.05, 0.15, n)
    return MonteCarloResult(base_disp=disp, base_shear_ratio=shear, smooth_base_disp=disp,
                            smooth_base_shear_ratio=shear, converged=np.ones(n, bool), pga=np.full(n, 3.0),
                            design={}, dims=("motion",), n_devices=1, chunk_size=n, wall_s=1.0, compile_s=0.5,
                            memory_estimate_bytes=0)


def test_montecarlo_legend_values_carry_their_units():
    result = _result()
    fig = montecarlo_figure(result, length=("in", INCH))
    try:
        disp, shear = (ax.get_legend().get_texts() for ax in fig.axes[:2])
        median = np.median(result.base_disp) / INCH
        assert f"median = {median:.3g} in" in [t.get_text() for t in disp]
        assert all(t.get_text().endswith((" in", "runs")) for t in disp)
        assert all(t.get_text().endswith(("[-]", "runs")) for t in shear)
    finally:
        plt.close(fig)


def test_montecarlo_figure_draws_each_slider_against_its_capacity():
    """A double pendulum's result: a third column holds each slider's exceedance curve in the
    output length unit, its capacity a dashed line of the curve's colour, the runs beyond it
    counted in the legend, and below the heated surface's rise in K; runs that did not
    converge are left out of both."""
    rng = np.random.default_rng(1)
    travel = rng.uniform(1.0, 6.0, (40, 1, 2)) * INCH
    rise = rng.uniform(10.0, 90.0, (40, 1, 1))
    converged = np.ones(40, bool)
    converged[:3] = False
    result = dataclasses.replace(_result(), converged=converged, slider_travel=travel,
                                 surface_temperature_rise=rise,
                                 attrs={"slider_names": ["bottom", "top"], "heated_surface_names": ["bottom"],
                                        "slider_capacities_m": [[4.0 * INCH, 12.0 * INCH]]})
    fig = montecarlo_figure(result, length=("in", INCH))
    try:
        assert len(fig.axes) == 6
        sliders, heated = fig.axes[2], fig.axes[5]
        assert sliders.get_xlabel() == "peak slider travel [in]"
        curves = [line for line in sliders.lines if line.get_linestyle() == "-"]
        limits = [line for line in sliders.lines if line.get_linestyle() == "--"]
        for e, (curve, limit) in enumerate(zip(curves, limits)):
            np.testing.assert_allclose(curve.get_xdata(), np.sort(travel[3:, 0, e]) / INCH)
            assert limit.get_xdata()[0] == pytest.approx((4.0, 12.0)[e])
            assert limit.get_color() == curve.get_color()
        beyond = int(np.sum(travel[3:, 0, 0] > 4.0 * INCH))
        assert 0 < beyond < 37
        texts = [t.get_text() for t in sliders.get_legend().get_texts()]
        assert texts == [f"bottom (capacity 4 in, {beyond} runs beyond)", "top (capacity 12 in, 0 runs beyond)"]
        assert heated.get_xlabel() == "peak surface temperature rise [K]"
        np.testing.assert_allclose(heated.lines[0].get_xdata(), np.sort(rise[3:, 0, 0]))
    finally:
        plt.close(fig)
    assert len(montecarlo_figure(_result()).axes) == 4  # flat sliders: the base's two columns
    plt.close("all")


def test_residual_maps_draw_speeds_in_the_output_length_unit():
    speed = np.linspace(0.0, 0.5, 20)  # [m/s]
    columns = [("speed |v| [m/s]", speed), ("time [s]", np.arange(20.0))]
    groups = [(np.ones(20, bool), "C0", "+x")]
    us = residual_maps(columns, np.zeros(20), groups, ylabel="d_mu [-]", title="", length=("in", INCH))
    si = residual_maps(columns, np.zeros(20), groups, ylabel="d_mu [-]", title="")
    assert [ax.get_xlabel() for ax in us.axes[:2]] == ["speed |v| [in/s]", "time [s]"]
    np.testing.assert_allclose(us.axes[0].lines[0].get_xdata(), speed / INCH)
    assert si.axes[0].get_xlabel() == "speed |v| [m/s]"
    np.testing.assert_allclose(si.axes[0].lines[0].get_xdata(), speed)


def _fit(std_b, warnings=()):
    t = np.linspace(0.0, 1.0, 50)
    u = 0.01 * np.sin(2 * np.pi * t)
    record = types.SimpleNamespace(name="test.csv", ux=u, measured=np.sign(np.cos(2 * np.pi * t)) * KIP,
                                   fitted=np.sign(np.cos(2 * np.pi * t)) * KIP, time=t, nrmse=0.01)
    return types.SimpleNamespace(records=[record], parameters={"f_max": 0.1, "breakaway_ratio": 1.05},
                                 std_errors={"f_max": 0.002, "breakaway_ratio": std_b},
                                 free=("f_max", "breakaway_ratio"), converged=True, warnings=list(warnings))


@pytest.mark.parametrize("std_b, warnings", [
    (float("inf"), ()),
    (0.01, ["breakaway_ratio: not identifiable; no record starts from rest (no first excursion)."]),
])
def test_fit_title_marks_a_constant_that_is_not_identified(std_b, warnings):
    fig = fit_figure(_fit(std_b, warnings))
    try:
        title = fig._suptitle.get_text().replace("\n", " ")
        assert "b = 1.05 (not identified)" in title and "f_max = 0.1 +- 0.002" in title
    finally:
        plt.close(fig)


def test_fit_title_gives_the_standard_error_of_an_identified_constant():
    fig = fit_figure(_fit(0.01))
    try:
        title = fig._suptitle.get_text().replace("\n", " ")
        assert "b = 1.05 +- 0.01" in title and "not identified" not in title
    finally:
        plt.close(fig)


def test_fig11_dimensionless_axes_say_so():
    sweep = types.SimpleNamespace(records=("elcentro",), systems=("sliding", "linear"),
                                  peaks={"base_disp": np.ones((1, 2, 3)), "base_shear_ratio": np.ones((1, 2, 3))})
    panels = fig11_panels(sweep, {"elcentro": {"pgd_in": 4.0, "name": "El Centro"}})
    assert [label for _, label, _ in panels] == ["peak base displacement / PGD [-]",
                                                 "peak first-storey shear / superstructure weight [-]"]
    np.testing.assert_allclose(panels[0][2][0][1], 1 / (4.0 * INCH))


def test_fit_status_says_what_the_exit_status_means():
    clean = types.SimpleNamespace(clean=True, converged=True, warnings=[])
    poor = types.SimpleNamespace(clean=False, converged=True, warnings=["asymmetric misfit", "normal load"])
    stuck = types.SimpleNamespace(clean=False, converged=False, warnings=[])
    assert fit_status(clean, 0, ["a.csv"]) == "clean"
    converged = fit_status(poor, 0, ["a.csv", "b.csv"])
    assert converged.startswith("converged, not clean (2 warning(s) above)")
    assert "`teflon-jax diagnose RECORD` on each of a.csv, b.csv looks for the effects the model lacks" in converged
    assert "`teflon-jax diagnose a.csv` looks for" in fit_status(poor, 0, ["a.csv"])
    assert fit_status(stuck, 0, ["a.csv"]).startswith("NOT CONVERGED") and "exit status 1" in fit_status(
        stuck, 0, ["a.csv"])
