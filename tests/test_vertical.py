"""The vertical ground acceleration on the isolators' normal load, N = W max(1 + a_v / g, 0).

Each test names the law it guards: a rigid mass on a friction pendulum under a constant a_v
oscillates with the period 2 pi sqrt(R / (g + a_v)) (the restoring force N u / R on the
mass W / g); a rigid mass on flat sliders starts to slide when the ground acceleration
exceeds mu (g + a_v) and then slides at the relative acceleration a_g - mu (g + a_v)
(Coulomb's law with the normal force N); an isolator with N <= 0 carries no shear, so the
rigid mass's total acceleration is zero while a_v < -g, and the run reports that time.
References: Almazan, De la Llera & Inaudi (1998); Zayas, Low & Mahin (1990).
"""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from teflon_jax.bearing import concave_surface, coulomb_friction, paper_bearing
from teflon_jax.excitation import uniform_signal
from teflon_jax.systems import (
    isolated_structure,
    peak_response,
    rigid_mass,
    simulate_history,
    with_vertical_component,
    with_vertical_motion,
)
from teflon_jax.units import STANDARD_GRAVITY

G = STANDARD_GRAVITY
WEIGHT = 100e3  # [N]
RADIUS = 2.0  # [m]
RECORD_STEP = 0.01  # [s]


def _record(values):
    return uniform_signal(jnp.asarray(values, float), RECORD_STEP)


def _times(duration):
    return np.arange(int(round(duration / RECORD_STEP)) + 1) * RECORD_STEP


def _zero_crossing_period(time, u, after=1.0):
    """Mean period [s] between upward zero crossings of u after `after` [s]."""
    keep = time > after
    t, x = time[keep], u[keep]
    i = np.where((x[:-1] < 0) & (x[1:] >= 0))[0]
    crossings = t[i] - x[i] * (t[i + 1] - t[i]) / (x[i + 1] - x[i])
    return np.mean(np.diff(crossings))


@pytest.mark.parametrize("linear_rule", ["newmark", "exact"])
@pytest.mark.parametrize("vertical", [-4.0, 3.0])
def test_pendulum_period_under_constant_vertical_acceleration(linear_rule, vertical):
    """T = 2 pi sqrt(R / (g + a_v)): the pendulum's stiffness N / R with N = W (1 + a_v / g)."""
    duration = 16.0
    t = _times(duration)
    structure = isolated_structure("rigid", isolator=concave_surface(RADIUS), friction_model="none",
                                   linear_rule=linear_rule, time_step=0.005)
    ground = (_record(np.where(t < 0.5, 1.0, 0.0)), _record(np.full(t.shape, vertical)))
    response = simulate_history(with_vertical_component(structure)(ground), duration)
    period = _zero_crossing_period(np.asarray(response.time), np.asarray(response.displacement[:, 0]))
    expected = 2 * np.pi * np.sqrt(RADIUS / (G + vertical))
    assert period == pytest.approx(expected, rel=2e-4)
    assert float(response.uplift_time) == 0.0


@pytest.mark.parametrize("friction_model", ["coulomb", "hysteretic"])
@pytest.mark.parametrize("load", [0.5, 1.5])
def test_sliding_threshold_scales_with_normal_load(friction_model, load):
    """A flat slider sticks under a_g = 0.9 mu g s and slides under 1.5 mu g s at the relative
    acceleration -(a_g - mu g s), s = 1 + a_v / g."""
    mu, duration = 0.1, 4.0
    t = _times(duration)
    ramp = np.minimum(t / 0.2, 1.0)  # the ground acceleration builds up over 0.2 s
    results = {}
    for factor in (0.9, 1.5):
        system = rigid_mass(weight=WEIGHT, bearing=paper_bearing(coulomb_friction(mu)), time_step=0.005,
                            ground_acceleration=_record(factor * mu * G * load * ramp),
                            friction_model=friction_model)
        system = with_vertical_motion(system, _record(np.full(t.shape, (load - 1) * G)))
        response = simulate_history(system, duration)
        results[factor] = (np.asarray(response.time), np.asarray(response.velocity[:, 0]),
                           np.asarray(response.displacement[:, 0]))
    time, _, stuck = results[0.9]
    # sticks: Coulomb exactly (up to the first step's average acceleration), Bouc-Wen within
    # its pre-sliding displacement of a few Y (Y = 0.127 mm); sliding goes metres
    assert np.max(np.abs(stuck)) < 10 * 0.005 * 0.0254
    _, velocity, slid = results[1.5]
    assert np.max(np.abs(slid)) > 0.5
    i1, i2 = np.searchsorted(time, [1.0, 4.0])
    slope = (velocity[i2] - velocity[i1]) / (time[i2] - time[i1])
    assert slope == pytest.approx(-0.5 * mu * G * load, rel=1e-3)


