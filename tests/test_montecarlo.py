"""Tests of the chunked, sharded Monte Carlo (teflon_jax.studies).

References: the full response histories of `simulate_history` (peaks taken with NumPy),
NumPy percentiles, a second process with two host CPU devices, and the process's peak
resident memory.
"""

import json
import os
import pathlib
import subprocess
import sys

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from teflon_jax import simulate_history, uniform_signal
from teflon_jax.excitation import StochasticGroundMotion, sample
from teflon_jax.studies import MonteCarloResult, RecordSet, monte_carlo, save_montecarlo
from teflon_jax.systems import isolated_structure, peak_response, smooth_max
from teflon_jax.units import PSI, STANDARD_GRAVITY

REPO = pathlib.Path(__file__).resolve().parent.parent


def _model(duration=4.0):
    return StochasticGroundMotion(
        peak_ground_acceleration=3.0, duration=duration, time_step=0.01, rise_time=0.5,
        strong_motion_duration=2.0,
    )


def test_uniform_signal_matches_linear_interpolation():
    values = jnp.asarray(np.random.default_rng(0).normal(size=50))
    signal = uniform_signal(values, 0.02)
    t = jnp.linspace(-0.1, 1.1, 301)
    # zero outside the record; a time within round-off of the last sample takes its value
    expected = np.interp(t, 0.02 * np.arange(50), values, left=0.0, right=0.0)
    expected = np.where(np.abs(np.asarray(t) - 0.98) < 1e-9, values[-1], expected)
    np.testing.assert_allclose(signal(t), expected, atol=1e-14)


@pytest.mark.parametrize("kind", ["rigid", pytest.param("building", marks=pytest.mark.slow)])
def test_peaks_match_full_history(kind):
    model = _model()
    record = sample(model, jax.random.key(3), 1)[0]
    structure = isolated_structure(kind, time_step=0.005, pressure=2000 * PSI, isolation_period=1.5)
    system = structure(uniform_signal(record, 0.01))
    peaks = peak_response(system, 4.0, disp_width=1e-4, shear_width=1e-3)
    history = simulate_history(system, 4.0)
    disp = np.abs(np.asarray(history.displacement[:, 0]))
    mass = np.asarray(system.mass)
    acc = np.asarray(history.total_acceleration)  # the base shear: every mass, the base slab's included
    shear = acc @ mass / (mass.sum() * STANDARD_GRAVITY)
    np.testing.assert_allclose(peaks.base_disp, disp.max(), rtol=1e-10)
    # read at every 4th step only (as a program recording at a coarser interval would)
    coarse = peak_response(system, 4.0, read_every=4)
    np.testing.assert_allclose(coarse.base_disp, disp[4::4].max(), rtol=1e-10)
    assert coarse.base_disp < peaks.base_disp or disp[4::4].max() == disp.max()
    np.testing.assert_allclose(peaks.base_shear_ratio, np.abs(shear).max(), rtol=1e-10)
    # log-mean-cosh of the whole history, in closed form
    n = len(disp)
    expected = 1e-3 * np.log(np.mean(np.cosh(shear / 1e-3)))
    np.testing.assert_allclose(peaks.smooth_base_shear_ratio, expected, rtol=1e-9)
    assert np.abs(shear).max() - 1e-3 * np.log(2 * n) <= peaks.smooth_base_shear_ratio <= np.abs(shear).max()
    assert bool(peaks.converged)


def test_smooth_max_limits():
    x = jnp.asarray([0.1, -0.7, 0.3, 0.69])
    assert float(smooth_max(x, 1e-4)) == pytest.approx(0.7 - 1e-4 * np.log(8), rel=1e-6)
    assert float(smooth_max(x, 10.0)) == pytest.approx(10 * np.log(np.mean(np.cosh(x / 10))), rel=1e-12)


def test_statistics_and_output(tmp_path):
    rng = np.random.default_rng(1)
    disp, shear = rng.lognormal(size=200), rng.normal(size=200) ** 2
    result = MonteCarloResult(
        base_disp=disp, base_shear_ratio=shear, smooth_base_disp=disp, smooth_base_shear_ratio=shear,
        converged=np.ones(200, bool), pga=np.ones(200), design={}, dims=("motion",), n_devices=1,
        chunk_size=10, wall_s=0.0, compile_s=0.0, memory_estimate_bytes=0,
    )
    stats = result.percentiles((16, 50, 84))
    assert stats["base_disp_m"]["p50"] == pytest.approx(np.median(disp))
    assert stats["base_shear_ratio"]["p84"] == pytest.approx(np.percentile(shear, 84))
    levels, probability = result.exceedance("base_disp")
    for level, p in zip(levels[::17], probability[::17]):
        assert p == pytest.approx(np.mean(disp > level))
    # the format asked for is the format written (no silent .npz for .nc)
    written = save_montecarlo(result, tmp_path / "mc.nc")
    assert written == [tmp_path / "mc.nc"]
    assert (tmp_path / "mc.nc").read_bytes()[:4] in (b"CDF\x01", b"CDF\x02", b"\x89HDF")
    assert not (tmp_path / "mc.npz").exists()
    with pytest.raises(ValueError, match="unknown results format '.txt'"):
        save_montecarlo(result, tmp_path / "mc.txt")
    rows = np.loadtxt(result.to_csv(tmp_path / "mc.csv"), delimiter=",", skiprows=1, usecols=(3,))
    np.testing.assert_allclose(rows, disp, rtol=1e-15)


