"""Structures on a plan of bearing groups: the rigid base slab with three degrees of freedom
(`slab_on_bearings`) and the six-storey building of Table 2 on that slab (`building_on_plan`).

The slab (three degrees of freedom x, y, rotation; the torsion of plan-asymmetric isolated
structures): coordinates q = (u_x, u_y, theta) of the centre of mass C relative to the ground;
a bearing group at plan position P, r = P - C, slides by (small rotations)

    d = (u_x - theta r_y, u_y + theta r_x),    i.e. B = [[1, 0, -r_y], [0, 1, r_x]]

(`teflon_jax.structures.plan_bearing_map`), and every group has its own PTFE constants,
contact pressure and tributary load W_g (the normal load of Eq. 1, F_g = mu_g W_g Z_g). Linear springs (isolation period T of the whole
slab, shared among the groups) and viscous dampers proportional to them (ratio zeta) sit at
the bearing positions, so the centre of stiffness is the spring-weighted centroid of the
groups; its offset from C (and any offset of the friction centroid) drives the torsion.
On single friction pendulums (`isolator=(bearing, concave_surface(R))`) each group restores with W_g / R_g d_g
instead (Zayas, Low & Mahin 1990), so the centre of stiffness is the load-weighted centroid of
the groups (for equal radii), which follows the loads: no torsion from stiffness eccentricity
when the loads' centroid is the centre of mass. With the centre of mass at a height h above
the sliding surface, the overturning moment changes each group's normal load
(`teflon_jax.structures`: `supported_loads`), on its friction and its pendulum alike.
Reference: Constantinou, Mokha & Reinhorn (1990), Eqs. 1, 8-9, 17 (bidirectional model);
plan kinematics as in 3D-BASIS (Nagarajaiah, Reinhorn & Constantinou 1991).

The building on the slab (torsion of the base and overturning loads from the inertia forces of
every floor): coordinates q (15,) relative to the ground: (x: base, floors 1-6; y: base, floors 1-6; theta),
the base's translations those of the slab's centre of mass C and theta its rotation about the
vertical axis. The building stands on the slab with its mass centred over C, so each floor
translates with the base in x and y through Table 2's frame (no torsion of the floors):

    M = diag(m_b, m_1..6, m_b, m_1..6, J),   K = diag(E^T K_s E, E^T K_s E, 0) + K_b,
    C = diag(E^T C_s E, E^T C_s E, 0) + (2 zeta_b / omega_b) K_b,   E = [-1 | I] (6, 7),

with the fixed-base K_s, C_s of `superstructure_matrices` (2 % in every mode), the base's own
mass m_b = W_base / g and the slab's rotational inertia J (a uniform slab, m_b (Lx^2 + Ly^2) / 12,
unless given). A bearing group at plan position P, r = P - C, slides by
d_g = (u_x - theta r_y, u_y + theta r_x) (`slab_on_bearings`' kinematics) and carries its
tributary load W_g (sum W_g = W, the building's weight); the isolation's stiffness
K_b = sum_g k_g B_g^T B_g sits at the groups: springs of period T_b shared among them
(k_g = (W / g) omega_b^2 share_g, carrying no vertical load) or single friction pendulums
(k_g = W_g / R_g), with zeta_b of the rigid-body mode as in `six_storey_building`, or double
or triple friction pendulums, each group the series model of `_series.py` with its reference
spring W_g / R_ref and no other spring or damper. On one group (or a symmetric plan without
overturning) this is `six_storey_building(components=2)` (the series pendulums: `triple_structure`).

Overturning: level i (the base, floors 1-6) lies at height h_i above the sliding surface
(h_0 = `base_height`, h_i = h_0 + the storey heights below it); the groups' normal loads follow
the moment sum_i h_i F_i of the levels' inertia forces F_i = m_i (q_i'' + a_g) by the lever rule
of the slab on vertical supports, redistributed while groups lift (`teflon_jax.structures`, with the
levels h_i / h_c about the height h_c = sum m_i h_i / sum m_i of the whole mass's centre).
References: Constantinou, Mokha & Reinhorn (1990), Table 2 and Fig. 11; Nagarajaiah, Reinhorn &
Constantinou (1991), 3D-BASIS, NCEER-91-0005 (a superstructure on a rigid base over bearings).
"""

