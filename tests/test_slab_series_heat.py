"""Heated sliding surfaces on a slab of double (or triple) friction pendulums: each surface of
group g takes the flux mu p (N_g / W_g) v of its own group's normal load and its friction
falls with its own temperature (Kumar et al. 2015; Carslaw & Jaeger's semi-infinite body).

Peers: the rigid mass on one heated pendulum of the same weight (`simulate_history`,
whose heating has its own tests against the heated single pendulum and the constant-flux
closed form, tests/test_series_heating.py); the unheated slab; the sign of the overturning
(the side the ground accelerates towards unloads); a lifted group's heat only decays."""

import json
import re

import equinox as eqx
import jax
import numpy as np
import pytest
from test_slab_series import (
    CORNERS,
    DOUBLE,
    DT_RECORD,
    DURATION,
    SQUARE,
    STEP,
    TIME,
    TRIPLE,
    W,
    _isolator_file,
    _plan,
    _pulse,
    _record,
    _slab,
    simulate,
)

from teflon_jax.bearing import FrictionalHeating
from teflon_jax.cli import main
from teflon_jax.excitation import uniform_signal
from teflon_jax.systems import (
    simulate_history,
    slab_on_bearings,
    triple_structure,
)
from teflon_jax.units import STANDARD_GRAVITY as G

PRESSURE = 20e6  # [Pa] on both surfaces under the static load


def _heated(pendulum=DOUBLE, heat_scale=1.0):
    """`pendulum` with both surfaces heated (contact area 0.05 m^2, 20 MPa)."""
    heating = FrictionalHeating(contact_area=0.05, heat_scale=heat_scale)
    return eqx.tree_at(lambda p: (p.bottom_heating, p.bottom_pressure, p.top_heating, p.top_pressure), pendulum,
                       (heating, PRESSURE, heating, PRESSURE), is_leaf=lambda x: x is None)


def _biased(bias=0.08, amplitude=0.15):
    """x: a sine of `amplitude` [g] at 0.7 Hz about a mean `bias` [g], under a sin^2 envelope."""
    shape = np.sin(np.pi * TIME / DURATION) ** 2
    return G * shape * (bias + amplitude * np.sin(2 * np.pi * 0.7 * TIME)), 0 * TIME


@pytest.mark.parametrize("pendulum", [DOUBLE, pytest.param(TRIPLE, marks=pytest.mark.slow)], ids=["double", "triple"])
def test_symmetric_heated_slab_is_the_heated_rigid_mass(pendulum):
    """h = 0, equal groups at the corners, x motion: every group carries W / 4 on a pendulum
    whose contact pressures are those of W, so each surface heats as on the rigid mass of
    weight W on one such pendulum: the displacements agree to 1e-10 m while heating itself
    moves them by > 1 cm (against heat scale 0), the slab does not twist, and all
    four groups' surfaces reach the same rise."""
    ax, ay = _pulse(0.35, 0.0)
    hot = _heated(pendulum)
    rigid = jax.jit(simulate_history, static_argnums=1)
    one = triple_structure("rigid", hot, uniform_signal(ax, DT_RECORD), time_step=STEP, weight=W)
    reference = np.asarray(rigid(one, DURATION).displacement[:, 0])
    response = simulate(_slab(ax, ay, 0.0, hot), DURATION)
    assert bool(np.all(response.converged))
    assert np.max(np.abs(np.asarray(response.displacement[:, 0]) - reference)) < 1e-10
    assert np.max(np.abs(response.displacement[:, 1:])) < 1e-12
    cold = triple_structure("rigid", _heated(pendulum, heat_scale=0.0), uniform_signal(ax, DT_RECORD), time_step=STEP,
                            weight=W)  # the unheated rigid mass (tests/test_series_heating.py)
    assert np.max(np.abs(np.asarray(rigid(cold, DURATION).displacement[:, 0]) - reference)) > 0.01
    rise = np.asarray(response.surface_temperature_rise)  # (nt, G, S)
    assert rise.shape == (round(DURATION / STEP) + 1, 4, pendulum.slider_count) and rise.max() > 20.0
    assert np.max(np.abs(rise - rise[:, :1])) < 1e-9 * rise.max()


