"""Bounding analysis on a Dask cluster (`teflon-jax montecarlo --property-factors LOWER,UPPER
--scheduler ADDRESS --out FILE.nc`): the three bearings are the design axis of one distributed
run, on the shared LocalCluster of 2 worker processes (tests/conftest.py).

Peer: the same command without --scheduler (the in-process bounding run, whose own tests check
it against Table 1 scaled by hand and isolator files scaled by hand). The motions are the same
(motion i from fold_in(key(seed), i)) and the friction of each case the same, so every JSON
number (each case's mean and maximum, converged counts, the governing case) agrees to
round-off; the results file's design coordinates are the friction of `bounding_design`."""

import json

import numpy as np
import pytest
import xarray

from teflon_jax.cli import main
from teflon_jax.studies import BOUNDING_CASES

distributed = pytest.importorskip("distributed")

COMMON = ["montecarlo", "--motions", "4", "--duration", "4s", "--strong-motion", "2s", "--pga", "0.4g",
          "--property-factors", "0.8,1.25", "--chunk-size", "2", "--no-progress"]


def _here_and_there(tmp_path, address, extra):
    """(exit status, JSON) of the in-process command and of the one on the cluster."""
    runs = {}
    for name, flags in (("here", []), ("there", ["--scheduler", address])):
        code = main([*COMMON, *extra, *flags, "--json", str(tmp_path / f"{name}.json"),
                     "--out", str(tmp_path / f"{name}.nc")])
        runs[name] = (code, json.loads((tmp_path / f"{name}.json").read_text()))
    return runs["here"], runs["there"]


def _assert_same_numbers(here, there, path="") -> None:
    """Every number of the JSON `here` equals `there`'s to 1e-12 (relative), every other value
    exactly; run times, file names and the command lines excepted."""
    if isinstance(here, dict):
        keys = set(here) - {"wall_s", "files", "command_line", "inputs"}
        assert keys == set(there) - {"wall_s", "files", "command_line", "inputs"}, path
        for key in keys:
            _assert_same_numbers(here[key], there[key], f"{path}/{key}")
    elif isinstance(here, float) and not isinstance(here, bool):
        assert there == pytest.approx(here, rel=1e-12, abs=1e-300), path
    elif isinstance(here, list):
        assert len(here) == len(there), path
        for i, (a, b) in enumerate(zip(here, there)):
            _assert_same_numbers(a, b, f"{path}[{i}]")
    else:
        assert here == there, path


@pytest.mark.slow  # two compiled bounding runs per bearing kind, on two shared cores
@pytest.mark.parametrize("extra", [[], ["--isolator", "single-fp", "--radius", "1.5m"]], ids=["flat", "single-fp"])
def test_bounds_on_the_cluster_equal_the_in_process_run(dask_cluster, tmp_path, extra, capsys):
    """Flat slider and single pendulum: the JSON's cases, counts and governing cases equal the
    in-process run's; the file holds the three cases (lower bound moves most, upper pushes
    hardest: more friction, less displacement and more base shear)."""
    (code_here, here), (code_there, there) = _here_and_there(tmp_path, dask_cluster.scheduler_address, extra)
    capsys.readouterr()
    assert code_here == code_there == 0
    _assert_same_numbers(here, there)
    assert there["files"] == [str(tmp_path / "there.nc")]
    with xarray.open_dataset(tmp_path / "there.nc") as dataset:
        assert dataset.attrs["complete"] == 1
        np.testing.assert_allclose(dataset["design_f_max"].values / dataset["design_f_max"].values[0],
                                   [1.0, 1.25, 0.8], rtol=1e-12)
        disp = dataset["base_disp"].values
        assert disp.shape == (3, 4)
    for i, case in enumerate(BOUNDING_CASES):
        assert there["cases"][case]["f_max"] == pytest.approx(float(dataset["design_f_max"].values[i]), rel=1e-15)
        assert there["cases"][case]["mean"]["base_disp_in"] == pytest.approx(disp[i].mean() / 0.0254, rel=1e-12)
    assert there["governs"]["base_disp_in"]["by_mean"] == "lower"
    assert there["governs"]["base_shear_ratio"]["by_mean"] == "upper"


