"""One imposed-path test for every isolator: `imposed_path_test` drives a sliding bearing or a
series pendulum along a `SampledPath`, under the path's normal load at each sample.

The series pendulum's forces are homogeneous of degree one in the normal load N (friction
mu N Z and the pendulum's N u / R alike, no pressure dependence here): the sliders' balance
at a sample does not depend on N, so along any path the force over N is the same whatever N
does. A test that held the first sample's load, or any other, breaks that. Under a vertical
ground record a structure's isolator carries N = s(t) W; its path and load imposed on the
test give the structure's force (the law fitted is the law run, also under a vertical
record), with surfaces that read their contact pressure (heating, pressure dependence) at
the pressure given under W times s(t) when the test is told W (`reference_load`). Options one
kind of isolator does not take are refused by name.
"""

import dataclasses

import diffrax
import jax
import numpy as np
import pytest
from test_series_one_law import DOUBLE, TRIPLE

from identification.bearing_fit import fit_series_pendulum_test, prepare_series_problem
from teflon_jax.bearing import (
    FrictionalHeating,
    FrictionParameters,
    PressureDependence,
    SurfaceParts,
    Wear,
    heat_kernel_exponentials,
    paper_bearing,
    single_pendulum,
)
from teflon_jax.excitation import SineMotion, StochasticGroundMotion, sample, uniform_signal
from teflon_jax.formats import test_record_from_arrays
from teflon_jax.solver import RiccatiNewmark
from teflon_jax.systems import (
    imposed_path_test,
    normal_load_varies,
    sampled_path,
    simulate_history,
    triple_structure,
    with_vertical_motion,
)
from teflon_jax.units import STANDARD_GRAVITY

WEIGHT = 1e6
PRESSED = dataclasses.replace(  # a heated bottom surface and a top surface whose friction falls with pressure
    TRIPLE, bottom_heating=FrictionalHeating(contact_area=0.05), bottom_pressure=30e6, top_pressure=25e6,
    surface_parts=(None, None, SurfaceParts(pressure_dependence=PressureDependence(
        exponent=0.3, reference_load=1e6, contact_area=0.05))))


def _path(planar=False):
    time = np.arange(0.0, 6.0 + 1e-9, 0.01)
    u = 0.2 * np.sin(2 * np.pi * time / 3.0) * np.minimum(time / 1.5, 1.0)
    if planar:
        u = np.stack([u, 0.5 * np.roll(u, 40)], -1)
    load = WEIGHT * (1.0 + 0.4 * np.sin(2 * np.pi * time / 0.7))  # 0.6 to 1.4 W
    return time, u, load


@pytest.mark.parametrize("pendulum, planar", [(DOUBLE, False), (TRIPLE, False), (TRIPLE, True)],
                         ids=["double", "triple", "triple-planar"])
def test_a_series_pendulums_force_follows_the_normal_load_of_each_sample(pendulum, planar):
    time, u, load = _path(planar)
    run = jax.jit(imposed_path_test)
    varying = run(pendulum, sampled_path(time, u, load))
    constant = run(pendulum, sampled_path(time, u, WEIGHT))
    assert bool(np.all(varying.converged)) and bool(np.all(constant.converged))
    np.testing.assert_array_equal(np.asarray(varying.normal_load), load)
    scale = load if not planar else load[:, None]
    ratio = np.asarray(varying.force) / scale
    np.testing.assert_allclose(ratio, np.asarray(constant.force) / WEIGHT, rtol=0, atol=1e-9)
    np.testing.assert_allclose(np.asarray(varying.slider), np.asarray(constant.slider), rtol=0, atol=1e-9)


def test_a_pendulum_test_under_a_recorded_load_is_the_same_force_over_n():
    """`imposed_path_test` takes a recorded normal load (a `Signal`) for a series pendulum too."""
    motion = SineMotion(0.15, 0.5, cycles=2)
    time = np.linspace(0.0, 4.0, 801)
    recorded = uniform_signal(WEIGHT * (1.0 + 0.3 * np.cos(2 * np.pi * time / 0.9)), float(time[1]))
    varying = imposed_path_test(DOUBLE, motion, recorded)
    constant = imposed_path_test(DOUBLE, motion, WEIGHT)
    load = np.asarray(varying.normal_load)
    assert np.ptp(load) > 0.5 * WEIGHT and bool(np.all(varying.converged))
    np.testing.assert_allclose(np.asarray(varying.force) / load, np.asarray(constant.force) / WEIGHT,
                               rtol=0, atol=1e-9)


