"""Table 1's bearings under a vertical record: Eq. 1's constants and the breakaway ratio at the
momentary contact pressure s p, in one and two directions and in `run --record-z`.

Peer: Table 1's rows (Constantinou, Mokha & Reinhorn 1990; UF sliding along the lay) written
out here, interpolated linearly in the pressure by hand, the first segment extended below
1000 psi. Under a constant load factor s the structure is the one whose constants are those of
the row at s p; under a varying one its friction force at every step is Eq. 1 at the
pressure of that step times s W Z. Held at the static pressure, as a given bearing without a
pressure dependence is, the answer differs.
"""

import dataclasses
import json

import jax.numpy as jnp
import numpy as np
import pytest
from histories import assert_plane_follows_line

from teflon_jax.bearing import FrictionParameters, paper_bearing
from teflon_jax.excitation import uniform_signal
from teflon_jax.formats import save_bearing
from teflon_jax.systems import (
    isolated_structure,
    rigid_mass,
    simulate_history,
    with_vertical_component,
    with_vertical_motion,
)
from teflon_jax.tables import friction_table
from teflon_jax.units import INCH, PSI, STANDARD_GRAVITY

ROWS = np.array([  # UF, P: p [psi], f_max [%], delta_f [%], a [s/in], b
    [1000, 11.93, 9.27, 0.60, 2.2],
    [2000, 8.70, 6.95, 0.60, 2.3],
    [3000, 7.03, 5.52, 0.80, 3.7],
    [6500, 5.72, 4.85, 0.50, 4.3],
])


def _row(pressure):
    """(Eq. 1's constants, b) of UF along the lay at `pressure` [Pa], by hand: linear between
    the rows, the first segment extended below 1000 psi."""
    p = pressure / PSI
    i = int(np.clip(np.searchsorted(ROWS[:, 0], p) - 1, 0, len(ROWS) - 2))
    (p0, *c0), (p1, *c1) = ROWS[i], ROWS[i + 1]
    f_max, delta_f, rate, b = np.asarray(c0) + (np.asarray(c1) - np.asarray(c0)) * (p - p0) / (p1 - p0)
    return FrictionParameters(f_max / 100, delta_f / 100, rate / INCH), b


def _horizontal(duration=8.0, dt=0.01):
    t = np.arange(0.0, duration + 1e-9, dt)
    return uniform_signal(jnp.asarray(3.0 * np.sin(2 * np.pi * t / 1.5) * np.minimum(t / 2, 1)), dt)


def _vertical(values, duration=8.0, dt=0.01):
    t = np.arange(0.0, duration + 1e-9, dt)
    return uniform_signal(jnp.asarray(np.broadcast_to(values(t), t.shape), float), dt)


@pytest.mark.parametrize("pressure_psi, a_v", [(2000, 0.3), (1500, -0.4)])
def test_under_a_constant_load_factor_the_bearing_runs_at_the_row_of_that_pressure(pressure_psi, a_v):
    """s = 1 + a_v / g held: 2600 psi between two rows, and 900 psi below the first one (its
    segment extended). The structure's displacement is that of the same structure with the
    constants and b of the row at s p written out, to rounding; held at p it is not."""
    structure = with_vertical_component(isolated_structure("rigid", pressure=pressure_psi * PSI, ptfe="UF"))
    system = structure((_horizontal(), _vertical(lambda t: a_v * STANDARD_GRAVITY + 0 * t)))
    assert system.pressure_table is not None
    friction, b = _row((1 + a_v) * pressure_psi * PSI)
    by_hand = dataclasses.replace(system, pressure_table=None, bearing=paper_bearing(friction, breakaway_ratio=b))
    held = dataclasses.replace(system, pressure_table=None)
    u, u_hand, u_held = (np.asarray(simulate_history(s, 7.5).displacement[:, 0]) for s in (system, by_hand, held))
    assert np.max(np.abs(u_hand)) > 0.05
    np.testing.assert_allclose(u, u_hand, rtol=0, atol=1e-9 * np.max(np.abs(u_hand)))
    assert np.max(np.abs(u_held - u_hand)) > 0.03 * np.max(np.abs(u_hand))


