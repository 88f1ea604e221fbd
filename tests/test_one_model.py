"""One bearing model for every consumer: its optional parts, the path it is driven along, the
bearing file, and what discovery and the fitter hand on to the commands that simulate.

Peers: numpy's second-order gradient, closed forms of each factor, the plain bearing (a part at
its neutral constants gives its numbers), the ODE simulator (`imposed_path_test` without
parts) and the forces discovery reports for its own model.
"""

import json
import math

import equinox as eqx
import jax.numpy as jnp
import numpy as np
import pytest

import teflon_jax as tj
from teflon_jax.bearing import (
    Backlash,
    DirectionAsymmetry,
    FrictionalHeating,
    PressureDependence,
    Wear,
    heat_kernel_exponentials,
    kumar_temperature_factor,
)
from teflon_jax.formats import bearing_from_dict, bearing_to_dict
from teflon_jax.systems import imposed_path_test, sample_velocity, sampled_path
from teflon_jax.units import INCH, KIP, PSI

UF, UF_B = tj.interface_parameters("UF", 1000 * PSI, "P")
UF_T, _ = tj.interface_parameters("UF", 1000 * PSI, "T")
AREA = 78.5 * INCH**2
LOAD = 78.5 * KIP


def with_parts(bearing, **parts):
    names = tuple(parts)
    return eqx.tree_at(lambda b: tuple(getattr(b, n) for n in names), bearing,
                       tuple(parts.values()), is_leaf=lambda x: x is None)


def sine_path(cycles=2, samples=200, amplitude=INCH, frequency=0.5, load=LOAD):
    t = np.linspace(0.0, cycles / frequency, cycles * samples + 1)
    w = 2 * math.pi * frequency
    return t, amplitude * np.sin(w * t), amplitude * w * np.cos(w * t), np.full_like(t, load)


def test_sample_velocity_is_numpys_second_order_gradient():
    rng = np.random.default_rng(1)
    t = np.cumsum(rng.uniform(0.5, 1.5, 60)) * 1e-2
    u = np.sin(3 * t) + t**2
    np.testing.assert_allclose(sample_velocity(t, u), np.gradient(u, t, edge_order=2),
                               rtol=1e-10, atol=1e-12)


@pytest.mark.parametrize("part", ["pressure", "heating", "wear", "asymmetry", "backlash"])
def test_a_part_at_its_neutral_constants_is_the_plain_bearing(part):
    """Each optional part has a neutral value at which the force is the 1990 model's."""
    plain = tj.paper_bearing(UF, breakaway_ratio=UF_B)
    neutral = {
        "pressure": {"pressure_dependence": PressureDependence(0.0, 2 * LOAD)},
        "heating": {"heating": FrictionalHeating(contact_area=AREA, heat_scale=0.0)},
        "wear": {"wear": Wear(0.0, 1.0)},
        "asymmetry": {"asymmetry": DirectionAsymmetry(0.0)},
        "backlash": {"backlash": Backlash(0.0)},
    }[part]
    t, u, v, load = sine_path()
    path = sampled_path(t, u, load, velocity=v)
    base = imposed_path_test(plain, path)
    other = imposed_path_test(with_parts(plain, **neutral), path)
    scale = float(jnp.max(jnp.abs(base.fx)))
    np.testing.assert_allclose(other.fx, base.fx, rtol=0, atol=1e-12 * scale)


def test_the_path_of_a_plain_bearing_is_the_ode_simulator():
    """Along x, Z exact between samples and mu at the motion's velocity: the simulator's own
    record (RiccatiNewmark at the same samples) to rounding."""
    bearing = tj.paper_bearing(UF, breakaway_ratio=UF_B)
    motion = tj.SineMotion(INCH, 0.5, cycles=2)
    result = tj.imposed_path_test(bearing, motion, LOAD, samples_per_cycle=200)
    path = sampled_path(result.time, result.ux, LOAD, velocity=result.vx)
    response = imposed_path_test(bearing, path)
    np.testing.assert_allclose(response.fx, result.fx, rtol=0,
                               atol=1e-10 * float(jnp.max(jnp.abs(result.fx))))


