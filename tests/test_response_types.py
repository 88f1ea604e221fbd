"""One response type for every structure's history (`StructureResponse`, `simulate_history`),
one mapping of the peaks (`Peaks` of `peak_response`, the smooth maximum written once) and one for imposed-path
tests (`BearingTestResult`): the drivers only package their engines' histories; the structure
on series pendulums is a `StructureOnSliders` whose steps `simulate_history` chooses."""

import dataclasses

import diffrax
import jax
import jax.numpy as jnp
import numpy as np
import pytest

from teflon_jax.bearing import BoucWen, DoublePendulum, FrictionParameters, TriplePendulum
from teflon_jax.excitation import uniform_signal
from teflon_jax.studies import bidirectional_isolated_structure
from teflon_jax.systems import (
    Peaks,
    StructureOnSliders,
    StructureResponse,
    imposed_path_test,
    isolated_structure,
    peak_response,
    sampled_path,
    simulate_history,
    smooth_max,
    smooth_max_update,
    smooth_max_value,
    structure_on_sliders,
    triple_structure,
)

STEP = 0.01
TIME = np.arange(0.0, 1.5 + 1e-9, STEP)
AX = 4.0 * np.sin(2 * np.pi * TIME) * np.minimum(TIME / 0.3, 1.0)
AY = 3.0 * np.cos(2 * np.pi * 1.3 * TIME) * np.minimum(TIME / 0.3, 1.0)
TRIPLE = TriplePendulum(inner_radius=0.3, bottom_radius=2.1, top_radius=2.1, inner_capacity=0.05,
                        bottom_capacity=0.4, top_capacity=0.4, inner_friction=FrictionParameters(0.03, 0.015, 20.0),
                        bottom_friction=FrictionParameters(0.07, 0.03, 20.0),
                        top_friction=FrictionParameters(0.11, 0.05, 20.0), hysteresis=BoucWen(1e-4))


def _signals():
    return uniform_signal(AX, STEP), uniform_signal(AY, STEP)


def _same_tree(a, b):
    leaves_a, tree_a = jax.tree_util.tree_flatten(a)
    leaves_b, tree_b = jax.tree_util.tree_flatten(b)
    assert tree_a == tree_b
    for x, y in zip(leaves_a, leaves_b):
        np.testing.assert_array_equal(np.asarray(x), np.asarray(y))


def test_one_driver_takes_every_structure_and_refuses_by_name_what_its_engine_does_not():
    """`simulate_history` steps every structure by its engine (keeping every `save_every`-th
    step, each with its `converged`), refusing the adaptive solve's options there, and solves
    flat sliders on their grid with an adaptive solver (its `result`; series pendulums have no
    such solve). Every engine rounds the duration down to whole steps: 1.0049 s of 5 ms steps
    is 200 steps, not the 201 of the nearest whole number, whose end lies past the duration."""
    gx, gy = _signals()
    rigid = isolated_structure("rigid", time_step=0.005)(gx)
    flat = simulate_history(rigid, 1.0049, save_every=2)
    np.testing.assert_allclose(np.diff(np.asarray(flat.time)), 2 * rigid.time_step, rtol=1e-12)
    assert flat.time.size == 101 and flat.displacement.shape == (101, 1) and flat.converged.shape == (101,)
    assert flat.result is None and bool(flat.succeeded)
    planar = simulate_history(bidirectional_isolated_structure("rigid", time_step=0.005)((gx, gy)), 1.0049)
    assert planar.ground.shape == (201, 2) and planar.bearing_displacement.shape == (201, 1, 2)
    assert planar.converged.shape == (201,) and planar.z.shape == (201, 1, 2)
    series = triple_structure("rigid", TRIPLE, gx, time_step=0.005)
    assert isinstance(series, StructureOnSliders) and series.pendulum is TRIPLE
    stepped = simulate_history(series, 1.0049)
    assert stepped.slider.shape == (201, 3) and stepped.converged.shape == (201,)
    for response in (flat, planar, stepped):
        np.testing.assert_allclose(float(response.time[-1]), 1.0, rtol=1e-12)
    np.testing.assert_array_equal(np.asarray(simulate_history(series, 1.0049, save_every=2).slider),
                                  np.asarray(stepped.slider)[::2])
    with pytest.raises(ValueError, match="rtol, adjoint: the fixed steps take no tolerances"):
        simulate_history(rigid, 1.0, rtol=1e-6, adjoint=diffrax.ForwardMode())
    with pytest.raises(ValueError, match="solver: a structure on series pendulums steps only at its time_step"):
        simulate_history(series, 1.0, solver=diffrax.Tsit5(), throw=False)
    adaptive = simulate_history(rigid, 1.0049, save_every=2, solver=diffrax.Tsit5(), rtol=1e-6)
    assert adaptive.result is not None and adaptive.converged is None and adaptive.time.size == 101
    # every step balanced: throw=False (the suites' option under vmap) gives the same history
    np.testing.assert_array_equal(np.asarray(simulate_history(series, 1.0, throw=False).slider),
                                  np.asarray(stepped.slider))
    with pytest.raises(TypeError, match="system: no history driver"):
        simulate_history(TRIPLE, 1.0)
    for bad in (0, 1.5):
        with pytest.raises(ValueError, match=f"save_every: must be a positive integer number of steps, got {bad}"):
            simulate_history(rigid, 1.0, save_every=bad)


