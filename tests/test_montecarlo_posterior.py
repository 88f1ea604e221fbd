"""Monte Carlo over a bearing posterior and ground motions together (teflon_jax.studies).

References: the law of total variance on synthetic peaks with known parts (closed form),
NumPy percentiles of the rows, and runs of each draw's bearing on its own
(`BearingPosterior.bearing(point, k)` in a structure of its own, compiled apart).
"""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest

import teflon_jax as tj
from teflon_jax.excitation import StochasticGroundMotion
from teflon_jax.formats import BearingPosterior
from teflon_jax.studies import (
    MonteCarloResult,
    monte_carlo,
    motion_draws,
    nested_draws,
    percentile_band,
    variance_split,
)
from teflon_jax.studies._montecarlo import ChunkRunner, _motion_source
from teflon_jax.systems import isolated_structure
from teflon_jax.units import PSI


def _model(duration=4.0):
    return StochasticGroundMotion(peak_ground_acceleration=3.0, duration=duration, time_step=0.01,
                                  rise_time=0.5, strong_motion_duration=2.0)


def _point():
    friction, b = tj.interface_parameters("UF", 1000 * PSI, "P")
    return tj.paper_bearing(friction, breakaway_ratio=b)


def _posterior(f_max, ratio, rate_a):
    """A posterior of draws f_max, delta_f = ratio f_max, rate_a (arrays of K)."""
    f_max = np.asarray(f_max, float)
    draws = {"f_max": f_max, "delta_f": np.asarray(ratio) * f_max, "rate_a": np.asarray(rate_a, float)}
    k = f_max.size
    return BearingPosterior(names=tuple(draws), draws=draws, effective_sample_size={n: 100.0 + k for n in draws},
                            draws_before_thinning=k, thinning=1, chains=2, seed=0)


def _normal_posterior(point, size, spread, seed=0, shift=1.0):
    """`size` draws of f_max, delta_f / f_max and rate_a normal about `shift` times the point's
    f_max (the others at the point's), each with relative standard deviation `spread`."""
    rng = np.random.default_rng(seed)
    f = point.friction
    ratio = float(f.delta_f / f.f_max)
    return _posterior(shift * float(f.f_max) * (1 + spread * rng.standard_normal(size)),
                      ratio * (1 + spread * rng.standard_normal(size)),
                      float(f.rate_a) * (1 + spread * rng.standard_normal(size)))


# --------------------------------------------------------------------------- draws


def test_draws_per_motion_without_replacement_then_cycled_and_seeded():
    n_draws = 7
    first = motion_draws(5, n_draws, seed=3)
    assert len(set(first.tolist())) == 5  # N <= S: no draw twice
    many = motion_draws(23, n_draws, seed=3)
    np.testing.assert_array_equal(many[:5], first)  # a longer run starts with the same draws
    np.testing.assert_array_equal(many[n_draws:2 * n_draws], many[:n_draws])  # then cycles
    counts = np.bincount(many, minlength=n_draws)
    assert counts.min() == 3 and counts.max() == 4  # 23 = 3 x 7 + 2: as even as can be
    np.testing.assert_array_equal(motion_draws(23, n_draws, seed=3), many)  # reproducible
    assert not np.array_equal(motion_draws(23, n_draws, seed=4), many)
    nested = nested_draws(4, n_draws, seed=3)
    np.testing.assert_array_equal(nested, many[:4])
    assert len(set(nested.tolist())) == 4


def test_draws_refuse_bad_counts():
    with pytest.raises(ValueError, match="n_bearings: 8 bearings asked for but the posterior has 7 draws"):
        nested_draws(8, 7)
    for bad in (0, -1, 2.5, True):
        with pytest.raises(ValueError, match="n_bearings"):
            nested_draws(bad, 7)
        with pytest.raises(ValueError, match="n_motions"):
            motion_draws(bad, 7)
    with pytest.raises(ValueError, match="seed"):
        motion_draws(3, 7, seed=-1)


# --------------------------------------------------------------------------- statistics


def _rows_with_variances(means, variances, n_motions, seed=0):
    """(K, M) peaks: row k has population mean means[k] and variance variances[k] exactly."""
    e = np.random.default_rng(seed).standard_normal((len(means), n_motions))
    e -= e.mean(axis=1, keepdims=True)
    e /= e.std(axis=1, keepdims=True)
    return np.asarray(means)[:, None] + np.sqrt(np.asarray(variances))[:, None] * e


