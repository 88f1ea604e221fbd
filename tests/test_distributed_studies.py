"""Record suites and design sweeps on the Dask engine (`teflon_jax.studies._cluster`), on the
shared LocalCluster of 2 worker processes: each pair's / design point's results equal the
in-process run with the same batch width bit for bit, for two chunk sizes (and across chunk
sizes to round-off: XLA's vectorised code rounds the last digits differently for another
width), the streamed NetCDF file reads back with xarray with its units, a worker killed mid-run
costs only a retry, and faults (an output file that cannot be written, a scheduler that does
not answer) fail fast with the reason."""

import os
import signal
import time

import equinox as eqx
import jax
import numpy as np
import pytest
import xarray

from teflon_jax.bearing import paper_bearing
from teflon_jax.excitation import StochasticGroundMotion, sample, uniform_signal
from teflon_jax.studies import (
    design_sweep,
    design_sweep_distributed,
    open_suite,
    open_sweep,
    save_suite,
    suite_peaks,
    suite_peaks_distributed,
)
from teflon_jax.systems import isolated_structure, rigid_mass
from teflon_jax.tables import interface_parameters
from teflon_jax.units import PSI

distributed = pytest.importorskip("distributed")

DT = 0.01
PAIRS = 5
SAMPLES = 201
SWEEP = {"isolation_period": np.array([1.0, 2.0, 3.0]), "pressure": np.array([1000.0, 1500.0]) * PSI}


def _pairs():
    t = DT * np.arange(SAMPLES)
    ramp = np.sin(np.pi * t / t[-1]) ** 2
    ax = np.stack([3.0 * np.sin(2 * np.pi * (0.6 + 0.1 * i) * t) * ramp for i in range(PAIRS)])
    ay = np.stack([2.0 * np.cos(2 * np.pi * (0.5 + 0.13 * i) * t) * ramp for i in range(PAIRS)])
    return [f"pair{i}" for i in range(PAIRS)], ax, ay


def _build():
    """A builder that pickles (a closure over an equinox module): only the ground changes."""
    _, ax, ay = _pairs()
    params, _ = interface_parameters("UF", 1000 * PSI, "P")
    template = rigid_mass(components=2, weight=1e5, bearing=paper_bearing(params), ground_acceleration=uniform_signal(ax[0], DT),
                                        ground_y=uniform_signal(ay[0], DT), time_step=DT, isolation_period=2.0)
    return lambda gx, gy: eqx.tree_at(lambda s: (s.ground_acceleration, s.ground_y), template, (gx, gy))


def _suite(**kwargs):
    names, ax, ay = _pairs()
    return suite_peaks_distributed(_build(), names, ax, ay, DT, (SAMPLES - 1) * DT, **kwargs)


@pytest.fixture(scope="module")
def suite_in_process():
    """The in-process suite in batches of `width` pairs (memoised: one compilation each)."""
    names, ax, ay = _pairs()
    done = {}

    def run(width):
        if width not in done:
            done[width] = suite_peaks(_build(), names, ax, ay, DT, (SAMPLES - 1) * DT, batch_size=width)
        return done[width]

    return run


def _structure():
    return isolated_structure("rigid", time_step=DT, isolation_period=1.5)


def _records():
    model = StochasticGroundMotion(peak_ground_acceleration=3.0, duration=2.0, time_step=DT,
                                   rise_time=0.5, strong_motion_duration=1.0)
    return np.asarray(sample(model, jax.random.key(3), 2))


def _sweep(**kwargs):
    return design_sweep_distributed(_structure(), _records(), DT, grid=SWEEP, disp_limit=0.05, **kwargs)


@pytest.fixture(scope="module")
def sweep_in_process():
    """The in-process sweep in batches of `width` design points (memoised)."""
    done = {}

    def run(width):
        if width not in done:
            done[width] = design_sweep(_structure(), _records(), DT, grid=SWEEP, disp_limit=0.05, batch_size=width)
        return done[width]

    return run


def _assert_suite_equal(result, expected):
    assert result.names == expected.names
    np.testing.assert_array_equal(result.converged, expected.converged)
    for name, values in expected.peaks.items():
        np.testing.assert_array_equal(result.peaks[name], values, err_msg=name)


def _assert_sweep_equal(result, expected):
    for name in ("objective", "shear", "disp", "converged", "n_failed"):
        np.testing.assert_array_equal(result[name], expected[name], err_msg=name)
    for name, mesh in expected["grid"].items():
        np.testing.assert_array_equal(result["grid"][name], mesh, err_msg=name)


