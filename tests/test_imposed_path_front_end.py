"""One front end for the imposed-path test of any isolator (`imposed_path_test`): the isolator's
static structure picks the strategy (`path_strategy`), a motion is driven along its samples by
the same strategy as those samples given as a `SampledPath`, and the old names call it."""

import dataclasses
import pathlib

import diffrax
import jax
import numpy as np
import pytest

from teflon_jax.bearing import (
    FrictionalHeating,
    FrictionParameters,
    paper_bearing,
    single_pendulum,
)
from teflon_jax.excitation import FigureEightMotion, SineMotion
from teflon_jax.formats import load_isolator
from teflon_jax.systems import (
    imposed_path_test,
    path_strategy,
    sampled_path,
)

jax.config.update("jax_enable_x64", True)

W = 1.0e6  # [N]
BENCHMARKS = pathlib.Path(__file__).parents[1] / "benchmarks"
FLAT = paper_bearing(FrictionParameters(0.12, 0.07, 25.0), breakaway_ratio=1.3)
HEATED = dataclasses.replace(paper_bearing(FrictionParameters(0.12, 0.07, 25.0)),
                             heating=FrictionalHeating(contact_area=0.01))
ETA3 = dataclasses.replace(FLAT, hysteresis=dataclasses.replace(FLAT.hysteresis, eta=3.0))
SINGLE = single_pendulum(paper_bearing(FrictionParameters(0.06, 0.03, 20.0)), radius=2.2, capacity=0.4)
DOUBLE = load_isolator(BENCHMARKS / "double_isolator.json")
TRIPLE = load_isolator(BENCHMARKS / "triple_isolator.json")
MOTION = SineMotion(amplitude=0.05, frequency=0.5, cycles=2)
EIGHT = FigureEightMotion(amplitude=0.02, angular_frequency=2.0)


def _samples(motion, samples_per_cycle):
    """The motion's save times, displacement and velocity, as the front end samples it."""
    time = np.linspace(0.0, motion.duration, int(round(motion.duration * motion.frequency * samples_per_cycle)) + 1)
    return time, np.asarray(jax.vmap(motion.displacement)(time)), np.asarray(jax.vmap(motion.velocity)(time))


@pytest.mark.parametrize("isolator, path, solver, strategy", [
    (FLAT, MOTION, None, "sampled"), (HEATED, MOTION, None, "sampled"), (HEATED, EIGHT, None, "sampled"),
    (FLAT, EIGHT, None, "integrated"), (FLAT, MOTION, diffrax.Tsit5(), "integrated"),
    (ETA3, MOTION, None, "integrated"), (SINGLE, MOTION, None, "balanced"), (DOUBLE, EIGHT, None, "balanced"),
    (TRIPLE, MOTION, None, "balanced")],
    ids=["flat", "heated", "heated-plane", "flat-plane", "flat-tsit5", "eta3", "single", "double", "triple"])
def test_the_isolators_static_structure_picks_the_strategy(isolator, path, solver, strategy):
    assert path_strategy(isolator, path, solver) == strategy


@pytest.mark.parametrize("isolator", [FLAT, HEATED, SINGLE, DOUBLE, TRIPLE],
                         ids=["flat", "heated", "single", "double", "triple"])
def test_a_motion_runs_the_strategy_of_its_samples(isolator):
    """The test along a motion is the test along its samples given as a `SampledPath` (with the
    motion's velocity), for every isolator: one force model, whichever way the path comes."""
    along_motion = imposed_path_test(isolator, MOTION, W, samples_per_cycle=200)
    time, u, v = _samples(MOTION, 200)
    along_samples = imposed_path_test(isolator, sampled_path(time, u[:, 0], W, velocity=v[:, 0]))
    np.testing.assert_allclose(np.asarray(along_motion.time), time, rtol=0, atol=1e-12)
    for key in ("fx", "z"):
        np.testing.assert_allclose(np.asarray(getattr(along_motion, key)), np.asarray(getattr(along_samples, key)),
                                   rtol=1e-12, atol=1e-12 * W if key == "fx" else 1e-12)
    assert float(np.max(np.abs(np.asarray(along_motion.fx)))) > 0.02 * W  # it slides


def test_a_flat_bearing_along_a_motion_starts_where_it_is_told():
    """z0 and z_peak0 set the start along a motion as along samples: mobilised (no breakaway)."""
    time, u, v = _samples(MOTION, 200)
    rest = imposed_path_test(FLAT, MOTION, W, samples_per_cycle=200)
    started = imposed_path_test(FLAT, MOTION, W, samples_per_cycle=200, z0=0.5, z_peak0=1.0)
    expected = imposed_path_test(FLAT, sampled_path(time, u[:, 0], W, velocity=v[:, 0]), z0=0.5, z_peak0=1.0)
    np.testing.assert_allclose(np.asarray(started.fx), np.asarray(expected.fx), rtol=1e-12, atol=1e-12 * W)
    assert np.max(np.abs(np.asarray(started.fx) - np.asarray(rest.fx))) > 1e-3 * W


def test_options_the_path_or_strategy_does_not_take_are_refused_by_name():
    time, u, _ = _samples(MOTION, 100)
    path = sampled_path(time, u[:, 0], W)
    with pytest.raises(ValueError, match="^samples_per_cycle, steps_per_sample: a SampledPath carries its samples"):
        imposed_path_test(FLAT, path, samples_per_cycle=50, steps_per_sample=2)
    with pytest.raises(ValueError, match="^normal_load: a SampledPath carries"):
        imposed_path_test(DOUBLE, path, W)
    with pytest.raises(ValueError, match="^normal_load: a test along a motion needs the normal load"):
        imposed_path_test(FLAT, MOTION)
    with pytest.raises(ValueError, match="^path: give an imposed motion"):
        imposed_path_test(FLAT, u[:, 0], W)
    with pytest.raises(ValueError, match="^path: a sliding bearing along a SampledPath in the plane"):
        imposed_path_test(ETA3, sampled_path(time, u[:, 0], W, uy=u[:, 0]))
    with pytest.raises(ValueError, match="^throw: the double friction pendulums balance their sliders"):
        imposed_path_test(DOUBLE, MOTION, W, throw=False)