@pytest.mark.parametrize("pendulum", [TRIPLE, PRESSED], ids=["triple", "heated-pressure-dependent"])
def test_under_a_vertical_record_the_test_along_the_structures_path_is_its_force(pendulum):
    """Also where the surfaces read their contact pressure, given under the structure's W: the
    test told that load (`reference_load`) scales it by N / W at each sample as the structure
    does; told another load, it runs another law."""
    ground = StochasticGroundMotion(peak_ground_acceleration=0.5 * STANDARD_GRAVITY, duration=8.0,
                                    time_step=0.01, rise_time=1.0, strong_motion_duration=5.0)
    horizontal, vertical = (np.asarray(sample(ground, jax.random.PRNGKey(k), 1))[0] for k in (3, 4))
    system = triple_structure("rigid", pendulum, uniform_signal(horizontal, 0.01), time_step=0.005)
    system = with_vertical_motion(system, uniform_signal(0.6 * vertical, 0.01))
    response = jax.jit(simulate_history, static_argnums=1)(system, 8.0)
    weight = float(system.bearing_load)
    factor = np.asarray(response.load_factor)
    assert bool(np.all(response.converged)) and factor.min() > 0.3 and np.ptp(factor) > 0.5
    path = np.asarray(response.displacement[:, 0])
    along = sampled_path(np.asarray(response.time), path, weight * factor)  # concrete: the heat kernel from its times
    test = imposed_path_test(pendulum, along, reference_load=weight)
    assert bool(np.all(test.converged))
    np.testing.assert_allclose(np.asarray(test.force) / weight, np.asarray(response.bearing_force) / weight,
                               rtol=0, atol=1e-9)
    if pendulum.reads_pressure:
        other = imposed_path_test(pendulum, along, reference_load=2 * weight)
        assert np.max(np.abs(np.asarray(other.force) - np.asarray(response.bearing_force))) > 1e-4 * weight


def test_a_pendulum_reading_its_pressure_takes_one_load_or_a_reference_and_every_load_must_be_positive():
    time, u, load = _path()
    with pytest.raises(ValueError, match="path.normal_load: .*positive"):
        imposed_path_test(DOUBLE, sampled_path(time, u, load - 0.7 * WEIGHT))
    heated = dataclasses.replace(DOUBLE, bottom_heating=FrictionalHeating(contact_area=0.05), bottom_pressure=30e6)
    assert heated.heated
    with pytest.raises(ValueError, match="path.normal_load: .*constant"):
        imposed_path_test(heated, sampled_path(time, u, load))
    assert bool(np.all(imposed_path_test(heated, sampled_path(time, u, WEIGHT)).converged))
    rounded = WEIGHT * (1 + 1e-12 * np.sin(time))  # one load to rounding, as diagnose takes it
    assert not bool(normal_load_varies(rounded)) and bool(normal_load_varies(load))
    assert bool(np.all(imposed_path_test(heated, sampled_path(time, u, rounded)).converged))
    pressed = dataclasses.replace(DOUBLE, top_pressure=25e6, surface_parts=(None, SurfaceParts(
        pressure_dependence=PressureDependence(exponent=0.3, reference_load=WEIGHT, contact_area=0.04))))
    assert pressed.reads_pressure and not pressed.heated
    with pytest.raises(ValueError, match="path.normal_load: it varies, .*reference_load") as refused:
        imposed_path_test(pressed, sampled_path(time, u, load))
    assert "positive" not in str(refused.value)  # what is wrong, and only that
    for pendulum in (heated, pressed):
        assert bool(np.all(imposed_path_test(pendulum, sampled_path(time, u, load), reference_load=WEIGHT).converged))
        with pytest.raises(ValueError, match="reference_load: give the positive load"):
            imposed_path_test(pendulum, sampled_path(time, u, load), reference_load=-WEIGHT)
    motion, recorded = SineMotion(0.15, 0.5, cycles=1), uniform_signal(load, float(time[1]))
    with pytest.raises(ValueError, match="path.normal_load: .*reference_load"):
        imposed_path_test(pressed, motion, recorded)
    assert bool(np.all(imposed_path_test(pressed, motion, recorded, reference_load=WEIGHT).converged))
    with pytest.raises(ValueError, match="reference_load: a sliding bearing"):
        imposed_path_test(paper_bearing(FrictionParameters(0.1, 0.05, 20.0)), motion, WEIGHT,
                              reference_load=WEIGHT)
    with pytest.raises(ValueError, match="reference_load: a sliding bearing"):
        imposed_path_test(paper_bearing(FrictionParameters(0.1, 0.05, 20.0)), sampled_path(time, u, load),
                           reference_load=WEIGHT)
    kernel = heat_kernel_exponentials(0.01, 3600.0)
    traced = jax.jit(lambda b, p: imposed_path_test(b, p, heat_kernel=kernel))
    with pytest.raises(Exception, match="constant normal load"):  # traced: refused when run
        jax.block_until_ready(traced(heated, sampled_path(time, u, load)).force)


