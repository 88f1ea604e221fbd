"""The linear structures on sliding bearings built, in one or two horizontal components: the
general structure (`structure_on_sliders`) and the paper's two (`rigid_mass`,
`six_storey_building`, their linear parts `teflon_jax.structures.rigid_mass_matrices`,
`building_matrices`), shapes checked, the step's matrices prefactored, and the optional bearing
parts a structure runs (heating, wear) with the heat kernel they need.

The number of horizontal components C is read from the arguments: one (the ground along x,
one isolator at degree of freedom 0) gives a `StructureOnSliders`, stepped by the bracketed
scalar Newton of one slider in one direction; two (the influence R (N, 2) and the bearing map
B (G, 2, N) of G bearing groups, or `components=2` for the paper's structures) give a
planar one, stepped by the planar coupled Newton of Park's Z. A structure on
series pendulums is built from the linear structure by `structure_on_isolator`.
Reference for the structures: Constantinou, Mokha & Reinhorn (1990), J. Struct. Eng. 116(2),
Figs. 7-11 and Table 2.
"""

import jax
import jax.numpy as jnp
import numpy as np

from ..bearing import (
    HEAT_HORIZON,
    SeriesPendulum,
    SlidingBearing,
    check_bearing,
    heat_kernel_exponentials,
)
from ..excitation import Signal
from ..solver import require_riccati_form
from ..structures import (
    LINEAR_RULES,
    building_matrices,
    exact_step_matrices,
    rigid_mass_matrices,
)
from ..tables import BuildingData
from ._planar_step import PLANAR_NEWTON_ITERATIONS
from ._structure import (
    FRICTION_MODELS,
    NEWTON_ITERATIONS,
    StructureOnSliders,
)

BIDIRECTIONAL_TIME_STEP = 0.0025
"""Default step [s] of the bidirectional structures: peak resultant base displacement and base
shear within 0.5 % of adaptive Tsit5 (rtol 1e-9) for the rigid mass and the building under the
PEER RSN6 pair and the SCT 1985 pair (tests/test_bidirectional_records.py); at 10 ms the RSN6
building is 1.2 % off."""


