"""Hand-made mutation run over the physics modules (friction, hysteresis, bearing, tables,
excitation signal, solver, structures).

Each mutant changes one physical statement (a sign, a factor, a threshold, an interpolation
rule) in a copy of the repository and runs the tests that guard it (`pytest -x -q`: the fast
tests of a file named whole, a test named by its node id even where it is slow; a time limit
per mutant). A mutant is *killed* when those tests fail,
*survived* when they pass (a statement no test guards, or an equivalent mutant to explain),
*timeout* when they run past the limit. The working tree is never modified.

Usage (from the repository root):

    python tools/mutants.py                 # all mutants
    python tools/mutants.py --only F1 S2    # some of them
    python tools/mutants.py --list          # what each mutant changes
    python tools/mutants.py --timeout 900 --no-baseline

Exit status: 0 when every mutant was killed, 1 otherwise.
"""

import argparse
import dataclasses
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile
import time

REPO = pathlib.Path(__file__).resolve().parent.parent
BT = "tests/test_bearing_tests.py"
BW = "tests/test_bouc_wen_general.py"
BR = "tests/test_breakaway.py"
SG = "tests/test_signal_and_speed.py"
SS = "tests/test_structure_solver.py"


@dataclasses.dataclass(frozen=True)
class Mutant:
    name: str
    path: str
    old: str
    new: str
    tests: tuple[str, ...]
    statement: str
    groups: tuple[tuple[str, tuple[str, ...]], ...] = ()


OL = "tests/test_one_law.py"


def law(name, path, old, new, case, statement, consumers=("simulator", "fitter", "discovery")):
    """A mutant of one law of the bearing model, run against the simulator's, the fitter's and
    discovery's test of that law (`tests/test_one_law.py`): killed only when all go red."""
    groups = tuple((who, (f"{OL}::test_{who}_follows_{case}",)) for who in consumers)
    return Mutant(name, path, old, new, tuple(t for _, ts in groups for t in ts), statement, groups)


EF = "teflon_jax/bearing/_effects.py"
LAWS = (
    law("L1", "teflon_jax/bearing/_friction.py", "params.delta_f * jnp.exp(-params.rate_a * speed)",
        "params.delta_f * jnp.exp(-0.5 * params.rate_a * speed)", "the_law[eq1]",
        "Eq. 1: exp(-a |v|) -> exp(-a |v| / 2)"),
    law("L2", "teflon_jax/bearing/_hysteresis.py", "c_plus = h.gamma + h.beta",
        "c_plus = h.gamma + 0.5 * h.beta", "the_law[bouc_wen]",
        "Eq. 3 (closed form): loading branch with gamma + beta / 2"),
    law("L3", "teflon_jax/bearing/_bearing.py",
        "return jnp.where(z_peak < BREAKAWAY_THRESHOLD, self.breakaway_ratio * params.f_min, mu)",
        "return jnp.where(z_peak < BREAKAWAY_THRESHOLD, self.breakaway_ratio * params.f_max, mu)",
        "the_law[breakaway]", "Eq. 17: b f_max instead of b (f_max - Df)"),
    law("L4", "teflon_jax/bearing/_friction.py", "return theta / (jnp.pi / 2)",
        "return jnp.sin(theta) ** 2", "park_and_anisotropy",
        "anisotropy: weight sin^2(theta) instead of theta / 90 degrees"),
    law("L5", "teflon_jax/solver/_park_path.py", "k = (h.gamma * s + h.beta) * e",
        "k = (h.gamma * s - h.beta) * e", "park_and_anisotropy",
        "Park's Eqs. 8-9 in closed form along a sampled path, sign of the beta term (the "
        "imposed-motion simulator "
        "integrates their rate form, mutants H3, H6)", consumers=("fitter", "discovery")),
    law("L6", EF, "jnp.power(0.70, temperature / 50.0)", "jnp.power(0.70, temperature / 40.0)",
        "the_law[heating]", "heating: k_T = 0.79 (0.70^(T/40) + 0.40)"),
    law("L7", EF, "jnp.exp(-self.exponent * jnp.log(normal_load / self.reference_load))",
        "1.0 - self.exponent * (normal_load / self.reference_load - 1.0)",
        "the_law[pressure_dependence]", "pressure dependence: linear in N instead of a power"),
    law("L8", EF, "1.0 + self.change * (travel / self.reference_travel)",
        "1.0 + self.change * (travel / self.reference_travel) ** 2", "the_law[wear]",
        "wear: quadratic in travel instead of linear"),
    law("L9", EF, "1.0 + self.asymmetry * z_x", "1.0 + self.asymmetry * jnp.sign(z_x)",
        "the_law[asymmetry]", "asymmetry: on the sliding direction sign(Z) instead of Z"),
    law("L10", EF, "available = jnp.maximum(0.5 * gap - sigma * gap_position, 0.0)",
        "available = jnp.maximum(gap - sigma * gap_position, 0.0)", "the_law[backlash]",
        "backlash: the gap crossed twice over"),
)