@pytest.mark.slow
@pytest.mark.parametrize("chunk_size", [2, 3])
def test_suite_equals_the_in_process_run(dask_cluster, suite_in_process, chunk_size, tmp_path):
    out = tmp_path / "suite.nc"
    result = _suite(out=out, scheduler=dask_cluster.scheduler_address, chunk_size=chunk_size)
    expected = suite_in_process(chunk_size)
    assert expected.converged.all() and expected.peaks["base_disp_x_m"].min() > 0
    _assert_suite_equal(result, expected)
    other = suite_in_process(5 - chunk_size)  # the other chunk size: round-off apart
    for name, values in other.peaks.items():
        np.testing.assert_allclose(result.peaks[name], values, rtol=1e-13, atol=0, err_msg=name)
    with xarray.open_dataset(out) as stored:  # what was streamed, with units and pair names
        assert list(stored["pair"].values) == list(expected.names)
        for name, units in (("base_disp_resultant_m", "m"), ("base_disp_x_m", "m"), ("base_disp_y_m", "m"),
                            ("base_shear_ratio_resultant", "1"), ("converged", "1")):
            assert stored[name].attrs["units"] == units and stored[name].attrs["long_name"]
        np.testing.assert_array_equal(stored["base_disp_x_m"].values, expected.peaks["base_disp_x_m"])
        assert stored["converged"].dtype == bool
        assert stored.attrs["chunk_size"] == chunk_size
        assert stored.attrs["base_disp_resultant_m_max"] == expected.summary["base_disp_resultant_m"]["max"]
    # the in-process file has the same layout and reads back into the same result
    save_suite(expected, netcdf_path=tmp_path / "same.nc")
    _assert_suite_equal(open_suite(tmp_path / "same.nc"), expected)


@pytest.mark.slow
@pytest.mark.parametrize("chunk_size", [2, 4])
def test_sweep_equals_the_in_process_run(dask_cluster, sweep_in_process, chunk_size, tmp_path):
    out = tmp_path / "sweep.nc"
    result = _sweep(out=out, scheduler=dask_cluster.scheduler_address, chunk_size=chunk_size)
    expected = sweep_in_process(chunk_size)
    assert expected["converged"].all() and np.ptp(expected["disp"]) > 0
    _assert_sweep_equal(result, expected)
    other = sweep_in_process(6 - chunk_size)
    for name in ("objective", "shear", "disp"):
        np.testing.assert_allclose(result[name], other[name], rtol=1e-13, atol=0, err_msg=name)
    with xarray.open_dataset(out) as stored:
        assert stored["objective"].dims == ("isolation_period", "pressure")
        np.testing.assert_array_equal(stored["pressure"].values, SWEEP["pressure"])
        units = {"isolation_period": "s", "pressure": "Pa", "objective": "1", "shear": "1", "disp": "m",
                 "converged": "1", "n_failed": "1"}
        for name, unit in units.items():
            assert stored[name].attrs["units"] == unit, name
        # the points at T_b = 3 s sit at their place on the grid
        np.testing.assert_array_equal(stored["disp"].sel(isolation_period=3.0).values, expected["disp"][2])
    from teflon_jax.studies import sweep_dataset

    sweep_dataset(expected).to_netcdf(tmp_path / "same.nc")
    _assert_sweep_equal(open_sweep(tmp_path / "same.nc"), expected)


@pytest.mark.slow
def test_a_killed_worker_costs_only_a_retry(dask_cluster, suite_in_process, sweep_in_process, tmp_path):
    client = distributed.Client(dask_cluster.scheduler_address)
    killed = []

    def kill_one(done, total):
        if not killed:  # after the first chunk is written, kill a worker (its chunks rerun)
            pids = client.run(os.getpid)
            victim = sorted(pids.values())[0]
            os.kill(victim, signal.SIGKILL)
            killed.append(victim)

    try:
        suite = _suite(out=tmp_path / "suite.nc", scheduler=dask_cluster.scheduler_address, chunk_size=2,
                       progress=kill_one)
        assert killed
        _assert_suite_equal(suite, suite_in_process(2))
        killed.clear()
        client.wait_for_workers(2, timeout=120)
        sweep = _sweep(out=tmp_path / "sweep.nc", scheduler=dask_cluster.scheduler_address, chunk_size=2,
                       progress=kill_one)
        assert killed
        _assert_sweep_equal(sweep, sweep_in_process(2))
    finally:
        client.close()


