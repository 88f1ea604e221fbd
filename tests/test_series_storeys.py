"""Storey results of the Table 2 building on triple friction pendulums under two horizontal
components (`peak_response(storey_height=...)`, `monte_carlo(...,
storey_height=...)`, `montecarlo --components 2 --storeys`): each storey's peak drift ratio
and each level's peak total acceleration in x and in y.

Peers: the saved histories of the same runs (`planar_histories`: drifts and total
accelerations taken with NumPy); the one-component building on the same pendulums
(`peak_response`), which a motion along x alone must reproduce, with nothing in y.
"""

import json

import jax
import numpy as np
import pytest
import xarray
from histories import planar_histories

from teflon_jax.cli import main
from teflon_jax.excitation import (
    StochasticGroundMotion,
    TwoComponentGroundMotion,
    uniform_signal,
)
from teflon_jax.formats import isolator_from_dict
from teflon_jax.studies import (
    bidirectional_isolated_structure,
    monte_carlo,
    monte_carlo_motion,
)
from teflon_jax.systems import (
    TRIPLE_MONTE_CARLO_TOLERANCE,
    isolated_structure,
    peak_response,
)
from teflon_jax.tables import load_table2

HEIGHT = load_table2().storey_height


def _document():
    def surface(radius, capacity, f_max, delta_f):
        friction = {"f_max": {"value": f_max, "unit": "1"}, "delta_f": {"value": delta_f, "unit": "1"},
                    "rate_a": {"value": 0.5, "unit": "s/in"}}
        return {"radius": {"value": radius, "unit": "in"}, "capacity": {"value": capacity, "unit": "in"},
                "friction": friction}

    return {"format": "teflon-jax isolator", "format_version": 1, "isolator": "triple-fp",
            "surfaces": {"inner": surface(12, 2, 0.02, 0.01), "bottom": surface(84, 12, 0.06, 0.02),
                         "top": surface(84, 14, 0.10, 0.03)},
            "yield_disp": {"value": 0.004, "unit": "in"}}


def _building(components=1):
    build = isolated_structure if components == 1 else bidirectional_isolated_structure
    return build("building", isolator=isolator_from_dict(_document()), time_step=0.005,
                 newton_tolerance=TRIPLE_MONTE_CARLO_TOLERANCE)


def _history_peaks(system, duration):
    """(drift ratios (2, 6), total accelerations (2, 7)) peaks of the saved histories."""
    _, x, _, _, acc, ok = jax.jit(planar_histories, static_argnums=1)(system, duration)
    assert bool(np.all(ok))
    u = np.asarray(x)[:, :, :7]  # (nt, x|y, base slab and floors)
    return np.abs(np.diff(u, axis=2)).max(axis=0) / HEIGHT, np.abs(np.asarray(acc)).max(axis=0)


def test_a_motion_along_x_alone_gives_the_one_component_storey_peaks():
    """The second component zero: the x storey peaks are the one-component building's, the y
    ones exactly zero; the base peaks agree too (the planar and the scalar balance are solved
    to the same tolerance)."""
    t = 0.01 * np.arange(151)
    ax = 3.0 * np.sin(2 * np.pi * t) * np.sin(np.pi * t / t[-1]) ** 2
    two = peak_response(_building(2)((uniform_signal(ax, 0.01), uniform_signal(0 * ax, 0.01))), 1.5,
                        storey_height=HEIGHT)
    one = jax.jit(lambda s: peak_response(s, 1.5, storey_height=HEIGHT))(_building()(uniform_signal(ax, 0.01)))
    assert two.storey_drift.shape == (2, 6) and two.floor_acceleration.shape == (2, 7)
    np.testing.assert_allclose(two.storey_drift[0], one.storey_drift, rtol=1e-8)
    np.testing.assert_allclose(two.floor_acceleration[0], one.floor_acceleration, rtol=1e-8)
    assert np.all(np.asarray(two.storey_drift[1]) == 0) and np.all(np.asarray(two.floor_acceleration[1]) == 0)
    assert float(two.base_disp) == pytest.approx(float(one.base_disp), rel=1e-8)
    assert bool(two.converged) and bool(one.converged) and float(one.storey_drift[0]) > 1e-4


@pytest.mark.slow  # four compiled programs of the building, about 1.5 min on two shared cores
def test_monte_carlo_storey_peaks_are_those_of_each_motion_history():
    """`monte_carlo(..., storey_height=...)` on the triple pendulum building: every motion's
    storey peaks in x and y are those of its saved histories (1e-8); with the minor component
    zero and the major along x, those of the one-component Monte Carlo of the same motions."""
    one = StochasticGroundMotion(peak_ground_acceleration=4.0, duration=2.0, time_step=0.01, rise_time=0.5,
                                 strong_motion_duration=1.0)
    structure, key = _building(2), jax.random.key(3)
    model = TwoComponentGroundMotion(one, principal_angle=0.4, minor_ratio=0.7)
    result = monte_carlo(structure, model, 2, key=key, storey_height=HEIGHT)
    assert result.storey_drift.shape == (2, 2, 6) and result.floor_acceleration.shape == (2, 2, 7)
    for i in range(2):
        values = np.asarray(monte_carlo_motion(model, key, i))
        drift, acc = _history_peaks(structure((uniform_signal(values[0], 0.01), uniform_signal(values[1], 0.01))), 2.0)
        np.testing.assert_allclose(result.storey_drift[i], drift, rtol=1e-8)
        np.testing.assert_allclose(result.floor_acceleration[i], acc, rtol=1e-8)
    along_x = monte_carlo(structure, TwoComponentGroundMotion(one, principal_angle=0.0, minor_ratio=0.0), 2, key=key,
                          storey_height=HEIGHT)
    uniaxial = monte_carlo(_building(), one, 2, key=key, storey_height=HEIGHT)
    np.testing.assert_allclose(along_x.storey_drift[:, 0], uniaxial.storey_drift, rtol=1e-8)
    np.testing.assert_allclose(along_x.floor_acceleration[:, 0], uniaxial.floor_acceleration, rtol=1e-8)
    assert np.all(along_x.storey_drift[:, 1] == 0) and np.all(along_x.floor_acceleration[:, 1] == 0)


@pytest.mark.slow  # a compiled two-component building, about 25 s on two shared cores
def test_montecarlo_storeys_under_two_components_on_a_triple_pendulum(tmp_path, capsys):
    """`montecarlo --components 2 --structure building --storeys --isolator triple-fp`: the
    summary's largest drift per storey and direction is that of the results file."""
    (tmp_path / "tfp.json").write_text(json.dumps(_document()))
    code = main(["montecarlo", "--motions", "2", "--duration", "4s", "--strong-motion", "2s", "--components", "2",
                 "--structure", "building", "--storeys", "--isolator", "triple-fp", "--isolator-file",
                 str(tmp_path / "tfp.json"), "--json", str(tmp_path / "mc.json"), "--out", str(tmp_path / "mc.nc"),
                 "--no-progress"])
    capsys.readouterr()
    assert code == 0
    storeys = json.loads((tmp_path / "mc.json").read_text())["levels"][0]["storeys"]
    with xarray.open_dataset(tmp_path / "mc.nc") as dataset:
        drift = dataset["storey_drift"].values
        assert dataset["storey_drift"].dims == ("motion", "direction", "storey")
    np.testing.assert_allclose(storeys["storey_drift_max"], drift.max(axis=0), rtol=1e-12)
    assert np.shape(storeys["level_acceleration_g_max"]) == (2, 7)
