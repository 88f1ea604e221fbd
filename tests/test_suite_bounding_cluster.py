"""Bounding analysis of a record suite on a Dask cluster (`teflon-jax run --suite FILE
--property-factors LOWER,UPPER --scheduler ADDRESS --out FILE.nc`), on the shared LocalCluster
of 2 worker processes (tests/conftest.py).

Peer: the same command without --scheduler (the in-process suite bounding, whose own tests
check each case against a suite of bearings scaled by hand). The pairs and each case's
friction are the same and `--chunk-size` is the in-process batch, so every JSON number (each
pair's peaks, each case's mean and maximum, failed counts, the governing case) agrees to
1e-12, and a pair that cannot be balanced is left out of the statistics on both sides. The
physical ordering of the bounds is asserted too: more friction, less displacement."""

import json
import pathlib

import numpy as np
import pytest

from teflon_jax.cli import main
from teflon_jax.studies import BOUNDING_CASES, open_suite_cases

distributed = pytest.importorskip("distributed")

BENCHMARKS = pathlib.Path(__file__).resolve().parents[1] / "benchmarks"
DT, SECONDS = 0.01, 2.0
OWN = {"wall_s", "files", "netcdf", "scheduler", "command_line", "inputs"}  # run times, file names and flags differ by design


def _write_suite(tmp_path):
    """Three pairs of sin^2-enveloped sines [g] (two-column files), one CSV with a scale column."""
    t = np.arange(0.0, SECONDS + DT / 2, DT)
    envelope = np.sin(np.pi * t / SECONDS) ** 2
    rows = ["name,record_x,record_y,scale"]
    for i, (peak, frequency) in enumerate(((0.3, 0.8), (0.45, 1.1), (0.2, 0.6))):
        for axis, phase in (("x", 0.0), ("y", 0.9)):
            np.savetxt(tmp_path / f"{axis}{i}.txt",
                       np.column_stack([t, peak * envelope * np.sin(2 * np.pi * frequency * t + phase)]))
        rows.append(f"p{i},x{i}.txt,y{i}.txt,{1.0 + 0.25 * i}")
    (tmp_path / "suite.csv").write_text("\n".join(rows) + "\n")
    return tmp_path / "suite.csv"


def _here_and_there(tmp_path, address, common):
    """(exit status, JSON) of the in-process command and of the one on the cluster."""
    runs = {}
    for name, flags in (("here", []), ("there", ["--scheduler", address])):
        code = main([*common, *flags, "--json", str(tmp_path / f"{name}.json"), "--out", str(tmp_path / f"{name}.nc")])
        runs[name] = (code, json.loads((tmp_path / f"{name}.json").read_text()))
    return runs["here"], runs["there"]


def _assert_same_numbers(here, there, path="") -> None:
    """Every number of `here` equals `there`'s to 1e-12 (relative; a failed pair's NaN peaks
    NaN on both sides), every other value exactly."""
    if isinstance(here, dict):
        assert set(here) == set(there), path
        for key in here:
            _assert_same_numbers(here[key], there[key], f"{path}/{key}")
    elif isinstance(here, list):
        assert len(here) == len(there), path
        for i, (a, b) in enumerate(zip(here, there)):
            _assert_same_numbers(a, b, f"{path}[{i}]")
    elif isinstance(here, float):
        assert there == pytest.approx(here, rel=1e-12, abs=1e-300, nan_ok=True), path
    else:
        assert here == there, path


def _without(payload: dict) -> dict:
    out = {k: v for k, v in payload.items() if k not in OWN}
    out["cases"] = {c: {k: v for k, v in entry.items() if k not in OWN} for c, entry in payload["cases"].items()}
    return out


@pytest.mark.slow  # three compiled cases in this process and on each of two workers (about 2 min on two cores)
@pytest.mark.parametrize("isolator", [
    ["--isolation-period", "2.5s"],
    ["--isolator", "single-fp", "--radius", "60in", "--ptfe", "UF", "--pressure", "1000psi"],
    ["--isolator", "double-fp", "--isolator-file", str(BENCHMARKS / "double_isolator.json")],
    ["--isolator", "triple-fp", "--isolator-file", str(BENCHMARKS / "triple_isolator.json")]],
    ids=["flat", "single-fp", "double-fp", "triple-fp"])
def test_suite_bounds_on_the_cluster_equal_the_in_process_run(dask_cluster, tmp_path, isolator, capsys):
    """Rigid mass on flat sliders with a 2.5 s restoring spring, or on single, double or triple
    pendulums (every surface's friction scaled), three pairs, chunks of two: the cluster's JSON equals the
    in-process one to 1e-12, its --out file holds the three cases (those of the in-process
    --out file), and the lower bound moves most, the upper least."""
    common = ["run", "--suite", str(_write_suite(tmp_path)), "--record-units", "g", *isolator,
              "--time-step", "0.01s", "--property-factors", "0.8,1.25", "--chunk-size", "2"]
    (code_here, here), (code_there, there) = _here_and_there(tmp_path, dask_cluster.scheduler_address, common)
    capsys.readouterr()
    assert code_here == code_there == 0
    _assert_same_numbers(_without(here), _without(there))
    assert there["netcdf"] == str(tmp_path / "there.nc") and there["scheduler"] == dask_cluster.scheduler_address
    stored = {side: open_suite_cases(tmp_path / f"{side}.nc") for side in ("here", "there")}
    assert list(stored["there"]) == list(BOUNDING_CASES) == list(stored["here"])
    for case in BOUNDING_CASES:
        a, b = stored["here"][case], stored["there"][case]
        assert a.names == b.names == ("p0", "p1", "p2")
        for key, values in a.peaks.items():
            np.testing.assert_allclose(b.peaks[key], values, rtol=1e-12, atol=0)
            assert [there["cases"][case]["pairs"][n][key] for n in b.names] == pytest.approx(b.peaks[key], rel=1e-12)
        assert (tmp_path / f"there-{case}.csv").is_file()
    disp = {c: there["cases"][c]["summary"]["base_disp_resultant_m"]["mean"] for c in BOUNDING_CASES}
    assert disp["upper"] < disp["nominal"] < disp["lower"]
    assert there["governs"]["base_disp_resultant_m"]["by_mean"] == "lower"


