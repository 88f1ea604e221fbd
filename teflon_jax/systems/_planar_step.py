"""The planar step of a linear structure on groups of sliding bearings under two horizontal
ground components (`StructureOnSliders` with a bearing map).

Equations of motion in coordinates q (N,) relative to the ground (for example the x and y
displacements of every floor, or the (x, y, rotation) of a rigid slab):

    M q'' + C q' + K q + sum_g B_g^T F_g = -M R a_g(t),     a_g = (a_x, a_y),

with R (N, 2) the influence of the two ground components and B_g (2, N) the kinematics of
bearing group g: its sliding displacement is d_g = B_g q. Every group carries the normal load
W_g and resists with F_g = mu_g W_g (Zx, Zy)_g: Park's biaxial Z (Eqs. 8-9), Eq. 1 at the
resultant sliding speed (interpolated in the angle to the lay for anisotropic bearings) and the
breakaway friction of Eq. 17 until the group's |Z| first reaches 0.999.
Reference: Constantinou, Mokha & Reinhorn (1990), J. Struct. Eng. 116(2), Eqs. 1, 8-9, 17.

`advance` (used by `RiccatiNewmark`) and the engine take Newmark's average-acceleration rule for q and the
bearing forces at the end of the step, with each group's Z updated exactly along its straight
sliding increment (`park_exact_update`); the 2G bearing displacements solve
d - d_lin + G_b F(d) = 0 (G_b = B K_eff^-1 B^T) by `coupled_newton` from a predictor that holds
the start-of-step forces. A member within tolerance keeps its iterate; a step that does not
converge is reported per batch member.

The other laws of a group: Coulomb friction (Eq. 2 in the plane: each group slides along its
force F_g = mu_g W_g v_g / |v_g| or sticks with |F_g| <= mu_g W_g; over a step the maximum
dissipation problem of `coulomb_disc_forces`), no friction (a linear structure), and a friction
pendulum's `ConcaveSurface`, whose restrainer and large-displacement force add
`ConcaveSurface.extra_force` at d_g (under the group's normal load) to the friction force, its
small-rotation part W_g / R being in K.
References: Moreau (1988); Beck & Teboulle (2009), SIAM J. Imaging Sciences 2(1), 183-202.
"""

import equinox as eqx
import jax
import jax.numpy as jnp

from ..bearing import SeriesPendulum, park_rate
from ..solver import (
    affine,
    block_matvec,
    coulomb_disc_forces,
    coupled_newton,
    matvec,
    park_exact_update,
    park_exact_update_and_slope,
    structure_step_end,
)
from ..structures import (
    group_factor,
    initial_normal_load,
    overturning_force,
    small_dot,
    supported_loads,
)
from ._bearing_test import running_peak_rate
from ._vertical import (
    loaded_bidirectional,
    loaded_heat,
    loaded_solve,
    pendulum_change,
)

PLANAR_NEWTON_ITERATIONS = 100
"""Most iterations per step, all kinds together (`coupled_newton`'s fixed Broyden step, its
Broyden loop and its Newton loop; the loops run only for members still above tolerance)."""


