"""`run --suite --structure slab --isolator triple-fp|double-fp`: record pairs through the rigid
slab on groups of series pendulums (a group may name its own isolator file) in one vmapped call.

Peers: the single `run` of each pair (the slab's peaks and each group's normal load N_g under
the overturning moment, to 1e-9), and, for the bounding cases of `--property-factors`, the
suite of isolator files whose surfaces' friction was scaled by hand; the physical order of the
cases (more friction, less displacement)."""

import csv
import json

import equinox as eqx
import pytest
from test_slab_series import DOUBLE
from test_slab_suite import CORNERS, NAMES, PEAKS, STATIC, _write_pairs

from teflon_jax.bearing import FrictionParameters
from teflon_jax.cli import main
from teflon_jax.formats import write_isolator

GROUP_KEYS = ("static_N", "peak_N", "min_N", "uplift_time_s")


def _scaled(pendulum, factor):
    """`pendulum` with f_max and delta_f of both surfaces times `factor`, written out by hand."""
    return eqx.tree_at(lambda p: (p.bottom_friction, p.top_friction), pendulum, tuple(
        FrictionParameters(f.f_max * factor, f.delta_f * factor, f.rate_a)
        for f in (pendulum.bottom_friction, pendulum.top_friction)))


def _files(tmp_path, height, factor=1.0):
    """(plan, default isolator file) of a 20 m x 12 m slab on four double-pendulum groups, the
    SE group on its own slipperier file; friction of both files times `factor`."""
    folder = tmp_path / f"isolators_{factor:g}"
    folder.mkdir(exist_ok=True)
    slippery = eqx.tree_at(lambda p: (p.bottom_friction, p.top_friction), DOUBLE,
                           (FrictionParameters(0.04, 0.02, 20.0), FrictionParameters(0.06, 0.03, 20.0)))
    write_isolator(folder / "double.json", _scaled(DOUBLE, factor))
    write_isolator(folder / "slippery.json", _scaled(slippery, factor))
    groups = [{"name": n, "x": f"{x}m", "y": f"{y}m", "load": "250kN"} for n, (x, y) in zip(NAMES, CORNERS)]
    groups[1]["isolator_file"] = f"{folder.name}/slippery.json"
    plan = tmp_path / f"plan_{height}_{factor:g}.json"
    plan.write_text(json.dumps({"length_x": "20m", "length_y": "12m", "weight": "1000kN",
                                "height_of_centre_of_mass": height, "groups": groups}))
    return plan, folder / "double.json"


def _run(tmp_path, plan, isolator_file, name, *flags):
    out = tmp_path / f"{name}.json"
    assert main(["run", "--structure", "slab", "--plan", str(plan), "--record-units", "g", "--time-step", "0.01s",
                 "--isolator", "double-fp", "--isolator-file", str(isolator_file), "--json", str(out),
                 *map(str, flags)]) == 0
    return json.loads(out.read_text())


@pytest.mark.slow  # a vmapped and a single compilation of the series slab (about 60 s on two cores)
def test_each_series_slab_suite_pair_is_its_single_run(tmp_path):
    """Height 2 m (the strong pair lifts a group, the slab still rests): each pair's peaks and
    each group's normal load (with its isolator file) are those of its own `run`; the
    overturning moves load between the sides."""
    suite = _write_pairs(tmp_path)
    plan, default = _files(tmp_path, "2m")
    result = _run(tmp_path, plan, default, "results", "--suite", suite)  # the tables beside: results.*
    assert result["failed"] == 0 and "normal_load_note" in result
    for name in ("calm", "strong"):
        single = _run(tmp_path, plan, default, name, "--record-x", tmp_path / f"{name}_x.txt",
                      "--record-y", tmp_path / f"{name}_y.txt")
        pair = result["pairs"][f"{name}_x"]
        for key in PEAKS:
            assert pair[key] == pytest.approx(single["peak"][key], rel=1e-9, abs=1e-12), (name, key)
        for group, loads in single["normal_load"]["groups"].items():
            got = pair["normal_load"]["groups"][group]
            assert got["radius_m"] is None and got["isolator_file"] == loads["isolator_file"]
            assert {k: got[k] for k in GROUP_KEYS} == pytest.approx({k: loads[k] for k in GROUP_KEYS},
                                                                     rel=1e-9, abs=1e-6), (name, group)
    groups = result["pairs"]["strong_x"]["normal_load"]["groups"]
    assert groups["SE"]["isolator_file"].endswith("slippery.json")
    assert max(g["peak_N"] for g in groups.values()) > 1.5 * STATIC  # the leaning side takes load
    assert min(g["min_N"] for g in groups.values()) == 0.0 and max(g["uplift_time_s"] for g in groups.values()) > 0
    with (tmp_path / "results.csv").open() as handle:
        rows = list(csv.DictReader(handle))
    assert float(rows[1]["NE_min_N"]) == pytest.approx(groups["NE"]["min_N"], rel=1e-5)


