"""The slab on triple or double friction pendulum groups (`_slab_series.py`): its construction
from a plan, and its histories from rest."""

import jax
import jax.numpy as jnp
import numpy as np

from ..bearing import SERIES_PENDULUMS, SeriesPendulum, check_series_pendulum
from ..excitation import Signal
from ..structures import overturning_map, support_plan
from ..units import STANDARD_GRAVITY
from ..validation import concrete
from ._isolator_balance import TRIPLE_NEWTON_ITERATIONS, TRIPLE_TOLERANCE
from ._response import StructureResponse
from ._slab_series import SlabOnSeries
from ._slider_forces import series_heat_kernel, surface_temperature_rises

SERIES_SLAB_ISOLATORS = tuple(SERIES_PENDULUMS)
"""`slab_on_bearings`'s isolators whose groups are series pendulums."""


def stack_pendulums(pendulums, isolator: str, groups: int) -> SeriesPendulum:
    """One `SeriesPendulum` whose array leaves hold every group's constants (G,), from one
    pendulum (all groups) or one per group, each of the kind `isolator` ("triple-fp" or
    "double-fp") and checked (`check_series_pendulum`); `ValueError` naming `pendulums`
    otherwise (another kind, a count other than G, groups that differ in their options, e.g.
    heating on different surfaces)."""
    if pendulums is None:
        raise ValueError(f"pendulums: isolator {isolator!r} needs its pendulum (one for all groups, or "
                         "one per group; e.g. formats.load_isolator(path)).")
    if isinstance(pendulums, SeriesPendulum):
        pendulums = [pendulums] * groups
    pendulums = list(pendulums)
    if len(pendulums) != groups:
        raise ValueError(f"pendulums: {len(pendulums)} given for {groups} groups; give one for all or one per group.")
    for index, pendulum in enumerate(pendulums):
        kind = getattr(pendulum, "isolator", type(pendulum).__name__)
        if not isinstance(pendulum, SeriesPendulum) or kind != isolator:
            raise ValueError(f"pendulums: group {index + 1} is a {kind}, not the {isolator} of isolator; "
                             "give every group a pendulum of that kind.")
        if all(concrete(leaf) is not None for leaf in jax.tree_util.tree_leaves(pendulum)):
            check_series_pendulum(pendulum)
    if len({jax.tree_util.tree_structure(p) for p in pendulums}) != 1:
        raise ValueError("pendulums: the groups' pendulums differ in their options (e.g. which surfaces "
                         "heat); give them the same.")
    return jax.tree_util.tree_map(lambda *leaves: jnp.stack([jnp.asarray(x, float) for x in leaves]),
                                  *pendulums)


def slab_step_matrix(mass, stiffness, influence, time_step):
    """(6, 16) [free (6, 6), start (6, 5), end (6, 5)] of the exact step of
    M q'' + K q = -M R a_g - f with x = (q, q') and the inputs (a_g (2,), f (3,)) varying
    linearly over `time_step` [s]: x1 = free x0 + start u0 + end u1. The blocks of the
    exponential of [[A, B, 0], [0, 0, I], [0, 0, 0]] dt (Van Loan 1978; as
    `exact_step_matrices` for one force)."""
    m = jnp.asarray(mass, float)
    eye, zeros = jnp.eye(3), jnp.zeros((3, 3))
    a = jnp.block([[zeros, eye], [-stiffness / m[:, None], zeros]])
    b = jnp.concatenate([jnp.zeros((3, 5)), jnp.concatenate([-jnp.asarray(influence, float), -jnp.diag(1 / m)], 1)])
    augmented = jnp.zeros((16, 16)).at[:6, :6].set(a).at[:6, 6:11].set(b).at[6:11, 11:].set(jnp.eye(5))
    e = jax.scipy.linalg.expm(augmented * time_step)
    end = e[:6, 11:] / time_step
    return jnp.concatenate([e[:6, :6], e[:6, 6:11] - end, end], axis=1)