def _uplift_case(kind="rigid"):
    """A friction pendulum under a harmonic horizontal motion and a_v = -1.5 g on the
    samples 4.00-4.50 s (zero elsewhere, linear between samples)."""
    duration = 10.0
    t = _times(duration)
    horizontal = 3.0 * np.sin(2 * np.pi * 0.8 * t)
    vertical = np.where((t > 4.0 - 1e-9) & (t < 4.5 + 1e-9), -1.5 * G, 0.0)
    structure = isolated_structure(kind, isolator=concave_surface(RADIUS))
    return with_vertical_component(structure), (_record(horizontal), _record(vertical)), duration


def test_uplift_carries_no_shear_and_is_reported():
    """While a_v <= -g the rigid mass's total acceleration (the isolator's shear over m) is
    zero, never NaN; the run reports the time with N <= 0."""
    structure, ground, duration = _uplift_case()
    system = structure(ground)
    response = simulate_history(system, duration)
    shear = np.asarray(response.total_acceleration[:, 0])
    loads = np.asarray(response.load_factor)
    assert np.all(np.isfinite(shear)) and np.all(np.isfinite(np.asarray(response.z)))
    uplifted = loads == 0
    assert uplifted.sum() > 50
    assert np.max(np.abs(shear[uplifted])) < 1e-9 * np.max(np.abs(shear))
    assert np.all(np.asarray(response.friction_force)[uplifted] == 0)
    # a_v <= -g from 3.99 + 0.01 * 2/3 s to 4.50 + 0.01 / 3 s (linear between samples)
    exact = 4.5 + RECORD_STEP / 3 - (4.0 - RECORD_STEP / 3)
    assert abs(float(response.uplift_time) - exact) <= system.time_step
    assert np.max(np.abs(shear[~uplifted])) > 1.0  # the isolator does carry shear outside
    peaks = peak_response(system, duration)
    assert bool(peaks.converged)
    assert float(peaks.uplift_time) == float(response.uplift_time)
    assert float(peaks.base_disp) == pytest.approx(np.max(np.abs(response.displacement[:, 0])), rel=1e-9)
    assert float(peaks.base_shear_ratio) == pytest.approx(np.max(np.abs(shear)) / G, rel=1e-9)


@pytest.mark.slow  # the same engine and checks on the rigid mass: test_uplift_carries_no_shear_and_is_reported
def test_building_uplift_finite_and_peaks_agree():
    """The building on a friction pendulum through the same uplift: finite, the bearing's
    friction zero while uplifted, and the peak loop's peaks those of the history."""
    structure, ground, duration = _uplift_case("building")
    system = structure(ground)
    response = simulate_history(system, duration)
    uplifted = np.asarray(response.load_factor) == 0
    assert np.all(np.isfinite(np.asarray(response.displacement)))
    assert np.all(np.asarray(response.friction_force)[uplifted] == 0)
    peaks = peak_response(system, duration)
    assert float(peaks.base_disp) == pytest.approx(np.max(np.abs(response.displacement[:, 0])), rel=1e-9)
    assert float(peaks.uplift_time) > 0.5


@pytest.mark.parametrize("kind", ["rigid", pytest.param("building", marks=pytest.mark.slow)])
def test_zero_vertical_record_changes_nothing(kind):
    """With a_v = 0 (N = W) the run is the one without a vertical record, to rounding."""
    duration = 6.0
    t = _times(duration)
    horizontal = _record(3.0 * np.sin(2 * np.pi * 0.8 * t) * np.minimum(t, 1.0))
    for isolator in (concave_surface(RADIUS), None):
        structure = isolated_structure(kind, isolator=isolator)
        plain = peak_response(structure(horizontal), duration)
        loaded = peak_response(with_vertical_component(structure)((horizontal, _record(0 * t))), duration)
        for name in ("base_disp", "base_shear_ratio", "smooth_base_disp"):
            assert float(getattr(loaded, name)) == pytest.approx(float(getattr(plain, name)), rel=1e-11)
        assert float(loaded.uplift_time) == 0.0 and plain.uplift_time is None


