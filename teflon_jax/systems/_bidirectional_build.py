"""Building a `BidirectionalStructure`: shapes checked, Newmark's matrix prefactored, and its
state at rest."""

import jax
import jax.numpy as jnp

from ..bearing import SlidingBearing, heat_kernel_exponentials
from ..excitation import Signal
from ..solver import require_riccati_form
from ._bidirectional import NEWTON_ITERATIONS, BidirectionalStructure
from ._bidirectional_laws import check_planar_law
from ._overturning import initial_normal_load
from ._structure_build import HEAT_HORIZON, PRESSURE_HINT, STRUCTURE_EFFECTS


def bidirectional_structure(
    *,
    mass,
    stiffness,
    damping,
    influence,
    bearing_map,
    bearing: SlidingBearing,
    bearing_load,
    ground_x: Signal,
    ground_y: Signal,
    time_step: float,
    newton_iterations: int = NEWTON_ITERATIONS,
    contact_pressure=None,
    friction_model: str = "hysteretic",
    surface=None,
) -> BidirectionalStructure:
    """Build a `BidirectionalStructure`, checking shapes and prefactoring Newmark's matrix
    K_eff = K + (2/dt) C + (4/dt^2) M for `time_step` [s]. Bearing constants are broadcast to
    one per group; a bearing with heating needs `contact_pressure` [Pa] (one, or one per
    group). `friction_model` "hysteretic", "coulomb" or "none"; `surface`: a friction
    pendulum's `ConcaveSurface` whose W / R is in `stiffness` (its restrainer and
    large-displacement force act in the bearings' solve; W_g / R the groups' `pendulum_stiffness`,
    which a vertical record's load scales), or `None`."""
    mass = jnp.asarray(mass, dtype=float)
    n = mass.shape[0]
    bearing_map = jnp.asarray(bearing_map, dtype=float)
    bearing_load = jnp.atleast_1d(jnp.asarray(bearing_load, dtype=float))
    groups = bearing_load.shape[0]
    if bearing_map.shape != (groups, 2, n):
        raise ValueError(
            f"bearing_map: shape {bearing_map.shape}, expected (groups, 2, dofs) = ({groups}, 2, {n})."
        )
    if not time_step > 0:
        raise ValueError(f"time_step: must be > 0 s, got {time_step}.")
    require_riccati_form(bearing.hysteresis)
    check_planar_law(friction_model, surface, bearing)
    other = [name for name in bearing.effects if name not in STRUCTURE_EFFECTS]
    if other:
        raise ValueError(
            f"bearing: the structures in two directions do not run its "
            f"{', '.join(other)} (they run Eq. 1 at the resultant speed, Park's Z, "
            "breakaway, anisotropy, stacks, heating, wear and asymmetry)"
            + (PRESSURE_HINT if "pressure_dependence" in other else "."))
    rates = weights = None
    if bearing.heating is not None and friction_model == "hysteretic":
        if contact_pressure is None:
            raise ValueError("contact_pressure: a bearing with heating needs the contact pressure "
                             "[Pa] of the bearings (the heat flux is mu p |v|).")
        rates, weights = (jnp.asarray(a) for a in heat_kernel_exponentials(float(time_step),
                                                                           HEAT_HORIZON))
        contact_pressure = jnp.broadcast_to(jnp.asarray(contact_pressure, float), (groups,))
    bearing = jax.tree_util.tree_map(
        lambda leaf: jnp.broadcast_to(jnp.asarray(leaf, dtype=float), (groups,)), bearing
    )
    stiffness = jnp.asarray(stiffness, dtype=float).reshape(n, n)
    damping = jnp.asarray(damping, dtype=float).reshape(n, n)
    k_eff = stiffness + 2 / time_step * damping + 4 / time_step**2 * jnp.diag(mass)
    return BidirectionalStructure(
        mass=mass,
        stiffness=stiffness,
        damping=damping,
        influence=jnp.asarray(influence, dtype=float).reshape(n, 2),
        bearing_map=bearing_map,
        bearing=bearing,
        bearing_load=bearing_load,
        ground_x=ground_x,
        ground_y=ground_y,
        newmark_inverse=jnp.linalg.inv(k_eff),
        time_step=float(time_step),
        newton_iterations=int(newton_iterations),
        contact_pressure=contact_pressure if rates is not None else None,
        heat_rates=rates,
        heat_weights=weights,
        friction_model=friction_model,
        surface=None if surface is None or surface.is_linear else surface,
        pendulum_stiffness=None if surface is None else bearing_load / jnp.asarray(surface.radius, float),
    )


def bidirectional_initial_state(system: BidirectionalStructure) -> dict:
    """At rest relative to the ground, Z = 0 in every group (and cold, unworn bearings; with
    overturning, the groups' normal loads under the vertical record at t = 0)."""
    n, groups = system.mass.shape[0], system.bearing_load.shape[0]
    state = {"q": jnp.zeros(n), "v": jnp.zeros(n), "z": jnp.zeros((groups, 2)),
             "z_peak": jnp.zeros(groups)}
    if system.history:
        n_heat = 0 if system.heat_rates is None else system.heat_rates.shape[0]
        state.update(heat=jnp.zeros((groups, n_heat)), travel=jnp.zeros(groups))
    if system.overturning is not None:  # the groups' normal loads N_g [N] (`_overturning.py`)
        state["normal_load"] = initial_normal_load(system)
    return state
