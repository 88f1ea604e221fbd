"""The reducers over a `StructureResponse` (`teflon_jax.studies`): each one against its closed
form on hand-made histories whose peaks are known (sines sampled at their crests), and the
command line's peaks equal to the reducers over `simulate_history` of the same structure."""

import json

import jax.numpy as jnp
import numpy as np
import pytest

from teflon_jax.cli import main
from teflon_jax.excitation import uniform_signal
from teflon_jax.formats import load_isolator
from teflon_jax.studies import (
    ResponseLayout,
    base_shear_ratio,
    first_storey_shear_ratio,
    isolator_force,
    level_acceleration,
    response_layout,
    response_peaks,
    slider_travel,
    storey_drift,
)
from teflon_jax.systems import StructureResponse, simulate_history, triple_structure
from teflon_jax.tables import load_table2
from teflon_jax.units import STANDARD_GRAVITY as G

T = jnp.linspace(0.0, 1.0, 401)  # t = 0.25, 0.5, 0.75 are samples: the sines' crests
SIN, COS = jnp.sin(2 * jnp.pi * T), jnp.cos(2 * jnp.pi * T)
MASS = jnp.array([2.0, 3.0, 5.0])  # base slab, floors 1 and 2 [kg]
DISP = jnp.array([0.10, 0.13, 0.17])  # amplitudes [m]
ACC = jnp.array([1.0, 2.0, 4.0])  # total acceleration amplitudes [m/s^2]
GROUND = 0.7 * jnp.sin(6 * jnp.pi * T)  # a ground motion unlike the structure's


def _response(displacement, total, ground, **parts):
    return StructureResponse(time=T, displacement=displacement, velocity=jnp.zeros_like(displacement),
                             total_acceleration=total, ground=ground, **parts)


def _building_one():
    """Three masses along one component: u_j = D_j sin, a_j^total = A_j sin, friction mu W sin."""
    layout = ResponseLayout(((0, 1, 2),), MASS, jnp.ones((3, 1)))
    response = _response(DISP * SIN[:, None], ACC * SIN[:, None], GROUND[:, None], friction_force=-0.3 * SIN)
    return layout, response


def _building_two():
    """The same building under two components turning in the plane: (x, y) = (cos, sin) times
    each amplitude, so every resultant is constant and equal to its amplitude."""
    influence = jnp.repeat(jnp.eye(2), 3, axis=0)
    layout = ResponseLayout(((0, 1, 2), (3, 4, 5)), jnp.concatenate([MASS, MASS]), influence)
    disp = jnp.concatenate([DISP * COS[:, None], DISP * SIN[:, None]], axis=1)
    total = jnp.concatenate([ACC * COS[:, None], ACC * SIN[:, None]], axis=1)
    force = jnp.stack([0.4 * COS, 0.4 * SIN], axis=-1)[:, None, :] * jnp.array([[0.25], [0.75]])  # 2 groups
    return layout, _response(disp, total, jnp.stack([GROUND, 0 * GROUND], -1), friction_force=force)


def test_one_component_building_peaks_are_their_closed_forms():
    layout, response = _building_one()
    peaks = response_peaks(layout, response, storey_height=3.0)
    weight = G * float(MASS.sum())
    assert float(peaks["base_disp"][0]) == pytest.approx(0.10, rel=1e-14)
    # the bearings' shear over the weight they carry: every mass, the base slab's included
    assert float(peaks["base_shear_ratio_resultant"]) == pytest.approx(float(MASS @ ACC) / weight, rel=1e-14)
    assert float(peaks["first_storey_shear_ratio_resultant"]) == pytest.approx(
        float(MASS[1:] @ ACC[1:]) / (G * float(MASS[1:].sum())), rel=1e-14)
    np.testing.assert_allclose(peaks["storey_drift_resultant"], [0.03, 0.04], rtol=1e-12)
    np.testing.assert_allclose(peaks["storey_drift_ratio"], [[0.01, 0.04 / 3]], rtol=1e-12)
    # total accelerations, not relative ones (the ground differs from the structure's motion)
    np.testing.assert_allclose(peaks["level_acceleration"], [ACC], rtol=1e-14)
    assert float(peaks["isolator_force_ratio_resultant"]) == pytest.approx(0.3 / weight, rel=1e-14)
    assert storey_drift(layout, response).shape == (401, 1, 2)


