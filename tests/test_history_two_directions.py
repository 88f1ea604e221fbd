"""Heating and wear in two directions: each group's heat states and travel carried step by step
with the flux of the resultant sliding speed, q = mu p |v| / n.

Peers: the one-direction structure (the same law, its own code path) under a record along x;
the same structure under the record turned by 45 degrees (an isotropic bearing gives the same
resultant); the cold bearing (heating lowers the friction); the full simulation against the
peak loop of Monte Carlo.
"""

import dataclasses
import math

import equinox as eqx
import jax.numpy as jnp
import numpy as np
import pytest

import teflon_jax as tj
from teflon_jax.bearing import FrictionalHeating, Wear
from teflon_jax.units import INCH, PSI

UF, UF_B = tj.interface_parameters("UF", 1000 * PSI, "P")
AREA = 10.0 * INCH**2
PRESSURE = 3000 * PSI
DT = 0.005


def _bearing(heat_scale=3.0, wear=None):
    plain = tj.paper_bearing(UF, breakaway_ratio=UF_B)
    parts = {"heating": FrictionalHeating(contact_area=AREA, heat_scale=heat_scale)}
    if wear is not None:
        parts["wear"] = Wear(wear, 1.0)
    return eqx.tree_at(lambda b: (b.heating, b.wear), plain,
                       (parts["heating"], parts.get("wear")), is_leaf=lambda x: x is None)


def _record(duration=10.0, peak=4.0):
    t = np.arange(0, duration, 0.01)
    return peak * np.sin(2 * np.pi * 0.4 * t) * np.exp(-0.15 * t)


def _two(bearing, ax, ay, **options):
    from teflon_jax.systems import rigid_mass

    return rigid_mass(components=2,
        weight=1e5, bearing=bearing, ground_acceleration=tj.uniform_signal(jnp.asarray(ax), 0.01),
        ground_y=tj.uniform_signal(jnp.asarray(ay), 0.01), time_step=DT,
        isolation_period=2.5, contact_pressure=PRESSURE, **options)


@pytest.mark.parametrize("wear", [pytest.param(None, marks=pytest.mark.slow), 0.5])
def test_along_x_two_directions_are_the_one_direction_structure(wear):
    from teflon_jax.systems import rigid_mass, simulate_history

    ag = _record()
    bearing = _bearing(wear=wear)
    one = rigid_mass(weight=1e5, bearing=bearing, time_step=DT, isolation_period=2.5,
                     ground_acceleration=tj.uniform_signal(jnp.asarray(ag), 0.01),
                     contact_pressure=PRESSURE)
    # both solved to rounding, so that the two codes' tolerances do not show
    a = simulate_history(dataclasses.replace(one, newton_tolerance=0.0), 9.0)
    two = dataclasses.replace(_two(bearing, ag, 0 * ag), newton_tolerance=0.0)
    b = simulate_history(two, 9.0)
    np.testing.assert_allclose(b.displacement[:, 0], a.displacement[:, 0], rtol=0, atol=1e-10)
    np.testing.assert_allclose(b.friction_force[:, 0, 0], a.friction_force, rtol=1e-7, atol=1e-6)
    cold = simulate_history(dataclasses.replace(
        one, newton_tolerance=0.0, bearing=tj.paper_bearing(UF, breakaway_ratio=UF_B)), 9.0)
    assert float(np.max(np.abs(cold.displacement[:, 0] - a.displacement[:, 0]))) > 1e-3


def test_the_flux_follows_the_resultant_speed():
    """A record along 45 degrees gives the resultant of the record along x (isotropic bearing)."""
    from teflon_jax.systems import simulate_history

    ag = _record()
    along_x = simulate_history(_two(_bearing(), ag, 0 * ag), 9.0)
    diagonal = simulate_history(_two(_bearing(), ag / math.sqrt(2), ag / math.sqrt(2)), 9.0)
    resultant = np.hypot(diagonal.displacement[:, 0], diagonal.displacement[:, 1])
    np.testing.assert_allclose(resultant, np.abs(along_x.displacement[:, 0]), rtol=0, atol=1e-8)


