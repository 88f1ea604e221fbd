"""The mixture section of the bearing file (`BearingMixture`): round trip, refusals, the share
of the motions each composition runs, and how the Monte Carlo runs the compositions."""

import json
import math

import numpy as np
import pytest

import teflon_jax as tj
from teflon_jax.formats import (
    BearingMixture,
    BearingPosterior,
    MixtureComposition,
    load_bearing_mixture,
    load_bearing_posterior,
    save_bearing,
)
from teflon_jax.units import INCH

ROW = tj.load_table1()[0]
FRICTION = tj.FrictionParameters(ROW.f_max, ROW.delta_f, ROW.rate_a)
WITH_BREAKAWAY = tj.paper_bearing(FRICTION, yield_disp=0.005 * INCH, breakaway_ratio=ROW.breakaway_ratio)
PLAIN = tj.paper_bearing(FRICTION, yield_disp=0.005 * INCH)
DELTA_BIC = 2 * math.log(9.0)  # the plain composition 9 times less likely: weights 0.9 and 0.1


def _posterior(names, size=120, seed=0):
    rng = np.random.default_rng(seed)
    centre = {"f_max": ROW.f_max, "delta_f": ROW.delta_f, "breakaway_ratio": ROW.breakaway_ratio}
    draws = {n: centre[n] * (1 + 0.01 * rng.standard_normal(size)) for n in names}
    return BearingPosterior(names=tuple(names), draws=draws,
                            effective_sample_size={n: float(size) for n in names},
                            draws_before_thinning=size, thinning=1, chains=1, seed=seed, method="Laplace")


def _mixture(delta_bic=DELTA_BIC, **kw):
    w = 1.0 / (1.0 + math.exp(-delta_bic / 2))
    return BearingMixture((
        MixtureComposition(("velocity_dependence", "breakaway"), w, WITH_BREAKAWAY,
                           _posterior(("f_max", "breakaway_ratio")), delta_bic=0.0),
        MixtureComposition(("velocity_dependence",), 1 - w, PLAIN, _posterior(("f_max", "delta_f"), seed=1),
                           delta_bic=delta_bic)), criterion="bic", **kw)


def test_bic_weights_are_exp_of_minus_half_the_delta_normalised():
    mixture = _mixture()
    np.testing.assert_allclose(mixture.weights, [0.9, 0.1], rtol=1e-12)
    assert mixture.size == 2 and mixture.compositions[1].label == "velocity_dependence"


def test_round_trip_keeps_each_composition(tmp_path):
    mixture = _mixture(left_out=({"effects": ["velocity_dependence", "wear"], "weight": 1e-5},),
                       min_weight=1e-3)
    path = save_bearing(tmp_path / "m.json", WITH_BREAKAWAY, sources=["r.csv"], mixture=mixture)
    section = json.loads(path.read_text())["mixture"]
    assert section["criterion"] == "bic" and section["min_weight"] == 1e-3
    assert [c["effects"] for c in section["compositions"]] == [["velocity_dependence", "breakaway"],
                                                               ["velocity_dependence"]]
    assert "breakaway" in section["compositions"][0]["parts"]
    assert "breakaway" not in section["compositions"][1]["parts"]
    assert section["compositions"][1]["posterior"]["sampler"] == {"method": "Laplace", "chains": 1,
                                                                  "seed": 1}
    loaded = load_bearing_mixture(path)
    np.testing.assert_array_equal(loaded.weights, mixture.weights)
    for a, b in zip(loaded.compositions, mixture.compositions):
        assert a.effects == b.effects and a.delta_bic == b.delta_bic
        assert (a.bearing.breakaway_ratio is None) == (b.bearing.breakaway_ratio is None)
        for name in b.posterior.names:
            np.testing.assert_array_equal(a.posterior.draws[name], b.posterior.draws[name])
    assert loaded.left_out == ({"effects": ["velocity_dependence", "wear"], "weight": 1e-5},)
    # the point estimate is read as before, and the file holds no posterior of one composition
    assert float(tj.load_bearing(path).breakaway_ratio) == ROW.breakaway_ratio
    assert load_bearing_posterior(path) is None
    assert load_bearing_mixture(save_bearing(tmp_path / "p.json", PLAIN)) is None


def _edited(tmp_path, edit):
    document = tj.formats.bearing_to_dict(WITH_BREAKAWAY, mixture=_mixture())
    edit(document)
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(document))
    return path