class PlanarStep(eqx.Module):
    """The step of a `StructureOnSliders` with a bearing map (G groups, two components): its
    strategy for the equations of the module docstring, chosen by the structure's static shape
    (`StructureOnSliders.planar`). No fields of its own: it reads the structure's.

    State: {"u": (N,) [m or rad] (the coordinates q), "v": (N,), "z": (G, 2) [-], "z_peak": (G,)
    [-]} relative to the ground, the keys of the scalar step's state; `z_peak` is the largest resultant |Z| of each group so far (Eq. 17 switch),
    with "heat" (G, K) and "travel" (G,) [m] for a bearing with history and "normal_load" (G,)
    [N] with overturning loads.
    """

    def load_at(self, t, y):
        """The load factor at time t [s] and state `y`: s (`load_factor`), or one per group
        from the state's normal loads with `overturning`."""
        if self.overturning is None:
            return self.load_factor(t)
        return group_factor(self, y["normal_load"])

    def at_load(self, load):
        """This structure under the load factor `load` (itself for `None`): `loaded_bidirectional`."""
        return self if load is None else loaded_bidirectional(self, load)

    def bearing_forces(self, y):
        """F_g (G, 2) [N] of state `y` (`friction_forces` at its velocities and history)."""
        return self.at_state(y).friction_forces(self.bearing_motion(y["v"]), y["z"], y["z_peak"])

    def bearing_motion(self, q):
        """Sliding displacement (or velocity) (G, 2) of every group for coordinates q."""
        return jnp.sum(self.bearing_map * q, axis=-1)

    def friction_forces(self, velocity, z, z_peak):
        """F_g = mu_g W_g Z_g (G, 2) [N] at sliding velocities (G, 2) [m/s] (zeros without
        friction)."""
        if self.friction_model == "none":
            return jnp.zeros_like(z)
        mu = self.bearing.coefficient(velocity[:, 0], velocity[:, 1], z_peak)
        return (mu * self.bearing_load * self._asymmetry(z[:, 0])[1])[:, None] * z

    def _asymmetry(self, zx):
        """(a, 1 + a Z_x) per group for a bearing with direction asymmetry, else (0, 1): the
        factor on mu of `DirectionAsymmetry`."""
        if self.bearing.asymmetry is None:
            return 0.0, jnp.ones_like(zx)
        a = self.bearing.asymmetry.asymmetry
        return a, 1 + a * zx

    def _load(self, ground):
        """-M R a_g [N] for the ground acceleration `ground` (a_x, a_y) [m/s^2]."""
        return -self.mass * small_dot(self.influence, ground)

    def _planar_acceleration(self, t, y):
        return self.at_load(self.load_at(t, y)).planar_acceleration_at(self.ground(t), y)

    def planar_acceleration_at(self, ground, y):
        """Acceleration [m/s^2 or rad/s^2] of state `y` under ground acceleration `ground` (2,)."""
        forces = self.bearing_forces(y)
        if self.surface is not None:
            d = self.bearing_motion(y["u"])
            forces = jnp.stack(with_surface_forces(self, (forces[:, 0], forces[:, 1]), (d[:, 0], d[:, 1])), -1)
        if self.load is not None:  # the pendulum's (s - 1) W_g / R d_g
            forces = forces + pendulum_change(self)[:, None] * self.bearing_motion(y["u"])
        restoring = jnp.sum(self.bearing_map * forces[..., None], axis=(0, 1))
        total = self._load(ground) - small_dot(self.damping, y["v"]) - small_dot(self.stiffness, y["u"]) - restoring
        return total / self.mass

    def planar_rates(self, t, y):
        """The vector field (`StructureOnSliders.__call__`) of the planar state."""
        velocity = self.bearing_motion(y["v"])
        dz = park_rate(self.bearing.hysteresis, y["z"], velocity)
        if self.friction_model == "coulomb":
            # the sliding branch of Eq. 2 (Z along v): general ODE solvers cannot represent
            # sticking; RiccatiNewmark treats stick-slip exactly
            speed = jnp.sqrt(jnp.sum(velocity**2, axis=-1, keepdims=True))
            dz = (velocity / jnp.maximum(speed, 1e-300) - y["z"]) / self.time_step
        elif self.friction_model == "none":
            dz = jnp.zeros_like(dz)
        z_abs = jnp.sqrt(jnp.sum(y["z"] ** 2, axis=-1) + 1e-300)
        z_abs_rate = jnp.sum(y["z"] * dz, axis=-1) / z_abs
        rates = {
            "u": y["v"],
            "v": self._planar_acceleration(t, y),
            "z": dz,
            "z_peak": running_peak_rate(z_abs, y["z_peak"], z_abs_rate),
        }
        if self.history:
            speed = jnp.sqrt(jnp.sum(velocity**2, axis=-1))
            loaded = self.at_load(self.load_at(t, y))
            mu = loaded.at_state(y).bearing.coefficient(velocity[:, 0], velocity[:, 1], y["z_peak"])
            mu, speed = loaded_heat(loaded, mu, speed)
            rates["heat"], rates["travel"] = self.bearing.history_rates(
                y["heat"], mu, self.contact_pressure, speed, self.heat_rates)
        if self.overturning is not None:  # held over fixed steps (RiccatiNewmark) only
            rates["normal_load"] = jnp.zeros_like(y["normal_load"])
        return rates

    def planar_advance(self, t0, t1, y0):
        """One `time_step` over [t0, t1] (checked) from the state `y0`, the engine's step
        (`newmark_update` under the load factor at t1; `overturning_step` with overturning
        loads), with the acceleration at (t0, y0) from the equation of motion
        (`RiccatiNewmark`)."""
        t1 = structure_step_end(t0, t1, self.time_step)
        a0 = self._planar_acceleration(t0, y0)
        if self.overturning is not None:
            return overturning_step(self, t0, t1, y0, a0)[:2]
        return self.at_load(self.load_factor(t1)).newmark_update(y0, a0, self.ground(t1))

    def newmark_update(self, y0, a0, ground1):
        """One step of `time_step` from state `y0` with acceleration `a0`, given the ground
        acceleration `ground1` (a_x, a_y) [m/s^2] at its end (a loop over a grid of steps can
        evaluate the record at all of them at once, outside the loop). A bearing with history
        steps with its friction at the start of the step, then advances its heat and travel.
        A loaded copy (`at_load`, the load factor at the step's end) steps under that load."""
        if not self.history:
            return self._update(y0, a0, ground1)
        stepped = self.at_state(y0)
        y1, converged = stepped._update(y0, a0, ground1)
        d0, d1, v0 = (self.bearing_motion(y0["u"]), self.bearing_motion(y1["u"]),
                      self.bearing_motion(y0["v"]))
        slide = jnp.sqrt(jnp.sum((d1 - d0) ** 2, axis=-1))
        mu0 = stepped.bearing.coefficient(v0[:, 0], v0[:, 1], y0["z_peak"])
        mu0, slide = loaded_heat(self, mu0 * self._asymmetry(y0["z"][:, 0])[1], slide)
        heat, travel = self.bearing.next_history(y0["heat"], y0["travel"], slide, mu0,
                                                 self.contact_pressure, self.time_step, self.heat_rates)
        return {**y1, "heat": heat, "travel": travel}, converged

    def _update(self, y0, a0, ground1):
        dt = self.time_step
        m, q0, v0 = self.mass, y0["u"], y0["v"]
        rhs = self._load(ground1) + m * (4 / dt**2 * q0 + 4 / dt * v0 + a0) + small_dot(self.damping, 2 / dt * q0 + v0)
        q_linear = small_dot(self.newmark_inverse, rhs)
        # Every vector over the bearings is kept as its x and y parts (G,) apart: under `vmap`
        # an interleaved (G, 2) layout keeps XLA's CPU loops from vectorising (4x dearer).
        bx, by = self.bearing_map[:, 0, :], self.bearing_map[:, 1, :]  # (G, N)
        cx, cy = small_dot(self.newmark_inverse, bx.T), small_dot(self.newmark_inverse, by.T)  # (N, G)
        # Breakaway (Eq. 17) is decided by the largest |Z| reached up to the start of the step,
        # in the equilibrium solved here and in the force reported for the stored state alike
        # (as in the scalar step of one component), so the switch acts once, at one step.
        z_peak = jnp.maximum(y0["z_peak"], jnp.sqrt(jnp.sum(y0["z"] ** 2, axis=-1)))
        # one product for the bearing motions of the three vectors (fewer small kernels)
        motion = small_dot(jnp.stack([q_linear, q0, v0]), jnp.concatenate([bx, by]).T)  # (3, 2G)
        n_groups = bx.shape[0]
        d_linear, d0, vb0 = ((row[:n_groups], row[n_groups:]) for row in motion)
        p = {
            "d_linear": d_linear,
            "flexibility": ((small_dot(bx, cx), small_dot(bx, cy)), (small_dot(by, cx), small_dot(by, cy))),
            "d0": d0,
            "vb0": vb0,
            "z0": (y0["z"][:, 0], y0["z"][:, 1]),
            "z_peak0": z_peak,
        }
        if self.load is None:
            (fx, fy), z1, converged = self._solve_bearings(p)
        else:  # the pendulum's change of stiffness moved into the bearings' problem
            (fx, fy), z1, converged = loaded_solve(self, p)
        q1 = q_linear - matvec(cx, fx) - matvec(cy, fy)
        v1 = 2 / dt * (q1 - q0) - v0
        return {"u": q1, "v": v1, "z": z1, "z_peak": z_peak}, converged

    def _forces_at(self, d, p):
        """Forces (x, y parts, each (G,)) [N] and Z (G, 2) for bearing displacements d = (dx, dy)
        at t1."""
        increment = [d[i] - p["d0"][i] for i in range(2)]
        z = park_exact_update(self.bearing.hysteresis, jnp.stack(p["z0"], -1), jnp.stack(increment, -1))
        vx, vy = (2 / self.time_step * increment[i] - p["vb0"][i] for i in range(2))
        capacity = self.bearing.coefficient(vx, vy, p["z_peak0"]) * self.bearing_load
        capacity = capacity * self._asymmetry(z[:, 0])[1]
        return with_surface_forces(self, (capacity * z[:, 0], capacity * z[:, 1]), d), z

    def _residual_forces(self, d, p):
        """(residual, (forces, Z)) at bearing displacements d = (dx, dy): r = d - d_lin + G_b F(d)."""
        forces, z = self._forces_at(d, p)
        return affine(p["flexibility"], forces, d, p["d_linear"]), (forces, z)

    def _tangent_jacobian(self, d, p, exact: bool = False):
        """Residual r at d = (dx, dy), the Jacobian dr/dd (blocks ((xx, xy), (yx, yy)), each
        (G, G)), and (the forces, Z) there. The Jacobian is I + G_b K, K each group's 2 x 2 block
        of the forces, W ((1 + a Z_x) (mu dZ/dU + Z dmu/dU^T) + a mu Z dZ_x/dU^T) with dmu/dv of
        Eq. 1, and by default the tangent of Park's law at the end of the increment,
        dZ/dU = (A I - Z w^T) / Y with w_i = (gamma s_i + beta) Z_i (exact along the increment,
        too stiff across a long one: the secant updates of `coupled_newton` correct it); with
        `exact`, Park's slope written out (`park_exact_update_and_slope`), the exact Jacobian
        of Newton's stage."""
        dt = self.time_step
        h = self.bearing.hysteresis
        increment = [d[i] - p["d0"][i] for i in range(2)]
        if exact:
            z, slope = park_exact_update_and_slope(h, jnp.stack(p["z0"], -1), jnp.stack(increment, -1))
        else:
            z = park_exact_update(h, jnp.stack(p["z0"], -1), jnp.stack(increment, -1))
        zs = (z[:, 0], z[:, 1])
        vx, vy = (2 / dt * increment[i] - p["vb0"][i] for i in range(2))

        def coefficient(vx, vy):
            return self.bearing.coefficient(vx, vy, p["z_peak0"])

        mu, dmu_x = jax.jvp(coefficient, (vx, vy), (jnp.ones_like(vx), jnp.zeros_like(vy)))
        _, dmu_y = jax.jvp(coefficient, (vx, vy), (jnp.zeros_like(vx), jnp.ones_like(vy)))
        load = self.bearing_load
        a, k = self._asymmetry(zs[0])
        forces = with_surface_forces(self, (mu * load * k * zs[0], mu * load * k * zs[1]), d)
        r = affine(p["flexibility"], forces, d, p["d_linear"])
        dmu = (dmu_x * (2 / dt), dmu_y * (2 / dt))
        # local 2 x 2 block per group: W ((1 + a Z_x) (mu dZ/dU + Z dmu/dU^T) + a mu Z dZ_x/dU^T)
        if exact:
            dz = [[slope[:, i, j] for j in range(2)] for i in range(2)]
        else:
            w = [(h.gamma * jnp.where(increment[i] * zs[i] >= 0, 1.0, -1.0) + h.beta) * zs[i] for i in range(2)]
            dz = [[((h.A if i == j else 0.0) - zs[i] * w[j]) / h.yield_disp for j in range(2)]
                  for i in range(2)]
        local = [[load * (k * (mu * dz[i][j] + zs[i] * dmu[j]) + a * mu * zs[i] * dz[0][j])
                  for j in range(2)] for i in range(2)]
        if self.surface is not None:
            stiffening = surface_tangent(self, d[0], d[1])
            local = [[local[i][j] + stiffening[i][j] for j in range(2)] for i in range(2)]
        flex = p["flexibility"]
        eye = jnp.eye(load.shape[0])
        jacobian = [[(eye if i == j else 0.0) + sum(flex[i][k] * local[k][j][None, :] for k in range(2))
                     for j in range(2)] for i in range(2)]
        return r, jacobian, (forces, z)

    def _solve_bearings(self, p):
        """Bearing forces (x, y parts), Z (G, 2) and convergence at t1: from the predictor
        that holds the start-of-step forces, `coupled_newton` (Broyden's secant iterations
        from the tangent of Park's law at the end state, then Newton's method on the exact
        Jacobian). Converged when max|r| <= tolerance. Coulomb friction: `coulomb_disc_forces`;
        no friction: zero forces, Z held."""
        if self.friction_model == "coulomb":
            return self._coulomb_solve(p)
        if self.friction_model == "none":
            zero = jnp.zeros_like(p["d_linear"][0])
            return (zero, zero), jnp.stack(p["z0"], -1), jnp.asarray(True)
        x, tolerance = self._predictor(p)
        r, (forces, z) = coupled_newton(lambda d: self._residual_forces(d, p),
                                        lambda d, exact: self._tangent_jacobian(d, p, exact), x, tolerance,
                                        self.newton_iterations)
        return forces, z, jnp.max(jnp.abs(r)) <= tolerance

    def _coulomb_solve(self, p):
        """Coulomb friction (Eq. 2 in the plane) over the step: the velocities at its end are
        v = v* - H F, H = (2 / dt) G_b, v* those of the step without bearing forces, and F the
        minimiser of F^T H F / 2 - v*^T F over the discs |F_g| <= mu_g W_g
        (`coulomb_disc_forces`); mu is Eq. 1 at |v*_g| (as in one direction) and
        Z_g = F_g / (mu_g W_g), along v* while a group is uplifted (N = 0)."""
        dt = self.time_step
        compliance = 2 / dt * jnp.block([list(row) for row in p["flexibility"]])
        v_star = jnp.concatenate([2 / dt * (p["d_linear"][i] - p["d0"][i]) - p["vb0"][i] for i in range(2)])
        n = p["d0"][0].shape[0]
        capacity = self.bearing.coefficient(v_star[:n], v_star[n:], 1.0) * self.bearing_load  # (G,)
        force, converged = coulomb_disc_forces(compliance, v_star, capacity)
        loaded = capacity > 0
        along = jnp.stack([v_star[:n], v_star[n:]], -1)
        direction = along / jnp.maximum(jnp.sqrt(jnp.sum(along**2, -1)), jnp.finfo(v_star.dtype).tiny)[:, None]
        z = jnp.where(loaded[:, None], force / jnp.where(loaded, capacity, 1.0)[:, None], direction)
        return (force[:, 0], force[:, 1]), z, converged

    def _predictor(self, p):
        """Bearing displacements (x, y parts) with the bearing forces held at their
        start-of-step values (exact while sliding at constant Z and speed) and the tolerance on
        the residual."""
        capacity = self.bearing.coefficient(p["vb0"][0], p["vb0"][1], p["z_peak0"]) * self.bearing_load
        capacity = capacity * self._asymmetry(p["z0"][0])[1]
        held = block_matvec(p["flexibility"], with_surface_forces(
            self, (capacity * p["z0"][0], capacity * p["z0"][1]), p["d0"]))
        x = tuple(p["d_linear"][i] - held[i] for i in range(2))
        scale = jnp.maximum(*(jnp.max(jnp.abs(x[i]) + jnp.abs(p["d_linear"][i])) for i in range(2)))
        eps = jnp.finfo(jnp.result_type(x[0])).eps
        yield_disp = jnp.min(jnp.asarray(self.bearing.hysteresis.yield_disp))
        return x, jnp.maximum(self.newton_tolerance * yield_disp, 1e3 * eps * scale)


