"""Frictional heating of each surface of the series friction pendulums: a double pendulum
whose top surface never slides against the single pendulum on a heated flat bearing, the
constant-flux temperature rise of Carslaw & Jaeger in a bearing test, the neutral heat
scale, the derivative in a radius, a strong heating's steps balanced and converged in the
step, a test path along a line in the plane, and what is refused."""

import dataclasses

import equinox as eqx
import jax
import numpy as np
import pytest
from histories import planar_histories

from teflon_jax.bearing import (
    DoublePendulum,
    FrictionalHeating,
    check_double_pendulum,
    concave_surface,
    coulomb_friction,
    kumar_temperature_factor,
    paper_bearing,
    surface_temperature_coefficient,
)
from teflon_jax.excitation import uniform_signal
from teflon_jax.systems import (
    imposed_path_test,
    isolated_structure,
    peak_response,
    sampled_path,
    simulate_history,
)

R1, MU, PRESSURE = 1.5, 0.06, 30e6
HEAT = FrictionalHeating(contact_area=0.05)
HYSTERESIS = paper_bearing(coulomb_friction(MU)).hysteresis


def _locked_top(heating=HEAT, pressure=PRESSURE, **changes):
    """A double pendulum whose top surface (f_max 5) never slides: the bottom one is a single
    pendulum of radius R1."""
    values = dict(bottom_radius=R1, top_radius=2.0, bottom_capacity=1.0, top_capacity=1.0,
                  bottom_friction=coulomb_friction(MU), top_friction=coulomb_friction(5.0),
                  hysteresis=HYSTERESIS, bottom_heating=heating,
                  bottom_pressure=None if heating is None else pressure)
    values.update(changes)
    return DoublePendulum(**values)


def _ground(dt, duration=6.0):
    t = np.arange(0, duration + dt / 2, dt)
    return uniform_signal(4.0 * np.sin(2 * np.pi * t / 1.5) * np.exp(-0.1 * t), dt)


def _double(dt, heating):
    system = isolated_structure("rigid", isolator=_locked_top(heating), time_step=dt)
    response = jax.jit(simulate_history, static_argnums=1)(system(_ground(dt)), 6.0)
    assert bool(np.all(response.converged))
    return np.asarray(response.displacement[:, 0])


def _single(dt, heating):
    bearing = paper_bearing(coulomb_friction(MU))
    if heating is not None:
        bearing = eqx.tree_at(lambda b: b.heating, bearing, heating, is_leaf=lambda x: x is None)
    system = isolated_structure("rigid", isolator=(bearing, concave_surface(R1)), pressure=PRESSURE,
                                time_step=dt, split_at_turn=False, breakaway=False)
    return np.asarray(jax.jit(simulate_history, static_argnums=1)(system(_ground(dt)), 6.0).displacement[:, 0])


@pytest.mark.slow
def test_a_heated_bottom_surface_is_the_heated_single_pendulum():
    """Top surface locked: the double pendulum is the single pendulum of radius R1 on a flat
    bearing with the same heating. Without heating the two agree to the top slider's elastic
    play (~1e-5 of the peak); with heating the two models differ only in the force at a
    step's start (carried from the last step here, recomputed with the new factor on the
    flat bearing), an O(dt) difference that halves with the step; the heating's own effect
    (the peak grows by ~10 %) is the same to 0.2 % of it, 0.1 % at half the step."""
    gaps = []
    for dt in (0.005, 0.0025):
        cold_d, cold_s, hot_d, hot_s = _double(dt, None), _single(dt, None), _double(dt, HEAT), _single(dt, HEAT)
        peak = np.abs(hot_s).max()
        assert np.abs(cold_d - cold_s).max() < 1e-4 * np.abs(cold_s).max()
        gaps.append(np.abs(hot_d - hot_s).max() / peak)
        effect = hot_s - cold_s
        assert np.abs(effect).max() > 0.05 * peak
        assert np.abs((hot_d - cold_d) - effect).max() < 3e-3 * np.abs(effect).max()
    assert gaps[0] < 5e-4
    assert gaps[1] < 0.6 * gaps[0]


