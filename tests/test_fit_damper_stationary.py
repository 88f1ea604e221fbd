"""`fit` on a real friction-damper test reaches the least-squares minimum of its model.

The banded rotary friction damper (ARTS Laboratory) has backlash and a friction that differs
between the two directions, which Eq. 1 with Bouc-Wen lacks: the misfit stays (nrmse about
0.2), and a fit must still end at the minimum of that misfit, within its step budget, with
and without the parts `diagnose` adds.
"""

import numpy as np
import pytest

import identification.bearing_fit._fit as bearing_fit_module
from identification.bearing_fit import fit_bearing_test
from identification.discovery import discover_effects
from identification.least_squares._marquardt import RELATIVE_OFFSET
from teflon_jax.formats import read_friction_damper_json, test_record_from_arrays
from teflon_jax.units import KIP

DAMPER = "friction_damper_brfd_arts_lab/1Hz30lbtension1amplitude.json"
NORMAL_LOAD = 25 * KIP
"""The load the tutorials give the damper (force / N near 0.1)."""

MAX_STEPS = 200
"""The step budget of every least-squares solve of `fit` (`fit_bearing_test`, discovery)."""


def _bates_watts(jac, r):
    """Bates & Watts' relative offset of r on the columns of J (QR)."""
    n, p = jac.shape
    q, _ = np.linalg.qr(jac, mode="complete")
    return np.linalg.norm(q[:, :p].T @ r) / np.sqrt(p) / (np.linalg.norm(q[:, p:].T @ r) / np.sqrt(n - p))


@pytest.fixture(scope="module")
def damper(external_data):
    measured = read_friction_damper_json(external_data / DAMPER)
    return test_record_from_arrays(measured.ux, measured.fx, time=measured.time,
                                   normal_load=np.full(measured.ux.shape, NORMAL_LOAD))


@pytest.mark.external
@pytest.mark.slow
def test_every_start_of_the_damper_fit_ends_at_a_stationary_point(damper, monkeypatch):
    solves = []

    def recorded(*args, **kwargs):
        results = original(*args, **kwargs)
        solves.append((kwargs.get("bounds", args[2]), results))
        return results

    original = bearing_fit_module.fit_least_squares_batch
    monkeypatch.setattr(bearing_fit_module, "fit_least_squares_batch", recorded)
    fit = fit_bearing_test(damper)
    assert fit.converged and fit.n_steps < MAX_STEPS
    # the full law and the reduced one: every start converged within the budget
    assert len(solves) >= 1
    for bounds, results in solves:
        for raw in results:
            assert raw.converged and raw.n_steps < MAX_STEPS, raw.message
        # Stationary: the constants inside their bounds are at a minimum, to RELATIVE_OFFSET
        # standard errors (Bates & Watts); those on a bound are there to a part in 1e3.
        best = min(results, key=lambda raw: raw.cost)
        inside = []
        for name in best.names:
            lo, hi = bounds[name]
            x = best.parameters[name]
            near = [abs(x - b) <= 1e-3 * max(abs(b), 1e-12) for b in (lo, hi) if np.isfinite(b)]
            inside.append(not any(near))
        assert _bates_watts(best.jacobian[:, inside], best.residual) < RELATIVE_OFFSET
        # every start ends at the same cost
        costs = np.array([raw.cost for raw in results])
        assert np.ptp(costs) < 1e-6 * costs.min()
    if fit.full_model is not None:
        assert fit.full_model["converged"] is True
    # The misfit the symmetric model leaves: about a fifth of the RMS force.
    assert 0.2 < fit.nrmse < 0.3


@pytest.mark.external
@pytest.mark.slow
def test_the_damper_fit_with_backlash_and_asymmetry_ends_converged(damper):
    result = discover_effects(damper, baseline=("velocity_dependence", "backlash", "asymmetry"),
                              max_effects=0, max_steps=MAX_STEPS)
    log = result.fit_convergence
    assert log["final_converged"] and log["unconverged"] == 0
    assert log["max_iterations_used"] < MAX_STEPS
    # backlash and asymmetry take away a part of the misfit, not all of it
    assert 0.1 < result.nrmse_final < 0.25
    assert result.parameters["asymmetry"] > 0.05
