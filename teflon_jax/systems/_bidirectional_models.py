"""Structures on bearing groups under two horizontal ground components: built (any linear
structure, the paper's rigid mass and six-storey building), at rest, and run over a record
(their histories and the building's storey peaks).

The rigid mass and the building sit on one group of sliding bearings with Park's biaxial Z
(Eqs. 8-9); x and y are uncoupled except through the bearings. Equations of motion and the
step: `_bidirectional.py`. Reference: Constantinou, Mokha & Reinhorn (1990), Eqs. 1, 8-9, 17,
Figs. 7-11, Table 2 (MODEL.md Sections 4 and 8).
"""

import dataclasses

import jax
import jax.numpy as jnp
import numpy as np

from ..bearing import HEAT_HORIZON, SeriesPendulum, SlidingBearing, heat_kernel_exponentials
from ..excitation import Signal
from ..solver import require_riccati_form
from ..structures import initial_normal_load
from ..tables import BuildingData
from ._bidirectional import (
    PLANAR_NEWTON_ITERATIONS,
    BidirectionalStructure,
    overturning_step,
)
from ._response import EngineRun, StructureResponse, uplift_time
from ._structure import FRICTION_MODELS
from ._structure_build import (
    check_storey_height,
    check_structure_parts,
    rigid_mass,
    six_storey_building,
)
from ._vertical import step_load_factors


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
    newton_iterations: int = PLANAR_NEWTON_ITERATIONS,
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
    overturning, the groups' normal loads under the vertical record at t = 0). `TypeError` for
    groups of series pendulums, whose state is `series_initial_state`'s."""
    check_sliding_groups(system)
    n, groups = system.mass.shape[0], system.bearing_load.shape[0]
    state = {"q": jnp.zeros(n), "v": jnp.zeros(n), "z": jnp.zeros((groups, 2)),
             "z_peak": jnp.zeros(groups)}
    if system.history:
        n_heat = 0 if system.heat_rates is None else system.heat_rates.shape[0]
        state.update(heat=jnp.zeros((groups, n_heat)), travel=jnp.zeros(groups))
    if system.overturning is not None:  # the groups' normal loads N_g [N] (`teflon_jax.structures`: `supported_loads`)
        state["normal_load"] = initial_normal_load(system)
    return state


def check_sliding_groups(system: BidirectionalStructure) -> None:
    """`TypeError` naming the structure where its groups are series pendulums (`SeriesPendulum`):
    their slab steps from `series_initial_state` (`_series.py`), not from the state of
    sliding groups."""
    if isinstance(system.bearing, SeriesPendulum):
        raise TypeError("system: a slab on triple or double pendulum groups starts from series_initial_state; "
                        "run it with simulate_history or peak_response.")


BIDIRECTIONAL_TIME_STEP = 0.0025
"""Default step [s] of the bidirectional structures: peak resultant base displacement and base
shear within 0.5 % of adaptive Tsit5 (rtol 1e-9) for the rigid mass and the building under the
PEER RSN6 pair and the SCT 1985 pair (tests/test_bidirectional_records.py); at 10 ms the RSN6
building is 1.2 % off."""


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


def _zero_signal(like: Signal) -> Signal:
    return Signal(times=like.times, values=jnp.zeros_like(like.values), uniform=like.uniform)


def _block(a, b):
    n = a.shape[0]
    out = jnp.zeros((2 * n, 2 * n))
    return out.at[:n, :n].set(a).at[n:, n:].set(b)


def _two_directions(x, y, bearing, ground_x, ground_y, time_step,
                    contact_pressure=None, **law) -> BidirectionalStructure:
    n = x.mass.shape[0]
    influence = np.zeros((2 * n, 2))
    influence[:n, 0] = 1.0
    influence[n:, 1] = 1.0
    bearing_map = np.zeros((1, 2, 2 * n))
    bearing_map[0, 0, 0] = 1.0
    bearing_map[0, 1, n] = 1.0
    return bidirectional_structure(
        mass=jnp.concatenate([x.mass, y.mass]),
        stiffness=_block(x.stiffness, y.stiffness),
        damping=_block(x.damping, y.damping),
        influence=influence,
        bearing_map=bearing_map,
        bearing=bearing,
        bearing_load=x.bearing_load[None],
        ground_x=ground_x,
        ground_y=_zero_signal(ground_x) if ground_y is None else ground_y,
        time_step=time_step,
        contact_pressure=contact_pressure,
        **law,
    )


def _one_direction(model, ground, time_step: float, **linear):
    """The linear part of one horizontal direction: `model` (`rigid_mass` or
    `six_storey_building`) with its `linear` keywords, no bearing and no friction, whose mass,
    stiffness, damping and bearing load `_two_directions` joins."""
    return model(bearing=None, ground_acceleration=ground, time_step=time_step, friction_model="none", **linear)


