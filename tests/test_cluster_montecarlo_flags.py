"""`teflon-jax montecarlo` on a Dask cluster with the flags that shape its result: the
building's storeys and two ground components in the bounding analysis (`--property-factors`,
the three bearings the design axis of the distributed run), and a vertical component over
several intensity levels (`--vertical-ratio` with `--pga L1,L2`), on the shared LocalCluster
of 2 worker processes (tests/conftest.py).

Peer: the same command without --scheduler. Motion i is drawn from fold_in(key(seed), i) (at
each level from the level's own model) on either side, so every number of the JSON (each
case's or level's statistics, counts, uplifted motions and their times, the governing case,
the fragility fits) agrees to 1e-12. Physical checks ride along: the lower bound moves most,
and more motions lift off at 1 g than at 0.3 g under a vertical peak of 1.2 x PGA."""

import json

import numpy as np
import pytest
import xarray

from teflon_jax.cli import main

distributed = pytest.importorskip("distributed")

COMMON = ["montecarlo", "--motions", "4", "--duration", "4s", "--strong-motion", "1.5s", "--chunk-size", "2",
          "--no-progress"]
OWN = {"wall_s", "compile_s", "files", "records_per_s", "records_per_s_after_first_chunk", "devices", "command_line",
       "inputs"}  # times, devices (a cluster's workers), file names and flags differ by design


def _here_and_there(tmp_path, address, extra):
    """(exit status, JSON) of the in-process command and of the one on the cluster."""
    runs = {}
    for name, flags in (("here", []), ("there", ["--scheduler", address])):
        code = main([*COMMON, *extra, *flags, "--json", str(tmp_path / f"{name}.json"),
                     "--out", str(tmp_path / f"{name}.nc")])
        runs[name] = (code, json.loads((tmp_path / f"{name}.json").read_text()))
    return runs["here"], runs["there"]


def _assert_same_numbers(here, there, path="") -> None:
    """Every number of `here` equals `there`'s to 1e-12 (relative), every other value exactly;
    the keys of `OWN` left out."""
    if isinstance(here, dict):
        assert set(here) - OWN == set(there) - OWN, path
        for key in set(here) - OWN:
            _assert_same_numbers(here[key], there[key], f"{path}/{key}")
    elif isinstance(here, list):
        assert len(here) == len(there), path
        for i, (a, b) in enumerate(zip(here, there)):
            _assert_same_numbers(a, b, f"{path}[{i}]")
    elif isinstance(here, float):
        assert there == pytest.approx(here, rel=1e-12, abs=1e-300, nan_ok=True), path
    else:
        assert here == there, path


@pytest.mark.slow  # two compiled bounding runs of a six-storey building or a two-component mass
@pytest.mark.parametrize("extra", [
    ["--structure", "building", "--isolation-period", "2.5s", "--storeys"],
    ["--components", "2", "--isolation-period", "2.5s"]], ids=["building-storeys", "two-components"])
def test_bounds_of_storeys_and_two_components_on_the_cluster_equal_the_in_process_run(
        dask_cluster, tmp_path, extra, capsys):
    """The building's storey drift and floor acceleration cases, or the resultant peaks of two
    components, are the in-process run's to 1e-12; the file holds the three cases of four
    motions, and the lower bound governs the isolators' displacement."""
    flags = [*extra, "--pga", "0.4g", "--property-factors", "0.8,1.25"]
    (code_here, here), (code_there, there) = _here_and_there(tmp_path, dask_cluster.scheduler_address, flags)
    capsys.readouterr()
    assert code_here == code_there == 0
    _assert_same_numbers(here, there)
    with xarray.open_dataset(tmp_path / "there.nc") as dataset:
        assert dataset.attrs["complete"] == 1 and dataset["base_disp"].shape == (3, 4)
    if "building" in extra:
        assert set(there["governs"]) >= {"storey_drift_max", "level_acceleration_max_g"}
    disp = {case: entry["mean"]["base_disp_in"] for case, entry in there["cases"].items()}
    assert disp["upper"] < disp["nominal"] < disp["lower"]
    assert there["governs"]["base_disp_in"]["by_mean"] == "lower"


@pytest.mark.slow  # two compiled runs at two levels with a vertical component
def test_vertical_component_over_levels_on_the_cluster_equals_the_in_process_run(dask_cluster, tmp_path, capsys):
    """Friction-only rigid mass at 0.3 g and 1 g with a vertical peak of 1.2 x PGA and a
    displacement limit: every level's statistics, uplifted motions and uplift times, the
    fragility counts and the exit status are the in-process run's; the file's uplift times
    are the JSON's, and more motions lift off at the higher level."""
    flags = ["--isolation-period", "none", "--isolation-damping", "0", "--pga", "0.3g,1g", "--vertical-ratio", "1.2",
             "--limit", "base_disp=2cm"]
    (code_here, here), (code_there, there) = _here_and_there(tmp_path, dask_cluster.scheduler_address, flags)
    capsys.readouterr()
    assert code_here == code_there
    _assert_same_numbers(here, there)
    with xarray.open_dataset(tmp_path / "there.nc") as dataset:
        assert dataset.attrs["complete"] == 1
        uplift, level = dataset["uplift_time"].values, dataset["intensity_level"].values
    counts = []
    for j, entry in enumerate(there["levels"]):
        rows = np.flatnonzero(level == np.unique(level)[j])
        assert entry["uplift"]["uplifted_motions"] == rows[uplift[rows] > 0].tolist()
        assert entry["uplift"]["uplift_time_s"] == pytest.approx(uplift[rows][uplift[rows] > 0].tolist(), rel=1e-12)
        counts.append(entry["uplift"]["n_uplifted"])
    assert counts[0] < counts[1] and there["vertical"]["n_uplifted"] == sum(counts)
