"""A record suite whose pairs carry vertical components (`record_z` in the suite CSV): each pair
runs as `run --record-z` runs it, its uplift reported per pair; the bounding cases and a
target spectrum take the vertical too; what cannot be run is refused by name before any run."""

import json
import pathlib

import numpy as np
import pytest

from teflon_jax.cli import main
from teflon_jax.studies import suite_peaks

BENCHMARKS = pathlib.Path(__file__).resolve().parents[1] / "benchmarks"

DT = 0.01
PULSE = (1.5, 1.8)  # s: a_v = -1.5 g, the isolators lifted
PEAK_Z = 0.4  # g: the vertical's oscillation outside the pulse


def _at2(path, values, dt=DT):
    lines = ["PEER NGA STRONG MOTION DATABASE RECORD", "Test event, 1/1/2000, Station, UP",
             "ACCELERATION TIME SERIES IN UNITS OF G", f"NPTS=  {len(values)}, DT=   {dt:.4f} SEC"]
    rows = [" ".join(f"{v: .7E}" for v in values[i:i + 5]) for i in range(0, len(values), 5)]
    path.write_text("\n".join(lines + rows) + "\n")
    return path


def _records(folder, dt_z=DT, n_z=301):
    t = DT * np.arange(301)
    _at2(folder / "x.at2", 0.4 * np.sin(2 * np.pi * 0.8 * t))
    _at2(folder / "y.at2", 0.3 * np.sin(2 * np.pi * 0.6 * t))
    tz = dt_z * np.arange(n_z)
    pulse = (tz > PULSE[0] - 1e-9) & (tz < PULSE[1] + 1e-9)
    _at2(folder / "z.at2", np.where(pulse, -1.5, PEAK_Z * np.sin(2 * np.pi * 3 * tz)), dt=dt_z)


def _suite(folder, rows, header="name,record_x,record_y,record_z,scale"):
    path = folder / "suite.csv"
    path.write_text(header + "\n" + "\n".join(rows) + "\n")
    return path


def _json(path):
    return json.loads(path.read_text())


@pytest.mark.slow
def test_each_pair_runs_as_run_does_with_its_vertical_record(tmp_path, capsys):
    """The pair with a vertical record has the peaks and the uplift of `run --record-z` on the
    same records (to 1e-9; the batch rounds otherwise), the pair without one those of `run`
    without it (N = W, its load factors 1, no uplift), as the notes say; the vertical moves
    the peaks. The table and the NetCDF file carry the uplift columns."""
    _records(tmp_path)
    suite = _suite(tmp_path, ["up,x.at2,y.at2,z.at2,1", "flat,x.at2,y.at2,,1"])
    assert main(["run", "--suite", str(suite), "--json", str(tmp_path / "s.json")]) == 0
    printed = capsys.readouterr().out
    assert main(["run", "--record-x", str(tmp_path / "x.at2"), "--record-y", str(tmp_path / "y.at2"),
                 "--record-z", str(tmp_path / "z.at2"), "--json", str(tmp_path / "r.json")]) == 0
    assert main(["run", "--record-x", str(tmp_path / "x.at2"), "--record-y", str(tmp_path / "y.at2"),
                 "--json", str(tmp_path / "h.json")]) == 0
    capsys.readouterr()
    pairs, vertical, horizontal = _json(tmp_path / "s.json")["pairs"], _json(tmp_path / "r.json"), _json(tmp_path / "h.json")
    for name, single in (("up", vertical), ("flat", horizontal)):
        for key in ("base_disp_resultant_m", "base_disp_x_m", "base_disp_y_m", "base_shear_ratio_resultant"):
            assert pairs[name][key] == pytest.approx(single["peak"][key], rel=1e-9)
    uplift = vertical["uplift"]
    assert uplift["occurred"]
    assert pairs["up"]["uplift_time_s"] == pytest.approx(uplift["time_s"], rel=1e-12)
    assert pairs["up"]["min_load_factor"] == uplift["min_load_factor"] == 0.0
    assert pairs["up"]["max_load_factor"] == pytest.approx(uplift["max_load_factor"], rel=1e-12)
    assert (pairs["flat"]["uplift_time_s"], pairs["flat"]["min_load_factor"], pairs["flat"]["max_load_factor"]) \
        == (0.0, 1.0, 1.0)
    assert abs(pairs["up"]["base_disp_resultant_m"] / pairs["flat"]["base_disp_resultant_m"] - 1) > 0.01
    payload = _json(tmp_path / "s.json")
    # the summary keeps the least load factor, the one uplift is read from, beside the largest
    assert payload["summary"]["min_load_factor"] == {"mean": 0.5, "min": 0.0, "max": 1.0}
    assert "min load factor: mean 0.5, min 0, max 1" in printed
    assert payload["records"]["up"]["record_z"] == str(tmp_path / "z.at2")
    assert payload["records"]["flat"]["record_z"] is None
    assert any("flat" in n and "N = W" in n for n in payload["notes"])
    assert any("Table 1 read from" in n for n in payload["notes"])
    header = (tmp_path / "s.csv").read_text().splitlines()[0].split(",")
    assert {"uplift_time_s", "min_load_factor", "max_load_factor"} <= set(header)
    import xarray

    with xarray.open_dataset(tmp_path / "s.nc") as data:
        assert float(data["uplift_time_s"].sel(pair="up")) == pairs["up"]["uplift_time_s"]