def test_each_factor_follows_its_law():
    """Closed forms where the plausible alternatives differ: a power of the load (not linear),
    wear linear in travel, asymmetry linear in Z_x, Kumar's k_T of the temperature."""
    assert float(PressureDependence(0.3, LOAD).factor(2 * LOAD)) == pytest.approx(2**-0.3, rel=1e-14)
    assert float(PressureDependence(0.3, LOAD).factor(0.5 * LOAD)) == pytest.approx(2**0.3, rel=1e-14)
    assert float(Wear(0.2, 4.0).factor(1.0)) == pytest.approx(1.05, rel=1e-14)
    assert float(DirectionAsymmetry(0.1).factor(-0.5)) == pytest.approx(0.95, rel=1e-14)
    heat = FrictionalHeating(contact_area=AREA, heat_scale=2.0, initial_temperature=30.0)
    expected = kumar_temperature_factor(30.0 + 2.0 * 40.0) / kumar_temperature_factor(30.0)
    assert float(heat.factor(40.0)) == pytest.approx(float(expected), rel=1e-14)
    assert float(kumar_temperature_factor(20.0)) == pytest.approx(1.0, abs=2e-3)


def test_heating_under_a_constant_flux_is_the_semi_infinite_body_rise():
    """The exponential states advanced step by step give dT = 2 q sqrt(kappa t / pi) / k."""
    heat = FrictionalHeating(contact_area=AREA)
    dt, steps = 1e-3, 2000
    rates, weights = (jnp.asarray(a) for a in heat_kernel_exponentials(dt, dt * steps))
    flux = 1e5
    states = jnp.zeros_like(rates)
    for _ in range(steps):
        states = heat.advance(states, flux, dt, rates)
    t = dt * steps
    exact = 2 * flux * math.sqrt(heat.diffusivity * t / math.pi) / heat.conductivity
    assert float(heat.rise(states, weights)) == pytest.approx(exact, rel=5e-3)


def test_heating_in_a_simulated_test_lowers_friction_cycle_by_cycle():
    bearing = tj.paper_bearing(UF)
    hot = with_parts(bearing, heating=FrictionalHeating(contact_area=AREA / 3))
    motion = tj.SineMotion(4 * INCH, 0.6, cycles=3)
    cold = tj.imposed_path_test(bearing, motion, LOAD)
    warm = tj.imposed_path_test(hot, motion, LOAD)
    n = cold.time.shape[0]
    one_cycle = (n - 1) // 3
    peak = [float(jnp.max(jnp.abs(warm.fx[i * one_cycle:(i + 1) * one_cycle]))) for i in range(3)]
    assert peak[0] > peak[1] > peak[2]
    np.testing.assert_allclose(jnp.max(jnp.abs(cold.fx[:one_cycle])),
                               jnp.max(jnp.abs(cold.fx[2 * one_cycle:])), rtol=1e-6)


# ------------------------------------------------------------------------------- bearing file


def full_bearing():
    bearing = tj.paper_bearing(UF, breakaway_ratio=UF_B, friction_perpendicular=UF_T,
                               lay_angle=0.3)
    return with_parts(bearing, pressure_dependence=PressureDependence(0.2, LOAD),
                      heating=FrictionalHeating(contact_area=AREA, heat_scale=1.3),
                      wear=Wear(-0.1, 2.0), asymmetry=DirectionAsymmetry(0.05),
                      backlash=Backlash(1e-4))


def test_bearing_file_round_trip(tmp_path):
    bearing = full_bearing()
    path = tj.save_bearing(tmp_path / "b.json", bearing,
                           standard_errors={("friction", "f_max"): 0.002}, sources=["t.csv"])
    back = tj.load_bearing(path)
    assert back.effects == bearing.effects
    assert len(jax_leaves(back)) == len(jax_leaves(bearing)) > 20
    for a, b in zip(jax_leaves(bearing), jax_leaves(back)):
        np.testing.assert_allclose(a, b, rtol=1e-15)
    document = json.loads(path.read_text())
    assert document["parts"]["friction"]["f_max"]["standard_error"] == 0.002
    assert document["sources"] == ["t.csv"]


def jax_leaves(tree):
    import jax

    return [np.asarray(x, float) for x in jax.tree_util.tree_leaves(tree)]


def test_a_bearing_file_in_paper_units_reads_to_si():
    document = bearing_to_dict(tj.paper_bearing(UF))
    document["parts"]["friction"]["rate_a"] = {"value": 0.6, "unit": "s/in"}
    document["parts"]["hysteresis"]["yield_disp"] = {"value": 0.005, "unit": "in"}
    bearing = bearing_from_dict(document)
    assert float(bearing.friction.rate_a) == pytest.approx(0.6 / INCH)
    assert float(bearing.hysteresis.yield_disp) == pytest.approx(0.005 * INCH)


