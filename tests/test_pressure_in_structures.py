"""A pressure-dependent bearing in the structures: the law mu *= (N / N_ref)^-exponent taken at
the load N = p A of the bearings' contact pressure p (constant in a structure, so a constant
factor on the friction), in one and two directions, on the slab per bearing group and in the
commands.

Peer: the same structure with f_max and delta_f multiplied by the factor written out here.
"""

import dataclasses
import json

import equinox as eqx
import jax.numpy as jnp
import numpy as np
import pytest
from histories import assert_plane_follows_line

import teflon_jax as tj
from teflon_jax.bearing import PressureDependence
from teflon_jax.formats import bearing_to_dict, save_bearing
from teflon_jax.units import INCH, KIP, PSI

UF, UF_B = tj.interface_parameters("UF", 1000 * PSI, "P")
AREA = 20.0 * INCH**2
TEST_LOAD = 20.0 * KIP  # tested at 1000 psi on 20 in^2
EXPONENT = 0.3


def _pressure_bearing(exponent=EXPONENT, area=AREA):
    plain = tj.paper_bearing(UF, breakaway_ratio=UF_B)
    return eqx.tree_at(lambda b: b.pressure_dependence, plain,
                       PressureDependence(exponent, TEST_LOAD, area), is_leaf=lambda x: x is None)


def _scaled_by_hand(factor):
    friction = tj.FrictionParameters(UF.f_max * factor, UF.delta_f * factor, UF.rate_a)
    return tj.paper_bearing(friction, breakaway_ratio=UF_B)


def _signal(duration=8.0, dt=0.01, peak=3.0):
    t = np.arange(0, duration, dt)
    return tj.uniform_signal(jnp.asarray(peak * np.sin(2 * np.pi * 0.5 * t) * np.exp(-0.2 * t)), dt)


def test_the_factor_is_the_law_at_the_load_of_the_pressure():
    bearing = _pressure_bearing()
    at_double = bearing.at_contact_pressure(2000 * PSI)
    assert at_double.pressure_dependence is None
    assert float(at_double.friction.f_max) == pytest.approx(float(UF.f_max) * 2**-EXPONENT, rel=1e-13)
    assert float(at_double.friction.delta_f) == pytest.approx(float(UF.delta_f) * 2**-EXPONENT,
                                                             rel=1e-13)
    at_test = bearing.at_contact_pressure(1000 * PSI)
    assert float(at_test.friction.f_max) == pytest.approx(float(UF.f_max), rel=1e-13)


@pytest.mark.parametrize("kind,period", [("rigid", None), ("building", 2.5)])
def test_one_direction_runs_the_bearing_at_its_pressure(kind, period):
    from teflon_jax.systems import isolated_structure, peak_response

    signal = _signal()
    options = dict(isolation_period=period, pressure=2500 * PSI)
    with_part = isolated_structure(kind, bearing=_pressure_bearing(), **options)(signal)
    by_hand = isolated_structure(kind, bearing=_scaled_by_hand(2.5**-EXPONENT), **options)(signal)
    unscaled = isolated_structure(kind, bearing=_scaled_by_hand(1.0), **options)(signal)
    a, b, c = (peak_response(s, 7.5) for s in (with_part, by_hand, unscaled))
    assert float(a.base_disp) == pytest.approx(float(b.base_disp), rel=1e-12)
    assert float(a.base_shear_ratio) == pytest.approx(float(b.base_shear_ratio), rel=1e-12)
    # less friction at the higher pressure: the part changes the answer
    assert float(a.base_disp) > 1.05 * float(c.base_disp)


def test_design_gradient_in_pressure_reaches_the_pressure_dependence():
    """d(peak)/d(pressure) of a given pressure-dependent bearing against central differences."""
    import jax

    from teflon_jax.systems import isolated_structure, peak_response

    structure = isolated_structure("rigid", bearing=_pressure_bearing(), isolation_period=2.5,
                                   pressure=2000 * PSI)
    signal = _signal()

    def peak(p):
        return peak_response(structure(signal, {"pressure": p}), 7.5).base_disp

    p0 = 2000 * PSI
    grad = float(jax.grad(peak)(p0))
    h = 1 * PSI  # the peak is a max over steps: a larger h crosses to another step's peak
    central = (float(peak(p0 + h)) - float(peak(p0 - h))) / (2 * h)
    assert grad > 0
    assert grad == pytest.approx(central, rel=1e-5)


