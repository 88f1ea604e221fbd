"""A Monte Carlo keeps the peaks of the isolator's surfaces where it has them: each slider's
travel of a series pendulum (`slider_travel` [m], (N, G, S)) and each heated surface's
temperature rise (`surface_temperature_rise` [K], (N, G, H), the unheated surfaces left out).

Peers: each motion's own history (`simulate_history`: max over time of the slider's travel and
of the surface's rise), for a double pendulum heated on its bottom surface under one and two
components and for a slab on four groups of heated single pendulums; the results file (NetCDF,
CSV) reads back the same numbers under the surfaces' and groups' names; a distributed run
writes the same variables as the in-process one."""

import csv
import dataclasses
import json

import equinox as eqx
import jax
import numpy as np
import pytest

from teflon_jax.bearing import (
    DoublePendulum,
    FrictionalHeating,
    coulomb_friction,
    paper_bearing,
)
from teflon_jax.cli import main
from teflon_jax.excitation import (
    StochasticGroundMotion,
    TwoComponentGroundMotion,
    uniform_signal,
)
from teflon_jax.studies import (
    BuiltStructure,
    MonteCarloResult,
    bidirectional_isolated_structure,
    monte_carlo,
    monte_carlo_distributed,
    monte_carlo_motion,
)
from teflon_jax.systems import (
    isolated_structure,
    simulate_history,
    slab_on_bearings,
    slider_travel,
    under_ground,
)
from teflon_jax.units import INCH

DT, DURATION, N = 0.01, 3.0, 3
MODEL = StochasticGroundMotion(peak_ground_acceleration=4.0, duration=DURATION, time_step=DT, rise_time=0.5,
                               strong_motion_duration=1.5)
TWO = TwoComponentGroundMotion(MODEL, principal_angle=0.4, minor_ratio=0.7)
HEAT = FrictionalHeating(contact_area=0.05)
HYSTERESIS = paper_bearing(coulomb_friction(0.06)).hysteresis


def _double():
    """A double pendulum whose bottom surface (R 1.5 m, mu 0.06) is heated, its top (R 2 m,
    mu 0.08) not: the two sliders travel different distances."""
    return DoublePendulum(bottom_radius=1.5, top_radius=2.0, bottom_capacity=1.0, top_capacity=1.0,
                          bottom_friction=coulomb_friction(0.06), top_friction=coulomb_friction(0.08),
                          hysteresis=HYSTERESIS, bottom_heating=HEAT, bottom_pressure=30e6)


def _structure(components):
    if components == 1:
        return isolated_structure("rigid", isolator=_double(), time_step=0.005)
    return bidirectional_isolated_structure("rigid", isolator=_double(), time_step=0.005)


def _own_peaks(structure, model, index):
    """(slider travel (G, S), temperature rise (G, S)) of motion `index`'s own history."""
    rows = [uniform_signal(row, DT) for row in np.atleast_2d(monte_carlo_motion(model, jax.random.key(5), index))]
    system = structure(rows[0] if len(rows) == 1 else tuple(rows))
    response = simulate_history(system, DURATION)
    assert bool(np.all(response.converged))
    travel = np.max(np.asarray(slider_travel(response)), axis=0)
    return np.atleast_2d(travel), np.max(np.asarray(response.surface_temperature_rise), axis=0)


@pytest.mark.parametrize("components", [1, 2])
def test_a_double_pendulum_keeps_each_slider_and_its_heated_surface(components, tmp_path):
    model = MODEL if components == 1 else TWO
    result = monte_carlo(_structure(components), model, N, key=jax.random.key(5), chunk_size=2)
    assert result.converged.all()
    assert result.attrs["slider_names"] == ["bottom", "top"]
    assert result.attrs["heated_surface_names"] == ["bottom"]
    assert result.slider_travel.shape == (N, 1, 2) and result.surface_temperature_rise.shape == (N, 1, 1)
    for index in range(N):
        travel, rise = _own_peaks(_structure(components), model, index)
        np.testing.assert_allclose(result.slider_travel[index], travel, rtol=1e-9)
        np.testing.assert_allclose(result.surface_temperature_rise[index], rise[:, :1], rtol=1e-9)
        assert rise[0, 1] == 0.0  # the top surface is not heated: left out of the result
    assert np.all(result.surface_temperature_rise > 1.0)  # the bottom surface warms in every run
    assert np.all(np.abs(result.slider_travel[:, 0, 0] - result.slider_travel[:, 0, 1]) > 1e-4)

    back = MonteCarloResult.open(result.save(tmp_path / "runs.nc"))
    np.testing.assert_array_equal(back.slider_travel, result.slider_travel)
    np.testing.assert_array_equal(back.surface_temperature_rise, result.surface_temperature_rise)
    dataset = back.to_dataset()
    assert list(dataset["slider"].values) == ["bottom", "top"]
    assert list(dataset["heated_surface"].values) == ["bottom"]
    assert dataset["surface_temperature_rise"].dims == ("motion", "group", "heated_surface")
    assert dataset["surface_temperature_rise"].attrs["units"] == "K"

    with open(result.save(tmp_path / "runs.csv")) as handle:
        rows = list(csv.DictReader(handle))
    assert [float(row["slider_travel_m_top"]) for row in rows] == pytest.approx(result.slider_travel[:, 0, 1],
                                                                               rel=1e-12)
    assert [float(row["surface_temperature_rise_K_bottom"]) for row in rows] == pytest.approx(
        result.surface_temperature_rise[:, 0, 0], rel=1e-12)


