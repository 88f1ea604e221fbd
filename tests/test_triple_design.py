"""Design of a triple friction pendulum (`IsolatedStructure` on it with design variables,
`design --isolator triple-fp`): each variable changes the bearing as its definition says (the
outer radii, Eq. 1 of the inner and outer surfaces, the capacities), the 95th-percentile peak
displacement's derivative in every variable agrees with central differences (with the
restrainers reached), and wrong combinations are refused by name.
References: Fenz & Constantinou (2008), Earthquake Spectra 24(4); Constantinou, Mokha &
Reinhorn (1990), Eq. 1.
"""

import json

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from teflon_jax.bearing import (
    BoucWen,
    FrictionParameters,
    TriplePendulum,
    design_space,
    designed_isolator,
    sliding_friction,
    triple_pendulum_backbone,
)
from teflon_jax.cli import main
from teflon_jax.excitation import StochasticGroundMotion, sample
from teflon_jax.formats import isolator_to_dict
from teflon_jax.studies import GRADIENT_TOLERANCE, percentile_disp_gradient_check
from teflon_jax.systems import (
    isolated_structure,
)


def _friction(f_max, delta_f, rate_a):
    return FrictionParameters(jnp.asarray(f_max), jnp.asarray(delta_f), jnp.asarray(rate_a))


TRIPLE = TriplePendulum(
    inner_radius=jnp.asarray(0.4), bottom_radius=jnp.asarray(2.2), top_radius=jnp.asarray(2.5),
    inner_capacity=jnp.asarray(0.05), bottom_capacity=jnp.asarray(0.30), top_capacity=jnp.asarray(0.35),
    inner_friction=_friction(0.03, 0.015, 20.0), bottom_friction=_friction(0.06, 0.03, 20.0),
    top_friction=_friction(0.10, 0.04, 20.0), hysteresis=BoucWen(1e-4))


def test_each_variable_changes_the_bearing_as_defined():
    design = {"outer_radius_scale": 1.3, "inner_f_max": 0.02, "outer_f_max": 0.08, "capacity_scale": 0.7}
    new = designed_isolator(isolated_structure("rigid", isolator=TRIPLE), design)
    assert float(new.inner_radius) == pytest.approx(0.4)
    assert (float(new.bottom_radius), float(new.top_radius)) == pytest.approx((1.3 * 2.2, 1.3 * 2.5))
    assert [float(new.inner_capacity), float(new.bottom_capacity), float(new.top_capacity)] == pytest.approx(
        [0.7 * 0.05, 0.7 * 0.30, 0.7 * 0.35])
    speeds = jnp.array([0.0, 0.01, 0.1, 1.0])
    for surface, factor in (("inner", 0.02 / 0.03), ("bottom", 0.08 / 0.06), ("top", 0.08 / 0.06)):
        before = sliding_friction(getattr(TRIPLE, f"{surface}_friction"), speeds)
        after = sliding_friction(getattr(new, f"{surface}_friction"), speeds)
        np.testing.assert_allclose(after, factor * before, rtol=1e-12)  # Eq. 1 scaled at every speed


def test_the_outer_radius_scale_softens_regimes_two_to_four_as_the_closed_forms():
    coulomb = designed_isolator(isolated_structure("rigid", isolator=TRIPLE), {})
    coulomb = TriplePendulum(**{**{f: getattr(coulomb, f) for f in (
        "inner_radius", "bottom_radius", "top_radius", "inner_capacity", "bottom_capacity", "top_capacity",
        "hysteresis")}, **{f"{s}_friction": _friction(m, 0.0, 0.0) for s, m in (
            ("inner", 0.03), ("bottom", 0.06), ("top", 0.10))}})
    s, a, b, c = 1.5, 0.4, 2.2, 2.5
    designed = designed_isolator(isolated_structure("rigid", isolator=coulomb), {"outer_radius_scale": s})
    slopes = [slope for _, _, slope in triple_pendulum_backbone(designed)[0]]
    assert slopes == pytest.approx([1 / (2 * a), 1 / (a + s * b), 1 / (s * b + s * c), 1 / (a + s * c), 1 / (2 * a)])


def test_unknown_variables_and_boxes_outside_the_series_model_are_refused():
    structure = isolated_structure("rigid", isolator=TRIPLE)
    with pytest.raises(ValueError, match="unknown variable.*'radius'.*outer_radius_scale"):
        structure(jnp.zeros(10), {"radius": 1.0})
    check = design_space("triple-fp").check
    with pytest.raises(ValueError, match="unknown variable 'radius' for the triple-fp isolator"):
        check(structure, {"radius": (1.0, 2.0)})
    with pytest.raises(ValueError, match="inner_f_max: bounds"):
        check(structure, {"inner_f_max": (0.01, 0.05), "outer_f_max": (0.04, 0.08)})
    with pytest.raises(ValueError, match="outer_radius_scale: bounds"):
        check(structure, {"outer_radius_scale": (0.1, 2.0)})  # 0.1 b < a
    with pytest.raises(ValueError, match="outer_f_max: bounds"):
        check(structure, {"outer_f_max": (0.04, 0.7)})  # the top's f_max would pass 1
    with pytest.raises(ValueError, match="outer_f_max: bounds"):  # its low end below the inner box's high end
        check(structure, {"outer_f_max": (0.04, 0.08), "inner_f_max": (0.01, 0.05)})
    check(structure, {"inner_f_max": (0.01, 0.04), "outer_f_max": (0.04, 0.08)})


