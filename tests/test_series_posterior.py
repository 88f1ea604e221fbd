"""The posterior of a double friction pendulum's surface friction, from its test to a Monte Carlo:
`fit_series_bayes` (NUTS through the series model the least-squares fit and the structures
run, radii held at their least-squares values), the draws in the isolator file
(`IsolatorPosterior`, checked draw by draw), and a Monte Carlo that runs one draw per motion,
each run the structure on that draw's pendulum. Constantinou, Mokha & Reinhorn (1990), Eq. 1;
Fenz & Constantinou (2006) (series model)."""

import json

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from test_bayes import interrupted_at_a_block
from test_double_fit import TRUE, _record, _start

from identification.bayes import fit_series_bayes, series_priors
from identification.bearing_fit import (
    fit_double_pendulum_test,
    series_parameters,
    series_with_parameters,
)
from teflon_jax.cli import main
from teflon_jax.excitation import StochasticGroundMotion
from teflon_jax.formats import (
    IsolatorPosterior,
    isolator_to_dict,
    load_isolator,
    load_isolator_posterior,
    write_isolator,
    write_test_record,
)
from teflon_jax.studies import monte_carlo, motion_draws
from teflon_jax.systems import isolated_structure
from teflon_jax.units import STANDARD_GRAVITY

SAMPLED = ("bottom_f_max", "bottom_delta_f", "bottom_rate_a", "top_f_max", "top_delta_f", "top_rate_a")


def _posterior(draws: dict, size=4) -> IsolatorPosterior:
    return IsolatorPosterior(names=tuple(draws), draws=draws, effective_sample_size={n: 400.0 for n in draws},
                             draws_before_thinning=size, thinning=1, chains=2, seed=0)


def test_the_isolator_file_keeps_the_draws_and_puts_each_into_its_surface(tmp_path):
    """Written and read back in SI; a file that gives them in s/in is converted; each draw lands
    in its own surface's friction, the other constants the file's."""
    draws = {"bottom_f_max": [0.05, 0.051, 0.049, 0.052], "top_rate_a": [20.0, 21.0, 19.0, 22.0]}
    path = tmp_path / "post.json"
    write_isolator(path, TRUE, posterior=_posterior(draws))
    again = load_isolator_posterior(path)
    assert again.names == ("bottom_f_max", "top_rate_a") and again.size == 4
    np.testing.assert_array_equal(again.draws["top_rate_a"], draws["top_rate_a"])
    stacked = again.bearings(load_isolator(path))
    np.testing.assert_allclose(stacked.bottom_friction.f_max, draws["bottom_f_max"])
    np.testing.assert_allclose(stacked.top_friction.rate_a, draws["top_rate_a"])
    np.testing.assert_allclose(stacked.top_friction.f_max, np.full(4, float(TRUE.top_friction.f_max)))
    document = json.loads(path.read_text())
    document["posterior"]["constants"]["top_rate_a"]["unit"] = "s/in"
    path.write_text(json.dumps(document))
    np.testing.assert_allclose(load_isolator_posterior(path).draws["top_rate_a"],
                               np.asarray(draws["top_rate_a"]) / 0.0254)
    plain = tmp_path / "plain.json"
    write_isolator(plain, TRUE)
    assert load_isolator_posterior(plain) is None


def _another(name, unit):
    """A change of a posterior object that adds the constant `name` with four draws."""
    def change(posterior):
        posterior["constants"][name] = {"unit": unit}
        posterior["draws"][name] = [0.05] * 4
        posterior["effective_sample_size"][name] = 400.0

    return change


@pytest.mark.parametrize("change, message", [
    (_another("bottom_radius", "m"), "unknown constant 'bottom_radius'"),
    (_another("inner_f_max", "1"), "has no surface 'inner'"),
    (lambda d: d["draws"]["bottom_f_max"].__setitem__(2, 0.01), "draw 2: "),
    (lambda d: d["effective_sample_size"].update({"bottom_f_max": 20.0}), "below the floor of 100"),
    (lambda d: d.pop("sampler"), r"missing key\(s\) \['sampler'\]"),
    (lambda d: d.update({"effective_sample_size": [812.0]}), "effective_sample_size: must be an object"),
    (lambda d: d["draws"].update({"bottom_f_max": "0.05"}), "draws.bottom_f_max: must be a list of numbers"),
])
def test_a_posterior_the_pendulum_cannot_take_is_refused_naming_it(tmp_path, change, message):
    """Unknown constants or surfaces, a draw whose delta_f exceeds its f_max (draw 2: f_max
    0.01 < delta_f 0.025), too few effective draws, a missing key, effective sample sizes not
    given by name, draws not a list: refused naming the file (the bearing file's reader)."""
    path = tmp_path / "post.json"
    write_isolator(path, TRUE, posterior=_posterior({"bottom_f_max": [0.05, 0.051, 0.049, 0.052]}))
    document = json.loads(path.read_text())
    change(document["posterior"])
    path.write_text(json.dumps(document))
    with pytest.raises(ValueError, match=message) as error:
        load_isolator(path)
    assert str(path) in str(error.value)