def test_the_heat_flux_takes_the_pressure_times_n_over_the_reference_load():
    """q = mu p (N / W_ref) v: a heated double pendulum at N = W told W_ref = W / 2 heats as the
    same pendulum with twice the contact pressure told nothing, to rounding, and more than the
    pendulum at its own pressure."""
    time, u, _ = _path()
    heated = dataclasses.replace(DOUBLE, bottom_heating=FrictionalHeating(contact_area=0.05, heat_scale=20.0),
                                 bottom_pressure=30e6)
    doubled = dataclasses.replace(heated, bottom_pressure=60e6)
    path = sampled_path(time, u, WEIGHT)
    halved = np.asarray(imposed_path_test(heated, path, reference_load=WEIGHT / 2).force)
    np.testing.assert_allclose(halved, np.asarray(imposed_path_test(doubled, path).force), rtol=0,
                               atol=1e-12 * WEIGHT)
    assert np.max(np.abs(halved - np.asarray(imposed_path_test(heated, path).force))) > 1e-4 * WEIGHT


def test_a_fit_refuses_a_varying_load_on_a_start_whose_surfaces_read_their_pressure():
    """The record's N varies and the start's top surface reads its contact pressure, given
    under a load neither states: refused by the record's name and the surface before any solve
    (the fit and diagnose alike)."""
    time, u, load = _path()
    pressed = dataclasses.replace(DOUBLE, top_pressure=25e6, surface_parts=(None, SurfaceParts(
        pressure_dependence=PressureDependence(exponent=0.3, reference_load=WEIGHT, contact_area=0.04))))
    force = np.asarray(imposed_path_test(pressed, sampled_path(time, u, load), reference_load=WEIGHT).force)
    record = test_record_from_arrays(u, force, time=time, normal_load=load)
    with pytest.raises(ValueError, match=r"record 0: its normal load varies .* surfaces top read"):
        fit_series_pendulum_test(record, pressed, max_steps=1)
    with pytest.raises(ValueError, match=r"record 0: its normal load varies .* surfaces top read"):
        prepare_series_problem(record, pressed)  # diagnose's


def test_options_one_kind_does_not_take_are_refused_by_name():
    time, u, load = _path()
    path = sampled_path(time, u, WEIGHT)
    with pytest.raises(ValueError, match="z0"):
        imposed_path_test(DOUBLE, path, z0=0.5)
    with pytest.raises(ValueError, match="z_peak0"):
        imposed_path_test(DOUBLE, path, z_peak0=1.0)
    with pytest.raises(ValueError, match="temperature_rise"):
        imposed_path_test(DOUBLE, sampled_path(time, u, WEIGHT, temperature_rise=0 * time))
    flat = paper_bearing(FrictionParameters(0.1, 0.05, 20.0))
    with pytest.raises(ValueError, match="heat_kernel"):
        imposed_path_test(flat, path, heat_kernel=(np.ones(1), np.ones(1)))
    with pytest.raises(ValueError, match="friction_velocity"):
        imposed_path_test(flat, path, friction_velocity="mean")
    worn = dataclasses.replace(flat, wear=Wear(0.1, 1.0))
    motion = SineMotion(amplitude=0.05, frequency=0.5, cycles=1)
    for options, named in (({"solver": diffrax.Tsit5()}, "solver"), ({"rtol": 1e-6, "atol": 1e-9}, "rtol, atol"),
                           ({"max_steps": 10}, "max_steps"), ({"adjoint": diffrax.ForwardMode()}, "adjoint")):
        with pytest.raises(ValueError, match=f"^{named}: a bearing with wear is driven along the sampled motion"):
            imposed_path_test(worn, motion, WEIGHT, **options)
    with pytest.raises(ValueError, match="^rtol: a bearing along x with the paper's Bouc-Wen shape .* give a "
                                         "diffrax solver"):
        imposed_path_test(flat, motion, WEIGHT, rtol=1e-6)
    along_x = imposed_path_test(worn, motion, WEIGHT, solver=RiccatiNewmark(), samples_per_cycle=50)
    np.testing.assert_array_equal(along_x.fx, imposed_path_test(worn, motion, WEIGHT, samples_per_cycle=50).fx)
    with pytest.raises(ValueError, match="ux: .*n, 2"):
        sampled_path(time, np.stack([u, u, u], -1), WEIGHT)
    with pytest.raises(ValueError, match="park_elements: .*under tracing"):
        jax.jit(lambda v: sampled_path(time, v, WEIGHT).ux)(np.stack([u, u], -1))
    assert jax.jit(lambda v: sampled_path(time, v, WEIGHT, park_elements=16).park_elements)(u) == 16


