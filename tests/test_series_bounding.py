"""Bounding analysis on triple and double friction pendulums (`montecarlo --property-factors
LOWER,UPPER --isolator triple-fp|double-fp`): every surface's Eq. 1 friction times the factor,
radii and capacities kept.

Peers: isolator files whose friction was multiplied by hand (each bound is a plain run on
such a file, number for number); the physics of friction bounds (more friction: less
displacement, more base shear); the scaling law itself, surface by surface.
"""

import copy
import json

import equinox as eqx
import jax
import numpy as np
import pytest
import xarray

from teflon_jax.bearing import (
    DoublePendulum,
    FrictionalHeating,
    coulomb_friction,
    designed_pendulum,
    paper_bearing,
)
from teflon_jax.cli import main
from teflon_jax.excitation import StochasticGroundMotion
from teflon_jax.formats import isolator_from_dict
from teflon_jax.studies import (
    BOUNDING_CASES,
    bounding_design,
    monte_carlo,
    series_bounding_design,
)
from teflon_jax.systems import (
    TRIPLE_MONTE_CARLO_TOLERANCE,
    isolated_structure,
    with_vertical_component,
)

LOWER, UPPER = 0.8, 1.25


def _surface(radius, capacity, f_max, delta_f):
    friction = {"f_max": {"value": f_max, "unit": "1"}, "delta_f": {"value": delta_f, "unit": "1"},
                "rate_a": {"value": 0.5, "unit": "s/in"}}
    return {"radius": {"value": radius, "unit": "in"}, "capacity": {"value": capacity, "unit": "in"},
            "friction": friction}


def _triple(friction):
    """The isolator file's document with (f_max, delta_f) of inner, bottom and top."""
    geometry = {"inner": (12, 2), "bottom": (84, 12), "top": (84, 14)}
    return {"format": "teflon-jax isolator", "format_version": 1, "isolator": "triple-fp",
            "surfaces": {name: _surface(*geometry[name], *friction[name]) for name in geometry},
            "yield_disp": {"value": 0.004, "unit": "in"}}


NOMINAL = {"inner": (0.02, 0.01), "bottom": (0.06, 0.02), "top": (0.10, 0.03)}
# the same friction times 1.25 and 0.8, multiplied by hand
BY_HAND = {"upper": {"inner": (0.025, 0.0125), "bottom": (0.075, 0.025), "top": (0.125, 0.0375)},
           "lower": {"inner": (0.016, 0.008), "bottom": (0.048, 0.016), "top": (0.08, 0.024)}}


def test_every_surface_friction_is_scaled_and_the_geometry_kept():
    """f_max, delta_f and so f_min = f_max - delta_f of each surface times the factor; rate_a,
    radii, capacities, hysteresis and a surface's heating stay; the design variable is the
    same scaling."""
    nominal = isolator_from_dict(_triple(NOMINAL))
    upper = nominal.scaled_friction(UPPER)
    by_hand = isolator_from_dict(_triple(BY_HAND["upper"]))
    for name in nominal.slider_names:
        got, want = getattr(upper, f"{name}_friction"), getattr(by_hand, f"{name}_friction")
        assert float(got.f_max) == pytest.approx(float(want.f_max), rel=1e-14)
        assert float(got.delta_f) == pytest.approx(float(want.delta_f), rel=1e-14)
        assert float(got.f_min) == pytest.approx(UPPER * float(getattr(nominal, f"{name}_friction").f_min), rel=1e-14)
        assert float(got.rate_a) == float(getattr(nominal, f"{name}_friction").rate_a)
    np.testing.assert_array_equal(upper.series_radii(), nominal.series_radii())
    np.testing.assert_array_equal(upper.series_capacities(), nominal.series_capacities())
    designed = designed_pendulum(nominal, {"friction_factor": UPPER})
    np.testing.assert_array_equal(designed.frictions().f_max, upper.frictions().f_max)
    # a Coulomb surface (delta_f = 0) has its mu scaled; a heated one keeps its heating
    heat = FrictionalHeating(contact_area=0.05)
    double = DoublePendulum(bottom_radius=1.5, top_radius=2.0, bottom_capacity=0.3, top_capacity=0.3,
                            bottom_friction=coulomb_friction(0.05), top_friction=coulomb_friction(0.09),
                            hysteresis=paper_bearing(coulomb_friction(0.05)).hysteresis,
                            bottom_heating=heat, bottom_pressure=30e6)
    low = double.scaled_friction(LOWER)
    assert float(low.bottom_friction.f_max) == pytest.approx(0.04, rel=1e-14)
    assert float(low.top_friction.delta_f) == 0.0
    assert eqx.tree_equal(low.bottom_heating, heat) and low.bottom_pressure == 30e6 and low.heated


