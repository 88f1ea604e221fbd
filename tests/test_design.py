"""Tests of gradient-based design (teflon_jax._design): gradients against central finite
differences, the BFGS optimum against a grid sweep of the same objective, and bad input."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from teflon_jax.excitation import StochasticGroundMotion, sample
from teflon_jax.studies import (
    GRADIENT_TOLERANCE,
    design_bounds,
    design_sweep,
    expected_response,
    gradient_check,
    optimise_design,
    penalised_objective,
    sweep_objective,
    sweep_start,
)
from teflon_jax.systems import isolated_structure
from teflon_jax.units import PSI

DT = 0.01


@pytest.fixture(scope="module")
def records():
    model = StochasticGroundMotion(
        peak_ground_acceleration=3.0, duration=4.0, time_step=DT, rise_time=0.5,
        strong_motion_duration=2.0,
    )
    return sample(model, jax.random.key(2), 3)


@pytest.mark.slow
def test_gradients_match_central_differences(records):
    structure = isolated_structure("rigid", time_step=DT)
    # pressure between Table 1's 1000 and 2000 psi rows (away from the interpolation's kinks)
    x = {"isolation_period": 1.7, "pressure": 1400 * PSI, "isolation_damping": 0.08,
         "delta_f": 0.05, "rate_a": 20.0}

    def statistic(x):
        r = expected_response(structure, x, records, DT, disp_width=2e-4, shear_width=2e-3)
        return r["shear"] + 10.0 * r["disp"]

    gradient, differences, error = gradient_check(statistic, x, relative_step=1e-5)
    assert error < 1e-4, (gradient, differences)
    # every variable matters (a zero gradient would pass trivially)
    assert all(abs(v) > 1e-12 for v in gradient.values())


def test_smooth_max_gradient_matches_central_differences():
    """Fast check of the gradient path of the statistics (the full chain is a slow test)."""
    from teflon_jax.systems import smooth_max

    t = jnp.linspace(0.0, 10.0, 501)

    def statistic(x):
        signal = x["amplitude"] * jnp.sin(x["frequency"] * t) * jnp.exp(-0.1 * t)
        return smooth_max(signal, 0.01)

    _, _, error = gradient_check(statistic, {"amplitude": 0.3, "frequency": 2.1})
    assert error < 1e-6


def test_unit_box_round_trip_and_exact_bounds():
    """x = lo + (hi - lo) s maps the box onto [0, 1]^n and back; s = 0 and 1 give the bounds
    themselves (a design on a bound is the bound, not a rounding of it)."""
    structure = isolated_structure("rigid")
    bounds = design_bounds(structure, {"isolation_period": (1.0, 4.0), "pressure": (1000 * PSI, 3000 * PSI)})
    x = {"isolation_period": 3.2, "pressure": 1234 * PSI}
    s = bounds.to_unit(x)
    np.testing.assert_allclose(s, [2.2 / 3.0, 234.0 / 2000.0], rtol=1e-14)
    back = bounds.from_unit(s)
    for k in x:
        assert back[k] == pytest.approx(x[k], rel=1e-14)
    assert bounds.from_unit([0.0, 1.0]) == {"isolation_period": 1.0, "pressure": 3000 * PSI}
    np.testing.assert_allclose(bounds.widths, [3.0, 2000 * PSI], rtol=1e-15)


@pytest.mark.slow
def test_optimum_beats_grid_sweep(records):
    structure = isolated_structure("rigid", time_step=DT, pressure=1000 * PSI)
    periods = np.linspace(0.8, 4.0, 9)
    # limit between the displacements at the grid's ends, so that it is active
    ends = [float(expected_response(structure, {"isolation_period": t}, records, DT)["disp"]) for t in (0.8, 4.0)]
    limit = 0.5 * (ends[0] + ends[1])
    sweep = design_sweep(structure, records, DT, grid={"isolation_period": periods}, disp_limit=limit)
    variables = {"isolation_period": (0.8, 4.0)}
    start = sweep_start(sweep, design_bounds(structure, variables))
    # the smooth problem the grid sweeps (no correction of the limit on true peaks)
    result = optimise_design(structure, records, DT, variables=variables, disp_limit=limit, start=start,
                             peak_corrections=0)
    spacing = periods[1] - periods[0]
    best = periods[int(np.argmin(sweep["objective"]))]
    # the smooth problem's optimum (its true mean peak may exceed the limit: limit_met says so)
    assert result.optimiser_converged and result.simulation_converged
    assert result.gradient_rel_error <= GRADIENT_TOLERANCE
    assert result.objective <= sweep["objective"].min()
    assert abs(result.optimum["isolation_period"] - best) <= spacing
    # the limit is active: the optimum sits at it (exterior penalty: slightly beyond)
    assert result.mean_disp == pytest.approx(limit, rel=0.05)
    # the objective is the one of the sweep: re-evaluated at the optimum it agrees
    again = expected_response(structure, result.optimum, records, DT)
    assert result.objective == pytest.approx(float(penalised_objective(again, limit, 100.0)), rel=1e-10)


def test_bad_design_input(records):
    structure = isolated_structure("rigid", time_step=DT)
    with pytest.raises(ValueError, match="pressure: outside the Table 1 rows"):
        design_bounds(structure, {"pressure": (500 * PSI, 2000 * PSI)})
    with pytest.raises(ValueError, match="pressure"):
        design_bounds(structure, {"pressure": (1000 * PSI, 7000 * PSI)})
    with pytest.raises(ValueError, match="isolation_period: bounds"):
        design_bounds(structure, {"isolation_period": (3.0, 1.0)})
    with pytest.raises(ValueError, match="unknown design variable"):
        design_bounds(structure, {"mass": (1.0, 2.0)})
    with pytest.raises(ValueError, match="disp_limit"):
        optimise_design(structure, records, DT, variables={"isolation_period": (1.0, 2.0)}, disp_limit=0.0)
    with pytest.raises(ValueError, match="start"):
        optimise_design(structure, records, DT, variables={"isolation_period": (1.0, 2.0)},
                        disp_limit=0.1, start={"isolation_period": 5.0})
    with pytest.raises(ValueError, match="pressure"):
        design_sweep(structure, records, DT, grid={"pressure": [1000 * PSI, 8000 * PSI]}, disp_limit=0.1)
    with pytest.raises(ValueError, match="records"):
        expected_response(structure, {}, np.zeros(10), DT)


@pytest.mark.slow
def test_forward_mode_gradient_equals_reverse_mode_on_a_simulation():
    """The custom-VJP wrapper gives jax.grad's answer through a structure simulation."""
    import jax
    import jax.numpy as jnp
    import numpy as np

    import teflon_jax as tj
    from teflon_jax.studies import forward_mode_gradient
    from teflon_jax.units import PSI, STANDARD_GRAVITY

    t = np.linspace(0.0, 4.0, 401)
    ground = tj.uniform_signal(0.3 * STANDARD_GRAVITY * np.sin(3.0 * t), 0.01)
    table = tj.friction_table("UF", "P")

    def peak_energy(x):
        friction, _ = table.at(x["pressure"])
        mass = 1e5
        k = mass * (2 * jnp.pi / x["period"]) ** 2
        system = tj.structure_on_sliders(
            mass=[mass], stiffness=[[k]], damping=[[0.0]], bearing=tj.paper_bearing(friction),
            bearing_load=mass * STANDARD_GRAVITY, ground_acceleration=ground, time_step=0.01,
        )
        r = tj.simulate_history(system, 4.0, throw=False)  # fixed steps: a lax.scan, either mode
        return jnp.sum(r.displacement[:, 0] ** 2)

    x = {"pressure": jnp.asarray(1500 * PSI), "period": jnp.asarray(2.0)}
    reverse = jax.grad(peak_energy)(x)
    forward = jax.grad(forward_mode_gradient(peak_energy))(x)
    for name in x:
        assert float(forward[name]) == pytest.approx(float(reverse[name]), rel=1e-9)
        assert float(forward[name]) != 0.0