def test_every_kth_step_kept_still_says_which_steps_did_not_converge():
    """Flat sliders with one Newton iteration per step (a real miss: 3 of 580 steps at 5 ms
    under a 0.6 g sine along x, at steps 350, 433 and 534): kept every 10th step, the samples
    that close the stretches holding those steps (35, 44 and 54) say so, and no other; every
    step kept, exactly those steps; the same run balances with the default iterations."""
    time = np.arange(0.0, 3.0 + 1e-9, STEP)
    gx = uniform_signal(6.0 * np.sin(2 * np.pi * time), STEP)
    short = isolated_structure("rigid", time_step=0.005, newton_iterations=1)(gx)
    every = simulate_history(short, 2.9, throw=False)
    missed = np.flatnonzero(~np.asarray(every.converged))
    np.testing.assert_array_equal(missed, [350, 433, 534])
    tenth = simulate_history(short, 2.9, save_every=10, throw=False)
    np.testing.assert_array_equal(np.flatnonzero(~np.asarray(tenth.converged)), [35, 44, 54])
    np.testing.assert_array_equal(np.asarray(tenth.displacement), np.asarray(every.displacement)[::10])
    assert not bool(tenth.succeeded)
    with pytest.raises(Exception, match="the isolators' balance .* missed its tolerance"):
        jax.block_until_ready(simulate_history(short, 2.9, save_every=10))
    assert bool(simulate_history(isolated_structure("rigid", time_step=0.005)(gx), 2.9).succeeded)


def test_a_series_structure_raises_where_a_step_missed_its_balance_unless_told_to_keep_it():
    """A step whose sliders' balance misses its tolerance raises, as a diffrax solve that fails
    does; with throw=False the response is kept and `converged` names the step. A real miss: a
    double pendulum under two components of 0.6 g at 10 ms steps with no Newton iteration
    beyond the rescue stage leaves one step (at 2.71 s) short; with them every step balances."""
    double = DoublePendulum(bottom_radius=2.1, top_radius=1.8, bottom_capacity=0.3, top_capacity=0.3,
                            bottom_friction=FrictionParameters(0.06, 0.03, 20.0),
                            top_friction=FrictionParameters(0.09, 0.04, 20.0), hysteresis=BoucWen(1.27e-4))
    time = np.arange(0.0, 3.0 + 1e-9, STEP)
    gx, gy = (uniform_signal(6.0 * f(2 * np.pi * time), STEP) for f in (np.sin, np.cos))
    short = triple_structure("rigid", double, gx, time_step=0.01, ground_y=gy, newton_iterations=0)
    kept = simulate_history(short, 2.9, throw=False)
    assert np.flatnonzero(~np.asarray(kept.converged)).size >= 1 and not bool(kept.succeeded)
    with pytest.raises(Exception, match="the isolators' balance .* missed its tolerance"):
        jax.block_until_ready(simulate_history(short, 2.9))  # raised as the run ends
    balanced = simulate_history(triple_structure("rigid", double, gx, time_step=0.01, ground_y=gy), 2.9)
    assert bool(np.all(balanced.converged)) and bool(balanced.succeeded)


def test_the_one_structure_refuses_by_name_what_its_isolator_does_not_take():
    """Series pendulums go on a linear structure through `structure_on_isolator`; a y component
    on flat sliders is taken by their bearing groups; a planar balance is one of `BALANCES`."""
    gx, gy = _signals()
    with pytest.raises(ValueError, match="bearing: triple friction pendulums .* structure_on_isolator"):
        structure_on_sliders(mass=1e4, stiffness=0.0, damping=0.0, bearing=TRIPLE, bearing_load=1e5,
                             ground_acceleration=gx, time_step=0.01)
    with pytest.raises(ValueError, match="ground_y: .* bearing groups .*influence and bearing_map"):
        isolated_structure("rigid")(gx).with_y_component(gy)
    with pytest.raises(ValueError, match="balance: unknown 'broyden'; accepted: newton, secant"):
        triple_structure("rigid", TRIPLE, gx, time_step=0.005, ground_y=gy, balance="broyden")
    short_y = uniform_signal(AY[:50], STEP)  # the y record ends at 0.49 s
    with pytest.raises(ValueError, match=r"duration \(y record\)"):
        simulate_history(triple_structure("rigid", TRIPLE, gx, time_step=0.005, ground_y=short_y), 1.0)


