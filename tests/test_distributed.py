"""Monte Carlo on the Dask engine (`monte_carlo_distributed`, `teflon_jax.studies._cluster`) on
a LocalCluster of 2 worker processes: per-motion results equal the in-process `monte_carlo`
with the same chunk size bit for bit (and to round-off across chunk sizes), for one and two
ground components, design variants and recorded motions; a worker killed mid-run costs only a
retry; runs whose solve failed are flagged and left out of the statistics as in-process; and
faults (a scheduler that does not answer, an output file that cannot be written, a chunk that
keeps failing) fail fast with the reason, in the library and in `teflon-jax montecarlo`."""

import json
import os
import signal
import time

import jax
import numpy as np
import pytest
import xarray

from teflon_jax.excitation import StochasticGroundMotion, TwoComponentGroundMotion, sample
from teflon_jax.studies import (
    ClusterRunError,
    MonteCarloResult,
    RecordSet,
    bidirectional_isolated_structure,
    monte_carlo,
    monte_carlo_distributed,
)
from teflon_jax.systems import isolated_structure

distributed = pytest.importorskip("distributed")

N = 6
NAMES = ("base_disp", "base_shear_ratio", "smooth_base_disp", "smooth_base_shear_ratio", "converged", "pga")


def _model():
    return StochasticGroundMotion(peak_ground_acceleration=3.0, duration=3.0, time_step=0.01,
                                  rise_time=0.5, strong_motion_duration=1.5)


def _structure():
    return isolated_structure("rigid", time_step=0.01, isolation_period=1.5)


@pytest.fixture(scope="module")
def cluster(dask_cluster):
    return dask_cluster  # one LocalCluster for all the distributed tests (tests/conftest.py)


def _in_process(chunk_size):
    return monte_carlo(_structure(), _model(), N, key=jax.random.key(7), chunk_size=chunk_size,
                       devices=jax.devices()[:1])


@pytest.fixture(scope="module")
def in_process():
    return _in_process(1)


@pytest.mark.slow
@pytest.mark.parametrize("chunk_size", [2, 4])
def test_equal_to_the_in_process_run(cluster, in_process, chunk_size, tmp_path):
    # Bit for bit against the in-process run with the same chunk size (each chunk is one task,
    # whichever worker runs it); across chunk sizes XLA's vectorised CPU code for a batch of
    # another width rounds differently in the last digits (seen: 5e-15 relative).
    out = tmp_path / "mc.nc"
    result = monte_carlo_distributed(_structure(), _model(), N, seed=7, out=out,
                                     scheduler=cluster.scheduler_address, chunk_size=chunk_size)
    assert result.n_motions == N and result.converged.all()
    same_layout = _in_process(chunk_size)
    for name in NAMES:
        np.testing.assert_array_equal(getattr(result, name), getattr(same_layout, name), err_msg=name)
        np.testing.assert_allclose(getattr(result, name), getattr(in_process, name), rtol=1e-13, atol=0)
    with xarray.open_dataset(out) as stored:  # what was streamed to the file
        np.testing.assert_array_equal(stored["base_disp"].values, same_layout.base_disp)
        assert stored["base_disp"].attrs["units"] == "m"
        assert stored.attrs["chunk_size"] == chunk_size


@pytest.mark.slow
def test_a_killed_worker_costs_only_a_retry(cluster, in_process, tmp_path):
    client = distributed.Client(cluster.scheduler_address)
    pids = client.run(os.getpid)
    killed = []

    def kill_one(done, total):
        if not killed:  # after the first chunk is written, kill a worker (its chunks rerun)
            victim = sorted(pids.values())[0]
            os.kill(victim, signal.SIGKILL)
            killed.append(victim)

    try:  # chunks of one motion: in_process ran them one at a time too (same layout)
        result = monte_carlo_distributed(_structure(), _model(), N, seed=7, out=tmp_path / "mc.nc",
                                         scheduler=cluster.scheduler_address, chunk_size=1,
                                         progress=kill_one)
    finally:
        client.close()
    assert killed
    for name in NAMES:
        np.testing.assert_array_equal(getattr(result, name), getattr(in_process, name), err_msg=name)


def test_a_scheduler_that_does_not_answer_fails_within_seconds(tmp_path):
    address = "tcp://127.0.0.1:9"
    tic = time.perf_counter()
    with pytest.raises(ConnectionError, match="tcp://127.0.0.1:9"):
        monte_carlo_distributed(_structure(), _model(), 4, out=tmp_path / "mc.nc", scheduler=address,
                                connect_timeout=3.0)
    assert time.perf_counter() - tic < 15.0


