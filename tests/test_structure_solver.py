"""RiccatiNewmark on structures: convergence order, energy balance, Coulomb limits, vmap."""

import dataclasses
import itertools

import diffrax
import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest

import teflon_jax as tj
from teflon_jax.units import PSI, STANDARD_GRAVITY

FRICTION, _ = tj.interface_parameters("UF", 1000 * PSI, "P")
WEIGHT = 1.0e6
MASS = WEIGHT / STANDARD_GRAVITY


def sine_ground(amplitude_g=0.3, omega=3.14, duration=6.0):
    t = np.linspace(0.0, duration, 6001)
    return tj.Signal(jnp.asarray(t), jnp.asarray(amplitude_g * STANDARD_GRAVITY * np.sin(omega * t)))


def rigid_mass(dt, ground, model="hysteretic", bearing=None, period=2.0, damping_ratio=0.05):
    k = MASS * (2 * np.pi / period) ** 2
    c = 2 * damping_ratio * np.sqrt(k * MASS)
    return tj.structure_on_sliders(
        mass=[MASS], stiffness=[[k]], damping=[[c]],
        bearing=tj.paper_bearing(FRICTION) if bearing is None else bearing,
        bearing_load=WEIGHT, ground_acceleration=ground, time_step=dt, friction_model=model,
    )


@pytest.mark.slow
def test_newmark_with_exact_z_converges_at_second_order():
    ground = sine_ground()
    reference = tj.simulate_history(rigid_mass(1e-3, ground), 6.0, solver=diffrax.Tsit5(),
                                      rtol=1e-9, atol=1e-11)
    u_ref = float(reference.displacement[-1, 0])
    errors = []
    for dt in (0.01, 0.005, 0.0025):
        response = tj.simulate_history(rigid_mass(dt, ground), 6.0)
        errors.append(abs(float(response.displacement[-1, 0]) - u_ref))
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(orders > 1.6), (errors, orders)


def reversing_ground(duration=3.0):
    """A record at 0.01 s (linear between samples) whose two tones make the sliding velocity
    reverse many times: 0.4 g sin(pi t / T) (sin(2 pi 1.3 t) + 0.7 sin(2 pi 3.1 t + 1))."""
    t = np.arange(0.0, duration + 1e-9, 0.01)
    envelope = 0.4 * STANDARD_GRAVITY * np.sin(np.pi * t / duration)
    return tj.uniform_signal(envelope * (np.sin(2 * np.pi * 1.3 * t) + 0.7 * np.sin(2 * np.pi * 3.1 * t + 1.0)), 0.01)


@pytest.mark.slow
def test_turning_point_update_converges_at_second_order_through_reversals():
    """Z updated along Newmark's path to the turning point and back (split_at_turn): through a
    record with many velocity reversals the displacement history converges at second order
    (slope of the RMS error against adaptive Tsit5 at rtol 1e-8 over steps 10 to 1.25 ms,
    all divisors of the record step), and with less than half the error of the update along
    the net increment at every step."""
    duration = 3.0
    ground = reversing_ground(duration)

    def system(dt, split=True):
        return dataclasses.replace(rigid_mass(dt, ground), split_at_turn=split)

    reference = tj.simulate_history(system(0.01), duration, solver=diffrax.Tsit5(), rtol=1e-8, atol=1e-10)
    u_ref = np.asarray(reference.displacement[:, 0])
    v_ref = np.asarray(reference.velocity[:, 0])
    sliding = v_ref[np.abs(v_ref) > 1e-3]
    assert np.count_nonzero(np.diff(np.sign(sliding))) >= 8  # the record really reverses the slider
    steps = np.array([0.01, 0.005, 0.0025, 0.00125])
    errors = {}
    for split in (True, False):
        rms = []
        for k, dt in enumerate(steps):
            response = tj.simulate_history(system(dt, split), duration, save_every=2**k)
            rms.append(np.sqrt(np.mean((np.asarray(response.displacement[:, 0]) - u_ref) ** 2)))
        errors[split] = np.array(rms)
    order = np.polyfit(np.log(steps), np.log(errors[True]), 1)[0]
    assert order > 1.7, (errors[True], order)
    assert np.all(errors[True] < 0.5 * errors[False]), errors