def slab_on_series(*, weight, mass_inertia, centre_of_mass, positions, loads, pendulums, isolator,
                   ground_x: Signal, ground_y: Signal, time_step: float, height=0.0, vertical_stiffness=None,
                   names=None, newton_iterations: int = TRIPLE_NEWTON_ITERATIONS,
                   newton_tolerance: float = TRIPLE_TOLERANCE) -> SlabOnSeries:
    """`slab_on_bearings` with `isolator` "triple-fp" or "double-fp" (the plan already checked):
    weight W [N], rotational inertia `mass_inertia` [kg m^2], positions (G, 2) [m], loads W_g
    (G,) [N], `pendulums` (`stack_pendulums`), the centre of mass at `height` h [m] above the
    sliding surface (0: constant loads). Heated surfaces carry the heat kernel of one step to
    `HEAT_HORIZON` (`series_heat_kernel`)."""
    positions = np.asarray(positions, dtype=float).reshape(-1, 2)
    loads = np.asarray(loads, dtype=float).reshape(-1)
    groups = loads.size
    pendulum = stack_pendulums(pendulums, isolator, groups)
    overturning = (np.zeros((groups, 2)) if height == 0 else
                   overturning_map(positions, centre_of_mass, height, vertical_stiffness, names))
    supports = None if height == 0 else support_plan(positions, centre_of_mass, height, vertical_stiffness)
    r = positions - np.asarray(centre_of_mass, dtype=float).reshape(2)
    bearing_map = np.zeros((groups, 2, 3))
    bearing_map[:, 0, 0] = bearing_map[:, 1, 1] = 1.0
    bearing_map[:, 0, 2], bearing_map[:, 1, 2] = -r[:, 1], r[:, 0]
    if isinstance(time_step, bool) or not (isinstance(time_step, (int, float)) and time_step > 0):
        raise ValueError(f"time_step: must be a positive number of seconds, got {time_step!r}.")
    heat_rates, heat_weights = series_heat_kernel(pendulum, time_step)
    reference = loads / pendulum.reference_radius()
    stiffness = jnp.einsum("g,gdn,gdm->nm", reference, bearing_map, bearing_map)
    mass = jnp.array([weight / STANDARD_GRAVITY] * 2 + [mass_inertia])
    influence = np.array([[1.0, 0.0], [0.0, 1.0], [0.0, 0.0]])
    return SlabOnSeries(mass=mass, stiffness=stiffness, influence=jnp.asarray(influence),
                        bearing_map=jnp.asarray(bearing_map), pendulum=pendulum, bearing_load=jnp.asarray(loads),
                        reference_stiffness=reference, overturning=jnp.asarray(overturning), ground_x=ground_x,
                        ground_y=ground_y, step_matrix=slab_step_matrix(mass, stiffness, influence, time_step),
                        supports=supports, time_step=float(time_step), newton_iterations=int(newton_iterations),
                        newton_tolerance=float(newton_tolerance), heat_rates=heat_rates,
                        heat_weights=heat_weights)


def slab_steps(system: SlabOnSeries, duration: float) -> int:
    """Whole steps in `duration` [s], after checking that the records last that long."""
    dt = float(system.time_step)
    n_steps = int(round(duration / dt + 1e-9))
    if n_steps < 1:
        raise ValueError(f"duration: must be at least one time step ({dt} s), got {duration}.")
    for name, signal in (("ground_x", system.ground_x), ("ground_y", system.ground_y),
                         ("vertical_acceleration", system.vertical_acceleration)):
        if signal is not None:
            signal.require_covers(n_steps * dt, f"duration ({name})")
    return n_steps


def simulate_slab_series(system: SlabOnSeries, duration: float) -> StructureResponse:
    """Integrate the slab from rest over `duration` [s] (whole steps), every step kept.
    jit/vmap/grad-safe.

    **Returns:** a `StructureResponse` (two ground components; coordinates (x, y, rotation)):
    `bearing_force` (nt, G, 2) [N], each group's isolator force resisting its displacement;
    `bearing_displacement` (nt, G, 2) [m]; `slider` (nt, G, S, 2) [m]; `normal_load` (nt, G)
    [N] (a step's load at its end) and `group_uplift_time` (G,) [s]; `converged` (nt,) (the
    sliders' balance converged and the slab rested); `tipped` (nt,) (the slab could not rest on
    its groups: the overturning moment beyond what they hold without tension,
    `supported_loads`); `surface_temperature_rise` (nt, G, S) [K] (`surface_temperature_rises`;
    0 on a surface without heating), `None` where no surface heats."""
    dt = float(system.time_step)
    n_steps = slab_steps(system, duration)
    time = jnp.arange(n_steps + 1) * dt
    ground = jax.vmap(system.ground)(time)

    def rises(state):
        if system.heat_rates is None:
            return None
        return jax.vmap(surface_temperature_rises, in_axes=(0, 0, None))(system.pendulum, state["heat"],
                                                                          system.heat_weights)

    def body(state, inputs):
        new, converged = system.step(state, *inputs)
        return new, (new["x"], new["extra"], new["force"], new["slider"], new["normal_load"], converged,
                     new["tipped"], rises(new))

    start = system.initial_state()
    _, out = jax.lax.scan(body, start, (ground[:-1], ground[1:], time[1:]))
    first = (start["x"], start["extra"], start["force"], start["slider"], start["normal_load"], jnp.array(True),
             start["tipped"], rises(start))
    x, extra, force, slider, loads, converged, tipped, rise = (
        None if b is None else jnp.concatenate([a[None], b]) for a, b in zip(first, out))
    q = x[:, :3]
    acceleration = -(q @ system.stiffness.T + extra) / system.mass - ground @ system.influence.T
    return StructureResponse(
        time=time, displacement=q, velocity=x[:, 3:], total_acceleration=acceleration + ground @ system.influence.T,
        ground=ground, bearing_force=force, slider=slider,
        bearing_displacement=jnp.einsum("gdn,tn->tgd", system.bearing_map, q), normal_load=loads,
        group_uplift_time=jnp.sum(loads[1:] <= 0, axis=0) * dt, surface_temperature_rise=rise, tipped=tipped,
        converged=converged)
