"""Tests of the building's storey results (teflon_jax.systems.peak_response with storey_height).

Reference: the full response histories of `simulate_history` (drifts and total floor
accelerations taken with NumPy from the saved displacements and accelerations).
"""

import jax
import numpy as np
import pytest

from teflon_jax import simulate_history, uniform_signal
from teflon_jax.excitation import StochasticGroundMotion, sample
from teflon_jax.systems import isolated_structure, peak_response
from teflon_jax.tables import load_table2
from teflon_jax.units import PSI


def _building(seed=3):
    model = StochasticGroundMotion(peak_ground_acceleration=3.0, duration=3.0, time_step=0.01,
                                   rise_time=0.5, strong_motion_duration=1.5)
    record = sample(model, jax.random.key(seed), 1)[0]
    structure = isolated_structure("building", time_step=0.005, pressure=2000 * PSI, isolation_period=1.5)
    return structure(uniform_signal(record, 0.01))


@pytest.mark.slow
def test_storey_peaks_match_the_full_history():
    """Peak |u_j - u_(j-1)| / h and peak |a_j + a_g| per floor equal those of the saved history;
    the base peaks equal `peak_response`'s."""
    system = _building()
    height = load_table2().storey_height
    peaks = peak_response(system, 3.0, storey_height=height)
    history = simulate_history(system, 3.0)
    u = np.asarray(history.displacement)
    drift = np.abs(np.diff(u, axis=1)).max(axis=0) / height
    floor_acc = np.abs(np.asarray(history.total_acceleration)).max(axis=0)  # base slab first
    assert peaks.storey_drift.shape == (6,) and peaks.floor_acceleration.shape == (7,)
    np.testing.assert_allclose(peaks.storey_drift, drift, rtol=1e-8)
    np.testing.assert_allclose(peaks.floor_acceleration, floor_acc, rtol=1e-8)
    base = peak_response(system, 3.0)
    assert base.storey_drift is None and base.floor_acceleration is None
    np.testing.assert_allclose(peaks.base_disp, base.base_disp, rtol=1e-12)
    np.testing.assert_allclose(peaks.base_shear_ratio, base.base_shear_ratio, rtol=1e-12)
    assert bool(peaks.converged)
    # read every 4th step: the same as the history's samples 0, 4, 8, ...
    sparse = peak_response(system, 3.0, storey_height=height, read_every=4, steps_per_pass=2)
    np.testing.assert_allclose(sparse.storey_drift, np.abs(np.diff(u[::4], axis=1)).max(axis=0) / height,
                               rtol=1e-8)


def test_storey_heights_divide_the_drift():
    system = _building()
    one = peak_response(system, 1.0, storey_height=1.0)
    heights = np.arange(1.0, 7.0)
    each = peak_response(system, 1.0, storey_height=heights)
    np.testing.assert_allclose(each.storey_drift, one.storey_drift / heights, rtol=1e-14)


def test_rigid_mass_and_bad_heights_are_refused():
    rigid = isolated_structure("rigid", time_step=0.005)(uniform_signal(np.zeros(101), 0.01))
    with pytest.raises(ValueError, match="^system: storey results need a building"):
        peak_response(rigid, 1.0, storey_height=3.0)
    with pytest.raises(ValueError, match="^storey_height: must be > 0"):
        peak_response(_building(), 1.0, storey_height=0.0)