@pytest.mark.parametrize("edit, message", [
    (lambda d: d["parts"]["heating"].pop("contact_area"), r"parts.heating: missing constant\(s\) \['contact_area'\]"),
    (lambda d: d["parts"].update(magnets={}), r"unknown part\(s\) \['magnets'\]"),
    (lambda d: d["parts"]["friction"]["rate_a"].pop("unit"), r"parts.friction.rate_a: missing 'unit'"),
    (lambda d: d["parts"]["friction"].update(rate_a=23.6), r"parts.friction.rate_a: write .*value without a unit"),
    (lambda d: d["parts"]["friction"]["rate_a"].update(unit="in"), r"rate_a.unit: 'in' is a unit of length"),
    (lambda d: d["parts"]["wear"]["reference_travel"].update(unit="s"), r"reference_travel.unit: 's' is a unit of time"),
    (lambda d: d.update(format_version=2), r"format_version 2 is newer"),
    (lambda d: d["parts"].pop("hysteresis"), r"the part 'hysteresis' is missing"),
    (lambda d: d["parts"]["friction"]["delta_f"].update(value=0.5), r"delta_f: must be smaller than f_max"),
    (lambda d: d["parts"]["heating"]["contact_area"].update(value=-1.0), r"heating.contact_area: must be"),
])
def test_bad_bearing_files_are_refused_by_key(edit, message):
    document = bearing_to_dict(full_bearing())
    edit(document)
    with pytest.raises(ValueError, match=r"^b.json: .*" + message):
        bearing_from_dict(document, where="b.json")


def test_structures_refuse_parts_they_do_not_run():
    with pytest.raises(ValueError, match="the structures do not run its backlash"):
        tj.systems.isolated_structure("rigid", bearing=with_parts(
            tj.paper_bearing(UF), backlash=Backlash(1e-3)))


def test_a_given_bearing_runs_as_table_1s_in_a_structure():
    """The same constants through `bearing=` or through Table 1 give the same structure."""
    table = tj.systems.isolated_structure("rigid", pressure=1000 * PSI)
    bearing, _, _ = table.isolation()
    given = tj.systems.isolated_structure("rigid", bearing=bearing)
    b1, p1, d1 = given.isolation({"f_max": 0.2})
    b0, p0, d0 = table.isolation({"f_max": 0.2})
    for a, b in zip(jax_leaves(b0), jax_leaves(b1)):
        np.testing.assert_allclose(a, b, rtol=1e-15)
    with pytest.raises(ValueError, match="'pressure' picks a Table 1 row"):
        given.isolation({"pressure": 2000 * PSI})


@pytest.mark.slow
def test_a_cold_unworn_bearing_with_history_runs_as_the_plain_one():
    """Heating at heat_scale 0 and wear at change 0 carry their states through every step and
    leave the peaks of the plain bearing (Monte Carlo's peak loop and the full simulation)."""
    from teflon_jax.systems import isolated_structure, peak_response, simulate_history

    plain = isolated_structure("building").isolation()[0]
    neutral = with_parts(plain, heating=FrictionalHeating(contact_area=AREA, heat_scale=0.0),
                         wear=Wear(0.0, 1.0))
    t = np.arange(0, 10.0, 0.01)
    ag = 3.0 * np.sin(2 * np.pi * 0.5 * t) * np.exp(-0.2 * t)
    signal = tj.uniform_signal(jnp.asarray(ag), 0.01)
    a = isolated_structure("building", bearing=plain)(signal)
    b = isolated_structure("building", bearing=neutral)(signal)
    assert b.history and not a.history
    pa, pb = peak_response(a, 9.0), peak_response(b, 9.0)
    assert float(pb.base_disp) == pytest.approx(float(pa.base_disp), rel=1e-12)
    assert float(pb.base_shear_ratio) == pytest.approx(float(pa.base_shear_ratio), rel=1e-12)
    ra, rb = simulate_history(a, 5.0), simulate_history(b, 5.0)
    np.testing.assert_allclose(rb.displacement, ra.displacement, rtol=0, atol=1e-12)


