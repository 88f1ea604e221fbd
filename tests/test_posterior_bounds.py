"""Tests of bounds from a bearing posterior (teflon_jax.studies.posterior_friction_bounds,
friction_factors, with_friction_factors and `--property-factors posterior` on `montecarlo` and
`run --suite`).

References: numpy's quantiles of known draws (normal around the point estimate), Eq. 1 evaluated
for every draw inside the quantile box (its curve lies between the two bound cases' at every
velocity), a structure built from the bound case's bearing by hand, and Table 1's constants
times the user's factors.
"""

import json

import jax
import numpy as np
import pytest
import xarray

import teflon_jax as tj
from teflon_jax.bearing import sliding_friction
from teflon_jax.cli import main
from teflon_jax.excitation import uniform_signal
from teflon_jax.formats import BearingPosterior, save_bearing
from teflon_jax.studies import (
    BOUNDING_CASES,
    bounding_design,
    friction_bounding_design,
    friction_factors,
    posterior_friction_bounds,
    with_friction_factors,
)
from teflon_jax.systems import isolated_structure, rigid_mass
from teflon_jax.units import PSI

FRICTION, _ = tj.interface_parameters("UF", 1000 * PSI, "P")
POINT = tj.paper_bearing(FRICTION)
CONSTANTS = ("f_max", "delta_f", "rate_a")


def _posterior(size=2000, spread=0.05, seed=0, extra=()):
    """Draws normal around the point's constants, relative standard deviation `spread`."""
    rng = np.random.default_rng(seed)
    centre = {n: float(getattr(FRICTION, n)) for n in CONSTANTS} | {n: float(POINT.hysteresis.yield_disp)
                                                                   for n in extra}
    draws = {n: v * (1 + spread * rng.standard_normal(size)) for n, v in centre.items()}
    return BearingPosterior(names=tuple(draws), draws=draws, effective_sample_size=dict.fromkeys(draws, 500.0),
                            draws_before_thinning=size, thinning=1, chains=1, seed=seed)


def _value(params, name):
    return float(np.asarray(getattr(params, name)))


@pytest.mark.parametrize("quantiles", [(0.05, 0.95), (0.1, 0.8)])
def test_bound_cases_take_the_numpy_quantiles_in_the_direction_of_more_friction(quantiles):
    posterior = _posterior(extra=("yield_disp",))
    cases = posterior_friction_bounds(FRICTION, posterior, quantiles=quantiles)
    assert list(cases) == list(BOUNDING_CASES)
    low, high = quantiles
    q = {n: np.quantile(posterior.draws[n], [low, high]) for n in CONSTANTS}
    # upper case: the most friction, f_max and rate_a high, delta_f low; lower case: the other ends
    assert [_value(cases["upper"], n) for n in CONSTANTS] == [q["f_max"][1], q["delta_f"][0], q["rate_a"][1]]
    assert [_value(cases["lower"], n) for n in CONSTANTS] == [q["f_max"][0], q["delta_f"][1], q["rate_a"][0]]
    assert cases["nominal"] is FRICTION
    design = friction_bounding_design(cases)
    for name in CONSTANTS:
        np.testing.assert_array_equal(design[name], [_value(cases[c], name) for c in BOUNDING_CASES])


def test_every_draw_inside_the_quantile_box_lies_between_the_bound_curves():
    """mu(v) = f_max - delta_f exp(-a |v|) (Eq. 1) of each draw whose three constants are
    inside their 5-95 % intervals lies between the lower and upper cases' at every velocity."""
    posterior = _posterior(spread=0.05, seed=1)
    cases = posterior_friction_bounds(FRICTION, posterior)
    draws = np.stack([posterior.draws[n] for n in CONSTANTS])
    ends = np.quantile(draws, [0.05, 0.95], axis=1)
    inside = np.all((draws >= ends[0][:, None]) & (draws <= ends[1][:, None]), axis=0)
    assert inside.sum() > 100
    speed = np.concatenate([[0.0], np.geomspace(1e-4, 2.0, 200)])
    lower = np.asarray(sliding_friction(cases["lower"], speed))
    upper = np.asarray(sliding_friction(cases["upper"], speed))
    for f_max, delta_f, rate_a in draws[:, inside].T:
        mu = np.asarray(sliding_friction(tj.FrictionParameters(f_max, delta_f, rate_a), speed))
        assert np.all(lower <= mu + 1e-15) and np.all(mu <= upper + 1e-15)
    assert np.all(lower < np.asarray(sliding_friction(FRICTION, speed)))


