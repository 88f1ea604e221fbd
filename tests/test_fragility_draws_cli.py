"""`teflon-jax montecarlo --pga L1,L2,... --limit ... --bearing FILE --bearing-draws K|motion`:
fragility curves over intensity levels with a bearing posterior's draws.

References: each draw's bearing written to a file of its own (no posterior) and run alone on
the same motions at the same levels (its counts must be the nested run's row of that draw,
exactly), `fragility_band` on those counts, a posterior whose draws are all one bearing (the
band is that bearing's single fit), the per-motion design's draws `motion_draws` and the
nested run's peaks of the same draw and motion, XLA's compile events (one compilation for
every level and draw) and a one-level run of a level's motions.
"""

import json

import jax
import jax.monitoring
import numpy as np
import pytest
import xarray

import teflon_jax as tj
from teflon_jax.cli import main
from teflon_jax.excitation import StochasticGroundMotion
from teflon_jax.formats import BearingPosterior, save_bearing
from teflon_jax.studies import (
    fragility_band,
    monte_carlo_levels,
    motion_draws,
    nested_draws,
)
from teflon_jax.systems import isolated_structure
from teflon_jax.units import PSI, STANDARD_GRAVITY

N, FACTORS = 8, (1.3, 0.7)  # motions per level; f_max of each draw over the point's
LEVELS = ["--pga", "0.2g,0.35g,0.5g,0.65g,0.8g"]
LIMITS = ("base_disp=1.5in", "base_disp=2in", "base_disp=2.5in")
COMMON = ["montecarlo", "--motions", str(N), "--duration", "4s", "--strong-motion", "1.5s", "--no-progress",
          "--chunk-size", str(N), *LEVELS, *(f for text in LIMITS for f in ("--limit", text))]
COMPILE_EVENT = "/jax/core/compile/backend_compile_duration"


def _posterior(point, factors):
    """Draws k of f_max = factors[k] times the point's (delta_f in the same ratio, rate_a the point's)."""
    f = point.friction
    f_max = float(f.f_max) * np.asarray(factors, float)
    draws = {"f_max": f_max, "delta_f": f_max * float(f.delta_f / f.f_max),
             "rate_a": np.full(f_max.size, float(f.rate_a))}
    return BearingPosterior(names=tuple(draws), draws=draws, effective_sample_size=dict.fromkeys(draws, 400.0),
                            draws_before_thinning=f_max.size, thinning=1, chains=1, seed=0)


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """{"posterior": 2 draws of f_max, "alike": 2 draws that are both draw 1, "draw k": draw k's
    bearing alone (no posterior), "folder"}."""
    jax.config.update("jax_enable_x64", True)
    folder = tmp_path_factory.mktemp("bearings")
    friction, b = tj.interface_parameters("UF", 1000 * PSI, "P")
    point = tj.paper_bearing(friction, breakaway_ratio=b)
    posterior = _posterior(point, FACTORS)
    out = {"folder": folder, "posterior": save_bearing(folder / "posterior.json", point, posterior=posterior),
           "alike": save_bearing(folder / "alike.json", point, posterior=_posterior(point, [FACTORS[1]] * 2))}
    for k in range(posterior.size):
        out[f"draw {k}"] = save_bearing(folder / f"draw{k}.json", posterior.bearing(point, k))
    return out


def _run(folder, name, bearing, *flags):
    """Run the command with --json (and the flags); (its exit status, the summary)."""
    summary = folder / f"summary_{name}.json"
    status = main([*COMMON, "--bearing", str(bearing), *flags, "--json", str(summary)])
    return status, json.loads(summary.read_text())


@pytest.fixture(scope="module")
def runs(files):
    """The summaries of each draw alone, of the nested run of the 2 draws (with its results file
    and plot), of the nested run of 2 alike draws and of one draw per motion."""
    folder, out = files["folder"], {}
    for k in range(len(FACTORS)):
        out[f"draw {k}"] = _run(folder, f"draw{k}", files[f"draw {k}"], "--bearing-draws", "point")
    out["nested"] = _run(folder, "nested", files["posterior"], "--bearing-draws", "2", "--bearing-seed", "4",
                         "--out", str(folder / "nested.nc"), "--plot", str(folder / "nested.png"))
    out["alike"] = _run(folder, "alike", files["alike"], "--bearing-draws", "2")
    out["motion"] = _run(folder, "motion", files["posterior"], "--bearing-draws", "motion", "--bearing-seed", "1",
                         "--out", str(folder / "motion.nc"))
    for name, (status, _) in out.items():
        assert status == 0, name
    return {name: summary for name, (_, summary) in out.items()}