def test_energy_balance_rigid_mass():
    ground = sine_ground()
    system = rigid_mass(0.002, ground)
    r = tj.simulate_history(system, 6.0)
    v = np.asarray(r.velocity[:, 0])
    u = np.asarray(r.displacement[:, 0])
    t = np.asarray(r.time)
    k, c = float(system.stiffness[0, 0]), float(system.damping[0, 0])
    input_energy = -np.trapezoid(MASS * np.asarray(r.ground[:, 0]) * v, t)
    kinetic = 0.5 * MASS * v[-1] ** 2
    strain = 0.5 * k * u[-1] ** 2
    viscous = np.trapezoid(c * v**2, t)
    friction = np.trapezoid(np.asarray(r.friction_force) * v, t)
    assert friction > 0.3 * input_energy  # the bearing really works
    assert kinetic + strain + viscous + friction == pytest.approx(input_energy, rel=1e-3)


def test_coulomb_sliding_acceleration_closed_form():
    """A constant ground acceleration above mu g: the mass slides with total acceleration mu g."""
    mu = 0.08
    t = np.array([0.0, 10.0])
    ground = tj.Signal(jnp.asarray(t), jnp.asarray([0.3 * STANDARD_GRAVITY] * 2))
    system = rigid_mass(0.01, ground, model="coulomb", bearing=tj.paper_bearing(tj.coulomb_friction(mu)),
                        period=1e9, damping_ratio=0.0)
    r = tj.simulate_history(system, 2.0)
    total = np.asarray(r.total_acceleration[5:, 0])
    np.testing.assert_allclose(total, mu * STANDARD_GRAVITY, rtol=1e-9)  # friction pulls it along
    # relative motion with constant acceleration -(a_g - mu g) once sliding
    t1, t2 = float(r.time[50]), float(r.time[-1])
    u1, v1, u2 = float(r.displacement[50, 0]), float(r.velocity[50, 0]), float(r.displacement[-1, 0])
    expected = u1 + v1 * (t2 - t1) - (0.3 - mu) * STANDARD_GRAVITY * (t2 - t1) ** 2 / 2
    assert u2 == pytest.approx(expected, rel=1e-9)


def test_coulomb_sticks_below_capacity():
    mu = 0.1
    ground = sine_ground(amplitude_g=0.05)
    system = rigid_mass(0.01, ground, model="coulomb", bearing=tj.paper_bearing(tj.coulomb_friction(mu)),
                        period=1e9, damping_ratio=0.0)
    r = tj.simulate_history(system, 6.0)
    assert float(jnp.max(jnp.abs(r.displacement))) < 1e-12
    assert float(jnp.max(jnp.abs(r.z))) < 0.51


@pytest.mark.slow
def test_vmap_over_pressures_equals_separate_runs():
    ground = sine_ground()
    table = tj.friction_table("UF", "P")

    def peak(pressure):
        bearing = tj.paper_bearing(table.at(pressure)[0])
        r = tj.simulate_history(rigid_mass(0.01, ground, bearing=bearing), 6.0, throw=False)
        return jnp.max(jnp.abs(r.displacement[:, 0]))

    pressures = jnp.array([1000.0, 2000.0, 3000.0]) * PSI
    batched = jax.jit(jax.vmap(peak))(pressures)
    single = [float(jax.jit(peak)(p)) for p in pressures[::2]]
    np.testing.assert_allclose(np.asarray(batched[::2]), single, rtol=1e-12)
    assert batched[0] < batched[1] < batched[2]  # higher pressure, lower friction, more sliding


def test_solver_failure_is_reported_not_hidden():
    """A wrong step size for the prefactored Newmark matrix is an error, not a silent result."""
    ground = sine_ground()
    system = rigid_mass(0.01, ground)
    with pytest.raises(Exception, match="time_step"):
        diffrax.diffeqsolve(
            diffrax.ODETerm(system), tj.RiccatiNewmark(), 0.0, 1.0, 0.02, tj.initial_state(system)
        )


# Every value of each of the four options, and every pair of values of any two, is in the six
# fast cases (each case compiles two programs, about 5 s); the other 18 of the product run
# with the slow tests.
_SLOPE_FAST = {(None, None, True, "newmark"), (None, 1.6, False, "exact"),
               ("pendulum", None, False, "exact"), ("pendulum", 1.6, True, "newmark"),
               ("asymmetry", None, True, "exact"), ("asymmetry", 1.6, False, "newmark")}