def test_an_unwritable_output_fails_before_computing(tmp_path):
    a_file = tmp_path / "a_file"
    a_file.write_text("")
    tic = time.perf_counter()
    with pytest.raises(ValueError, match="cannot write results"):
        monte_carlo_distributed(_structure(), _model(), 4, out=a_file / "mc.nc", scheduler="local:2")
    assert time.perf_counter() - tic < 2.0  # no cluster was started, nothing computed
    with pytest.raises(ValueError, match="give a .nc file"):
        monte_carlo_distributed(_structure(), _model(), 4, out=tmp_path / "mc.csv", scheduler="local:2")


@pytest.mark.slow
def test_two_components_with_design_variants_equal_the_in_process_run(cluster, tmp_path):
    # the bidirectional rigid mass under (x, y) motions drawn from fold_in(key(5), i), two
    # isolation periods per motion: the same peaks as in-process, on ("design", "motion")
    structure = bidirectional_isolated_structure("rigid", time_step=0.01, isolation_period=1.5)
    motions = TwoComponentGroundMotion(_model(), principal_angle=0.5, minor_ratio=0.7)
    design = {"isolation_period": np.array([1.5, 2.5])}
    out = tmp_path / "two.nc"
    result = monte_carlo_distributed(structure, motions, 3, seed=5, out=out, design=design,
                                     scheduler=cluster.scheduler_address, chunk_size=2)
    expected = monte_carlo(structure, motions, 3, key=jax.random.key(5), design=design, chunk_size=2,
                           devices=jax.devices()[:1])
    assert result.dims == ("design", "motion") and result.base_disp.shape == (2, 3)
    assert expected.converged.all() and np.all(expected.base_disp[1] != expected.base_disp[0])
    for name in NAMES:
        np.testing.assert_array_equal(getattr(result, name), getattr(expected, name), err_msg=name)
    assert result.attrs["components"] == 2 and result.attrs["minor_ratio"] == 0.7
    with xarray.open_dataset(out) as stored:
        assert stored["base_disp"].dims == ("design", "motion")
        assert stored["design_isolation_period"].attrs["units"] == "s"
        np.testing.assert_array_equal(stored["design_isolation_period"].values, design["isolation_period"])
        assert stored["pga"].attrs["units"] == "m s-2" and stored["converged"].dtype == bool
        assert list(stored.attrs["n_converged"]) == [3, 3] and stored.attrs["complete"] == 1


@pytest.mark.slow
def test_recorded_motions_equal_the_in_process_run(cluster, tmp_path):
    # a RecordSet: each chunk's records travel with its task
    records = RecordSet(acceleration=np.asarray(sample(_model(), jax.random.key(3), 3)), time_step=0.01,
                        names=("a", "b", "c"))
    result = monte_carlo_distributed(_structure(), records, out=tmp_path / "rec.nc",
                                     scheduler=cluster.scheduler_address, chunk_size=2)
    expected = monte_carlo(_structure(), records, chunk_size=2, devices=jax.devices()[:1])
    assert result.n_motions == 3 and np.ptp(expected.base_disp) > 0
    for name in NAMES:
        np.testing.assert_array_equal(getattr(result, name), getattr(expected, name), err_msg=name)
    np.testing.assert_allclose(result.pga, np.abs(records.acceleration).max(axis=1), rtol=1e-15)


@pytest.mark.slow
def test_failed_solves_are_flagged_and_left_out_on_the_cluster_as_in_process(cluster, tmp_path, capsys):
    # a real failure: one Newton iteration per 7.5 ms step, with the equilibrium asked to
    # 5e-5 Y, is too few for some motions' sliding steps (here 2 of 4); the command exits 1
    # naming the runs, the statistics rest on the converged runs only
    from teflon_jax.cli import main

    argv = ["montecarlo", "--motions", "4", "--duration", "4s", "--strong-motion", "1s", "--pga", "0.5g",
            "--time-step", "7.5ms", "--newton-iterations", "1", "--newton-tolerance", "5e-5", "--chunk-size", "2",
            "--no-progress"]
    here = main(argv + ["--json", str(tmp_path / "here.json"), "--out", str(tmp_path / "here.nc")])
    there = main(argv + ["--json", str(tmp_path / "there.json"), "--out", str(tmp_path / "there.nc"),
                         "--scheduler", cluster.scheduler_address])
    assert here == there == 1
    assert capsys.readouterr().err.count("runs had a time step whose Newton solve did not converge") == 2
    here, there = (json.loads((tmp_path / f"{n}.json").read_text()) for n in ("here", "there"))
    assert there["not_converged"] == here["not_converged"] and 0 < len(here["not_converged"]) < 4
    for name, stats in here["statistics"].items():  # the in-process command shards over 2 CPU
        assert there["statistics"][name] == pytest.approx(stats, rel=1e-12), name  # devices: round-off
    stored = MonteCarloResult.open(tmp_path / "there.nc")
    assert np.flatnonzero(~stored.converged).tolist() == here["not_converged"]
    assert there["statistics"]["base_shear_ratio"]["n"] == 4 - len(here["not_converged"])