def test_each_draws_counts_are_those_of_its_bearing_run_alone(runs):
    """Row k of the nested run took draw d = nested_draws(2, 2, seed 4)[k] (1, 0) at every level: its
    counts are those of draw d's file run alone on the same motions, exactly, and the fit of
    all runs rests on their sum."""
    nested = runs["nested"]
    draws = nested_draws(2, len(FACTORS), seed=4).tolist()
    assert draws == [1, 0]  # bearing k is not draw k: the rows follow the draws they ran
    assert nested["bearing_posterior"]["bearing_draw"] == draws and nested["n_runs"] == 2 * 5 * N
    for text in LIMITS:
        entry, band = nested["fragility"][text], nested["fragility"][text]["bearing_band"]
        assert band["draws"] == draws
        alone = [runs[f"draw {d}"]["fragility"][text] for d in draws]
        assert band["n_exceed"] == [a["n_exceed"] for a in alone]
        assert band["n_runs"] == [a["n_runs"] for a in alone] == [[N] * 5] * 2
        assert entry["n_exceed"] == np.sum([a["n_exceed"] for a in alone], axis=0).tolist()
        assert band["draw_medians"] == [a["median"] for a in alone]
    assert len({tuple(runs[f"draw {d}"]["fragility"][LIMITS[1]]["n_exceed"]) for d in draws}) == 2  # they differ


def _ends(interval):
    """An interval as the JSON writes it: an end the data cannot bound (0 or inf) is null."""
    return [v if np.isfinite(v) and v > 0 else None for v in interval]


def test_the_band_is_fragility_band_of_the_draws_counts(runs, files):
    """The JSON's band is `fragility_band` (90 %) of the draws' counts from their runs alone;
    its median is that of the fit of all runs; the plot is written."""
    nested = runs["nested"]
    for text in LIMITS:
        entry, band = nested["fragility"][text], nested["fragility"][text]["bearing_band"]
        alone = [runs[f"draw {d}"]["fragility"][text] for d in band["draws"]]
        levels = alone[0]["levels"]
        want = fragility_band(levels, np.array([a["n_runs"] for a in alone]),
                              np.array([a["n_exceed"] for a in alone]), band=0.9)
        assert band["n_fitted"] == 2 and band["band"] == 0.9 and entry["levels"] == levels
        assert band["median_band"] == list(want.median_band)
        assert band["dispersion_band"] == list(want.dispersion_band)
        assert band["median_interval"] == _ends(want.median_interval)
        assert band["dispersion_interval"] == _ends(want.dispersion_interval)
        assert band["probability_band_at_levels"] == [side.tolist() for side in want.probability_band(levels)]
        assert entry["median"] == want.pooled.median and entry["dispersion"] == want.pooled.dispersion
        assert want.median_band[0] < want.median_band[1]  # the draws differ: a band of some width
    png = files["folder"] / "nested.png"
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 20_000
    with xarray.open_dataset(files["folder"] / "nested.nc") as data:
        assert data["base_disp"].dims == ("bearing", "motion") and data["base_disp"].shape == (2, 5 * N)
        assert data["bearing_draw"].values.tolist() == band["draws"]
        assert data["intensity_level"].values.tolist() == np.repeat(
            np.array([0.2, 0.35, 0.5, 0.65, 0.8]) * STANDARD_GRAVITY, N).tolist()


def test_alike_draws_collapse_the_band_onto_the_single_fit(runs):
    """Two draws that are both draw 1's bearing: each has draw 1's counts, the band of the
    median, the dispersion and the curve is that bearing's fit alone (no width), and the fit
    of all runs (twice the counts) has the same maximum."""
    single = runs["draw 1"]
    for text in LIMITS:
        entry, band = runs["alike"]["fragility"][text], runs["alike"]["fragility"][text]["bearing_band"]
        assert band["n_exceed"] == [single["fragility"][text]["n_exceed"]] * 2
        fit = single["fragility"][text]
        assert band["median_band"] == [fit["median"]] * 2 and band["dispersion_band"] == [fit["dispersion"]] * 2
        assert band["median_interval"] == fit["median_interval"]
        below, above = band["probability_band_at_levels"]
        assert below == above
        assert entry["median"] == pytest.approx(fit["median"], rel=1e-6)
        assert entry["dispersion"] == pytest.approx(fit["dispersion"], rel=1e-5)