import dataclasses

import jax
import jax.numpy as jnp
import numpy as np

from ..bearing import SeriesPendulum, check_series_pendulum
from ..elements import TRIPLE_NEWTON_ITERATIONS, TRIPLE_TOLERANCE, series_heat_kernel
from ..excitation import Signal
from ..structures import (
    check_plan,
    first_order_hold,
    level_heights,
    overturning_map,
    plan_bearing_map,
    plan_isolator,
    refuse_springs,
    stack_bearings,
    superstructure_matrices,
    support_plan,
)
from ..tables import BuildingData, load_table2
from ..units import STANDARD_GRAVITY
from ..validation import concrete
from ._structure import StructureOnSliders
from ._structure_build import structure_on_sliders, zero_signal


def slab_on_bearings(
    *,
    length_x: float,
    length_y: float,
    weight: float,
    centre_of_mass,
    positions,
    bearings=None,
    loads,
    ground_acceleration: Signal,
    ground_y: Signal,
    time_step: float,
    isolation_period=None,
    isolation_damping=0.0,
    spring_shares=None,
    rotational_inertia=None,
    names=None,
    contact_pressures=None,
    isolator=None,
    radii=None,
    height_of_centre_of_mass=0.0,
    vertical_stiffness=None,
    pendulums=None,
    friction_model: str = "hysteretic",
):
    """A rigid slab (x, y, rotation) on bearing groups (module docstring).

    **Arguments:**

    - `length_x`, `length_y` [m]: plan of the slab, spanning [0, length_x] x [0, length_y].
    - `weight` W [N]; `centre_of_mass` (x, y) [m] in plan coordinates.
    - `positions` (G, 2) [m]; `bearings`: a sequence of G `SlidingBearing`s (or one, used for
      all groups); `loads` (G,) [N] tributary normal loads, adding up to W.
    - `ground_acceleration`, `ground_y`: `Signal`s [m/s^2] along x and y; `time_step` [s].
    - `isolation_period` T [s] of the springs (`None`: none), `isolation_damping` zeta [-]
      (damping proportional to the springs), `spring_shares` (G,) [-] relative spring
      stiffness per group (default equal).
    - `rotational_inertia` [kg m^2] about C (default m (Lx^2 + Ly^2) / 12, a uniform slab).
    - `contact_pressures` (G,) [Pa] (or one for all): the bearings' contact pressure per group,
      for bearings with heating (each group's steel heats at its own mu p |v|).
    - `isolator`: the groups' isolator value, one for all groups or a list of one per group
      (`plan_isolator`, `bearing.isolator_kind`): `SlidingBearing`s, flat sliders with the
      springs above; (`SlidingBearing`, `concave_surface(R_g)`) pairs, single friction
      pendulums of stiffness W_g / R_g at their positions, no springs (`isolation_damping`
      zeta then acts on the pendulums' stiffness at omega = sqrt(g / R_e),
      W / R_e = sum W_g / R_g); `TriplePendulum`s or `DoublePendulum`s, below. Or its name
      ("flat", the default, "single-fp", "triple-fp", "double-fp") with the parts apart:
      `bearings`, `radii` R_g [m] (one for all, or (G,)), `pendulums`.
    - `height_of_centre_of_mass` h [m] >= 0 above the sliding surface: the normal loads vary
      with the overturning moment (0: constant loads); `vertical_stiffness` (G,) relative
      vertical stiffness of the groups (default equal) for the lever rule (`overturning_map`).
    - series pendulums (`TriplePendulum` or `DoublePendulum`, one for all groups or one per
      group) balance their sliders at each step: no springs, radii or contact pressures (heated surfaces take theirs from the
      pendulums, each group's times its N_g / W_g; `_series.py`).
    - `friction_model`: "hysteretic" (Park's Z), "coulomb" or "none" for flat sliders and
      single pendulums (`_planar_step.py`); the series pendulums' sliders follow Park's Z.

    **Returns:** a planar `StructureOnSliders` with q = (u_x [m], u_y [m], theta [rad]) for every
    isolator (`simulate_history`); series pendulums as its stacked `bearing`.
    """
    positions = np.asarray(positions, dtype=float).reshape(-1, 2)
    loads = np.asarray(loads, dtype=float).reshape(-1)
    centre = np.asarray(centre_of_mass, dtype=float).reshape(2)
    check_plan(length_x=length_x, length_y=length_y, weight=weight, centre_of_mass=centre,
               positions=positions, loads=loads, names=names)
    groups = positions.shape[0]
    mass = weight / STANDARD_GRAVITY
    inertia = mass * (length_x**2 + length_y**2) / 12 if rotational_inertia is None else rotational_inertia
    height = _height(height_of_centre_of_mass)
    plan_isolators = plan_isolator(isolator, groups, bearings=bearings, radii=radii, pendulums=pendulums)
    series = plan_isolators.pendulums is not None  # series pendulums (S > 1 sliders): the series slab
    if series:
        _refuse_for_series(plan_isolators.name, bearings=bearings, radii=radii, isolation_period=isolation_period,
                           spring_shares=spring_shares, isolation_damping=isolation_damping or None,
                           contact_pressures=contact_pressures,
                           friction_model=None if friction_model == "hysteretic" else friction_model)
    else:
        refuse_springs(plan_isolators.radii, isolation_period, spring_shares)
    loading = _overturning_loads(positions, centre, height, vertical_stiffness, names)
    bearing_map = plan_bearing_map(positions - centre, 3, (0, 1, 2))
    influence = np.array([[1.0, 0.0], [0.0, 1.0], [0.0, 0.0]])
    if series:
        return _on_series_groups(
            mass=np.array([mass, mass, inertia]), influence=influence, bearing_map=bearing_map, loads=loads,
            pendulums=plan_isolators.pendulums, isolator=plan_isolators.name,
            ground_acceleration=ground_acceleration, ground_y=ground_y, time_step=time_step, **loading)
    bearings, radii = plan_isolators.bearings, plan_isolators.radii
    stiffness, damping = _isolation_stiffness(bearing_map, loads, weight, isolation_period, spring_shares, radii,
                                              isolation_damping, springs_needed=False)
    system = structure_on_sliders(
        mass=jnp.array([mass, mass, inertia]), stiffness=stiffness, damping=damping, influence=influence,
        bearing_map=bearing_map, bearing=stack_bearings(bearings), bearing_load=loads, ground_acceleration=ground_acceleration,
        ground_y=ground_y, time_step=time_step, contact_pressure=contact_pressures, friction_model=friction_model)
    return dataclasses.replace(system, pendulum_stiffness=None if radii is None else jnp.asarray(loads / radii),
                               **loading)