def test_the_friction_falls_as_the_constant_flux_rise_of_carslaw_and_jaeger():
    """A bearing test sliding the bottom surface at constant speed v: the flux q = mu p v is
    (nearly) constant, the surface warms by dT = 2 q sqrt(kappa t / pi) / k, and the friction
    falls as k_T(T0 + dT) / k_T(T0) (Kumar et al. 2015); the top surface, unheated, keeps its
    friction. The rise here is ~2 K, so the friction's own fall changes q by < 1 %."""
    speed, pressure = 0.05, 3e6
    time = np.linspace(0.0, 2.0, 801)
    bearing = _locked_top(pressure=pressure)
    response = imposed_path_test(bearing, sampled_path(time, speed * time, 1e6))
    assert bool(np.all(response.converged))
    slider = np.asarray(response.slider[:, 0])
    mu = np.asarray(response.force) / 1e6 - slider / R1
    rise = 2 * MU * pressure * speed * surface_temperature_coefficient() * np.sqrt(time)
    expected = MU * kumar_temperature_factor(20.0 + rise) / kumar_temperature_factor(20.0)
    later = time > 0.2
    assert MU - mu[-1] > 4e-3 * MU  # the friction does fall
    np.testing.assert_allclose(MU - mu[later], MU - np.asarray(expected)[later], rtol=5e-2)
    assert np.all(np.diff(mu[later]) < 0)


@pytest.mark.slow
def test_a_heated_surface_slides_further_and_a_zero_heat_scale_changes_nothing():
    """Heating lowers the friction, so the isolator moves further; with heat_scale 0 the
    factor is exactly 1 and the response is bit for bit the unheated one (structure and
    bearing test), whatever the pressure."""
    dt = 0.005
    cold, hot = _double(dt, None), _double(dt, HEAT)
    assert np.abs(hot).max() > 1.05 * np.abs(cold).max()
    neutral = FrictionalHeating(contact_area=0.05, heat_scale=0.0)
    np.testing.assert_array_equal(_double(dt, neutral), cold)
    time = np.linspace(0.0, 6.0, 601)
    path = 0.3 * np.sin(2 * np.pi * time / 3.0)
    both = _locked_top(neutral, top_friction=coulomb_friction(0.08), top_heating=neutral, top_pressure=1e7)
    plain = _locked_top(None, top_friction=coulomb_friction(0.08))
    np.testing.assert_array_equal(np.asarray(imposed_path_test(both, sampled_path(time, path, 1e6)).force),
                                  np.asarray(imposed_path_test(plain, sampled_path(time, path, 1e6)).force))


@pytest.mark.slow
def test_the_heated_peak_is_differentiable_in_the_bottom_radius():
    """d(smooth peak)/dR_1 by reverse mode through the heat states, against central differences."""
    dt = 0.01
    bearing = _locked_top(top_friction=coulomb_friction(0.09), top_heating=HEAT, top_pressure=PRESSURE)
    system = isolated_structure("rigid", isolator=bearing, time_step=dt)(_ground(dt))

    def peak(radius):
        moved = eqx.tree_at(lambda s: s.pendulum.bottom_radius, system, radius)
        return peak_response(moved, 6.0).smooth_base_disp

    assert bool(peak_response(system, 6.0).converged)
    reverse = float(jax.jit(jax.grad(peak))(R1))
    h = 1e-4
    central = (float(peak(R1 + h)) - float(peak(R1 - h))) / (2 * h)
    assert abs(central) > 1e-3
    assert reverse == pytest.approx(central, rel=1e-4)


def _both_heated(pressure=30e6):
    """Both surfaces heated at `pressure` [Pa], the top one (f_max 0.09) sliding too."""
    return _locked_top(pressure=pressure, top_friction=coulomb_friction(0.09), top_heating=HEAT,
                       top_pressure=pressure)