def test_bounding_design_of_a_series_pendulum_and_its_refusals():
    structure = isolated_structure("rigid", isolator=isolator_from_dict(_triple(NOMINAL)))
    design = bounding_design(structure, lower=LOWER, upper=UPPER)
    assert list(design) == ["friction_factor"]
    np.testing.assert_array_equal(design["friction_factor"], [1.0, UPPER, LOWER])
    vertical = bounding_design(with_vertical_component(structure), lower=LOWER, upper=UPPER)  # read through
    np.testing.assert_array_equal(vertical["friction_factor"], design["friction_factor"])
    # the top surface's f_max 0.10 may be multiplied by at most 10
    with pytest.raises(ValueError, match=r"^upper: 12 times the top surface's f_max 0.1 is 1.2, above 1"):
        series_bounding_design(structure.pendulum, lower=LOWER, upper=12.0)
    with pytest.raises(ValueError, match="^lower: a property modification factor must be finite and > 0"):
        series_bounding_design(structure.pendulum, lower=-1.0, upper=UPPER)


@pytest.mark.parametrize("factors, message", [
    ("0.8,12", "--property-factors 0.8,12: upper: 12 times the top surface's f_max 0.1 is 1.2, above 1"),
    ("1.3,0.85", "--property-factors 1.3,0.85: lower: the lower-bound factor 1.3 is above"),
    ("0,1.2", "--property-factors 0,1.2: lower: a property modification factor must be finite and > 0"),
    ("0.85", "--property-factors: write LOWER,UPPER"),
])
def test_bad_factors_on_a_triple_pendulum_are_refused_by_name(factors, message, tmp_path, capsys):
    (tmp_path / "tfp.json").write_text(json.dumps(_triple(NOMINAL)))
    code = main(["montecarlo", "--motions", "2", "--isolator", "triple-fp", "--isolator-file",
                 str(tmp_path / "tfp.json"), "--property-factors", factors, "--json", str(tmp_path / "b.json")])
    assert code == 2
    assert message in capsys.readouterr().err
    assert not (tmp_path / "b.json").exists()


def _model():
    return StochasticGroundMotion(peak_ground_acceleration=4.0, duration=2.0, time_step=0.01, rise_time=0.5,
                                  strong_motion_duration=1.5)


@pytest.mark.slow
def test_each_bound_is_the_run_on_the_friction_scaled_by_hand():
    """The three cases in one call: the upper bound's peaks are, motion by motion, those of a
    plain run on the isolator file with every friction constant multiplied by hand; more
    friction moves the rigid mass less and pushes it harder."""
    def structure(friction):
        return isolated_structure("rigid", isolator=isolator_from_dict(_triple(friction)),
                                  time_step=0.005, newton_tolerance=TRIPLE_MONTE_CARLO_TOLERANCE)

    key = jax.random.key(1)
    nominal = structure(NOMINAL)
    bounds = monte_carlo(nominal, _model(), 2, key=key, design=bounding_design(nominal, lower=LOWER, upper=UPPER))
    assert bounds.base_disp.shape == (3, 2) and bool(np.all(bounds.converged))
    upper = monte_carlo(structure(BY_HAND["upper"]), _model(), 2, key=key)
    index = BOUNDING_CASES.index("upper")
    np.testing.assert_allclose(bounds.base_disp[index], upper.base_disp, rtol=1e-12)
    np.testing.assert_allclose(bounds.base_shear_ratio[index], upper.base_shear_ratio, rtol=1e-12)
    mean = {case: (bounds.base_disp[i].mean(), bounds.base_shear_ratio[i].mean())
            for i, case in enumerate(BOUNDING_CASES)}
    assert mean["lower"][0] > mean["nominal"][0] > mean["upper"][0]
    assert mean["upper"][1] > mean["nominal"][1] > mean["lower"][1]


