"""Each physical law of the bearing model reaches the simulator, the fitter and discovery alike.

For every law (Eq. 1, Eq. 3, Eq. 17, pressure dependence, heating, wear, asymmetry, backlash,
Park's Eqs. 8-9 with anisotropy) a noise-free record comes from an independent peer written
in numpy/scipy (`test_discovery.generate_record`: RK4 of Eq. 3 with the effects applied
sample by sample; `_planar_record`: scipy's integration of Park's equations), and:

- the simulator (`imposed_path_test` of the bearing with that part) reproduces it;
- the fitter (`fit_bearing_test`, or for an optional part the fit of a chosen composition,
  `fit --effects`) recovers the law's constant from it;
- discovery's candidate model (`simulate_augmented`) at the true constants reproduces it.

Change the law in `teflon_jax.bearing` and all three go red (`tools/mutants.py`).
"""

import math

import equinox as eqx
import jax.numpy as jnp
import numpy as np
import pytest
from scipy.integrate import solve_ivp
from test_discovery import HIDDEN, UF_1000_P, UF_1000_T, generate_record

import teflon_jax as tj
from identification.bearing_fit import fit_bearing_test
from identification.discovery import (
    active_mask,
    default_parameters,
    discover_effects,
    prepare_record,
    simulate_augmented,
)
from teflon_jax.bearing import (
    Backlash,
    DirectionAsymmetry,
    FrictionalHeating,
    PressureDependence,
    Wear,
)
from teflon_jax.formats import test_record_from_arrays
from teflon_jax.units import INCH, KIP

Y = 0.005 * INCH
AREA = 78.5 * INCH**2  # generate_record's contact area

# law -> (generator settings, discovery effects, fitted constant and its true value,
#         relative tolerance of the simulator and of discovery against the peer)
LAWS = {
    "eq1": ({"amplitude": 2 * INCH, "frequency": 0.3}, (), ("rate_a", UF_1000_P["rate_a"]), 2e-4),
    "bouc_wen": ({"amplitude": 0.3 * INCH}, (), ("yield_disp", Y), 2e-4),
    "breakaway": (HIDDEN["breakaway"], ("breakaway",), ("breakaway_ratio", 3.0), 2e-4),
    "pressure_dependence": (HIDDEN["pressure_dependence"], ("pressure_dependence",),
                            ("pressure_exponent", 0.5), 2e-4),
    "heating": (HIDDEN["heating"], ("heating",), ("heat_scale", 1.0), 3e-3),
    "wear": (HIDDEN["wear"], ("wear",), ("wear_change", -0.35), 2e-4),
    "asymmetry": (HIDDEN["asymmetry"], ("asymmetry",), ("asymmetry", 0.12), 2e-4),
    "backlash": ({"backlash_gap": 0.05 * INCH}, ("backlash",), ("backlash_gap", 0.05 * INCH), 2e-3),
}


def _record(law, **extra):
    settings = dict(LAWS[law][0])
    settings.update(extra)
    return generate_record(noise=0.0, cycles=2, samples_per_cycle=400, **settings), settings


def _nrmse(model, measured):
    model, measured = np.asarray(model), np.asarray(measured)
    return float(np.sqrt(np.mean((model - measured) ** 2) / np.mean(measured**2)))


def _bearing_of(record, settings):
    """The bearing the generator used, with its optional part (SI)."""
    friction = settings.get("friction", UF_1000_P)
    bearing = tj.paper_bearing(tj.FrictionParameters(**{k: jnp.asarray(v) for k, v in friction.items()}),
                               breakaway_ratio=settings.get("breakaway_ratio"))
    load, ux = np.asarray(record.normal_load), np.asarray(record.ux)
    parts = {}
    if settings.get("pressure_exponent"):
        parts["pressure_dependence"] = PressureDependence(settings["pressure_exponent"],
                                                          float(np.mean(load)))
    if settings.get("heat_scale"):
        parts["heating"] = FrictionalHeating(contact_area=AREA, heat_scale=settings["heat_scale"])
    if settings.get("wear_change"):
        parts["wear"] = Wear(settings["wear_change"], float(np.sum(np.abs(np.diff(ux)))))
    if settings.get("asymmetry"):
        parts["asymmetry"] = DirectionAsymmetry(settings["asymmetry"])
    if settings.get("backlash_gap"):
        parts["backlash"] = Backlash(settings["backlash_gap"])
    if not parts:
        return bearing
    names = tuple(parts)
    return eqx.tree_at(lambda b: tuple(getattr(b, n) for n in names), bearing,
                       tuple(parts.values()), is_leaf=lambda x: x is None)


@pytest.mark.parametrize("law", list(LAWS))
def test_simulator_follows_the_law(law):
    record, settings = _record(law)
    bearing = _bearing_of(record, settings)
    motion = tj.SineMotion(settings.get("amplitude", INCH), settings.get("frequency", 0.16), cycles=2)
    load = tj.uniform_signal(jnp.asarray(record.normal_load), float(record.time[1] - record.time[0]))
    result = tj.imposed_path_test(bearing, motion, load, samples_per_cycle=400)
    assert _nrmse(result.fx, record.fx) < LAWS[law][3]