def test_a_two_component_run_longer_than_a_record_is_refused_by_name():
    """A `Signal` is zero past its last sample: a history or a peak run of a structure on
    sliding groups that outlasts its x or y record is refused naming the record, before any
    step, as on one component; within the records it runs."""
    gx, gy = _signals()
    short_y = uniform_signal(AY[:50], STEP)  # ends at 0.49 s
    planar = bidirectional_isolated_structure("rigid")
    for run in (simulate_history, peak_response):
        with pytest.raises(ValueError, match=r"duration \(y record\): 1 s asked, but the record lasts only 0.49 s"):
            run(planar((gx, short_y)), 1.0)
        with pytest.raises(ValueError, match=r"^duration: 1 s asked, but the record lasts only 0.49 s"):
            run(planar((uniform_signal(AX[:50], STEP), gy)), 1.0)
    assert bool(peak_response(planar((gx, short_y)), 0.45)["converged"])


def test_every_history_has_the_ground_as_an_axis_and_total_accelerations():
    """One component: ground (nt, 1), the total acceleration of the rigid mass is the relative
    one plus a_g; two: ground (nt, 2) and the x, y blocks of the coordinates."""
    gx, gy = _signals()
    one = simulate_history(isolated_structure("rigid")(gx), 1.0)
    assert isinstance(one, StructureResponse) and one.ground.shape == (one.time.size, 1)
    np.testing.assert_allclose(np.asarray(one.ground[:, 0]), np.interp(np.asarray(one.time), TIME, AX), atol=1e-12)
    two = simulate_history(bidirectional_isolated_structure("building")((gx, gy)), 1.0)
    assert two.ground.shape == (two.time.size, 2) and two.displacement.shape == (two.time.size, 14)
    assert two.slider is None and two.bearing_force is None and two.friction_force.shape == (two.time.size, 1, 2)
    assert bool(two.succeeded) and bool(one.succeeded)


def test_succeeded_reads_the_steps_convergence():
    gx, _ = _signals()
    r = simulate_history(triple_structure("rigid", TRIPLE, gx, time_step=0.005), 1.0)
    assert bool(r.succeeded)
    failed = dataclasses.replace(r, converged=r.converged.at[3].set(False))
    assert not bool(failed.succeeded)


def test_the_running_smooth_maximum_is_the_smooth_maximum():
    """`smooth_max_update` sample by sample, then `smooth_max_value`, is the log-mean-cosh of
    `smooth_max`: M_w = w log(mean cosh(x / w)), to rounding."""
    x = jnp.asarray(np.random.default_rng(2).normal(size=300) * 0.02)
    for width in (1e-3, 1e-2):
        top, total = jnp.zeros(()), jnp.ones(())  # the rest state x = 0 at t = 0
        for value in x:
            top, total = smooth_max_update(top, total, value, width)
        running = smooth_max_value(top, total, x.size + 1, width)
        direct = smooth_max(jnp.concatenate([jnp.zeros(1), x]), width)
        np.testing.assert_allclose(float(running), float(direct), rtol=1e-13)
        expected = width * np.log(np.mean(np.cosh(np.concatenate([[0.0], np.asarray(x)]) / width)))
        np.testing.assert_allclose(float(running), expected, rtol=1e-12)


def test_peaks_of_one_and_two_components_are_one_type_and_match_the_histories():
    gx, gy = _signals()
    one = isolated_structure("rigid")(gx)
    peaks = peak_response(one, 1.0, disp_width=1e-3)
    history = simulate_history(one, 1.0)
    u = history.displacement[:, 0]
    np.testing.assert_allclose(float(peaks.smooth_base_disp), float(smooth_max(u, 1e-3)), rtol=1e-6)
    two = bidirectional_isolated_structure("rigid")((gx, gy))
    planar = peak_response(two, 1.0, disp_width=1e-3)
    assert isinstance(peaks, Peaks) and isinstance(planar, Peaks)
    resultant = jnp.hypot(*simulate_history(two, 1.0).bearing_displacement[:, 0].T)
    np.testing.assert_allclose(float(planar.base_disp), float(jnp.max(resultant)), rtol=1e-9)
    np.testing.assert_allclose(float(planar.smooth_base_disp), float(smooth_max(resultant, 1e-3)), rtol=1e-6)