@pytest.mark.slow
def test_heating_in_a_structure_lowers_friction_and_raises_the_displacement():
    """The heating bearing's peak displacement exceeds the cold one's (less friction as the
    steel warms), and the peak loop agrees with the full simulation step for step."""
    from teflon_jax.systems import isolated_structure, peak_response, simulate_history

    plain = isolated_structure("rigid", isolation_period=2.5).isolation()[0]
    hot = with_parts(plain, heating=FrictionalHeating(contact_area=AREA / 4, heat_scale=3.0))
    t = np.arange(0, 12.0, 0.01)
    ag = 4.0 * np.sin(2 * np.pi * 0.4 * t) * np.exp(-0.15 * t)
    signal = tj.uniform_signal(jnp.asarray(ag), 0.01)
    cold_run = isolated_structure("rigid", bearing=plain, isolation_period=2.5)(signal)
    hot_run = isolated_structure("rigid", bearing=hot, isolation_period=2.5,
                                 pressure=3000 * PSI)(signal)
    cold, warm = peak_response(cold_run, 11.0), peak_response(hot_run, 11.0)
    assert float(warm.base_disp) > 1.02 * float(cold.base_disp)
    full = simulate_history(hot_run, 11.0)
    assert float(jnp.max(jnp.abs(full.displacement[:, 0]))) == pytest.approx(
        float(warm.base_disp), rel=1e-9)


# ------------------------------------------------------------------------------- the commands


def _cli(argv, capsys):
    from teflon_jax.cli import main

    code = main(argv)
    return code, capsys.readouterr().err


def test_fit_refuses_an_unknown_effect_with_the_list(tmp_path, capsys):
    record = tmp_path / "r.csv"
    record.write_text("time [s],ux [in],fx [kip],N [kip]\n0,0,0,78.5\n1,1,5,78.5\n2,0,-5,78.5\n")
    code, err = _cli(["fit", str(record), "--effects", "magnets", "--json", str(tmp_path / "f.json")],
                     capsys)
    assert code == 2
    assert "--effects: unknown effect(s) magnets; the known effects are" in err
    assert "heating" in err and "backlash" in err


def test_bearing_flags_are_checked_before_any_work(tmp_path, capsys):
    good = tj.save_bearing(tmp_path / "b.json", tj.paper_bearing(UF))
    hot = tj.save_bearing(tmp_path / "hot.json", full_bearing())
    cases = [
        (["montecarlo", "--motions", "5", "--bearing", str(tmp_path / "none.json")],
         "none.json: no such bearing file"),
        (["montecarlo", "--motions", "5", "--bearing", str(good), "--ptfe", "15GF"],
         "--ptfe: the bearing comes from --bearing"),
        (["montecarlo", "--motions", "5", "--bearing", str(good), "--pressure", "2000psi"],
         "--pressure: the bearing comes from --bearing"),
        (["simulate-test", "--bearing", str(good), "--normal-load", "10kN", "--interfaces-in-series", "2"],
         "--interfaces-in-series: the bearing comes from --bearing"),  # the flag as typed, not its attribute
        (["montecarlo", "--motions", "5", "--bearing", str(hot)],
         "the structures do not run its backlash"),
        (["diagnose", str(tmp_path / "r.csv"), "--json", str(tmp_path / "d.json"), "--report",
          str(tmp_path / "rep"), "--save-bearing", str(tmp_path)], "--save-bearing"),
    ]
    for argv, message in cases:
        code, err = _cli(argv, capsys)
        assert code == 2, (argv, err)
        assert message in err, (argv, err)


def test_simulate_test_runs_a_bearing_file(tmp_path, capsys):
    """The record `simulate-test --bearing` writes is the bearing's response along the motion."""
    hot = with_parts(tj.paper_bearing(UF), heating=FrictionalHeating(contact_area=AREA / 3))
    path = tj.save_bearing(tmp_path / "hot.json", hot)
    out = tmp_path / "hot.csv"
    code, err = _cli(["simulate-test", "--bearing", str(path), "--amplitude", "4in", "--frequency",
                      "0.6Hz", "--cycles", "1", "--normal-load", "78.5kip", "--units", "si",
                      "--out", str(out)], capsys)
    assert code == 0, err
    record = tj.read_test_record(out)
    direct = tj.imposed_path_test(hot, tj.SineMotion(4 * INCH, 0.6, cycles=1), LOAD)
    np.testing.assert_allclose(record.fx, direct.fx, rtol=1e-6, atol=1e-6 * LOAD)
    assert float(record.metadata["contact_area"]) == pytest.approx(AREA / 3)