def test_steps_per_pass_change_nothing():
    """Two steps written out per pass of the peak loop (what `monte_carlo` runs) give the peaks
    of one step per pass, also over an odd number of steps."""
    record = sample(_model(), jax.random.key(5), 1)[0]
    structure = isolated_structure("rigid", time_step=0.005, pressure=2000 * PSI, isolation_period=1.5)
    system = structure(uniform_signal(record, 0.01))
    for duration in (3.995, 4.0):
        one, two = (peak_response(system, duration, steps_per_pass=k) for k in (1, 2))
        for name in ("base_disp", "base_shear_ratio", "smooth_base_disp", "smooth_base_shear_ratio"):
            np.testing.assert_allclose(getattr(two, name), getattr(one, name), rtol=1e-13, err_msg=name)
    with pytest.raises(ValueError, match="steps_per_pass"):
        peak_response(system, 4.0, steps_per_pass=0)


def test_statistics_leave_out_failed_runs():
    # made-up peaks: the statistics must rest on the converged runs only, and say how many
    disp = np.array([1.0, 2.0, 3.0, 100.0, 200.0])
    ok = np.array([True, True, True, False, False])
    result = MonteCarloResult(
        base_disp=disp, base_shear_ratio=disp / 10, smooth_base_disp=disp,
        smooth_base_shear_ratio=disp / 10, converged=ok, pga=np.ones(5), design={},
        dims=("motion",), n_devices=1, chunk_size=5, wall_s=0.0, compile_s=0.0,
        memory_estimate_bytes=0,
    )
    stats = result.percentiles((50,))
    assert stats["base_disp_m"]["mean"] == pytest.approx(2.0)
    assert stats["base_disp_m"]["p50"] == pytest.approx(2.0)
    assert stats["base_disp_m"]["n"] == stats["n_converged"] == 3
    assert stats["n_failed"] == 2
    levels, probability = result.exceedance("base_disp")
    np.testing.assert_array_equal(levels, [1.0, 2.0, 3.0])
    np.testing.assert_allclose(probability, [2 / 3, 1 / 3, 0.0])


def test_real_solver_failure_is_reported_per_motion_and_left_out_of_statistics():
    # One Newton iteration per step cannot solve a sliding step: motions that make the
    # bearing slide fail for real; a motionless record needs no iteration and converges.
    records = np.asarray(sample(_model(), jax.random.key(9), 3))
    quiet = np.zeros_like(records[0])
    motions = RecordSet(np.stack([records[0], quiet, records[1], quiet, records[2]]), 0.01, tuple("abcde"))
    short = isolated_structure("rigid", time_step=0.01, isolation_period=1.5, newton_iterations=1)
    result = monte_carlo(short, motions, chunk_size=5)
    np.testing.assert_array_equal(result.converged, [False, True, False, True, False])
    full = monte_carlo(isolated_structure("rigid", time_step=0.01, isolation_period=1.5), motions, chunk_size=5)
    assert full.converged.all()
    stats = result.percentiles((50,))
    assert (stats["n_converged"], stats["n_failed"], stats["base_disp_m"]["n"]) == (2, 3, 2)
    # the failed runs' (untrusted, non-zero) peaks are left out: only the motionless runs count
    assert np.all(result.base_disp[~result.converged] > 1e-3)
    assert stats["base_disp_m"]["mean"] == 0.0 and stats["base_shear_ratio"]["p50"] == 0.0
    with pytest.raises(ValueError, match="newton_iterations"):
        isolated_structure("rigid", newton_iterations=0)


_SHARDED = """
import json, resource, sys
import jax, numpy as np
jax.config.update("jax_enable_x64", True)
from teflon_jax.studies import monte_carlo
from teflon_jax.systems import isolated_structure
from teflon_jax.excitation import StochasticGroundMotion
mode = sys.argv[1]
if mode == "shard":
    model = StochasticGroundMotion(peak_ground_acceleration=3.0, duration=4.0, time_step=0.01,
                                   rise_time=0.5, strong_motion_duration=2.0)
    structure = isolated_structure("rigid", time_step=0.01, isolation_period=1.5)
    r = monte_carlo(structure, model, 7, key=jax.random.key(5), chunk_size=4,
                    design={"isolation_period": [1.0, 2.5]})
    print(json.dumps({"devices": r.n_devices, "disp": r.base_disp.tolist(),
                      "shear": r.base_shear_ratio.tolist()}))
else:
    model = StochasticGroundMotion(peak_ground_acceleration=3.0, duration=40.0, time_step=0.01)
    structure = isolated_structure("rigid", time_step=0.02, friction_model="none")
    rss = []
    for n in (32, 1024):
        monte_carlo(structure, model, n, chunk_size=32)
        rss.append(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024)
    print(json.dumps({"rss": rss}))
"""


