"""Tests of the pelicun demand file (teflon_jax.formats.write_pelicun_demands).

References: the file read back as text (labels, units row, values in the units named, the
ERROR flags), and pelicun's own `DemandModel.load_sample` and a FEMA P-58 damage calculation
on the file (when pelicun is installed: `pip install teflon-jax[pelicun]`).
"""

import os

import numpy as np
import pytest

from teflon_jax.formats import pelicun_demand_table, write_pelicun_demands
from teflon_jax.units import INCH, STANDARD_GRAVITY


def _peaks(rows=12, storeys=6, seed=0):
    rng = np.random.default_rng(seed)
    return {"base_disp": rng.uniform(0.02, 0.1, rows), "failed": np.arange(rows) == 3,
            "pga": rng.uniform(2.0, 4.0, rows), "level_acceleration": rng.uniform(1.0, 3.0, (rows, storeys + 1)),
            "storey_drift": rng.uniform(1e-3, 1e-2, (rows, storeys))}


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

    t = 0.01 * np.arange(201)
    rows, peaks_x = [], []
    for i in range(2):
        for axis, peak in (("x", 0.3), ("y", 0.2)):
            a = peak * (i + 1) * np.sin(2 * np.pi * (0.8 + 0.3 * i) * t) * np.sin(np.pi * t / t[-1]) ** 2
            peaks_x += [np.abs(a).max()] if axis == "x" else []
            (tmp_path / f"{axis}{i}.txt").write_text("time acc\n" + "\n".join(f"{u:.4f} {v:.6e}" for u, v in zip(t, a)))
        rows.append(f"p{i},x{i}.txt,y{i}.txt,1\n")
    (tmp_path / "suite.csv").write_text("name,record_x,record_y,scale\n" + "".join(rows))
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
