"""Every heated isolator reports the surface temperature rise s dT [K] that enters its friction
(`StructureResponse.surface_temperature_rise`, (nt, G, S)): flat sliders and single pendulums
under one and two components against the rise of Carslaw & Jaeger for the flux the bearing
took (q = mu p |du| / dt held over each step, mu at the step's start lowered by the rise
reported there, Kumar et al. 2015), and a double pendulum whose top never slides against the
single pendulum of its bottom surface; `teflon-jax run` prints the peak and writes the history."""

import json

import equinox as eqx
import jax
import numpy as np
import pytest

from teflon_jax.bearing import (
    DoublePendulum,
    FrictionalHeating,
    concave_surface,
    coulomb_friction,
    kumar_temperature_factor,
    paper_bearing,
    surface_temperature_coefficient,
)
from teflon_jax.excitation import uniform_signal
from teflon_jax.studies import bidirectional_isolated_structure
from teflon_jax.systems import isolated_structure, simulate_history

MU, PRESSURE, RADIUS, DT, DURATION = 0.08, 30e6, 1.5, 0.005, 6.0
SCALE = 2.0  # heat_scale s: the rise reported is s dT, the one k_T reads
HEAT = FrictionalHeating(contact_area=0.05, heat_scale=SCALE)


def _ground(scale=1.0):
    t = np.arange(0, DURATION + DT / 2, DT)
    return uniform_signal(scale * 4.0 * np.sin(2 * np.pi * t / 1.5) * np.exp(-0.1 * t), DT)


def _heated(heating=HEAT):
    bearing = paper_bearing(coulomb_friction(MU))
    return eqx.tree_at(lambda b: b.heating, bearing, heating, is_leaf=lambda x: x is None)


def _run(system):
    response = jax.jit(simulate_history, static_argnums=1)(system, DURATION)
    assert bool(np.all(response.converged))
    return response


def _carslaw_jaeger(time, slide, rise):
    """s dT(t_n) = s C sum_k q_k 2 (sqrt(t_n - t_k) - sqrt(t_n - t_k+1)) [K] of the flux held
    over each step, q_k = mu_k p slide_k / dt, mu_k = MU k_T(T0 + rise_k) / k_T(T0) (T0 =
    20 degC)."""
    mu = MU * np.asarray(kumar_temperature_factor(20.0 + rise[:-1]) / kumar_temperature_factor(20.0))
    flux = mu * PRESSURE * slide / DT
    coefficient = SCALE * float(surface_temperature_coefficient())
    out = np.zeros_like(time)
    for n in range(1, time.size):
        age0, age1 = time[n] - time[:n], time[n] - time[1:n + 1]
        out[n] = coefficient * np.sum(flux[:n] * 2 * (np.sqrt(age0) - np.sqrt(age1)))
    return out


@pytest.mark.parametrize("isolator", ["flat", "single-fp"])
@pytest.mark.parametrize("components", [1, 2])
def test_the_reported_rise_is_carslaw_and_jaeger_of_the_flux_taken(isolator, components):
    """The rise reported at every step against the convolution of the flux the bearing took
    (the step's slide at the friction of the step's start), to the heat kernel's quadrature
    (3e-4 of the peak; one step's change is 7e-3), under one component and under two with the
    ground along x alone."""
    surface = None if isolator == "flat" else concave_surface(RADIUS)
    options = dict(isolator=_heated() if surface is None else (_heated(), surface), pressure=PRESSURE,
                   time_step=DT, breakaway=False, isolation_period=3.0 if surface is None else None)
    if components == 1:
        response = _run(isolated_structure("rigid", **options)(_ground()))
    else:
        response = _run(bidirectional_isolated_structure("rigid", **options)((_ground(), _ground(0.0))))
    rise = np.asarray(response.surface_temperature_rise)
    assert rise.shape == (response.time.shape[0], 1, 1)
    rise = rise[:, 0, 0]
    base = np.asarray(response.displacement)[:, 0]
    expected = _carslaw_jaeger(np.asarray(response.time), np.abs(np.diff(base)), rise)
    assert rise.max() > 5.0  # the bearing does heat
    assert np.abs(rise - expected).max() < 2e-3 * rise.max()
    assert np.abs(rise[1:] - expected[1:]).max() > 0  # not read back from the convolution


