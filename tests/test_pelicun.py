"""Tests of the pelicun demand file (teflon_jax.formats.write_pelicun_demands).

References: the file read back as text (labels, units row, values in the units named, the
ERROR flags), and pelicun's own `DemandModel.load_sample` and a FEMA P-58 damage calculation
on the file (when pelicun is installed: `pip install teflon-jax[pelicun]`).
"""

import json
import os
import pathlib

import numpy as np
import pytest

from teflon_jax.formats import pelicun_demand_table, write_pelicun_demands
from teflon_jax.units import INCH, MM, STANDARD_GRAVITY

BENCHMARKS = pathlib.Path(__file__).resolve().parents[1] / "benchmarks"


def _peaks(rows=12, storeys=6, seed=0):
    rng = np.random.default_rng(seed)
    return {"base_disp": rng.uniform(0.02, 0.1, rows), "failed": np.arange(rows) == 3,
            "pga": rng.uniform(2.0, 4.0, rows), "level_acceleration": rng.uniform(1.0, 3.0, (rows, storeys + 1)),
            "storey_drift": rng.uniform(1e-3, 1e-2, (rows, storeys))}


def _two_pairs(folder) -> list:
    """suite.csv of two record pairs p0, p1 (x, y in g, 2 s at 0.01 s) written in `folder`;
    the peak |a_x| [g] of each pair's x record."""
    t = 0.01 * np.arange(201)
    rows, peaks_x = [], []
    for i in range(2):
        for axis, peak in (("x", 0.3), ("y", 0.2)):
            a = peak * (i + 1) * np.sin(2 * np.pi * (0.8 + 0.3 * i) * t) * np.sin(np.pi * t / t[-1]) ** 2
            peaks_x += [np.abs(a).max()] if axis == "x" else []
            (folder / f"{axis}{i}.txt").write_text("time acc\n" + "\n".join(f"{u:.4f} {v:.6e}" for u, v in zip(t, a)))
        rows.append(f"p{i},x{i}.txt,y{i}.txt,1\n")
    (folder / "suite.csv").write_text("name,record_x,record_y,scale\n" + "".join(rows))
    return peaks_x


def test_file_layout_units_and_failed_runs(tmp_path):
    peaks = _peaks()
    path = write_pelicun_demands(tmp_path / "demands.csv", **peaks)
    lines = path.read_text().splitlines()
    header, units = lines[0].split(","), lines[1].split(",")
    assert header[0] == "" and units[0] == "Units"
    assert header[1:] == (["1-PFA-0-1"] + [f"1-PFA-{j}-1" for j in range(1, 8)]
                          + [f"1-PID-{j}-1" for j in range(2, 8)] + ["1-BRD-1-1", "1-ERROR"])
    assert units[1:] == ["g"] * 8 + ["unitless"] * 6 + ["in", ""]
    assert len(lines) == 2 + 12  # the failed run is kept, flagged
    table = np.array([[float(v) for v in line.split(",")] for line in lines[2:]])
    np.testing.assert_array_equal(table[:, 0], np.arange(12))
    np.testing.assert_allclose(table[:, 1], peaks["pga"] / STANDARD_GRAVITY, rtol=1e-9)
    np.testing.assert_allclose(table[:, 2], peaks["level_acceleration"][:, 0] / STANDARD_GRAVITY, rtol=1e-9)
    np.testing.assert_allclose(table[:, 9:15], peaks["storey_drift"], rtol=1e-9)
    np.testing.assert_allclose(table[:, 15], peaks["base_disp"] / INCH, rtol=1e-9)
    np.testing.assert_array_equal(table[:, 16], (np.arange(12) == 3).astype(float))


def test_si_units_and_bad_input():
    labels, units, values = pelicun_demand_table(base_disp=[0.05], failed=[False], acceleration_unit="mps2",
                                                 length_unit="mm")
    assert labels == ["1-BRD-1-1", "1-ERROR"] and units == ["mm", ""]
    np.testing.assert_allclose(values, [[50.0, 0.0]])
    with pytest.raises(ValueError, match="^length_unit: unknown 'ft'"):
        pelicun_demand_table(base_disp=[0.05], failed=[False], length_unit="ft")
    with pytest.raises(ValueError, match=r"^storey_drift: expected shape \(2, L\) or \(2, 2, L\)"):
        pelicun_demand_table(base_disp=[0.05, 0.06], failed=[False, True], storey_drift=np.zeros((3, 3)))
    with pytest.raises(ValueError, match="^base_direction: 1, or 0 for a resultant"):
        pelicun_demand_table(base_disp=[0.05], failed=[False], base_direction=2)


