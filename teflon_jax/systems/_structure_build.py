"""Building a `StructureOnSliders`: shapes checked, the step's matrices prefactored, and the
optional bearing parts a structure runs (heating, wear) with the heat kernel they need."""

import jax.numpy as jnp

from ..bearing import SlidingBearing, check_bearing, heat_kernel_exponentials
from ..excitation import Signal
from ._propagators import LINEAR_RULES, exact_step_matrices
from ._structure import FRICTION_MODELS, NEWTON_ITERATIONS, StructureOnSliders


def structure_on_sliders(
    *,
    mass,
    stiffness,
    damping,
    bearing: SlidingBearing | None,
    bearing_load,
    ground_acceleration: Signal,
    time_step: float,
    friction_model: str = "hysteretic",
    newton_iterations: int = NEWTON_ITERATIONS,
    split_at_turn: bool = False,
    linear_rule: str = "newmark",
    contact_pressure=None,
    surface=None,
    pendulum_stiffness=None,
) -> StructureOnSliders:
    """Build a `StructureOnSliders`, checking shapes and prefactoring the step's matrices.

    Newmark (average acceleration): K_eff = K + (2/dt) C + (4/dt^2) M, inverted once for
    `time_step`; with `linear_rule="exact"` also the exact step's matrices (`_propagators.exact_step_matrices`).
    A bearing with `heating` needs `contact_pressure` [Pa] (its kernel spans one time step to
    `HEAT_HORIZON`); of the optional parts, structures run `STRUCTURE_EFFECTS`. `surface`: a
    friction pendulum's `ConcaveSurface` whose force beyond W u / R the step solves
    (`StructureOnSliders.surface`; W / R itself belongs in `stiffness`). `pendulum_stiffness`
    W / R [N/m]: the part of K[0, 0] a vertical record's normal load scales (`with_vertical_motion`).
    """
    if friction_model not in FRICTION_MODELS:
        raise ValueError(
            f"friction_model: unknown {friction_model!r}; accepted values: {', '.join(FRICTION_MODELS)}."
        )
    if linear_rule not in LINEAR_RULES:
        raise ValueError(f"linear_rule: unknown {linear_rule!r}; accepted values: {', '.join(LINEAR_RULES)}.")
    mass = jnp.atleast_1d(jnp.asarray(mass, dtype=float))
    n = mass.shape[-1]
    stiffness = jnp.asarray(stiffness, dtype=float).reshape(mass.shape[:-1] + (n, n))
    damping = jnp.asarray(damping, dtype=float).reshape(mass.shape[:-1] + (n, n))
    if not time_step > 0:
        raise ValueError(f"time_step: must be > 0 s, got {time_step}.")
    if friction_model != "none":
        if bearing is None:
            raise ValueError("bearing: a SlidingBearing is needed unless friction_model='none'.")
        check_bearing(bearing)
    else:
        from ..bearing import coulomb_friction, paper_bearing

        bearing = paper_bearing(coulomb_friction(0.0)) if bearing is None else bearing
    rates, weights = _heat_kernel(bearing, friction_model, contact_pressure, time_step)
    k_eff = stiffness + 2 / time_step * damping + 4 / time_step**2 * jnp.vectorize(
        jnp.diag, signature="(n)->(n,n)"
    )(mass)
    return StructureOnSliders(
        mass=mass,
        stiffness=stiffness,
        damping=damping,
        bearing=bearing,
        bearing_load=jnp.asarray(bearing_load, dtype=float),
        ground_acceleration=ground_acceleration,
        time_step=float(time_step),
        newmark_inverse=jnp.linalg.inv(k_eff),
        friction_model=friction_model,
        newton_iterations=int(newton_iterations),
        split_at_turn=bool(split_at_turn),
        linear_rule=linear_rule,
        exact_step=_exact_step_matrix(mass, stiffness, damping, float(time_step)) if linear_rule == "exact" else None,
        contact_pressure=None if contact_pressure is None else jnp.asarray(contact_pressure, float),
        heat_rates=rates,
        heat_weights=weights,
        surface=surface,
        pendulum_stiffness=pendulum_stiffness,
    )


STRUCTURE_EFFECTS = ("heating", "wear", "asymmetry")
"""Optional bearing parts a structure on sliders runs (besides Eq. 1, breakaway, anisotropy,
stacks): heating and wear, factors on mu held over each step, and the direction asymmetry
1 + a Z, part of the bearing force solved for in each step. Only the hysteretic friction
model runs them."""

HEAT_HORIZON = 3600.0
"""Longest time [s] the heat kernel of a structure represents (the 1/sqrt(t) kernel is
accurate from one time step to this; an earthquake record is far shorter)."""


def check_structure_parts(bearing: SlidingBearing) -> None:
    """`ValueError` naming the optional parts of `bearing` a structure does not run."""
    other = [name for name in bearing.effects if name not in STRUCTURE_EFFECTS]
    if other:
        raise ValueError(
            f"bearing: the structures do not run its {', '.join(other)} (they run Eq. 1, "
            f"breakaway, anisotropy, stacks, {', '.join(STRUCTURE_EFFECTS)}); simulate the "
            "bearing test with `simulate-test --bearing`, or fit without these effects"
            + (PRESSURE_HINT if "pressure_dependence" in other else "."))


PRESSURE_HINT = ("; a pressure dependence is a constant factor at the bearings' contact "
                 "pressure p: give the structure `bearing.at_contact_pressure(p)` (the "
                 "isolated structures and the commands do this with their pressure).")


def _heat_kernel(bearing, friction_model, contact_pressure, time_step):
    """(rates, weights) of the heat kernel for a bearing with heating, else (None, None);
    `ValueError` for parts a structure does not run or a missing contact pressure."""
    if bearing is None:
        return None, None
    if friction_model != "hysteretic":
        if bearing.effects and friction_model == "coulomb":
            raise ValueError(f"bearing: the Coulomb model runs Eq. 1 alone, not its "
                             f"{', '.join(bearing.effects)}; use friction_model='hysteretic'.")
        return None, None
    check_structure_parts(bearing)
    if bearing.heating is None:
        return None, None
    if contact_pressure is None:
        raise ValueError("contact_pressure: a bearing with heating needs the contact pressure "
                         "[Pa] of the bearings (the heat flux is mu p |v|).")
    rates, weights = heat_kernel_exponentials(float(time_step), HEAT_HORIZON)
    return jnp.asarray(rates), jnp.asarray(weights)


def _exact_step_matrix(mass, stiffness, damping, time_step):
    """(R | f) of `_propagators.exact_step_matrices`, for a structure or a batch of them."""
    def one(m, k, c):
        step, force = exact_step_matrices(m, k, c, time_step)
        return jnp.concatenate([step, force[:, None]], 1)

    return jnp.vectorize(one, signature="(n),(n,n),(n,n)->(m,k)")(mass, stiffness, damping)


