"""The posterior section of the bearing file: round trip, draws put into the bearing, refusals."""

import json

import jax
import numpy as np
import pytest

import teflon_jax as tj
from teflon_jax.formats import (
    MIN_POSTERIOR_ESS,
    BearingPosterior,
    load_bearing_posterior,
    save_bearing,
    thinned_posterior,
)
from teflon_jax.units import INCH

ROW = tj.load_table1()[0]
POINT = tj.paper_bearing(tj.FrictionParameters(ROW.f_max, ROW.delta_f, ROW.rate_a),
                         yield_disp=0.005 * INCH, breakaway_ratio=ROW.breakaway_ratio)
NAMES = ("f_max", "delta_f", "rate_a", "yield_disp", "breakaway_ratio")
CENTRE = dict(f_max=ROW.f_max, delta_f=ROW.delta_f, rate_a=ROW.rate_a, yield_disp=0.005 * INCH,
              breakaway_ratio=ROW.breakaway_ratio)


def _samples(chains=4, draws=250, seed=0):
    rng = np.random.default_rng(seed)
    return {n: CENTRE[n] * np.exp(0.01 * rng.standard_normal((chains, draws))) for n in NAMES}


def _posterior(max_draws=200, **kw):
    ess = {n: 800.0 + 10 * i for i, n in enumerate(NAMES)}
    return thinned_posterior(_samples(**kw), ess, max_draws=max_draws, chains=4, seed=7)


def test_round_trip_keeps_point_draws_ess_and_sampler(tmp_path):
    posterior = _posterior()
    path = save_bearing(tmp_path / "b.json", POINT, sources=["t.csv"], posterior=posterior)
    document = json.loads(path.read_text())
    section = document["posterior"]
    assert section["constants"]["rate_a"] == {"part": "friction", "constant": "rate_a",
                                              "unit": "s/m"}
    assert section["constants"]["breakaway_ratio"]["part"] == "breakaway"
    assert section["draws_before_thinning"] == 1000 and section["thinning"] == 5
    assert section["sampler"] == {"method": "NUTS", "chains": 4, "seed": 7}
    assert all(len(x) == 200 for x in section["draws"].values())
    point = tj.load_bearing(path)  # the point estimate, as without a posterior
    assert float(point.friction.rate_a) == ROW.rate_a
    loaded = tj.load_bearing_posterior(path)
    assert isinstance(loaded, tj.BearingPosterior)
    assert loaded.names == NAMES and loaded.size == 200
    for name in NAMES:
        np.testing.assert_array_equal(loaded.draws[name], posterior.draws[name])
        assert loaded.effective_sample_size[name] == posterior.effective_sample_size[name]
    assert (loaded.draws_before_thinning, loaded.thinning, loaded.chains, loaded.seed,
            loaded.method) == (1000, 5, 4, 7, "NUTS")


def test_a_file_without_posterior_has_none(tmp_path):
    path = save_bearing(tmp_path / "b.json", POINT)
    assert load_bearing_posterior(path) is None
    assert "posterior" not in json.loads(path.read_text())


def test_thinning_keeps_every_kth_draw_of_the_chains_in_turn():
    samples = _samples(chains=2, draws=501)
    posterior = thinned_posterior(samples, {n: 500.0 for n in NAMES}, max_draws=1000,
                                  chains=2, seed=0)
    assert posterior.thinning == 2 and posterior.size == 501  # ceil(1002 / 2)
    np.testing.assert_array_equal(posterior.draws["rate_a"],
                                  samples["rate_a"].reshape(-1)[::2])
    whole = thinned_posterior(samples, {n: 500.0 for n in NAMES}, max_draws=5000, chains=2, seed=0)
    assert whole.thinning == 1 and whole.size == 1002
    assert whole.quantile("f_max", 0.05) == np.quantile(samples["f_max"], 0.05)


def test_draw_k_goes_into_the_bearing_and_the_rest_stays():
    posterior = _posterior()
    for k in (0, 17, posterior.size - 1, -1):
        b = posterior.bearing(POINT, k)
        assert float(b.friction.f_max) == posterior.draws["f_max"][k]
        assert float(b.friction.delta_f) == posterior.draws["delta_f"][k]
        assert float(b.friction.rate_a) == posterior.draws["rate_a"][k]
        assert float(b.hysteresis.yield_disp) == posterior.draws["yield_disp"][k]
        assert float(b.breakaway_ratio) == posterior.draws["breakaway_ratio"][k]
        assert float(b.hysteresis.beta) == float(POINT.hysteresis.beta)
        assert b.n_interfaces == POINT.n_interfaces
    with pytest.raises(IndexError, match="draw 200 of 200"):
        posterior.bearing(POINT, 200)


def test_bearings_batch_is_each_draw_under_vmap():
    posterior = _posterior(max_draws=50)
    batch = posterior.bearings(POINT)
    assert all(np.shape(leaf)[0] == posterior.size for leaf in jax.tree_util.tree_leaves(batch))
    speed = 0.1
    mu = jax.vmap(lambda b: tj.sliding_friction(b.friction, speed))(batch)
    each = [float(tj.sliding_friction(posterior.bearing(POINT, k).friction, speed))
            for k in range(posterior.size)]
    np.testing.assert_allclose(np.asarray(mu), each, rtol=1e-15)


def test_a_subset_of_constants_and_a_bearing_without_their_part():
    subset = thinned_posterior({n: _samples()[n] for n in ("f_max", "rate_a")},
                               {"f_max": 400.0, "rate_a": 300.0}, max_draws=100, chains=4, seed=0)
    b = subset.bearing(POINT, 3)
    assert float(b.friction.delta_f) == ROW.delta_f
    no_breakaway = tj.paper_bearing(POINT.friction)
    with pytest.raises(ValueError, match="no part 'breakaway'"):
        _posterior().bearing(no_breakaway, 0)
    with pytest.raises(ValueError, match="no part 'breakaway'"):
        save_bearing("never.json", no_breakaway, posterior=_posterior())