def test_two_directions_and_a_resultant_isolator_displacement():
    """Per location the directions 1 (x) and 2 (y); the resultant base displacement as
    direction 0; no ground PFA."""
    drift = np.arange(12.0).reshape(2, 2, 3) / 1000  # (R, direction, storey)
    labels, units, values = pelicun_demand_table(base_disp=[0.05, 0.06], failed=[False, False],
                                                 storey_drift=drift, base_direction=0)
    assert labels == ["1-PID-2-1", "1-PID-2-2", "1-PID-3-1", "1-PID-3-2", "1-PID-4-1", "1-PID-4-2",
                      "1-BRD-1-0", "1-ERROR"]
    np.testing.assert_allclose(values[1, :6], [0.006, 0.009, 0.007, 0.010, 0.008, 0.011])


@pytest.mark.filterwarnings("ignore::FutureWarning", "ignore::DeprecationWarning",
                            "ignore::UserWarning", "ignore::RuntimeWarning")
def test_pelicun_loads_the_file_and_runs_a_p58_damage_assessment(tmp_path):
    """pelicun reads the file unedited (SI values back, the failed run dropped on loading),
    and a P-58 damage calculation with components of its library finishes on it."""
    if os.environ.get("CI"):  # the test extra installs pelicun: in CI this test must run
        import pelicun.assessment as assessment
    else:
        assessment = pytest.importorskip("pelicun.assessment")
    import pandas as pd

    peaks = _peaks()
    path = write_pelicun_demands(tmp_path / "demands.csv", **peaks)
    run = assessment.Assessment({"PrintLog": False, "Seed": 1, "Verbose": False,
                                 "LogFile": str(tmp_path / "log.txt")})
    run.demand.load_sample(str(path))
    sample = run.demand.sample
    assert sample.shape == (11, 15)  # 12 realisations less the failed one; ERROR removed
    kept = np.arange(12) != 3
    np.testing.assert_allclose(sample[("PFA", "1", "1")], peaks["level_acceleration"][kept, 0], rtol=1e-8)
    np.testing.assert_allclose(sample[("PID", "7", "1")], peaks["storey_drift"][kept, 5], rtol=1e-8)
    np.testing.assert_allclose(sample[("BRD", "1", "1")], peaks["base_disp"][kept], rtol=1e-8)
    run.stories = 7
    components = pd.DataFrame({"Units": ["ea", "ea"], "Location": ["2--7", "1--7"], "Direction": ["1", "1"],
                               "Theta_0": [1, 1]}, index=["B.10.41.001a", "C.30.32.001a"])
    run.asset.load_cmp_model({"marginals": components})
    run.asset.generate_cmp_sample(sample.shape[0])
    run.damage.load_model_parameters(["PelicunDefault/FEMA P-58/fragility.csv"],
                                     set(run.asset.list_unique_component_ids()))
    run.damage.calculate()
    damage = run.damage.ds_model.sample
    assert damage.shape[0] == 11
    assert set(damage.columns.get_level_values("cmp")) == {"B.10.41.001a", "C.30.32.001a"}


@pytest.mark.slow
def test_run_suite_writes_the_buildings_demands_per_direction(tmp_path, capsys):
    """`run --suite --structure building --pelicun-demands`: one row per pair, the ground's
    PFA in x and y as read from the records, PID per storey and direction equal to the
    suite's NetCDF file."""
    import xarray

    from teflon_jax.cli import main

    peaks_x = _two_pairs(tmp_path)
    code = main(["run", "--suite", str(tmp_path / "suite.csv"), "--structure", "building", "--record-units", "g",
                 "--isolation-period", "2.5s", "--json", str(tmp_path / "s.json"),
                 "--pelicun-demands", str(tmp_path / "d.csv")])
    assert code == 0
    lines = (tmp_path / "d.csv").read_text().splitlines()
    header = lines[0].split(",")
    assert header[1:3] == ["1-PFA-0-1", "1-PFA-0-2"] and header[-2:] == ["1-BRD-1-0", "1-ERROR"]
    assert "1-PFA-7-2" in header and "1-PID-7-2" in header and len(lines) == 2 + 2
    table = np.array([[float(v) for v in line.split(",")] for line in lines[2:]])
    np.testing.assert_allclose(table[:, 1], peaks_x, rtol=1e-6)  # peak |a_x| [g] of the records
    with xarray.open_dataset(tmp_path / "s.nc") as dataset:
        drift = dataset["storey_drift"].values  # (pair, direction, storey)
    for d in (1, 2):
        np.testing.assert_allclose(table[:, header.index(f"1-PID-4-{d}")], drift[:, d - 1, 2], rtol=1e-9)