def _set(keys, value):
    def edit(document):
        entry = document
        for key in keys[:-1]:
            entry = entry[key]
        entry[keys[-1]] = value
    return edit


def _two_weights(a, b):
    def edit(document):
        document["mixture"]["compositions"][0]["weight"] = a
        document["mixture"]["compositions"][1]["weight"] = b
    return edit


@pytest.mark.parametrize("edit, message", [
    (_set(["mixture", "compositions", 0, "weight"], 0.8), r"mixture.compositions: the weights sum to 0\.9"),
    (_two_weights(0.5, 0.5), r"mixture.compositions\[velocity_dependence\].weight: 0.5 does not follow "
                             r"from its delta_bic"),
    (_set(["mixture", "compositions", 1, "posterior"], None), r"mixture.compositions\[1\]: posterior: must be "
                                                             "an object"),
    (_set(["mixture", "compositions", 0, "weight"], float("nan")), r"mixture.compositions\[0\].weight: must be a finite number"),
    (_set(["mixture", "compositions", 1, "delta_bic"], float("nan")), r"mixture.compositions\[1\].delta_bic: must be a finite number"),
    (_set(["mixture", "compositions", 1, "posterior", "draws", "f_max", 3], float("nan")),
     r"mixture.compositions\[1\]: posterior.draws.f_max: draw 3 is nan"),
    (_set(["mixture", "compositions", 1, "effects"], ["breakaway", "velocity_dependence"]),
     "is listed twice"),
    (_set(["mixture", "criterion"], "aic"), r"mixture.criterion: unknown 'aic'"),
    (_set(["mixture", "compositions", 0, "posterior", "draws", "breakaway_ratio", 0], 0.5),
     r"mixture.compositions\[0\]: posterior.draws: breakaway_ratio"),
    (_set(["mixture", "compositions", 1, "parts", "friction", "delta_f", "value"], 0.5),
     r"mixture.compositions\[1\]: parts.friction.delta_f: must be smaller than f_max \(0.1"),
    (_set(["mixture", "compositions", 1, "colour"], "red"), r"mixture.compositions\[1\]: must be an object "
                                                           "with the keys"),
    (_set(["posterior"], {}), "holds a 'posterior'.*or a 'mixture'.*not both"),
])
def test_a_bad_mixture_is_refused_naming_the_file_and_key(tmp_path, edit, message):
    path = _edited(tmp_path, edit)
    for read in (load_bearing_mixture, tj.load_bearing):
        with pytest.raises(ValueError, match=message) as error:
            read(path)
        assert str(error.value).startswith(str(path))


def test_the_type_refuses_a_composition_without_draws_and_weights_not_summing_to_one():
    with pytest.raises(ValueError, match="every composition carries draws"):
        MixtureComposition(("velocity_dependence",), 1.0, PLAIN, None, delta_bic=0.0)
    one = MixtureComposition(("velocity_dependence",), 0.6, PLAIN, _posterior(("f_max",)), delta_bic=0.0)
    with pytest.raises(ValueError, match="the weights sum to 0.6"):
        BearingMixture((one,))
    with pytest.raises(ValueError, match="weight: must be a finite number in"):
        MixtureComposition(("velocity_dependence",), 0.0, PLAIN, _posterior(("f_max",)), delta_bic=0.0)


@pytest.mark.parametrize("n", [1, 7, 10, 1000])
def test_each_composition_runs_the_floor_or_ceiling_of_its_share(n):
    mixture = _mixture(delta_bic=1.3)
    for seed in range(20):
        counts = mixture.motion_counts(n, seed=seed)
        assert counts.sum() == n
        share = n * mixture.weights
        assert np.all((counts == np.floor(share)) | (counts == np.ceil(share))), (counts, share)
        of = mixture.composition_of_motions(n, seed=seed)
        np.testing.assert_array_equal(np.bincount(of, minlength=2), counts)
        assert np.all(np.diff(of) >= 0)  # composition c on the motions after those of 0..c-1


def test_the_shares_are_unbiased_over_seeds():
    # systematic sampling: E[n_c] = N w_c, so the mean over seeds tends to N w_c (std <= 0.5 / sqrt(S))
    mixture = _mixture(delta_bic=1.3)
    mean = np.mean([mixture.motion_counts(7, seed=s) for s in range(4000)], axis=0)
    np.testing.assert_allclose(mean, 7 * mixture.weights, atol=0.03)


