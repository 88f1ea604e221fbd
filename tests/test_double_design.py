"""Design of a double friction pendulum (`IsolatedStructure` on a `DoublePendulum` with
design variables, `design --isolator double-fp`): each variable changes the bearing as its
definition says, the radius scale s divides every slope of the closed-form backbone (F/W =
mu_1 + u / R_1 on surface 1 alone, then slope 1 / (R_1 + R_2) on both; Fenz & Constantinou
2006, Earthquake Engng Struct. Dyn. 35), the 95th-percentile peak displacement's derivative
in every variable agrees with central differences, and wrong combinations are refused by name.
Constantinou, Mokha & Reinhorn (1990), Eq. 1.
"""

import json
import pathlib

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from test_double_fit import TRUE
from test_triple_design import design_payload, design_refusal, strong_motions

from teflon_jax.bearing import (
    BoucWen,
    DoublePendulum,
    coulomb_friction,
    design_space,
    designed_isolator,
    sliding_friction,
)
from teflon_jax.formats import isolator_to_dict
from teflon_jax.studies import GRADIENT_TOLERANCE, percentile_disp_gradient_check
from teflon_jax.systems import (
    imposed_path_test,
    isolated_structure,
    sampled_path,
)

TRIPLE_FILE = pathlib.Path(__file__).parents[1] / "benchmarks" / "triple_isolator.json"


DOUBLE = TRUE
"""The double pendulum of the fit's tests (R_1 = 2.0 m, R_2 = 2.6 m, f_max 0.05 and 0.09)."""


def test_each_variable_changes_the_bearing_as_defined():
    new = designed_isolator(isolated_structure("rigid", isolator=DOUBLE), {"radius_scale": 1.3, "surface_f_max": 0.07, "capacity_scale": 0.6})
    assert (float(new.bottom_radius), float(new.top_radius)) == pytest.approx((1.3 * 2.0, 1.3 * 2.6))
    assert (float(new.bottom_capacity), float(new.top_capacity)) == pytest.approx((0.18, 0.18))
    speeds = jnp.array([0.0, 0.01, 0.1, 1.0])
    for surface in ("bottom", "top"):  # Eq. 1 of both scaled by 0.07 / 0.05 at every speed
        before = sliding_friction(getattr(DOUBLE, f"{surface}_friction"), speeds)
        after = sliding_friction(getattr(new, f"{surface}_friction"), speeds)
        np.testing.assert_allclose(after, 0.07 / 0.05 * before, rtol=1e-6)


def test_the_radius_scale_divides_the_slopes_of_the_closed_form_backbone():
    """A slow push of Coulomb surfaces on the designed bearing follows mu_1 + u / (s R_1), then
    mu_2 + (u - s R_1 (mu_2 - mu_1)) / (s R_1 + s R_2)."""
    coulomb = DoublePendulum(bottom_radius=1.5, top_radius=2.5, bottom_capacity=0.5, top_capacity=0.5,
                             bottom_friction=coulomb_friction(0.04), top_friction=coulomb_friction(0.08),
                             hysteresis=BoucWen(1e-5))
    s = 1.4
    designed = jax.tree_util.tree_map(jnp.asarray, designed_isolator(isolated_structure("rigid", isolator=coulomb), {"radius_scale": s}))
    t = np.linspace(0.0, 100.0, 1001)
    u = 0.2 * t / t[-1]
    force = np.asarray(imposed_path_test(designed, sampled_path(t, u, 1.0)).force)
    r1, r2 = s * 1.5, s * 2.5
    both = r1 * 0.04
    closed = np.where(u < both, 0.04 + u / r1, 0.08 + (u - both) / (r1 + r2))
    away = np.abs(u - both) > 0.01  # away from the transition (Bouc-Wen's rounded corner)
    away[:5] = False
    np.testing.assert_allclose(force[away], closed[away], rtol=2e-3)