COMPONENTS = (1, 2)
"""The numbers of horizontal ground components a structure takes."""


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
    newton_iterations: int | None = None,
    split_at_turn: bool = False,
    linear_rule: str = "newmark",
    contact_pressure=None,
    surface=None,
    pendulum_stiffness=None,
    influence=None,
    bearing_map=None,
    ground_y: Signal | None = None,
) -> StructureOnSliders:
    """Build a linear structure on sliding bearings under one or two ground components.

    M q'' + C q' + K q + sum_g B_g^T F_g = -M R a_g(t): without `influence` and `bearing_map`
    one component along x on one isolator at degree of freedom 0 (R = 1, B = e_0); with them
    two, R (N, 2) and B (G, 2, N) of G bearing groups (their sliding displacements d_g = B_g q),
    under (a_x, a_y) = (`ground_acceleration`, `ground_y`; `None`: no y motion).

    **Arguments:** `mass` (N,) [kg or kg m^2], `stiffness`, `damping` (N, N) [N/m, N s/m],
    including any restoring spring and viscous damper of the isolation system; `bearing` a
    `SlidingBearing` (`None` allowed with `friction_model="none"` in one component; in two its
    constants are broadcast to one per group); `bearing_load` W [N] (one per group in two
    components); `ground_acceleration` a_x(t) [m/s^2] (`Signal`); `time_step` [s] of the fixed
    steps: Newmark's K_eff = K + (2/dt) C + (4/dt^2) M is inverted once for it;
    `friction_model` "hysteretic", "coulomb" or "none"; `newton_iterations` the most
    iterations of a step's balance (`None`: `NEWTON_ITERATIONS` in one component,
    `PLANAR_NEWTON_ITERATIONS` in two); a bearing with `heating` needs `contact_pressure`
    [Pa] (its kernel spans one time step to `HEAT_HORIZON`); of the optional parts, structures
    run `STRUCTURE_EFFECTS`; `surface`: a friction pendulum's `ConcaveSurface` whose force
    beyond W u / R the step solves (W / R itself belongs in `stiffness`).

    One component only: `split_at_turn` (`StructureOnSliders.split_at_turn`), `linear_rule`
    ("newmark", or "exact": `structures.exact_step_matrices`) and `pendulum_stiffness` W / R
    [N/m], the part of K[0, 0] a vertical record's normal load scales (`with_vertical_motion`;
    in two components it is W_g / R of `surface`).

    **Returns:** a `StructureOnSliders`, planar (`planar`) in two components.
    """
    if friction_model not in FRICTION_MODELS:
        raise ValueError(
            f"friction_model: unknown {friction_model!r}; accepted values: {', '.join(FRICTION_MODELS)}."
        )
    if influence is None and bearing_map is None:
        if ground_y is not None:
            raise ValueError("ground_y: a structure in two components needs its influence R (N, 2) and "
                             "bearing_map B (G, 2, N); give them (or use rigid_mass / six_storey_building "
                             "with components=2).")
        return _on_one_isolator(
            mass=mass, stiffness=stiffness, damping=damping, bearing=bearing, bearing_load=bearing_load,
            ground_acceleration=ground_acceleration, time_step=time_step, friction_model=friction_model,
            newton_iterations=NEWTON_ITERATIONS if newton_iterations is None else newton_iterations,
            split_at_turn=split_at_turn, linear_rule=linear_rule, contact_pressure=contact_pressure,
            surface=surface, pendulum_stiffness=pendulum_stiffness)
    if influence is None or bearing_map is None:
        missing = "influence" if influence is None else "bearing_map"
        raise ValueError(f"{missing}: a structure in two components needs both influence R (N, 2) and "
                         "bearing_map B (G, 2, N); give both, or neither for one component.")
    _refuse_other_count(2, {"split_at_turn": split_at_turn is not False, "linear_rule": linear_rule != "newmark",
                            "pendulum_stiffness": pendulum_stiffness is not None},
                        "a structure on bearing groups (influence and bearing_map given; its pendulum stiffness is "
                        "W_g / R of `surface`)")
    return _on_groups(
        mass=mass, stiffness=stiffness, damping=damping, influence=influence, bearing_map=bearing_map,
        bearing=bearing, bearing_load=bearing_load, ground_x=ground_acceleration,
        ground_y=zero_signal(ground_acceleration) if ground_y is None else ground_y, time_step=time_step,
        newton_iterations=PLANAR_NEWTON_ITERATIONS if newton_iterations is None else newton_iterations,
        contact_pressure=contact_pressure, friction_model=friction_model, surface=surface)


def _component_count(components, ground_y, one_only: dict, two_only: dict) -> int:
    """C, the number of horizontal components of a paper structure (`components`; `None`: 2
    with a y record, else 1), checked, after refusing by name the options the other count
    alone takes (`one_only`, `two_only`: name -> whether given)."""
    if components is None:
        components = 1 if ground_y is None else 2
    if isinstance(components, bool) or components not in COMPONENTS:
        raise ValueError(f"components: 1 or 2 horizontal components, got {components!r}.")
    if components == 1 and ground_y is not None:
        raise ValueError("ground_y: a structure in one component takes no y record; give components=2.")
    _refuse_other_count(components, two_only if components == 1 else one_only, f"components={components}")
    return components


def _refuse_other_count(components: int, other: dict, where: str) -> None:
    """`ValueError` naming the options of `other` (name -> whether given) that only the other
    number of components takes, for a structure in `components` described as `where`."""
    given = [name for name, set_ in other.items() if set_]
    if given:
        raise ValueError(f"{', '.join(given)}: only with components={3 - components}; leave out for {where}.")