def test_a_sliding_bearings_test_along_x_is_its_force_along_the_sampled_motion():
    """The test that `simulate-test` writes and the force a fit of that record evaluates are one
    computation (`imposed_path_test`) for every sliding bearing along x, with or without
    optional parts: bit for bit at the samples, with the motion's own velocity; a diffrax
    solver, asked for, integrates Eq. 3 instead, to its tolerance."""
    motion = SineMotion(amplitude=0.05, frequency=0.5, cycles=2)
    for bearing in (paper_bearing(FrictionParameters(0.1, 0.05, 20.0), breakaway_ratio=1.6),
                    dataclasses.replace(paper_bearing(FrictionParameters(0.1, 0.05, 20.0)), wear=Wear(0.1, 1.0))):
        test = imposed_path_test(bearing, motion, WEIGHT, samples_per_cycle=200)
        path = sampled_path(test.time, jax.vmap(motion.displacement)(test.time)[:, 0], test.normal_load,
                            velocity=jax.vmap(motion.velocity)(test.time)[:, 0])
        along = imposed_path_test(bearing, path)
        np.testing.assert_array_equal(test.fx, along.fx)
        np.testing.assert_array_equal(test.z, along.z)
    plain = paper_bearing(FrictionParameters(0.1, 0.05, 20.0))
    exact = imposed_path_test(plain, motion, WEIGHT, samples_per_cycle=200)
    general = imposed_path_test(plain, motion, WEIGHT, samples_per_cycle=200, solver=diffrax.Tsit5(),
                                    rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(exact.fx, general.fx, rtol=0, atol=1e-6 * WEIGHT)


def test_the_mean_speed_of_a_step_is_its_increment_over_its_own_interval():
    """On samples at uneven intervals, one surface's force is Eq. 1 at |du| / dt of each step's
    own interval: F = N (u / R + f_min Z + (mu(|du| / dt) - f_min) <sgn(du) Z>_+ sgn(du))."""
    friction = FrictionParameters(0.10, 0.05, 20.0)
    pendulum = single_pendulum(paper_bearing(friction), radius=2.0, capacity=1.0)
    rng = np.random.default_rng(4)
    time = np.concatenate([[0.0], np.cumsum(rng.uniform(0.004, 0.02, 500))])
    u = 0.1 * np.sin(2 * np.pi * time / 2.0)
    test = imposed_path_test(pendulum, sampled_path(time, u, WEIGHT))
    z = np.asarray(test.z)[:, 0]
    du, dt = np.diff(u), np.diff(time)
    mu = friction.f_max - friction.delta_f * np.exp(-friction.rate_a * np.abs(du) / dt)
    f_min = friction.f_max - friction.delta_f
    n = np.sign(du)
    expected = WEIGHT * (u[1:] / 2.0 + f_min * z[1:] + (mu - f_min) * np.maximum(n * z[1:], 0.0) * n)
    np.testing.assert_allclose(np.asarray(test.force)[1:] / WEIGHT, expected / WEIGHT, rtol=0, atol=1e-11)
