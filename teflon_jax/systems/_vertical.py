"""The vertical ground acceleration on any structure the library steps: the isolators' normal load.

With the superstructure rigid in the vertical direction, the normal load on the isolators
follows the vertical ground acceleration a_v(t) [m/s^2, up positive]:

    N(t) = W (1 + a_v(t) / g) = s(t) W,   s = max(1 + a_v / g, 0),

W the weight above the isolators (W_g per bearing group in two components). The friction
force mu N Z and a friction pendulum's restoring force N u / R scale with s; a restoring spring
(rubber, carrying no vertical load) does not. At s = 0 (N <= 0, uplift) the bearing carries no
shear: its friction and restoring forces are exactly zero, Z follows the slider's motion (so
that it is the sliding state again at touchdown) and no heat enters the steel, nor does a
wearing bearing count travel. Every isolator takes N at the end of each step, the time at
which its force is reported and uplift counted.

Records put under a structure built once: `under_ground` replaces any structure's horizontal
records and its vertical one (a suite's pairs, a Monte Carlo's motions).

One record, one function: `with_vertical_motion` puts it on any stepped structure (the rigid
mass, the building, the slab; one or two components; flat sliders, single, double and triple
pendulums), `with_vertical_component` on the isolated structure of the studies
(`IsolatedStructure.vertical`), which then takes (horizontal, vertical) ground motions. The stepped structures take the load at the step's
end from `load_factor_at`; the flat sliders and single pendulums solve their step under it with
`loaded_isolator_force` (one component) and `loaded_solve` (two; `loaded_bidirectional`).

References: Almazan, De la Llera & Inaudi (1998), Earthquake Eng. Struct. Dyn. 27(8),
845-867 (the friction pendulum's force under a varying normal load); Mokha, Constantinou &
Reinhorn (1990), J. Struct. Eng. 116(2), 438-454 (the normal load's effect on PTFE friction).
"""

import dataclasses
import functools

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ..bearing import FrictionParameters
from ..excitation import Signal
from ..tables import FrictionTable
from ..units import STANDARD_GRAVITY


def normal_load_factor(vertical_acceleration):
    """s = N / W = max(1 + a_v / g, 0) [-] at vertical ground acceleration a_v [m/s^2, up +]."""
    return jnp.maximum(1 + jnp.asarray(vertical_acceleration) / STANDARD_GRAVITY, 0.0)


def load_factor_at(vertical_acceleration: Signal | None, t):
    """`normal_load_factor` of the record `vertical_acceleration` at time t [s]; `None`
    without a vertical record (the load is then W throughout)."""
    if vertical_acceleration is None:
        return None
    return normal_load_factor(vertical_acceleration(t))


def pressure_factor(exponent, load):
    """s^-e [-]: the factor on a bearing's friction of its pressure dependence (N / N_ref)^-e
    (Mokha, Constantinou & Reinhorn 1990; `PressureDependence`) under the load factor s = N / W,
    with the friction at the static load W folded in (`SlidingBearing.at_contact_pressure`); 1
    while uplifted (s = 0), where the bearing carries no force."""
    return jnp.where(load > 0, load, 1.0) ** -jnp.asarray(exponent)


LAW_REACH = ("beyond where Table 1's extended end segments give Eq. 1 constants (f_max > delta_f >= 0, rate_a >= 0, "
             "breakaway ratio >= 1)")
"""Where Table 1's pressure law, its end segments extended, stops giving Eq. 1 constants
(`TablePressure.valid_at`): the words of every report of a run or a pair beyond it."""