def test_two_component_building_resultants_are_their_amplitudes():
    layout, response = _building_two()
    peaks = response_peaks(layout, response, storey_height=[2.0, 4.0])
    weight = G * float(MASS.sum())
    assert float(peaks["base_disp_resultant"]) == pytest.approx(0.10, rel=1e-14)
    np.testing.assert_allclose(peaks["base_disp"], [0.10, 0.10], rtol=1e-14)
    assert float(peaks["base_shear_ratio_resultant"]) == pytest.approx(float(MASS @ ACC) / weight, rel=1e-14)
    np.testing.assert_allclose(peaks["storey_drift_ratio_resultant"], [0.03 / 2, 0.04 / 4], rtol=1e-12)
    np.testing.assert_allclose(peaks["level_acceleration_resultant"], ACC, rtol=1e-14)
    # the groups' friction on the structure, summed and turned to the force resisting the base
    np.testing.assert_allclose(isolator_force(response), -0.4 * jnp.stack([COS, SIN], -1), atol=1e-15)
    assert float(peaks["isolator_force_ratio_resultant"]) == pytest.approx(0.4 / weight, rel=1e-14)
    shear = base_shear_ratio(layout, response)
    np.testing.assert_allclose(shear, float(MASS @ ACC) / weight * jnp.stack([COS, SIN], -1), atol=1e-15)
    first = first_storey_shear_ratio(layout, response)
    np.testing.assert_allclose(first[:, 1], float(MASS[1:] @ ACC[1:]) / (G * float(MASS[1:].sum())) * SIN,
                               atol=1e-15)
    np.testing.assert_allclose(level_acceleration(layout, response)[:, 1], ACC * SIN[:, None], atol=1e-15)


def test_slab_peaks_and_sliders():
    """A slab (x, y, rotation), its rotational inertia out of the shear; series sliders per group."""
    layout = ResponseLayout(((0,), (1,)), jnp.array([4.0, 4.0, 50.0]),
                            jnp.array([[1.0, 0.0], [0.0, 1.0], [0.0, 0.0]]), rotation=2)
    q = jnp.stack([0.2 * SIN, 0.1 * SIN, 0.01 * COS], -1)
    total = jnp.stack([3.0 * SIN, 4.0 * SIN, 9.0 * COS], -1)
    slider = jnp.stack([0.03 * COS, 0.04 * COS], -1)[:, None, None, :] * jnp.ones((1, 2, 3, 1))  # (nt, G, S, 2)
    bearing = jnp.stack([0.2 * SIN, 0.1 * SIN], -1)[:, None, :] * jnp.ones((1, 2, 1))
    loads = jnp.stack([5.0 + SIN, 5.0 - 2 * SIN], -1)
    response = _response(q, total, jnp.zeros((401, 2)), slider=slider, bearing_displacement=bearing,
                         normal_load=loads, group_uplift_time=jnp.array([0.0, 0.5]))
    peaks = response_peaks(layout, response)
    assert float(peaks["base_disp_resultant"]) == pytest.approx(float(jnp.hypot(0.2, 0.1)), rel=1e-14)
    assert float(peaks["base_shear_ratio_resultant"]) == pytest.approx(5.0 / G, rel=1e-14)
    assert float(peaks["rotation"]) == pytest.approx(0.01, rel=1e-14)
    np.testing.assert_allclose(peaks["slider_travel"], np.full((2, 3), 0.05), rtol=1e-14)
    np.testing.assert_allclose(peaks["group_disp_resultant"], np.full(2, float(jnp.hypot(0.2, 0.1))), rtol=1e-14)
    assert "group_normal_load" not in peaks  # the groups share the weight evenly: no result
    loads_peaks = response_peaks(layout._replace(overturning=True), response)["group_normal_load"]
    np.testing.assert_allclose(loads_peaks["peak_N"], [6.0, 7.0], rtol=1e-14)
    np.testing.assert_allclose(loads_peaks["min_N"], [4.0, 3.0], rtol=1e-14)
    np.testing.assert_allclose(slider_travel(response)[:, 0, 0], 0.05 * jnp.abs(COS), atol=1e-15)