def test_a_flat_slider_without_heating_keeps_no_surface_peaks():
    result = monte_carlo(isolated_structure("rigid", time_step=0.01, isolation_period=2.0), MODEL, 2,
                         key=jax.random.key(5), chunk_size=2)
    assert result.slider_travel is None and result.surface_temperature_rise is None
    assert "slider_names" not in result.attrs and result.group_names == []
    assert "slider" not in result.to_dataset().dims


def _slab():
    """A 1000 kN slab on four groups of heated single pendulums (R 2.2 m, mu 0.06), its mass
    off the plan's centre: the groups carry unequal loads and so heat unequally."""
    bearing = paper_bearing(coulomb_friction(0.06), yield_disp=1e-3)
    bearing = eqx.tree_at(lambda b: b.heating, bearing, HEAT, is_leaf=lambda x: x is None)
    zero = uniform_signal(np.zeros(int(round(DURATION / DT)) + 1), DT)
    loads = [1.5e5, 2.5e5, 3.75e5, 2.25e5]
    return slab_on_bearings(
        length_x=20.0, length_y=12.0, weight=1e6, centre_of_mass=[12.0, 7.0],
        positions=[[2.0, 1.0], [18.0, 1.0], [18.0, 11.0], [2.0, 11.0]], loads=loads,
        ground_acceleration=zero, ground_y=zero, time_step=0.005, isolator="single-fp", bearings=bearing, radii=2.2,
        contact_pressures=[30e6 * load / 2.5e5 for load in loads])


@pytest.mark.slow
def test_a_slab_keeps_each_groups_heated_surface(tmp_path):
    slab = _slab()
    result = monte_carlo(BuiltStructure(slab), TWO, 2, key=jax.random.key(5), chunk_size=2)
    assert result.converged.all() and result.slider_travel is None
    assert result.surface_temperature_rise.shape == (2, 4, 1)
    for index in range(2):
        rows = [uniform_signal(row, DT) for row in np.asarray(monte_carlo_motion(TWO, jax.random.key(5), index))]
        response = simulate_history(under_ground(slab, *rows), DURATION)
        np.testing.assert_allclose(result.surface_temperature_rise[index],
                                   np.max(np.asarray(response.surface_temperature_rise), axis=0), rtol=1e-9)
    spread = result.surface_temperature_rise[:, :, 0]
    assert np.all(spread.max(axis=1) > 1.2 * spread.min(axis=1))  # the heavier groups run hotter
    dataset = MonteCarloResult.open(result.save(tmp_path / "slab.nc")).to_dataset()
    assert dataset["surface_temperature_rise"].dims == ("motion", "group", "heated_surface")
    assert dataset.sizes["group"] == 4


@pytest.mark.slow
def test_a_distributed_run_writes_the_surface_peaks(dask_cluster, tmp_path):
    local = monte_carlo(_structure(1), MODEL, N, key=jax.random.key(5), chunk_size=2, devices=jax.devices()[:1])
    spread = monte_carlo_distributed(_structure(1), MODEL, N, out=tmp_path / "runs.nc", seed=5,
                                     scheduler=dask_cluster.scheduler_address, chunk_size=2)
    np.testing.assert_allclose(spread.slider_travel, local.slider_travel, rtol=1e-12)
    np.testing.assert_allclose(spread.surface_temperature_rise, local.surface_temperature_rise, rtol=1e-12)
    assert spread.attrs["slider_names"] == ["bottom", "top"]
    assert spread.attrs["heated_surface_names"] == ["bottom"]