def test_heating_in_two_directions_lowers_friction_and_the_peak_loop_agrees():
    from teflon_jax.systems import peak_response, simulate_history

    ax, ay = _record(), 0.7 * _record(peak=3.0)[::-1].copy()
    hot = _two(_bearing(), ax, ay)
    cold = _two(_bearing(heat_scale=0.0), ax, ay)
    assert hot.history and cold.history
    peak_hot, peak_cold = peak_response(hot, 9.0), peak_response(cold, 9.0)
    assert float(peak_hot.base_disp) > 1.02 * float(peak_cold.base_disp)
    full = simulate_history(hot, 9.0)
    resultant = np.hypot(full.displacement[:, 0], full.displacement[:, 1])
    assert float(np.max(resultant)) == pytest.approx(float(peak_hot.base_disp), rel=1e-9)
    plain = _two(tj.paper_bearing(UF, breakaway_ratio=UF_B), ax, ay)
    assert float(peak_response(plain, 9.0).base_disp) == pytest.approx(
        float(peak_cold.base_disp), rel=1e-12)


def test_each_slab_group_heats_at_its_own_pressure():
    """Two groups at 1000 and 4000 psi: the slab with both at 1000 psi differs, and the high
    pressure group's friction ends lower (hotter steel)."""
    from teflon_jax.systems import simulate_history, slab_on_bearings

    ag = _record(8.0)
    signal = tj.uniform_signal(jnp.asarray(ag), 0.01)

    def slab(pressures):
        return slab_on_bearings(
            length_x=20.0, length_y=10.0, weight=1e6, centre_of_mass=(10.0, 5.0),
            positions=[(0.0, 5.0), (20.0, 5.0)], bearings=_bearing(), loads=[5e5, 5e5],
            ground_acceleration=signal, ground_y=tj.uniform_signal(jnp.asarray(0.5 * ag), 0.01),
            time_step=DT, isolation_period=2.5, contact_pressures=pressures)

    mixed = simulate_history(slab([1000 * PSI, 4000 * PSI]), 7.0)
    low = simulate_history(slab([1000 * PSI, 1000 * PSI]), 7.0)
    assert float(np.max(np.abs(mixed.displacement[:, 0] - low.displacement[:, 0]))) > 1e-4
    # the same sliding in both groups (no rotation excited at first): the hotter one slides
    # with less force at the end
    fx = np.abs(mixed.friction_force[-200:, :, 0]).max(axis=0)
    assert fx[1] < fx[0]


def test_two_directions_need_the_contact_pressure_of_a_heating_bearing():
    from teflon_jax.systems import rigid_mass

    signal = tj.uniform_signal(jnp.asarray(_record()), 0.01)
    with pytest.raises(ValueError, match="contact_pressure"):
        rigid_mass(components=2, weight=1e5, bearing=_bearing(), ground_acceleration=signal, time_step=DT)


@pytest.mark.slow
def test_montecarlo_with_two_components_runs_a_heating_bearing(tmp_path):
    """`montecarlo --components 2 --bearing`: the heating bearing moves more than the cold one
    on the same motions (the command ran it, it did not drop the part)."""
    import json

    from teflon_jax.cli import main

    tj.save_bearing(tmp_path / "hot.json", _bearing())
    tj.save_bearing(tmp_path / "cold.json", _bearing(heat_scale=0.0))
    medians = {}
    for name in ("hot", "cold"):
        out = tmp_path / f"{name}_mc.json"
        code = main(["montecarlo", "--components", "2", "--motions", "4", "--duration", "12s",
                     "--structure", "rigid", "--isolation-period", "2.5s", "--no-progress",
                     "--bearing", str(tmp_path / f"{name}.json"), "--pressure", "3000psi",
                     "--json", str(out)])
        assert code == 0
        medians[name] = json.loads(out.read_text())
    hot, cold = (medians[k]["statistics"]["base_disp_in"]["p50"] for k in ("hot", "cold"))
    assert hot > 1.05 * cold