def test_a_zero_heat_scale_is_the_unheated_slab():
    """With the heat scale 0 the factor on every surface's friction is exactly 1: the slab
    is the unheated slab to rounding (two programs that XLA may round differently: the y and
    rotation under a motion along x are pure rounding), and its surfaces report no rise."""
    ax, ay = _pulse(0.35, 0.0)
    neutral = simulate(_slab(ax, ay, 0.0, _heated(heat_scale=0.0)), DURATION, throw=False)
    cold = simulate(_slab(ax, ay, 0.0, DOUBLE), DURATION, throw=False)
    assert bool(np.all(neutral.converged)) and bool(np.all(cold.converged))
    for name in ("displacement", "bearing_force", "slider", "normal_load"):
        a, b = np.asarray(getattr(neutral, name)), np.asarray(getattr(cold, name))
        assert np.max(np.abs(a - b)) <= 1e-12 * np.max(np.abs(b))
    assert cold.surface_temperature_rise is None and np.all(np.asarray(neutral.surface_temperature_rise) == 0)


@pytest.mark.slow
def test_the_more_loaded_groups_heat_more():
    """h = 4 m under x motion about a mean of +0.08 g: the mean inertia force leans the slab
    towards -x, so the west pair carries more than W / 4 on average and the east pair less.
    Every surface of the west groups heats more than the same surface of the east groups
    (equal within each pair by symmetry), and the heated run differs from the run at heat
    scale 0 (the unheated slab) by more than 1 cm."""
    ax, ay = _biased()
    response = simulate(_slab(ax, ay, 4.0, _heated()), DURATION)
    neutral = simulate(_slab(ax, ay, 4.0, _heated(heat_scale=0.0)), DURATION)
    assert bool(np.all(response.converged)) and bool(np.all(neutral.converged))
    loads = np.asarray(response.normal_load)
    assert np.all(loads > 0)
    mean = loads.mean(axis=0)  # SW, SE, NE, NW
    assert mean[0] == pytest.approx(mean[3], rel=1e-9) and mean[1] == pytest.approx(mean[2], rel=1e-9)
    assert mean[0] > 1.01 * W / 4 > 1.02 * mean[1]
    peak = np.asarray(response.surface_temperature_rise).max(axis=0)  # (G, S)
    assert np.allclose(peak[0], peak[3], rtol=1e-9) and np.allclose(peak[1], peak[2], rtol=1e-9)
    assert np.all(peak[0] > 1.02 * peak[1]) and peak.min() > 20.0
    assert np.max(np.abs(np.asarray(response.displacement[:, 0]) - np.asarray(neutral.displacement[:, 0]))) > 0.01


def test_a_lifted_group_generates_no_heat():
    """The 4 m square under h = 20 m (the slab tips while a side lifts, those steps reported):
    while a group's N_g <= 0 it carries no shear, and its surfaces' temperature only decays (no flux enters the steel), while they rise on the
    steps it carries load."""
    ax, ay = _pulse(0.5, 0.0)
    response = simulate(_slab(ax, ay, 20.0, _heated(), positions=SQUARE), DURATION, throw=False)
    assert np.array_equal(~np.asarray(response.converged), np.asarray(response.tipped))  # on two groups
    lifted = np.asarray(response.normal_load)[1:] <= 0
    change = np.diff(np.asarray(response.surface_temperature_rise), axis=0)  # (nt - 1, G, S)
    assert lifted.sum() > 20
    assert np.all(change[lifted] < 0) and change[~lifted].max() > 1.0
    assert np.all(np.asarray(response.bearing_force)[1:][lifted] == 0.0)


def test_groups_whose_surfaces_heat_differently_are_refused_by_name():
    ax, ay = _pulse(0.1, 0.1)
    with pytest.raises(ValueError, match=r"pendulums: the groups' pendulums differ in their options"):
        slab_on_bearings(length_x=20.0, length_y=12.0, weight=W, centre_of_mass=[10.0, 6.0],
                         positions=SQUARE, loads=[W / 4] * 4, ground_acceleration=uniform_signal(ax, DT_RECORD),
                         ground_y=uniform_signal(ay, DT_RECORD), time_step=STEP, isolator="double-fp",
                         pendulums=[_heated(), DOUBLE, DOUBLE, DOUBLE])


# --------------------------------------------------------------------------- command line