def test_the_monte_carlo_runs_each_composition_on_its_motions_and_joins_them():
    """`runner_of` with a recording stand-in for `monte_carlo`: composition c runs its count of
    motions from the first after those of 0..c-1, with its point bearing in the structure and
    one of its draws per motion; the results are joined in the order of the motions."""
    from teflon_jax.cli._mixture_runs import MixtureRun, joined, runner_of
    from teflon_jax.studies import MonteCarloResult, motion_draws, structure_bearing

    mixture = _mixture(delta_bic=1.3)
    counts = mixture.motion_counts(9, seed=4)
    run = MixtureRun(mixture, "mixture", None, 4, "m.json", counts)
    calls, ticks = [], []

    def stand_in(structure, motions, n, *, key, chunk_size, progress, first_motion, bearings, bearing_draw):
        calls.append((structure_bearing(structure), n, first_motion, bearings, np.asarray(bearing_draw)))
        progress(n, n)
        motion = first_motion + np.arange(n)
        return MonteCarloResult(base_disp=motion * 1.0, base_shear_ratio=motion * 0.1,
                                smooth_base_disp=motion * 1.0, smooth_base_shear_ratio=motion * 0.1,
                                converged=np.ones(n, bool), pga=np.ones(n), design={}, dims=("motion",),
                                n_devices=1, chunk_size=chunk_size, wall_s=1.0, compile_s=0.5,
                                memory_estimate_bytes=10 * n, bearing_draw=np.asarray(bearing_draw))

    structure = tj.isolated_structure("rigid", bearing=PLAIN, pressure=1000 * 6894.757)
    result = runner_of(run, stand_in)(structure, "motions", 9, key=None, chunk_size=4,
                                      progress=lambda done, total: ticks.append((done, total)))
    assert [c[1] for c in calls] == [int(n) for n in counts if n]
    assert [c[2] for c in calls] == list(np.cumsum([0, *counts])[:-1][counts > 0])
    for (bearing, n, _first, bearings, draws), c in zip(calls, mixture.compositions):
        assert (bearing.breakaway_ratio is None) == (c.bearing.breakaway_ratio is None)
        np.testing.assert_array_equal(draws, motion_draws(n, c.posterior.size, seed=4))
        np.testing.assert_array_equal(np.asarray(bearings.friction.f_max), c.posterior.draws["f_max"])
    np.testing.assert_array_equal(result.base_disp, np.arange(9.0))
    assert result.wall_s == len(calls) and result.memory_estimate_bytes == 10 * max(counts)
    assert ticks[-1] == (9, 9)
    assert runner_of(None, stand_in) is stand_in
    assert joined([result]).n_motions == 9


def _mixture_file(tmp_path, *, backlash=False):
    import equinox as eqx

    mixture = _mixture()
    if backlash:
        gapped = eqx.tree_at(lambda b: b.backlash, PLAIN, tj.bearing.Backlash(0.001),
                             is_leaf=lambda x: x is None)
        second = mixture.compositions[1]
        mixture = BearingMixture((mixture.compositions[0], MixtureComposition(
            ("velocity_dependence", "backlash"), second.weight, gapped, second.posterior,
            delta_bic=second.delta_bic)))
    return save_bearing(tmp_path / "mixture.json", WITH_BREAKAWAY, mixture=mixture)


@pytest.mark.parametrize("flags, message", [
    (["--bearing-draws", "5"], "--bearing-draws 5: --bearing .* holds a mixture of 2 compositions"),
    (["--pga", "0.2g,0.4g"], "--pga 0.2g,0.4g: runs one --pga level without --limit over the mixture"),
    (["--limit", "base_disp=2in"], "--limit base_disp=2in: runs one --pga level"),
    (["--storeys"], "--storeys: runs without the posterior draws"),
    (["backlash"], "mixture composition velocity_dependence\\+backlash \\(weight 0.1\\): .*backlash"),
])
def test_what_the_monte_carlo_cannot_run_over_a_mixture_is_refused_before_any_work(tmp_path, capsys,
                                                                                    flags, message):
    from teflon_jax.cli import main

    path = _mixture_file(tmp_path, backlash=flags == ["backlash"])
    flags = [] if flags == ["backlash"] else flags
    structure = ["--structure", "building"] if "--storeys" in flags else []
    code = main(["montecarlo", "--motions", "4", "--bearing", str(path), "--json", str(tmp_path / "mc.json"),
                 "--no-progress", *structure, *flags])
    assert code == 2
    assert __import__("re").search(message, capsys.readouterr().err)
    assert not (tmp_path / "mc.json").exists()