def _record(path, dt=0.01, n=401):
    t = dt * np.arange(n)
    a = 0.3 * np.sin(2 * np.pi * t) * np.sin(np.pi * t / t[-1]) ** 2
    path.write_text("time acc\n" + "\n".join(f"{ti:.4f} {ai:.6e}" for ti, ai in zip(t, a)) + "\n")
    return np.asarray([float(f"{ai:.6e}") for ai in a]) * G


def _isolator_file(path):
    def surface(radius, capacity, f_max):
        return {"radius": {"value": radius, "unit": "in"}, "capacity": {"value": capacity, "unit": "in"},
                "friction": {"f_max": {"value": f_max, "unit": "1"}, "delta_f": {"value": 0.01, "unit": "1"},
                             "rate_a": {"value": 0.5, "unit": "s/in"}}}

    path.write_text(json.dumps({"format": "teflon-jax isolator", "format_version": 1, "isolator": "triple-fp",
                                "surfaces": {"inner": surface(12, 2, 0.02), "bottom": surface(84, 12, 0.06),
                                             "top": surface(84, 14, 0.10)},
                                "yield_disp": {"value": 0.004, "unit": "in"}}))
    return path


def test_run_peaks_are_the_reducers_over_the_history(tmp_path, capsys):
    """`run` on a building on triple pendulums (one component): its JSON peaks are the reducers
    over `simulate_history` of the same structure, and its base shear the bearings' whole force
    sum_j m_j a_j^total over g sum_j m_j (every mass, as on flat sliders)."""
    acc = _record(tmp_path / "x.txt")
    isolator = _isolator_file(tmp_path / "tfp.json")
    out = tmp_path / "run.json"
    assert main(["run", "--structure", "building", "--record-x", str(tmp_path / "x.txt"), "--record-units", "g",
                 "--isolator", "triple-fp", "--isolator-file", str(isolator), "--json", str(out)]) == 0
    capsys.readouterr()
    peak = json.loads(out.read_text())["peak"]
    system = triple_structure("building", load_isolator(isolator), uniform_signal(acc, 0.01), time_step=0.0025,
                              weight=100e3)
    response = simulate_history(system, 4.0)
    values = response_peaks(response_layout(system), response, storey_height=load_table2().storey_height)
    mass, total = np.asarray(system.mass), np.asarray(response.total_acceleration)
    shear = np.max(np.abs(total @ mass)) / (G * mass.sum())
    assert peak["base_shear_ratio_resultant"] == pytest.approx(shear, rel=1e-9)
    assert peak["base_shear_ratio_resultant"] == pytest.approx(float(values["base_shear_ratio_resultant"]), rel=1e-9)
    assert peak["base_disp_x_m"] == pytest.approx(float(values["base_disp"][0]), rel=1e-9)
    assert peak["bearing_force_ratio_resultant"] == pytest.approx(
        float(values["isolator_force_ratio_resultant"]), rel=1e-9)
    assert peak["first_storey_shear_ratio_resultant"] == pytest.approx(
        np.max(np.abs(total[:, 1:] @ mass[1:])) / (G * mass[1:].sum()), rel=1e-9)
    np.testing.assert_allclose(peak["floor_acceleration_resultant_g"],
                               np.max(np.abs(total[:, 1:]), axis=0) / G, rtol=1e-9)
    np.testing.assert_allclose(peak["storey_drift_ratio_x"], values["storey_drift_ratio"][0], rtol=1e-9)
    np.testing.assert_allclose(list(peak["slider_disp_m"].values()), values["slider_travel"], rtol=1e-9)
    assert peak["base_disp_y_m"] == 0.0 and max(peak["storey_drift_ratio_y"]) == 0.0
