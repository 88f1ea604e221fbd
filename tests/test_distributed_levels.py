"""`teflon-jax montecarlo` over several --pga levels (with --limit, --storeys, --pelicun-demands)
on a Dask LocalCluster (`monte_carlo_levels_distributed`): every level's motions run as chunks on
the workers, their peaks (storey peaks included) stream to the NetCDF file, and the counts,
fragility fits, statistics and pelicun files computed from them are those of the in-process
run; runs whose Newton solve failed are flagged and left out of the counts and statistics as
in-process.

References: the in-process `monte_carlo_levels` on one device with the same chunk size (the
same program at the same batch width, compiled in each process: equal to 1e-12 relative), and the in-process command (its
chunks split over two CPU devices: equal to round-off, 1e-12 relative)."""

import json

import jax
import numpy as np
import pytest
import xarray

from teflon_jax.cli import main
from teflon_jax.excitation import StochasticGroundMotion
from teflon_jax.studies import monte_carlo_levels, monte_carlo_levels_distributed
from teflon_jax.systems import isolated_structure
from teflon_jax.tables import load_table2
from teflon_jax.units import STANDARD_GRAVITY

distributed = pytest.importorskip("distributed")

LEVELS = (0.2 * STANDARD_GRAVITY, 0.5 * STANDARD_GRAVITY)
NAMES = ("base_disp", "base_shear_ratio", "smooth_base_disp", "smooth_base_shear_ratio", "converged", "pga",
         "storey_drift", "floor_acceleration")
TIMINGS = ("wall_s", "compile_s", "files", "command_line", "inputs")  # differ by design


def _model():
    return StochasticGroundMotion(peak_ground_acceleration=1.0, duration=3.0, time_step=0.01, rise_time=0.5,
                                  strong_motion_duration=1.5)


@pytest.mark.slow  # a building compiled in this process and on the two workers (about 60 s on two cores)
def test_levels_with_storey_peaks_equal_the_in_process_run(dask_cluster, tmp_path):
    structure, height, out = isolated_structure("building"), load_table2().storey_height, tmp_path / "mc.nc"
    result, index = monte_carlo_levels_distributed(structure, _model(), LEVELS, 3, out=out, seed=4,
                                                   scheduler=dask_cluster.scheduler_address, chunk_size=2,
                                                   storey_height=height)
    expected, expected_index = monte_carlo_levels(structure, _model(), LEVELS, 3, key=jax.random.key(4),
                                                  chunk_size=2, devices=jax.devices()[:1], storey_height=height)
    np.testing.assert_array_equal(index, expected_index)
    assert expected.converged.all() and result.storey_drift.shape == (6, 6)
    for name in NAMES:
        # to rounding: the workers' and this process's compiled programs may differ in the last bits
        np.testing.assert_allclose(getattr(result, name), getattr(expected, name), rtol=1e-12, err_msg=name)
    assert result.attrs["intensity_levels_m_s2"] == list(LEVELS) and result.attrs["motions_per_level"] == 3
    with xarray.open_dataset(out) as stored:  # the layout save_levels writes, levels included
        np.testing.assert_array_equal(stored["intensity_level"].values, np.repeat(LEVELS, 3))
        assert stored["storey_drift"].dims == ("motion", "storey") and stored["level"].values.tolist() == list(range(7))
        assert stored["intensity_level"].attrs["units"] == "m s-2" and stored.attrs["complete"] == 1


def _numbers_equal(here, there, path=""):
    """The JSON `there` has `here`'s keys and values, numbers to 1e-12 relative."""
    if isinstance(here, dict):
        assert set(here) == set(there), path
        for key in here:
            if key not in TIMINGS:
                _numbers_equal(here[key], there[key], f"{path}/{key}")
    elif isinstance(here, list):
        assert len(here) == len(there), path
        for i, (a, b) in enumerate(zip(here, there)):
            _numbers_equal(a, b, f"{path}[{i}]")
    elif isinstance(here, float):
        assert there == pytest.approx(here, rel=1e-12, abs=0), path
    else:
        assert there == here, path