def test_a_command_reads_its_bearing_file_once_and_warns_once(tmp_path, capsys, monkeypatch):
    """`simulate-test --bearing FILE` with a constant its fit could not determine: the file is
    read once (the warning comes from the same read as the bearing run), and warned of once."""
    import pathlib

    path = tj.save_bearing(tmp_path / "b.json", tj.paper_bearing(UF),
                           standard_errors={("friction", "f_max"): 0.001, ("friction", "rate_a"): math.inf})
    reads, read_text = [], pathlib.Path.read_text

    def counted(self, *args, **kwargs):
        if self.resolve() == path.resolve():
            reads.append(self)
        return read_text(self, *args, **kwargs)

    monkeypatch.setattr(pathlib.Path, "read_text", counted)
    code, err = _cli(["simulate-test", "--bearing", str(path), "--amplitude", "1in", "--frequency", "0.5Hz",
                      "--cycles", "1", "--normal-load", "10kN", "--out", str(tmp_path / "t.csv")], capsys)
    assert code == 0, err
    assert err.count("friction.rate_a = ") == 1 and "was not determined by the fit" in err, err
    assert len(reads) == 1, reads


def test_discovery_refuses_a_normal_load_that_puts_force_over_n_out_of_range():
    """With N = 1 N every friction constant within its bounds (f_max <= 0.5) gives a force
    near zero: refused, with a load that works."""
    from identification.discovery import discover_effects

    t, u, v, _ = sine_path()
    record = tj.test_record_from_arrays(u, 2e3 * np.tanh(v / 1e-3), time=t, normal_load=1.0)
    with pytest.raises(ValueError, match=r"force / normal load reaches .* --normal-load"):
        discover_effects(record)


def test_one_table_of_bounds_serves_the_fitter_discovery_and_the_posterior(monkeypatch):
    """The physical and search ranges of each constant are `PARAMETER_BOUNDS`: the fitter's
    default bounds are its `physical` pairs (its `search` pairs for the rates of Eq. 1), the
    posterior's physical ranges its `physical` pairs, discovery's
    its `search` ranges and log flags, the bearing-file fields its `field` column; a change in
    the table reaches discovery and the posterior's default prior."""
    from identification.bayes import PHYSICAL, build_priors
    from identification.bearing_fit import PARAMETER_FIELDS, PARAMETER_NAMES
    from identification.bearing_fit._plan import _DEFAULT_BOUNDS, RATE_NAMES
    from identification.discovery import EFFECTS
    from identification.discovery._augmented import PARAMETERS
    from teflon_jax.bearing import PARAMETER_BOUNDS, ConstantBounds

    for name in PARAMETER_NAMES:  # the rates of Eq. 1 kept in their search range (_plan.py)
        table = PARAMETER_BOUNDS[name].search if name in RATE_NAMES else PARAMETER_BOUNDS[name].physical
        assert _DEFAULT_BOUNDS[name] is table, name
    for name, pair in PHYSICAL.items():
        assert pair is PARAMETER_BOUNDS[name].physical, name
    assert PARAMETER_FIELDS == {n: b.field for n, b in PARAMETER_BOUNDS.items() if b.field}
    for p in PARAMETERS:
        bounds = PARAMETER_BOUNDS[p.name]
        assert (p.lower, p.upper, p.log_scale) == (*bounds.search, bounds.log_scale), p.name
        lo, hi = bounds.physical
        assert lo <= bounds.search[0] < bounds.search[1] <= hi, p.name
        assert not bounds.log_scale or bounds.search[0] > 0, p.name

    record = {"fx": np.array([1.0, -1.0]), "load": np.array([10.0, 10.0]),
              "ux": np.array([0.0, 0.01])}
    wider = ConstantBounds((0.0, math.inf), (0.01, 5e3), log_scale=True, unit="s/m",
                           field=("friction", "rate_a"))
    monkeypatch.setitem(PARAMETER_BOUNDS, "rate_a", wider)
    monkeypatch.setitem(PARAMETER_BOUNDS, "asymmetry",
                        PARAMETER_BOUNDS["asymmetry"]._replace(search=(-0.3, 0.3)))
    prior = build_priors(("rate_a",), [record])["rate_a"]
    assert (prior.low, prior.high) == (0.01, 5e3)
    assert (EFFECTS["asymmetry"].parameters[0].lower, EFFECTS["asymmetry"].parameters[0].upper) \
        == (-0.3, 0.3)