class TablePressure(eqx.Module):
    """Table 1's pressure dependence on a bearing folded at its static contact pressure, under
    a varying normal load.

    A bearing whose Eq. 1 constants (and breakaway ratio) were read off Table 1 at the
    static contact pressure p (`pressure` [Pa], one, or one per group) takes, under the load
    factor s = N / W, each constant times its table ratio c(s p) / c(p) (`table` a
    `FrictionTable`, or one per group stacked along a first axis: linear in the pressure
    between the tabulated rows, its end segments extended beyond them); an anisotropic
    bearing's constants across the lay take the ratios of `perpendicular`, the table of
    sliding across it. For constants taken from the table this is the table at the
    momentary pressure s p; constants a design or a bounding factor set are scaled alike.
    While uplifted (s = 0) the bearing carries no force and the ratios are 1. Where an
    extended segment gives constants Eq. 1 cannot take (f_max <= delta_f, a negative delta_f
    or rate_a, a breakaway ratio below 1), the run stops with an error, not a clipped value
    (Mokha, Constantinou & Reinhorn 1990: the friction of PTFE on steel falls as the contact
    pressure rises; Constantinou, Mokha & Reinhorn 1990, Table 1); with `stop` False (a study
    of many runs, `flag_pressure_law`) it goes on and the peak driver reports the run as
    beyond the law (`within_pressure_law`), its peaks not to be trusted.
    """

    table: FrictionTable
    pressure: jnp.ndarray
    perpendicular: FrictionTable | None = None
    stop: bool = eqx.field(static=True, default=True)

    def bearing_at(self, bearing, load):
        """`bearing` (a `SlidingBearing` folded at `pressure`) under the load factor `load` s [-];
        a run stops with an error where the constants are invalid (`valid_at`)."""
        fields, bad = self._fields_at(bearing, load)
        if not self.stop:
            return dataclasses.replace(bearing, **fields)
        fields["friction"] = eqx.error_if(
            fields["friction"], jnp.any(bad),
            f"the vertical record takes the bearings' contact pressure {LAW_REACH}; give the bearing's "
            "constants at such pressures (a bearing file with a pressure dependence).")
        return dataclasses.replace(bearing, **fields)

    def valid_at(self, bearing, load):
        """Whether Eq. 1 can take `bearing`'s constants under the load factor `load` s [-]
        (f_max > delta_f >= 0, rate_a >= 0 and a breakaway ratio >= 1 in every group; always
        while uplifted, s = 0): a bool array, for checking a record before it runs."""
        return ~jnp.any(self._fields_at(bearing, load)[1])

    def groups_valid_at(self, bearing, load):
        """`valid_at` of each group apart: a bool per group (the broadcast shape of the bearing's
        constants and `load`), True where Eq. 1 can take that group's constants."""
        return ~self._fields_at(bearing, load)[1]

    def constant_breaks(self):
        """The load factors s [-] at which some group's constants change slope (its table's rows
        over its static pressure): with the ends of a range of s, where the constants, linear in
        s between them, are least valid."""
        tables = [self.table] + ([] if self.perpendicular is None else [self.perpendicular])
        rows = np.concatenate([np.asarray(t.pressures).reshape(-1) for t in tables])
        return np.unique(rows[:, None] / np.asarray(self.pressure, float).reshape(-1)[None, :])

    def _fields_at(self, bearing, load):
        pressure = jnp.where(load > 0, load, 1.0) * self.pressure
        friction, ratio = _scaled_by_table(self.table, self.pressure, pressure, bearing.friction)
        fields = {"friction": friction}
        if bearing.breakaway_ratio is not None:
            fields["breakaway_ratio"] = bearing.breakaway_ratio * ratio
        if bearing.friction_perpendicular is not None:
            fields["friction_perpendicular"] = _scaled_by_table(self.perpendicular, self.pressure, pressure,
                                                                bearing.friction_perpendicular)[0]
        bad = [~((f.f_max > f.delta_f) & (f.delta_f >= 0) & (f.rate_a >= 0)) for name, f in fields.items()
               if name != "breakaway_ratio"]
        if "breakaway_ratio" in fields:
            bad.append(~(fields["breakaway_ratio"] >= 1))
        return fields, functools.reduce(jnp.logical_or, bad) & (load > 0)  # per group


def _scaled_by_table(table, static, pressure, friction):
    """(`friction` with each constant times the table's c(pressure) / c(static), the ratio
    b(pressure) / b(static) of the breakaway ratio); a table per group (stacked) is read
    at its group's pressures."""
    def read(table, static, pressure):
        (then, b_then), (now, b_now) = table.at(static), table.at(pressure)
        return then, b_then, now, b_now

    if table.pressures.ndim == 2:
        read = jax.vmap(read)
    then, b_then, now, b_now = read(table, static, pressure)
    scaled = FrictionParameters(f_max=friction.f_max * (now.f_max / then.f_max),
                                delta_f=friction.delta_f * (now.delta_f / then.delta_f),
                                rate_a=friction.rate_a * (now.rate_a / then.rate_a))
    return scaled, b_now / b_then