@pytest.mark.slow  # two levels in this process and on the cluster (about 60 s on two cores)
def test_cli_levels_on_the_cluster_write_what_the_in_process_run_writes(dask_cluster, tmp_path, capsys):
    # one Newton iteration per 7.5 ms step, the equilibrium asked to 5e-5 Y: some motions' sliding
    # steps fail; they are flagged, named, and out of the counts and statistics in both runs
    argv = ["montecarlo", "--motions", "4", "--duration", "4s", "--strong-motion", "1s", "--pga", "0.3g,0.5g",
            "--time-step", "7.5ms", "--newton-iterations", "1", "--newton-tolerance", "5e-5", "--chunk-size", "2",
            "--limit", "base_disp=0.4in", "--limit", "base_shear_ratio=0.1", "--no-progress"]
    statuses = [main(argv + ["--json", str(tmp_path / f"{n}.json"), "--out", str(tmp_path / f"{n}.nc"),
                             "--pelicun-demands", str(tmp_path / f"{n}.csv"), *extra])
                for n, extra in (("here", []), ("there", ["--scheduler", dask_cluster.scheduler_address]))]
    assert statuses == [1, 1]
    assert capsys.readouterr().err.count("runs had a time step whose Newton solve did not converge") == 2
    here, there = (json.loads((tmp_path / f"{n}.json").read_text()) for n in ("here", "there"))
    _numbers_equal(here, there)
    failed = here["not_converged"]
    assert 0 < len(failed) < 8 and there["not_converged"] == failed
    with xarray.open_dataset(tmp_path / "there.nc") as stored:
        ok, level = stored["converged"].values, stored["intensity_level"].values
        disp = stored["base_disp"].values
    assert np.flatnonzero(~ok).tolist() == failed
    for j, (entry, x) in enumerate(zip(there["levels"], np.unique(level))):  # counts and statistics: converged runs
        rows = np.flatnonzero(level == x)  # the level's motions, as a range
        assert entry["motions"] == {"first": int(rows[0]), "last": int(rows[-1]), "count": rows.size}
        assert entry["n_converged"] == int(np.sum(ok & (level == x)))
        assert entry["statistics"]["base_shear_ratio"]["n"] == entry["n_converged"]
        assert there["fragility"]["base_disp=0.4in"]["n_exceed"][j] == int(np.sum(ok & (level == x)
                                                                             & (disp > 0.4 * 0.0254)))
    for j in (1, 2):  # pelicun's demand files: the same runs, the failed ones marked
        here_rows = (tmp_path / f"here-level{j}.csv").read_text().splitlines()
        there_rows = (tmp_path / f"there-level{j}.csv").read_text().splitlines()
        assert len(there_rows) == len(here_rows) == 2 + 4 and there_rows[:2] == here_rows[:2]
        for a, b in zip(here_rows[2:], there_rows[2:]):
            assert np.allclose([float(v or "nan") for v in b.split(",")], [float(v or "nan") for v in a.split(",")],
                               rtol=1e-12, atol=0, equal_nan=True)


def test_design_variants_over_levels_are_refused_before_a_cluster_starts(tmp_path):
    with pytest.raises(ValueError, match="design: design variants over intensity levels"):
        monte_carlo_levels_distributed(isolated_structure("rigid"), _model(), LEVELS, 2, out=tmp_path / "mc.nc",
                                       scheduler="tcp://127.0.0.1:9", design={"isolation_period": [2.0, 3.0]})
    with pytest.raises(ValueError, match="system: storey results need a building"):
        monte_carlo_levels_distributed(isolated_structure("rigid"), _model(), LEVELS, 2, out=tmp_path / "mc.nc",
                                       scheduler="tcp://127.0.0.1:9", storey_height=3.0)
    assert not list(tmp_path.iterdir())