@pytest.mark.slow  # as above, without overturning
def test_series_slab_suite_without_height_is_its_single_run_without_group_loads(tmp_path):
    suite = _write_pairs(tmp_path)
    plan, default = _files(tmp_path, "0m")
    result = _run(tmp_path, plan, default, "results", "--suite", suite)
    single = _run(tmp_path, plan, default, "strong", "--record-x", tmp_path / "strong_x.txt",
                  "--record-y", tmp_path / "strong_y.txt")
    pair = result["pairs"]["strong_x"]
    sliders = [f"slider_travel_m_{group}_{slider}" for group in NAMES for slider in ("bottom", "top")]
    assert set(pair) == {*PEAKS, *sliders, "converged"} and "normal_load_note" not in result
    for key in PEAKS:
        assert pair[key] == pytest.approx(single["peak"][key], rel=1e-9, abs=1e-12), key
    for group in NAMES:  # each group's sliders under the plan's names, as the single run gives them
        for slider in ("bottom", "top"):
            assert pair[f"slider_travel_m_{group}_{slider}"] == pytest.approx(
                single["slider_disp_m"][group][slider], rel=1e-9, abs=1e-12), (group, slider)
    header = (tmp_path / "results.csv").read_text().splitlines()[0]
    assert header == "pair," + ",".join([*PEAKS, *sliders]) + ",converged"


@pytest.mark.slow  # three bounding cases and the suite of the scaled files (about 90 s on two cores)
def test_series_slab_suite_bounds_are_the_suites_of_scaled_isolator_files(tmp_path):
    """`--property-factors 0.8,1.25`: the upper case (peaks and group loads) is the nominal suite
    of isolator files whose every surface's f_max and delta_f were multiplied by 1.25 by hand
    (each group's file, to 1e-9); more friction, less displacement."""
    suite = _write_pairs(tmp_path)
    plan, default = _files(tmp_path, "2m")
    bounds = _run(tmp_path, plan, default, "bounds", "--suite", suite, "--property-factors", "0.8,1.25")
    upper_plan, upper_default = _files(tmp_path, "2m", factor=1.25)
    by_hand = _run(tmp_path, upper_plan, upper_default, "hand", "--suite", suite)
    for name, pair in by_hand["pairs"].items():
        got = bounds["cases"]["upper"]["pairs"][name]
        for key in PEAKS:
            assert got[key] == pytest.approx(pair[key], rel=1e-9, abs=1e-12), (name, key)
        for group, loads in pair["normal_load"]["groups"].items():
            for key in ("peak_N", "min_N", "uplift_time_s"):
                assert got["normal_load"]["groups"][group][key] == pytest.approx(loads[key], rel=1e-9, abs=1e-6)
    disp = {c: bounds["cases"][c]["summary"]["base_disp_resultant_m"]["mean"] for c in ("lower", "nominal", "upper")}
    assert disp["upper"] < disp["nominal"] < disp["lower"]