@pytest.mark.slow  # two compiled bounding runs of a poorly resolved slider
def test_failed_solves_stay_out_of_the_cluster_bounds_as_in_process(dask_cluster, tmp_path, capsys):
    """One Newton iteration per 7.5 ms step (equilibrium to 5e-5 Y) fails some motions' sliding
    steps: both commands exit 1, the same runs of each case fail, and the statistics rest on
    the converged runs only, on the cluster as in this process."""
    extra = ["--time-step", "7.5ms", "--newton-iterations", "1", "--newton-tolerance", "5e-5", "--pga", "0.5g"]
    (code_here, here), (code_there, there) = _here_and_there(tmp_path, dask_cluster.scheduler_address, extra)
    assert code_here == code_there == 1
    err = capsys.readouterr().err
    assert err.count("runs had a time step whose Newton solve did not converge (case:motion ") == 2
    assert err.count("they are flagged in the results and left out of the table") == 2 and "tipped" not in err
    _assert_same_numbers(here, there)
    with xarray.open_dataset(tmp_path / "there.nc") as dataset:
        ok = dataset["converged"].values.astype(bool)
        disp = dataset["base_disp"].values
    assert not ok.all() and ok.any()
    for i, case in enumerate(BOUNDING_CASES):
        assert there["cases"][case]["n_converged"] == int(ok[i].sum())
        if ok[i].any():
            assert there["cases"][case]["max"]["base_disp_in"] == pytest.approx(disp[i][ok[i]].max() / 0.0254,
                                                                                 rel=1e-12)


def test_bounds_go_to_the_scheduler_that_is_named(tmp_path, capsys):
    """The refusal of --scheduler is gone: an address that does not answer is the failure,
    named, before anything is computed; a missing --out is asked for."""
    assert main([*COMMON, "--scheduler", "tcp://127.0.0.1:9", "--out", str(tmp_path / "b.nc")]) == 2
    err = capsys.readouterr().err
    assert "tcp://127.0.0.1:9" in err and "leave out --scheduler" not in err
    assert main([*COMMON, "--scheduler", "local:2"]) == 2
    assert "add --out FILE.nc" in capsys.readouterr().err


@pytest.mark.slow  # two compiled triple-pendulum bounding runs
def test_triple_pendulum_bounds_on_the_cluster_equal_the_in_process_run(dask_cluster, tmp_path, capsys):
    """A triple pendulum (every surface's friction times the case's factor, the design variable
    `friction_factor`): the cluster's JSON, per-surface friction included, is the in-process one."""
    from test_series_bounding import NOMINAL, _triple

    (tmp_path / "tfp.json").write_text(json.dumps(_triple(NOMINAL)))
    extra = ["--isolator", "triple-fp", "--isolator-file", str(tmp_path / "tfp.json")]
    (code_here, here), (code_there, there) = _here_and_there(tmp_path, dask_cluster.scheduler_address, extra)
    capsys.readouterr()
    assert code_here == code_there == 0
    _assert_same_numbers(here, there)
    with xarray.open_dataset(tmp_path / "there.nc") as dataset:
        np.testing.assert_array_equal(dataset["design_friction_factor"].values, [1.0, 1.25, 0.8])
    assert there["cases"]["upper"]["f_max"] == pytest.approx({k: 1.25 * v[0] for k, v in NOMINAL.items()}, rel=1e-12)
    assert there["governs"]["base_disp_in"]["by_mean"] == "lower"


@pytest.mark.slow  # two compiled bounding runs with a vertical component
def test_bounds_with_a_vertical_component_on_the_cluster_equal_the_in_process_run(dask_cluster, tmp_path, capsys):
    """Friction-only rigid mass at PGA 1 g with a vertical component of 1.2 x PGA (N = W max(1 +
    a_v / g, 0), so some motions lift off): the three bearings see the same vertical records on the cluster as in this process, so
    the uplifted motions and their times and every case's statistics agree."""
    extra = ["--isolation-period", "none", "--isolation-damping", "0", "--pga", "1g", "--vertical-ratio", "1.2"]
    (code_here, here), (code_there, there) = _here_and_there(tmp_path, dask_cluster.scheduler_address, extra)
    capsys.readouterr()
    assert code_here == code_there
    assert there["vertical"]["vertical_ratio"] == 1.2
    _assert_same_numbers(here, there)
    with xarray.open_dataset(tmp_path / "there.nc") as dataset:
        uplift = dataset["uplift_time"].values
    assert uplift.shape == (3, 4)
    np.testing.assert_array_equal(uplift[1], uplift[0])  # the vertical record's, whatever the friction
    assert there["vertical"]["n_uplifted"] == int((uplift[0] > 0).sum()) > 0