def test_two_directions_run_the_bearing_at_its_pressure():
    from teflon_jax.studies import bidirectional_isolated_structure
    from teflon_jax.systems import peak_response

    gx, gy = _signal(6.0), _signal(6.0, peak=2.0)
    options = dict(isolation_period=2.5, pressure=3000 * PSI)
    a = bidirectional_isolated_structure("rigid", bearing=_pressure_bearing(), **options)((gx, gy))
    b = bidirectional_isolated_structure("rigid", bearing=_scaled_by_hand(3.0**-EXPONENT),
                                         **options)((gx, gy))
    pa, pb = peak_response(a, 5.5), peak_response(b, 5.5)
    assert float(pa.base_disp) == pytest.approx(float(pb.base_disp), rel=1e-12)


def _plain_pressure_bearing():
    """UF with its pressure dependence and no breakaway (whose switch reads Z's running peak
    one step apart in a structure and in a test)."""
    return eqx.tree_at(lambda b: b.pressure_dependence, tj.paper_bearing(UF),
                       PressureDependence(EXPONENT, TEST_LOAD, AREA), is_leaf=lambda x: x is None)


def _vertical_pair(duration=8.0, dt=0.01):
    t = np.arange(0, duration, dt)
    vertical = 4.0 * np.sin(2 * np.pi * 2.3 * t) * np.exp(-0.15 * t)  # N from about 0.6 W to 1.4 W
    return _signal(duration, dt), tj.uniform_signal(jnp.asarray(vertical), dt)


def test_under_a_vertical_record_the_friction_follows_the_pressure_as_in_the_bearings_test():
    """The rigid mass on a pressure-dependent bearing under a vertical record: its friction
    force at every step is the bearing test's along the structure's path (displacement and
    velocity of the isolator) under the load of one bearing s p A, scaled to the structure's
    weight: mu (s p A / N_ref)^-e s W Z. Held at the static pressure, as before, it is not."""
    from teflon_jax.systems import (
        imposed_path_test,
        isolated_structure,
        sampled_path,
        simulate_history,
        with_vertical_component,
    )

    pressure = 2500 * PSI
    bearing = _plain_pressure_bearing()
    structure = with_vertical_component(isolated_structure(
        "rigid", bearing=bearing, pressure=pressure, split_at_turn=False, newton_tolerance=0.0))
    system = structure(_vertical_pair())
    assert float(system.pressure_exponent) == EXPONENT
    response = simulate_history(system, 7.5)
    weight, s = float(system.bearing_load), np.asarray(response.load_factor)
    assert bool(response.succeeded) and s.min() > 0.3 and np.ptp(s) > 0.5
    path = sampled_path(np.asarray(response.time), np.asarray(response.displacement[:, 0]), s * pressure * AREA,
                        velocity=np.asarray(response.velocity[:, 0]))
    test = imposed_path_test(bearing, path)
    friction = np.asarray(response.friction_force)
    np.testing.assert_allclose(np.asarray(test.fx) * weight / (pressure * AREA), friction, rtol=0,
                               atol=1e-9 * weight)
    held = simulate_history(dataclasses.replace(system, pressure_exponent=None), 7.5)
    assert np.max(np.abs(np.asarray(held.friction_force) - friction)) > 1e-3 * weight


def test_under_a_vertical_record_two_directions_along_a_line_are_the_one_direction():
    """The same bearing and vertical record under two components whose y record is zero: the
    x response is the one-component response (both solved to rounding, Newmark's rule, no
    split of a step at a turn), the friction following the pressure in both."""
    from teflon_jax.studies import bidirectional_isolated_structure
    from teflon_jax.systems import (
        isolated_structure,
        with_vertical_component,
    )

    horizontal, vertical = _vertical_pair()
    zero = tj.uniform_signal(jnp.zeros(800), 0.01)
    options = dict(bearing=_plain_pressure_bearing(), pressure=2500 * PSI, time_step=0.0025, newton_tolerance=0.0)
    line = with_vertical_component(isolated_structure("rigid", linear_rule="newmark", split_at_turn=False,
                                                      **options))((horizontal, vertical))
    plane = with_vertical_component(bidirectional_isolated_structure("rigid", **options))(((horizontal, zero),
                                                                                           vertical))
    plane = dataclasses.replace(plane, newton_tolerance=0.0)
    assert float(plane.pressure_exponent) == EXPONENT
    assert_plane_follows_line(line, plane, 7.5, moves=0.02, without={"pressure_exponent": None}, changes=1e-4)


def test_without_the_contact_area_a_structure_refuses_by_key():
    with pytest.raises(ValueError, match="parts.pressure_dependence.contact_area"):
        tj.systems.isolated_structure("rigid", bearing=_pressure_bearing(area=None),
                                      pressure=2000 * PSI)
    with pytest.raises(ValueError, match="at_contact_pressure"):
        tj.systems.rigid_mass(weight=1e5, bearing=_pressure_bearing(), ground_acceleration=_signal(),
                              time_step=0.005)