def test_each_sliders_travel_is_a_column_in_the_length_unit(tmp_path):
    """A series pendulum's sliders: one column BRD_<slider> each after BRD, in the length unit,
    with BRD's direction (0 for the resultant of two components); numbered without names."""
    travel = np.array([[0.01, 0.12, 0.2], [0.02, 0.05, 0.0], [0.005, 0.3, 0.25]])  # (R, S) [m]
    labels, units, values = pelicun_demand_table(base_disp=travel.sum(axis=1), failed=[False, True, False],
                                                 base_direction=0, slider_travel=travel,
                                                 slider_names=("inner", "bottom", "top"), length_unit="mm")
    assert labels == ["1-BRD-1-0", "1-BRD_inner-1-0", "1-BRD_bottom-1-0", "1-BRD_top-1-0", "1-ERROR"]
    assert units == ["mm"] * 4 + [""]
    np.testing.assert_allclose(values[:, 1:4], travel / MM, rtol=1e-12)
    lines = write_pelicun_demands(tmp_path / "d.csv", base_disp=travel[:, 0], failed=[False, True, False],
                                  slider_travel=travel[:, 1:]).read_text().splitlines()
    assert lines[0] == ",1-BRD-1-1,1-BRD_1-1-1,1-BRD_2-1-1,1-ERROR" and lines[1] == "Units,in,in,in,"
    table = np.array([[float(v) for v in line.split(",")] for line in lines[2:]])
    np.testing.assert_allclose(table[:, 2:4], travel[:, 1:] / INCH, rtol=1e-9)
    np.testing.assert_array_equal(table[:, 4], [0, 1, 0])


@pytest.mark.parametrize(("shape", "names", "message"), [
    ((3,), None, r"^slider_travel: expected shape \(3, S\)"),
    ((2, 2), None, r"^slider_travel: expected shape \(3, S\) .* got \(2, 2\)"),
    ((3, 2, 1), None, r"^slider_travel: expected shape \(3, S\)"),
    ((3, 2), ("bottom",), "^slider_names: expected 2 names"),
    ((3, 2), ("bottom", "top-1"), "^slider_names: 'top-1' is not a demand subtype"),
    ((3, 2), ("top", "top"), "^slider_names: each slider needs its own name"),
])
def test_a_wrong_slider_travel_is_refused_by_name(shape, names, message):
    with pytest.raises(ValueError, match=message):
        pelicun_demand_table(base_disp=[0.05] * 3, failed=[False] * 3, slider_travel=np.zeros(shape),
                             slider_names=names)


@pytest.mark.filterwarnings("ignore::FutureWarning", "ignore::DeprecationWarning",
                            "ignore::UserWarning", "ignore::RuntimeWarning")
def test_pelicun_reads_each_slider_as_its_own_bearing_demand(tmp_path):
    """pelicun loads the slider columns back in SI as types BRD_<slider>, and a fragility on the
    demand type "Peak Bearing Deformation|bottom" (a restrainer reached at 4 in) is damaged in
    exactly the realisations whose bottom slider travelled beyond 4 in, not by BRD or the top."""
    if os.environ.get("CI"):
        import pelicun.assessment as assessment
    else:
        assessment = pytest.importorskip("pelicun.assessment")
    import pandas as pd

    rng = np.random.default_rng(1)
    travel = rng.uniform(0.02, 0.2, (12, 2))  # bottom and top [m]
    kept = np.arange(12) != 3
    path = write_pelicun_demands(tmp_path / "demands.csv", base_disp=travel.sum(axis=1), failed=~kept,
                                 base_direction=0, slider_travel=travel, slider_names=["bottom", "top"])
    run = assessment.Assessment({"PrintLog": False, "Seed": 1, "Verbose": False, "LogFile": str(tmp_path / "log.txt"),
                                 "NonDirectionalMultipliers": {"ALL": 1.0}})
    run.demand.load_sample(str(path))
    sample = run.demand.sample
    assert list(sample.columns) == [("BRD", "1", "0"), ("BRD_bottom", "1", "0"), ("BRD_top", "1", "0")]
    np.testing.assert_allclose(sample[("BRD_bottom", "1", "0")], travel[kept, 0], rtol=1e-8)
    np.testing.assert_allclose(sample[("BRD_top", "1", "0")], travel[kept, 1], rtol=1e-8)
    run.stories = 1
    run.asset.load_cmp_model({"marginals": pd.DataFrame({"Units": ["ea"], "Location": ["1"], "Direction": ["0"],
                                                         "Theta_0": [1]}, index=["SLD.bottom"])})
    run.asset.generate_cmp_sample(sample.shape[0])
    fragility = pd.DataFrame({"Incomplete": [0], "Demand-Type": ["Peak Bearing Deformation|bottom"],
                              "Demand-Unit": ["in"], "Demand-Offset": [0], "Demand-Directional": [0],
                              "LS1-Family": [""], "LS1-Theta_0": [4.0]}, index=pd.Index(["SLD.bottom"], name="ID"))
    fragility.to_csv(tmp_path / "fragility.csv")
    run.damage.load_model_parameters([str(tmp_path / "fragility.csv")], {"SLD.bottom"})
    run.damage.calculate()
    damaged = run.damage.ds_model.sample[("SLD.bottom", "1", "0", "0", "1")].to_numpy()
    np.testing.assert_array_equal(damaged, (travel[kept, 0] > 4.0 * INCH).astype(float))
    assert 0 < damaged.sum() < damaged.size


