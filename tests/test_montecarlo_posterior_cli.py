"""`teflon-jax montecarlo --bearing FILE` with a bearing file that holds posterior draws:
one draw per motion (the default), K bearings x M motions (`--bearing-draws K`) with the
variance split, the point estimate (`--bearing-draws point`), and the inputs refused by name
before any work.

References: `motion_draws` / `nested_draws` for the draws the command must take, the SHA-256
of the file's bytes, and the identity of the variance parts (they add up to the total)."""

import hashlib
import json

import jax
import numpy as np
import pytest
import xarray

import teflon_jax as tj
from teflon_jax.cli import main
from teflon_jax.formats import BearingPosterior, save_bearing
from teflon_jax.studies import motion_draws, nested_draws
from teflon_jax.units import PSI

COMMON = ["montecarlo", "--duration", "4s", "--strong-motion", "1.5s", "--no-progress"]
SIZE = 120


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """(a bearing file with 120 draws of f_max, delta_f and rate_a, the same without them)."""
    jax.config.update("jax_enable_x64", True)
    folder = tmp_path_factory.mktemp("bearings")
    friction, b = tj.interface_parameters("UF", 1000 * PSI, "P")
    point = tj.paper_bearing(friction, breakaway_ratio=b)
    rng = np.random.default_rng(0)
    f_max = float(friction.f_max) * (1 + 0.1 * rng.standard_normal(SIZE))
    draws = {"f_max": f_max, "delta_f": f_max * float(friction.delta_f / friction.f_max),
             "rate_a": float(friction.rate_a) * (1 + 0.1 * rng.standard_normal(SIZE))}
    posterior = BearingPosterior(names=tuple(draws), draws=draws, effective_sample_size=dict.fromkeys(draws, 400.0),
                                 draws_before_thinning=4 * SIZE, thinning=4, chains=4, seed=0)
    return (save_bearing(folder / "posterior.json", point, posterior=posterior),
            save_bearing(folder / "point.json", point))


@pytest.mark.parametrize("flags, words", [
    (["--bearing-draws", "3"], "--bearing-draws 3: --bearing {point} holds no posterior draws"),
    (["--bearing-draws", "121"], "--bearing-draws 121: the posterior of --bearing {posterior} has 120 draws; "
                                 "ask for at most 120 bearings"),
    (["--bearing-draws", "0"], "--bearing-draws: the number of bearings K must be at least 1, got 0"),
    (["--bearing-draws", "many"], "--bearing-draws: expected 'point', 'motion' or a number of bearings"),
    (["--motions", "0"], "--motions"),
    (["--no-bearing", "--bearing-draws", "motion"], "--bearing-draws motion: needs --bearing FILE"),
    (["--storeys", "--structure", "building"], "--storeys: runs without the posterior draws of --bearing "
                                               "{posterior} (--bearing-draws motion); give --bearing-draws point"),
    (["--structure", "building", "--pga", "0.1g,0.2g", "--limit", "drift=0.5%", "--bearing-draws", "4"],
     "--limit drift=0.5%: runs without the posterior draws"),
    (["--scheduler", "local:2", "--out", "{folder}/mc.nc"], "--scheduler: runs without the posterior draws"),
    (["--no-bearing", "--bearing-seed", "3"], "--bearing-seed 3: orders the posterior draws (or a mixture's) of a "
                                              "--bearing file or an --isolator-file, and no --bearing FILE is given"),
    (["--point", "--bearing-seed", "3"], "--bearing-seed 3: orders the posterior draws (or a "
                                                      "mixture's) of a --bearing file or an --isolator-file, and "
                                                      "--bearing {point} runs as its point estimate here"),
    (["--bearing-draws", "point", "--bearing-seed", "0"], "--bearing-seed 0: orders the posterior draws"),
], ids=["no-posterior", "too-many", "zero", "word", "no-motions", "no-file", "storeys", "storey-limit", "scheduler",
        "seed-no-file", "seed-no-posterior", "seed-point"])