def test_the_bearing_file_keeps_the_optional_contact_area(tmp_path):
    from teflon_jax.formats import bearing_from_dict

    document = bearing_to_dict(_pressure_bearing())
    assert document["parts"]["pressure_dependence"]["contact_area"]["unit"] == "m^2"
    again = bearing_from_dict(document)
    assert float(again.pressure_dependence.contact_area) == pytest.approx(AREA, rel=1e-15)
    del document["parts"]["pressure_dependence"]["contact_area"]
    assert bearing_from_dict(document).pressure_dependence.contact_area is None


def _at2(path, values, dt=0.01):
    lines = ["PEER", "test", "ACCELERATION TIME SERIES IN UNITS OF G",
             f"NPTS= {len(values)}, DT= {dt:.4f} SEC"]
    lines += [" ".join(f"{v:.7e}" for v in values[i:i + 5]) for i in range(0, len(values), 5)]
    path.write_text("\n".join(lines) + "\n")
    return path


def _run_peak(tmp_path, name, argv):
    from teflon_jax.cli import main

    out = tmp_path / f"peaks_{name}.json"
    code = main(["run", *map(str, argv), "--duration", "5s", "--json", str(out)])
    assert code == 0
    return json.loads(out.read_text())["peak"]["base_disp_resultant_m"]


@pytest.mark.slow
def test_run_and_the_slab_take_each_pressure(tmp_path):
    """`run --bearing`: the pressure-dependent file at --pressure gives the hand-scaled file's
    peaks; on the slab, each group at the pressure of its line in the plan."""
    t = np.arange(0, 6.0, 0.01)
    records = ["--record-x", _at2(tmp_path / "x.AT2", 0.3 * np.sin(2 * np.pi * 0.5 * t)),
               "--record-y", _at2(tmp_path / "y.AT2", 0.2 * np.cos(2 * np.pi * 0.4 * t))]
    save_bearing(tmp_path / "pd.json", _pressure_bearing())
    save_bearing(tmp_path / "hand.json", _scaled_by_hand(2.0**-EXPONENT))
    rigid = ["--structure", "rigid", *records]
    pd = _run_peak(tmp_path, "pd", rigid + ["--bearing", tmp_path / "pd.json", "--pressure", "2000psi"])
    hand = _run_peak(tmp_path, "hand", rigid + ["--bearing", tmp_path / "hand.json"])
    tested = _run_peak(tmp_path, "pd1", rigid + ["--bearing", tmp_path / "pd.json",
                                                 "--pressure", "1000psi"])
    assert pd == pytest.approx(hand, rel=1e-12)
    assert pd > 1.05 * tested

    def slab(name, file, pressures):
        groups = [{"name": "W", "x": "0m", "y": "5m", "load": "500kN"},
                  {"name": "E", "x": "20m", "y": "5m", "load": "500kN"}]
        for group, pressure in zip(groups, pressures):
            group.update({"pressure": pressure} if pressure else {})
        plan = {"length_x": "20m", "length_y": "10m", "weight": "1000kN", "groups": groups}
        (tmp_path / f"{name}_plan.json").write_text(json.dumps(plan))
        return _run_peak(tmp_path, name, ["--structure", "slab", "--plan",
                                          tmp_path / f"{name}_plan.json", *records,
                                          "--isolation-period", "2.5s", "--bearing", file])

    same = slab("slab_pd", tmp_path / "pd.json", ("2000psi", "2000psi"))
    assert same == pytest.approx(slab("slab_hand", tmp_path / "hand.json", (None, None)),
                                 rel=1e-12)
    assert slab("slab_mixed", tmp_path / "pd.json", ("1000psi", "2000psi")) < same


def test_run_under_a_vertical_record_follows_the_pressure_of_a_bearing_file(tmp_path):
    """`run --bearing --record-z`: the pressure-dependent file at 2000 psi against the file
    with its friction written out at that pressure: under a vertical record (N from about 0.5 W
    to 1.5 W) the pressure-dependent bearing's friction follows N, the other's does not."""
    t = np.arange(0, 6.0, 0.01)
    records = ["--record-x", _at2(tmp_path / "x.AT2", 0.3 * np.sin(2 * np.pi * 0.5 * t)),
               "--record-z", _at2(tmp_path / "z.AT2", 0.5 * np.sin(2 * np.pi * 3.1 * t))]
    save_bearing(tmp_path / "pd.json", _pressure_bearing())
    save_bearing(tmp_path / "hand.json", _scaled_by_hand(2.0**-EXPONENT))
    pd = _run_peak(tmp_path, "pd", records + ["--bearing", tmp_path / "pd.json", "--pressure", "2000psi"])
    hand = _run_peak(tmp_path, "hand", records + ["--bearing", tmp_path / "hand.json"])
    assert abs(pd - hand) > 1e-3 * hand
