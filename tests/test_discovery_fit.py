"""Discovery's fits: on data its own candidate model made without noise they return the
constants that made it (to the solver's tolerance), from the starts discovery chooses; the
log-bounded bijection and both Levenberg-Marquardt dampings of the least-squares layer they
run on recover a closed-form model to rounding.
"""

import numpy as np
import pytest
from test_discovery import HIDDEN, UF_1000_P, generate_record

from identification.discovery import (
    active_mask,
    default_parameters,
    discover_effects,
    prepare_record,
    simulate_augmented,
)
from teflon_jax.formats import test_record_from_arrays
from teflon_jax.units import INCH

EFFECTS = ("velocity_dependence", "asymmetry", "wear")
TRUTH = {**UF_1000_P, "yield_disp": 0.004 * INCH, "asymmetry": 0.08, "wear_change": -0.25}


def _own_record():
    """A record whose force is discovery's candidate model (`simulate_augmented`) at `TRUTH`."""
    path = generate_record(noise=0.0, cycles=2, samples_per_cycle=400, **HIDDEN["asymmetry"])
    data, _ = prepare_record(path)
    params = {**default_parameters(), **TRUTH}
    force = np.asarray(simulate_augmented(params, data, active_mask(EFFECTS))["force"])
    return test_record_from_arrays(path.ux, force, time=path.time,
                                   normal_load=path.normal_load,
                                   metadata={"contact_area": path.metadata["contact_area"]})


def test_fit_of_its_own_noise_free_model_returns_the_constants():
    result = discover_effects(_own_record(), baseline=EFFECTS, max_effects=0)
    assert result.fit_convergence["final_converged"], result.fit_convergence
    assert result.nrmse_final < 1e-7
    for name, value in TRUTH.items():
        assert result.parameters[name] == pytest.approx(value, rel=1e-5), name


def test_log_bounded_bijection_is_a_sigmoid_in_log_x():
    """x = exp(log lo + (log hi - log lo) sigmoid(u)): u = 0 is the geometric mean, the inverse
    returns u, and x stays strictly inside (lo, hi)."""
    from identification.least_squares._transform import (
        _make_transform,
        _to_physical,
        _to_unconstrained,
    )

    lo, hi = 1e-3, 1e3
    x0 = np.array([[1.0], [0.02], [500.0]])
    tr = _make_transform(("a",), np.array([lo]), np.array([hi]), x0, log_scale=("a",))
    u = _to_unconstrained(x0, tr.kinds, tr.lower, tr.upper, tr.scale, tr.origin)
    assert u[0, 0] == pytest.approx(0.0, abs=1e-12)
    x = np.asarray(_to_physical(u, tr.kinds, tr.lower, tr.upper, tr.scale, tr.origin))
    np.testing.assert_allclose(x, x0, rtol=1e-12)
    far = np.asarray(_to_physical(np.array([[-50.0], [50.0]]), tr.kinds, tr.lower[:2],
                                  tr.upper[:2], tr.scale[:2], tr.origin[:2]))
    assert lo < far[0, 0] < 1.001 * lo and 0.999 * hi < far[1, 0] < hi


@pytest.mark.parametrize("solver", ["levenberg_marquardt", "levenberg_marquardt_scaled"])
def test_least_squares_recovers_a_log_scaled_rate_to_rounding(solver):
    """y = c exp(-k t) from noise-free samples, k searched in log space over six decades."""
    import jax.numpy as jnp

    from identification.least_squares import fit_least_squares

    t = np.linspace(0.0, 2.0, 50)

    def residual(p, data):
        return p["c"] * jnp.exp(-p["k"] * data) - 3.0 * np.exp(-7.0 * t)

    fit = fit_least_squares(residual, {"c": 1.0, "k": 0.5}, {"c": (0.0, 10.0), "k": (1e-3, 1e3)},
                            args=jnp.asarray(t), log_scale=("k",), solver=solver,
                            converged_on="residuals", rtol=1e-12, atol=1e-12)
    assert fit.converged, fit.message
    assert fit.parameters["k"] == pytest.approx(7.0, rel=1e-9)
    assert fit.parameters["c"] == pytest.approx(3.0, rel=1e-9)
