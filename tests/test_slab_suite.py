"""`run --suite` on a slab whose plan has overturning (height_of_centre_of_mass > 0): each pair
of the vmapped suite is the single-pair `run` of that pair (peaks and each group's normal load
N_g = W_g + dN_g, the lever rule of a rigid slab on vertical supports), uplifted pairs kept;
its bounding cases are the suites of bearings whose friction was scaled by hand (the upper
bound's base shear the larger on pendulums of long radius), and the suite on a Dask cluster
holds the in-process suite's numbers, group loads included."""

import csv
import json

import numpy as np
import pytest

from teflon_jax.cli import main
from teflon_jax.units import STANDARD_GRAVITY

G = STANDARD_GRAVITY
DT, DURATION = 0.01, 2.0
TIME = np.arange(0.0, DURATION + DT / 2, DT)
CORNERS = ((2.0, 1.0), (18.0, 1.0), (18.0, 11.0), (2.0, 11.0))  # SW, SE, NE, NW
NAMES = ("SW", "SE", "NE", "NW")
STATIC = 250e3  # W / 4 [N]
PEAKS = ("base_disp_resultant_m", "base_disp_x_m", "base_disp_y_m", "base_shear_ratio_resultant")
PAIRS = (("calm", 0.15, 0.05, 0.9), ("strong", 0.4, 0.2, 0.6))  # name, peak x, peak y [g], frequency [Hz]


def _write_pairs(tmp_path):
    """Two-component sine pulses (sin^2 envelope) as two-column files [s, g]; the suite CSV."""
    rows = ["record_x,record_y,scale"]
    for name, px, py, f in PAIRS:
        shape = np.sin(np.pi * TIME / DURATION) ** 2
        for axis, peak, phase in (("x", px, 0.0), ("y", py, 0.7)):
            np.savetxt(tmp_path / f"{name}_{axis}.txt",
                       np.column_stack([TIME, peak * np.sin(2 * np.pi * f * TIME + phase) * shape]))
        rows.append(f"{name}_x.txt,{name}_y.txt,1")
    (tmp_path / "suite.csv").write_text("\n".join(rows) + "\n")
    return tmp_path / "suite.csv"


def _plan(tmp_path, height):
    groups = [{"name": n, "x": f"{x}m", "y": f"{y}m", "load": "250kN"} for n, (x, y) in zip(NAMES, CORNERS)]
    path = tmp_path / f"plan_{height}.json"
    path.write_text(json.dumps({"length_x": "20m", "length_y": "12m", "weight": "1000kN",
                                "height_of_centre_of_mass": height, "groups": groups}))
    return path


ISOLATORS = {"single-fp": ["--isolator", "single-fp", "--radius", "2m"],
             "flat": ["--isolator", "flat", "--isolation-period", "3s"]}


def _run(tmp_path, isolator, height, *flags):
    out = tmp_path / f"out_{len(list(tmp_path.glob('out_*')))}.json"
    code = main(["run", "--structure", "slab", "--plan", str(_plan(tmp_path, height)), "--record-units", "g",
                 "--time-step", "0.01s", "--json", str(out), *ISOLATORS[isolator], *map(str, flags)])
    assert code == 0
    return json.loads(out.read_text()), out


@pytest.mark.parametrize(("isolator", "checked"), [
    ("single-fp", ("strong",)),
    pytest.param("flat", ("calm",), marks=pytest.mark.slow),
    pytest.param("single-fp", ("calm", "strong"), marks=pytest.mark.slow),
    pytest.param("flat", ("calm", "strong"), marks=pytest.mark.slow)])
