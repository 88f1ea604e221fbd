"""512-bit vector code on AVX-512 processors (`prefer_wide_cpu_vectors`): asked for only where
the processor has it, never over the user's own XLA_FLAGS, and the same peaks to rounding."""

import json
import os
import subprocess
import sys

import numpy as np
import pytest

from teflon_jax.studies import prefer_wide_cpu_vectors
from teflon_jax.studies._cpu_vectors import (
    WIDE_VECTOR_FLAG,
    cpu_has_avx512,
    with_wide_vectors,
)


def test_flag_added_unless_a_width_is_set():
    assert with_wide_vectors("") == WIDE_VECTOR_FLAG
    assert with_wide_vectors("--xla_cpu_enable_fast_math=false") == f"--xla_cpu_enable_fast_math=false {WIDE_VECTOR_FLAG}"
    assert with_wide_vectors("--xla_cpu_prefer_vector_width=256") == "--xla_cpu_prefer_vector_width=256"


def test_only_on_processors_with_avx512(tmp_path, monkeypatch):
    with_avx512 = tmp_path / "with"
    with_avx512.write_text("processor\t: 0\nflags\t\t: fpu sse2 avx2 avx512f avx512dq\n")
    without = tmp_path / "without"
    without.write_text("processor\t: 0\nflags\t\t: fpu sse2 avx2 fma\n")
    assert cpu_has_avx512(with_avx512) and not cpu_has_avx512(without)
    assert not cpu_has_avx512(tmp_path / "missing")  # not Linux: the default width is kept

    monkeypatch.setenv("XLA_FLAGS", "--xla_cpu_enable_fast_math=false")
    assert not prefer_wide_cpu_vectors(without)
    assert os.environ["XLA_FLAGS"] == "--xla_cpu_enable_fast_math=false"
    assert prefer_wide_cpu_vectors(with_avx512)
    assert os.environ["XLA_FLAGS"] == f"--xla_cpu_enable_fast_math=false {WIDE_VECTOR_FLAG}"
    monkeypatch.setenv("XLA_FLAGS", "--xla_cpu_prefer_vector_width=256")
    assert not prefer_wide_cpu_vectors(with_avx512)  # the user's width stands
    assert os.environ["XLA_FLAGS"] == "--xla_cpu_prefer_vector_width=256"


_PEAKS = """
import json, jax
jax.config.update("jax_enable_x64", True)
from teflon_jax.excitation import StochasticGroundMotion
from teflon_jax.studies import monte_carlo
from teflon_jax.systems import isolated_structure
motions = StochasticGroundMotion(peak_ground_acceleration=3.0, duration=8.0, time_step=0.01, rise_time=1.0,
                                 strong_motion_duration=4.0)
out = {}
for kind in ("rigid", "building"):
    structure = isolated_structure(kind, time_step=0.005, newton_tolerance=1e-3)
    result = monte_carlo(structure, motions, 8, key=jax.random.key(3))
    out[kind] = [result.base_disp.tolist(), result.base_shear_ratio.tolist(),
                 result.smooth_base_disp.tolist(), bool(result.converged.all())]
print(json.dumps(out))
"""


def _peaks(xla_flags):
    env = {**os.environ, "XLA_FLAGS": xla_flags}
    done = subprocess.run([sys.executable, "-c", _PEAKS], env=env, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    return json.loads(done.stdout.strip().splitlines()[-1])


@pytest.mark.slow
def test_same_peaks_with_wide_vectors():
    """On any x86 processor XLA honours the width (on one without AVX-512 it splits the
    vectors), so the comparison runs everywhere: wide or not, the peaks agree to rounding."""
    default, wide = _peaks(""), _peaks(WIDE_VECTOR_FLAG)
    for kind in ("rigid", "building"):
        assert default[kind][3] and wide[kind][3]
        for a, b in zip(default[kind][:3], wide[kind][:3]):
            np.testing.assert_allclose(b, a, rtol=1e-12, atol=0)