def test_one_draw_per_motion_keeps_each_motions_draw_at_every_level(runs, files):
    """Motion m of every level runs draw motion_draws(N, 2, seed 1)[m]: its peaks are the nested
    run's of that draw on the same motion; the counts are of those peaks; no band, and the JSON
    says why."""
    summary = runs["motion"]
    draws = motion_draws(N, len(FACTORS), seed=1)
    assert summary["bearing_posterior"]["bearing_draw"] == draws.tolist()
    assert summary["bearing_posterior"]["bearing_draws"] == "motion"
    folder = files["folder"]
    with xarray.open_dataset(folder / "motion.nc") as motion, xarray.open_dataset(folder / "nested.nc") as nested:
        assert motion["bearing_draw"].dims == ("motion",)
        np.testing.assert_array_equal(motion["bearing_draw"].values, np.tile(draws, 5))
        row = {int(d): k for k, d in enumerate(nested["bearing_draw"].values)}
        peaks = nested["base_disp"].values[[row[int(d)] for d in np.tile(draws, 5)], np.arange(5 * N)]
        np.testing.assert_allclose(motion["base_disp"].values, peaks, rtol=1e-12)
        level = np.repeat(np.arange(5), N)
    for text, inches in zip(LIMITS, (1.5, 2.0, 2.5)):
        entry = summary["fragility"][text]
        exceed = peaks > inches * 0.0254
        assert entry["n_exceed"] == np.bincount(level, exceed, 5).astype(int).tolist()
        assert entry["bearing_band"] is None and "no band over the draws" in entry["bearing_band_none"]
    assert len(set(draws.tolist())) == 2  # every draw ran


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


def test_levels_and_draws_share_one_compiled_program(files):
    """Three levels x two nested draws: one compilation; the result keeps the bearing axis and
    its draws, the levels joined along the motions; the last level's rows are, bit for bit,
    a one-level nested run of that level's motions (motions 2 N .. 3 N - 1 of the key)."""
    from teflon_jax.formats import load_bearing, load_bearing_posterior
    from teflon_jax.studies import monte_carlo, motions_at_level
    from teflon_jax.studies._posterior_motions import check_bearings

    point, posterior = load_bearing(files["posterior"]), load_bearing_posterior(files["posterior"])
    model = StochasticGroundMotion(peak_ground_acceleration=1.0, duration=3.0, time_step=0.01, rise_time=0.5,
                                   strong_motion_duration=1.5)
    structure, key = isolated_structure("rigid", bearing=point), jax.random.key(3)
    draws, stacked = np.array([1, 0]), posterior.bearings(point)
    levels = np.array([0.1, 0.3, 0.6]) * STANDARD_GRAVITY
    options = {"chunk_size": 2, "devices": jax.devices()[:1], "bearings": stacked, "bearing_draw": draws,
               "nested": True}
    check_bearings(structure, stacked)  # its eager checks compile small programs of their own
    (result, index), n_compiled = _compiles(lambda: monte_carlo_levels(structure, model, levels, 2, key=key,
                                                                        **options))
    assert n_compiled == 1
    assert result.dims == ("bearing", "motion") and result.base_disp.shape == (2, 6)
    np.testing.assert_array_equal(result.bearing_draw, draws)
    assert index.tolist() == [0, 0, 1, 1, 2, 2]
    alone = monte_carlo(structure, motions_at_level(model, levels[2]), 2, key=key, first_motion=4, **options)
    for name in ("base_disp", "base_shear_ratio", "converged"):
        np.testing.assert_array_equal(getattr(result, name)[:, 4:], getattr(alone, name), name)
    np.testing.assert_array_equal(result.pga[4:], alone.pga)


@pytest.mark.parametrize("flags, words", [
    (["--storeys", "--structure", "building"], "--storeys: runs without the posterior draws of --bearing"),
    (["--structure", "building", "--limit", "drift=0.5%"],
     "--limit drift=0.5%: runs without the posterior draws of --bearing"),
    (["--pelicun-demands", "{folder}/d.csv"], "--pelicun-demands: runs without the posterior draws"),
    (["--scheduler", "local:2", "--out", "{folder}/mc.nc"], "--scheduler: runs without the posterior draws"),
], ids=["storeys", "storey-limit", "pelicun", "scheduler"])
@pytest.mark.parametrize("draws", ["2", "motion"])
def test_runs_without_draws_are_refused_by_name(files, tmp_path, capsys, flags, words, draws):
    flags = [f.format(folder=tmp_path) for f in flags]
    argv = [*COMMON, "--bearing", str(files["posterior"]), "--bearing-draws", draws, *flags,
            "--json", str(tmp_path / "mc.json")]
    assert main(argv) == 2
    assert words in capsys.readouterr().err
    assert not list(tmp_path.iterdir())