def test_under_a_varying_record_the_friction_is_eq1_at_the_pressure_of_each_step():
    """N from about 0.55 W to 1.45 W around 1500 psi: the rows 1000 and 2000 psi and the first
    segment's extension below 1000 psi are all crossed. At every step
    F = (f_max(s p) - delta_f(s p) exp(-a(s p) |v|)) s W Z (no breakaway here)."""
    pressure = 1500 * PSI
    structure = with_vertical_component(isolated_structure("rigid", pressure=pressure, ptfe="UF", breakaway=False))
    system = structure((_horizontal(), _vertical(lambda t: 0.45 * STANDARD_GRAVITY * np.sin(2 * np.pi * 2.3 * t))))
    response = simulate_history(system, 7.5)
    s, v, z = (np.asarray(a) for a in (response.load_factor, response.velocity[:, 0], response.z))
    assert bool(response.succeeded) and s.min() < 0.6 and s.max() > 1.4
    mu = []
    for factor, speed in zip(s, v):
        row = _row(factor * pressure)[0]
        mu.append(row.f_max - row.delta_f * np.exp(-row.rate_a * abs(speed)))
    weight = float(system.bearing_load)
    expected = np.asarray(mu) * s * weight * z
    np.testing.assert_allclose(np.asarray(response.friction_force), expected, rtol=0, atol=1e-9 * weight)


def test_two_directions_along_a_line_are_the_one_direction():
    """A zero y record under two components: the x response is the one-component response
    (Newmark's rule, no split of a step at a turn, solved to rounding), both following the
    table; without it the two components give another answer."""
    table, pressure = friction_table("UF", "P", extrapolate=True), 1500 * PSI
    friction, b = _row(pressure)
    bearing = paper_bearing(friction, breakaway_ratio=b)
    horizontal = _horizontal()
    vertical = _vertical(lambda t: 0.45 * STANDARD_GRAVITY * np.sin(2 * np.pi * 2.3 * t))
    zero = uniform_signal(jnp.zeros(801), 0.01)
    options = dict(weight=100e3, bearing=bearing, time_step=0.0025, isolation_period=3.0)
    line = dataclasses.replace(rigid_mass(ground_acceleration=horizontal, **options), newton_tolerance=0.0)
    plane = dataclasses.replace(rigid_mass(components=2, ground_acceleration=horizontal, ground_y=zero, **options),
                                newton_tolerance=0.0)
    law = dict(friction_table=table, table_pressure=pressure)
    line, plane = (with_vertical_motion(s, vertical, **law) for s in (line, plane))
    assert_plane_follows_line(line, plane, 7.5, moves=0.05, without={"pressure_table": None}, changes=1e-3)


def test_the_table_law_is_refused_where_it_cannot_apply():
    structure = rigid_mass(ground_acceleration=_horizontal(), bearing=paper_bearing(_row(1500 * PSI)[0]),
                           weight=100e3, time_step=0.005, isolation_period=3.0)
    vertical = _vertical(lambda t: 0 * t)
    table = friction_table("UF", "P", extrapolate=True)
    with pytest.raises(ValueError, match="table_pressure: give the contact pressure"):
        with_vertical_motion(structure, vertical, friction_table=table)
    with pytest.raises(ValueError, match="table_pressure: must be > 0"):
        with_vertical_motion(structure, vertical, friction_table=table, table_pressure=-1.0)
    with pytest.raises(ValueError, match="friction_table: give the FrictionTable"):
        with_vertical_motion(structure, vertical, friction_table="UF", table_pressure=1e7)
    with pytest.raises(ValueError, match="pressure_exponent: a bearing follows its contact pressure by one law"):
        with_vertical_motion(structure, vertical, friction_table=table, table_pressure=1e7, pressure_exponent=0.3)
    with pytest.raises(ValueError, match="friction_table: an anisotropic bearing takes the pair"):
        with_vertical_motion(structure, vertical, friction_table=(table, table), table_pressure=1e7)


def test_a_pressure_beyond_where_the_extended_rows_hold_stops_the_run():
    """At 6000 psi under s = 1.9 (11,400 psi) the last segment extended gives f_max below
    delta_f: the run stops with an error, not a clipped or silently wrong value."""
    structure = with_vertical_component(isolated_structure("rigid", pressure=6000 * PSI, ptfe="UF"))
    system = structure((_horizontal(), _vertical(lambda t: 0.9 * STANDARD_GRAVITY + 0 * t)))
    with pytest.raises(Exception, match="beyond where Table 1's extended end segments give Eq. 1 constants"):
        simulate_history(system, 2.0)