def test_a_monte_carlo_over_draws_runs_each_motion_on_its_own_pendulum():
    """`monte_carlo(bearings=...)` on a double pendulum: motion m's peaks are those of the same
    motion under the structure built on its draw k(m) alone, to rounding (the draws' friction
    0.6-1.6 times the point's, so the draws do differ)."""
    draws = {"bottom_f_max": [0.03, 0.05, 0.08], "top_f_max": [0.06, 0.09, 0.14]}
    posterior = _posterior(draws, size=3)
    structure = isolated_structure("rigid", isolator=TRUE, time_step=0.005)
    model = StochasticGroundMotion(peak_ground_acceleration=0.3 * STANDARD_GRAVITY, duration=8.0, time_step=0.01,
                                   rise_time=1.0, strong_motion_duration=4.0)
    order = motion_draws(3, 3, seed=1)
    result = monte_carlo(structure, model, 3, key=jax.random.key(2), chunk_size=3,
                         bearings=posterior.bearings(TRUE), bearing_draw=order)
    assert np.all(result.converged)
    np.testing.assert_array_equal(result.bearing_draw, order)
    alone = [monte_carlo(isolated_structure("rigid", isolator=posterior.bearing(TRUE, k), time_step=0.005),
                         model, 3, key=jax.random.key(2), chunk_size=3) for k in range(3)]
    for m, k in enumerate(order):
        np.testing.assert_allclose(result.base_disp[m], alone[int(k)].base_disp[m], rtol=1e-12)
        np.testing.assert_allclose(result.base_shear_ratio[m], alone[int(k)].base_shear_ratio[m], rtol=1e-12)
    assert len({round(float(run.base_disp[0]), 9) for run in alone}) == 3


@pytest.fixture
def record_files(tmp_path):
    record = _record(noise=0.01)
    write_test_record(tmp_path / "test.csv", record)
    (tmp_path / "start.json").write_text(json.dumps(isolator_to_dict(_start())))
    return tmp_path


@pytest.mark.parametrize("extra, message", [
    (["--bayes", "B", "--prior", "table1"], "--prior table1: Table 1's prior is that of one flat interface"),
    (["--bayes", "B", "--posterior-draws", "50"], "add --save-isolator FILE"),
    (["--bayes", "B", "--each"], "--each: the posterior is sampled for the flat slider's law"),
])
def test_the_series_posteriors_flags_are_checked_before_any_work(record_files, capsys, extra, message):
    named = {"B": str(record_files / "b")}
    code = main(["fit", str(record_files / "test.csv"), "--isolator", "double-fp", "--isolator-file",
                 str(record_files / "start.json"), "--json", str(record_files / "f.json"),
                 *[named.get(e, e) for e in extra]])
    assert code == 2 and message in capsys.readouterr().err
    assert not (record_files / "f.json").exists()


def test_draws_asked_of_an_isolator_file_without_them_are_refused(tmp_path, capsys):
    """--bearing-draws K, or more draws than the file holds, refused naming the file and how to
    write draws into it; an isolator file's draws run under --bearing-seed, its point without."""
    plain, drawn = tmp_path / "plain.json", tmp_path / "drawn.json"
    write_isolator(plain, TRUE)
    write_isolator(drawn, TRUE, posterior=_posterior({"bottom_f_max": [0.05, 0.051, 0.049, 0.052]}))
    common = ["montecarlo", "--motions", "2", "--structure", "rigid", "--isolator", "double-fp", "--json",
              str(tmp_path / "mc.json"), "--isolator-file"]
    for file, extra, message in (
            (plain, ["--bearing-draws", "3"], f"--bearing-draws 3: --isolator-file {plain} holds no posterior draws"),
            (plain, ["--bearing-seed", "1"], f"--isolator-file {plain} runs as its point estimate here"),
            (drawn, ["--bearing-draws", "5"], f"the posterior of --isolator-file {drawn} has 4 draws")):
        assert main([*common, str(file), *extra]) == 2
        err = capsys.readouterr().err
        assert message in err, err
    assert not (tmp_path / "mc.json").exists()


def test_a_plan_runs_an_isolator_files_point_and_refuses_its_draws(tmp_path, capsys):
    """A structure on --plan is built once: an isolator file with draws is refused until
    --bearing-draws point asks for its constants, which then run as the file without draws does."""
    plain, drawn = tmp_path / "plain.json", tmp_path / "drawn.json"
    write_isolator(plain, TRUE)
    write_isolator(drawn, TRUE, posterior=_posterior({"bottom_f_max": [0.05, 0.051, 0.049, 0.052]}))
    groups = [{"name": n, "x": x, "y": y, "load": "50kip"}
              for n, x, y in (("SW", "0m", "0m"), ("SE", "20m", "0m"), ("NE", "20m", "12m"), ("NW", "0m", "12m"))]
    plan = tmp_path / "plan.json"
    plan.write_text(json.dumps({"length_x": "20m", "length_y": "12m", "weight": "200kip",
                                "centre_of_mass": ["10m", "6m"], "groups": groups}))
    common = ["montecarlo", "--motions", "2", "--duration", "8s", "--strong-motion", "4s", "--structure", "slab",
              "--plan", str(plan),
              "--components", "2", "--isolator", "double-fp"]
    assert main([*common, "--isolator-file", str(drawn), "--json", str(tmp_path / "a.json")]) == 2
    assert "holds posterior draws" in capsys.readouterr().err and not (tmp_path / "a.json").exists()
    peaks = []
    for file, extra, out in ((drawn, ["--bearing-draws", "point"], "b.json"), (plain, [], "c.json")):
        assert main([*common, "--isolator-file", str(file), *extra, "--json", str(tmp_path / out)]) == 0
        peaks.append(json.loads((tmp_path / out).read_text())["statistics"])
    assert peaks[0] == peaks[1]