def test_factors_are_the_bounds_over_the_point_and_lambda_for_user_factors():
    posterior = _posterior()
    cases = posterior_friction_bounds(FRICTION, posterior)
    table = friction_factors(cases)
    for case in BOUNDING_CASES:
        for name in CONSTANTS:
            assert table[case][name] == pytest.approx(_value(cases[case], name) / _value(FRICTION, name), rel=1e-14)
        f_min = _value(cases[case], "f_max") - _value(cases[case], "delta_f")
        assert table[case]["f_min"] == pytest.approx(f_min / float(FRICTION.f_min), rel=1e-12)
    scaled = {"nominal": FRICTION, "upper": FRICTION.scaled(1.3), "lower": FRICTION.scaled(0.85)}
    assert friction_factors(scaled)["lower"] == pytest.approx({"f_max": 0.85, "delta_f": 0.85, "rate_a": 1.0,
                                                               "f_min": 0.85}, rel=1e-12)


def test_a_structure_with_factors_is_the_one_built_from_the_case_bearing():
    """`with_friction_factors` on a built structure gives the structure built from the bound
    case's bearing, leaf for leaf; (lambda, lambda, 1) on an anisotropic bearing is its
    `scaled(lambda)`."""
    cases = posterior_friction_bounds(FRICTION, _posterior())
    factors = {k: v for k, v in friction_factors(cases)["lower"].items() if k != "f_min"}
    ground = uniform_signal(np.zeros(50), 0.01)
    built = dict(weight=1e5, ground_acceleration=ground, ground_y=ground, time_step=0.005, isolation_period=2.0)
    got = with_friction_factors(rigid_mass(components=2, bearing=POINT, **built), factors)
    case_bearing = tj.paper_bearing(cases["lower"])
    want = rigid_mass(components=2, bearing=case_bearing, **built)
    for a, b in zip(_leaves(got), _leaves(want), strict=True):
        np.testing.assert_allclose(np.asarray(a), np.asarray(b), rtol=1e-14)
    perpendicular, _ = tj.interface_parameters("UF", 1000 * PSI, "T")
    anisotropic = tj.paper_bearing(FRICTION, friction_perpendicular=perpendicular)
    scaled = with_friction_factors(anisotropic, {"f_max": 1.3, "delta_f": 1.3})
    for a, b in zip(_leaves(scaled), _leaves(anisotropic.scaled(1.3))):
        np.testing.assert_allclose(np.asarray(a), np.asarray(b), rtol=1e-15)
    with pytest.raises(ValueError, match="^structure: has no SlidingBearing"):
        with_friction_factors({"mass": np.ones(2)}, factors)


def test_a_slab_with_factors_is_the_slab_on_the_case_bearings():
    """Bearing groups of different friction (a slab's stacked bearings): each group's
    constants times the factors, as a slab built on the groups' case bearings."""
    from teflon_jax.systems import slab_on_bearings

    factors = {"f_max": 0.9, "delta_f": 1.1, "rate_a": 0.95}
    other = tj.FrictionParameters(0.15, 0.1, 30.0)
    ground = uniform_signal(np.zeros(50), 0.01)

    def slab(bearings):
        return slab_on_bearings(length_x=20.0, length_y=12.0, weight=1e6, centre_of_mass=(10.0, 6.0),
                                positions=[(2.0, 2.0), (18.0, 10.0)], bearings=bearings, loads=[5e5, 5e5],
                                ground_acceleration=ground, ground_y=ground, time_step=0.005, isolation_period=2.0)

    def times(params):
        return tj.FrictionParameters(*(getattr(params, n) * factors[n] for n in CONSTANTS))

    got = with_friction_factors(slab([POINT, tj.paper_bearing(other)]), factors)
    want = slab([tj.paper_bearing(times(FRICTION)), tj.paper_bearing(times(other))])
    for a, b in zip(_leaves(got), _leaves(want), strict=True):
        np.testing.assert_allclose(np.asarray(a), np.asarray(b), rtol=1e-14)


def _leaves(tree):
    return jax.tree_util.tree_leaves(tree)