_SLOPE_CASES = [pytest.param(*case, id="-".join(map(str, case)),
                             marks=() if case in _SLOPE_FAST else pytest.mark.slow)
                for case in itertools.product([None, "pendulum", "asymmetry"], [None, 1.6],
                                              [True, False], ["newmark", "exact"])]


@pytest.mark.parametrize(("extra", "breakaway", "split_at_turn", "gain"), _SLOPE_CASES)
def test_newton_slope_is_the_derivative_of_the_residual(split_at_turn, breakaway, gain, extra):
    """The slope written out for Newton's steps (flow derivatives of Bouc-Wen, with and without
    a turn inside the step; the end velocity of Newmark's step, 2 / dt per metre, or of the
    exact step, about 3 / dt for a rigid mass) equals the automatic derivative of the residual;
    with a friction pendulum's nonlinear surface (large-displacement form and a restrainer
    engaged about x = 0.01 m) its stiffness is in the slope, and with a direction asymmetry
    (F = mu W Z (1 + a Z)) its term."""
    from teflon_jax.elements import isolator_residual, residual_and_slope

    bearing = tj.paper_bearing(FRICTION, breakaway_ratio=breakaway)
    rng = np.random.default_rng(1)
    n = 4000
    z0, vb0 = rng.uniform(-1.05, 1.05, n), 0.3 * rng.normal(size=n)
    x = 0.01 + 3e-3 * rng.normal(size=n) * 10 ** rng.uniform(-4, 0, n)
    z_peak = rng.uniform(0.99, 1.0, n)
    rule = (0.005, split_at_turn)

    def step_state(z0, vb0, z_peak):
        p = {"bearing": bearing, "W": WEIGHT, "z0": z0, "z_peak": z_peak, "ub0": 0.01, "vb0": vb0,
                "g0": 1e-8, "ub_linear": 0.01, "reversal_length": tj.bouc_wen_reversal_length(bearing.hysteresis, z0),
                "vb_linear": -vb0 if gain == "newmark" else 0.05 - 0.5 * vb0,
                "velocity_gain": (2.0 if gain == "newmark" else 3.0) / 0.005}
        if extra == "asymmetry":
            p["asymmetry"] = 0.15
        if extra == "pendulum":
            p["surface"] = tj.concave_surface(0.05, displacement_capacity=0.01, restrainer_stiffness=3e7,
                                              large_displacement=True)
        return p

    def both(z0, vb0, x, z_peak):
        p = step_state(z0, vb0, z_peak)
        r, slope, _, _ = residual_and_slope(x, p, rule)
        r_auto, slope_auto = jax.jvp(lambda y: isolator_residual(y, p, rule), (x,), (jnp.ones_like(x),))
        return r, r_auto, slope, slope_auto

    r, r_auto, slope, slope_auto = jax.jit(jax.vmap(both))(z0, vb0, x, z_peak)
    # the slopes of F and Z that the custom JVP of the root uses, against automatic derivatives
    from teflon_jax.elements import bearing_force, force_and_slopes

    def slopes(z0, vb0, x, z_peak):
        p = step_state(z0, vb0, z_peak)
        _, _, d_force, d_z = force_and_slopes(x, p, rule)
        _, (d_force_auto, d_z_auto) = jax.jvp(lambda y: bearing_force(y, p, rule), (x,), (jnp.ones_like(x),))
        return d_force, d_force_auto, d_z, d_z_auto

    d_force, d_force_auto, d_z, d_z_auto = jax.jit(jax.vmap(slopes))(z0, vb0, x, z_peak)
    np.testing.assert_allclose(d_force, d_force_auto, rtol=1e-9, atol=1e-9 * float(np.max(np.abs(d_force_auto))))
    np.testing.assert_allclose(d_z, d_z_auto, rtol=1e-9, atol=1e-9 * float(np.max(np.abs(d_z_auto))))
    np.testing.assert_allclose(r, r_auto, rtol=1e-12, atol=1e-17)
    turning = vb0 * (2 / 0.005 * (x - 0.01) - vb0) < 0
    assert turning.sum() > n // 10  # the turning branch is exercised
    np.testing.assert_allclose(slope, slope_auto, rtol=1e-9)