def test_a_double_pendulum_with_a_locked_top_reports_its_bottom_surface_rise():
    """Top surface locked (f_max 5): the bottom surface is the heated single pendulum of radius
    R1; its rise is that pendulum's to the models' O(dt) difference (4e-4 of the peak), the
    top stays cold."""
    double = DoublePendulum(bottom_radius=RADIUS, top_radius=2.0, bottom_capacity=1.0, top_capacity=1.0,
                            bottom_friction=coulomb_friction(MU), top_friction=coulomb_friction(5.0),
                            hysteresis=_heated().hysteresis, bottom_heating=HEAT, bottom_pressure=PRESSURE)
    series = _run(isolated_structure("rigid", isolator=double, time_step=DT)(_ground()))
    single = _run(isolated_structure("rigid", isolator=(_heated(), concave_surface(RADIUS)), pressure=PRESSURE,
                                     time_step=DT, breakaway=False, split_at_turn=False)(_ground()))
    series_rise, single_rise = np.asarray(series.surface_temperature_rise), np.asarray(single.surface_temperature_rise)
    assert series_rise.shape == (series.time.shape[0], 1, 2)
    assert np.all(series_rise[:, 0, 1] == 0.0)  # the unheated, locked top
    np.testing.assert_allclose(series_rise[:, 0, 0], single_rise[:, 0, 0], atol=2e-3 * single_rise.max())


def test_a_cold_bearing_reports_no_rise():
    """No heating, no temperature in the response (its reducer is then absent)."""
    response = _run(isolated_structure("rigid", isolator=paper_bearing(coulomb_friction(MU)), pressure=PRESSURE,
                                       time_step=DT)(_ground()))
    assert response.surface_temperature_rise is None


def _run_reports_the_rise(tmp_path, capsys, flags, surface, components=1):
    """`teflon-jax run` with `flags` under a decaying pulse: the peak rise of `surface` alone
    in the JSON and on the terminal, the CSV history's peak the JSON's."""
    from teflon_jax.cli import main

    t = np.arange(0, DURATION + 0.01 / 2, 0.01)
    record = tmp_path / "ground.txt"
    np.savetxt(record, np.c_[t, 0.4 * np.sin(2 * np.pi * t / 1.5) * np.exp(-0.1 * t)])
    records = ["--record-x", str(record)] + ["--record-y", str(record)] * (components == 2)
    out, histories = tmp_path / "run.json", tmp_path / "run.csv"
    code = main(["run", *records, "--record-units", "g", *flags, "--json", str(out), "--histories", str(histories)])
    assert code == 0
    rise = json.loads(out.read_text())["surface_temperature_rise_K"]
    assert set(rise) == {surface} and rise[surface] > 5.0
    assert f"surface temperature rise: {surface} {rise[surface]:.4g} K" in capsys.readouterr().out
    table = np.genfromtxt(histories, delimiter=",", names=True)
    assert table[f"temperature_rise_{surface}_K"].max() == pytest.approx(rise[surface], rel=1e-12)


@pytest.mark.parametrize("components", [1, 2])
def test_run_prints_and_writes_the_rise_of_a_heated_flat_bearing(tmp_path, capsys, components):
    """`teflon-jax run --bearing FILE` whose bearing has a heating part: the peak rise in the
    JSON and on the terminal, its history in the CSV (the JSON's peak is the history's)."""
    from teflon_jax.formats import save_bearing

    bearing = tmp_path / "hot.json"
    save_bearing(bearing, _heated())
    _run_reports_the_rise(tmp_path, capsys, ["--bearing", str(bearing)], "surface", components)


def test_run_reports_the_heated_surfaces_of_a_double_pendulum(tmp_path, capsys):
    """`teflon-jax run --isolator double-fp` with an isolator file whose bottom surface heats:
    that surface's peak rise alone (the top has no heating) in the JSON and on the terminal,
    its history in the CSV."""
    from teflon_jax.formats import write_isolator

    double = DoublePendulum(bottom_radius=RADIUS, top_radius=2.0, bottom_capacity=1.0, top_capacity=1.0,
                            bottom_friction=coulomb_friction(MU), top_friction=coulomb_friction(0.12),
                            hysteresis=_heated().hysteresis, bottom_heating=HEAT, bottom_pressure=PRESSURE)
    isolator = tmp_path / "double.json"
    write_isolator(isolator, double)
    _run_reports_the_rise(tmp_path, capsys, ["--isolator", "double-fp", "--isolator-file", str(isolator)], "bottom")
