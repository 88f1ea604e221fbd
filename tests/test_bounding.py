"""Tests of the bounding analysis (teflon_jax.studies.bounding_design, governing_cases and
`teflon-jax montecarlo --property-factors`).

References: Table 1's constants times the factors by hand, statistics recomputed from the
results file, failed runs kept out, and the physical ordering of friction bounds (more
friction, less displacement and more base shear).
"""

import json

import numpy as np
import pytest
import xarray

from teflon_jax.cli import main
from teflon_jax.studies import BOUNDING_CASES, bounding_design, governing_cases
from teflon_jax.systems import isolated_structure
from teflon_jax.tables import friction_table
from teflon_jax.units import INCH, PSI


def test_bounding_design_multiplies_f_max_and_delta_f():
    structure = isolated_structure("rigid", pressure=2000 * PSI, isolation_period=2.0)
    params, _ = friction_table("UF", "P", extrapolate=True).at(2000 * PSI)
    design = bounding_design(structure, lower=0.8, upper=1.25)
    np.testing.assert_allclose(design["f_max"], float(params.f_max) * np.array([1.0, 1.25, 0.8]), rtol=1e-15)
    np.testing.assert_allclose(design["delta_f"], float(params.delta_f) * np.array([1.0, 1.25, 0.8]), rtol=1e-15)
    # f_min = f_max - delta_f scales by the same factor
    f_min = design["f_max"] - design["delta_f"]
    np.testing.assert_allclose(f_min / f_min[0], [1.0, 1.25, 0.8], rtol=1e-12)


@pytest.mark.parametrize("lower, upper, message", [
    (0.0, 1.3, "^lower: a property modification factor must be finite and > 0"),
    (0.9, -1.0, "^upper: a property modification factor must be finite and > 0"),
    (1.2, 1.1, "^lower: the lower-bound factor 1.2 is above the upper-bound factor 1.1"),
])
def test_bad_factors_are_refused(lower, upper, message):
    with pytest.raises(ValueError, match=message):
        bounding_design(isolated_structure("rigid"), lower=lower, upper=upper)


def test_governing_case_is_the_largest_statistic_of_converged_runs():
    peaks = {"d": np.array([[1.0, 2.0, 3.0], [0.5, 1.0, 1.5], [2.0, 2.5, 90.0]])}
    converged = np.array([[True] * 3, [True] * 3, [True, True, False]])
    table = governing_cases(peaks, converged)
    assert (table["d"]["nominal"], table["d"]["upper"], table["d"]["lower"]) == (2.0, 1.0, 2.25)
    assert table["d"]["governs"] == "lower"  # the failed run's 90 is left out
    assert governing_cases(peaks, converged, statistic="max")["d"]["governs"] == "nominal"
    none = governing_cases(peaks, np.zeros((3, 3), bool))["d"]
    assert none["governs"] is None and none["upper"] is None


@pytest.mark.parametrize("argv, message", [
    (["--property-factors", "0.85"], "--property-factors: write LOWER,UPPER"),
    (["--property-factors", "0,1.3"], "--property-factors 0,1.3: lower: a property modification factor"),
    (["--property-factors", "1.3,0.85"], "is above the upper-bound factor"),
    (["--property-factors", "0.85,1.3", "--pga", "0.1g,0.2g"], "leave out --pga levels"),
    (["--property-factors", "0.85,1.3", "--limit", "base_disp=2in"], "leave out --limit"),
    (["--property-factors", "0.85,1.3", "--storeys"], "--storeys: storey results need --structure building"),
])
def test_bad_property_factors_exit_before_any_run(argv, message, capsys):
    assert main(["montecarlo", "--motions", "2", *argv]) == 2
    assert message in capsys.readouterr().err


def test_montecarlo_bounding_table_matches_the_results_file(tmp_path, capsys):
    """Three bearings under the same 6 motions: the JSON's means are those of the NetCDF's
    peaks per design; the lower bound moves most and the upper bound pushes hardest."""
    status = main(["montecarlo", "--motions", "6", "--pga", "0.4g", "--duration", "8s", "--strong-motion", "4s",
                   "--property-factors", "0.8,1.25", "--json", str(tmp_path / "b.json"), "--out",
                   str(tmp_path / "b.nc"), "--no-progress"])
    data = json.loads((tmp_path / "b.json").read_text())
    with xarray.open_dataset(tmp_path / "b.nc") as dataset:
        disp = dataset["base_disp"].values
        shear = dataset["base_shear_ratio"].values
        ok = dataset["converged"].values.astype(bool)
    assert status == (0 if ok.all() else 1)
    assert disp.shape == (3, 6)
    for i, case in enumerate(BOUNDING_CASES):
        assert data["cases"][case]["mean"]["base_disp_in"] == pytest.approx(disp[i][ok[i]].mean() / INCH, rel=1e-12)
        assert data["cases"][case]["max"]["base_shear_ratio"] == pytest.approx(shear[i][ok[i]].max(), rel=1e-12)
    means = [data["cases"][c]["mean"]["base_disp_in"] for c in ("upper", "nominal", "lower")]
    assert means[0] < means[1] < means[2]
    assert data["governs"]["base_disp_in"]["by_mean"] == "lower"
    assert data["governs"]["base_shear_ratio"]["by_mean"] == "upper"
    assert data["motions"]["pga_g"] == pytest.approx([0.4], rel=1e-12)  # a list, as every summary's
    # the devices and speed of a plain Monte Carlo, counted in runs: each motion under three bearings
    assert data["devices"] >= 1 and data["device_kind"]
    assert data["records_per_s"] == pytest.approx(3 * 6 / (data["wall_s"] - data["compile_s"]), rel=1e-12)
    assert f"6 motions x 3 bearings on {data['devices']} device(s) in" in capsys.readouterr().out


def _pairs(tmp_path, count=3, seconds=3.0):
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


@pytest.mark.slow  # three compilations of the suite (about 50 s on two shared cores)
def test_run_suite_bounding_writes_each_case_and_the_governing_one(tmp_path, capsys):
    """`run --suite --property-factors`: per case the table's mean row is the JSON's, the
    governing case is the one with the largest mean; lower bound moves most."""
    suite = _pairs(tmp_path)
    code = main(["run", "--suite", str(suite), "--record-units", "g", "--isolation-period", "2.5s",
                 "--property-factors", "0.8,1.25", "--json", str(tmp_path / "b.json")])
    data = json.loads((tmp_path / "b.json").read_text())
    assert code == 0
    means = {}
    for case in BOUNDING_CASES:
        table = (tmp_path / f"b-{case}.csv").read_text().splitlines()
        header, mean_row = table[0].split(","), next(r for r in table if r.startswith("mean,")).split(",")
        column = header.index("base_disp_resultant_m")
        means[case] = float(mean_row[column])
        assert data["cases"][case]["summary"]["base_disp_resultant_m"]["mean"] == pytest.approx(means[case], rel=1e-5)
        assert (tmp_path / f"b-{case}.nc").stat().st_size > 0
    assert data["governs"]["base_disp_resultant_m"]["by_mean"] == max(means, key=means.get) == "lower"
    assert means["upper"] < means["nominal"] < means["lower"]


def test_run_property_factors_need_a_suite(tmp_path, capsys):
    code = main(["run", "--record-x", str(tmp_path / "x.txt"), "--record-units", "g", "--property-factors", "0.8,1.2"])
    assert code == 2
    assert "--property-factors: bounds a suite's analysis; add --suite FILE" in capsys.readouterr().err
