"""Tests of `teflon-jax montecarlo` over intensity levels with limits (fragility), storey
results and pelicun demand files.

References: the counts recomputed from the NetCDF file's per-motion peaks and levels, and
`fit_fragility` on those counts; refused input checked before any run.
"""

import json

import numpy as np
import pytest
import xarray

from teflon_jax.cli import main
from teflon_jax.studies import fit_fragility
from teflon_jax.units import INCH, STANDARD_GRAVITY

SHORT = ["--duration", "6s", "--strong-motion", "3s", "--no-progress"]


@pytest.mark.parametrize("argv, message", [
    (["--pga", "0.3g,0.2g"], "--pga: levels must increase; 0.2g (level 2) is not above 0.3g (level 1)"),
    (["--pga", "0.1g,,0.2g"], "--pga: an empty item"),
    (["--pga", "0.1g,0.2"], "--pga: '0.2' has no unit"),
    (["--limit", "uplift=1in"], "--limit uplift=1in: unknown 'uplift'; accepted: base_disp"),
    (["--limit", "base_disp"], "--limit base_disp: write NAME=VALUE"),
    (["--limit", "base_disp=2"], "--limit base_disp: '2' has no unit"),
    (["--limit", "base_disp=-2in"], "--limit base_disp=-2in: the value must be finite and > 0"),
    (["--limit", "drift=1%"], "--limit drift=1%: storey results need --structure building"),
    (["--limit", "base_disp=2in", "--limit", "base_disp=2in"], "--limit base_disp=2in: given twice"),
    (["--storeys"], "--storeys: storey results need --structure building"),
    (["--pga", "0.1g,0.2g", "--out", "{tmp}/x.csv"], "the motions' levels are kept in NetCDF or Zarr"),
    (["--pelicun-demands", "{tmp}/d.txt"], "--pelicun-demands: {tmp}/d.txt: pelicun's demand file is a .csv"),
    (["--pga", "0.1g,0.2g", "--scheduler", "local:2", "--out", "{tmp}/x.csv"], "streams its results to NetCDF"),
    (["--pga", "0.1g,0.2g", "--limit", "base_disp=1in", "--scheduler", "local:2"], "add --out FILE.nc"),
])
def test_bad_levels_limits_and_files_are_refused_before_any_run(argv, message, tmp_path, capsys):
    argv = [a.replace("{tmp}", str(tmp_path)) for a in argv]
    status = main(["montecarlo", "--motions", "2", *argv])
    err = capsys.readouterr().err
    assert status == 2
    assert message.replace("{tmp}", str(tmp_path)) in err
    assert not list(tmp_path.iterdir())  # nothing written


def test_fragility_over_levels_matches_the_counts_in_the_results_file(tmp_path, capsys):
    """The JSON's counts are those of the NetCDF file's peaks at each level (converged runs),
    its fit that of `fit_fragility` on them; one pelicun file per level, every run in it."""
    out, summary = tmp_path / "mc.nc", tmp_path / "mc.json"
    status = main(["montecarlo", "--motions", "12", "--pga", "0.15g,0.25g,0.35g,0.45g", *SHORT,
                   "--limit", "base_disp=0.5in", "--limit", "base_shear_ratio=0.12", "--out", str(out),
                   "--json", str(summary), "--plot", str(tmp_path / "f.png"),
                   "--pelicun-demands", str(tmp_path / "d.csv")])
    data = json.loads(summary.read_text())
    with xarray.open_dataset(out) as dataset:
        levels = dataset["intensity_level"].values
        peaks = {"base_disp": dataset["base_disp"].values, "base_shear_ratio": dataset["base_shear_ratio"].values}
        ok = dataset["converged"].values.astype(bool)
    assert status == (0 if ok.all() and all("error" not in f for f in data["fragility"].values()) else 1)
    np.testing.assert_allclose(np.unique(levels), np.array([0.15, 0.25, 0.35, 0.45]) * STANDARD_GRAVITY)
    assert data["motions_per_level"] == 12 and data["n_motions"] == 48
    for text, name, limit in (("base_disp=0.5in", "base_disp", 0.5 * INCH),
                              ("base_shear_ratio=0.12", "base_shear_ratio", 0.12)):
        entry = data["fragility"][text]
        counts = [int(np.sum(ok & (levels == x) & (peaks[name] > limit))) for x in np.unique(levels)]
        assert entry["n_exceed"] == counts
        assert entry["levels"] == pytest.approx([0.15, 0.25, 0.35, 0.45])
        if "error" not in entry:
            fit = fit_fragility(entry["levels"], entry["n_runs"], entry["n_exceed"])
            assert entry["median"] == pytest.approx(fit.median, rel=1e-9)
            assert entry["dispersion"] == pytest.approx(fit.dispersion, rel=1e-9)
            assert entry["median_interval"][0] < entry["median"] < (entry["median_interval"][1] or np.inf)
    assert any("error" not in entry for entry in data["fragility"].values())
    for j in range(1, 5):
        lines = (tmp_path / f"d-level{j}.csv").read_text().splitlines()
        assert lines[0] == ",1-PFA-0-1,1-PFA-1-1,1-BRD-1-1,1-ERROR" and len(lines) == 2 + 12
    assert (tmp_path / "f.png").stat().st_size > 0


def test_one_level_with_a_limit_gives_the_fraction_and_a_pelicun_file(tmp_path):
    """One level: the fraction exceeding (no fit, said so), exit 0, the pelicun file at the
    path given with every run."""
    summary = tmp_path / "mc.json"
    status = main(["montecarlo", "--motions", "6", "--pga", "0.3g", *SHORT, "--limit", "base_disp=0.5in",
                   "--json", str(summary), "--pelicun-demands", str(tmp_path / "d.csv"), "--units", "si"])
    data = json.loads(summary.read_text())
    entry = data["fragility"]["base_disp=0.5in"]
    assert status == (0 if data["all_converged"] else 1)
    assert entry["n_runs"] == [data["n_converged"]] and "two or more --pga levels" in entry["error"]
    lines = (tmp_path / "d.csv").read_text().splitlines()
    assert lines[1] == "Units,g,g,mm," and len(lines) == 2 + 6
    disp = np.array([float(line.split(",")[3]) for line in lines[2:]])
    assert entry["n_exceed"] == [int(np.sum(disp > 0.5 * INCH / 1e-3))]