@pytest.mark.slow
def test_gradients_through_uplift_finite_and_match_differences():
    """d(peak) / d(vertical scale) is finite with uplift, and equals central differences
    where the vertical motion does not lift the isolators."""
    structure, (horizontal, vertical), duration = _uplift_case()
    values = np.asarray(vertical.values)

    def peak(scale, base):
        signal = _record(scale * base)
        return peak_response(structure((horizontal, signal)), duration).smooth_base_disp

    with_uplift = jax.grad(peak)(1.0, values)
    assert np.isfinite(float(with_uplift))
    t = _times(duration)
    gentle = 0.3 * G * np.sin(2 * np.pi * 3.0 * t)  # N between 0.7 W and 1.3 W
    gradient = float(jax.grad(peak)(1.0, gentle))
    h = 1e-3
    difference = (float(peak(1 + h, gentle)) - float(peak(1 - h, gentle))) / (2 * h)
    assert gradient == pytest.approx(difference, rel=1e-3, abs=1e-7)
    assert abs(gradient) > 1e-5  # the vertical motion does change the peak


def test_vertical_inputs_refused():
    structure = isolated_structure("rigid", isolator=concave_surface(RADIUS))
    system = structure(_record(np.zeros(301)))
    with pytest.raises(ValueError, match="vertical_acceleration"):
        with_vertical_motion(system, np.zeros(301))
    with pytest.raises(ValueError, match="radius"):
        with_vertical_motion(system, _record(np.zeros(301)), radius=-1.0)
    short = with_vertical_motion(system, _record(np.zeros(101)), radius=RADIUS)
    with pytest.raises(ValueError, match="vertical record"):
        peak_response(short, 3.0)


@pytest.mark.slow
def test_two_directions_under_one_component_reproduce_one_direction():
    """The bidirectional rigid mass on a pendulum (W / R as its springs) under a_x alone and a
    vertical record with uplift: the same response as the one-direction structure (Park's Z
    reduces to Eq. 3 along one axis), zero shear while uplifted, the same uplift time."""
    from teflon_jax.bearing import FrictionParameters
    from teflon_jax.systems import rigid_mass, simulate_history

    duration = 10.0
    t = _times(duration)
    ground = _record(3.0 * np.sin(2 * np.pi * 0.8 * t))
    vertical = _record(np.where((t > 4.0 - 1e-9) & (t < 4.5 + 1e-9), -1.5 * G,
                                0.4 * G * np.sin(2 * np.pi * 4.0 * t)))
    bearing = paper_bearing(FrictionParameters(f_max=0.1, delta_f=0.06, rate_a=20.0))
    one = with_vertical_motion(rigid_mass(weight=WEIGHT, bearing=bearing, ground_acceleration=ground,
                                          time_step=0.005, radius=RADIUS), vertical, radius=RADIUS)
    two = rigid_mass(components=2, weight=WEIGHT, bearing=bearing, ground_acceleration=ground, time_step=0.005,
                                   isolation_period=2 * np.pi * np.sqrt(RADIUS / G))
    two = with_vertical_motion(two, vertical, radius=RADIUS)
    r1, r2 = simulate_history(one, duration), simulate_history(two, duration)
    u1 = np.asarray(r1.displacement[:, 0])
    assert np.max(np.abs(u1 - np.asarray(r2.displacement[:, 0]))) < 1e-6 * np.max(np.abs(u1))
    shear = np.asarray(r2.total_acceleration[:, 0])
    uplifted = np.asarray(r2.load_factor) == 0
    assert uplifted.sum() > 50 and np.max(np.abs(shear[uplifted])) < 1e-9 * np.max(np.abs(shear))
    assert float(r2.uplift_time) == float(r1.uplift_time)
    peaks = peak_response(two, duration)
    assert float(peaks.base_disp) == pytest.approx(np.max(np.abs(u1)), rel=1e-6)
    assert float(peaks.uplift_time) == float(r1.uplift_time) and bool(peaks.converged)