def overturning_step(system, t0, t1, y0, a0):
    """One step of `system` (a planar `StructureOnSliders` with `overturning`) from (t0, y0) with
    acceleration a0: the groups' loads from H at t0 and the vertical record at t1, held over the
    step; the loads are kept in the state ("normal_load"). **Returns:** (state, whether the
    step balanced, whether the slab tipped on it (`supported_loads`), which is not balanced)."""
    loads, rests = supported_loads(system, overturning_force(system, a0, system.ground(t0)), t1)
    y1, converged = system.at_load(group_factor(system, loads)).newmark_update(y0, a0, system.ground(t1))
    return {**y1, "normal_load": loads}, converged & rests, ~rests


def _surface_forces(system, dx, dy):
    """The surface's force beyond W_g d_g / R (x and y parts, each (G,)) [N] at the groups'
    displacements (dx, dy) [m], under the groups' loads `bearing_load`."""
    force = system.surface.extra_force(jnp.stack([dx, dy], -1), system.bearing_load)
    return force[:, 0], force[:, 1]


def with_surface_forces(system, forces, d):
    """`forces` (x, y parts) [N] plus the surface's at the displacements `d` (x, y parts) [m];
    `forces` themselves without a nonlinear surface (no work added to the flat sliders' step)."""
    if system.surface is None:
        return forces
    extra = _surface_forces(system, d[0], d[1])
    return forces[0] + extra[0], forces[1] + extra[1]