@pytest.mark.slow
def test_gradient_check_at_a_table1_row_needs_one_sided_differences(records):
    """Table 1 is interpolated linearly: at a tabulated pressure the friction constants have
    a kink. A central difference straddling 2000 psi averages two slopes and cannot match the
    derivative (the cause of the 57 % error of the old default design); on a bound at that
    row the check differences inward and agrees."""
    from teflon_jax.studies import GRADIENT_TOLERANCE, design_gradient_check

    structure = isolated_structure("rigid", time_step=DT)

    def response(x):
        return expected_response(structure, x, records[:2], DT, duration=2.0)

    x = {"pressure": 2000 * PSI}
    across = design_gradient_check(structure, response, x, design_bounds(structure, {"pressure": (1000 * PSI, 3000 * PSI)}))
    assert across["rel_error"] > 0.05
    assert any("kink" in m for m in across["messages"])
    assert across["at_bounds"] == ()
    inward = design_gradient_check(structure, response, x, design_bounds(structure, {"pressure": (1000 * PSI, 2000 * PSI)}))
    assert inward["rel_error"] <= GRADIENT_TOLERANCE, inward
    assert inward["at_bounds"] == ("pressure",)
    assert any("upper bound" in m for m in inward["messages"])


@pytest.mark.slow  # three compilations (sweep, optimiser, gradient check): ~80 s on 2 busy cores
def test_failed_simulations_make_the_design_fail(records):
    # a real solver failure (one Newton iteration per step), not a patched flag
    structure = isolated_structure("rigid", time_step=DT, newton_iterations=1)
    variables = {"isolation_period": (1.0, 3.0)}
    sweep = design_sweep(structure, records, DT, grid={"isolation_period": [1.5, 2.5]}, disp_limit=0.1,
                         duration=1.5)
    assert not sweep["converged"].any() and (sweep["n_failed"] == 3).all()
    with pytest.raises(ValueError, match="no grid point converged"):
        sweep_start(sweep, design_bounds(structure, variables))
    result = optimise_design(structure, records, DT, variables=variables, disp_limit=0.1, max_steps=1,
                             duration=1.5)
    assert not result.simulation_converged and result.n_failed_motions == 3
    assert not result.converged
    assert any("3 of 3 motions" in m for m in result.messages)