def _overturning_loads(positions, centre, height, vertical_stiffness, names, heights=None,
                       height_name="height_of_centre_of_mass") -> dict:
    """The groups' `overturning` map and `supports` of a structure whose horizontal force acts at
    `height` h [m] above the sliding surface (its coordinates' own `heights` h_i [m] for the
    building: the supports' levels h_i / h); {} at h = 0 (constant loads). Errors name the
    height as `height_name`."""
    if height == 0:
        return {}
    return {"overturning": jnp.asarray(overturning_map(positions, centre, height, vertical_stiffness, names,
                                                       height_name=height_name)),
            "supports": support_plan(positions, centre, height, vertical_stiffness,
                                     levels=None if heights is None else heights / height)}


def _height(height_of_centre_of_mass) -> float:
    """h [m], checked: `ValueError` unless finite and >= 0."""
    height = float(height_of_centre_of_mass)
    if not (np.isfinite(height) and height >= 0):
        raise ValueError(f"height_of_centre_of_mass: must be >= 0 m, got {height:g}.")
    return height


def _refuse_for_series(isolator, **given):
    """`ValueError` naming the first of `given` (inputs of the flat sliders and the single
    pendulum) that is set with a series pendulum `isolator`."""
    for name, value in given.items():
        if value is not None:
            raise ValueError(f"{name}: does not apply to isolator {isolator!r} (each group is the series "
                             "pendulum of `pendulums`, with its own radii and friction); leave it out.")


