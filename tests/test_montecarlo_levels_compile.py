"""`monte_carlo_levels` compiles one chunk function for all its intensity levels (the level is
an argument of each call, not a constant of the program) and gives, motion for motion, the
peaks of separate `monte_carlo` runs of the model built at each level from the same key
(level j: motions j N .. (j + 1) N - 1), bit for bit: the same program at the same batch width.
"""

import jax
import jax.monitoring
import numpy as np
import pytest

from teflon_jax.excitation import StochasticGroundMotion
from teflon_jax.studies import (
    monte_carlo,
    monte_carlo_levels,
    monte_carlo_motion,
    motions_at_level,
)
from teflon_jax.systems import isolated_structure
from teflon_jax.units import STANDARD_GRAVITY

LEVELS = (0.1 * STANDARD_GRAVITY, 0.25 * STANDARD_GRAVITY, 0.6 * STANDARD_GRAVITY)
N = 3
FIELDS = ("base_disp", "base_shear_ratio", "smooth_base_disp", "smooth_base_shear_ratio", "converged", "pga")
COMPILE_EVENT = "/jax/core/compile/backend_compile_duration"


def _model(pga=1.0):
    return StochasticGroundMotion(peak_ground_acceleration=pga, duration=3.0, time_step=0.01, rise_time=0.5,
                                  strong_motion_duration=1.5)


def _compiles(function):
    """(function(), the number of XLA compilations it ran)."""
    seen = []

    def listen(event, duration, **_):
        if event == COMPILE_EVENT:
            seen.append(duration)

    jax.monitoring.register_event_duration_secs_listener(listen)
    try:
        value = function()
    finally:
        jax.monitoring.unregister_event_duration_listener(listen)
    return value, len(seen)


def test_levels_compile_once_and_equal_a_loop_of_single_level_runs():
    structure, key, device = isolated_structure("rigid"), jax.random.key(7), jax.devices()[:1]
    options = {"chunk_size": 2, "devices": device}  # 3 motions: the last chunk of each level is padded
    model = _model()  # its checks run eagerly (small programs of their own) before the count
    (result, index), n_compiled = _compiles(lambda: monte_carlo_levels(structure, model, LEVELS, N, key=key,
                                                                        **options))
    assert n_compiled == 1  # three levels: one compilation of the chunk function
    assert index.tolist() == [0, 0, 0, 1, 1, 1, 2, 2, 2]
    for j, level in ((0, LEVELS[0]), (2, LEVELS[2])):  # the first and last levels (a compilation each)
        alone = monte_carlo(structure, motions_at_level(_model(), level), N, key=key, first_motion=j * N, **options)
        for name in FIELDS:
            np.testing.assert_array_equal(getattr(result, name)[j * N:(j + 1) * N], getattr(alone, name), name)
    # each level's motions are the model's at that level: peak |a_g| of the record drawn again
    for i in (0, 4, 8):
        record = monte_carlo_motion(_model(LEVELS[index[i]]), key, i)
        assert result.pga[i] == pytest.approx(float(np.max(np.abs(record))), rel=1e-12)
    assert np.all(np.diff(result.pga.reshape(3, N).mean(axis=1)) > 0)


def test_first_motion_is_refused_with_levels():
    with pytest.raises(ValueError, match="first_motion"):
        monte_carlo_levels(isolated_structure("rigid"), _model(), LEVELS, N, first_motion=3)
