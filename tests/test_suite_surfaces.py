"""A record suite keeps the peaks of the isolator's surfaces where it has them: each slider's
travel of a series pendulum and each heated surface's temperature rise, per pair, in the
suite's result, table, NetCDF file and JSON, in the bounding cases too.

Peers: each pair's own history (`simulate_history`), the in-process suite for the distributed
one, and the physical order of the bounding cases (the lower-bound friction slides farthest)."""

import csv
import json

import jax
import numpy as np
import pytest
from test_montecarlo_surfaces import _heated_file, _slab
from test_series_suite import _write_pairs

from teflon_jax.bearing import (
    DoublePendulum,
    FrictionalHeating,
    coulomb_friction,
    paper_bearing,
)
from teflon_jax.cli import main
from teflon_jax.excitation import uniform_signal
from teflon_jax.studies import (
    bidirectional_isolated_structure,
    open_suite,
    save_suite,
    suite_cases_distributed,
    suite_peaks,
    suite_peaks_distributed,
)
from teflon_jax.systems import simulate_history, slider_travel, under_ground
from teflon_jax.units import STANDARD_GRAVITY

DT, SECONDS = 0.01, 4.0
HEAT = FrictionalHeating(contact_area=0.05)


def _double():
    """A double pendulum heated on its bottom surface (R 1.5 m, mu 0.06); its top (R 2 m,
    mu 0.08) is not heated."""
    return DoublePendulum(bottom_radius=1.5, top_radius=2.0, bottom_capacity=1.0, top_capacity=1.0,
                          bottom_friction=coulomb_friction(0.06), top_friction=coulomb_friction(0.08),
                          hysteresis=paper_bearing(coulomb_friction(0.06)).hysteresis, bottom_heating=HEAT,
                          bottom_pressure=30e6)


STRUCTURE = bidirectional_isolated_structure("rigid", isolator=_double(), time_step=0.005)


def build(gx, gy):
    return STRUCTURE((gx, gy))


def _pairs(count=2, seed=4, scale=1.0):
    t = DT * np.arange(int(SECONDS / DT) + 1)
    rng = np.random.default_rng(seed)
    envelope = np.sin(np.pi * t / t[-1]) ** 2
    ax = np.stack([0.4 * scale * STANDARD_GRAVITY * envelope * np.sin(2 * np.pi * 0.6 * t + rng.uniform(0, 6))
                   for _ in range(count)])
    ay = np.stack([0.3 * scale * STANDARD_GRAVITY * envelope * rng.normal(size=t.size) for _ in range(count)])
    return [f"p{i}" for i in range(count)], ax, ay


def test_each_pair_keeps_its_sliders_and_heated_surface(tmp_path):
    names, ax, ay = _pairs()
    result = suite_peaks(build, names, ax, ay, DT, SECONDS)
    assert result.converged.all()
    surfaces = result.surfaces
    assert surfaces["slider_names"] == ("bottom", "top") and surfaces["heated_surface_names"] == ("bottom",)
    assert surfaces["slider_travel"].shape == (2, 1, 2) and surfaces["surface_temperature_rise"].shape == (2, 1, 1)
    for i in range(2):
        response = simulate_history(build(uniform_signal(ax[i], DT), uniform_signal(ay[i], DT)), SECONDS)
        np.testing.assert_allclose(surfaces["slider_travel"][i, 0],
                                   np.max(np.asarray(slider_travel(response)), axis=0), rtol=1e-9)
        rise = np.max(np.asarray(response.surface_temperature_rise), axis=0)[0]
        np.testing.assert_allclose(surfaces["surface_temperature_rise"][i, 0], rise[:1], rtol=1e-9)
        assert rise[1] == 0.0 and rise[0] > 1.0  # the top is not heated, the bottom warms
    travel = surfaces["slider_travel"][:, 0, 0]
    assert result.summary["slider_travel_m_bottom"]["max"] == pytest.approx(travel.max(), rel=1e-12)
    assert result.summary["slider_travel_m_bottom"]["mean"] == pytest.approx(travel.mean(), rel=1e-12)

    save_suite(result, table_path=tmp_path / "s.csv", netcdf_path=tmp_path / "s.nc")
    with open(tmp_path / "s.csv") as handle:
        rows = list(csv.DictReader(handle))
    assert [float(r["surface_temperature_rise_K_bottom"]) for r in rows[:2]] == pytest.approx(
        surfaces["surface_temperature_rise"][:, 0, 0], rel=1e-5)
    assert [r["pair"] for r in rows[2:]] == ["mean", "min", "max"]
    assert float(rows[3]["slider_travel_m_top"]) == pytest.approx(surfaces["slider_travel"][:, 0, 1].min(), rel=1e-5)
    assert float(rows[4]["slider_travel_m_top"]) == pytest.approx(surfaces["slider_travel"][:, 0, 1].max(), rel=1e-5)
    assert rows[4]["converged"] == ""  # the summary rows leave the pair-only columns empty
    back = open_suite(tmp_path / "s.nc")
    np.testing.assert_array_equal(back.surfaces["slider_travel"], surfaces["slider_travel"])
    assert back.surfaces["heated_surface_names"] == ("bottom",) and back.groups is None
    assert back.summary == result.summary