def _heated_file(path, **heating_changes):
    """A heated double pendulum's isolator file, with `heating_changes` in the bottom surface's
    `heating` entry."""
    _isolator_file(path, _heated())
    document = json.loads(path.read_text())
    document["surfaces"]["bottom"]["heating"].update(heating_changes)
    path.write_text(json.dumps(document))
    return path


def test_run_reports_each_groups_surface_temperature(tmp_path, capsys):
    """`run --structure slab --isolator double-fp` with a heated isolator file: each group's
    peak surface temperature rise per heated surface in the JSON and the histories (their
    peaks), printed; under +x pulses the east pair unloads first, the loads swing both ways
    and all groups heat."""
    path = _heated_file(tmp_path / "hot.json")
    out, histories = tmp_path / "run.json", tmp_path / "run.csv"
    code = main(["run", "--structure", "slab", "--plan", str(_plan(tmp_path)), "--record-x", str(_record(tmp_path)),
                 "--record-units", "g", "--isolator", "double-fp", "--isolator-file", str(path), "--json",
                 str(out), "--histories", str(histories), "--time-step", "0.005s"])
    assert code == 0
    assert "surface temperature rise SW: bottom" in capsys.readouterr().out
    payload = json.loads(out.read_text())
    rises = payload["surface_temperature_rise_K"]
    assert set(rises) == {"SW", "SE", "NE", "NW"}
    table = np.genfromtxt(histories, delimiter=",", names=True)
    for name, row in rises.items():
        assert set(row) == {"bottom", "top"} and min(row.values()) > 5.0
        for surface, value in row.items():
            assert table[f"temperature_rise_{name}_{surface}_K"].max() == pytest.approx(value, rel=1e-12)
    groups = payload["normal_load"]["groups"]
    assert all(g["min_N"] < 250e3 < g["peak_N"] for g in groups.values())


@pytest.mark.parametrize(("changes", "message"), [
    ({"heat_scal": {"value": 1, "unit": "1"}}, r"surfaces.bottom.heating: unknown \['heat_scal'\]"),
    ({"heat_scale": {"value": -1, "unit": "1"}}, "surfaces.bottom.heating.heat_scale: must be >= 0"),
])
def test_run_refuses_a_bad_heating_key_by_name(tmp_path, capsys, changes, message):
    path = _heated_file(tmp_path / "bad.json", **changes)
    for flags in (["--isolator-file", str(path)],
                  ["--isolator-file", str(_isolator_file(tmp_path / "cold.json", DOUBLE))]):
        plan = _plan(tmp_path, isolator_file="bad.json") if "cold.json" in flags[1] else _plan(tmp_path)
        code = main(["run", "--structure", "slab", "--plan", str(plan), "--record-x",
                     str(tmp_path / "missing.txt"), "--record-units", "g", "--isolator", "double-fp", *flags])
        assert code == 2
        err = capsys.readouterr().err
        assert re.search(message, err) and "missing.txt" not in err


@pytest.mark.slow
def test_the_heated_slab_is_differentiable_in_a_surface_friction():
    """d(slab displacement at 2 s)/d(f_max of the bottom surfaces) with both surfaces heated
    and h = 3 m: through every group's heat states and sliders' balance (implicit derivative),
    equal to central differences within 1e-4 relative."""
    ax, ay = _pulse(0.4, 0.2)
    base = _slab(ax, ay, 3.0, DOUBLE)

    def displacement(f_max):
        pendulum = eqx.tree_at(lambda p: p.bottom_friction.f_max, _heated(), f_max)
        system = slab_on_bearings(
            length_x=20.0, length_y=12.0, weight=W, centre_of_mass=[10.0, 6.0], positions=CORNERS,
            loads=[W / 4] * 4, ground_acceleration=base.ground_acceleration, ground_y=base.ground_y, time_step=STEP,
            isolator="double-fp", pendulums=pendulum, height_of_centre_of_mass=3.0)
        return simulate_history(system, 2.0).displacement[-1, 0]

    value, slope = jax.jit(jax.value_and_grad(displacement))(0.06)
    h = 1e-5
    forward = jax.jit(displacement)
    central = (forward(0.06 + h) - forward(0.06 - h)) / (2 * h)
    assert abs(float(value)) > 0.01
    assert abs(float(slope) - float(central)) < 1e-4 * abs(float(central))