@pytest.mark.slow
def test_the_95th_percentile_displacements_gradient_is_the_central_difference():
    """Three short motions strong enough to reach the restrainers (capacities halved), so that
    every variable moves the percentile."""
    triple = jax.tree_util.tree_map(lambda x: jnp.asarray(x, float), TRIPLE)
    structure = isolated_structure("rigid", isolator=triple, time_step=0.005,
                                   newton_tolerance=0.0)
    records = strong_motions()
    design = {"outer_radius_scale": 1.1, "outer_f_max": 0.07, "inner_f_max": 0.025, "capacity_scale": 0.4}
    check = percentile_disp_gradient_check(structure, design, records, 0.01)
    assert check["rel_error"] <= GRADIENT_TOLERANCE, check
    assert all(abs(g) > 0 for g in check["gradient"].values()), check["gradient"]
    assert check["gradient"]["outer_f_max"] < 0 and check["gradient"]["capacity_scale"] > 0


def strong_motions():
    """Three 6 s Clough-Penzien motions of PGA 0.4 g at 0.01 s."""
    motion = StochasticGroundMotion(peak_ground_acceleration=0.4 * 9.81, site_frequency=2 * np.pi * 1.5,
                                    site_damping=0.6, high_pass_frequency=2 * np.pi * 0.15,
                                    strong_motion_duration=3.0, duration=6.0, time_step=0.01)
    return sample(motion, jax.random.key(0), 3)


def design_refusal(tmp_path, capsys, isolator_file, flags) -> str:
    """stderr of `design` with `flags` ("FILE" standing for --isolator-file `isolator_file`),
    which must exit 2 before any work (two short motions)."""
    flags = [a for f in flags for a in (["--isolator-file", str(isolator_file)] if f == "FILE" else [f])]
    assert main(["--no-compile-cache", "design", *flags, "--motions", "2", "--duration", "4s", "--json",
                 str(tmp_path / "d.json"), "--no-progress"]) == 2
    return capsys.readouterr().err


def design_payload(tmp_path, capsys, isolator_file, flags) -> dict:
    """The JSON of `design --isolator-file isolator_file *flags` on three 8 s motions against a
    0.075 m limit (grid 3), which must exit 0."""
    out = tmp_path / "design.json"
    code = main(["design", "--isolator-file", str(isolator_file), *flags, "--motions", "3", "--duration",
                 "8s", "--strong-motion", "4s", "--pga", "0.3g", "--grid", "3", "--disp-limit", "0.075m",
                 "--json", str(out), "--no-progress", "--units", "si"])
    assert code == 0, capsys.readouterr().err
    return json.loads(out.read_text())


@pytest.fixture
def isolator_file(tmp_path):
    path = tmp_path / "tfp.json"
    path.write_text(json.dumps(isolator_to_dict(TRIPLE)))
    return path


@pytest.mark.parametrize("flags, message", [
    (["--isolator", "triple-fp", "FILE", "--period-range", "1s", "3s"], "--period-range: does not apply to --isolator triple-fp"),
    (["--isolator", "triple-fp", "FILE", "--pressure", "1000psi", "--outer-f-max-range", "0.04", "0.08"], "--pressure: does not apply"),
    (["--isolator", "triple-fp", "FILE"], "give at least one of --outer-radius-scale-range"),
    (["--isolator", "triple-fp", "--outer-f-max-range", "0.04", "0.08"], "--isolator-file: --isolator triple-fp designs"),
    (["--isolator", "triple-fp", "FILE", "--inner-f-max-range", "0.01", "0.07"], "--inner-f-max-range: bounds"),
    (["--isolator", "triple-fp", "FILE", "--outer-f-max-range", "0.08", "0.04"], "--outer-f-max-range: LOW must be below HIGH"),
    (["--outer-f-max-range", "0.04", "0.08"], "--outer-f-max-range: applies to --isolator triple-fp only"),
    (["--isolator", "single-fp", "FILE"], "--isolator-file: applies to --isolator triple-fp or double-fp only"),
])
def test_the_design_command_refuses_wrong_combinations(tmp_path, capsys, isolator_file, flags, message):
    assert message in design_refusal(tmp_path, capsys, isolator_file, flags)


@pytest.mark.slow
def test_the_design_command_meets_a_binding_limit(tmp_path, capsys, isolator_file):
    payload = design_payload(tmp_path, capsys, isolator_file, ["--isolator", "triple-fp",
                                                               "--outer-f-max-range", "0.04", "0.09"])
    assert payload["optimum"]["disp_limit_met"] and 0.04 < payload["optimum"]["outer_f_max"] < 0.09
    assert payload["optimum"]["mean_peak_base_disp_mm"] == pytest.approx(75.0, rel=0.01)  # the limit binds
    assert payload["p95_disp_gradient_rel_error"] <= GRADIENT_TOLERANCE