@pytest.mark.slow
def test_distributed_suites_write_the_same_surfaces(dask_cluster, tmp_path):
    names, ax, ay = _pairs(count=3)
    local = suite_peaks(build, names, ax, ay, DT, SECONDS, batch_size=2)
    spread = suite_peaks_distributed(build, names, ax, ay, DT, SECONDS, out=tmp_path / "s.nc",
                                     scheduler=dask_cluster.scheduler_address, chunk_size=2)
    cases = suite_cases_distributed({"one": build, "two": build}, names, ax, ay, DT, SECONDS,
                                    out=tmp_path / "cases.nc", scheduler=dask_cluster.scheduler_address, chunk_size=2)
    for result in (spread, *cases.values()):
        for name in ("slider_travel", "surface_temperature_rise"):
            np.testing.assert_array_equal(result.surfaces[name], local.surfaces[name])
        assert result.surfaces["slider_names"] == ("bottom", "top")
        assert result.summary == local.summary


@pytest.mark.slow  # three compilations of the double pendulum's suite
def test_run_suite_bounding_reports_the_surfaces(tmp_path, capsys):
    """`run --suite --property-factors`: every case's pairs carry each slider's travel, whose sum
    bounds the base's displacement, and the heated surface's rise, highest under the upper-bound
    friction (the heat flux is mu p |v|)."""
    _, ax, ay = _pairs(scale=0.5)  # the sliders short of their 12 in restrainers
    suite = _write_pairs(tmp_path, list(zip(ax, ay)))
    code = main(["run", "--suite", str(suite), "--record-units", "g", "--isolator", "double-fp",
                 "--isolator-file", str(_heated_file(tmp_path / "dfp.json")), "--property-factors", "0.8,1.25",
                 "--json", str(tmp_path / "b.json")])
    assert code == 0, capsys.readouterr().err
    payload = json.loads((tmp_path / "b.json").read_text())
    rise = "surface_temperature_rise_K_bottom"
    means = {case: payload["cases"][case]["summary"][rise]["mean"] for case in payload["cases"]}
    assert means["lower"] < means["nominal"] < means["upper"]  # the heat flux is mu p |v|
    assert payload["governs"][rise]["by_mean"] == "upper"
    for case in payload["cases"].values():
        for pair in case["pairs"].values():  # |u| = |s_bottom + s_top| <= |s_bottom| + |s_top| at every step
            assert pair["base_disp_resultant_m"] <= pair["slider_travel_m_bottom"] + pair["slider_travel_m_top"]
            assert pair["base_disp_resultant_m"] > 0.5 * (pair["slider_travel_m_bottom"] + pair["slider_travel_m_top"])
            assert max(pair["slider_travel_m_bottom"], pair["slider_travel_m_top"]) < 12 * 0.0254
    assert "surface_temperature_rise_K_bottom" in capsys.readouterr().out
    jax.clear_caches()


@pytest.mark.slow  # the slab's suite compiles in about 20 s
def test_a_plans_names_label_the_surfaces_of_a_slab_without_overturning():
    """A slab at no height on four groups of heated single pendulums: the groups report no loads
    of their own, yet each group's surfaces are kept under the plan's names, each that of the
    pair's own history; names of another number of groups are refused by name."""
    slab = _slab()
    names, ax, ay = _pairs()

    def on_slab(gx, gy):
        return under_ground(slab, gx, gy)

    result = suite_peaks(on_slab, names, ax, ay, DT, SECONDS, group_names=["SW", "SE", "NE", "NW"])
    assert result.converged.all() and result.groups is None
    assert result.surfaces["group_names"] == ("SW", "SE", "NE", "NW")
    response = simulate_history(on_slab(uniform_signal(ax[1], DT), uniform_signal(ay[1], DT)), SECONDS)
    np.testing.assert_allclose(result.surfaces["surface_temperature_rise"][1],
                               np.max(np.asarray(response.surface_temperature_rise), axis=0), rtol=1e-9)
    assert "surface_temperature_rise_K_NE_surface" in result.summary
    with pytest.raises(ValueError, match="group_names: 2 names for the structure's 4 bearing groups"):
        suite_peaks(on_slab, names, ax, ay, DT, SECONDS, group_names=["A", "B"])