def test_factors_scale_a_given_bearing_not_table_1():
    """`bounding_design` of a structure running a bearing file's bearing multiplies that
    bearing's f_max and delta_f, not Table 1's at the structure's pressure."""
    given = tj.paper_bearing(tj.FrictionParameters(0.2, 0.1, 30.0))
    design = bounding_design(isolated_structure("rigid", bearing=given), lower=0.8, upper=1.25)
    np.testing.assert_allclose(design["f_max"], 0.2 * np.array([1.0, 1.25, 0.8]), rtol=1e-15)
    np.testing.assert_allclose(design["delta_f"], 0.1 * np.array([1.0, 1.25, 0.8]), rtol=1e-15)


@pytest.mark.parametrize("quantiles, message", [
    ((0.0, 0.9), r"^lower: a quantile must lie strictly between 0 and 1"),
    ((0.1, 1.0), r"^upper: a quantile must lie strictly between 0 and 1"),
    ((0.9, 0.1), r"^lower: the lower quantile 0.9 is not below the upper quantile 0.1"),
    ((0.5, 0.5), r"^lower: the lower quantile 0.5 is not below"),
])
def test_bad_quantiles_are_refused(quantiles, message):
    with pytest.raises(ValueError, match=message):
        posterior_friction_bounds(FRICTION, _posterior(), quantiles=quantiles)


def test_a_lower_case_without_positive_f_min_is_refused():
    """Wide draws (30 %): the 5 % f_max less the 95 % delta_f is not > 0."""
    with pytest.raises(ValueError, match=r"^quantiles: the lower case's f_max .* leaves f_min = .*, not > 0"):
        posterior_friction_bounds(FRICTION, _posterior(spread=0.3))


def _files(tmp_path, **kw):
    posterior = _posterior(size=400, **kw)
    save_bearing(tmp_path / "post.json", POINT, posterior=posterior)
    save_bearing(tmp_path / "plain.json", POINT)
    return posterior


MC = ["montecarlo", "--motions", "2", "--no-progress"]


@pytest.mark.parametrize("argv, message", [
    (MC + ["--property-factors", "posterior"], "--property-factors posterior: takes the bounds from the "
     "posterior of a bearing file; add --bearing FILE"),
    (MC + ["--property-factors", "posterior", "--bearing", "{plain}"], "--property-factors posterior: --bearing "
     "{plain} has no posterior section"),
    (MC + ["--property-factors", "posterior", "--bearing", "{post}", "--posterior-quantiles", "0,0.9"],
     "--posterior-quantiles 0,0.9: lower: a quantile must lie strictly between 0 and 1"),
    (MC + ["--property-factors", "posterior", "--bearing", "{post}", "--posterior-quantiles", "0.95,0.05"],
     "--posterior-quantiles 0.95,0.05: lower: the lower quantile 0.95 is not below the upper quantile 0.05"),
    (MC + ["--property-factors", "posterior", "--bearing", "{post}", "--posterior-quantiles", "0.9"],
     "--posterior-quantiles: write LOWER,UPPER, e.g. 0.05,0.95"),
    (MC + ["--posterior-quantiles", "0.1,0.9"], "--posterior-quantiles: picks the bounds of --property-factors "
     "posterior; add it"),
    (MC + ["--property-factors", "0.85,1.3", "--bearing", "{plain}", "--posterior-quantiles", "0.1,0.9"],
     "--posterior-quantiles: applies to the posterior of a --bearing file, and --property-factors 0.85,1.3 has none"),
    (MC + ["--property-factors", "posteriors"], "--property-factors: write LOWER,UPPER, e.g. 0.85,1.3 (or posterior)"),
    (["run", "--suite", "{suite}", "--record-units", "g", "--property-factors", "posterior"],
     "--property-factors posterior: takes the bounds from the posterior of a bearing file; add --bearing FILE"),
    (["run", "--suite", "{suite}", "--record-units", "g", "--property-factors", "posterior", "--bearing",
      "{plain}"], "--property-factors posterior: --bearing {plain} has no posterior section"),
    (["run", "--suite", "{suite}", "--record-units", "g", "--property-factors", "posterior", "--bearing",
      "{post}", "--posterior-quantiles", "0.2,1.5"], "--posterior-quantiles 0.2,1.5: upper: a quantile must lie"),
])
def test_bad_posterior_bounds_exit_before_any_run(argv, message, tmp_path, capsys):
    _files(tmp_path)
    (tmp_path / "suite.csv").write_text("record_x,record_y,scale\nnot_read.txt,,1\n")
    names = {"post": tmp_path / "post.json", "plain": tmp_path / "plain.json", "suite": tmp_path / "suite.csv"}
    assert main([a.format(**names) for a in argv]) == 2
    assert message.format(**names) in capsys.readouterr().err