@pytest.mark.slow  # four compiled Monte Carlo commands, about 1 min on two shared cores
def test_montecarlo_bounds_equal_the_commands_on_hand_scaled_files(tmp_path, capsys):
    """`montecarlo --property-factors` on a triple pendulum: each case's peaks in the results
    file are those of `montecarlo` on the isolator file scaled by hand (number for number), the
    JSON's friction per surface is the hand-scaled one, the lower bound governs displacement
    and the upper one base shear."""
    common = ["montecarlo", "--motions", "3", "--duration", "5s", "--strong-motion", "2s", "--pga", "0.4g",
              "--isolator", "triple-fp", "--no-progress"]
    files = {"nominal": NOMINAL, **BY_HAND}
    for case, friction in files.items():
        (tmp_path / f"{case}.json").write_text(json.dumps(_triple(friction)))
    code = main([*common, "--isolator-file", str(tmp_path / "nominal.json"), "--property-factors", "0.8,1.25",
                 "--json", str(tmp_path / "b.json"), "--out", str(tmp_path / "b.nc")])
    assert code == 0
    data = json.loads((tmp_path / "b.json").read_text())
    with xarray.open_dataset(tmp_path / "b.nc") as dataset:
        disp, shear = dataset["base_disp"].values, dataset["base_shear_ratio"].values
        np.testing.assert_array_equal(dataset["design_friction_factor"].values, [1.0, 1.25, 0.8])
    for i, case in enumerate(BOUNDING_CASES):
        assert main([*common, "--isolator-file", str(tmp_path / f"{case}.json"), "--out",
                     str(tmp_path / f"{case}.nc")]) == 0
        with xarray.open_dataset(tmp_path / f"{case}.nc") as dataset:
            np.testing.assert_allclose(disp[i], dataset["base_disp"].values, rtol=1e-12)
            np.testing.assert_allclose(shear[i], dataset["base_shear_ratio"].values, rtol=1e-12)
        entry = data["cases"][case]
        for name, (f_max, delta_f) in files[case].items():
            assert entry["f_max"][name] == pytest.approx(f_max, rel=1e-12)
            assert entry["delta_f"][name] == pytest.approx(delta_f, rel=1e-12)
        assert entry["mean"]["base_disp_in"] == pytest.approx(disp[i].mean() / 0.0254, rel=1e-12)
    capsys.readouterr()
    assert data["governs"]["base_disp_in"]["by_mean"] == "lower"
    assert data["governs"]["base_shear_ratio"]["by_mean"] == "upper"
    assert data["property_factors"] == {**data["property_factors"], "lower": 0.8, "upper": 1.25}


@pytest.mark.slow  # a compiled two-component building, about 30 s on two shared cores
def test_montecarlo_bounds_a_double_pendulum_building_under_two_components(tmp_path, capsys):
    """The double pendulum's two surfaces scaled alike; under two components the building's
    storey results (x and y) enter the governing cases."""
    document = copy.deepcopy(_triple(NOMINAL))
    document["isolator"] = "double-fp"
    document["surfaces"] = {"bottom": document["surfaces"]["bottom"], "top": document["surfaces"]["top"]}
    (tmp_path / "dfp.json").write_text(json.dumps(document))
    code = main(["montecarlo", "--motions", "2", "--duration", "4s", "--strong-motion", "2s", "--pga", "0.4g",
                 "--structure", "building", "--components", "2", "--isolator", "double-fp", "--isolator-file",
                 str(tmp_path / "dfp.json"), "--property-factors", "0.8,1.25", "--json", str(tmp_path / "b.json"),
                 "--no-progress"])
    capsys.readouterr()
    assert code == 0
    data = json.loads((tmp_path / "b.json").read_text())
    assert data["cases"]["lower"]["f_max"] == pytest.approx({"bottom": 0.048, "top": 0.08}, rel=1e-12)
    assert set(data["governs"]) == {"base_disp_in", "base_shear_ratio", "storey_drift_max",
                                    "level_acceleration_max_g", "slider_travel_m_bottom", "slider_travel_m_top"}
    means = {case: data["cases"][case]["mean"] for case in BOUNDING_CASES}
    assert means["lower"]["base_disp_in"] > means["upper"]["base_disp_in"]
    assert means["upper"]["base_shear_ratio"] > means["lower"]["base_shear_ratio"]
