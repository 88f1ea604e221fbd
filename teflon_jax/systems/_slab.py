"""A rigid base slab with three degrees of freedom (x, y, rotation) on groups of sliding
bearings at plan positions: torsion of plan-asymmetric isolated structures.

Coordinates q = (u_x, u_y, theta) of the centre of mass C relative to the ground. A bearing
group at plan position P, r = P - C, slides by (small rotations)

    d = (u_x - theta r_y, u_y + theta r_x),    i.e. B = [[1, 0, -r_y], [0, 1, r_x]],

and every group has its own PTFE constants, contact pressure and tributary load W_g (the
normal load of Eq. 1, F_g = mu_g W_g Z_g). Linear springs (isolation period T of the whole
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
"""

import dataclasses

import jax.numpy as jnp
import numpy as np

from ..excitation import Signal
from ..structures import (
    check_plan,
    overturning_map,
    plan_bearing_map,
    plan_isolator,
    refuse_springs,
    stack_bearings,
    support_plan,
)
from ..units import STANDARD_GRAVITY
from ._bidirectional_models import bidirectional_structure
from ._slab_series_build import slab_on_series


def slab_on_bearings(
    *,
    length_x: float,
    length_y: float,
    weight: float,
    centre_of_mass,
    positions,
    bearings=None,
    loads,
    ground_x: Signal,
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
    - `ground_x`, `ground_y`: `Signal`s [m/s^2]; `time_step` [s].
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
      group) run on the series slab's engine: no springs, radii or contact pressures (heated surfaces take theirs from the
      pendulums, each group's times its N_g / W_g; `_slab_series.py`).
    - `friction_model`: "hysteretic" (Park's Z), "coulomb" or "none" for flat sliders and
      single pendulums (`_bidirectional_laws.py`); the series pendulums' sliders follow Park's Z.

    **Returns:** a `BidirectionalStructure` with q = (u_x [m], u_y [m], theta [rad]); a
    `SlabOnSeries` (`simulate_slab_series`) for the series pendulums.
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
    if plan_isolators.pendulums is not None:  # series pendulums (S > 1 sliders): the series slab
        _refuse_for_series(plan_isolators.name, bearings=bearings, radii=radii, isolation_period=isolation_period,
                           spring_shares=spring_shares, isolation_damping=isolation_damping or None,
                           contact_pressures=contact_pressures,
                           friction_model=None if friction_model == "hysteretic" else friction_model)
        return slab_on_series(weight=weight, mass_inertia=inertia, centre_of_mass=centre, positions=positions,
                              loads=loads, pendulums=plan_isolators.pendulums, isolator=plan_isolators.name,
                              ground_x=ground_x, ground_y=ground_y, time_step=time_step, height=height,
                              vertical_stiffness=vertical_stiffness, names=names)
    bearings, radii = plan_isolators.bearings, plan_isolators.radii
    refuse_springs(radii, isolation_period, spring_shares)
    overturning = None if height == 0 else overturning_map(positions, centre, height, vertical_stiffness, names)
    bearing_map = plan_bearing_map(positions - centre, 3, (0, 1, 2))
    stiffness = np.zeros((3, 3))
    damping = np.zeros((3, 3))
    if isolation_period is not None:
        shares = np.ones(groups) if spring_shares is None else np.asarray(spring_shares, float)
        if shares.shape != (groups,) or np.any(shares < 0) or not np.sum(shares) > 0:
            raise ValueError("spring_shares: one share >= 0 per group, not all zero.")
        omega = 2 * np.pi / float(isolation_period)
        k = mass * omega**2 * shares / np.sum(shares)
        stiffness = np.einsum("g,gdn,gdm->nm", k, bearing_map, bearing_map)
        damping = 2 * float(isolation_damping) / omega * stiffness
    elif radii is not None:
        k = loads / radii
        stiffness = np.einsum("g,gdn,gdm->nm", k, bearing_map, bearing_map)
        damping = 2 * float(isolation_damping) / np.sqrt(STANDARD_GRAVITY * np.sum(k) / weight) * stiffness
    elif float(isolation_damping) > 0:
        raise ValueError("isolation_damping: needs springs (isolation_period), or 0.")
    system = bidirectional_structure(
        mass=jnp.array([mass, mass, inertia]),
        stiffness=stiffness,
        damping=damping,
        influence=np.array([[1.0, 0.0], [0.0, 1.0], [0.0, 0.0]]),
        bearing_map=bearing_map,
        bearing=stack_bearings(bearings),
        bearing_load=loads,
        ground_x=ground_x,
        ground_y=ground_y,
        time_step=time_step,
        contact_pressure=contact_pressures,
        friction_model=friction_model,
    )
    return dataclasses.replace(system, pendulum_stiffness=None if radii is None else jnp.asarray(loads / radii),
                               overturning=None if overturning is None else jnp.asarray(overturning),
                               supports=None if overturning is None else support_plan(
                                   positions, centre, height, vertical_stiffness))


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