def test_montecarlo_posterior_bounds_run_the_quantiles(tmp_path, capsys):
    """Three bearings under the same 6 motions: the cases run the numpy quantiles of the
    file's draws (JSON and the results file's design), reported as factors of the point."""
    posterior = _files(tmp_path)
    status = main(["montecarlo", "--motions", "6", "--pga", "0.4g", "--duration", "8s", "--strong-motion", "4s",
                   "--bearing", str(tmp_path / "post.json"), "--property-factors", "posterior",
                   "--posterior-quantiles", "0.1,0.9", "--json", str(tmp_path / "b.json"),
                   "--out", str(tmp_path / "b.nc"), "--no-progress"])
    data = json.loads((tmp_path / "b.json").read_text())
    q = {n: np.quantile(posterior.draws[n], [0.1, 0.9]) for n in CONSTANTS}
    want = {"upper": (q["f_max"][1], q["delta_f"][0], q["rate_a"][1]),
            "lower": (q["f_max"][0], q["delta_f"][1], q["rate_a"][0])}
    with xarray.open_dataset(tmp_path / "b.nc") as dataset:
        design = {n: dataset[f"design_{n}"].values for n in CONSTANTS}
        ok = dataset["converged"].values.astype(bool)
    assert status == (0 if ok.all() else 1)
    for i, case in enumerate(BOUNDING_CASES):
        values = want.get(case, tuple(_value(FRICTION, n) for n in CONSTANTS))
        assert tuple(data["cases"][case][n] for n in CONSTANTS) == pytest.approx(values, rel=1e-12)
        assert tuple(design[n][i] for n in CONSTANTS) == pytest.approx(values, rel=1e-12)
        assert data["cases"][case]["friction_factors"]["f_max"] == pytest.approx(values[0] / _value(FRICTION, "f_max"), rel=1e-12)
    entry = data["property_factors"]
    assert entry["quantiles"] == [0.1, 0.9] and entry["draws"] == 400 and entry["sampled"] == list(CONSTANTS)
    assert data["governs"]["base_disp_in"]["by_mean"] == "lower"
    assert data["governs"]["base_shear_ratio"]["by_mean"] == "upper"
    out = capsys.readouterr().out
    assert "posterior 0.1-0.9" in out and f"{q['f_max'][0] / _value(FRICTION, 'f_max'):.3f} / " in out


def test_factors_with_a_posterior_bearing_report_its_bounds_beside_them(tmp_path, capsys):
    """User factors on a bearing file that holds a posterior: the posterior's factors at the
    default quantiles are in the JSON beside the factors, for comparison."""
    posterior = _files(tmp_path)
    status = main(["montecarlo", "--motions", "2", "--pga", "0.3g", "--duration", "6s", "--strong-motion", "3s",
                   "--bearing", str(tmp_path / "post.json"), "--property-factors", "0.85,1.3",
                   "--json", str(tmp_path / "b.json"), "--no-progress"])
    data = json.loads((tmp_path / "b.json").read_text())
    assert status in (0, 1)
    entry = data["property_factors"]
    assert entry["factors"]["upper"] == {"f_max": 1.3, "delta_f": 1.3, "rate_a": 1.0, "f_min": 1.3}
    beside = entry["posterior_factors"]
    assert beside["quantiles"] == [0.05, 0.95]
    assert beside["factors"]["upper"]["f_max"] == pytest.approx(
        np.quantile(posterior.draws["f_max"], 0.95) / _value(FRICTION, "f_max"), rel=1e-12)
    # the factors scale the file's bearing (here Table 1's row, as saved)
    assert data["cases"]["upper"]["f_max"] == pytest.approx(1.3 * _value(FRICTION, "f_max"), rel=1e-12)
    out = capsys.readouterr().out
    assert "factors 0.85,1.3" in out and "posterior 0.05-0.95" in out