@pytest.mark.slow
def test_bounds_and_a_target_spectrum_take_the_vertical_too(tmp_path, capsys):
    """With --property-factors each case runs under the pair's vertical record (its uplift the
    same in every case, left out of the governing cases); with a target spectrum the vertical
    is scaled by its pair's factor: the largest N / W is 1 + factor 0.4 (the record's
    oscillation, the peak of its samples)."""
    _records(tmp_path)
    suite = _suite(tmp_path, ["up,x.at2,y.at2,z.at2,1"])
    assert main(["run", "--suite", str(suite), "--property-factors", "0.8,1.3", "--json",
                 str(tmp_path / "b.json")]) == 0
    cases = _json(tmp_path / "b.json")["cases"]
    times = {c: cases[c]["pairs"]["up"]["uplift_time_s"] for c in cases}
    assert len(set(times.values())) == 1 and times["nominal"] > 0
    assert cases["upper"]["pairs"]["up"]["base_shear_ratio_resultant"] \
        > cases["nominal"]["pairs"]["up"]["base_shear_ratio_resultant"]
    assert "uplift_time_s" not in _json(tmp_path / "b.json")["governs"]
    target = tmp_path / "target.csv"
    target.write_text("period [s], Sa [g]\n0.1, 0.6\n0.5, 1.0\n1.0, 0.6\n3.0, 0.2\n")
    assert main(["run", "--suite", str(suite), "--target-spectrum", str(target), "--period-range", "0.5s", "2s",
                 "--json", str(tmp_path / "t.json")]) == 0
    capsys.readouterr()
    payload = _json(tmp_path / "t.json")
    factor = payload["spectrum_scaling"]["factors"]["up"]
    assert abs(factor - 1) > 0.05
    samples = PEAK_Z * np.sin(2 * np.pi * 3 * DT * np.arange(301))
    assert payload["pairs"]["up"]["max_load_factor"] == pytest.approx(1 + factor * samples.max(), rel=1e-9)
    assert any("vertical component is scaled" in n for n in payload["notes"])


@pytest.mark.slow
@pytest.mark.parametrize("flags", [["--isolator", "triple-fp", "--isolator-file", str(BENCHMARKS / "triple_isolator.json")],
                                   ["--isolator", "single-fp", "--radius", "2m"]], ids=["triple-fp", "single-fp"])