def bidirectional_rigid_mass(
    *,
    weight,
    bearing: SlidingBearing,
    ground_x: Signal,
    ground_y: Signal | None = None,
    time_step: float,
    isolation_period=None,
    damping_ratio=0.0,
    contact_pressure=None,
    friction_model: str = "hysteretic",
    surface=None,
) -> BidirectionalStructure:
    """A rigid mass W/g on sliding bearings under (a_x, a_y) (TASS-type system with springs):

        m u'' + c u' + k u + mu(|u'|) W Z = -m a_g,   u, Z, a_g in the plane,

    k = m (2 pi / T)^2 in both directions from `isolation_period` T [s] (`None`: flat sliders
    alone), c = 2 zeta m (2 pi / T) from `damping_ratio` zeta [-].

    **Arguments:** `weight` W [N]; `bearing`: `SlidingBearing` (x = parallel to the lay when
    it has `friction_perpendicular`); `ground_x`, `ground_y`: `Signal`s [m/s^2] (y `None` = no
    y motion); `time_step` [s] of `RiccatiNewmark`; `contact_pressure` [Pa] of the bearings
    (for a bearing with heating); `friction_model` "hysteretic", "coulomb" or "none";
    `surface`: a friction pendulum's `ConcaveSurface` (its period is `isolation_period`; its
    restrainer and large-displacement force act in the bearings' solve).

    **Returns:** a `BidirectionalStructure` with q = (u_x, u_y).
    """
    one = _one_direction(rigid_mass, ground_x, time_step, weight=weight, isolation_period=isolation_period,
                         damping_ratio=damping_ratio)
    return _two_directions(one, one, bearing, ground_x, ground_y, time_step, contact_pressure,
                           friction_model=friction_model, surface=surface)


def bidirectional_building(
    *,
    bearing: SlidingBearing,
    ground_x: Signal,
    ground_y: Signal | None = None,
    time_step: float,
    isolation_period,
    isolation_damping=0.05,
    building: BuildingData | None = None,
    building_y: BuildingData | None = None,
    isolation_period_y=None,
    contact_pressure=None,
    friction_model: str = "hysteretic",
    surface=None,
) -> BidirectionalStructure:
    """The six-storey frame of Table 2 in x and y on sliding bearings with springs (Fig. 11).

    Each direction is the 7-degree-of-freedom model of `six_storey_building` (base + six
    floors, 2 % modal damping, springs of period T_b and damping zeta_b in the rigid-body
    mode); y uses the same modal data unless `building_y` (and `isolation_period_y`) are given.
    The bearings carry the total weight W and couple the two bases through Park's Z;
    `contact_pressure` [Pa] of the bearings is needed for a bearing with heating;
    `friction_model` and `surface` as in `bidirectional_rigid_mass`.

    **Returns:** a `BidirectionalStructure` with q = (x: base, floors 1-6; y: base, floors 1-6).
    """
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
    return _two_directions(x, y, bearing, ground_x, ground_y, time_step, contact_pressure,
                           friction_model=friction_model, surface=surface)


def planar_records(system: BidirectionalStructure) -> tuple:
    """(record, what its length bounds) of a two-component structure's records (`step_count`):
    the x and y ground records and the vertical one (a `Signal` is zero past its end, so a run
    longer than a record is refused by name, not padded)."""
    return ((system.ground_x, "duration"), (system.ground_y, "duration (y record)"),
            (system.vertical_acceleration, "duration (vertical record)"))


def solved_planar_response(system: BidirectionalStructure, save_times, solution, n_steps: int) -> StructureResponse:
    """The `StructureResponse` (two ground components) of a structure on sliding bearing groups
    from an adaptive diffrax `solution` saved at `save_times` [s] over `n_steps` steps
    (`simulate_history`; no overturning loads, which only the fixed steps carry): at each saved
    time the sample of `planar_run`, under the load factor there."""
    loads = None if system.vertical_acceleration is None else jax.vmap(system.load_factor)(save_times)

    def sample(time, y, load):
        return _planar_sample(system.at_load(load), time, y, system._acceleration(time, y), system.ground(time),
                              load, None)

    response = jax.vmap(sample)(save_times, solution.ys, loads)
    dt = float(system.time_step)
    return dataclasses.replace(response, result=solution.result, uplift_time=None if loads is None else uplift_time(
        step_load_factors(system, n_steps), dt))