def rigid_mass(*, weight, bearing: SlidingBearing | None, ground_acceleration: Signal, time_step: float,
               isolation_period=None, damping_ratio=0.0, radius=None, friction_model: str = "hysteretic",
               linear_rule: str = "newmark", contact_pressure=None, components: int | None = None,
               ground_y: Signal | None = None, surface=None) -> StructureOnSliders:
    """A rigid mass W/g on sliding bearings (Figs. 7-10 of the paper; TASS-type system):

        m u'' + c u' + (k + W/R) u + mu(|u'|) W Z = -m a_g(t),   m = W/g,

    u, Z and a_g along x (`components` 1) or in the plane (2: Park's Z; `None`: 2 with
    `ground_y`, else 1); the linear part `rigid_mass_matrices` (`weight` W [N],
    `isolation_period` T [s] or `None`, `damping_ratio` zeta [-]) on `bearing` (a
    `SlidingBearing`; `None` allowed with `friction_model="none"`) under the `Signal`s
    `ground_acceleration` a_x(t) and `ground_y` a_y(t) [m/s^2] (`None`: no y motion), stepped at
    `time_step` [s] (0.005 s recommended for 0.02 s records in one component,
    `BIDIRECTIONAL_TIME_STEP` in two). `friction_model`: "hysteretic" (the paper's model),
    "coulomb" (Eq. 2) or "none"; `contact_pressure` [Pa] of a bearing with heating. A friction
    pendulum: in one component its `radius` R [m] (W/R in K) and `linear_rule`
    (`structure_on_sliders`); in two its `surface` (`ConcaveSurface`, its period
    `isolation_period`; its restrainer and large-displacement force act in the bearings' solve).

    **Returns:** a 1-degree-of-freedom `StructureOnSliders`, or a planar one with q = (u_x,
    u_y).
    """
    _check_friction_model(friction_model)
    count = _component_count(components, ground_y, {"radius": radius is not None,
                                                    "linear_rule": linear_rule != "newmark"},
                             {"surface": surface is not None})
    if count == 2:
        one = _one_direction(rigid_mass, ground_acceleration, time_step, weight=weight,
                             isolation_period=isolation_period, damping_ratio=damping_ratio)
        return _two_directions(one, one, bearing, ground_acceleration, ground_y, time_step, contact_pressure,
                               friction_model=friction_model, surface=surface)
    linear = rigid_mass_matrices(weight=weight, isolation_period=isolation_period, damping_ratio=damping_ratio,
                                 radius=radius)
    return structure_on_sliders(**linear._asdict(), bearing=bearing, ground_acceleration=ground_acceleration,
                                time_step=time_step, friction_model=friction_model, linear_rule=linear_rule,
                                contact_pressure=contact_pressure)


def six_storey_building(*, bearing: SlidingBearing | None, ground_acceleration: Signal, time_step: float,
                        isolation_period, isolation_damping=0.05, friction_model: str = "hysteretic",
                        linear_rule: str = "newmark", contact_pressure=None,
                        building: BuildingData | None = None, components: int | None = None,
                        ground_y: Signal | None = None, building_y: BuildingData | None = None,
                        isolation_period_y=None, surface=None) -> StructureOnSliders:
    """The six-storey frame of Table 2 on an isolation system (Fig. 11 of the paper): the
    linear part `building_matrices` (`isolation_period` T_b [s] > 0, `isolation_damping`
    zeta_b [-] >= 0: 0.05 for the sliding system, 0.10 for the paper's linear high-damping
    rubber system; `building` default Table 2) on `bearing` (paper: UF PTFE parallel to lay at
    1000-3000 psi with breakaway b = 4; `None` allowed with `friction_model="none"`), carrying
    the total weight W, under `ground_acceleration` a_x(t) [m/s^2], stepped at `time_step` [s].
    `friction_model`: "hysteretic", "coulomb", or "none" (linear isolation system);
    `contact_pressure` [Pa] of a bearing with heating.

    `components` (`None`: 2 with `ground_y`, else 1): in two, x and y are each the model above
    (y the same unless `building_y`, `isolation_period_y` are given), under a_y(t) `ground_y`
    too (`None`: no y motion), the bases coupled through Park's Z of the bearings, which may be
    a friction pendulum's `surface` (as in `rigid_mass`); `linear_rule` in one only.

    **Returns:** a 7-degree-of-freedom `StructureOnSliders` (0 = base, 1-6 = floors), or a
    planar one with q = (x: base, floors 1-6; y: base, floors 1-6).
    """
    _check_friction_model(friction_model)
    count = _component_count(components, ground_y, {"linear_rule": linear_rule != "newmark"},
                             {"building_y": building_y is not None,
                              "isolation_period_y": isolation_period_y is not None,
                              "surface": surface is not None})
    if count == 2:
        return _building_in_two(bearing, ground_acceleration, ground_y, time_step, isolation_period,
                                isolation_damping, building, building_y, isolation_period_y, contact_pressure,
                                friction_model=friction_model, surface=surface)
    linear = building_matrices(isolation_period=isolation_period, isolation_damping=isolation_damping,
                               building=building)
    return structure_on_sliders(**linear._asdict(), bearing=bearing, ground_acceleration=ground_acceleration,
                                time_step=time_step, friction_model=friction_model, linear_rule=linear_rule,
                                contact_pressure=contact_pressure)


