"""Digitised loops: (u, F) points without time, plus the protocol, fitted like time histories."""

import numpy as np
import pytest

import teflon_jax as tj
from identification import fit_bearing_test, point_branches
from teflon_jax.formats import (
    Protocol,
    read_test_record,
    test_record_from_arrays,
    write_test_record,
)
from teflon_jax.units import INCH, KIP

Y_PAPER = 0.005 * INCH
NORMAL_LOAD = 78.5 * KIP
AMPLITUDE, FREQUENCY, CYCLES = 4 * INCH, 0.6, 3


def _time_history(row, seed):
    """Test No. 75 protocol (sine 4 in, 0.6 Hz, 3 cycles), 2 kHz, 1 % force noise."""
    bearing = tj.paper_bearing(tj.FrictionParameters(row.f_max, row.delta_f, row.rate_a),
                               yield_disp=Y_PAPER)
    motion = tj.SineMotion(amplitude=AMPLITUDE, frequency=FREQUENCY, cycles=CYCLES)
    result = tj.imposed_path_test(bearing, motion, NORMAL_LOAD, samples_per_cycle=3000)
    force = np.asarray(result.fx)
    rng = np.random.default_rng(seed)
    force = force + 0.01 * np.sqrt(np.mean(force**2)) * rng.standard_normal(force.size)
    return np.asarray(result.time), np.asarray(result.ux), force


def _digitise(time, ux, force, points_per_branch, seed):
    """Points of the last cycle, evenly spaced in phase, as one would click along a figure,
    with a reading error of 0.5 % of the peak force and 0.05 % of the amplitude."""
    period = 1.0 / FREQUENCY
    start = time[-1] - 1.75 * period  # from the +x extreme of the 2nd cycle, once round
    picks = start + np.linspace(0.0, period, 2 * points_per_branch, endpoint=False)
    u = np.interp(picks, time, ux)
    f = np.interp(picks, time, force)
    rng = np.random.default_rng(seed)
    u = u + 0.0005 * AMPLITUDE * rng.standard_normal(u.size)
    u = np.clip(u, -AMPLITUDE, AMPLITUDE)
    f = f + 0.005 * np.abs(force).max() * rng.standard_normal(f.size)
    return u, f


def test_point_branches_follow_the_order_of_reading():
    u = np.array([1.0, 0.5, 0.0, -0.5, -1.0, -0.5, 0.0, 0.5, 1.0])
    np.testing.assert_array_equal(point_branches(u), [-1, -1, -1, -1, 1, 1, 1, 1, 1])


@pytest.mark.parametrize("index", [0, 9])
def test_digitised_loop_gives_the_time_history_parameters(index, tmp_path):
    row = tj.load_table1()[index]
    time, ux, force = _time_history(row, seed=index)
    reference = fit_bearing_test(
        test_record_from_arrays(ux, force, time=time, normal_load=NORMAL_LOAD),
        free=["f_max", "delta_f", "rate_a"], fixed={"yield_disp": Y_PAPER}, n_starts=2)
    u, f = _digitise(time, ux, force, points_per_branch=60, seed=index)
    protocol = Protocol("sine", amplitude=AMPLITUDE, frequency=FREQUENCY, cycles=CYCLES)
    record = test_record_from_arrays(u, f, normal_load=NORMAL_LOAD,
                                     metadata={"protocol": protocol})
    path = tmp_path / "digitised.csv"
    write_test_record(path, record, units={"length": "in", "force": "kip"})
    record = read_test_record(path)
    assert record.is_digitised
    fit = fit_bearing_test(record, n_starts=3)
    assert fit.converged, fit.message
    # A few dozen points per branch do not resolve Y = 0.005 in: held at the paper value.
    assert "yield_disp" not in fit.free and "breakaway_ratio" not in fit.free
    assert any(w.startswith("yield_disp") for w in fit.warnings)
    truth = dict(f_max=row.f_max, delta_f=row.delta_f, rate_a=row.rate_a)
    for name, tol in (("f_max", 0.02), ("delta_f", 0.02), ("rate_a", 0.10)):
        assert fit.parameters[name] == pytest.approx(reference.parameters[name], rel=tol), name
        assert fit.parameters[name] == pytest.approx(truth[name], rel=tol), name


def test_digitised_point_outside_protocol_is_rejected():
    protocol = Protocol("sine", amplitude=0.01, frequency=0.5, cycles=3)
    u = np.linspace(-0.01, 0.02, 20)
    record = test_record_from_arrays(u, np.ones(20), normal_load=1e4,
                                     metadata={"protocol": protocol})
    with pytest.raises(ValueError, match="outside the protocol amplitude"):
        fit_bearing_test(record)