HEIGHT_NAMES = "storey_heights, base_height"
"""The arguments that place the levels above the sliding surface, as errors name them."""


def building_on_plan(
    *,
    length_x: float,
    length_y: float,
    centre_of_mass,
    positions,
    loads,
    bearings=None,
    ground_acceleration: Signal,
    ground_y: Signal | None = None,
    time_step: float,
    isolation_period=None,
    isolation_damping=None,
    spring_shares=None,
    isolator=None,
    radii=None,
    pendulums=None,
    storey_heights=None,
    base_height=0.0,
    vertical_stiffness=None,
    rotational_inertia=None,
    building: BuildingData | None = None,
    names=None,
    contact_pressures=None,
    friction_model: str = "hysteretic",
) -> StructureOnSliders:
    """The Table 2 building on a rigid base slab over bearing groups (module docstring).

    **Arguments:**

    - `length_x`, `length_y` [m]: plan of the base slab, spanning [0, length_x] x [0, length_y];
      `centre_of_mass` (x, y) [m]: the slab's centre of mass, over which the building stands.
    - `positions` (G, 2) [m]; `loads` (G,) [N] the groups' tributary loads, adding up to the
      building's weight W (Table 2: 672 kip); `bearings`: G `SlidingBearing`s (or one for all).
    - `ground_acceleration`, `ground_y`: `Signal`s [m/s^2] along x and y (`ground_y` `None`: no y
      motion); `time_step` [s].
    - `isolator`: the groups' isolator value, one for all groups or one per group
      (`plan_isolator`): `SlidingBearing`s, flat sliders with springs of period
      `isolation_period` T_b [s] shared among the groups by `spring_shares` (G,) [-] (default
      equal); (`SlidingBearing`, `concave_surface(R_g)`) pairs, single friction pendulums, no
      springs. Or its name ("flat", the default, or "single-fp") with `bearings` and `radii`
      R_g [m] (one, or (G,)) apart. `isolation_damping` zeta_b [-] of the rigid-body mode
      (default 0.05, the paper's sliding system). Or `TriplePendulum`s or `DoublePendulum`s
      ("triple-fp", "double-fp" with `pendulums`, one for all groups or one per group): each
      group balances its sliders at every step (`slab_on_bearings`' series pendulums), without
      springs, radii, isolation damping or contact pressures.
    - `storey_heights` [m] (one, or one per storey, >= 0; default the `building`'s storey
      height, Table 2's 12 ft) and `base_height` h_0 [m] (>= 0, default 0) of the base's
      inertia force: the levels' heights above the sliding surface for the overturning loads
      (all 0: constant loads);
      `vertical_stiffness` (G,) relative vertical stiffness of the groups (default equal).
    - `rotational_inertia` J [kg m^2] of the slab about C (default the uniform slab's).
    - `building`: `BuildingData` (default Table 2); `names`: the groups' names for errors;
      `contact_pressures` (G,) [Pa] for bearings with heating; `friction_model` "hysteretic",
      "coulomb" or "none".

    **Returns:** a planar `StructureOnSliders` with q = (x: base, floors 1-6; y: base, floors 1-6;
    theta [rad]) (`simulate_history`; a vertical record by `with_vertical_motion`).
    """
    building = load_table2() if building is None else building
    positions = np.asarray(positions, dtype=float).reshape(-1, 2)
    loads = np.asarray(loads, dtype=float).reshape(-1)
    centre = np.asarray(centre_of_mass, dtype=float).reshape(2)
    weight = float(building.total_weight)
    check_plan(length_x=length_x, length_y=length_y, weight=weight, centre_of_mass=centre,
               positions=positions, loads=loads, names=names)
    plan_isolators = plan_isolator(isolator, positions.shape[0], bearings=bearings, radii=radii, pendulums=pendulums)
    level_mass, frame_k, frame_c = _frame(building)
    n = level_mass.shape[0]
    heights = _level_heights(building, storey_heights, base_height, n)
    mass, influence, bearing_map = _building_coordinates(level_mass, positions - centre, length_x, length_y,
                                                         rotational_inertia)
    ground_y = zero_signal(ground_acceleration) if ground_y is None else ground_y
    # the levels' moment sum_i h_i F_i as h_c H_h at the mass centre's height h_c (`overturning_force`)
    centre_height = _centre_height(level_mass, heights) if np.any(heights > 0) else 0.0
    loading = _overturning_loads(positions, centre, centre_height, vertical_stiffness, names,
                                 heights=np.concatenate([heights, heights, [0.0]]), height_name=HEIGHT_NAMES)
    if plan_isolators.pendulums is not None:
        _refuse_for_series(plan_isolators.name, bearings=bearings, radii=radii, isolation_period=isolation_period,
                           spring_shares=spring_shares, isolation_damping=isolation_damping,
                           contact_pressures=contact_pressures,
                           friction_model=None if friction_model == "hysteretic" else friction_model)
        return _on_series_groups(
            mass=mass, frame=(frame_k, frame_c), influence=influence, bearing_map=bearing_map, loads=loads,
            pendulums=plan_isolators.pendulums, isolator=plan_isolators.name,
            ground_acceleration=ground_acceleration, ground_y=ground_y, time_step=time_step, **loading)
    radii = plan_isolators.radii
    refuse_springs(radii, isolation_period, spring_shares)
    isolation = _isolation_stiffness(bearing_map, loads, weight, isolation_period, spring_shares, radii,
                                     0.05 if isolation_damping is None else isolation_damping)
    system = structure_on_sliders(
        mass=mass, stiffness=frame_k + isolation[0], damping=frame_c + isolation[1], influence=influence,
        bearing_map=bearing_map, bearing=stack_bearings(plan_isolators.bearings), bearing_load=loads,
        ground_acceleration=ground_acceleration, ground_y=ground_y, time_step=time_step, contact_pressure=contact_pressures,
        friction_model=friction_model)
    return dataclasses.replace(system, pendulum_stiffness=None if radii is None else jnp.asarray(loads / radii),
                               **loading)