def test_a_chunk_that_keeps_failing_stops_the_run_and_the_file_says_so(tmp_path):
    # a real failure on the worker: a worker computing in float32 (JAX_ENABLE_X64 unset there)
    # refuses a float64 run's chunks; after the retries the run stops naming the motions, and
    # the file it leaves is refused on reading (its chunks hold fill values)
    out = tmp_path / "mc.nc"
    env = {"JAX_ENABLE_X64": "0", "JAX_PLATFORMS": "cpu"}
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None,
                                  env=env) as float32:
        with pytest.raises(ClusterRunError, match=r"motions 0\.\.1 failed on the cluster after 1 retries"
                                                  r".*JAX_ENABLE_X64=1"):
            monte_carlo_distributed(_structure(), _model(), 3, out=out, scheduler=float32.scheduler_address,
                                    chunk_size=2, retries=1)
    with xarray.open_dataset(out) as stored:
        assert stored.attrs["complete"] == 0
    with pytest.raises(ValueError, match="did not finish"):
        MonteCarloResult.open(out)


def test_cli_cluster_faults_fail_fast_with_the_reason(tmp_path, capsys):
    from teflon_jax.cli import main

    a_file = tmp_path / "a_file"
    a_file.write_text("")
    argv = ["montecarlo", "--motions", "2", "--duration", "4s", "--strong-motion", "1s", "--no-progress"]
    cases = [
        (["--scheduler", "local:2"], "add --out FILE.nc"),
        (["--scheduler", "local:2", "--out", str(a_file / "mc.nc")], "cannot write results"),
        (["--scheduler", "local:2", "--out", str(tmp_path / "mc.csv")], "--out: " + str(tmp_path / "mc.csv")),
        (["--scheduler", "tcp://127.0.0.1:9", "--out", str(tmp_path / "mc.nc")], "tcp://127.0.0.1:9"),
    ]
    for extra, message in cases:
        tic = time.perf_counter()
        assert main(argv + extra) == 2, extra
        assert message in capsys.readouterr().err, extra
        assert time.perf_counter() - tic < 15.0, extra  # connect timeout 10 s; nothing computed


_SCRIPT = """
import jax  # imported by the main module before the workers start: they must still get float64
import numpy as np
from teflon_jax.excitation import StochasticGroundMotion, TwoComponentGroundMotion, sample
from teflon_jax.studies import (
    ClusterRunError,
    MonteCarloResult,
    RecordSet,
    bidirectional_isolated_structure,
    monte_carlo,
    monte_carlo_distributed,
)
from teflon_jax.systems import isolated_structure


def main(out):
    jax.config.update("jax_enable_x64", True)
    model = StochasticGroundMotion(peak_ground_acceleration=3.0, duration=2.0, time_step=0.01,
                                   rise_time=0.5, strong_motion_duration=1.0)
    structure = isolated_structure("rigid", time_step=0.01, isolation_period=1.5)
    result = monte_carlo_distributed(structure, model, 3, seed=2, out=out, scheduler="local:2",
                                     chunk_size=2)
    same = monte_carlo(structure, model, 3, key=jax.random.key(2), chunk_size=2,
                       devices=jax.devices()[:1])
    assert np.array_equal(result.base_disp, same.base_disp), (result.base_disp, same.base_disp)
    print("ok", result.attrs["precision"])


if __name__ == "__main__":
    import sys

    main(sys.argv[1])
"""


@pytest.mark.slow
def test_local_scheduler_starts_workers_in_the_callers_precision(tmp_path):
    import subprocess
    import sys

    script = tmp_path / "run.py"
    script.write_text(_SCRIPT)
    env = dict(os.environ, JAX_PLATFORMS="cpu")
    env.pop("JAX_ENABLE_X64", None)
    out = subprocess.run([sys.executable, str(script), str(tmp_path / "mc.nc")], env=env,
                         capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr[-3000:]
    assert "ok float64" in out.stdout