@pytest.mark.slow
def test_newton_in_line_iterations_give_the_loop_iterates():
    """Newton iterations written out in line (`newton_unrolled`) follow the loop's iterates;
    a solve cut short is still reported as not converged, in line or in the loop."""
    from teflon_jax.systems import peak_response

    system = rigid_mass(0.01, sine_ground(duration=3.0))
    loop = tj.simulate_history(system, 3.0)
    inline = tj.simulate_history(dataclasses.replace(system, newton_unrolled=3), 3.0)
    np.testing.assert_allclose(inline.displacement, loop.displacement, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(inline.z, loop.z, rtol=1e-12, atol=1e-14)
    for unrolled in (0, 1):
        short = dataclasses.replace(system, newton_iterations=1, newton_unrolled=unrolled)
        assert not bool(peak_response(short, 3.0).converged)
        assert bool(peak_response(dataclasses.replace(short, newton_iterations=3), 3.0).converged)


@pytest.mark.slow
@pytest.mark.parametrize("linear_rule", ["newmark", "exact"])
def test_step_matrix_is_the_step(linear_rule):
    """`step_from` (the engine's step) is the linear map of `step_matrices` with the bearing
    force solved at the step's end, and by Newmark's rule it is Newmark's average-acceleration
    step written out: K_eff u_lin = -M a_g1 + M (4/dt^2 u0 + 4/dt v0 + a0) + C (2/dt u0 + v0),
    u1 = u_lin - K_eff^-1 e0 F, v1 = 2/dt (u1 - u0) - v0."""
    system = tj.isolated_structure("building", linear_rule=linear_rule)(sine_ground())
    n = system.mass.shape[0]
    rng = np.random.default_rng(2)
    y0 = {"u": jnp.asarray(1e-2 * rng.normal(size=n)), "v": jnp.asarray(0.1 * rng.normal(size=n)),
          "z": jnp.asarray(0.4), "z_peak": jnp.asarray(1.0)}
    ground0, ground1 = -1.5, 2.0
    y1, converged = system.step_from(y0, ground0, ground1)
    assert bool(converged)
    stepped = jnp.concatenate([y1["u"], y1["v"]])
    matrix, force_column = system.step_matrices()
    start_force = system.friction_force(y0["v"][0], y0["z"], y0["z_peak"])
    linear = matrix @ jnp.concatenate([y0["u"], y0["v"], jnp.stack([ground0, start_force, ground1])])
    force, z1, _, _ = system.isolator_force(linear[0], y0, linear[n], (-force_column[0], -force_column[n]))
    np.testing.assert_allclose(linear + force_column * force, stepped, rtol=1e-10, atol=1e-12)
    assert abs(float(force)) > 0.1 * float(system.bearing_load) * 0.05  # the bearing force takes part
    if linear_rule == "newmark":
        dt, m, u0, v0 = system.time_step, system.mass, y0["u"], y0["v"]
        a0 = system.acceleration_at(ground0, y0)
        rhs = -m * ground1 + m * (4 / dt**2 * u0 + 4 / dt * v0 + a0) + system.damping @ (2 / dt * u0 + v0)
        u_linear = system.newmark_inverse @ rhs
        g0 = system.newmark_inverse[0, 0]
        force, _, _, _ = system.isolator_force(u_linear[0], y0, 2 / dt * (u_linear[0] - u0[0]) - v0[0],
                                               (g0, 2 / dt * g0))
        u1 = u_linear - system.newmark_inverse[:, 0] * force
        np.testing.assert_allclose(jnp.concatenate([u1, 2 / dt * (u1 - u0) - v0]), stepped, rtol=1e-9, atol=1e-12)


def test_vector_arctan_is_the_arctan_to_an_ulp():
    """The rational arctan of the exact Bouc-Wen and Park updates against NumPy's, over the
    three ranges of its argument reduction, tiny and huge arguments, signs and infinities;
    its derivative against 1 / (1 + x^2)."""
    from teflon_jax.bearing import vector_arctan

    x = np.concatenate([np.linspace(-40.0, 40.0, 400_001), np.geomspace(1e-300, 1e300, 20_001),
                        -np.geomspace(1e-12, 1e12, 2_001), [0.0, 0.66, 1 + np.sqrt(2), np.inf, -np.inf]])
    value = np.asarray(jax.jit(tj.bearing.vector_arctan)(x))
    exact = np.arctan(x)
    assert np.all(np.abs(value - exact) <= np.spacing(np.abs(exact)) + 1e-300)
    points = jnp.array([0.0, 0.3, 0.66, 1.0, 2.5, -9.0])
    slope = jax.vmap(jax.grad(vector_arctan))(points)
    np.testing.assert_allclose(slope, 1 / (1 + np.asarray(points) ** 2), rtol=1e-14)


def _stepped_structure(case):
    """A structure of each case of the test below, whose `advance` steps it."""
    from teflon_jax.bearing import FrictionalHeating, Wear
    from teflon_jax.systems import slab_on_bearings, with_vertical_motion

    t = np.arange(0.0, 3.0 + 1e-9, 0.01)
    shaking = tj.uniform_signal(0.5 * STANDARD_GRAVITY * np.sin(2 * np.pi * t / 0.9), 0.01)
    across = tj.uniform_signal(0.3 * STANDARD_GRAVITY * np.cos(2 * np.pi * t / 1.3), 0.01)
    vertical = tj.uniform_signal(1.2 * STANDARD_GRAVITY * np.sin(2 * np.pi * 1.7 * t), 0.01)
    if case == "rigid mass":
        return rigid_mass(0.005, shaking)
    if case == "building, pendulum":
        return tj.isolated_structure("building", isolator=tj.concave_surface(2.0), linear_rule="newmark")(shaking)
    heated = eqx.tree_at(lambda b: (b.heating, b.wear), tj.paper_bearing(FRICTION),
                         (FrictionalHeating(contact_area=0.05, heat_scale=2.0), Wear(0.5, 1.0)),
                         is_leaf=lambda x: x is None)
    options = dict(weight=WEIGHT, bearing=heated, time_step=0.005, isolation_period=2.5, contact_pressure=20e6)
    if case == "heated, vertical":
        return with_vertical_motion(tj.rigid_mass(ground_acceleration=shaking, **options), vertical)
    if case == "heated, two components, vertical":
        return with_vertical_motion(tj.rigid_mass(components=2, ground_acceleration=shaking, ground_y=across,
                                                  **options), vertical)
    return slab_on_bearings(length_x=20.0, length_y=12.0, weight=3e5, centre_of_mass=[10.0, 6.0],
                            positions=[[2.0, 1.0], [18.0, 1.0], [18.0, 11.0], [2.0, 11.0]], loads=[75e3] * 4,
                            bearings=tj.paper_bearing(FRICTION), ground_acceleration=shaking, ground_y=across, time_step=0.005,
                            isolation_period=3.0, height_of_centre_of_mass=2.0)


@pytest.mark.parametrize("case", ["rigid mass", "building, pendulum", "heated, vertical",
                                  "heated, two components, vertical", "slab, overturning"])
def test_riccati_newmark_on_a_structure_takes_the_engines_step(case):
    """`diffrax.diffeqsolve` with `RiccatiNewmark` steps a structure by its `advance`, the
    engine's own step (`StructureOnSliders.step_from`, `PlanarStep.newmark_update`
    or `overturning_step`): its states are `simulate_history`'s to rounding's order (1e-10 of
    the peak displacement; the engine's matrices and records evaluated once outside its loop
    round differently in the last bits), under one and two
    components, with a heated, wearing bearing under a vertical record that lifts it (in one and
    two components), and on a slab whose groups carry the overturning loads."""
    system = _stepped_structure(case)
    duration = 2.0
    history = tj.simulate_history(system, duration)
    y0 = tj.initial_state(system)
    solution = diffrax.diffeqsolve(diffrax.ODETerm(system), tj.RiccatiNewmark(), 0.0, duration, system.time_step, y0,
                                   saveat=diffrax.SaveAt(t0=True, steps=True), max_steps=int(duration / system.time_step))
    coordinates = solution.ys["u"]
    assert bool(np.all(history.converged))
    if "vertical" in case:
        assert np.any(np.asarray(history.load_factor) == 0)  # the bearing lifts
    if case == "slab, overturning":
        loads = np.asarray(history.normal_load)
        assert np.ptp(loads[:, 0]) > 0.1 * loads[0, 0]  # the groups' loads swing
        np.testing.assert_allclose(solution.ys["normal_load"], loads, rtol=1e-10)
    peak = np.max(np.abs(history.displacement))
    np.testing.assert_allclose(coordinates, history.displacement, rtol=0, atol=1e-10 * peak)  # rounding's order
    np.testing.assert_allclose(solution.ys["z"], history.z, rtol=0, atol=1e-9)