def test_variance_split_equals_its_closed_form():
    """Rows of means a_k and variances v_k: E_k[Var_m] = mean(v), Var_k[E_m] = var(a)."""
    means, variances = np.array([0.10, 0.30, -0.20, 0.50]), np.array([1.0, 2.0, 3.0, 4.0]) * 1e-2
    x = _rows_with_variances(means, variances, 9)
    split = variance_split(x)
    assert split["motion"] == pytest.approx(variances.mean(), rel=1e-12)
    assert split["bearing"] == pytest.approx(np.var(means), rel=1e-12)
    assert split["total"] == pytest.approx(variances.mean() + np.var(means), rel=1e-12)
    assert split["bearing_share"] == pytest.approx(np.var(means) / (variances.mean() + np.var(means)), rel=1e-12)
    assert (split["n"], split["n_bearings"]) == (36, 4)


def test_variance_parts_add_up_to_the_total_with_failed_runs_left_out():
    """The identity Var = E_k[Var_m] + Var_k[E_m] with bearings weighted by their converged runs
    (the total computed directly over the runs kept); a bearing without any run is left out."""
    rng = np.random.default_rng(1)
    x = rng.gamma(2.0, 1.0, (6, 11)) + rng.normal(0, 2, (6, 1))
    ok = rng.random((6, 11)) > 0.3
    ok[4] = False
    split = variance_split(x, ok)
    assert split["motion"] + split["bearing"] == pytest.approx(np.var(x[ok]), rel=1e-12)
    assert split["total"] == pytest.approx(np.var(x[ok]), rel=1e-12)
    assert (split["n"], split["n_bearings"]) == (int(ok.sum()), 5)
    # brute force: the pooled runs' mean squared deviation, split by bearing
    kept = [row[good] for row, good in zip(x, ok) if good.any()]
    mean = np.concatenate(kept).mean()
    within = sum(((r - r.mean()) ** 2).sum() for r in kept) / ok.sum()
    between = sum(r.size * (r.mean() - mean) ** 2 for r in kept) / ok.sum()
    assert (split["motion"], split["bearing"]) == pytest.approx((within, between), rel=1e-12)


def test_identical_bearings_have_no_bearing_share():
    row = np.random.default_rng(2).gamma(2.0, 1.0, 13)
    split = variance_split(np.tile(row, (5, 1)))
    assert split["bearing"] == 0.0 and split["bearing_share"] == 0.0
    assert split["motion"] == pytest.approx(np.var(row), rel=1e-12)


def test_percentile_band_is_the_spread_of_the_per_bearing_percentiles():
    x = np.random.default_rng(3).gamma(2.0, 1.0, (20, 40)) * np.linspace(1.0, 2.0, 20)[:, None]
    band = percentile_band(x, q=95, band=(10, 90))
    per_bearing = np.percentile(x, 95, axis=1)
    np.testing.assert_allclose(band["per_bearing"], per_bearing, rtol=1e-14)
    np.testing.assert_allclose(band["band"], np.percentile(per_bearing, [10, 90]), rtol=1e-14)
    assert band["median"] == pytest.approx(np.median(per_bearing), rel=1e-14)
    assert band["pooled"] == pytest.approx(np.percentile(x, 95), rel=1e-14)
    with pytest.raises(ValueError, match="band"):
        percentile_band(x, band=(90, 10))


# --------------------------------------------------------------------------- runs


def _single_runs(point, posterior, draws, model, n_motions):
    """Each draw's peaks under the motions, from a structure of its own bearing."""
    out = []
    for k in draws:
        structure = isolated_structure("rigid", bearing=posterior.bearing(point, int(k)))
        out.append(monte_carlo(structure, model, n_motions, chunk_size=n_motions))
    return out


