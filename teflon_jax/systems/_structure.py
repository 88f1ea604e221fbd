"""Linear structures on sliding bearings under ground acceleration: the one stepped structure of
the library, for one or two horizontal components, one isolator or groups of them. Its step is
chosen by its static shape: the scalar step below for one isolator in one component (flat
sliders and single pendulums), the planar step (`_planar_step.py`) for groups of bearings
mapped by B (G, 2, N) under two, and the series balance (`_series.py`) for a friction pendulum
of sliders in series (`bearing` a `SeriesPendulum`), in one or two components.

Equations of motion in displacements relative to the ground (degree of freedom 0 is the
isolator, i.e. the base slab sliding on the bearings):

    M u'' + C u' + K u + e0 F = -M 1 a_g(t),     F = mu(u0', Zpeak) W Z

with W the normal load carried by the bearings, Z from Bouc-Wen (Eq. 3), mu from Eq. 1 / 17,
or, for the modified Coulomb model (Eq. 2), F = mu W sgn(u0') with sticking when the
demand is below mu W. The rigid mass of Figs. 7-10 is the 1-degree-of-freedom case; the
six-storey building of Fig. 11 has 7 (base + six floors).
Reference: Constantinou, Mokha & Reinhorn (1990), J. Struct. Eng. 116(2), Eqs. 2, 10-13.
"""

import dataclasses

import equinox as eqx
import jax.numpy as jnp

from ..bearing import (
    ConcaveSurface,
    SeriesPendulum,
    SlidingBearing,
    bouc_wen_rate,
    bouc_wen_reversal_length,
)
from ..elements import BALANCES, isolator_root, predicted_root
from ..excitation import Signal
from ..solver import AbstractSteppedSystem, require_riccati_form, structure_step_end
from ..structures import SupportPlan, newmark_step_matrices, small_dot
from ._bearing_test import running_peak_rate
from ._planar_step import PlanarStep, planar_initial_state
from ._vertical import (
    TablePressure,
    bearing_under_load,
    load_factor_at,
    loaded_isolator_force,
    loaded_surface_force,
)

FRICTION_MODELS = ("hysteretic", "coulomb", "none")


NEWTON_ITERATIONS = 40
"""Most bracketed Newton iterations per step (typically 2-4 are needed; the loop stops early)."""

NEWTON_TOLERANCE = 1e-5
"""Default `StructureOnSliders.newton_tolerance` [-]: the isolator's equilibrium is solved to
1e-5 Y (2.5 nm for Y = 0.01 in), far below anything a peak or an energy balance resolves; 1e-6
costs about 10 % more Newton iterations in a batch (measured on the rigid-mass Monte Carlo)."""

WRITTEN_OUT_PRODUCT = 8
"""Contraction length up to which the step's linear map is written out as sums of element
products (`small_dot`): the rigid mass (5 terms; 5 % faster on a CPU than a dot kernel per
step), not the building (17 terms: the written-out sum was 13 % slower, a broadcast product
and sum 50 %)."""

NEWTON_UNROLLED = 0
"""Newton iterations written out before the loop (`StructureOnSliders.newton_unrolled`): none, as
on a CPU XLA then recomputes the residual in each consumer (rigid-mass Monte Carlo 1.6-2.5x slower)."""