@pytest.mark.slow
def test_monte_carlo_keeps_storey_peaks_and_writes_them(tmp_path):
    """Each motion's storey peaks equal `peak_response`'s on the same motion, and the
    NetCDF file holds them on a "floor" dimension that reads back."""
    from teflon_jax.studies import MonteCarloResult, monte_carlo, monte_carlo_motion

    model = StochasticGroundMotion(peak_ground_acceleration=3.0, duration=2.0, time_step=0.01,
                                   rise_time=0.5, strong_motion_duration=1.0)
    structure = isolated_structure("building", time_step=0.005, pressure=2000 * PSI, isolation_period=1.5)
    height = load_table2().storey_height
    key = jax.random.key(5)
    result = monte_carlo(structure, model, 2, key=key, storey_height=height)
    assert result.storey_drift.shape == (2, 6) and result.floor_acceleration.shape == (2, 7)
    system = structure(uniform_signal(monte_carlo_motion(model, key, 1), 0.01))
    one = peak_response(system, 2.0, storey_height=height)
    np.testing.assert_allclose(result.storey_drift[1], one.storey_drift, rtol=1e-9)
    np.testing.assert_allclose(result.floor_acceleration[1], one.floor_acceleration, rtol=1e-9)
    path = result.save(tmp_path / "mc.nc")
    back = MonteCarloResult.open(path)
    np.testing.assert_array_equal(back.storey_drift, result.storey_drift)
    assert back.to_dataset()["floor_acceleration"].dims == ("motion", "level")
    header = result.save(tmp_path / "mc.csv").read_text().splitlines()[0].split(",")
    assert "storey_drift_6" in header and "floor_acceleration_0_m_s2" in header
    with pytest.raises(ValueError, match="^system: storey results need a building"):
        monte_carlo(isolated_structure("rigid"), model, 2, key=key, storey_height=height)


@pytest.mark.slow
def test_run_building_reports_storey_results_per_direction(tmp_path, capsys):
    """`run --structure building`: drift ratios per storey and accelerations per level in x, y
    and as resultants; the resultant drift ratio is the resultant drift over the storey height,
    each direction's peak at most the resultant's, x alone under an x-only record."""
    from teflon_jax.cli import main

    t = 0.01 * np.arange(301)
    a = 0.3 * np.sin(2 * np.pi * t) * np.sin(np.pi * t / t[-1]) ** 2
    (tmp_path / "x.txt").write_text("time acc\n" + "\n".join(f"{ti:.4f} {ai:.6e}" for ti, ai in zip(t, a)))
    code = main(["run", "--structure", "building", "--record-x", str(tmp_path / "x.txt"), "--record-units", "g",
                 "--isolation-period", "2.5s", "--json", str(tmp_path / "out.json")])
    assert code == 0
    import json

    peak = json.loads((tmp_path / "out.json").read_text())["peak"]
    height = load_table2().storey_height
    np.testing.assert_allclose(peak["storey_drift_ratio_resultant"], np.array(peak["storey_drift_resultant_m"]) / height,
                               rtol=1e-12)
    np.testing.assert_allclose(peak["level_acceleration_g_resultant"][1:], peak["floor_acceleration_resultant_g"],
                               rtol=1e-12)
    assert len(peak["storey_drift_ratio_x"]) == 6 and len(peak["level_acceleration_g_y"]) == 7
    np.testing.assert_allclose(peak["storey_drift_ratio_x"], peak["storey_drift_ratio_resultant"], rtol=1e-12)
    assert max(peak["storey_drift_ratio_y"]) == 0.0


@pytest.mark.slow
def test_two_component_storey_peaks_match_the_histories():
    """`peak_response(storey_height=...)` in x and y equals the peaks of
    `simulate_history`'s saved histories (`bidirectional_storey_peaks`)."""
    from teflon_jax.excitation import TwoComponentGroundMotion
    from teflon_jax.studies import bidirectional_isolated_structure, monte_carlo_motion
    from teflon_jax.systems import (
        bidirectional_storey_peaks,
        peak_response,
        simulate_history,
    )

    model = TwoComponentGroundMotion(StochasticGroundMotion(peak_ground_acceleration=3.0, duration=2.0, time_step=0.01,
                                                            rise_time=0.5, strong_motion_duration=1.0), minor_ratio=0.7)
    values = np.asarray(monte_carlo_motion(model, jax.random.key(2), 0))
    structure = bidirectional_isolated_structure("building", pressure=2000 * PSI, isolation_period=1.5)
    system = structure((uniform_signal(values[0], 0.01), uniform_signal(values[1], 0.01)))
    height = load_table2().storey_height
    peaks = peak_response(system, 2.0, storey_height=height)
    history = bidirectional_storey_peaks(simulate_history(system, 2.0), system, height)
    assert peaks.storey_drift.shape == (2, 6) and peaks.floor_acceleration.shape == (2, 7)
    np.testing.assert_allclose(peaks.storey_drift, history["storey_drift"], rtol=1e-6)
    np.testing.assert_allclose(peaks.floor_acceleration, history["level_acceleration"], rtol=1e-6)
    assert np.all(peaks.storey_drift[1] > 0)