def _document(tmp_path):
    path = save_bearing(tmp_path / "b.json", POINT, posterior=_posterior(max_draws=20))
    return json.loads(path.read_text())


def _nan(d):
    d["posterior"]["draws"]["rate_a"][3] = float("nan")


def _inf(d):
    d["posterior"]["draws"]["yield_disp"][0] = float("inf")


REFUSALS = {
    "missing draws": (lambda d: d["posterior"]["draws"].pop("delta_f"),
                      "posterior.draws: no draws for delta_f"),
    "unequal lengths": (lambda d: d["posterior"]["draws"]["f_max"].pop(),
                        "posterior.draws: every constant needs the same number"),
    "NaN draw": (_nan, "posterior.draws.rate_a: draw 3 is nan"),
    "infinite draw": (_inf, "posterior.draws.yield_disp: draw 0 is inf"),
    "unknown name": (lambda d: d["posterior"]["constants"].update(
        friction_ratio={"part": "friction", "constant": "f_max", "unit": "1"}),
        "posterior.constants: unknown constant 'friction_ratio'"),
    "negative ESS": (lambda d: d["posterior"]["effective_sample_size"].update(rate_a=-5.0),
                     "posterior.effective_sample_size.rate_a: must be a finite number > 0"),
    "zero ESS": (lambda d: d["posterior"]["effective_sample_size"].update(f_max=0),
                 "posterior.effective_sample_size.f_max: must be a finite number > 0"),
    "ESS below the floor": (
        lambda d: d["posterior"]["effective_sample_size"].update(f_max=MIN_POSTERIOR_ESS - 1),
        "posterior.effective_sample_size.f_max: 99 effective draws is below the floor of 100"),
    "missing ESS": (lambda d: d["posterior"]["effective_sample_size"].pop("yield_disp"),
                    "posterior.effective_sample_size: missing for yield_disp"),
    "wrong part": (lambda d: d["posterior"]["constants"]["rate_a"].update(part="hysteresis"),
                   "posterior.constants.rate_a: is the constant 'rate_a' of the part 'friction'"),
    "part not in the bearing": (lambda d: d["parts"].pop("breakaway"),
                                "posterior.constants.breakaway_ratio: the bearing has no parts"),
    "thinning does not match": (lambda d: d["posterior"].update(thinning=3),
                                "posterior: 20 draws kept, but every 3-th of 1000"),
    "draw out of range": (lambda d: d["posterior"]["draws"]["delta_f"].__setitem__(
        2, 2 * ROW.f_max), "posterior.draws: delta_f: must be smaller than f_max"),
    "unitless draws": (lambda d: d["posterior"]["constants"]["f_max"].pop("unit"),
                       "posterior.constants.f_max: write"),
    "missing key": (lambda d: d["posterior"].pop("sampler"), "missing key\\(s\\) \\['sampler'\\]"),
}


@pytest.mark.parametrize("case", REFUSALS)
def test_a_bad_posterior_is_refused_naming_the_file_and_key(tmp_path, case):
    change, message = REFUSALS[case]
    document = _document(tmp_path)
    change(document)
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(document))
    with pytest.raises(ValueError, match=message) as error:
        load_bearing_posterior(path)
    assert str(error.value).startswith(str(path) + ": ")
    with pytest.raises(ValueError, match=message):
        tj.load_bearing(path)  # the file as a whole is refused, not read in part


def test_draws_in_another_unit_are_read_in_si(tmp_path):
    document = _document(tmp_path)
    section = document["posterior"]
    section["constants"]["rate_a"]["unit"] = "s/in"
    section["draws"]["rate_a"] = [x * INCH for x in section["draws"]["rate_a"]]
    section["constants"]["yield_disp"]["unit"] = "mm"
    section["draws"]["yield_disp"] = [x * 1e3 for x in section["draws"]["yield_disp"]]
    path = tmp_path / "units.json"
    path.write_text(json.dumps(document))
    loaded = load_bearing_posterior(path)
    reference = _posterior(max_draws=20)
    np.testing.assert_allclose(loaded.draws["rate_a"], reference.draws["rate_a"], rtol=1e-14)
    np.testing.assert_allclose(loaded.draws["yield_disp"], reference.draws["yield_disp"],
                               rtol=1e-14)
    section["constants"]["rate_a"]["unit"] = "in"
    path.write_text(json.dumps(document))
    with pytest.raises(ValueError, match="posterior.constants.rate_a.unit"):
        load_bearing_posterior(path)


def test_the_type_refuses_bad_draws_without_a_file():
    good = dict(names=("f_max",), draws={"f_max": [0.1, 0.11]},
                effective_sample_size={"f_max": 150.0}, draws_before_thinning=2, thinning=1,
                chains=2, seed=0)
    assert BearingPosterior(**good).size == 2
    with pytest.raises(ValueError, match="unknown constant 'mu'"):
        BearingPosterior(**{**good, "names": ("mu",)})
    with pytest.raises(ValueError, match="below the floor"):
        BearingPosterior(**{**good, "effective_sample_size": {"f_max": 50.0}})
    with pytest.raises(ValueError, match="not among the sampled constants"):
        BearingPosterior(**good).quantile("rate_a", 0.5)
    posterior = BearingPosterior(**good)
    with pytest.raises(ValueError):
        posterior.draws["f_max"][0] = 1.0  # read-only