def _energies(dt):
    """Histories of the rigid mass on `_both_heated` at step dt: (u, the bearing's work
    int F du [J], the energy balance's largest gap |E_in - E_k - int F du| over max E_in, all
    steps balanced); E_in = -int m a_g du, E_k = m v^2 / 2 (trapezoids)."""
    system = isolated_structure("rigid", isolator=_both_heated(), time_step=dt)(_ground(dt))
    r = jax.jit(simulate_history, static_argnums=1)(system, 6.0)
    u, v, force, ground = (np.asarray(a) for a in (r.displacement[:, 0], r.velocity[:, 0], r.bearing_force,
                                                   r.ground[:, 0]))
    mass, du = float(system.mass[0]), np.diff(u)
    work = np.concatenate([[0.0], np.cumsum(0.5 * (force[1:] + force[:-1]) * du)])
    supplied = np.concatenate([[0.0], np.cumsum(-mass * 0.5 * (ground[1:] + ground[:-1]) * du)])
    gap = np.abs(supplied - 0.5 * mass * v**2 - work).max() / supplied.max()
    return u, work[-1], gap, bool(np.all(r.converged))


@pytest.mark.slow
def test_a_strong_heating_balances_every_step_and_converges_in_the_step():
    """30 MPa on both surfaces: the sliding surface's friction drops by several per cent in a
    step while the other reverses, where a full Newton step overshoots the reversal's kink;
    the line search's second stage balances every step. The energy balance closes to O(dt^2)
    (the gap falls fourfold as the step halves), and the history and the bearing's work
    approach those at 0.625 ms as the step halves."""
    fine_u, fine_work, fine_gap, fine_ok = _energies(0.000625)
    errors = []
    for dt in (0.005, 0.0025):
        u, work, gap, ok = _energies(dt)
        assert ok and fine_ok
        stride = round(dt / 0.000625)
        errors.append((np.abs(u - fine_u[::stride]).max() / np.abs(fine_u).max(), abs(work - fine_work) / fine_work,
                       gap))
    (u5, work5, gap5), (u25, work25, gap25) = errors
    assert u5 < 6e-3 and work5 < 5e-3 and gap5 < 3e-5
    assert u25 < 0.65 * u5 and work25 < 0.85 * work5
    assert gap25 < 0.3 * gap5 and fine_gap < 0.1 * gap25


def test_a_strong_heating_balances_the_bearing_test_in_the_step():
    """The bearing test of the same pendulum (0.3 m at 1/3 Hz): every sample balances, and the
    force at 5 ms is the force at 1.25 ms to 5 % of the peak (within a step of each surface's
    switch between sliding and sticking) and the loop's work to 0.5 %."""
    runs = []
    for n in (1200, 4800):
        time = np.linspace(0.0, 6.0, n + 1)
        path = 0.3 * np.sin(2 * np.pi * time / 3.0)
        response = imposed_path_test(_both_heated(), sampled_path(time, path, 1e6))
        assert bool(np.all(response.converged))
        force = np.asarray(response.force)
        runs.append((force, np.sum(0.5 * (force[1:] + force[:-1]) * np.diff(path))))
    (coarse, coarse_work), (fine, fine_work) = runs
    assert np.abs(coarse - fine[::4]).max() < 0.05 * np.abs(fine).max()
    assert abs(coarse_work - fine_work) < 5e-3 * fine_work


@pytest.mark.slow  # reverse mode through 1200 heated steps: about a minute on two cores
def test_the_derivative_through_a_rebalanced_step_is_the_central_difference():
    """d(smooth peak)/dR_1 at 5 ms, where one step of `_both_heated` needs the second stage:
    the implicit derivative at the balanced root against central differences."""
    dt = 0.005
    system = isolated_structure("rigid", isolator=_both_heated(), time_step=dt)(_ground(dt))

    def peak(radius):
        return peak_response(eqx.tree_at(lambda s: s.pendulum.bottom_radius, system, radius), 6.0).smooth_base_disp

    assert bool(peak_response(system, 6.0).converged)
    h = 1e-4
    central = (float(peak(R1 + h)) - float(peak(R1 - h))) / (2 * h)
    assert float(jax.jit(jax.grad(peak))(R1)) == pytest.approx(central, rel=1e-5)


@pytest.mark.parametrize("changes, message", [
    (dict(bottom_pressure=None), "bottom_pressure: a surface with bottom_heating needs"),
    (dict(bottom_pressure=-1.0), "bottom_pressure"),
    (dict(bottom_heating=FrictionalHeating(contact_area=0.0)), "bottom_heating.contact_area"),
    (dict(bottom_heating=FrictionalHeating(0.05, heat_scale=-1.0)), "bottom_heating.heat_scale"),
    (dict(top_heating=FrictionalHeating(0.05, initial_temperature=-300.0)), "top_heating.initial_temperature"),
])
def test_bad_heating_is_refused_by_name(changes, message):
    bearing = _locked_top(**changes)
    with pytest.raises(ValueError, match=message):
        check_double_pendulum(bearing)