MUTANTS = (
    # Eq. 1 friction law
    Mutant("F1", "teflon_jax/bearing/_friction.py",
           "params.delta_f * jnp.exp(-params.rate_a * speed)", "params.delta_f * 1.0",
           (f"{BT}::test_62_friction_at_peak_velocity",), "Eq. 1: exp(-a|v|) -> 1 (no velocity dependence)"),
    Mutant("F2", "teflon_jax/bearing/_friction.py",
           "speed = jnp.abs(speed) / n_interfaces", "speed = jnp.abs(speed)",
           (f"{BT}::test_stack_of_24_interfaces_follows_eq1_at_v_over_n",), "stack: Eq. 1 at v instead of v/n"),
    Mutant("F3", "teflon_jax/bearing/_friction.py",
           "return theta / (jnp.pi / 2)", "return theta / jnp.pi",
           (f"{BR}::test_anisotropy_at_45_degrees_is_the_mean_of_the_two_laws",),
           "anisotropy: weight of the perpendicular constants theta/pi instead of theta/(pi/2)"),
    Mutant("F4", "teflon_jax/bearing/_friction.py",
           "return (1 - weight) * p + weight * q", "return weight * p + (1 - weight) * q",
           (f"{BR}::test_anisotropy_at_45_degrees_is_the_mean_of_the_two_laws",
            f"{BT}::test_figure_eight_anisotropic_high_speed_friction"),
           "anisotropy: P and T constants swapped in the interpolation"),
    # Eq. 3 and Eqs. 8-9 (hysteresis)
    Mutant("H1", "teflon_jax/bearing/_hysteresis.py",
           "- h.beta * velocity * z_eta_1 * jnp.abs(z)", "+ h.beta * velocity * z_eta_1 * jnp.abs(z)",
           (f"{BW}::test_uniaxial_sine_test_matches_scipy",), "Eq. 3: sign of the beta term"),
    Mutant("H2", "teflon_jax/bearing/_hysteresis.py",
           "common = common * _abs_power(_norm(z), h.eta - 2.0)", "common = common * 1.0",
           (f"{BW}::test_figure_eight_matches_scipy",), "Eqs. 8-9: the |Z|^(eta-2) factor dropped (eta ignored)"),
    Mutant("H3", "teflon_jax/bearing/_hysteresis.py",
           "common = h.gamma * (jnp.abs(vx * zx) + jnp.abs(vy * zy))",
           "common = h.gamma * jnp.abs(vx * zx + vy * zy)",
           (f"{BW}::test_figure_eight_matches_scipy", f"{BT}::test_figure_eight_isotropic_z_follows_velocity_direction"),
           "Eqs. 8-9: gamma (|Ux Zx| + |Uy Zy|) -> gamma |U . Z|"),
    Mutant("H4", "teflon_jax/bearing/_hysteresis.py",
           "c_plus = h.gamma + h.beta", "c_plus = h.gamma + 0.5 * h.beta",
           (f"{BT}::test_riccati_update_matches_the_ode_along_the_path",),
           "closed-form Z: loading branch with a wrong beta + gamma"),
    Mutant("H5", "teflon_jax/bearing/_hysteresis.py",
           "w_plus, k_plus = jnp.sqrt(h.A / c_plus), jnp.sqrt(h.A * c_plus)",
           "w_plus, k_plus = jnp.sqrt(1.0 / c_plus), jnp.sqrt(h.A * c_plus)",
           (f"{BW}::test_riccati_newmark_with_a_above_beta_plus_gamma_agrees_with_tsit5",),
           "closed-form Z: sliding value sqrt(1/(beta+gamma)) (assumes A = 1)"),
    Mutant("H6", "teflon_jax/bearing/_hysteresis.py",
           "+ h.beta * (vx * zx + vy * zy)", "- h.beta * (vx * zx + vy * zy)",
           (f"{BW}::test_figure_eight_matches_scipy",), "Eqs. 8-9: sign of the beta term"),
    Mutant("H7", "teflon_jax/bearing/_hysteresis.py",
           "    c_minus = h.gamma - h.beta\n    return", "    c_minus = h.gamma + h.beta\n    return",
           (f"{BT}::test_reversal_length_is_where_z_crosses_zero",), "closed-form Z: reversal length with gamma + beta"),
    # Bearing: breakaway (Eq. 17), speed, checks
    Mutant("B1", "teflon_jax/bearing/_bearing.py",
           "return jnp.where(z_peak < BREAKAWAY_THRESHOLD, self.breakaway_ratio * params.f_min, mu)",
           "return jnp.where(z_peak < 0.5, self.breakaway_ratio * params.f_min, mu)",
           (f"{BR}::test_191_breakaway_then_eq1_on_every_half_cycle",), "Eq. 17: breakaway threshold 0.5 instead of 0.999"),
    Mutant("B2", "teflon_jax/bearing/_bearing.py",
           "return jnp.where(z_peak < BREAKAWAY_THRESHOLD, self.breakaway_ratio * params.f_min, mu)",
           "return jnp.where(z_peak < BREAKAWAY_THRESHOLD, self.breakaway_ratio * params.f_max, mu)",
           (f"{BR}::test_191_breakaway_then_eq1_on_every_half_cycle",), "Eq. 17: b f_max instead of b (f_max - Df)"),
    Mutant("B3", "teflon_jax/bearing/_bearing.py",
           "return jnp.where(moving, jnp.sqrt(jnp.where(moving, square, 1.0)), 0.0)",
           "return jnp.sqrt(square + 1e-300)",
           (f"{SG}::test_speed_and_friction_gradients_are_finite_at_rest",), "speed: sqrt(v^2 + 1e-300) (NaN gradient in float32)"),
    Mutant("B4", "teflon_jax/bearing/_bearing.py",
           'lambda x: np.isfinite(x) & (x >= 1), "eta"', 'lambda x: np.isfinite(x) & (x >= 0), "eta"',
           (f"{BW}::test_check_bearing_names_each_bouc_wen_constant",), "check: eta < 1 accepted"),
    Mutant("B5", "teflon_jax/bearing/_bearing.py",
           "BREAKAWAY_THRESHOLD = 0.999", "BREAKAWAY_THRESHOLD = 0.99",
           (f"{BR}::test_191_breakaway_then_eq1_on_every_half_cycle", f"{BR}::test_breakaway_acts_once_in_a_structure"),
           "Eq. 17: threshold constant 0.99 instead of the paper's 0.999"),
    # Table 1
    Mutant("T1", "teflon_jax/tables/_table1.py",
           "jnp.searchsorted(self.pressures, pressure) - 1", "jnp.searchsorted(self.pressures, pressure)",
           (f"{BT}::test_pressure_interpolation_between_rows_and_gradient",), "Table 1: interpolation on the next segment"),
    Mutant("T2", "teflon_jax/tables/_table1.py",
           "return v0 + (v1 - v0) * (pressure - p0) / (p1 - p0)", "return v0 + (v1 - v0) * (pressure - p0) / (p1 - p0) / 2",
           (f"{BT}::test_pressure_interpolation_between_rows_and_gradient",), "Table 1: interpolation slope halved"),
    Mutant("T3", "teflon_jax/tables/_table1.py",
           'rate_a=float(row["rate_a [s/in]"]) / INCH', 'rate_a=float(row["rate_a [s/in]"]) * INCH',
           (f"{BT}::test_62_friction_at_peak_velocity",), "Table 1: a [s/in] converted with the wrong power of inch"),
    # Signal past its end
    Mutant("E1", "teflon_jax/excitation/_signal.py",
           "return jnp.where(inside, value, 0.0)", "return value",
           (f"{SG}::test_signal_is_zero_outside_its_record_and_exact_at_its_ends",), "Signal: last value held past the end"),
    Mutant("E2", "teflon_jax/excitation/_signal.py",
           "if not np.all(float(duration) <= ends", "if False and not np.all(float(duration) <= ends",
           (f"{SG}::test_simulations_refuse_a_duration_longer_than_the_record",), "no duration check against the record"),
    # Solver: closed-form restrictions
    Mutant("R1", "teflon_jax/solver/_riccati_newmark.py",
           "if eta is not None and not np.all(eta == 2.0):", "if False:",
           (f"{BW}::test_closed_form_solver_refuses_other_shapes", f"{BW}::test_rigid_mass_with_eta_3_matches_scipy"),
           "RiccatiNewmark accepts eta != 2 (concrete)"),
    Mutant("R2", "teflon_jax/solver/_riccati_newmark.py",
           "bad = jnp.any(jnp.asarray(h.eta) != 2.0) |", "bad = False |",
           (f"{BW}::test_closed_form_solver_refuses_other_shapes",), "RiccatiNewmark accepts traced eta != 2"),
    Mutant("R3", "teflon_jax/systems/_bearing_test.py",
           "if solver is None and _riccati_admitted(bearing.hysteresis):", "if solver is None:",
           (f"{BW}::test_eta_changes_the_force_along_a_path",), "force_along_path: closed form whatever eta"),
    # Structures
    Mutant("S6", "teflon_jax/systems/_structure.py",
           "+ m * (4 / dt**2 * u0 + 4 / dt * v0 + a0)", "+ m * (4 / dt**2 * u0 + 4 / dt * v0 + 0.9 * a0)",
           (f"{SS}::test_newmark_with_exact_z_converges_at_second_order",), "Newmark: beta != 1/4 in the predictor"),
    Mutant("S7", "teflon_jax/systems/_structure.py",
           "u1 = u_linear - compliance * force", "u1 = u_linear + compliance * force",
           (f"{SS}::test_energy_balance_rigid_mass",), "Newmark: bearing force pushes the isolator"),
    Mutant("S1", "teflon_jax/systems/_structure.py",
           "v1 = 2 / dt * (u1 - u0) - v0", "v1 = 2.4 / dt * (u1 - u0) - 1.4 * v0",
           (f"{SS}::test_energy_balance_rigid_mass", f"{BR}::test_breakaway_acts_once_in_a_structure"),
           "Newmark: gamma = 0.6 in the velocity update"),
    Mutant("S2", "teflon_jax/systems/_structure.py",
           'return {"u": u1, "v": v1, "z": z1, "z_peak": z_peak1}, converged',
           'return {"u": u1, "v": v1, "z": z1, "z_peak": jnp.maximum(z_peak1, jnp.abs(z1))}, converged',
           (f"{BR}::test_breakaway_acts_once_in_a_structure",),
           "breakaway: reported force switched one step before the equilibrium's (the old lag)"),
    Mutant("S3", "teflon_jax/systems/_structure.py",
           "z_bound = jnp.maximum(jnp.abs(z0), (h.A / (h.beta + h.gamma)) ** (1 / h.eta))",
           "z_bound = jnp.maximum(jnp.abs(z0), 1.0)",
           (f"{BW}::test_riccati_newmark_with_a_above_beta_plus_gamma_agrees_with_tsit5",
            f"{BW}::test_newton_bracket_holds_a_step_that_saturates_z_above_one"),
           "Newton bracket assumes A <= beta + gamma"),
    Mutant("S4", "teflon_jax/systems/_structure.py",
           "force = force.at[0].add(-bearing_force)",
           "force = force.at[0].add(bearing_force)",
           (f"{BW}::test_rigid_mass_with_eta_3_matches_scipy",), "vector field: friction pushes instead of resisting"),
    Mutant("S5", "teflon_jax/systems/_structure.py",
           'force = -self.mass * ground - self.damping @ y["v"]', 'force = self.mass * ground - self.damping @ y["v"]',
           (f"{SS}::test_coulomb_sliding_acceleration_closed_form",), "equation of motion: sign of the ground load"),
    # the optional parts in the structures
    Mutant("S8", EF, "return self.factor(pressure * self.contact_area)",
           "return self.factor(pressure * self.contact_area ** 0.5)",
           ("tests/test_pressure_in_structures.py",), "pressure dependence in a structure: N = p sqrt(A)"),
    Mutant("S9", "teflon_jax/systems/_bidirectional.py",
           "slide = jnp.sqrt(jnp.sum((d1 - d0) ** 2, axis=-1))", "slide = jnp.abs(d1 - d0)[:, 0]",
           ("tests/test_history_two_directions.py",), "heating in two directions: flux of the x speed only"),
    Mutant("S10", "teflon_jax/elements/_one_slider.py",
           "force = force * (1 + a * z)", "force = force * (1 - a * z)",
           ("tests/test_asymmetry_in_structures.py",), "asymmetry in the step's solve: 1 - a Z"),
    Mutant("S11", "teflon_jax/systems/_structure.py",
           "return self.bearing.asymmetry.factor(z)", "return 1.0",
           ("tests/test_asymmetry_in_structures.py",), "asymmetry left out of the reported force"),
    # the triple friction pendulum's series model
    Mutant("P1", "teflon_jax/bearing/_triple_pendulum.py",
           "return jnp.stack([2 * a, self.bottom_radius - a, self.top_radius - a])",
           "return jnp.stack([2 * a, self.bottom_radius, self.top_radius - a])",
           ("tests/test_triple_pendulum.py",), "series model: outer slider of radius b, not b - a"),
    Mutant("P2", "teflon_jax/bearing/_triple_pendulum.py",
           "inner = 2 * (self.inner_capacity + a * jnp.minimum(self.bottom_capacity / b,",
           "inner = 2 * (self.inner_capacity + a * jnp.maximum(self.bottom_capacity / b,",
           ("tests/test_triple_pendulum.py",), "series model: inner ring at the later outer ring"),
    # the triple pendulum in a structure, the vertical component, the pendulum's test record
    Mutant("P3", "teflon_jax/elements/_sliders.py",
           "speed, heading = slide * pendulum.velocity_factors() / time_step, direction",
           "speed, heading = slide / time_step, direction",
           ("tests/test_triple_structure.py",), "triple pendulum in a structure: Eq. 1 at the slider's speed, not the surface's"),
    Mutant("P4", "teflon_jax/cli/_simulate.py",
           "(result.fx + load * result.ux / radius, result.fy + load * result.uy / radius)",
           "(result.fx + load * result.ux / (2 * radius), result.fy + load * result.uy / (2 * radius))",
           ("tests/test_pendulum_fit.py",), "pendulum's test record: restoring force N u / (2 R)"),
    Mutant("V1", "teflon_jax/systems/_vertical.py",
           "return jnp.maximum(1 + jnp.asarray(vertical_acceleration) / STANDARD_GRAVITY, 0.0)",
           "return jnp.maximum(1 - jnp.asarray(vertical_acceleration) / STANDARD_GRAVITY, 0.0)",
           ("tests/test_vertical.py",), "vertical component: N = W (1 - a_v / g)"),
    Mutant("V2", "teflon_jax/systems/_vertical.py",
           "return jnp.maximum(1 + jnp.asarray(vertical_acceleration) / STANDARD_GRAVITY, 0.0)",
           "return 1 + jnp.asarray(vertical_acceleration) / STANDARD_GRAVITY",
           ("tests/test_vertical.py",), "uplift: a bearing in tension keeps carrying shear"),
    Mutant("D1", "teflon_jax/bearing/_series_pendulum.py",
           "return jnp.stack([jnp.asarray(self.bottom_capacity, float), jnp.asarray(self.top_capacity, float)])",
           "return jnp.stack([jnp.asarray(self.top_capacity, float), jnp.asarray(self.bottom_capacity, float)])",
           ("tests/test_double_pendulum.py",), "double pendulum: each surface's restrainer on the other surface"),
    Mutant("D2", "teflon_jax/bearing/_series_pendulum.py",
           '''        """(1, 1): each slider is its surface."""
        return jnp.ones(2)''',
           '''        """(1, 1): each slider is its surface."""
        return 2 * jnp.ones(2)''',
           ("tests/test_double_pendulum.py", "tests/test_double_fit.py"),
           "double pendulum: Eq. 1 at twice the surface's velocity"),
    Mutant("O1", "teflon_jax/structures/_overturning.py",
           "return -float(height) * k[:, None] * (p @ columns)",
           "return float(height) * k[:, None] * (p @ columns)",
           ("tests/test_slab_pendulum.py",), "overturning: the side the slab leans toward unloads"),
    Mutant("O2", "teflon_jax/structures/_overturning.py",
           "return jnp.maximum(normal_load, 0.0) / system.bearing_load",
           "return jnp.mean(jnp.maximum(normal_load, 0.0) / system.bearing_load) * jnp.ones_like(system.bearing_load)",
           ("tests/test_slab_pendulum.py",), "overturning: one load factor for every group (their mean)"),
    Mutant("O3", "teflon_jax/structures/_overturning.py",
           "return jnp.where(ok & lifts, n, jnp.where(rests, linear, tipped)), rests",
           "return jnp.where(ok & lifts, linear, jnp.where(rests, linear, tipped)), rests",
           ("tests/test_slab_series.py",), "uplift: a lifted group's share stays with the lever rule "
           "(the other supports take no more)"),
    Mutant("O5", "teflon_jax/structures/_overturning.py",
           "tipped = pressed * total / jnp.where(pressed_sum > 0, pressed_sum, 1.0)",
           "tipped = pressed",
           ("tests/test_slab_series.py",), "a slab that tips: the groups still down carry the lever "
           "rule's compressions, more than the weight"),
    Mutant("P5", "teflon_jax/bearing/_series_pendulum.py",
           "[getattr(self, n).scaled(factor) for n in names])",
           "[getattr(self, n).scaled(factor if i == 0 else 1.0) for i, n in enumerate(names)])",
           ("tests/test_series_bounding.py",), "bounding of a series pendulum: only the first "
           "surface's friction is scaled"),
    Mutant("O4", "teflon_jax/systems/_series.py",
           "system.bearing, state[\"heat\"], p[\"k\"], slider_lengths(d), system.time_step, system.heat_rates,\n"
           "            factor)",
           "system.bearing, state[\"heat\"], p[\"k\"], slider_lengths(d), system.time_step, system.heat_rates,\n"
           "            jnp.ones_like(factor))",
           ("tests/test_slab_series_heat.py",), "heated slab: each group's surfaces heat under the "
           "weight W_g, not its own normal load N_g"),
) + LAWS