def test_a_scheduler_that_does_not_answer_fails_within_seconds(tmp_path):
    address = "tcp://127.0.0.1:9"
    for run in (_suite, _sweep):
        tic = time.perf_counter()
        with pytest.raises(ConnectionError, match="tcp://127.0.0.1:9"):
            run(out=tmp_path / "r.nc", scheduler=address, connect_timeout=3.0)
        assert time.perf_counter() - tic < 15.0


def test_an_unwritable_output_fails_before_computing(tmp_path):
    a_file = tmp_path / "a_file"
    a_file.write_text("")
    for run in (_suite, _sweep):
        tic = time.perf_counter()
        with pytest.raises(ValueError, match="cannot write results"):
            run(out=a_file / "r.nc", scheduler="local:2")
        assert time.perf_counter() - tic < 2.0  # no cluster was started, nothing computed
        with pytest.raises(ValueError, match="give a .nc file"):
            run(out=tmp_path / "r.csv", scheduler="local:2")


def _suite_files(tmp_path):
    """A suite CSV of 3 two-column record pairs (one scaled by 2) in g."""
    names, ax, ay = _pairs()
    t = DT * np.arange(SAMPLES)
    for i in range(3):
        for axis, values in (("x", ax[i]), ("y", ay[i])):
            rows = "\n".join(f"{ti:.4f} {a / 9.80665:.9e}" for ti, a in zip(t, values))
            (tmp_path / f"{axis}{i}.txt").write_text("time acc\n" + rows + "\n")
    (tmp_path / "suite.csv").write_text("name,record_x,record_y,scale\na,x0.txt,y0.txt,1\n"
                                        "b,x1.txt,y1.txt,1\nc,x2.txt,y2.txt,2\n")
    return ["run", "--suite", str(tmp_path / "suite.csv"), "--record-units", "g", "--time-step", "10ms",
            "--isolation-period", "2s"]


def test_cli_refuses_cluster_flags_it_cannot_honour(tmp_path, capsys):
    from teflon_jax.cli import main

    suite = _suite_files(tmp_path)
    a_file = tmp_path / "a_file"
    a_file.write_text("")
    cases = [
        (suite + ["--scheduler", "local:2"], "add --out FILE.nc"),
        (suite + ["--scheduler", "local:2", "--out", str(a_file / "s.nc")], "cannot write results"),
        (["run", "--record-x", str(tmp_path / "x0.txt"), "--record-units", "g", "--scheduler", "local:2"],
         "--scheduler: only used with --suite"),
        (["design", "--scheduler", "local:2"], "add --out FILE.nc"),
        (["design", "--scheduler", "local:2", "--out", str(tmp_path / "sweep.csv")], "give a .nc file"),
    ]
    for argv, message in cases:  # refused before any record is run or any cluster started
        assert main(argv) == 2, argv
        assert message in capsys.readouterr().err, argv


@pytest.mark.slow
def test_cli_suite_on_the_cluster_writes_what_the_in_process_run_writes(dask_cluster, tmp_path, capsys):
    from teflon_jax.cli import main

    suite = _suite_files(tmp_path)
    assert main(suite + ["--json", str(tmp_path / "here.json"), "--chunk-size", "2"]) == 0
    assert main(suite + ["--json", str(tmp_path / "there.json"), "--scheduler", dask_cluster.scheduler_address,
                         "--chunk-size", "2", "--out", str(tmp_path / "there.nc")]) == 0
    here, there = open_suite(tmp_path / "here.nc"), open_suite(tmp_path / "there.nc")
    _assert_suite_equal(there, here)
    assert here.peaks["base_disp_resultant_m"][2] > here.peaks["base_disp_resultant_m"][0] > 0
    assert (tmp_path / "here.csv").read_text() == (tmp_path / "there.csv").read_text()


@pytest.mark.slow
def test_a_chunk_that_keeps_failing_stops_the_run_naming_its_pairs(dask_cluster, tmp_path):
    # a builder that returns no structure fails on the worker as it traces (a real error)
    names, ax, ay = _pairs()
    out = tmp_path / "suite.nc"
    with pytest.raises(RuntimeError, match=r"pairs \d\.\.\d failed on the cluster after 1 retries"):
        suite_peaks_distributed(lambda gx, gy: None, names, ax, ay, DT, (SAMPLES - 1) * DT, out=out,
                                scheduler=dask_cluster.scheduler_address, chunk_size=2, retries=1)
    with pytest.raises(ValueError, match="did not finish"):
        open_suite(out)  # the file says it is incomplete