def _run(mode, devices):
    env = dict(os.environ, XLA_FLAGS=f"--xla_force_host_platform_device_count={devices}",
               JAX_PLATFORMS="cpu")
    out = subprocess.run([sys.executable, "-c", _SHARDED, mode], env=env, capture_output=True,
                         text=True, cwd=REPO, timeout=600)
    assert out.returncode == 0, out.stderr[-3000:]
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_sharded_equals_unsharded():
    model = _model()
    structure = isolated_structure("rigid", time_step=0.01, isolation_period=1.5)
    single = monte_carlo(structure, model, 7, key=jax.random.key(5), chunk_size=3,
                         design={"isolation_period": [1.0, 2.5]}, devices=jax.devices()[:1])
    two = _run("shard", 2)
    assert two["devices"] == 2
    assert single.base_disp.shape == (2, 7)
    np.testing.assert_allclose(two["disp"], single.base_disp, rtol=1e-8)
    np.testing.assert_allclose(two["shear"], single.base_shear_ratio, rtol=1e-8)
    # (chunk layouts differ: 3 vs 4 motions; round-off is all that may differ)
    # and the variants differ (the comparison is not trivially equal)
    assert np.all(np.abs(single.base_disp[0] - single.base_disp[1]) > 1e-6)


def test_peak_memory_flat_in_n():
    rss_small, rss_large = _run("memory", 1)["rss"]
    # Without chunking 1024 forty-second records and their generation temporaries would take
    # about 1024 * 8 * 8 * 4001 bytes = 260 MB more than 32 do.
    assert rss_large - rss_small < 40e6, (rss_small, rss_large)


def test_record_set_runs_like_generated_motions():
    model = _model()
    records = np.asarray(sample(model, jax.random.key(9), 3))
    structure = isolated_structure("rigid", time_step=0.01, isolation_period=1.5)
    result = monte_carlo(structure, RecordSet(records, 0.01, ("a", "b", "c")), chunk_size=2)
    for i in range(3):
        system = structure(uniform_signal(jnp.asarray(records[i]), 0.01))
        assert result.base_disp[i] == pytest.approx(float(peak_response(system, 4.0).base_disp), rel=1e-12)
    np.testing.assert_allclose(result.pga, np.abs(records).max(axis=1))


def test_bad_input():
    model = _model()
    structure = isolated_structure("rigid", time_step=0.01)
    with pytest.raises(ValueError, match="n_motions"):
        monte_carlo(structure, model, 0)
    with pytest.raises(ValueError, match="n_motions"):
        monte_carlo(structure, model, -5)
    with pytest.raises(ValueError, match="chunk_size"):
        monte_carlo(structure, model, 10, chunk_size=0)
    with pytest.raises(ValueError, match="chunk_size: .*MiB"):
        monte_carlo(structure, model, 10**12, chunk_size=10**11)
    with pytest.raises(ValueError, match="chunk_size"):
        monte_carlo(structure, model, 100, chunk_size=100, memory_limit_bytes=10**6)
    with pytest.raises(ValueError, match="pressure: outside the Table 1 rows of UF/P, 1000-6500 psi"):
        isolated_structure("rigid", pressure=500 * PSI)
    with pytest.raises(ValueError, match="pressure"):
        monte_carlo(structure, model, 4, design={"pressure": [2000 * PSI, 7000 * PSI]})
    with pytest.raises(ValueError, match="isolation_period"):
        isolated_structure("building", isolation_period=-1.0)
    with pytest.raises(ValueError, match="design: unknown"):
        monte_carlo(structure, model, 4, design={"stiffness": [1.0]})
    with pytest.raises(ValueError, match="structure"):
        isolated_structure("bridge")
    with pytest.raises(ValueError, match="motions"):
        monte_carlo(structure, np.zeros((3, 10)), 3)


class _Accelerator:
    """A device as `jax.devices()` lists it: an accelerator with `free` bytes free."""

    platform = "gpu"

    def __init__(self, free):
        self.free = free

    def memory_stats(self):
        return {"bytes_limit": self.free + 10**9, "bytes_in_use": 10**9}


def test_default_chunk_of_a_run_fits_half_the_free_memory_of_the_accelerators():
    from teflon_jax.studies import monte_carlo_chunk_size
    from teflon_jax.studies._montecarlo import bytes_per_motion, stochastic_grid

    structure = isolated_structure("rigid", time_step=0.01, isolation_period=1.5)
    model = _model()
    per_motion = bytes_per_motion(stochastic_grid(model)[1], 1, 1)  # a rigid mass: one dof
    one = monte_carlo_chunk_size(structure, model, devices=[_Accelerator(2000 * per_motion)])
    assert one == 512  # 1000 motions fit in half: the largest power of two below
    two = monte_carlo_chunk_size(structure, model,
                                 devices=[_Accelerator(2000 * per_motion)] * 2)
    assert two == 1024  # two devices, each with its half of the chunk
    assert monte_carlo_chunk_size(structure, model) == 512  # this CPU