def flag_pressure_law(system):
    """`system` whose Table 1 pressure law (`TablePressure`) lets a run go on beyond its
    extended rows, the peak driver then reporting it (`within_pressure_law`): how a study of
    many runs keeps the others; `system` itself without that law."""
    table = getattr(system, "pressure_table", None)
    return system if table is None else dataclasses.replace(system, pressure_table=dataclasses.replace(table, stop=False))


def pressure_law_loads(system, layout, sample):
    """(largest, least positive) load factor s = N / W [-] of each bearing group (or the
    isolator) at one sample, the second inf where uplifted: the pressures a run's Table 1 law
    is read at (`within_pressure_law`)."""
    overturning = layout.overturning and sample.normal_load is not None
    load = sample.normal_load / system.bearing_load if overturning else sample.load_factor
    return load, jnp.where(load > 0, load, jnp.inf)


def within_pressure_law(system, extremes):
    """Whether Table 1's law of `system` (`TablePressure`) gives Eq. 1 constants at every load
    factor between the `extremes` (largest, least positive; `pressure_law_loads` folded over a
    run from s = 1 at rest): at both ends and at the table's rows between, where the constants, linear in s
    between rows, change slope; a bool."""
    table, (high, low) = system.pressure_table, extremes  # both folded from s = 1 at rest: finite
    within = table.valid_at(system.bearing, high) & table.valid_at(system.bearing, low)
    tables = [table.table] + ([] if table.perpendicular is None else [table.perpendicular])
    rows = jnp.concatenate([jnp.ravel(t.pressures) for t in tables])  # traced in a study: no NumPy here
    breaks = jnp.ravel(rows[:, None] / jnp.ravel(jnp.asarray(table.pressure))[None, :])

    def valid_inside(row):  # read only where inside a group's range (0: always valid)
        return table.valid_at(system.bearing, jnp.where((low < row) & (row < high), row, 0.0))

    return within & jnp.all(jax.vmap(valid_inside)(breaks))


def pressure_law_valid(system, response):
    """Whether Table 1's law of `system` (`TablePressure`) gave Eq. 1 constants at the loads of
    each sample of its `response` (a `StructureResponse` saved at every step, the rest
    included), which are the loads its steps read: each group's N_g / W_g under overturning
    (`normal_load`), else the load factor s; a bool (nt,), True throughout without that law
    (`flag_pressure_law` lets a run go on past the first sample beyond it) and at the samples
    the run did not reach: after the first step that did not balance (`converged`), and where
    the loads are not finite (a solve that stopped)."""
    table = getattr(system, "pressure_table", None)
    if table is None:
        return jnp.ones(jnp.shape(response.time), bool)
    overturning = getattr(system, "overturning", None) is not None and response.normal_load is not None
    loads = response.normal_load / system.bearing_load if overturning else response.load_factor
    valid = jax.vmap(lambda load: table.valid_at(system.bearing, load))(loads)
    reached = jnp.all(jnp.isfinite(loads).reshape(loads.shape[0], -1), axis=-1)
    if response.converged is not None:
        failed = ~response.converged
        reached = reached & (jnp.cumsum(failed) - failed == 0)  # the first failed step's loads were read
    return valid | ~reached


def bearing_under_load(system, load) -> dict:
    """The fields of `system` (a stepped structure on flat sliders or single pendulums) whose
    bearing is at the contact pressure of the load factor `load` s: its bearing by its pressure
    law (`pressure_exponent`, s^-e on the friction, `pressure_factor`; `pressure_table`,
    Table 1's ratios, `TablePressure`), the law then spent; {} without one."""
    if system.pressure_exponent is not None:
        bearing = system.bearing.scaled(pressure_factor(system.pressure_exponent, load))
    elif system.pressure_table is not None:
        bearing = system.pressure_table.bearing_at(system.bearing, load)
    else:
        return {}
    return {"bearing": bearing, "pressure_exponent": None, "pressure_table": None}