def test_unknown_variables_and_boxes_outside_the_model_are_refused():
    structure = isolated_structure("rigid", isolator=DOUBLE)
    check = design_space("double-fp").check
    with pytest.raises(ValueError, match="unknown variable.*'outer_radius_scale'.*radius_scale"):
        structure(jnp.zeros(10), {"outer_radius_scale": 1.0})
    with pytest.raises(ValueError, match="surface_f_max: bounds"):
        check(structure, {"surface_f_max": (0.04, 0.6)})  # the top's f_max would pass 1
    with pytest.raises(ValueError, match="radius_scale: bounds"):
        check(structure, {"radius_scale": (0.0, 2.0)})
    with pytest.raises(ValueError, match="design: unknown variable 'inner_f_max'"):
        check(structure, {"inner_f_max": (0.01, 0.02)})
    check(structure, {"surface_f_max": (0.03, 0.5), "radius_scale": (0.5, 2.0)})


def test_the_95th_percentile_displacements_gradient_is_the_central_difference():
    """Three short motions strong enough to reach the restrainers (capacities scaled down), so
    that every variable moves the percentile."""
    double = jax.tree_util.tree_map(lambda x: jnp.asarray(x, float), DOUBLE)
    structure = isolated_structure("rigid", isolator=double, time_step=0.005,
                                   newton_tolerance=0.0)
    records = strong_motions()
    design = {"radius_scale": 1.1, "surface_f_max": 0.045, "capacity_scale": 0.3}
    check = percentile_disp_gradient_check(structure, design, records, 0.01)
    assert check["rel_error"] <= GRADIENT_TOLERANCE, check
    assert all(abs(g) > 0 for g in check["gradient"].values()), check["gradient"]
    assert check["gradient"]["surface_f_max"] < 0 and check["gradient"]["capacity_scale"] > 0


@pytest.fixture
def isolator_file(tmp_path):
    path = tmp_path / "dfp.json"
    path.write_text(json.dumps(isolator_to_dict(DOUBLE)))
    return path


@pytest.mark.parametrize("flags, message", [
    (["--isolator", "double-fp", "FILE", "--period-range", "1s", "3s"], "--period-range: does not apply to --isolator double-fp"),
    (["--isolator", "double-fp", "FILE", "--outer-f-max-range", "0.04", "0.08"],
     "--outer-f-max-range: does not apply to --isolator double-fp"),
    (["--isolator", "double-fp", "FILE"], "give at least one of --radius-scale-range"),
    (["--isolator", "double-fp", "--surface-f-max-range", "0.04", "0.08"], "--isolator-file: --isolator double-fp designs"),
    (["--isolator", "double-fp", "FILE", "--surface-f-max-range", "0.04", "0.7"], "--surface-f-max-range: bounds"),
    (["--isolator", "double-fp", "--isolator-file", str(TRIPLE_FILE), "--radius-scale-range", "1", "2"],
     "holds a triple-fp isolator"),
    (["--isolator", "triple-fp", "--isolator-file", str(TRIPLE_FILE), "--radius-scale-range", "1", "2"],
     "--radius-scale-range: does not apply to --isolator triple-fp"),
    (["--surface-f-max-range", "0.04", "0.08"], "--surface-f-max-range: applies to --isolator double-fp only"),
    (["--capacity-scale-range", "0.5", "1"], "--capacity-scale-range: applies to --isolator triple-fp or double-fp"),
])
def test_the_design_command_refuses_wrong_combinations(tmp_path, capsys, isolator_file, flags, message):
    assert message in design_refusal(tmp_path, capsys, isolator_file, flags)


@pytest.mark.slow
def test_the_design_command_meets_a_binding_limit(tmp_path, capsys, isolator_file):
    """The 95th percentile's gradient check (1e-4) passes at the optimum, inside the bounds."""
    flags = ["--isolator", "double-fp", "--surface-f-max-range", "0.03", "0.09"]
    payload = design_payload(tmp_path, capsys, isolator_file, flags)
    optimum = payload["optimum"]
    assert optimum["disp_limit_met"] and 0.03 < optimum["surface_f_max"] < 0.09
    assert payload["p95_disp_gradient_rel_error"] <= 1e-4