def _building_coordinates(level_mass, arms, length_x, length_y, rotational_inertia):
    """(mass (2n + 1,), influence R (2n + 1, 2), bearing map B (G, 2, 2n + 1)) of the building's
    coordinates (x: base, floors; y: base, floors; the slab's rotation) over the groups at
    `arms` (G, 2) [m] from the mass centre; J of the uniform slab unless given (> 0)."""
    n = level_mass.shape[0]
    inertia = level_mass[0] * (length_x**2 + length_y**2) / 12 if rotational_inertia is None else rotational_inertia
    if not (np.isfinite(inertia) and inertia > 0):
        raise ValueError(f"rotational_inertia: must be > 0 kg m^2, got {rotational_inertia}.")
    influence = np.zeros((2 * n + 1, 2))
    influence[:n, 0] = influence[n:2 * n, 1] = 1.0
    mass = np.concatenate([level_mass, level_mass, [inertia]])
    return mass, influence, plan_bearing_map(arms, 2 * n + 1, (0, n, 2 * n))


def building_centre_height(building: BuildingData | None = None, storey_heights=None, base_height=0.0) -> float:
    """h_c = sum_i m_i h_i / sum_i m_i [m]: the height above the sliding surface of the centre of
    mass of `building_on_plan`'s base and floors (default Table 2 at its 12 ft storeys, the
    base at 0), the lever arm of the horizontal force in the groups' overturning loads."""
    building = load_table2() if building is None else building
    level_mass = _frame(building)[0]
    return _centre_height(level_mass, _level_heights(building, storey_heights, base_height, level_mass.shape[0]))