def _building_in_two(bearing, ground_x, ground_y, time_step, isolation_period, isolation_damping, building,
                     building_y, isolation_period_y, contact_pressure, **law) -> StructureOnSliders:
    """`six_storey_building` in two components: the x model, and the y model when it differs."""
    x = _one_direction(six_storey_building, ground_x, time_step, isolation_period=isolation_period,
                       isolation_damping=isolation_damping, building=building)
    y = x
    if building_y is not None or isolation_period_y is not None:
        y = _one_direction(
            six_storey_building, ground_x, time_step,
            isolation_period=isolation_period if isolation_period_y is None else isolation_period_y,
            isolation_damping=isolation_damping, building=building if building_y is None else building_y,
        )
        if not np.isclose(float(jnp.sum(y.mass)), float(jnp.sum(x.mass))):
            raise ValueError(
                "building_y: its total weight differs from the x model's; one structure has one weight."
            )
    return _two_directions(x, y, bearing, ground_x, ground_y, time_step, contact_pressure, **law)


def _on_one_isolator(*, mass, stiffness, damping, bearing, bearing_load, ground_acceleration, time_step,
                     friction_model, newton_iterations, split_at_turn, linear_rule, contact_pressure, surface,
                     pendulum_stiffness) -> StructureOnSliders:
    """`structure_on_sliders` in one component: Newmark's K_eff = K + (2/dt) C + (4/dt^2) M inverted
    once for `time_step` (and the exact step's matrices for `linear_rule="exact"`)."""
    if linear_rule not in LINEAR_RULES:
        raise ValueError(f"linear_rule: unknown {linear_rule!r}; accepted values: {', '.join(LINEAR_RULES)}.")
    mass = jnp.atleast_1d(jnp.asarray(mass, dtype=float))
    n = mass.shape[-1]
    stiffness = jnp.asarray(stiffness, dtype=float).reshape(mass.shape[:-1] + (n, n))
    damping = jnp.asarray(damping, dtype=float).reshape(mass.shape[:-1] + (n, n))
    if not time_step > 0:
        raise ValueError(f"time_step: must be > 0 s, got {time_step}.")
    if isinstance(bearing, SeriesPendulum):
        raise ValueError(f"bearing: {bearing.description} balance their sliders at each step; build the linear "
                         "structure with bearing=None, friction_model='none' and put it on them with "
                         "structure_on_isolator(linear, pendulum).")
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