@pytest.mark.slow
@pytest.mark.last_bit
def test_nested_and_per_motion_runs_equal_each_draw_run_alone(tmp_path):
    """Nested: bearing k's row equals draw k's bearing run on its own, to rounding. One draw per
    motion: motion m's peaks equal those of draw k(m)'s run; both written and read back with
    the draw of each bearing or motion."""
    point = _point()
    posterior = _normal_posterior(point, 9, 0.15)
    structure, model = isolated_structure("rigid", bearing=point), _model()
    chosen = nested_draws(4, posterior.size, seed=1)  # the draws motion_draws gives 4 motions
    nested = monte_carlo(structure, model, 4, chunk_size=5, bearings=posterior.bearings(point),
                         bearing_draw=chosen, nested=True)
    assert nested.dims == ("bearing", "motion") and nested.base_disp.shape == (4, 4)
    alone = _single_runs(point, posterior, chosen, model, 4)
    for k, run in enumerate(alone):
        np.testing.assert_allclose(nested.base_disp[k], run.base_disp, rtol=1e-12)
        np.testing.assert_allclose(nested.base_shear_ratio[k], run.base_shear_ratio, rtol=1e-12)
        np.testing.assert_array_equal(nested.pga, run.pga)
    assert len({tuple(r.base_disp) for r in alone}) == 4  # the draws do differ
    draws = motion_draws(4, posterior.size, seed=1)
    per_motion = monte_carlo(structure, model, 4, chunk_size=3, bearings=posterior.bearings(point),
                             bearing_draw=draws)
    alone = dict(zip(chosen.tolist(), alone))
    for m, k in enumerate(draws):
        np.testing.assert_allclose(per_motion.base_disp[m], alone[int(k)].base_disp[m], rtol=1e-12)
    for result, name in ((nested, "nested.nc"), (per_motion, "per_motion.nc")):
        back = MonteCarloResult.open(result.save(tmp_path / name))
        np.testing.assert_array_equal(back.bearing_draw, result.bearing_draw)
        assert back.dims == result.dims
        np.testing.assert_array_equal(back.base_disp, result.base_disp)
    np.testing.assert_array_equal(per_motion.bearing_draw, draws)
    assert nested.percentiles()["base_disp_m"]["n"] == 16  # the runs pooled


def test_draws_are_arguments_of_one_compiled_program():
    """Another posterior through the same compiled chunk function: no new compilation, and
    the peaks follow the new draws."""
    point = _point()
    structure, model = isolated_structure("rigid", bearing=point), _model()
    source, _ = _motion_source(model, 2, jax.random.key(0))
    first, second = _normal_posterior(point, 4, 0.1, seed=0), _normal_posterior(point, 4, 0.1, seed=5)
    runner = ChunkRunner(structure, source, (source.samples - 1) * source.time_step, None, jax.devices()[:1], 2, None, None,
                         bearings=first.bearings(point))
    peaks_first, _ = runner(np.array([0, 1]), draws=np.array([0, 3]))
    compiled = runner.compiled
    runner.bearings = jax.device_put(second.bearings(point), runner.replicated)
    peaks_second, _ = runner(np.array([0, 1]), draws=np.array([0, 3]))
    assert runner.compiled is compiled
    alone = monte_carlo(isolated_structure("rigid", bearing=second.bearing(point, 3)), model, 2, chunk_size=2)
    np.testing.assert_allclose(np.asarray(peaks_second["base_disp"])[1], alone.base_disp[1], rtol=1e-12)
    assert not np.allclose(np.asarray(peaks_first["base_disp"]), np.asarray(peaks_second["base_disp"]))


def test_identical_draws_give_no_bearing_share_in_a_run():
    point = _point()
    f = point.friction
    same = _posterior(np.full(4, float(f.f_max)), np.full(4, float(f.delta_f / f.f_max)), np.full(4, float(f.rate_a)))
    result = monte_carlo(isolated_structure("rigid", bearing=point), _model(), 6, chunk_size=24,
                         bearings=same.bearings(point), bearing_draw=np.arange(4), nested=True)
    for name in ("base_disp", "base_shear_ratio"):
        split = result.variance_split(name)
        assert split["total"] > 0
        assert split["bearing"] == pytest.approx(0.0, abs=1e-15 * split["total"])


def test_band_covers_the_true_bearings_95th_percentile():
    """The true bearing, 24 draws about it (4 % spread) and 24 draws about a bearing with 25 %
    more friction, all on the same 24 motions in one run: the 5-95 % band of the per-bearing
    95th percentile of the base displacement from the draws about the truth holds the true
    bearing's, and the band from the shifted draws does not."""
    point = _point()
    near, shifted = _normal_posterior(point, 24, 0.04, seed=7), _normal_posterior(point, 24, 0.04, seed=8, shift=1.25)
    stacked = jax.tree_util.tree_map(lambda a, b, c: jnp.concatenate([a, b, c]),
                                     jax.tree_util.tree_map(lambda x: jnp.asarray(x)[None], point),
                                     near.bearings(point), shifted.bearings(point))
    model = StochasticGroundMotion(peak_ground_acceleration=3.0, duration=8.0, time_step=0.01, rise_time=1.0,
                                   strong_motion_duration=4.0)
    result = monte_carlo(isolated_structure("rigid", bearing=point), model, 24, bearings=stacked,
                         bearing_draw=np.arange(49), nested=True)
    assert np.all(result.converged)
    truth = float(np.percentile(result.base_disp[0], 95))
    for rows, covers in ((slice(1, 25), True), (slice(25, 49), False)):
        band = percentile_band(result.base_disp[rows], q=95, band=(5, 95))["band"]
        assert (band[0] <= truth <= band[1]) is covers, (band, truth)


