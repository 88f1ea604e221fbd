"""`run --suite` on a slab whose plan has overturning (height_of_centre_of_mass > 0): each pair
of the vmapped suite is the single-pair `run` of that pair (peaks and each group's normal load
N_g = W_g + dN_g, the lever rule of a rigid slab on vertical supports), uplifted pairs kept."""

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
def test_suite_without_height_reports_no_group_loads(tmp_path):
    """Height 0: the suite's output keeps its columns and keys (no group loads)."""
    suite = _write_pairs(tmp_path)
    result, out = _run(tmp_path, "single-fp", "0m", "--suite", suite)
    assert "normal_load" not in result["pairs"]["strong_x"] and "normal_load_note" not in result
    assert set(result["pairs"]["strong_x"]) == {*PEAKS, "converged"}
    header = out.with_suffix(".csv").read_text().splitlines()[0]
    assert header == "pair," + ",".join(PEAKS) + ",converged"


def test_overturning_suite_refuses_scheduler_and_bounding_by_name(tmp_path, capsys):
    suite = _write_pairs(tmp_path)
    for flags, name in ((["--scheduler", "local:1", "--out", str(tmp_path / "s.nc")], "--scheduler"),
                        (["--property-factors", "0.85,1.3"], "--property-factors")):
        code = main(["run", "--structure", "slab", "--plan", str(_plan(tmp_path, "30m")), "--suite", str(suite),
                     "--record-units", "g", *ISOLATORS["single-fp"], *flags])
        assert code == 2
        assert f"{name}: a suite of the plan's overturning slab" in capsys.readouterr().err