def test_pendulums_in_a_suite_run_as_run_does_with_the_vertical(tmp_path, capsys, flags):
    """On triple pendulums (the series model) and single pendulums (W / R under N): the pair
    with a vertical record has the peaks and uplift of `run --record-z` (1e-9), the vertical
    moves the peaks."""
    _records(tmp_path)
    suite = _suite(tmp_path, ["up,x.at2,y.at2,z.at2,1", "flat,x.at2,y.at2,,1"])
    assert main(["run", "--suite", str(suite), "--json", str(tmp_path / "s.json"), *flags]) == 0
    assert main(["run", "--record-x", str(tmp_path / "x.at2"), "--record-y", str(tmp_path / "y.at2"), "--record-z",
                 str(tmp_path / "z.at2"), "--json", str(tmp_path / "r.json"), *flags]) == 0
    capsys.readouterr()
    pairs, single = _json(tmp_path / "s.json")["pairs"], _json(tmp_path / "r.json")
    for key in ("base_disp_resultant_m", "base_disp_x_m", "base_disp_y_m", "base_shear_ratio_resultant"):
        assert pairs["up"][key] == pytest.approx(single["peak"][key], rel=1e-9)
    assert pairs["up"]["uplift_time_s"] == pytest.approx(single["uplift"]["time_s"], rel=1e-12)
    assert pairs["up"]["uplift_time_s"] > 0
    assert abs(pairs["up"]["base_disp_resultant_m"] / pairs["flat"]["base_disp_resultant_m"] - 1) > 0.01


def test_a_vertical_record_that_does_not_fit_its_pair_is_refused_by_name(tmp_path, capsys):
    """Before any run: a vertical record at another step (without --resample), one shorter than
    its pair, a missing one and an unknown column are refused naming the suite file, the pair
    and the column."""
    _records(tmp_path, dt_z=0.02, n_z=151)
    suite = _suite(tmp_path, ["up,x.at2,y.at2,z.at2,1"])
    assert main(["run", "--suite", str(suite)]) != 0
    err = capsys.readouterr().err
    assert f"--suite {suite}, pair up: record_z" in err and "--resample" in err
    _records(tmp_path, n_z=201)
    assert main(["run", "--suite", str(suite)]) != 0
    err = capsys.readouterr().err
    assert f"--suite {suite}, pair up: record_z" in err and "shorter" in err
    suite = _suite(tmp_path, ["up,x.at2,y.at2,missing.at2,1"])
    assert main(["run", "--suite", str(suite)]) != 0
    err = capsys.readouterr().err
    assert "pair up" in err and "missing.at2" in err
    suite = _suite(tmp_path, ["up,x.at2,y.at2,z.at2,1"], header="name,record_x,record_y,record-z,scale")
    assert main(["run", "--suite", str(suite)]) != 0
    err = capsys.readouterr().err
    assert "line 1" in err and "'record-z'" in err and "record_z" in err


def test_suite_peaks_refuses_vertical_components_of_another_shape():
    ax = np.zeros((2, 11))
    with pytest.raises(ValueError, match="ax, ay, az"):
        suite_peaks(lambda *g: None, ["a", "b"], ax, ax, 0.01, 0.1, az=np.zeros((2, 10)))


def _vertical_build(ax, ay, az, dt):
    """A suite builder that pickles: the rigid mass on Table 1's flat sliders under a vertical
    record whose friction follows Table 1 at the momentary pressure; the ground replaced."""
    import equinox as eqx

    from teflon_jax.bearing import paper_bearing
    from teflon_jax.excitation import uniform_signal
    from teflon_jax.systems import rigid_mass, with_vertical_motion
    from teflon_jax.tables import friction_table, interface_parameters
    from teflon_jax.units import PSI

    params, _ = interface_parameters("UF", 1000 * PSI, "P")
    template = rigid_mass(components=2, weight=1e5, bearing=paper_bearing(params), ground_acceleration=uniform_signal(ax[0], dt),
                                        ground_y=uniform_signal(ay[0], dt), time_step=dt, isolation_period=2.0)
    template = with_vertical_motion(template, uniform_signal(az[0], dt), friction_table=friction_table("UF", "P", extrapolate=True),
                                    table_pressure=1000 * PSI)
    return lambda gx, gy, gz: eqx.tree_at(lambda s: (s.ground_acceleration, s.ground_y, s.vertical_acceleration), template,
                                          (gx, gy, gz))