@pytest.mark.slow  # three compiled building cases in this process and on the workers (about 2 min on two cores)
def test_building_suite_bounds_on_the_cluster_keep_the_storeys(dask_cluster, tmp_path, capsys):
    """Table 2's building on flat sliders, two pairs: the JSON (the largest storey drift of each
    pair and case among it) equals the in-process one to 1e-12, the --out file holds each case's
    peak drift per storey and acceleration per level in x and y as the in-process file does,
    and the upper bound, the stiffer in friction, pushes the base shear highest."""
    suite = _write_suite(tmp_path)
    suite.write_text("\n".join(suite.read_text().splitlines()[:3]) + "\n")  # pairs p0 and p1
    common = ["run", "--suite", str(suite), "--structure", "building", "--record-units", "g",
              "--isolation-period", "2.5s", "--time-step", "0.01s", "--property-factors", "0.8,1.25", "--chunk-size", "2"]
    (code_here, here), (code_there, there) = _here_and_there(tmp_path, dask_cluster.scheduler_address, common)
    capsys.readouterr()
    assert code_here == code_there == 0
    _assert_same_numbers(_without(here), _without(there))
    stored = {side: open_suite_cases(tmp_path / f"{side}.nc") for side in ("here", "there")}
    for case in BOUNDING_CASES:
        a, b = stored["here"][case].storeys, stored["there"][case].storeys
        assert b["storey_drift"].shape == (2, 2, 6) and b["level_acceleration"].shape == (2, 2, 7)
        for key in a:
            np.testing.assert_allclose(b[key], a[key], rtol=1e-12, atol=0)
        # max_t |(d_x, d_y)| lies between the larger of max_t |d_x|, max_t |d_y| and their hypotenuse
        drift = np.array([there["cases"][case]["pairs"][n]["storey_drift_max_resultant"] for n in ("p0", "p1")])
        assert np.all(np.max(b["storey_drift"], axis=(1, 2)) <= drift * (1 + 1e-12))
        assert np.all(drift <= np.max(np.hypot(b["storey_drift"][:, 0], b["storey_drift"][:, 1]), axis=-1) * (1 + 1e-12))
    assert there["governs"]["base_shear_ratio_resultant"]["by_mean"] == "upper"
    assert there["governs"]["base_disp_resultant_m"]["by_mean"] == "lower"


@pytest.mark.slow  # three compiled slab cases in this process and on each of two workers
def test_a_pair_that_tips_the_slab_stays_out_of_the_cluster_bounds_as_in_process(dask_cluster, tmp_path, capsys):
    """Slab on single pendulums with its centre of mass 30 m up: the strong pair tips it (its
    steps cannot be balanced) in some case. Both commands exit 1 and name the pair, the same
    pairs fail in each case, the failed counts and the statistics (the calm pair's alone where
    the strong one failed) agree to 1e-12, group loads included."""
    from test_slab_suite import ISOLATORS, _plan, _write_pairs

    common = ["run", "--structure", "slab", "--plan", str(_plan(tmp_path, "30m")), "--record-units", "g",
              "--time-step", "0.01s", *ISOLATORS["single-fp"], "--suite", str(_write_pairs(tmp_path)),
              "--property-factors", "0.8,1.25", "--chunk-size", "1"]
    (code_here, here), (code_there, there) = _here_and_there(tmp_path, dask_cluster.scheduler_address, common)
    err = capsys.readouterr().err
    assert code_here == code_there == 1
    assert err.count("left out of the statistics") == 2 and "strong_x" in err
    _assert_same_numbers(_without(here), _without(there))
    stored = open_suite_cases(tmp_path / "there.nc")
    failed = 0
    for case in BOUNDING_CASES:
        ok = stored[case].converged
        assert there["cases"][case]["failed"] == int((~ok).sum())
        failed += int((~ok).sum())
        calm = there["cases"][case]["pairs"]["calm_x"]["base_disp_resultant_m"]
        if not ok[1]:  # the strong pair failed: the calm one is the whole statistic
            assert there["cases"][case]["summary"]["base_disp_resultant_m"] == {"mean": calm, "min": calm, "max": calm}
        assert "normal_load" in there["cases"][case]["pairs"]["calm_x"]
    assert failed > 0 and stored["nominal"].converged[0]


def test_suite_bounds_on_a_cluster_need_an_output_file(tmp_path, capsys):
    """--scheduler without --out is asked for --out before any record is read (the records named
    in the suite file do not exist); the refusal of --scheduler with --property-factors is gone."""
    suite = tmp_path / "suite.csv"
    suite.write_text("record_x,record_y,scale\nmissing_x.txt,missing_y.txt,1\n")
    code = main(["run", "--suite", str(suite), "--record-units", "g", "--property-factors", "0.85,1.3",
                 "--scheduler", "local:2"])
    assert code == 2
    err = capsys.readouterr().err
    assert "add --out FILE.nc" in err and "missing" not in err and "leave out --scheduler" not in err