@pytest.mark.parametrize("law", list(LAWS))
def test_discovery_follows_the_law(law):
    record, settings = _record(law)
    effects, (name, value), tolerance = LAWS[law][1], LAWS[law][2], LAWS[law][3]
    data, _ = prepare_record(record)
    params = default_parameters()
    params.update(settings.get("friction", UF_1000_P), yield_disp=Y)
    params[name] = value
    sim = simulate_augmented(params, data, active_mask(("velocity_dependence", *effects)))
    assert _nrmse(sim["force"], record.fx) < tolerance


@pytest.mark.parametrize("law", [pytest.param(law, marks=pytest.mark.slow) if law in ("heating", "pressure_dependence")
                                 else law for law in LAWS])
def test_fitter_follows_the_law(law):
    """The Eq. 1 / Eq. 3 / Eq. 17 constants by least squares (`fit`), an optional part's by the
    fit of Eq. 1 with that part (`fit --effects`), from the noise-free peer record."""
    record, settings = _record(law)
    effects, (name, value) = LAWS[law][1], LAWS[law][2]
    if not effects or law == "breakaway":
        fit = fit_bearing_test(record)
        assert fit.converged, fit.message
        friction = settings.get("friction", UF_1000_P)
        assert fit.parameters["f_max"] == pytest.approx(friction["f_max"], rel=5e-3)
        assert fit.nrmse < LAWS[law][3]
        found = fit.parameters[name]
    else:
        known = {"yield_disp": Y, **settings.get("friction", UF_1000_P)}
        result = discover_effects(record, baseline=("velocity_dependence", *effects),
                                  max_effects=0, known=known)
        assert result.fit_convergence["final_converged"]
        assert result.nrmse_final < LAWS[law][3]  # the law itself, not a refit around it
        found = result.parameters[name]
    assert found == pytest.approx(value, rel=2e-2)


# ------------------------------------------------------------------ Park's Eqs. 8-9, anisotropy


def _planar_record(amplitude=0.5 * INCH, w=1.5, cycles=1.0, samples=200):
    """A figure-eight (Eq. 16) on an anisotropic bearing, integrated by scipy: Park's Eqs. 8-9
    (A = 1, beta = 0.1, gamma = 0.9, eta = 2) and Eq. 1 with constants linear in the sliding
    angle to the lay (x): weight = angle / 90 degrees."""
    t = np.linspace(0.0, cycles * 2 * math.pi / w, int(cycles * samples) + 1)

    def velocity(s):
        return amplitude * w * np.array([np.cos(w * s), 2 * np.cos(2 * w * s)])

    def rhs(s, z):
        v = velocity(s)
        common = 0.9 * (abs(v[0] * z[0]) + abs(v[1] * z[1])) + 0.1 * (v[0] * z[0] + v[1] * z[1])
        return (v - common * z) / Y

    sol = solve_ivp(rhs, (0.0, t[-1]), [0.0, 0.0], t_eval=t, rtol=1e-11, atol=1e-13,
                    method="LSODA", max_step=float(t[1] - t[0]) / 4)
    v = velocity(t)
    weight = np.arctan2(np.abs(v[1]), np.abs(v[0])) / (math.pi / 2)
    mix = {k: (1 - weight) * UF_1000_P[k] + weight * UF_1000_T[k] for k in UF_1000_P}
    mu = mix["f_max"] - mix["delta_f"] * np.exp(-mix["rate_a"] * np.hypot(v[0], v[1]))
    load = 78.5 * KIP
    ux, uy = amplitude * np.sin(w * t), amplitude * np.sin(2 * w * t)
    return test_record_from_arrays(ux, mu * load * sol.y[0], time=t, uy=uy,
                                   fy=mu * load * sol.y[1], normal_load=load)


def _planar_forces(record):
    return np.concatenate([np.asarray(record.fx), np.asarray(record.fy)])


def test_simulator_follows_park_and_anisotropy():
    record = _planar_record()
    bearing = tj.paper_bearing(tj.FrictionParameters(**UF_1000_P),
                               friction_perpendicular=tj.FrictionParameters(**UF_1000_T))
    motion = tj.FigureEightMotion(0.5 * INCH, 1.5, cycles=1.0)
    result = tj.imposed_path_test(bearing, motion, 78.5 * KIP, samples_per_cycle=200)
    assert _nrmse(np.concatenate([result.fx, result.fy]), _planar_forces(record)) < 1e-4


def test_discovery_follows_park_and_anisotropy():
    record = _planar_record()
    data, _ = prepare_record(record)
    params = default_parameters()
    params.update(UF_1000_P, yield_disp=Y, **{f"{k}_perpendicular": v for k, v in UF_1000_T.items()})
    sim = simulate_augmented(params, data, active_mask(("velocity_dependence", "anisotropy")))
    assert _nrmse(np.concatenate([sim["force"], sim["force_y"]]), _planar_forces(record)) < 1e-3


def test_fitter_follows_park_and_anisotropy():
    fit = fit_bearing_test(_planar_record(), fixed={"breakaway_ratio": 1.0}, n_starts=2)
    assert fit.converged, fit.message
    truth = {**UF_1000_P, **{f"{k}_perpendicular": v for k, v in UF_1000_T.items()}}
    for name in ("f_max", "delta_f", "f_max_perpendicular", "delta_f_perpendicular"):
        assert fit.parameters[name] == pytest.approx(truth[name], rel=1e-2), name