def run(mutant: Mutant, timeout: float, source: pathlib.Path) -> tuple[str, float, str]:
    """Apply `mutant` in a fresh copy of `source`, run its tests, return (outcome, seconds, tail)."""
    with tempfile.TemporaryDirectory(prefix=f"mutant-{mutant.name}-") as tmp:
        root = pathlib.Path(tmp)
        for part in ("teflon_jax", "identification", "tests", "data", "pyproject.toml"):
            src = source / part
            (shutil.copytree if src.is_dir() else shutil.copy)(src, root / part)
        target = root / mutant.path
        text = target.read_text()
        if text.count(mutant.old) != 1:
            return "stale", 0.0, f"{mutant.path}: the original text occurs {text.count(mutant.old)} times"
        target.write_text(text.replace(mutant.old, mutant.new))
        if not mutant.groups:
            return pytest(root, mutant.tests, timeout)
        outcomes, total, tails = [], 0.0, []
        for who, tests in mutant.groups:
            outcome, seconds, _ = pytest(root, tests, timeout)
            outcomes.append(outcome)
            total += seconds
            tails.append(f"{who} {outcome}")
        killed_all = all(o == "killed" for o in outcomes)
        return ("killed" if killed_all else "survived"), total, "; ".join(tails)


def pytest(root: pathlib.Path, tests, timeout: float) -> tuple[str, float, str]:
    # whole files run their fast tests; a test named by its node id runs even where it is slow
    named = all("::" in t for t in tests)
    command = [sys.executable, "-m", "pytest", "-x", "-q", "-p", "no:cacheprovider",
               *(() if named else ("-m", "not slow")), *tests]
    env = dict(os.environ, PYTHONPATH=str(root), JAX_PLATFORMS=os.environ.get("JAX_PLATFORMS", "cpu"))
    start = time.monotonic()
    try:
        done = subprocess.run(command, cwd=root, env=env, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return "timeout", time.monotonic() - start, ""
    tail = (done.stdout + done.stderr).strip().splitlines()[-1:] or [""]
    outcome = "survived" if done.returncode == 0 else "killed"
    if done.returncode not in (0, 1):
        outcome = f"error (pytest exit {done.returncode})"
    return outcome, time.monotonic() - start, tail[0]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--only", nargs="*", help="names of the mutants to run (default: all)")
    parser.add_argument("--list", action="store_true", help="print the mutants and exit")
    parser.add_argument("--timeout", type=float, default=900.0, help="seconds per mutant's tests")
    parser.add_argument("--no-baseline", action="store_true", help="skip the unmutated run of all the tests")
    args = parser.parse_args()
    chosen = [m for m in MUTANTS if not args.only or m.name in args.only]
    if args.list:
        for m in chosen:
            print(f"{m.name}  {m.path}: {m.statement}\n      tests: {', '.join(m.tests)}")
        return 0
    if not args.no_baseline:
        tests = sorted({t for m in chosen for t in m.tests})
        outcome, seconds, tail = pytest(REPO, tests, args.timeout * 2)
        print(f"baseline (unmutated): {'pass' if outcome == 'survived' else outcome} in {seconds:.0f} s  {tail}",
              flush=True)
        if outcome != "survived":
            print("the unmutated tests do not pass; fix them before reading mutants", file=sys.stderr)
            return 2
    killed = 0
    for m in chosen:
        outcome, seconds, tail = run(m, args.timeout, REPO)
        killed += outcome == "killed"
        print(f"{m.name:3} {outcome:9} {seconds:6.0f} s  {m.statement}  [{tail}]", flush=True)
    print(f"killed {killed} / {len(chosen)}")
    return 0 if killed == len(chosen) else 1


if __name__ == "__main__":
    sys.exit(main())