@pytest.mark.slow
def test_on_a_cluster_the_vertical_suite_is_the_in_process_one(dask_cluster, tmp_path):
    """`suite_peaks_distributed` and `suite_cases_distributed` with vertical components stream
    the in-process peaks and uplift of the same chunk width bit for bit; the vertical matters."""
    from teflon_jax.studies import (
        open_suite,
        suite_cases_distributed,
        suite_peaks_distributed,
    )

    t = DT * np.arange(201)
    ax = np.stack([3.0 * np.sin(2 * np.pi * (0.6 + 0.1 * i) * t) for i in range(3)])
    ay = 0.7 * ax[::-1]
    az = np.stack([-12.0 * ((t > 0.8 + 0.1 * i) & (t < 1.1 + 0.1 * i)) for i in range(3)])
    names, duration, build = ["a", "b", "c"], (t.size - 1) * DT, _vertical_build(ax, ay, az, DT)
    here = suite_peaks(build, names, ax, ay, DT, duration, batch_size=2, az=az)
    there = suite_peaks_distributed(build, names, ax, ay, DT, duration, out=tmp_path / "s.nc", az=az,
                                    scheduler=dask_cluster.scheduler_address, chunk_size=2)
    assert set(here.peaks) >= {"uplift_time_s", "min_load_factor", "max_load_factor"}
    assert np.all(here.peaks["uplift_time_s"] > 0)
    for name, values in here.peaks.items():
        np.testing.assert_array_equal(there.peaks[name], values, err_msg=name)
    np.testing.assert_array_equal(open_suite(tmp_path / "s.nc").peaks["uplift_time_s"], here.peaks["uplift_time_s"])
    cases = suite_cases_distributed({"one": build, "two": build}, names, ax, ay, DT, duration, out=tmp_path / "c.nc",
                                    az=az, scheduler=dask_cluster.scheduler_address, chunk_size=2)
    for name, values in here.peaks.items():
        np.testing.assert_array_equal(cases["two"].peaks[name], values, err_msg=name)
    flat = suite_peaks(build, names, ax, ay, DT, duration, batch_size=2, az=np.zeros_like(az))
    assert np.all(np.abs(flat.peaks["base_disp_resultant_m"] / here.peaks["base_disp_resultant_m"] - 1) > 1e-3)


def test_a_vertical_record_beyond_the_table_is_refused_before_the_run(tmp_path, capsys):
    """UF at 6000 psi under a_v = +1 g (N = 2 W, 12,000 psi): Table 1's extended segments give
    no Eq. 1 constants there; `run --record-z` and a suite pair are refused naming the record
    or the pair and the pressure reached, before anything is compiled; at 1000 psi the same
    record is taken."""
    from teflon_jax.cli._normal_load import check_vertical_pressures

    t = DT * np.arange(301)
    _at2(tmp_path / "x.at2", 0.3 * np.sin(2 * np.pi * 0.8 * t))
    _at2(tmp_path / "z.at2", np.where(t > 1.0, 1.0, 0.0))
    argv = ["run", "--record-x", str(tmp_path / "x.at2"), "--record-z", str(tmp_path / "z.at2"), "--pressure", "6000psi"]
    assert main(argv) != 0
    err = capsys.readouterr().err
    assert f"--record-z {tmp_path / 'z.at2'}" in err and "12000 psi" in err and "compiling" not in err
    suite = _suite(tmp_path, ["heavy,x.at2,,z.at2,1"])
    assert main(["run", "--suite", str(suite), "--pressure", "6000psi"]) != 0
    err = capsys.readouterr().err
    assert f"--suite {suite}, pair heavy: record_z" in err and "12000 psi" in err
    from teflon_jax.bearing import paper_bearing
    from teflon_jax.excitation import uniform_signal
    from teflon_jax.systems import rigid_mass, with_vertical_motion
    from teflon_jax.tables import friction_table, interface_parameters
    from teflon_jax.units import PSI, STANDARD_GRAVITY

    for psi, refused in ((6000, True), (1000, False)):
        params, _ = interface_parameters("UF", psi * PSI, "P")
        system = rigid_mass(weight=1e5, bearing=paper_bearing(params), ground_acceleration=uniform_signal(t, DT),
                            time_step=DT, isolation_period=2.0)
        system = with_vertical_motion(system, uniform_signal(t, DT), friction_table=friction_table("UF", "P", extrapolate=True),
                                      table_pressure=psi * PSI)
        record = [("the record", np.where(t > 1.0, STANDARD_GRAVITY, 0.0))]
        if refused:
            with pytest.raises(ValueError, match="the record: .* 12000 psi"):
                check_vertical_pressures(system, record, DT)
        else:
            check_vertical_pressures(system, record, DT)