def test_each_suite_pair_is_its_single_run_with_overturning(tmp_path, isolator, checked):
    """Pairs `checked` of the suite against their single runs (the fast cases one pair each)."""
    suite = _write_pairs(tmp_path)
    result, out = _run(tmp_path, isolator, "20m", "--suite", suite)
    assert result["failed"] == 0 and set(result["pairs"]) == {"calm_x", "strong_x"}
    for name in checked:
        single, _ = _run(tmp_path, isolator, "20m", "--record-x", tmp_path / f"{name}_x.txt",
                         "--record-y", tmp_path / f"{name}_y.txt")
        pair = result["pairs"][f"{name}_x"]
        for key in PEAKS:
            assert pair[key] == pytest.approx(single["peak"][key], rel=1e-9, abs=1e-12), key
        assert pair["normal_load"]["groups"].keys() == single["normal_load"]["groups"].keys()
        for group, loads in single["normal_load"]["groups"].items():
            got = pair["normal_load"]["groups"][group]
            assert got["radius_m"] == loads.pop("radius_m")  # None: flat sliders
            assert {k: got[k] for k in loads} == pytest.approx(loads, rel=1e-9, abs=1e-6), group
    # the overturning is in the suite: each group's load swings about W / 4 (without it N_g = W / 4)
    calm = result["pairs"]["calm_x"]["normal_load"]["groups"]
    for group in calm.values():
        assert group["peak_N"] > 1.1 * STATIC and group["min_N"] < 0.9 * STATIC
    # the strong pair uplifts a group for a while (the slab resting on the other three; 30 m would
    # tip it, a step reported unbalanced): kept, finite, in the statistics
    strong = result["pairs"]["strong_x"]
    assert max(g["uplift_time_s"] for g in strong["normal_load"]["groups"].values()) > 0
    assert all(np.isfinite(v) for g in strong["normal_load"]["groups"].values() for v in g.values() if v is not None)
    assert result["summary"]["base_disp_resultant_m"]["max"] == pytest.approx(
        max(p["base_disp_resultant_m"] for p in result["pairs"].values()))
    with out.with_suffix(".csv").open() as handle:
        rows = list(csv.DictReader(handle))
    assert float(rows[1]["SW_peak_N"]) == pytest.approx(strong["normal_load"]["groups"]["SW"]["peak_N"], rel=1e-5)


@pytest.mark.slow
def test_a_pair_whose_slab_tips_is_named_and_left_out_of_the_summary(tmp_path, capsys):
    """Height 30 m: the strong pair tips the slab (h |H| beyond the weight's hold about the
    leaning pair), so its steps are reported unbalanced: the suite exits 1, names the pair on
    stderr as one that tipped the slab, marks it converged: false and tipped: true and keeps it
    out of the summary (the calm pair's alone)."""
    suite = _write_pairs(tmp_path)
    out = tmp_path / "tips.json"
    code = main(["run", "--structure", "slab", "--plan", str(_plan(tmp_path, "30m")), "--record-units", "g",
                 "--time-step", "0.01s", "--json", str(out), *ISOLATORS["single-fp"], "--suite", str(suite)])
    assert code == 1
    err = capsys.readouterr().err
    assert "1 of 2 pairs tipped the slab" in err and "(strong_x)" in err and "could not be balanced" not in err
    result = json.loads(out.read_text())
    assert result["failed"] == 1
    assert result["pairs"]["strong_x"]["converged"] is False and result["pairs"]["calm_x"]["converged"] is True
    assert result["pairs"]["strong_x"]["tipped"] is True and result["pairs"]["calm_x"]["tipped"] is False
    calm = result["pairs"]["calm_x"]["base_disp_resultant_m"]
    assert result["summary"]["base_disp_resultant_m"] == {"mean": calm, "min": calm, "max": calm}


@pytest.mark.slow
def test_suite_without_height_reports_no_group_loads(tmp_path):
    """Height 0: the suite's output keeps its columns and keys (no group loads)."""
    suite = _write_pairs(tmp_path)
    result, out = _run(tmp_path, "single-fp", "0m", "--suite", suite)
    assert "normal_load" not in result["pairs"]["strong_x"] and "normal_load_note" not in result
    assert set(result["pairs"]["strong_x"]) == {*PEAKS, "converged"}
    header = out.with_suffix(".csv").read_text().splitlines()[0]
    assert header == "pair," + ",".join(PEAKS) + ",converged"