@pytest.mark.slow
def test_the_surfaces_posterior_covers_the_truth_and_travels_into_a_monte_carlo(record_files, capsys):
    """A noisy (1 %) test of a double pendulum, fitted from a start 8-10 % off: each surface's
    Eq. 1 constant lies within three posterior standard deviations of the truth (1.8 at most
    here), each spread below the least-squares standard error, which carries the radii's
    uncertainty too (0.6-0.95 of it), and the isolator file keeps the draws, which `montecarlo
    --isolator-file` runs one per motion."""
    out = record_files
    code = main(["fit", str(out / "test.csv"), "--isolator", "double-fp", "--isolator-file", str(out / "start.json"),
                 "--json", str(out / "f.json"), "--save-isolator", str(out / "fitted.json"), "--bayes",
                 str(out / "post"), "--draws", "500", "--chains", "2", "--no-progress", "--posterior-draws", "100"])
    summary = json.loads((out / "post" / "posterior.json").read_text())
    assert code == 0, summary["messages"]
    truth = series_parameters(TRUE)
    for name in SAMPLED:
        row = summary["posterior"][name]
        assert abs(row["mean"] - truth[name]) < 3 * row["sd"], (name, row)
        assert 0.4 < row["sd"] / summary["least_squares"]["std_errors"][name] < 1.2, (name, row)
    posterior = load_isolator_posterior(out / "fitted.json")
    assert posterior.names == SAMPLED and posterior.size == 100
    code = main(["montecarlo", "--motions", "6", "--structure", "rigid", "--isolator", "double-fp",
                 "--isolator-file", str(out / "fitted.json"), "--json", str(out / "mc.json")])
    assert code == 0
    entry = json.loads((out / "mc.json").read_text())["bearing_posterior"]
    assert entry["bearing_draws"] == "motion" and len(set(entry["bearing_draw"])) == 6


@pytest.mark.slow
def test_the_sampler_needs_the_fitted_radii():
    """The test above against a plausible wrong law, sampling the friction under the start's
    radii (9-10 % off) in place of the fitted ones: the pendulum's stiffness then takes
    friction's place, and constants land many posterior standard deviations off the truth
    (bottom_f_max 16, bottom_rate_a 11)."""
    record = _record(noise=0.01)
    fit = fit_double_pendulum_test(record, _start())
    start = series_parameters(_start())
    held = series_with_parameters(fit.bearing, {n: jnp.asarray(start[n]) for n in ("bottom_radius", "top_radius")})
    moved = type(fit)(**{**fit.__dict__, "bearing": held})
    assert set(series_priors(moved)) == set(SAMPLED)
    result = fit_series_bayes(record, moved, num_warmup=300, num_samples=300)
    truth = series_parameters(TRUE)
    off = max(abs(result.table[n]["mean"] - truth[n]) / result.table[n]["sd"] for n in SAMPLED)
    assert off > 5, "the friction's posterior does not depend on the radii it is sampled at"


@pytest.mark.slow  # a least-squares fit and the series model's NUTS compiled in a new process: about a minute
def test_ctrl_c_keeps_the_surfaces_draws_so_far_and_says_not_converged(record_files):
    """A real SIGINT once a block of draws is done: the draws finished are written
    (posterior.json, posterior.nc) as not converged, the isolator file keeps the least-squares
    constants without draws, and the command exits 130."""
    import xarray as xr

    out = record_files
    seen, code, rest = interrupted_at_a_block(
        ["fit", str(out / "test.csv"), "--isolator", "double-fp", "--isolator-file", str(out / "start.json"),
         "--json", str(out / "f.json"), "--save-isolator", str(out / "fitted.json"), "--bayes", str(out / "post"),
         "--draws", "40", "--chains", "2", "--no-progress"], out)
    assert any("10 of 40 draws per chain done" in line for line in seen), "".join(seen)
    assert code == 130, rest
    posterior = json.loads((out / "post" / "posterior.json").read_text())
    assert posterior["converged"] is False and posterior["status"].startswith("interrupted after")
    assert 10 <= posterior["num_samples"] < 40
    with xr.open_dataset(out / "post" / "posterior.nc", group="posterior") as ds:
        assert ds.sizes["draw"] == posterior["num_samples"]
        assert set(SAMPLED) <= set(ds.data_vars)
    assert load_isolator_posterior(out / "fitted.json") is None
    assert "interrupted after" in rest and "holds the least-squares isolator only" in rest