def test_bad_input_refused_by_name_before_any_work(files, tmp_path, capsys, flags, words):
    posterior, point = files
    file = point if flags[:2] == ["--bearing-draws", "3"] or "--point" in flags else posterior
    flags = [f.format(folder=tmp_path) for f in flags]
    given = [] if "--no-bearing" in flags else ["--bearing", str(file)]
    flags = [f for f in flags if f not in ("--no-bearing", "--point")]
    motions = [] if "--motions" in flags else ["--motions", "2"]
    argv = [*COMMON, *motions, *given, *flags, "--json", str(tmp_path / "mc.json")]
    if words.startswith("--bearing-draws:") or words == "--motions":  # the parser's own message
        with pytest.raises(SystemExit) as exit_status:
            main(argv)
        assert exit_status.value.code == 2
    else:
        assert main(argv) == 2
    assert words.format(point=point, posterior=posterior) in capsys.readouterr().err
    assert not (tmp_path / "mc.json").exists() and not (tmp_path / "mc.nc").exists()


def _run(argv, capsys):
    assert main(argv) == 0
    return capsys.readouterr().out


def test_nested_run_reports_the_variance_split_and_the_band(files, tmp_path, capsys):
    """K = 3 bearings x 4 motions: the draws nested_draws takes for --bearing-seed, in the JSON
    and over the NetCDF file's "bearing" axis; the parts of each peak's variance add up to the
    total; the bearing file named by its path and SHA-256."""
    posterior, _ = files
    out = _run([*COMMON, "--motions", "4", "--bearing", str(posterior), "--bearing-draws", "3",
                "--bearing-seed", "5", "--json", str(tmp_path / "mc.json"), "--out", str(tmp_path / "mc.nc")],
               capsys)
    summary = json.loads((tmp_path / "mc.json").read_text())
    entry = summary["bearing_posterior"]
    expected = nested_draws(3, SIZE, seed=5).tolist()
    assert (entry["bearing_draws"], entry["bearings"], entry["bearing_draw"]) == ("nested", 3, expected)
    assert summary["n_runs"] == 12 and summary["statistics"]["base_disp_in"]["n"] == 12
    for key in ("base_disp_in", "base_shear_ratio"):
        variance = entry[key]["variance"]
        assert variance["motion"] + variance["bearing"] == pytest.approx(variance["total"], rel=1e-12)
        assert 0 < variance["bearing_share"] < 1
        low, high = entry[key]["p95"]["band"]
        assert min(entry[key]["p95"]["per_bearing"]) <= low <= high <= max(entry[key]["p95"]["per_bearing"])
    assert summary["design"]["bearing_file_sha256"] == hashlib.sha256(posterior.read_bytes()).hexdigest()
    assert "base_disp_in: bearing share of the variance" in out
    with xarray.open_dataset(tmp_path / "mc.nc") as data:
        assert data["base_disp"].dims == ("bearing", "motion")
        assert data["bearing_draw"].dims == ("bearing",)
        assert data["bearing_draw"].values.tolist() == expected
        assert data.attrs["bearing_file_sha256"] == summary["design"]["bearing_file_sha256"]
        inches = data["base_disp"].values / 0.0254
        assert np.percentile(inches, 95) == pytest.approx(entry["base_disp_in"]["p95"]["pooled"], rel=1e-12)


def test_one_draw_per_motion_by_default_and_the_point_on_request(files, tmp_path, capsys):
    """A file with draws runs motion m with draw motion_draws(N, S, seed)[m]; --bearing-draws
    point runs the file's point estimate, exactly as the file without draws."""
    posterior, point = files
    _run([*COMMON, "--motions", "3", "--bearing", str(posterior), "--bearing-seed", "2",
          "--json", str(tmp_path / "drawn.json"), "--out", str(tmp_path / "drawn.nc")], capsys)
    drawn = json.loads((tmp_path / "drawn.json").read_text())
    assert drawn["bearing_posterior"]["bearing_draw"] == motion_draws(3, SIZE, seed=2).tolist()
    with xarray.open_dataset(tmp_path / "drawn.nc") as data:
        assert data["bearing_draw"].dims == ("motion",)
        assert data["bearing_draw"].values.tolist() == drawn["bearing_posterior"]["bearing_draw"]
    runs = {}
    for name, file, flags in (("point", posterior, ["--bearing-draws", "point"]), ("plain", point, [])):
        _run([*COMMON, "--motions", "3", "--bearing", str(file), *flags, "--json", str(tmp_path / f"{name}.json")],
             capsys)
        runs[name] = json.loads((tmp_path / f"{name}.json").read_text())
    assert "bearing_posterior" not in runs["point"]
    assert runs["point"]["statistics"] == runs["plain"]["statistics"]
    assert runs["point"]["statistics"] != drawn["statistics"]