@pytest.mark.parametrize(("isolator", "sliders"), [("double-fp", ["bottom", "top"]),
                                                   ("triple-fp", ["inner", "bottom", "top"])])
def test_montecarlo_on_a_series_pendulum_writes_its_sliders_travel(tmp_path, capsys, isolator, sliders):
    """`montecarlo --isolator double-fp|triple-fp --pelicun-demands`: one column per slider,
    equal (in inches) to the results file's `slider_travel` of the same motions."""
    from teflon_jax.cli import main
    from teflon_jax.studies import MonteCarloResult

    example = BENCHMARKS / f"{isolator.split('-')[0]}_isolator.json"
    code = main(["montecarlo", "--motions", "2", "--duration", "6s", "--strong-motion", "2s", "--isolator", isolator,
                 "--isolator-file", str(example), "--no-progress", "--out", str(tmp_path / "mc.nc"),
                 "--pelicun-demands", str(tmp_path / "d.csv"), "--json", str(tmp_path / "mc.json")])
    err = capsys.readouterr().err
    assert code == 0, err
    lines = (tmp_path / "d.csv").read_text().splitlines()
    header = lines[0].split(",")
    s = len(sliders)
    assert header[-s - 2:] == ["1-BRD-1-1", *(f"1-BRD_{name}-1-1" for name in sliders), "1-ERROR"]
    assert len(lines) == 2 + 2
    table = np.array([[float(v) for v in line.split(",")] for line in lines[2:]])
    result = MonteCarloResult.open(tmp_path / "mc.nc")
    travel = np.asarray(result.slider_travel)[:, 0, :]  # (N, S) of the one group [m]
    assert list(result.attrs["slider_names"]) == sliders and np.all(travel > 0)
    np.testing.assert_allclose(table[:, -s - 1:-1], travel / INCH, rtol=1e-9)
    np.testing.assert_allclose(table[:, -s - 2], np.asarray(result.base_disp) / INCH, rtol=1e-9)


@pytest.mark.slow
def test_run_suite_on_a_double_pendulum_writes_its_sliders_travel(tmp_path, capsys):
    """`run --suite --isolator double-fp --pelicun-demands`: the sliders' resultant travel as
    BRD_<slider>-1-0, equal to the suite's table of the same pairs."""
    from teflon_jax.cli import main

    _two_pairs(tmp_path)
    code = main(["run", "--suite", str(tmp_path / "suite.csv"), "--record-units", "g", "--isolator", "double-fp",
                 "--isolator-file", str(BENCHMARKS / "double_isolator.json"), "--json", str(tmp_path / "s.json"),
                 "--pelicun-demands", str(tmp_path / "d.csv")])
    assert code == 0, capsys.readouterr().err
    lines = (tmp_path / "d.csv").read_text().splitlines()
    header = lines[0].split(",")
    assert header[-4:] == ["1-BRD-1-0", "1-BRD_bottom-1-0", "1-BRD_top-1-0", "1-ERROR"] and len(lines) == 2 + 2
    table = np.array([[float(v) for v in line.split(",")] for line in lines[2:]])
    pairs = json.loads((tmp_path / "s.json").read_text())["pairs"]
    for name, column in (("bottom", -3), ("top", -2)):
        travel = np.array([pairs[f"p{i}"][f"slider_travel_m_{name}"] for i in range(2)])
        assert np.all(travel > 0)
        np.testing.assert_allclose(table[:, column], travel / INCH, rtol=1e-9)