def _heated_file(path, bottom_capacity=12.0):
    """A double pendulum's isolator file, its bottom surface (capacity `bottom_capacity` [in])
    heated."""
    def surface(radius, capacity, mu):
        return {"radius": {"value": radius, "unit": "in"}, "capacity": {"value": capacity, "unit": "in"},
                "friction": {"f_max": {"value": mu, "unit": "1"}, "delta_f": {"value": 0.0, "unit": "1"},
                             "rate_a": {"value": 0.0, "unit": "s/in"}}}

    bottom = surface(60.0, bottom_capacity, 0.04)
    bottom["heating"] = {"contact_area": {"value": 0.05, "unit": "m^2"},
                         "contact_pressure": {"value": 30, "unit": "MPa"}, "heat_scale": {"value": 1, "unit": "1"},
                         "conductivity": {"value": 16.2, "unit": "W/(m K)"},
                         "diffusivity": {"value": 4.4, "unit": "mm^2/s"},
                         "initial_temperature": {"value": 20, "unit": "degC"}}
    path.write_text(json.dumps({"format": "teflon-jax isolator", "format_version": 1, "isolator": "double-fp",
                                "surfaces": {"bottom": bottom, "top": surface(100.0, 12.0, 0.08)},
                                "yield_disp": {"value": 0.004, "unit": "in"}}))
    return path


def test_montecarlo_reports_the_sliders_and_the_heated_surface(tmp_path, capsys):
    """`teflon-jax montecarlo` of a double pendulum heated on its bottom surface, whose 4 in
    capacity some runs exceed: the summary JSON's percentiles of each slider's travel and of the
    bottom surface's rise are those of the results file's converged runs, in the output units,
    with the runs beyond each slider's capacity (on its restrainer); the printed lines name them."""
    isolator = _heated_file(tmp_path / "dfp.json", bottom_capacity=4.0)
    code = main(["montecarlo", "--motions", "3", "--duration", "6s", "--strong-motion", "2s", "--pga", "0.5g",
                 "--isolator", "double-fp", "--isolator-file", str(isolator),
                 "--no-progress", "--units", "us", "--json", str(tmp_path / "mc.json"),
                 "--out", str(tmp_path / "mc.nc")])
    out = capsys.readouterr().out
    assert code == 0
    surfaces = json.loads((tmp_path / "mc.json").read_text())["surfaces"]
    result = MonteCarloResult.open(tmp_path / "mc.nc")
    travel = result.slider_travel[:, 0] / INCH
    for e, name in enumerate(("bottom", "top")):
        assert surfaces["slider_travel_in"][name]["max"] == pytest.approx(travel[:, e].max(), rel=1e-12)
        assert surfaces["slider_travel_in"][name]["p50"] == pytest.approx(np.median(travel[:, e]), rel=1e-12)
        assert surfaces["slider_travel_in"][name]["capacity"] == pytest.approx((4.0, 12.0)[e], rel=1e-12)
        assert surfaces["slider_travel_in"][name]["n_on_restrainer"] == int(np.sum(travel[:, e] > (4.0, 12.0)[e]))
    assert surfaces["slider_travel_in"]["bottom"]["n_on_restrainer"] >= 1  # the 4 in bottom surface is reached
    assert surfaces["slider_travel_in"]["top"]["n_on_restrainer"] == 0
    assert list(surfaces["surface_temperature_rise_K"]) == ["bottom"]
    assert surfaces["surface_temperature_rise_K"]["bottom"]["max"] == pytest.approx(
        result.surface_temperature_rise.max(), rel=1e-12)
    assert "slider travel [in] over the 3 converged runs: bottom p50" in out
    assert "surface temperature rise [K] over the 3 converged runs: bottom p50" in out
    np.testing.assert_allclose(result.attrs["slider_capacities_m"], [[4.0 * INCH, 12.0 * INCH]], rtol=1e-12)


def test_the_statistics_and_exceedance_of_each_surface_are_those_of_the_converged_runs():
    """`percentiles` and `exceedance` read a slider's travel and a heated surface's rise by
    their columns (as `surface_peaks` and the CSV name them), over the converged runs alone
    (a run marked unconverged leaves every statistic, its count "n" included); an unknown
    column is refused by name, the accepted ones listed."""
    result = monte_carlo(_structure(1), MODEL, N, key=jax.random.key(5), chunk_size=2)
    stats = result.percentiles(q=(50, 84))
    travel = result.slider_travel[:, 0, 1]
    assert stats["slider_travel_m_top"]["p84"] == pytest.approx(np.percentile(travel, 84), rel=1e-12)
    assert stats["slider_travel_m_top"]["n"] == N
    assert stats["surface_temperature_rise_K_bottom"]["mean"] == pytest.approx(
        result.surface_temperature_rise[:, 0, 0].mean(), rel=1e-12)
    levels, probability = result.exceedance("slider_travel_m_bottom")
    np.testing.assert_array_equal(levels, np.sort(result.slider_travel[:, 0, 0]))
    np.testing.assert_allclose(probability, [2 / 3, 1 / 3, 0.0])

    failed = dataclasses.replace(result, converged=np.array([True, False, True]))
    assert failed.percentiles()["slider_travel_m_top"]["n"] == 2
    assert failed.percentiles()["slider_travel_m_top"]["p50"] == pytest.approx(np.mean(travel[[0, 2]]), rel=1e-12)
    np.testing.assert_array_equal(failed.exceedance("slider_travel_m_top")[0], np.sort(travel[[0, 2]]))
    with pytest.raises(ValueError, match="unknown 'slider_travel_m_middle'; accepted: base_disp, "
                                         "base_shear_ratio, slider_travel_m_bottom, slider_travel_m_top, "
                                         "surface_temperature_rise_K_bottom"):
        result.exceedance("slider_travel_m_middle")