@pytest.mark.slow
def test_two_components_along_a_line_are_the_heated_one_direction_response():
    """Both surfaces heated and sliding: a record along x (y at rest) gives the one-direction
    histories to the sliders' balance tolerance (as it does unheated), one along 0.6 rad the same response turned (the heat flux takes the
    length of each surface's increment)."""
    dt = 0.005
    bearing = _locked_top(pressure=10e6, top_friction=coulomb_friction(0.09), top_heating=HEAT, top_pressure=10e6)
    ground = _ground(dt)
    acc = np.asarray(jax.vmap(ground)(np.arange(0, 6 + dt / 2, dt)))
    structure = isolated_structure("rigid", isolator=bearing, time_step=dt)
    one = jax.jit(simulate_history, static_argnums=1)(structure(ground), 6.0)
    u, slider = np.asarray(one.displacement[:, 0]), np.asarray(one.slider)
    assert np.abs(slider).max(axis=0).min() > 0.05  # both surfaces slide
    assert bool(np.all(one.converged))
    histories = jax.jit(planar_histories, static_argnums=1)
    planar = dataclasses.replace(structure, components=2)  # bidirectional_isolated_structure's
    along_x = histories(planar((ground, uniform_signal(0 * acc, dt))), 6.0)
    np.testing.assert_allclose(along_x[1][:, 0, 0], u, rtol=0, atol=1e-9)
    c, s = np.cos(0.6), np.sin(0.6)
    _, x, _, sliders, _, ok = histories(planar((uniform_signal(c * acc, dt), uniform_signal(s * acc, dt))), 6.0)
    assert bool(np.all(ok))
    np.testing.assert_allclose(x[:, 0, 0], c * u, rtol=0, atol=1e-9)
    np.testing.assert_allclose(x[:, 1, 0], s * u, rtol=0, atol=1e-9)
    np.testing.assert_allclose(np.asarray(sliders)[:, :, 1], s * slider, rtol=0, atol=1e-9)


def test_a_test_path_along_a_line_in_the_plane_is_the_heated_one_axis_test():
    """Both surfaces heated (30 MPa) and sliding: a bearing test along a line at 0.6 rad is
    the one-axis test turned, forces to 2e-5 N of a ~1.5e5 N peak (2e-11 W: each test step is
    balanced to 1e-12 W) and slider displacements to 1e-11 m (each surface's flux takes the
    length of its increment, Park's Z along a line is Bouc-Wen's), while the heating itself moves the force by > 1e4 N."""
    time = np.linspace(0.0, 3.0, 601)
    path = 0.3 * np.sin(2 * np.pi * time / 3.0)
    one = imposed_path_test(_both_heated(), sampled_path(time, path, 1e6))
    c, s = np.cos(0.6), np.sin(0.6)
    two = imposed_path_test(_both_heated(), sampled_path(time, np.stack([c * path, s * path], -1), 1e6))
    assert bool(np.all(one.converged)) and bool(np.all(two.converged))
    force, turned = np.asarray(one.force), np.asarray(two.force)
    cold = np.asarray(imposed_path_test(_locked_top(None, top_friction=coulomb_friction(0.09)), sampled_path(time, path, 1e6)).force)
    assert np.abs(force - cold).max() > 1e4
    np.testing.assert_allclose(turned[:, 0], c * force, rtol=0, atol=2e-5)
    np.testing.assert_allclose(turned[:, 1], s * force, rtol=0, atol=2e-5)
    np.testing.assert_allclose(np.asarray(two.slider)[..., 1], s * np.asarray(one.slider), rtol=0, atol=1e-11)