def _by_hand(tmp_path, factor, radius):
    """The suite's slab (`_plan(tmp_path, "6m")`, single pendulums of `radius` [m], UF PTFE at
    1000 psi) built here with f_max and delta_f of Eq. 1 multiplied by `factor` by hand, run
    through `suite_peaks` in one call: (pair names, `SuiteResult`)."""
    import equinox as eqx

    from teflon_jax.bearing import FrictionParameters, paper_bearing
    from teflon_jax.excitation import uniform_signal
    from teflon_jax.studies import suite_peaks
    from teflon_jax.systems import slab_on_bearings
    from teflon_jax.tables import interface_parameters
    from teflon_jax.units import PSI

    nominal, _ = interface_parameters("UF", 1000 * PSI, "P")
    scaled = FrictionParameters(f_max=nominal.f_max * factor, delta_f=nominal.delta_f * factor, rate_a=nominal.rate_a)
    records = [[np.loadtxt(tmp_path / f"{name}_{axis}.txt")[:, 1] * G for axis in "xy"] for name, *_ in PAIRS]
    ax, ay = (np.stack([r[i] for r in records]) for i in (0, 1))
    template = slab_on_bearings(
        length_x=20.0, length_y=12.0, weight=1e6, centre_of_mass=(10.0, 6.0), positions=CORNERS,
        bearings=[paper_bearing(scaled)] * 4, loads=[STATIC] * 4, ground_acceleration=uniform_signal(ax[0], DT),
        ground_y=uniform_signal(ay[0], DT), time_step=DT, names=NAMES, contact_pressures=[1000 * PSI] * 4,
        height_of_centre_of_mass=6.0, isolator="single-fp", radii=[radius] * 4)
    build = lambda gx, gy: eqx.tree_at(lambda s: (s.ground_acceleration, s.ground_y), template, (gx, gy))  # noqa: E731
    return suite_peaks(build, [f"{name}_x" for name, *_ in PAIRS], ax, ay, DT, DURATION, group_names=NAMES)


@pytest.mark.slow  # three bounding cases and a suite by hand: four compilations (about 60 s on two cores)
def test_overturning_suite_bounds_are_the_suites_of_scaled_bearings(tmp_path):
    """`--property-factors 0.8,1.25` on a slab with overturning: the upper and lower cases are
    the suites of bearings whose Eq. 1 friction was scaled by hand (peaks and each group's
    loads, to 1e-9), each case keeps its group loads in the JSON, CSV and NetCDF; on pendulums
    of 50 m radius (W / R = 0.02 W per metre) the peak force is the friction's, so the upper
    bound's base shear exceeds the lower's by about the ratio of the factors (1.56)."""
    from teflon_jax.studies import open_suite

    suite = _write_pairs(tmp_path)
    out = tmp_path / "bounds.json"
    assert main(["run", "--structure", "slab", "--plan", str(_plan(tmp_path, "6m")), "--record-units", "g",
                 "--time-step", "0.01s", "--json", str(out), "--isolator", "single-fp", "--radius", "50m",
                 "--ptfe", "UF", "--pressure", "1000psi", "--suite", str(suite),
                 "--property-factors", "0.8,1.25"]) == 0
    result = json.loads(out.read_text())
    assert "normal_load_note" in result
    for case, factor in (("upper", 1.25), ("lower", 0.8)):
        hand = _by_hand(tmp_path, factor, 50.0)
        stored = open_suite(tmp_path / f"bounds-{case}.nc")
        for i, name in enumerate(hand.names):
            pair = result["cases"][case]["pairs"][name]
            for key in PEAKS:
                assert pair[key] == pytest.approx(hand.peaks[key][i], rel=1e-9), (case, key)
            for j, group in enumerate(NAMES):
                got = pair["normal_load"]["groups"][group]
                for key in ("peak_N", "min_N", "uplift_time_s"):
                    assert got[key] == pytest.approx(hand.groups[key][i, j], rel=1e-9, abs=1e-6), (case, group)
                    assert stored.groups[key][i, j] == pytest.approx(got[key], rel=1e-12, abs=1e-9)
        header = (tmp_path / f"bounds-{case}.csv").read_text().splitlines()[0]
        assert "SW_peak_N" in header and "NW_uplift_time_s" in header
    shear = {case: result["cases"][case]["pairs"]["strong_x"]["base_shear_ratio_resultant"]
             for case in ("lower", "nominal", "upper")}
    assert shear["lower"] < shear["nominal"] < shear["upper"]
    assert 1.3 < shear["upper"] / shear["lower"] < 1.7
    # the overturning moment grows with the base shear: the leaning group's peak load too
    peak = {case: max(g["peak_N"] for g in result["cases"][case]["pairs"]["strong_x"]["normal_load"]["groups"].values())
            for case in ("lower", "upper")}
    assert peak["upper"] > peak["lower"] > STATIC