def _at2(path, values, dt=0.01):
    lines = ["PEER", "test", "ACCELERATION TIME SERIES IN UNITS OF G", f"NPTS= {len(values)}, DT= {dt:.4f} SEC"]
    lines += [" ".join(f"{v:.7e}" for v in values[i:i + 5]) for i in range(0, len(values), 5)]
    path.write_text("\n".join(lines) + "\n")
    return path


def _run(tmp_path, name, argv, capsys):
    from teflon_jax.cli import main

    out = tmp_path / f"{name}-peaks.json"
    code = main(["run", *map(str, argv), "--duration", "5s", "--json", str(out)])
    assert code == 0, capsys.readouterr().err
    return json.loads(out.read_text())


def test_run_reads_table_1_at_the_momentary_pressure(tmp_path, capsys):
    """`run --record-z` with Table 1's bearing at 2000 psi under a constant a_v = 0.3 g: the
    peaks of a bearing file holding the row at 2600 psi under the same record, which the
    note names; the file's constants are held, so they stand for the table at s p."""
    t = np.arange(0, 6.0, 0.01)
    records = ["--record-x", _at2(tmp_path / "x.AT2", 0.3 * np.sin(2 * np.pi * 0.5 * t)),
               "--record-z", _at2(tmp_path / "z.AT2", np.full(t.size, 0.3))]
    friction, b = _row(2600 * PSI)
    save_bearing(tmp_path / "row.json", paper_bearing(friction, breakaway_ratio=b))
    table = _run(tmp_path, "table", records + ["--pressure", "2000psi", "--breakaway", "table"], capsys)
    assert "Table 1 read from 2600 to 2600 psi" in capsys.readouterr().err
    assert any("Table 1 read from 2600 to 2600 psi" in note for note in table["notes"])
    row = _run(tmp_path, "row", records + ["--bearing", tmp_path / "row.json"], capsys)
    for key in ("base_disp_resultant_m", "base_shear_ratio_resultant", "friction_force_ratio_resultant"):
        assert table["peak"][key] == pytest.approx(row["peak"][key], rel=1e-9), key


@pytest.mark.slow
def test_the_slab_reads_each_groups_table_at_its_momentary_pressure(tmp_path, capsys):
    """`run --structure slab --plan --record-z`: two groups of UF at 2000 psi under a constant
    a_v = 0.3 g take the row at 2600 psi, as a bearing file holding it does on the same slab."""
    t = np.arange(0, 6.0, 0.01)
    records = ["--record-x", _at2(tmp_path / "x.AT2", 0.3 * np.sin(2 * np.pi * 0.5 * t)),
               "--record-y", _at2(tmp_path / "y.AT2", 0.2 * np.cos(2 * np.pi * 0.4 * t)),
               "--record-z", _at2(tmp_path / "z.AT2", np.full(t.size, 0.3))]
    groups = [{"name": "W", "x": "0m", "y": "5m", "load": "500kN", "ptfe": "UF", "pressure": "2000psi"},
              {"name": "E", "x": "20m", "y": "5m", "load": "500kN", "ptfe": "UF", "pressure": "2000psi"}]
    (tmp_path / "plan.json").write_text(json.dumps({"length_x": "20m", "length_y": "10m", "weight": "1000kN",
                                                    "groups": groups}))
    (tmp_path / "held.json").write_text(json.dumps({"length_x": "20m", "length_y": "10m", "weight": "1000kN",
                                                    "groups": [{k: v for k, v in g.items() if k in ("name", "x", "y",
                                                               "load")} for g in groups]}))
    friction, b = _row(2600 * PSI)
    save_bearing(tmp_path / "row.json", paper_bearing(friction, breakaway_ratio=b))
    slab = ["--structure", "slab", "--isolation-period", "2.5s", *records]
    table = _run(tmp_path, "table", slab + ["--plan", tmp_path / "plan.json", "--breakaway", "table"], capsys)
    assert any("Table 1 read from 2600 to 2600 psi" in note for note in table["notes"])
    row = _run(tmp_path, "row", slab + ["--plan", tmp_path / "held.json", "--bearing", tmp_path / "row.json"], capsys)
    for key in ("base_disp_resultant_m", "base_shear_ratio_resultant"):
        assert table["peak"][key] == pytest.approx(row["peak"][key], rel=1e-9), key