def directional_storeys(q, total_acceleration, storey_height):
    """Drift ratios (..., 2, S) [-] and total accelerations (..., 2, S + 1) [m/s^2] in x and y
    of the two-direction building (`bidirectional_building`: q = (x: base slab, floors 1..S;
    y: the same); `building_on_plan`: the same and the slab's rotation last),
    `total_acceleration` the same layout [m/s^2]: (q_j - q_(j-1)) / h_j per storey and
    a_j + a_g per level, level 0 the base slab. jit/vmap-safe in q and the accelerations;
    `storey_height` [m] scalar or (S,), not traced."""
    n = q.shape[-1] // 2
    height = jnp.asarray(check_storey_height(n, storey_height), q.dtype)
    x, y = q[..., :n], q[..., n:2 * n]
    drift = jnp.stack([jnp.diff(x, axis=-1), jnp.diff(y, axis=-1)], axis=-2) / height
    acc = jnp.stack([total_acceleration[..., :n], total_acceleration[..., n:2 * n]], axis=-2)
    return drift, acc


def bidirectional_storey_peaks(response, system, storey_height) -> dict:
    """Peak storey results of a run of the two-direction building (`bidirectional_building`)
    from its histories (`simulate_history`), by `directional_storeys`:

    - `storey_drift` (2, S) [-]: max_t |q_j - q_(j-1)| / h_j in x and in y, storey 1 first;
    - `storey_drift_resultant` (S,) [-]: max_t of the drift vector's length over h_j;
    - `level_acceleration` (2, S + 1) [m/s^2]: max_t |a_j + a_g| in x and y, level 0 the base slab;
    - `level_acceleration_resultant` (S + 1,) [m/s^2]: max_t of the total acceleration's length.
    """
    q = jnp.asarray(response.displacement)
    total = jnp.asarray(response.total_acceleration)
    drift, acc = (np.asarray(v) for v in directional_storeys(q, total, storey_height))  # (nt, 2, .)
    return {"storey_drift": np.abs(drift).max(axis=0), "storey_drift_resultant": np.hypot(*np.moveaxis(drift, 1, 0)).max(axis=0),
            "level_acceleration": np.abs(acc).max(axis=0),
            "level_acceleration_resultant": np.hypot(*np.moveaxis(acc, 1, 0)).max(axis=0)}


def planar_run(system: BidirectionalStructure, n_steps) -> EngineRun:
    """Flat sliders or single pendulums under two components, each step as the history's
    (`newmark_update` under the load factor of the step's end; with a slab's overturning,
    `overturning_step`: the groups' loads from the horizontal force at the step's start and
    the vertical record at its end, held over the step, a step on which the slab tips not
    converged), the accelerations the equation of motion's at each step's end."""
    dt = float(system.time_step)
    times = jnp.arange(n_steps + 1) * dt
    ground = jax.vmap(system.ground)(times)
    loads = None if system.vertical_acceleration is None else jax.vmap(system.load_factor)(times)
    overturning = system.overturning is not None
    y0 = bidirectional_initial_state(system)
    load0 = system.load_at(times[0], y0) if overturning else None if loads is None else loads[0]
    a0 = system.at_load(load0).acceleration_at(ground[0], y0)

    def step(state, inputs):
        y, a = state
        time0, time1, ground1, load1 = inputs
        tipped = None
        if overturning:
            y1, converged, tipped = overturning_step(system, time0, time1, y, a)
            loaded = system.at_load(system.load_at(time1, y1))  # the groups' loads kept in the state
        else:
            loaded = system.at_load(load1)  # the normal load at the step's end (vertical record)
            y1, converged = loaded.newmark_update(y, a, ground1)
        a1 = loaded.acceleration_at(ground1, y1)
        sample = _planar_sample(loaded, time1, y1, a1, ground1, load1, tipped)
        return (y1, a1), sample, converged

    inputs = (times[:-1], times[1:], ground[1:], None if loads is None else loads[1:])
    first = _planar_sample(system.at_load(load0), times[0], y0, a0, ground[0], None if loads is None else loads[0],
                           jnp.array(False) if overturning else None)
    return EngineRun((y0, a0), inputs, step, first)


def _planar_sample(loaded, time, y, acceleration, ground, load, tipped):
    """One sample of a `BidirectionalStructure`'s run: its coordinates, total accelerations,
    the groups' bearing displacements, friction forces (under the step's normal loads), Z,
    running peak of |Z|, heated bearings' surface temperature rise (G, 1) and, with
    overturning loads, the groups' loads and whether the slab tipped on the step."""
    rise = None
    if loaded.bearing.heating is not None:
        rise = loaded.bearing.surface_temperature_rise(y["heat"], loaded.heat_weights)[:, None]
    return StructureResponse(time=time, displacement=y["q"], velocity=y["v"],
                             total_acceleration=acceleration + loaded.influence @ ground, ground=ground,
                             friction_force=loaded.bearing_forces(y), z=y["z"], z_peak=y["z_peak"],
                             bearing_displacement=loaded.bearing_motion(y["q"]),
                             normal_load=y.get("normal_load"), surface_temperature_rise=rise, tipped=tipped,
                             load_factor=load)