@pytest.mark.slow
def test_default_design_problem_is_trustworthy():
    """The default problem of `teflon-jax design`: the optimiser, every simulation and the
    gradient check (<= 1e-4 at the optimum) succeed, and the displacement limit binds."""
    from teflon_jax.studies import GRADIENT_TOLERANCE, default_design_problem
    from teflon_jax.units import STANDARD_GRAVITY

    problem = default_design_problem("rigid")
    model = StochasticGroundMotion(
        peak_ground_acceleration=problem["pga"], site_frequency=15.6, site_damping=0.6,
        high_pass_frequency=1.56, strong_motion_duration=10.0, duration=problem["duration"],
        time_step=problem["record_time_step"],
    )
    assert problem["pga"] == pytest.approx(0.3 * STANDARD_GRAVITY)
    motions = sample(model, jax.random.key(0), problem["n_motions"])
    low = {k: v[0] for k, v in problem["variables"].items()}
    structure = isolated_structure("rigid", isolation_damping=problem["isolation_damping"],
                                   **problem["structure_options"], **low)
    grid = {k: np.linspace(a, b, 5) for k, (a, b) in problem["variables"].items()}
    sweep = design_sweep(structure, motions, problem["record_time_step"], grid=grid,
                         disp_limit=problem["disp_limit"], penalty=problem["penalty"])
    start = sweep_start(sweep, design_bounds(structure, problem["variables"]))
    result = optimise_design(structure, motions, problem["record_time_step"],
                             variables=problem["variables"], disp_limit=problem["disp_limit"],
                             penalty=problem["penalty"], start=start)
    assert result.converged, result.messages
    assert result.gradient_rel_error <= GRADIENT_TOLERANCE
    # the limit binds on the mean true peak, which meets it
    assert problem["disp_limit"] * 0.99 <= result.peak_disp <= problem["disp_limit"]
    assert result.objective <= np.nanmin(sweep_objective(sweep, result.smooth_disp_limit, problem["penalty"]))