def _on_groups(*, mass, stiffness, damping, influence, bearing_map, bearing, bearing_load, ground_x, ground_y,
               time_step, newton_iterations, contact_pressure, friction_model,
               surface) -> StructureOnSliders:
    """`structure_on_sliders` in two components: K_eff^-1 for `time_step`, the bearing's constants
    and `contact_pressure` broadcast to one per group, `pendulum_stiffness` W_g / R of `surface`."""
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
    check_structure_parts(bearing, _two_direction_refusal)
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
    return StructureOnSliders(
        mass=mass,
        stiffness=stiffness,
        damping=damping,
        influence=jnp.asarray(influence, dtype=float).reshape(n, 2),
        bearing_map=bearing_map,
        bearing=bearing,
        bearing_load=bearing_load,
        ground_acceleration=ground_x,
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


STRUCTURE_EFFECTS = ("heating", "wear", "asymmetry")
"""Optional bearing parts a structure on sliders runs (besides Eq. 1, breakaway, anisotropy,
stacks): heating and wear, factors on mu held over each step, and the direction asymmetry
1 + a Z, part of the bearing force solved for in each step. Only the hysteretic friction
model runs them."""


def _one_direction_refusal(names: str) -> str:
    return (f"bearing: the structures do not run its {names} (they run Eq. 1, breakaway, anisotropy, "
            f"stacks, {', '.join(STRUCTURE_EFFECTS)}); simulate the bearing test with `simulate-test "
            "--bearing`, or fit without these effects")


def check_structure_parts(bearing: SlidingBearing, refusal=_one_direction_refusal) -> None:
    """`ValueError` naming the optional parts of `bearing` a structure does not run (those
    not in `STRUCTURE_EFFECTS`): `refusal(their names)` and, for pressure dependence,
    `PRESSURE_HINT` (default: the message of the structures in one direction)."""
    other = [name for name in bearing.effects if name not in STRUCTURE_EFFECTS]
    if other:
        raise ValueError(refusal(", ".join(other)) + (PRESSURE_HINT if "pressure_dependence" in other else "."))


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
    """(R | f) of `structures.exact_step_matrices`, for a structure or a batch of them."""
    def one(m, k, c):
        step, force = exact_step_matrices(m, k, c, time_step)
        return jnp.concatenate([step, force[:, None]], 1)

    return jnp.vectorize(one, signature="(n),(n,n),(n,n)->(m,k)")(mass, stiffness, damping)


def check_planar_law(friction_model, surface, bearing):
    """`ValueError` naming the argument for an unknown friction model, a Coulomb bearing with
    parts beyond Eq. 1, or a restrainer or large-displacement surface without Park's Z."""
    if friction_model not in FRICTION_MODELS:
        raise ValueError(f"friction_model: unknown {friction_model!r}; accepted: {', '.join(FRICTION_MODELS)}.")
    if friction_model == "coulomb" and bearing is not None and bearing.effects:
        raise ValueError(f"bearing: the Coulomb model runs Eq. 1 alone, not its "
                         f"{', '.join(bearing.effects)}; use friction_model='hysteretic'.")
    if surface is not None and not surface.is_linear and friction_model != "hysteretic":
        raise ValueError("surface: its restrainer or large-displacement force is solved with the "
                         f"hysteretic friction model, not {friction_model!r}.")


def _two_direction_refusal(names: str) -> str:
    return (f"bearing: the structures in two directions do not run its {names} (they run Eq. 1 at the "
            "resultant speed, Park's Z, breakaway, anisotropy, stacks, heating, wear and asymmetry)")


def zero_signal(like: Signal) -> Signal:
    return Signal(times=like.times, values=jnp.zeros_like(like.values), uniform=like.uniform)


def _block(a, b):
    n = a.shape[0]
    out = jnp.zeros((2 * n, 2 * n))
    return out.at[:n, :n].set(a).at[n:, n:].set(b)


def _two_directions(x, y, bearing, ground_x, ground_y, time_step,
                    contact_pressure=None, **law) -> StructureOnSliders:
    n = x.mass.shape[0]
    influence = np.zeros((2 * n, 2))
    influence[:n, 0] = 1.0
    influence[n:, 1] = 1.0
    bearing_map = np.zeros((1, 2, 2 * n))
    bearing_map[0, 0, 0] = 1.0
    bearing_map[0, 1, n] = 1.0
    return structure_on_sliders(
        mass=jnp.concatenate([x.mass, y.mass]),
        stiffness=_block(x.stiffness, y.stiffness),
        damping=_block(x.damping, y.damping),
        influence=influence,
        bearing_map=bearing_map,
        bearing=bearing,
        bearing_load=x.bearing_load[None],
        ground_acceleration=ground_x,
        ground_y=ground_y,
        time_step=time_step,
        contact_pressure=contact_pressure,
        **law,
    )


def _one_direction(model, ground, time_step: float, **linear):
    """The linear part of one horizontal direction: `model` (`rigid_mass` or
    `six_storey_building`) with its `linear` keywords, no bearing and no friction, whose mass,
    stiffness, damping and bearing load `_two_directions` joins."""
    return model(bearing=None, ground_acceleration=ground, time_step=time_step, friction_model="none", **linear)


def _check_friction_model(friction_model: str) -> None:
    if friction_model not in FRICTION_MODELS:
        raise ValueError(
            f"friction_model: unknown {friction_model!r}; accepted values: "
            f"{', '.join(repr(m) for m in FRICTION_MODELS)}."
        )