def step_load_factors(system, n_steps: int):
    """N / W (n_steps + 1,) [-] of `system`'s vertical record at the ends 0..n_steps of its steps
    of `time_step`, as its step reads it (`load_factor`: the record linear between samples)."""
    return jax.vmap(system.load_factor)(jnp.arange(n_steps + 1) * system.time_step)


# --------------------------------------------------------------------------- the record on a structure


def with_vertical_motion(system, vertical_acceleration: Signal, radius=None, pressure_exponent=None,
                         friction_table=None, table_pressure=None):
    """`system` with the vertical ground acceleration `vertical_acceleration` [m/s^2, up +] on
    its isolators' normal load N = W max(1 + a_v / g, 0) (module docstring).

    `system`: any stepped structure (a `StructureOnSliders`: the rigid mass, the building and
    the slab, on any isolator, in one or two components).

    A single friction pendulum's structure holds the part W / R of its stiffness that the
    normal load carries (`pendulum_stiffness`, scaled by N / W in each step; W_g / R per group
    in two components) when built with its radius or surface (`rigid_mass(radius=...)`,
    `isolated_structure(kind, isolator=concave_surface(R))`, `rigid_mass(components=2, surface=...)`, the
    slab, the building on a plan); flat sliders' restoring springs keep their stiffness.
    `radius` R [m] sets W / R on a `StructureOnSliders` built
    without it (a pendulum given by its period alone); `None` keeps what the structure holds.
    Triple and double pendulums carry their surfaces' radii: `radius` must be `None` there.
    `pressure_exponent` e [-] (one, or one per group): the exponent of the pressure dependence
    of flat sliders or single pendulums whose friction was taken at their static contact
    pressure (`SlidingBearing.at_contact_pressure`), so that it follows N as mu s^-e
    (`pressure_factor`), as the bearing's test and a series pendulum's surfaces follow it;
    `None` for bearings without one (a series pendulum's surfaces carry theirs).
    `friction_table` (a `FrictionTable`, one per group stacked, or for an anisotropic bearing
    the pair along and across the lay) and `table_pressure` p [Pa] (one, or one per group):
    flat sliders or single pendulums whose constants were read off Table 1 at p, so that
    they follow the momentary contact pressure s p (`TablePressure`); not with
    `pressure_exponent`. `ValueError` naming the argument otherwise.
    """
    if not isinstance(vertical_acceleration, Signal):
        raise ValueError("vertical_acceleration: expected a Signal of the vertical ground "
                         f"acceleration [m/s^2], got {type(vertical_acceleration).__name__}.")
    fields = {field.name for field in dataclasses.fields(system)} if dataclasses.is_dataclass(system) else set()
    if "vertical_acceleration" not in fields:
        raise ValueError("system: expected a stepped structure (StructureOnSliders, "
                         f"on any isolator), got {type(system).__name__}.")
    if getattr(system, "pendulum", None) is not None:  # series pendulums: the load acts on their sliders
        _no_radius(radius)
        for name, value in (("pressure_exponent", pressure_exponent), ("friction_table", friction_table)):
            if value is not None:
                raise ValueError(f"{name}: a triple or double pendulum's surfaces carry their own pressure "
                                 f"dependence (surface_parts); leave {name} out.")
        return dataclasses.replace(system, vertical_acceleration=vertical_acceleration)
    table = _table_pressure(system, friction_table, table_pressure, pressure_exponent)
    if pressure_exponent is not None:
        value = np.asarray(pressure_exponent) if not isinstance(pressure_exponent, jax.core.Tracer) else None
        if value is not None and not np.all(np.isfinite(value)):
            raise ValueError(f"pressure_exponent: must be finite, got {value.tolist()}.")
        pressure_exponent = jnp.asarray(pressure_exponent, float)
    stiffness = system.pendulum_stiffness
    if radius is not None:
        value = np.asarray(radius) if not isinstance(radius, jax.core.Tracer) else None
        if value is not None and not np.all(np.isfinite(value) & (value > 0)):
            raise ValueError(f"radius: must be > 0 [m] (the pendulum's radius), got {value.tolist()}.")
        stiffness = system.bearing_load / jnp.asarray(radius, float)
    return dataclasses.replace(system, vertical_acceleration=vertical_acceleration,
                               pendulum_stiffness=stiffness, pressure_exponent=pressure_exponent,
                               pressure_table=table)