def test_a_series_pendulum_test_is_a_bearing_test_result():
    t = np.arange(0.0, 2.0 + 1e-9, 0.01)
    u = 0.1 * np.sin(np.pi * t)
    along = imposed_path_test(TRIPLE, sampled_path(t, u, 1e6))
    assert along.force.shape == t.shape and along.uy is None and along.slider.shape == (t.size, 3)
    np.testing.assert_array_equal(along.ux, u)
    np.testing.assert_array_equal(along.fy, 0.0)
    orbit = imposed_path_test(TRIPLE, sampled_path(t, np.stack([u, 0 * u], -1), 1e6))
    assert orbit.force.shape == (t.size, 2) and orbit.slider.shape == (t.size, 3, 2)
    np.testing.assert_allclose(orbit.fx, along.fx, rtol=0, atol=1e-9 * 1e6)  # a plane orbit along x
    assert bool(along.succeeded) and bool(orbit.succeeded)


def test_one_study_structure_takes_one_or_two_components_and_refuses_the_other_by_name():
    """Every isolator of the studies is one type in one or two components
    (`IsolatedStructure.components`): flat sliders build their engine's structure, a triple
    pendulum its sliders in series, each refusing the other number of components by name
    instead of failing inside the engine; a design reaches the pendulum's surfaces."""
    gx, gy = _signals()
    one, two = isolated_structure("building"), bidirectional_isolated_structure("building", isolator=None)
    assert type(one) is type(two) and (one.components, two.components) == (1, 2)
    assert isinstance(one(gx), StructureOnSliders)
    planar = two((gx, gy), {"f_max": 0.09})
    assert planar.mass.shape == (14,) and np.asarray(planar.bearing.friction.f_max) == pytest.approx([0.09])
    series_one = isolated_structure("building", isolator=TRIPLE)
    series_two = bidirectional_isolated_structure("building", isolator=TRIPLE)
    assert type(series_one) is type(series_two) is type(one) and (series_one.components, series_two.components) == (1, 2)
    assert series_one(gx).ground_y is None and series_two((gx, gy)).ground_y is gy
    designed = series_two((gx, gy), {"outer_f_max": 0.09}).bearing
    assert [float(designed.bottom_friction.f_max), float(designed.top_friction.f_max)] == pytest.approx(
        [0.09, 0.11 * 0.09 / 0.07])  # the outer surfaces scaled together, the bottom's f_max to the value
    for structure, components in ((one, 1), (two, 2), (series_one, 1), (series_two, 2)):
        with pytest.raises(ValueError, match=rf"ground_acceleration: this structure takes {components} horizontal"):
            structure(gx if components == 2 else (gx, gy))


@pytest.mark.parametrize("radius", [None, 1.5])
def test_a_history_and_its_peaks_are_the_same_samples_on_every_isolator(radius):
    """Flat sliders and single pendulums, on the rigid mass and the building, in one and two
    components with a vertical record: the peaks of `peak_response` are the maxima of the same
    reducers over `simulate_history`'s samples (one engine run for both: equal but for the two
    compiled programs' rounding, which the sliding carries to 2e-13 on the rigid mass under
    two components and a vertical record), and every step's `converged` is kept."""
    from teflon_jax.bearing import concave_surface
    from teflon_jax.studies import response_peaks
    from teflon_jax.systems import response_layout, with_vertical_component

    gx, gy = _signals()
    gz = uniform_signal(0.4 * AY[::-1], STEP)
    isolator = None if radius is None else concave_surface(radius)
    for kind in ("rigid", "building"):
        one = isolated_structure(kind, isolator=isolator)
        two = bidirectional_isolated_structure(kind, isolator=isolator)
        systems = (one(gx), two((gx, gy)), with_vertical_component(one)((gx, gz)),
                   with_vertical_component(two)(((gx, gy), gz)))
        for system in systems:
            history = jax.jit(simulate_history, static_argnums=1)(system, 1.4)
            peaks = jax.jit(peak_response, static_argnums=1)(system, 1.4)
            kept = response_peaks(response_layout(system), history)
            assert history.converged.shape == history.time.shape and bool(history.succeeded)
            for name in ("base_disp_resultant", "base_shear_ratio_resultant"):
                np.testing.assert_allclose(float(peaks[name]), float(kept[name]), rtol=1e-11, atol=0)