def _level_heights(building: BuildingData, storey_heights, base_height, levels: int) -> np.ndarray:
    return level_heights(building.storey_height if storey_heights is None else storey_heights, base_height,
                         levels - 1)


def _centre_height(level_mass, heights) -> float:
    return float(level_mass @ heights / np.sum(level_mass))


def _frame(building: BuildingData):
    """(level masses (S + 1,) [kg], base first; the frame's stiffness and damping in x and y,
    diag(E^T K_s E, E^T K_s E, 0) and the same of C_s (2S + 3, 2S + 3), E = [-1 | I] the
    storey drifts of one direction), from `superstructure_matrices`."""
    m_floor, k_s, c_s, _ = superstructure_matrices(building)
    base_mass = building.base_weight / STANDARD_GRAVITY
    if not base_mass > 0:
        raise ValueError(f"building: total_weight must exceed the floor weights; base weight is "
                         f"{building.base_weight} N.")
    storeys = m_floor.shape[0]
    drift = np.hstack([-np.ones((storeys, 1)), np.eye(storeys)])
    return (np.concatenate([[base_mass], m_floor]),
            *(_two_directions(drift.T @ matrix @ drift) for matrix in (k_s, c_s)))


def _two_directions(block) -> np.ndarray:
    """diag(`block`, `block`, 0): one direction's (n, n) matrix in x and in y, none on theta."""
    n = block.shape[0]
    out = np.zeros((2 * n + 1, 2 * n + 1))
    out[:n, :n] = out[n:2 * n, n:2 * n] = block
    return out


def _isolation_stiffness(bearing_map, loads, weight, isolation_period, spring_shares, radii, isolation_damping, *,
                         springs_needed: bool = True):
    """(K_b, C_b) (N, N): the isolation's stiffness at the groups, k_g = (W / g) omega_b^2 share_g
    (springs) or W_g / R_g (pendulums), and its damping (2 zeta_b / omega_b) K_b,
    omega_b^2 = g sum_g k_g / W (`ValueError` naming the argument for a missing one); springs
    where the groups have no `radii` (flat sliders), none where `springs_needed` is false and
    no `isolation_period` is given (zeros, with `isolation_damping` zeta_b 0)."""
    zeta, groups, size = float(isolation_damping), loads.shape[0], bearing_map.shape[-1]
    if not (np.isfinite(zeta) and zeta >= 0):
        raise ValueError(f"isolation_damping: must be >= 0, got {isolation_damping}.")
    if radii is None and isolation_period is None and not springs_needed:
        if zeta > 0:
            raise ValueError("isolation_damping: needs springs (isolation_period), or 0.")
        return np.zeros((size, size)), np.zeros((size, size))
    if radii is None:
        if isolation_period is None:
            raise ValueError("isolation_period: the building's springs need their period T_b [s] "
                             "(Table 2's rubber springs carry no vertical load).")
        period = float(isolation_period)
        if not (np.isfinite(period) and period > 0):
            raise ValueError(f"isolation_period: must be > 0 s, got {isolation_period}.")
        shares = np.ones(groups) if spring_shares is None else np.asarray(spring_shares, float).reshape(-1)
        if shares.shape != (groups,) or np.any(shares < 0) or not np.sum(shares) > 0:
            raise ValueError("spring_shares: one share >= 0 per group, not all zero.")
        k = weight / STANDARD_GRAVITY * (2 * np.pi / period) ** 2 * shares / np.sum(shares)
    else:
        k = loads / radii
    stiffness = np.einsum("g,gdn,gdm->nm", k, bearing_map, bearing_map)
    omega = np.sqrt(STANDARD_GRAVITY * np.sum(k) / weight)
    return stiffness, 2 * zeta / omega * stiffness


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