def _isolator_document():
    def surface(radius, mu, heating=None):
        part = {"radius": {"value": radius, "unit": "m"}, "capacity": {"value": 0.2, "unit": "m"},
                "friction": {"f_max": {"value": mu, "unit": "1"}, "delta_f": {"value": 0.0, "unit": "1"},
                             "rate_a": {"value": 0.0, "unit": "s/m"}}}
        if heating:
            part["heating"] = {"contact_area": {"value": 500, "unit": "cm^2"},
                               "contact_pressure": {"value": 30, "unit": "MPa"},
                               "heat_scale": {"value": 1, "unit": "1"},
                               "conductivity": {"value": 16.2, "unit": "W/(m K)"},
                               "diffusivity": {"value": 4.4, "unit": "mm^2/s"},
                               "initial_temperature": {"value": 10, "unit": "degC"}}
        return part

    return {"format": "teflon-jax isolator", "format_version": 1, "isolator": "double-fp",
            "surfaces": {"bottom": surface(1.5, 0.04, heating=True), "top": surface(2.5, 0.08)},
            "yield_disp": {"value": 1e-4, "unit": "m"}}


def test_the_isolator_file_reads_and_writes_a_surface_heating(tmp_path):
    from teflon_jax.formats import isolator_from_dict, load_isolator, write_isolator

    bearing = isolator_from_dict(_isolator_document())
    assert bearing.top_heating is None and bearing.top_pressure is None
    assert float(bearing.bottom_pressure) == pytest.approx(30e6, rel=1e-12)
    assert float(bearing.bottom_heating.contact_area) == pytest.approx(0.05, rel=1e-12)
    assert float(bearing.bottom_heating.diffusivity) == pytest.approx(4.4e-6, rel=1e-12)
    assert float(bearing.bottom_heating.initial_temperature) == 10.0
    write_isolator(tmp_path / "dfp.json", bearing)
    again = load_isolator(tmp_path / "dfp.json")
    for a, b in zip(jax.tree_util.tree_leaves(bearing), jax.tree_util.tree_leaves(again)):
        assert float(a) == pytest.approx(float(b), rel=1e-15)
    assert again.top_heating is None and again.bottom_heating is not None


@pytest.mark.parametrize("key, value, message", [
    ("contact_pressure", None, r"surfaces.bottom.heating: missing \['contact_pressure'\]"),
    ("contact_pressure", 30.0, r"surfaces.bottom.heating.contact_pressure: write"),
    ("contact_pressure", {"value": -1.0, "unit": "MPa"}, "surfaces.bottom.heating.contact_pressure"),
    ("contact_area", {"value": 0.05, "unit": "m"}, r"surfaces.bottom.heating.contact_area.unit"),
    ("heat_scale", {"value": -1.0, "unit": "1"}, "surfaces.bottom.heating.heat_scale"),
    ("speed", {"value": 1.0, "unit": "1"}, r"surfaces.bottom.heating: unknown \['speed'\]"),
])
def test_a_bad_surface_heating_is_refused_by_key(key, value, message):
    from teflon_jax.formats import isolator_from_dict

    document = _isolator_document()
    heating = document["surfaces"]["bottom"]["heating"]
    if value is None:
        del heating[key]
    else:
        heating[key] = value
    with pytest.raises(ValueError, match=message):
        isolator_from_dict(document, where="dfp.json")


def test_simulate_test_runs_a_heated_isolator_file(tmp_path, capsys):
    """`simulate-test --isolator-file` with a heated bottom surface: the loop's force at the
    last peak is below the unheated file's (the bottom surface, the slipperier, slides first)."""
    import json

    from teflon_jax.cli import main
    from teflon_jax.formats import read_test_record

    heated = _isolator_document()
    cold = json.loads(json.dumps(heated))
    del cold["surfaces"]["bottom"]["heating"]
    peaks = []
    for name, document in (("hot", heated), ("cold", cold)):
        (tmp_path / f"{name}.json").write_text(json.dumps(document))
        code = main(["simulate-test", "--isolator-file", str(tmp_path / f"{name}.json"), "--normal-load", "1MN",
                     "--amplitude", "0.1m", "--frequency", "0.5Hz", "--cycles", "3",
                     "--samples-per-cycle", "400", "--out", str(tmp_path / f"{name}.csv")])
        assert code == 0, capsys.readouterr().err
        record = read_test_record(tmp_path / f"{name}.csv")
        u, f = np.asarray(record.ux), np.asarray(record.fx)
        peaks.append(f[np.argmax(u[-400:]) + len(u) - 400])
    assert peaks[0] < peaks[1] - 0.002 * 1e6