class StructureOnSliders(AbstractSteppedSystem, PlanarStep):
    """A linear structure isolated on sliding bearings, as a diffrax vector field.

    Without a bearing map (`planar` False) the fields and state are those below. With one
    (`influence` R (N, 2), `bearing_map` B (G, 2, N): `structure_on_sliders`, the slab, the
    building on a plan) the structure steps G groups under two components (`PlanarStep`):
    coordinates q (N,), array leaves of `bearing` (G,), `bearing_load` W_g (G,), state
    {"u" (N,), "v", "z" (G, 2), "z_peak" (G,)}; `load` the load factor of a copy at one time
    (`at_load`), `overturning` L (G, 2) and `supports` (`SupportPlan`) the groups' loads under
    the horizontal force, `step_matrix` the exact step of series pendulums on a plan.

    State: {"u": (n,) [m], "v": (n,) [m/s], "z": () [-], "z_peak": () [-]}, relative to the
    ground; index 0 is the isolator. `z_peak` is the running max |Z| that switches breakaway
    (Eq. 17) off: continuous for ODE solvers; for the stepped engine the max up to the start of
    each step, so that the force solved for and the force reported are one and the same.
    Bouc-Wen in the vector field (`__call__`) takes any A, beta, gamma, eta; `advance`
    (`RiccatiNewmark`) needs eta = 2 and gamma > beta and refuses other shapes.

    **Fields:**

    - `mass` (n,) [kg]; `stiffness` (n, n) [N/m]; `damping` (n, n) [N s/m] — including
      any restoring spring and viscous damper of the isolation system at index 0.
    - `bearing`: the isolator: a `SlidingBearing` (flat sliders or a single pendulum with
      `surface`; ignored when `friction_model == "none"`), or a `SeriesPendulum` (S sliders in
      series, `pendulum`), whose steps balance its sliders (`_series.py`: the structure's
      stiffness then holds the reference spring `reference_stiffness` at the isolator).
    - `bearing_load` W [N]: total normal load on the bearings.
    - `ground_acceleration`: `Signal` of a_g(t) [m/s^2].
    - `time_step` [s] (static): the step `RiccatiNewmark` uses (its Newmark matrix
      `newmark_inverse` = K_eff^-1 is prefactored for it).
    - `friction_model` (static): "hysteretic" (Bouc-Wen, the paper's model), "coulomb"
      (Eq. 2, stick-slip) or "none" (a linear isolation system).
    - `newton_iterations` (static): the most bracketed Newton iterations per step (the loop
      stops at tolerance); a step whose residual is still above tolerance after them is
      reported as not converged.
    - `split_at_turn` (static): in a step where the isolator's velocity changes sign, update
      Z along the two monotone pieces of Newmark's path (True: `isolated_structure`'s default,
      what its `RECOMMENDED_TIME_STEPS` rest on), or along the net increment (False, the
      default here, as the biaxial systems: it needs about half the step for that accuracy).
    - `newton_unrolled` (static): how many of the Newton iterations are written out in line
      before the loop (`NEWTON_UNROLLED`); the iterates, and so the results, do not depend on it.
    - `newton_tolerance` (static) [-]: converged when |residual| <= this Y (0: to rounding).
    - `linear_rule` (static): how the linear structure is advanced over a step (`LINEAR_RULES`):
      "newmark" (average acceleration, the default) or "exact" (exact for ground acceleration
      and bearing force linear over the step; `exact_step` holds its matrices).
    - `exact_step`: (R | f) (2n, 2n + 4) of `structures.exact_step_matrices` for "exact", else None.
    - `contact_pressure` [Pa]: pressure of the bearings on the steel, for a bearing with
      `heating` (the heat flux q = mu p |v| / n); `heat_rates`, `heat_weights`: its 1/sqrt(t)
      kernel (`heat_kernel_exponentials`). A bearing with heating or wear adds the state
      "heat" (the kernel's exponential states) and "travel" [m]; their factor on mu
      (`SlidingBearing.effect_factor`) is taken at the start of each step and held over it.
    - `surface`: a friction pendulum's `ConcaveSurface` whose large-displacement form or
      restrainer adds a nonlinear force E(u0) = `extra_force` at the isolator, solved with the
      friction in each step (hysteretic friction only); its linear part W / R is in
      `stiffness`. `None`: flat sliders, or a pendulum in the small-rotation form alone.
    - `vertical_acceleration`: `Signal` of a_v(t) [m/s^2, up +] or `None`: the normal load is
      then N = W max(1 + a_v / g, 0), on the friction and on `pendulum_stiffness` W / R [N/m]
      (the part of K[0, 0] the load carries), `_vertical.py` (`with_vertical_motion`); the
      friction then follows the contact pressure by `pressure_exponent` e (mu s^-e of a
      pressure dependence folded in at W, `pressure_factor`) or `pressure_table` (Table 1's
      ratios, `TablePressure`, `under_load`), or neither (`None`).
    - On a `SeriesPendulum` only: `reference_stiffness` W / R_ref [N/m] held in `stiffness`;
      `friction_velocity` (static, `FRICTION_VELOCITIES`): "mean" or, one surface, "end";
      `ground_y`: the y component's `Signal` [m/s^2] (the structure the same along y), or
      `None`; `balance` (static, `BALANCES`): how a two-component balance is iterated.
    """

    mass: jnp.ndarray
    stiffness: jnp.ndarray
    damping: jnp.ndarray
    bearing: SlidingBearing | SeriesPendulum | None
    bearing_load: jnp.ndarray
    ground_acceleration: Signal
    newmark_inverse: jnp.ndarray
    time_step: float = eqx.field(static=True)
    friction_model: str = eqx.field(static=True, default="hysteretic")
    newton_iterations: int = eqx.field(static=True, default=NEWTON_ITERATIONS)
    split_at_turn: bool = eqx.field(static=True, default=False)
    newton_unrolled: int = eqx.field(static=True, default=NEWTON_UNROLLED)
    newton_tolerance: float = eqx.field(static=True, default=NEWTON_TOLERANCE)
    linear_rule: str = eqx.field(static=True, default="newmark")
    exact_step: jnp.ndarray | None = None
    contact_pressure: jnp.ndarray | None = None
    heat_rates: jnp.ndarray | None = None
    heat_weights: jnp.ndarray | None = None
    surface: ConcaveSurface | None = None
    vertical_acceleration: Signal | None = None
    pendulum_stiffness: jnp.ndarray | None = None
    pressure_exponent: jnp.ndarray | None = None
    pressure_table: TablePressure | None = None
    reference_stiffness: jnp.ndarray | None = None
    friction_velocity: str = eqx.field(static=True, default="mean")
    ground_y: Signal | None = None
    balance: str = eqx.field(static=True, default="newton")
    influence: jnp.ndarray | None = None
    bearing_map: jnp.ndarray | None = None
    load: jnp.ndarray | None = None
    overturning: jnp.ndarray | None = None
    supports: SupportPlan | None = None
    step_matrix: jnp.ndarray | None = None

    def __check_init__(self):
        if self.balance not in BALANCES:
            raise ValueError(f"balance: unknown {self.balance!r}; accepted: {', '.join(BALANCES)}.")
        if (self.influence is None) != (self.bearing_map is None):
            raise ValueError("influence, bearing_map: a structure on bearing groups takes both (R (N, 2), B (G, 2, N)).")
        if self.ground_y is not None and self.pendulum is None and not self.planar:
            raise ValueError("ground_y: a structure on flat sliders or single pendulums takes two components "
                             "on its bearing groups (structure_on_sliders with influence and bearing_map).")

    @property
    def planar(self) -> bool:
        """True when stepped by groups under two components (`PlanarStep`; a bearing map)."""
        return self.bearing_map is not None

    @property
    def pendulum(self) -> SeriesPendulum | None:
        """The isolator when it is a `SeriesPendulum` (stepped by its sliders' balance), else None."""
        return self.bearing if isinstance(self.bearing, SeriesPendulum) else None

    @property
    def components(self) -> int:
        """C: 1 (the ground along x) or 2 (with `ground_y`)."""
        return 1 if self.ground_y is None else 2

    @property
    def uniaxial(self) -> "StructureOnSliders":
        """The same structure under the x component alone."""
        return dataclasses.replace(self, ground_y=None)

    def with_y_component(self, ground_y: Signal, balance: str = "newton") -> "StructureOnSliders":
        """The same structure on series pendulums (the same in x and in y) under the y ground
        component `ground_y` [m/s^2] too, its planar balance iterated by `balance` (`BALANCES`)."""
        return dataclasses.replace(self, ground_y=ground_y, balance=balance)

    def ground(self, t):
        """The ground acceleration at time t [s]: a_x (one component) or (a_x, a_y) [m/s^2]."""
        if self.ground_y is None:
            return self.ground_acceleration(t)
        return jnp.stack([self.ground_acceleration(t), self.ground_y(t)])

    def load_factor(self, t):
        """N(t) / W [-] at time t [s] (`normal_load_factor`); `None` without a vertical record."""
        return load_factor_at(self.vertical_acceleration, t)

    def loaded(self, value, load):
        """`value` (a force or a friction factor) times the load factor N / W `load`; itself
        for `load` `None`."""
        return value if load is None else value * load

    def under_load(self, load) -> "StructureOnSliders":
        """This structure, its bearing at the pressure of load factor `load` (`bearing_under_load`)."""
        return self if load is None else dataclasses.replace(self, **bearing_under_load(self, load))

    @property
    def history(self) -> bool:
        """True when the bearing's friction depends on the history (heating, wear)."""
        return self.friction_model == "hysteretic" and self.bearing.has_history

    def history_factor(self, heat, travel):
        """Factor on mu [-] of the surface temperature (heat states) and the travel [m]."""
        return self.bearing.history_factor(heat, travel, self.heat_weights)

    def at_history(self, heat, travel) -> "StructureOnSliders":
        """This structure with the friction of its bearing at that temperature and travel."""
        if not self.history:
            return self
        factor = self.history_factor(heat, travel)
        return eqx.tree_at(lambda s: s.bearing, self, self.bearing.scaled(factor))

    def at_state(self, y) -> "StructureOnSliders":
        """`at_history` of the state `y` (itself for a bearing without history)."""
        return self.at_history(y["heat"], y["travel"]) if self.history else self

    def next_history(self, heat, travel, u0, u1, v0, z_peak0, z0=0.0, load0=None):
        """Heat states and travel after a step from isolator displacement `u0` to `u1` [m]: the
        heat flux of the friction at the step's start, q = mu(v0) (1 + a z0) p |u1 - u0| /
        (dt n), held over the step (as `imposed_path_test` does between samples); with the
        load factor `load0`, q scales with it and an uplifted bearing (0) counts no travel."""
        mu0 = self.under_load(load0).at_history(heat, travel).bearing.coefficient(v0, 0.0, z_peak0)
        mu0 = mu0 * self.asymmetry_factor(z0)
        slide = jnp.abs(u1 - u0)
        if load0 is not None:
            mu0, slide = self.loaded(mu0, load0), jnp.where(load0 > 0, slide, 0.0)
        return self.bearing.next_history(heat, travel, slide, mu0, self.contact_pressure, self.time_step,
                                         self.heat_rates)

    def surface_force(self, u0, load=None):
        """E(u0) [N]: the surface's force beyond W u0 / R at isolator displacement u0 [m]
        (`ConcaveSurface.extra_force` under the bearings' load W; 0 without `surface`); with
        the load factor `load` = N / W, `loaded_surface_force`."""
        if load is not None:
            return loaded_surface_force(self, u0, load)
        if self.surface is None:
            return jnp.zeros_like(jnp.asarray(u0, dtype=float))
        return self.surface.extra_force(u0, self.bearing_load)

    def friction_force(self, velocity, z, z_peak, load=None):
        """F = mu W Z [N] at isolator `velocity` [m/s] (times `asymmetry_factor`, and the
        load factor N / W `load` when given)."""
        if self.friction_model == "none":
            return jnp.zeros_like(z)
        force = self.under_load(load).bearing.coefficient(velocity, 0.0, z_peak) * self.bearing_load * z
        force = force * self.asymmetry_factor(z)
        return self.loaded(force, load)

    def asymmetry_factor(self, z):
        """1 + a Z [-] of a bearing with direction asymmetry (`DirectionAsymmetry`), else 1."""
        if self.bearing.asymmetry is None:
            return 1.0
        return self.bearing.asymmetry.factor(z)

    def friction_factors(self, velocity, z_peak, load=None):
        """(mu W [N], d(mu W)/dv [N s/m]) at isolator `velocity` [m/s]: the bearing force per
        unit Z (F = mu W Z, `friction_force`) and its slope in the velocity, written out
        (`SlidingBearing.uniaxial_coefficient`); zeros for friction_model "none"; times the
        load factor N / W `load` when given."""
        if self.friction_model == "none":
            zero = jnp.zeros_like(jnp.asarray(velocity, dtype=float))
            return zero, zero
        mu, slope = self.under_load(load).bearing.uniaxial_coefficient(velocity, z_peak)
        load = self.loaded(self.bearing_load, load)
        return mu * load, slope * load

    def _acceleration(self, t, y):
        if self.planar:
            return self._planar_acceleration(t, y)
        return self.acceleration_at(self.ground_acceleration(t), y, self.load_factor(t))

    def acceleration_at(self, ground, y, load=None):
        """Relative acceleration [m/s^2] of state `y` under ground acceleration `ground` [m/s^2]
        (and the load factor N / W `load`); planar: `ground` (a_x, a_y), the load on the copy."""
        if self.planar:
            return self.planar_acceleration_at(ground, y)
        force = -self.mass * ground - self.damping @ y["v"] - self.stiffness @ y["u"]
        bearing_force = self.at_state(y).friction_force(y["v"][0], y["z"], y["z_peak"], load)
        if self.surface is not None or load is not None:
            bearing_force = bearing_force + self.surface_force(y["u"][0], load)
        force = force.at[0].add(-bearing_force)
        return force / self.mass

    def __call__(self, t, y, args):
        if self.planar:
            return self.planar_rates(t, y)
        dz = bouc_wen_rate(self.bearing.hysteresis, y["z"], y["v"][0])
        if self.friction_model == "coulomb":
            # Sliding branch of Eq. 2 only (Z = sign(v)): general ODE solvers cannot represent
            # sticking; RiccatiNewmark treats stick-slip exactly.
            dz = (jnp.sign(y["v"][0]) - y["z"]) / self.time_step
        elif self.friction_model == "none":
            dz = jnp.zeros_like(dz)
        rates = {
            "u": y["v"],
            "v": self._acceleration(t, y),
            "z": dz,
            "z_peak": running_peak_rate(jnp.abs(y["z"]), y["z_peak"], jnp.sign(y["z"]) * dz),
        }
        if self.history:
            rates.update(self._history_rates(y, self.load_factor(t)))
        return rates

    def _history_rates(self, y, load=None):
        """d(heat)/dt = q - lambda heat (the kernel's states), d(travel)/dt = |v| (q times the
        load factor `load`, no travel while uplifted)."""
        mu = self.under_load(load).at_state(y).bearing.coefficient(y["v"][0], 0.0, y["z_peak"])
        speed = jnp.abs(y["v"][0])
        if load is not None:
            mu, speed = self.loaded(mu, load), jnp.where(load > 0, speed, 0.0)
        heat, travel = self.bearing.history_rates(y["heat"], mu, self.contact_pressure, speed, self.heat_rates)
        return {"heat": heat, "travel": travel}

    def advance(self, t0, t1, y0, args):
        """`step_from` over [t0, t1], one `time_step` (checked), with the records evaluated at
        both ends (`RiccatiNewmark`); planar: `PlanarStep.planar_advance`."""
        if self.planar:
            return self.planar_advance(t0, t1, y0)
        t1 = structure_step_end(t0, t1, self.time_step)
        return self.step_from(y0, self.ground_acceleration(t0), self.ground_acceleration(t1),
                              self.load_factor(t0), self.load_factor(t1))

    def step_matrices(self):
        """(R (2n, 2n + 3), f (2n,)) of one step by `linear_rule` (`structures.newmark_step_matrices`, `structures.exact_step_matrices`):
        (u1, v1) = R (u0, v0, a_g0, F_r0, a_g1) + f F."""
        if self.linear_rule == "exact":
            return self.exact_step[:, :-1], self.exact_step[:, -1]
        return newmark_step_matrices(self.mass, self.stiffness, self.damping, self.newmark_inverse, self.time_step)

    def step_from(self, y0, ground0, ground1, load0=None, load1=None):
        """One step of `time_step` from the state `y0` (dict) by the engine's step
        (`history_step`, the step of `simulate_history` and `peak_response`), given the ground
        acceleration `ground0`, `ground1` [m/s^2] and, with `vertical_acceleration`, the load
        factors N / W `load0`, `load1` at its two ends. **Returns:** (state at the step's end,
        whether its balance converged)."""
        n = self.mass.shape[-1]
        history = (y0["heat"], y0["travel"]) if self.history else ()
        x1, z1, z_peak1, converged, history = self.history_step(
            jnp.concatenate([y0["u"], y0["v"]]), y0["z"], y0["z_peak"], None, ground0, ground1, history, load0, load1)
        return {"u": x1[:n], "v": x1[n:], "z": z1, "z_peak": z_peak1, **dict(zip(("heat", "travel"), history))}, converged

    def history_step(self, x0, z0, z_peak0, start_factors, ground0, ground1, history=(), load0=None, load1=None,
                     matrices=None):
        """`propagated_step` of a bearing with or without history (heating, wear): with
        `history` (heat states, travel) the step takes the friction of its start's history
        (`at_history`; `start_factors` recomputed under it), then advances the history
        (`next_history`); without, `start_factors` (`None`: `friction_factors` of the start).
        **Returns:** ((u1, v1), Z, running peak of |Z|, whether the solve converged, the
        history at the step's end (`()` without))."""
        n = self.mass.shape[-1]
        stepped = self.at_history(*history) if history else self
        if history or start_factors is None:  # the force at the step's start under the start's history
            start_factors = stepped.friction_factors(x0[n], z_peak0, load0)
        x1, z1, z_peak1, converged = stepped.propagated_step(x0, z0, z_peak0, start_factors, ground0, ground1,
                                                             matrices, load0, load1)
        if history:
            history = self.next_history(*history, x0[0], x1[0], x0[n], z_peak0, z0, load0)
        return x1, z1, z_peak1, converged, history

    def propagated_step(self, x0, z0, z_peak0, start_factors, ground0, ground1, matrices=None,
                        load0=None, load1=None):
        """One step as the linear map (u1, v1) = R w + f F of `step_matrices` (or `matrices`,
        the same computed once outside a loop), w = (u0, v0, a_g0, F_r0, a_g1), with F solved by
        `isolator_force`.

        **Arguments:** `x0` = (u0, v0) (2n,) [m, m/s]; `z0`, `z_peak0` [-]; `start_factors`
        (mu W, d(mu W)/dv) of the start state (`friction_factors`; F_r0 = mu W z0);
        `ground0`, `ground1` [m/s^2] at both ends; `load0`, `load1` the load factors N / W
        there (with `vertical_acceleration`; `start_factors` then under `load0`).

        **Returns:** ((u1, v1), Z, running peak of |Z|, whether the solve converged).
        """
        n = self.mass.shape[-1]
        step_matrix, force_column = self.step_matrices() if matrices is None else matrices
        start_force = start_factors[0] * z0 * self.asymmetry_factor(z0)
        if self.surface is not None or load0 is not None:
            start_force = start_force + self.surface_force(x0[0], load0)
        w = jnp.concatenate([x0, jnp.stack([ground0, start_force, ground1])])
        linear = small_dot(step_matrix, w, WRITTEN_OUT_PRODUCT)
        force, z1, z_peak1, converged = self.isolator_force(
            linear[0], {"u": x0[:n], "v": x0[n:], "z": z0, "z_peak": z_peak0}, linear[n],
            (-force_column[0], -force_column[n]), start_factors, load1)
        return linear + force_column * force, z1, z_peak1, converged

    def isolator_force(self, ub_linear, y0, vb_linear, compliance, start_factors=None, load=None):
        """The bearing force F [N] at the end of a step (and Z, the running peak of |Z| and
        whether the solve converged), given the isolator's displacement `ub_linear` [m] and
        velocity `vb_linear` [m/s] at the end of the step without the force and the state `y0`
        at its start. The isolator's displacement and velocity at the end are
        (ub_linear, vb_linear) - (g0, gv) F with `compliance` = (g0 [m/N], gv [m/(N s)]) (the
        force column of `step_matrices`; Newmark's: g0 = K_eff^-1[0, 0], gv = 2 g0 / dt).
        `start_factors`: `friction_factors` of
        `y0` (computed when not given), for the Newton iteration's first guess. `load`: the
        load factor N / W at the end of the step (`loaded_isolator_force`)."""
        ub0, vb0 = y0["u"][0], y0["v"][0]
        g0, gv = compliance
        if load is not None:
            return loaded_isolator_force(self, ub_linear, vb_linear, compliance, y0, start_factors, load)
        z0 = y0["z"]
        if self.surface is not None and self.friction_model != "hysteretic":
            raise ValueError("surface: the pendulum's nonlinear force is solved with hysteretic "
                             f"friction only, not {self.friction_model!r}.")
        # Breakaway (Eq. 17) is decided by the largest |Z| reached up to the start of the step:
        # the same running peak sets the force in the equilibrium below and the force reported
        # at the end of the step (`friction_force` of the stored state), so the switch acts once,
        # at one step, in both.
        z_peak1 = jnp.maximum(y0["z_peak"], jnp.abs(z0))
        if self.friction_model == "none":
            force, z1, converged = jnp.zeros_like(z0), z0, jnp.array(True)
        elif self.friction_model == "coulomb":
            force, z1 = self._coulomb_force(vb_linear, gv)
            converged = jnp.array(True)
        else:
            if start_factors is None:
                start_factors = self.friction_factors(vb0, y0["z_peak"])
            force, z1, converged = self._hysteretic_force(ub_linear, vb_linear, ub0, vb0, z0, z_peak1, g0, gv,
                                                          start_factors)
        return force, z1, z_peak1, converged

    def _coulomb_force(self, v_star, h):
        # Eq. 2 with an implicit (set-valued) friction force: the isolator velocity at the end of
        # the step is v* - h F; the force sticks (v = 0) when |v*/h| <= mu W, else slides at mu W.
        mu = self.bearing.coefficient(v_star, 0.0, 1.0)
        capacity = mu * self.bearing_load
        stick_force = v_star / h
        sticking = jnp.abs(stick_force) <= capacity
        force = jnp.where(sticking, stick_force, capacity * jnp.sign(v_star))
        loaded = capacity > 0  # not while uplifted (N = 0): Z = sgn(v*) there
        return force, jnp.where(loaded, force / jnp.where(loaded, capacity, 1.0), jnp.sign(v_star))

    def _hysteretic_force(self, ub_linear, vb_linear, ub0, vb0, z0, z_peak, g0, gv, start_factors):
        h = require_riccati_form(self.bearing.hysteresis)
        bearing = eqx.tree_at(lambda b: b.hysteresis, self.bearing, h)
        W = self.bearing_load
        f = self.bearing.friction
        mu_bound = f.f_max
        if self.bearing.breakaway_ratio is not None:
            mu_bound = jnp.maximum(mu_bound, self.bearing.breakaway_ratio * f.f_min)
        # Along a monotone increment |Z| stays below max(|z0|, its sliding value
        # (A / (beta + gamma))^(1/eta)), whatever A is, so |F| <= mu_bound W that.
        z_bound = jnp.maximum(jnp.abs(z0), (h.A / (h.beta + h.gamma)) ** (1 / h.eta))
        force_bound = mu_bound * W * z_bound * (1 + 1e-9)
        p = {"bearing": bearing, "W": W, "z0": z0, "z_peak": z_peak, "ub0": ub0,
             "vb0": vb0, "g0": g0, "ub_linear": ub_linear, "vb_linear": vb_linear,
             "velocity_gain": gv / g0,
             "reversal_length": bouc_wen_reversal_length(h, z0)}  # the same for every iterate
        if self.bearing.asymmetry is not None:  # |1 + a Z| <= 1 + |a| for |Z| <= 1
            p["asymmetry"] = self.bearing.asymmetry.asymmetry
            force_bound = force_bound * (1 + jnp.abs(p["asymmetry"]))
        lo, hi = ub_linear - g0 * force_bound, ub_linear + g0 * force_bound
        if self.surface is not None:  # E(x) increases with x and has its sign: the root lies
            p["surface"] = self.surface  # between the bracket and 0
            lo, hi = jnp.minimum(lo, 0.0), jnp.maximum(hi, 0.0)
        x0 = predicted_root(p, start_factors, lo, hi)
        eps = jnp.finfo(jnp.result_type(x0)).eps
        tolerance = jnp.maximum(self.newton_tolerance * h.yield_disp, 1e3 * eps * (jnp.abs(x0) + jnp.abs(ub_linear)))
        rule = (self.time_step, self.split_at_turn)
        x, force, z1 = isolator_root(rule, (self.newton_unrolled, self.newton_iterations), p, x0, lo, hi,
                                      tolerance)
        converged = jnp.abs(x - ub_linear + g0 * force) <= tolerance  # `isolator_residual`
        return force, z1, converged


def initial_state(system: StructureOnSliders) -> dict:
    """At rest, relative to the ground, with Z = 0 (and a cold, unworn bearing); planar: every
    group's (`planar_initial_state`)."""
    if system.planar:
        return planar_initial_state(system)
    n = system.mass.shape[-1]
    state = {"u": jnp.zeros(n), "v": jnp.zeros(n), "z": jnp.zeros(()), "z_peak": jnp.zeros(())}
    if system.history:
        rates = system.heat_rates if system.heat_rates is not None else jnp.zeros(0)
        state.update(heat=jnp.zeros_like(rates), travel=jnp.zeros(()))
    return state