def _series_step_matrix(mass, stiffness, damping, influence, time_step):
    """[free (2N, 2N), start (2N, N + 2), end (2N, N + 2)] of the exact step of
    M q'' + C q' + K q = -M R a_g - f with x = (q, q') and the inputs (a_g (2,), f (N,))
    varying linearly over `time_step` [s]: x1 = free x0 + start u0 + end u1
    (`structures.first_order_hold`)."""
    m = jnp.asarray(mass, float)
    n = m.shape[0]
    a = jnp.block([[jnp.zeros((n, n)), jnp.eye(n)], [-stiffness / m[:, None], -damping / m[:, None]]])
    b = jnp.concatenate([jnp.zeros((n, n + 2)),
                         jnp.concatenate([-jnp.asarray(influence, float), -jnp.diag(1 / m)], 1)])
    return jnp.concatenate(first_order_hold(a, b, time_step), axis=1)


def _on_series_groups(*, mass, influence, bearing_map, loads, pendulums, isolator, ground_acceleration: Signal,
                      ground_y: Signal, time_step: float, frame=None, overturning=None, supports=None,
                      newton_iterations: int = TRIPLE_NEWTON_ITERATIONS,
                      newton_tolerance: float = TRIPLE_TOLERANCE) -> StructureOnSliders:
    """The planar `StructureOnSliders` of masses `mass` (N,) [kg, kg m^2] (ground `influence`
    (N, 2)) on groups of series pendulums (`isolator` "triple-fp" or "double-fp", the plan
    already checked): bearing map B (G, 2, N), loads W_g (G,) [N], `pendulums`
    (`stack_pendulums`), `frame` the structure's own (K, C) (N, N) (`None`: a rigid slab), and
    the groups' `overturning` map and `supports` (`None`: constant loads). Heated surfaces carry
    the heat kernel of one step to `HEAT_HORIZON` (`series_heat_kernel`). Its `bearing` is the
    stacked pendulum; K adds the reference springs K_ref = sum_g (W_g / R_ref) B_g^T B_g
    (`_series.py`), and no other spring or damper acts at the groups."""
    groups = loads.size
    pendulum = stack_pendulums(pendulums, isolator, groups)
    if isinstance(time_step, bool) or not (isinstance(time_step, (int, float)) and time_step > 0):
        raise ValueError(f"time_step: must be a positive number of seconds, got {time_step!r}.")
    heat_rates, heat_weights = series_heat_kernel(pendulum, time_step)
    reference = jnp.einsum("g,gdn,gdm->nm", loads / pendulum.reference_radius(), bearing_map, bearing_map)
    count = mass.shape[0]
    stiffness, damping = (reference, jnp.zeros((count, count))) if frame is None else (frame[0] + reference, frame[1])
    mass = jnp.asarray(mass, float)
    return StructureOnSliders(
        mass=mass, stiffness=stiffness, damping=jnp.asarray(damping, float), influence=jnp.asarray(influence),
        bearing_map=jnp.asarray(bearing_map), bearing=pendulum, bearing_load=jnp.asarray(loads),
        ground_acceleration=ground_acceleration, ground_y=ground_y, newmark_inverse=jnp.zeros((count, count)), time_step=float(time_step),
        newton_iterations=int(newton_iterations), newton_tolerance=float(newton_tolerance), heat_rates=heat_rates,
        heat_weights=heat_weights, overturning=overturning, supports=supports, reference_stiffness=reference,
        step_matrix=_series_step_matrix(mass, stiffness, damping, influence, time_step))