def surface_tangent(system, dx, dy):
    """d(surface force)/d(d) per group: ((xx, xy), (yx, yy)), each (G,) [N/m]."""
    def force(dx, dy):
        return _surface_forces(system, dx, dy)

    _, column_x = jax.jvp(force, (dx, dy), (jnp.ones_like(dx), jnp.zeros_like(dy)))
    _, column_y = jax.jvp(force, (dx, dy), (jnp.zeros_like(dx), jnp.ones_like(dy)))
    return (column_x[0], column_y[0]), (column_x[1], column_y[1])


def planar_initial_state(system) -> dict:
    """At rest relative to the ground, Z = 0 in every group (and cold, unworn bearings; with
    overturning, the groups' normal loads under the vertical record at t = 0). `TypeError` for
    groups of series pendulums, whose state is `series_initial_state`'s."""
    check_sliding_groups(system)
    n, groups = system.mass.shape[0], system.bearing_load.shape[0]
    state = {"u": jnp.zeros(n), "v": jnp.zeros(n), "z": jnp.zeros((groups, 2)),
             "z_peak": jnp.zeros(groups)}
    if system.history:
        n_heat = 0 if system.heat_rates is None else system.heat_rates.shape[0]
        state.update(heat=jnp.zeros((groups, n_heat)), travel=jnp.zeros(groups))
    if system.overturning is not None:  # the groups' normal loads N_g [N] (`teflon_jax.structures`: `supported_loads`)
        state["normal_load"] = initial_normal_load(system)
    return state


def check_sliding_groups(system) -> None:
    """`TypeError` naming the structure where its groups are series pendulums (`SeriesPendulum`):
    their slab steps from `series_initial_state` (`_series.py`), not from the state of
    sliding groups."""
    if isinstance(system.bearing, SeriesPendulum):
        raise TypeError("system: a slab on triple or double pendulum groups starts from series_initial_state; "
                        "run it with simulate_history or peak_response.")