def _table_pressure(system, friction_table, table_pressure, pressure_exponent):
    """The `TablePressure` of `with_vertical_motion`'s arguments (None without a table);
    `ValueError` naming the argument that is missing, not positive or not with the others."""
    if friction_table is None and table_pressure is None:
        return None
    if table_pressure is None:
        raise ValueError("table_pressure: give the contact pressure [Pa] the bearing's constants were read "
                         "off friction_table at.")
    if pressure_exponent is not None:
        raise ValueError("pressure_exponent: a bearing follows its contact pressure by one law; give "
                         "pressure_exponent or friction_table, not both.")
    perpendicular = None
    if isinstance(friction_table, tuple) and len(friction_table) == 2:
        friction_table, perpendicular = friction_table
    if system.bearing is None:
        raise ValueError("friction_table: the structure has no friction law to follow the table (friction "
                         "model 'none'); leave it out.")
    if not all(isinstance(t, FrictionTable) for t in (friction_table, perpendicular) if t is not None):
        raise ValueError("friction_table: give the FrictionTable the bearing's constants were read off "
                         f"(tables.friction_table) with table_pressure, got {type(friction_table).__name__}.")
    if (system.bearing.friction_perpendicular is not None) != (perpendicular is not None):
        raise ValueError("friction_table: an anisotropic bearing takes the pair (table along the lay, table "
                         "across it), an isotropic one a single table.")
    value = np.asarray(table_pressure) if not isinstance(table_pressure, jax.core.Tracer) else None
    if value is not None and not np.all(np.isfinite(value) & (value > 0)):
        raise ValueError(f"table_pressure: must be > 0 [Pa], got {value.tolist()}.")
    return TablePressure(friction_table, jnp.asarray(table_pressure, float), perpendicular)


def _no_radius(radius) -> None:
    if radius is not None:
        raise ValueError("radius: a triple or double pendulum's radii are its surfaces' (its "
                         "SeriesPendulum); leave radius out.")


# --------------------------------------------------------------------------- one component


def loaded_surface_force(system, u0, load):
    """The isolator's force [N] beyond the structure's linear stiffness at displacement u0 [m]
    and load factor s = N / W: the pendulum's (s - 1) W u0 / R (its stiffness W / R is in
    the structure's K) and its surface's large-displacement and restrainer terms under N."""
    u0 = jnp.asarray(u0, dtype=float)
    force = jnp.zeros_like(u0)
    if system.surface is not None:
        force = system.surface.extra_force(u0, load * system.bearing_load)
    if system.pendulum_stiffness is not None:
        force = force + (load - 1) * system.pendulum_stiffness * u0
    return force


def loaded_isolator_force(system, ub_linear, vb_linear, compliance, y0, start_factors, load):
    """`StructureOnSliders.isolator_force` under the normal load s W at the end of the step.

    The total isolator force is F = F_b(x) + a x with F_b the bearing's (friction mu s W Z
    and surface terms under s W) and a = (s - 1) W / R the pendulum's change of stiffness
    (0 for flat sliders). Its equilibrium x = u_lin - g0 (F_b(x) + a x) is the same problem as
    without the load change, x = u_lin / c - (g0 / c) F_b(x) with c = 1 + g0 a, solved by
    the structure at load s W; its velocity stays the same function of x when v_lin becomes
    v_lin - gv a u_lin / c and gv becomes gv / c. At s = 0, F_b = 0 and F = -W x / R cancels
    the pendulum's stiffness: no shear.

    **Returns:** (F [N], Z, running peak of |Z|, converged), as `isolator_force`.
    """
    g0, gv = compliance
    a = 0.0 if system.pendulum_stiffness is None else (load - 1) * system.pendulum_stiffness
    c = 1 + g0 * a
    ub, vb = ub_linear / c, vb_linear - gv * a * ub_linear / c
    loaded = dataclasses.replace(system, bearing_load=load * system.bearing_load, vertical_acceleration=None,
                                 pendulum_stiffness=None, **bearing_under_load(system, load))
    force, z1, z_peak1, converged = loaded.isolator_force(ub, y0, vb, (g0 / c, gv / c), start_factors)
    x = ub - g0 / c * force
    return force + a * x, z1, z_peak1, converged


