"""The vertical ground component over several intensity levels (`monte_carlo_levels`) and in
the bounding analysis (`monte_carlo(design=bounding_design(...))`): a vertical record of zeros
leaves every level's (every case's) peaks as the horizontal-only run's, bit for bit; at each
level the vertical component's peak is `vertical_ratio` times that level's, so the uplift time
of every motion is the time its vertical record, drawn again from a model built at that level,
spends at 1 + a_v / g <= 0, and more motions lift off at the higher level; and a friction-only
rigid mass, whose horizontal-only shear cannot exceed f_max W, carries up to f_max N > f_max W
under the vertical component."""

import jax
import numpy as np
import pytest

from teflon_jax.excitation import StochasticGroundMotion, VerticalGroundMotion
from teflon_jax.studies import (
    bounding_design,
    monte_carlo,
    monte_carlo_levels,
    monte_carlo_motion,
    motions_at_level,
)
from teflon_jax.systems import isolated_structure, with_vertical_component
from teflon_jax.units import STANDARD_GRAVITY

DURATION = 3.0
N = 3
LEVELS = (0.3 * STANDARD_GRAVITY, 1.0 * STANDARD_GRAVITY)
PEAKS = ("base_disp", "base_shear_ratio", "smooth_base_disp", "smooth_base_shear_ratio", "converged", "pga")


def _horizontal(pga):
    return StochasticGroundMotion(peak_ground_acceleration=pga, duration=DURATION, time_step=0.01, rise_time=0.5,
                                  strong_motion_duration=1.5)


def _levels(structure, motions):
    return monte_carlo_levels(structure, motions, LEVELS, N, key=jax.random.key(5), chunk_size=N,
                              devices=jax.devices()[:1])


def _uplift_of_record(vertical, record_step, time_step, n_steps):
    """dt times the steps k = 1..n whose end has 1 + a_v(k dt) / g <= 0, a_v the record
    interpolated linearly (as a `Signal` reads it)."""
    t = np.arange(1, n_steps + 1) * time_step
    a_v = np.interp(t, record_step * np.arange(vertical.size), vertical)
    return np.sum(1 + a_v / STANDARD_GRAVITY <= 0) * time_step


def test_a_zero_vertical_ratio_gives_every_levels_horizontal_only_peaks():
    """vertical_ratio = 0 at every level: N = W throughout, every peak of every level is the
    horizontal-only run's, bit for bit, and no motion lifts off."""
    structure = isolated_structure("rigid", isolation_period=2.5)
    plain, plain_index = _levels(structure, _horizontal(LEVELS[0]))
    loaded, index = _levels(with_vertical_component(structure), VerticalGroundMotion(_horizontal(LEVELS[0]), 0.0))
    for name in PEAKS:
        np.testing.assert_array_equal(getattr(loaded, name), getattr(plain, name), err_msg=name)
    np.testing.assert_array_equal(index, plain_index)
    assert plain.uplift_time is None and np.array_equal(loaded.uplift_time, np.zeros(len(LEVELS) * N))
    assert loaded.attrs["intensity_levels_m_s2"] == list(LEVELS)


def test_each_levels_uplift_is_its_vertical_records_and_grows_with_the_level():
    """Motion j N + i of level j is drawn from a model built at that level from scratch (its
    vertical peak vertical_ratio times the level): the Monte Carlo's uplift time of every motion
    is the time that record spends with 1 + a_v / g <= 0 (a vertical component left at the
    first level's peak, or dropped, would not match at the second level), and more motions
    lift off at the higher level."""
    ratio = 1.5
    structure = isolated_structure("rigid", isolation_period=2.5)
    result, index = _levels(with_vertical_component(structure), VerticalGroundMotion(_horizontal(LEVELS[0]), ratio))
    dt, n_steps = structure.time_step, round(DURATION / structure.time_step)
    counts = []
    for j, level in enumerate(LEVELS):
        at_level = VerticalGroundMotion(_horizontal(level), ratio)
        for i in np.flatnonzero(index == j):
            rows = np.asarray(monte_carlo_motion(at_level, jax.random.key(5), int(i)))
            assert result.uplift_time[i] == pytest.approx(_uplift_of_record(rows[1], 0.01, dt, n_steps), abs=1e-12)
            assert result.pga[i] == pytest.approx(np.abs(rows[0]).max(), rel=1e-15)
        counts.append(int(np.sum(result.uplift_time[index == j] > 0)))
    assert counts[0] < counts[1] and result.converged.all()
    # the public helper gives the same model as the one built at the level
    same = motions_at_level(VerticalGroundMotion(_horizontal(LEVELS[0]), ratio), LEVELS[1])
    np.testing.assert_array_equal(monte_carlo_motion(same, jax.random.key(5), 4),
                                  monte_carlo_motion(VerticalGroundMotion(_horizontal(LEVELS[1]), ratio),
                                                     jax.random.key(5), 4))


def test_bounding_cases_with_the_vertical_component():
    """Friction-only rigid mass (no restoring force, no damping), the three bounding cases of
    f_max: with vertical_ratio 0 each case's peaks are the horizontal-only ones bit for bit;
    horizontal only, the force on the mass mu(v) W Z stays at or below f_max W in every case;
    with a strong vertical component N reaches above W, some runs carry more than f_max W, and
    none more than f_max W (1 + max a_v / g); the uplift time, the record's alone, is the same
    in the three cases."""
    structure = isolated_structure("rigid", isolation_period=None, isolation_damping=0.0)
    design = bounding_design(structure, lower=0.8, upper=1.25)
    f_max = design["f_max"][:, None]

    def run(build, motions):
        return monte_carlo(build, motions, N, key=jax.random.key(3), design=design, chunk_size=N,
                           devices=jax.devices()[:1])

    horizontal = _horizontal(0.6 * STANDARD_GRAVITY)
    plain = run(structure, horizontal)
    zero = run(with_vertical_component(structure), VerticalGroundMotion(horizontal, 0.0))
    for name in PEAKS:
        np.testing.assert_array_equal(getattr(zero, name), getattr(plain, name), err_msg=name)
    assert np.all(plain.base_shear_ratio <= f_max * (1 + 1e-9))
    motions = VerticalGroundMotion(horizontal, 1.2)
    loaded = run(with_vertical_component(structure), motions)
    peak_up = np.array([np.asarray(monte_carlo_motion(motions, jax.random.key(3), i))[1].max() for i in range(N)])
    assert loaded.converged.all()
    assert np.any(loaded.base_shear_ratio > f_max * 1.01)
    assert np.all(loaded.base_shear_ratio <= f_max * (1 + peak_up / STANDARD_GRAVITY) * (1 + 1e-9))
    assert loaded.uplift_time.shape == (3, N) and np.all(loaded.uplift_time == loaded.uplift_time[0])