@pytest.mark.slow  # a LocalCluster of two workers and two compilations (about 60 s on two cores)
def test_overturning_suite_on_a_cluster_equals_the_in_process_suite(dask_cluster, tmp_path):
    """`--scheduler ADDRESS --chunk-size 1` (the shared LocalCluster of two worker processes):
    every pair's peaks and each group's loads equal those of the in-process suite of the same
    chunk size number for number (NetCDF, CSV, JSON)."""
    from teflon_jax.studies import open_suite

    suite = _write_pairs(tmp_path)
    common = ["run", "--structure", "slab", "--plan", str(_plan(tmp_path, "20m")), "--record-units", "g",
              "--time-step", "0.01s", *ISOLATORS["single-fp"], "--suite", str(suite), "--chunk-size", "1"]
    assert main([*common, "--json", str(tmp_path / "here.json")]) == 0
    assert main([*common, "--json", str(tmp_path / "there.json"), "--scheduler", dask_cluster.scheduler_address,
                 "--out", str(tmp_path / "there.nc")]) == 0
    here, there = open_suite(tmp_path / "here.nc"), open_suite(tmp_path / "there.nc")
    assert there.names == here.names and there.groups["names"] == here.groups["names"] == NAMES
    for key in PEAKS:
        np.testing.assert_array_equal(there.peaks[key], here.peaks[key])
    for key in ("peak_N", "min_N", "uplift_time_s"):
        np.testing.assert_array_equal(there.groups[key], here.groups[key])
    assert max(here.groups["uplift_time_s"][1]) > 0  # the strong pair lifts a group
    assert (tmp_path / "here.csv").read_text() == (tmp_path / "there.csv").read_text()
    a, b = (json.loads((tmp_path / f"{n}.json").read_text()) for n in ("here", "there"))
    assert a["pairs"] == b["pairs"]


def test_overturning_suite_bounds_read_the_bearing_file_first(tmp_path, capsys):
    """--property-factors scales a --bearing file's friction too: the file is read, and a
    missing one refused by name, before any record is read (the records named do not exist)."""
    suite = tmp_path / "suite.csv"
    suite.write_text("record_x,record_y,scale\nmissing_x.txt,missing_y.txt,1\n")
    code = main(["run", "--structure", "slab", "--plan", str(_plan(tmp_path, "30m")), "--suite", str(suite),
                 "--record-units", "g", "--bearing", str(tmp_path / "missing_bearing.json"),
                 "--property-factors", "0.85,1.3"])
    assert code == 2
    err = capsys.readouterr().err
    assert "--bearing " in err and "missing_bearing.json: no such bearing file" in err and "missing_x" not in err