def _history_run(system, n_steps):
    """(load factors, travel, heat states) at the end of each step (`advance`) from rest."""
    from teflon_jax.systems import initial_state

    dt = system.time_step
    y0 = initial_state(system)

    def body(y, k):
        y1, _ = system.advance(k * dt, (k + 1) * dt, y, None)
        return y1, (y1["travel"], y1["heat"])

    _, (travel, heat) = jax.lax.scan(body, y0, jnp.arange(n_steps))
    loads = jax.vmap(system.load_factor)(jnp.arange(1, n_steps + 1) * dt)
    return np.asarray(loads), np.asarray(travel).reshape(n_steps, -1)[:, 0], np.asarray(heat).reshape(n_steps, -1)


@pytest.mark.parametrize("directions", [1, 2])
def test_uplifted_bearing_neither_heats_nor_wears(directions):
    """While N = 0 no heat flux q = mu N |v| / A enters the steel (the heat states only decay)
    and a wearing bearing counts no travel; outside it does both."""
    import equinox as eqx

    from teflon_jax.bearing import FrictionalHeating, FrictionParameters, Wear
    from teflon_jax.systems import rigid_mass
    from teflon_jax.units import INCH, PSI

    bearing = paper_bearing(FrictionParameters(f_max=0.1, delta_f=0.06, rate_a=20.0))
    bearing = eqx.tree_at(lambda b: (b.heating, b.wear), bearing,
                          (FrictionalHeating(contact_area=10 * INCH**2, heat_scale=3.0), Wear(0.5, 1.0)),
                          is_leaf=lambda x: x is None)
    _, (horizontal, vertical), duration = _uplift_case()
    options = {"weight": WEIGHT, "bearing": bearing, "time_step": 0.005, "isolation_period": 2.5,
               "contact_pressure": 3000 * PSI}
    if directions == 1:
        system = rigid_mass(ground_acceleration=horizontal, **options)
    else:
        system = rigid_mass(components=2, ground_acceleration=horizontal, **options)
    loads, travel, heat = _history_run(with_vertical_motion(system, vertical), 1200)
    slid = np.diff(travel)
    uplifted = loads[1:] == 0  # steps that start uplifted (the step's flux is its start's)
    uplifted &= loads[:-1] == 0
    assert uplifted.sum() > 50
    assert np.all(slid[uplifted] == 0) and np.sum(slid[~uplifted]) > 0.1
    decays = np.all(np.abs(heat[1:]) <= np.abs(heat[:-1]) + 1e-300, axis=1)
    assert np.all(decays[uplifted])
    assert not np.all(decays[~uplifted])


@pytest.mark.slow
def test_varying_load_step_matches_an_adaptive_solver():
    """A pendulum under a harmonic a_v (a parametrically excited oscillator,
    u'' + (g + a_v(t)) u / R = -a_g): the Newmark step with the load change moved into the
    isolator's equilibrium against diffrax's Tsit5 on the equations of motion."""
    import diffrax

    duration = 6.0
    t = _times(duration)
    ground = _record(np.where(t < 0.5, 1.0, 0.0))
    vertical = _record(0.5 * G * np.sin(2 * np.pi * 2.0 * t))
    system = rigid_mass(weight=WEIGHT, bearing=None, ground_acceleration=ground, time_step=0.001,
                        radius=RADIUS, friction_model="none")
    system = with_vertical_motion(system, vertical, radius=RADIUS)
    stepped = np.asarray(simulate_history(system, duration, save_every=10).displacement[:, 0])
    reference = np.asarray(simulate_history(system, duration, save_every=10, solver=diffrax.Tsit5(),
                                              rtol=1e-9, atol=1e-12).displacement[:, 0])
    assert np.max(np.abs(stepped - reference)) < 1e-3 * np.max(np.abs(reference))
    plain = np.asarray(simulate_history(with_vertical_motion(system, _record(0 * t), radius=RADIUS),
                                          duration, save_every=10).displacement[:, 0])
    assert np.max(np.abs(plain - reference)) > 1e-2 * np.max(np.abs(reference))  # a_v matters