# --------------------------------------------------------------------------- two components


def loaded_bidirectional(system, load):
    """`system` (a planar `StructureOnSliders`) under the load factor `load` = N / W [-]: its
    groups' loads s W_g, with `load` kept for the pendulum's change (`pendulum_change`), and
    with `pressure_exponent` or `pressure_table` the friction at the contact pressure of s W_g
    (`pressure_factor`, `TablePressure`)."""
    return dataclasses.replace(system, bearing_load=system.bearing_load * load, load=jnp.asarray(load),
                               vertical_acceleration=None, **bearing_under_load(system, load))


def pendulum_change(system):
    """(s - 1) W_g / R (G,) [N/m] of a loaded copy: the change of the pendulum's stiffness
    (zeros for flat sliders)."""
    if system.pendulum_stiffness is None:
        return jnp.zeros_like(system.bearing_load)
    return (system.load - 1) * system.pendulum_stiffness


def loaded_heat(system, coefficient, slide):
    """(mu s, slide) of a loaded copy for the heat flux mu s p |v| and the travel (none while
    uplifted); unchanged for a structure without a load factor."""
    if system.load is None:
        return coefficient, slide
    return coefficient * system.load, jnp.where(system.load > 0, slide, 0.0)


def loaded_solve(system, p):
    """`PlanarStep._solve_bearings` of a loaded copy with the pendulum's change of
    stiffness moved into the bearings' equilibrium d = d_lin - G_b (F(d) + A d),
    A = diag((s - 1) W_g / R):

        d = (I + G_b A)^-1 d_lin - (I + G_b A)^-1 G_b F(d),

    the same problem with d_lin and the flexibility G_b replaced (the velocity at the end of
    the step is Newmark's 2 (d - d0) / dt - v0 whatever the forces). Returns the total bearing
    forces F + A d (x, y parts), Z and convergence."""
    a = pendulum_change(system)
    n = a.shape[0]
    (xx, xy), (yx, yy) = p["flexibility"]
    flexibility = jnp.block([[xx, xy], [yx, yy]])
    matrix = jnp.eye(2 * n) + flexibility * jnp.concatenate([a, a])[None, :]
    flexibility = jnp.linalg.solve(matrix, flexibility)
    d_linear = jnp.linalg.solve(matrix, jnp.concatenate(p["d_linear"]))
    blocks = ((flexibility[:n, :n], flexibility[:n, n:]), (flexibility[n:, :n], flexibility[n:, n:]))
    (fx, fy), z, converged = system._solve_bearings(
        {**p, "flexibility": blocks, "d_linear": (d_linear[:n], d_linear[n:])})
    d = d_linear - flexibility @ jnp.concatenate([fx, fy])
    return (fx + a * d[:n], fy + a * d[n:]), z, converged


def under_ground(system, ground_acceleration: Signal, ground_y: Signal | None = None,
                 ground_z: Signal | None = None):
    """`system` (any structure `teflon_jax.systems` builds) under other records: the ground
    `Signal`s `ground_acceleration` (x) and, where it steps under two components, `ground_y` [m/s^2] in place
    of its own, and `ground_z` [m/s^2, up +] in place of its vertical record (where
    `with_vertical_motion` gave it one). `ValueError` naming the argument that does not fit."""
    if (ground_y is None) != (system.ground_y is None):
        raise ValueError(f"ground_y: the structure steps under {1 if system.ground_y is None else 2} horizontal "
                         "component(s); give its y record exactly where it steps under two.")
    system = eqx.tree_at(lambda s: s.ground_acceleration, system, ground_acceleration)
    if ground_y is not None:
        system = eqx.tree_at(lambda s: s.ground_y, system, ground_y)
    if ground_z is None:
        return system
    if system.vertical_acceleration is None:
        raise ValueError("ground_z: the structure has no vertical record to replace (with_vertical_motion first).")
    return eqx.tree_at(lambda s: s.vertical_acceleration, system, ground_z)