def _suite(tmp_path, count=2, seconds=3.0):
    t = 0.01 * np.arange(int(seconds / 0.01) + 1)
    rng = np.random.default_rng(11)
    rows = []
    for i in range(count):
        for axis in "xy":
            a = 0.3 * rng.normal(size=t.size) * np.sin(np.pi * t / t[-1]) ** 2
            (tmp_path / f"{axis}{i}.txt").write_text(
                "time acc\n" + "\n".join(f"{ti:.4f} {ai:.6e}" for ti, ai in zip(t, a)) + "\n")
        rows.append(f"p{i},x{i}.txt,y{i}.txt,1\n")
    (tmp_path / "suite.csv").write_text("name,record_x,record_y,scale\n" + "".join(rows))
    return tmp_path / "suite.csv"


@pytest.mark.slow  # four compilations of a two-component suite (about 70 s on two shared cores)
def test_run_suite_posterior_cases_are_the_case_bearings_run_alone(tmp_path, capsys):
    """`run --suite --bearing post.json --property-factors posterior`: the lower case's peaks
    are those of the suite run with a bearing file holding the lower case's constants."""
    posterior = _files(tmp_path)
    suite = _suite(tmp_path)
    common = ["run", "--suite", str(suite), "--record-units", "g", "--isolation-period", "2.5s"]
    assert main(common + ["--bearing", str(tmp_path / "post.json"), "--property-factors", "posterior",
                          "--json", str(tmp_path / "b.json")]) == 0
    data = json.loads((tmp_path / "b.json").read_text())
    lower = posterior_friction_bounds(FRICTION, posterior)["lower"]
    assert data["cases"]["lower"]["f_max"] == np.quantile(posterior.draws["f_max"], 0.05)
    save_bearing(tmp_path / "lower.json", tj.paper_bearing(lower))
    assert main(common + ["--bearing", str(tmp_path / "lower.json"), "--json", str(tmp_path / "alone.json")]) == 0
    alone = json.loads((tmp_path / "alone.json").read_text())
    for pair, peaks in alone["pairs"].items():
        assert data["cases"]["lower"]["pairs"][pair]["base_disp_resultant_m"] == pytest.approx(
            peaks["base_disp_resultant_m"], rel=1e-12)
    means = {c: data["cases"][c]["summary"]["base_disp_resultant_m"]["mean"] for c in BOUNDING_CASES}
    assert means["upper"] < means["nominal"] < means["lower"]
    assert data["governs"]["base_disp_resultant_m"]["by_mean"] == "lower"
    assert data["governs"]["base_shear_ratio_resultant"]["by_mean"] == "upper"


def test_factors_beside_a_posterior_without_bounds_run_and_say_why(tmp_path):
    """User factors on a bearing whose posterior gives no lower case at the default quantiles
    (draws of f_max spread 15 % with f_min pinned, so delta_f follows f_max: the corner's
    f_min <= 0, every draw's > 0): the factors are read, the report beside them says why;
    asking for those quantiles by name, or for the posterior's bounds, is refused."""
    import argparse

    from teflon_jax.cli._bounding import read_bounds
    from teflon_jax.formats import read_bearing_file

    rng = np.random.default_rng(2)
    f_max = _value(FRICTION, "f_max") * (1 + 0.15 * rng.standard_normal(400))
    f_min = float(FRICTION.f_min) * (1 + 0.05 * rng.standard_normal(400))
    draws = {"f_max": f_max, "delta_f": f_max - f_min}
    posterior = BearingPosterior(names=tuple(draws), draws=draws, effective_sample_size=dict.fromkeys(draws, 400.0),
                                 draws_before_thinning=400, thinning=1, chains=1, seed=0)
    save_bearing(tmp_path / "wide.json", POINT, posterior=posterior)

    def args(factors, quantiles=None):
        return argparse.Namespace(property_factors=factors, posterior_quantiles=quantiles,
                                  bearing=tmp_path / "wide.json", isolator="flat")

    read = read_bearing_file(tmp_path / "wide.json")
    bounds = read_bounds(args("0.85,1.3"), read)
    assert bounds.factors == (0.85, 1.3) and bounds.posterior_table() is None
    assert "f_min" in bounds.unbounded and "quantiles 0.05,0.95" in bounds.unbounded
    assert bounds.payload("wide.json")["posterior_factors"]["error"] == bounds.unbounded
    for text, quantiles in (("0.85,1.3", "0.05,0.95"), ("posterior", None)):
        with pytest.raises(ValueError, match="leaves f_min = .*, not > 0"):
            read_bounds(args(text, quantiles), read)