def test_bad_bearings_refused_by_name():
    point, model = _point(), _model()
    structure = isolated_structure("rigid", bearing=point)
    stacked = _normal_posterior(point, 5, 0.1).bearings(point)
    with pytest.raises(ValueError, match="bearing_draw: give the draw of each motion"):
        monte_carlo(structure, model, 3, bearings=stacked)
    with pytest.raises(ValueError, match="bearing_draw: 2 draws for 3 motions"):
        monte_carlo(structure, model, 3, bearings=stacked, bearing_draw=np.array([0, 1]))
    with pytest.raises(ValueError, match=r"bearing_draw: indices must lie in \[0, 5\)"):
        monte_carlo(structure, model, 3, bearings=stacked, bearing_draw=np.array([0, 1, 5]))
    with pytest.raises(ValueError, match="bearing_draw, nested: apply to stacked bearings"):
        monte_carlo(structure, model, 3, bearing_draw=np.array([0, 1, 2]))
    with pytest.raises(ValueError, match="design: the runs take the bearings' draws"):
        monte_carlo(structure, model, 3, bearings=stacked, bearing_draw=np.arange(3), design={"f_max": [0.1]})
    with pytest.raises(ValueError, match="bearings: the structure runs no bearing of its own"):
        monte_carlo(isolated_structure("rigid"), model, 3, bearings=stacked, bearing_draw=np.arange(3))
    no_breakaway = eqx.tree_at(lambda b: b.breakaway_ratio, stacked, None, is_leaf=lambda x: x is None)
    with pytest.raises(ValueError, match="bearings: their parts differ"):
        monte_carlo(structure, model, 3, bearings=no_breakaway, bearing_draw=np.arange(3))
    bad = eqx.tree_at(lambda b: b.friction.delta_f, stacked, 2 * stacked.friction.f_max)
    with pytest.raises(ValueError, match="bearings: a draw is outside the bearing's ranges: delta_f"):
        monte_carlo(structure, model, 3, bearings=bad, bearing_draw=np.arange(3))


def test_nested_result_files_name_the_bearing_and_its_draw(tmp_path):
    """A (bearing, motion) result written as CSV (a row per run with its bearing, motion and
    draw) and NetCDF (the draws over "bearing") reads back whole."""
    peaks = np.arange(6.0).reshape(2, 3) / 100
    result = MonteCarloResult(base_disp=peaks, base_shear_ratio=peaks + 0.1, smooth_base_disp=peaks,
                              smooth_base_shear_ratio=peaks + 0.1, converged=np.ones((2, 3), bool),
                              pga=np.array([1.0, 2.0, 3.0]), design={}, dims=("bearing", "motion"), n_devices=1,
                              chunk_size=6, wall_s=1.0, compile_s=0.5, memory_estimate_bytes=1,
                              bearing_draw=np.array([7, 2]))
    rows = np.genfromtxt(result.to_csv(tmp_path / "mc.csv"), delimiter=",", names=True)
    assert rows.dtype.names[:3] == ("bearing", "motion", "bearing_draw")
    np.testing.assert_array_equal(rows["bearing"], [0, 0, 0, 1, 1, 1])
    np.testing.assert_array_equal(rows["bearing_draw"], [7, 7, 7, 2, 2, 2])
    np.testing.assert_array_equal(rows["base_disp_m"], peaks.reshape(-1))
    back = MonteCarloResult.open(result.save(tmp_path / "mc.nc"))
    assert back.nested and back.bearing_draw.tolist() == [7, 2]
    assert back.n_converged == 6
    np.testing.assert_array_equal(back.converged_values("base_disp"), peaks.reshape(-1))
    np.testing.assert_array_equal(back.converged_values("base_disp", 1), peaks[1])