@pytest.mark.slow  # three bearings of the double pendulum in one compiled run
def test_montecarlo_bounding_names_the_case_that_heats_the_surface_most(tmp_path, capsys):
    """`montecarlo --property-factors`: each slider's travel and the heated surface's rise are
    in the governing table; the upper-bound friction heats the surface most (the flux is
    mu p |v|)."""
    code = main(["montecarlo", "--motions", "3", "--duration", "6s", "--strong-motion", "2s", "--pga", "0.4g",
                 "--isolator", "double-fp", "--isolator-file", str(_heated_file(tmp_path / "dfp.json")),
                 "--property-factors", "0.8,1.25", "--no-progress", "--json", str(tmp_path / "b.json")])
    assert code == 0, capsys.readouterr().err
    payload = json.loads((tmp_path / "b.json").read_text())
    rise = "surface_temperature_rise_K_bottom"
    means = {case: entry["mean"][rise] for case, entry in payload["cases"].items()}
    assert means["lower"] < means["nominal"] < means["upper"]
    assert payload["governs"][rise]["by_mean"] == "upper"
    assert {"slider_travel_m_bottom", "slider_travel_m_top"} <= set(payload["governs"])


def test_a_slider_capacity_fragility_counts_the_runs_on_a_restrainer(tmp_path, capsys):
    """`--limit slider_capacity_ratio=1` over five levels: at each level, the runs counted as
    exceeding are those of the results file whose largest slider travel over its capacity
    passes 1, more of them as the level rises (4 in bottom capacity, 12 in top), and the
    fitted fragility's median lies inside the levels."""
    isolator = _heated_file(tmp_path / "dfp.json", bottom_capacity=4.0)
    code = main(["montecarlo", "--motions", "6", "--duration", "6s", "--strong-motion", "2s",
                 "--pga", "0.2g,0.3g,0.4g,0.5g,0.6g", "--limit", "slider_capacity_ratio=1", "--isolator", "double-fp",
                 "--isolator-file", str(isolator), "--no-progress", "--json", str(tmp_path / "f.json"),
                 "--out", str(tmp_path / "f.nc")])
    assert code == 0, capsys.readouterr().err
    entry = json.loads((tmp_path / "f.json").read_text())["fragility"]["slider_capacity_ratio=1"]
    result = MonteCarloResult.open(tmp_path / "f.nc")
    np.testing.assert_allclose(result.attrs["slider_capacities_m"], [[4.0 * INCH, 12.0 * INCH]], rtol=1e-12)
    ratio = np.max(result.slider_travel[:, 0] / np.array([4.0, 12.0]) / INCH, axis=-1).reshape(5, 6)
    assert entry["n_exceed"] == np.sum(ratio > 1.0, axis=1).tolist()
    assert entry["n_exceed"][0] < entry["n_exceed"][-1]
    assert 0.2 < entry["median"] < 0.6


def test_a_slider_capacity_limit_needs_sliders(tmp_path, capsys):
    code = main(["montecarlo", "--motions", "2", "--pga", "0.2g,0.4g", "--limit", "slider_capacity_ratio=1",
                 "--no-progress", "--json", str(tmp_path / "f.json")])
    assert code == 2
    assert ("--limit slider_capacity_ratio=1: the isolator has no sliders in series; it needs --isolator "
            "double-fp or triple-fp.") in capsys.readouterr().err
    assert not (tmp_path / "f.json").exists()


@pytest.mark.slow
def test_a_streamed_levels_file_keeps_the_slider_capacities(dask_cluster, tmp_path, capsys):
    """`montecarlo --scheduler` over two levels: the NetCDF file the cluster's chunks stream
    keeps each slider's capacity, as the file written in this process does."""
    code = main(["montecarlo", "--motions", "2", "--duration", "4s", "--strong-motion", "2s", "--pga", "0.2g,0.4g",
                 "--isolator", "double-fp", "--isolator-file", str(_heated_file(tmp_path / "dfp.json", 4.0)),
                 "--no-progress", "--json", str(tmp_path / "f.json"), "--out", str(tmp_path / "f.nc"),
                 "--scheduler", dask_cluster.scheduler_address])
    assert code == 0, capsys.readouterr().err
    back = MonteCarloResult.open(tmp_path / "f.nc")
    np.testing.assert_allclose(back.attrs["slider_capacities_m"], [[4.0 * INCH, 12.0 * INCH]], rtol=1e-12)