@pytest.mark.slow
@pytest.mark.parametrize("directions", [1, 2])
def test_a_pendulum_holds_the_stiffness_its_load_scales(directions):
    """A single pendulum built with its radius (one component) or surface (two) holds W / R,
    the part of its stiffness the normal load N = s W carries: the vertical record alone then
    scales it, to the bit as when the radius is given, and unlike a spring (W / R left
    unscaled), which moves the response."""
    import dataclasses

    from teflon_jax.bearing import FrictionParameters, concave_surface
    from teflon_jax.systems import rigid_mass, simulate_history

    duration = 2.0
    t = _times(duration)
    ground = _record(3.0 * np.sin(2 * np.pi * 0.8 * t))
    vertical = _record(0.6 * G * np.sin(2 * np.pi * 3.0 * t))
    bearing = paper_bearing(FrictionParameters(f_max=0.1, delta_f=0.06, rate_a=20.0))
    if directions == 1:
        system = rigid_mass(weight=WEIGHT, bearing=bearing, ground_acceleration=ground, time_step=0.005,
                            radius=RADIUS)
        run = simulate_history
    else:
        system = rigid_mass(components=2, weight=WEIGHT, bearing=bearing, ground_acceleration=ground, time_step=0.005,
                                          isolation_period=2 * np.pi * np.sqrt(RADIUS / G),
                                          surface=concave_surface(RADIUS))
        run = simulate_history
    assert np.allclose(np.asarray(system.pendulum_stiffness), WEIGHT / RADIUS, rtol=1e-15, atol=0)

    def displacement(s):
        response = run(s, duration)
        return np.asarray(response.displacement)[:, 0]

    held = displacement(with_vertical_motion(system, vertical))
    given = displacement(with_vertical_motion(system, vertical, radius=RADIUS))
    spring = displacement(with_vertical_motion(dataclasses.replace(system, pendulum_stiffness=None), vertical))
    assert np.array_equal(held, given)
    assert np.max(np.abs(held - spring)) > 1e-3 * np.max(np.abs(held))


def test_a_vertical_record_goes_on_structures_only():
    """`with_vertical_motion` names `system` for what is not a stepped structure, and
    `with_vertical_component` names `structure` for what is not an isolated structure."""
    system = rigid_mass(weight=WEIGHT, bearing=None, ground_acceleration=_record(np.zeros(101)),
                        time_step=0.005, friction_model="none")
    with pytest.raises(ValueError, match="system: expected a stepped structure"):
        with_vertical_motion(isolated_structure("rigid"), _record(np.zeros(101)))
    with pytest.raises(ValueError, match="structure: expected an IsolatedStructure"):
        with_vertical_component(system)


def test_the_vertical_component_is_a_field_of_the_one_study_structure():
    """`with_vertical_component` gives the same `IsolatedStructure` with `vertical` set, whose
    system is the horizontal one's with the record on its normal load, on flat sliders and on a
    series pendulum alike; applied twice, or called without the (horizontal, vertical) pair,
    it is refused by name."""
    from teflon_jax.bearing import BoucWen, FrictionParameters, TriplePendulum

    triple = TriplePendulum(inner_radius=0.3, bottom_radius=2.1, top_radius=2.1, inner_capacity=0.05,
                            bottom_capacity=0.4, top_capacity=0.4,
                            inner_friction=FrictionParameters(0.03, 0.015, 20.0),
                            bottom_friction=FrictionParameters(0.07, 0.03, 20.0),
                            top_friction=FrictionParameters(0.11, 0.05, 20.0), hysteresis=BoucWen(1e-4))
    horizontal, vertical = _record(np.zeros(101)), _record(np.full(101, 0.3 * STANDARD_GRAVITY))
    for structure in (isolated_structure("rigid"), isolated_structure("rigid", isolator=triple)):
        loaded = with_vertical_component(structure)
        assert type(loaded) is type(structure) and loaded.vertical and not structure.vertical
        system = loaded((horizontal, vertical))
        assert system.vertical_acceleration is vertical and structure(horizontal).vertical_acceleration is None
        assert float(system.load_factor(0.5)) == pytest.approx(1.3)
        with pytest.raises(ValueError, match="structure: it takes a vertical component already"):
            with_vertical_component(loaded)
        with pytest.raises(ValueError, match=r"ground_acceleration: this structure takes \(horizontal, vertical\)"):
            loaded(horizontal)
